/* Shared plumbing: error messages, whole-or-nothing files, the progress
 * line, and the one argument style of every tool. */
#include "vr_test.h"
#include "vr/args.h"
#include "vr/atomic_file.h"
#include "vr/out_guard.h"
#include "vr/error.h"
#include "vr/progress.h"
#include "vr/hash64.h"
#include "vr/sha256.h"

#include <sys/stat.h>

static void error_messages(void **state) {
  (void)state;
  vr_error err = {0};
  assert_int_equal(vr_error_at(&err, VR_E_PARSE, "a.csv", 12, 3, "field '%s': bad", "T"), VR_E_PARSE);
  assert_string_equal(err.message, "a.csv:12:3: field 'T': bad");
  vr_error_at(&err, VR_E_IO, "b.dat", 7, 0, "short");
  assert_string_equal(err.message, "b.dat:7: short");
  vr_error_prefix(&err, "while importing %s: ", "x");
  assert_string_equal(err.message, "while importing x: b.dat:7: short");
  assert_int_equal(vr_error_set(NULL, VR_E_ARG, "ignored"), VR_E_ARG);
  assert_string_equal(vr_status_name(VR_E_NOT_FOUND), "not found");
}

static void atomic_files_appear_whole_or_not_at_all(void **state) {
  (void)state;
  char dir[] = "/tmp/vr_atomic_XXXXXX";
  assert_non_null(mkdtemp(dir));
  char path[128];
  snprintf(path, sizeof path, "%s/out.txt", dir);
  FILE *f = fopen(path, "w");
  fputs("old", f);
  fclose(f);
  vr_atomic_file af;
  vr_error err = {0};
  /* An aborted write leaves the old content and no temporary file. */
  assert_int_equal(vr_atomic_file_open(&af, path, &err), VR_OK);
  fputs("partial", af.fp);
  vr_atomic_file_abort(&af);
  char buf[16] = {0};
  f = fopen(path, "r");
  assert_non_null(fgets(buf, sizeof buf, f));
  fclose(f);
  assert_string_equal(buf, "old");
  /* A committed write replaces it. */
  assert_int_equal(vr_atomic_file_open(&af, path, &err), VR_OK);
  fputs("new", af.fp);
  assert_int_equal(vr_atomic_file_commit(&af, &err), VR_OK);
  f = fopen(path, "r");
  assert_non_null(fgets(buf, sizeof buf, f));
  fclose(f);
  assert_string_equal(buf, "new");
  remove(path);
  assert_int_equal(rmdir(dir), 0); /* nothing else was left in the directory */
}

static void progress_line(void **state) {
  (void)state;
  char line[128];
  vr_progress_format(line, sizeof line, "fit", 25, 100, 10.0, 10);
  assert_string_equal(line, "fit [##        ]  25%  ETA 0:30");
  vr_progress_format(line, sizeof line, "fit", 100, 100, 3725.0, 4);
  assert_string_equal(line, "fit [####] 100%  took 1:02:05");
  vr_progress_format(line, sizeof line, "x", 0, 10, 1.0, 2);
  assert_string_equal(line, "x [  ]   0%  ETA --:--");
  /* Not a terminal under ctest: the bar is silent and NULL is accepted. */
  vr_progress *p = vr_progress_create("quiet", 10);
  vr_progress_update(p, 5);
  vr_progress_finish(p);
}

static const vr_option OPTS[] = {
    {"db", 'd', "FILE", "database"},
    {"json", 'j', NULL, "JSON output"},
    {"angle", 0, "DEG", "angle"},
};

static void arguments(void **state) {
  (void)state;
  vr_args a;
  char *argv1[] = {"t", "in.csv", "--db=x.db", "-j", "--angle", "-12.5", "-3", "--", "--json", NULL};
  assert_int_equal(vr_args_parse(&a, "t", "FILE", "", OPTS, 3, 9, argv1), VR_ARGS_RUN);
  assert_string_equal(vr_args_get(&a, "db"), "x.db");
  assert_true(vr_args_flag(&a, "json"));
  double v;
  assert_int_equal(vr_args_double(&a, "angle", 0, &v, NULL), VR_OK);
  assert_near(v, -12.5, 0);
  assert_int_equal(a.noperands, 3);
  assert_string_equal(a.operands[0], "in.csv");
  assert_string_equal(a.operands[1], "-3");
  assert_string_equal(a.operands[2], "--json");
  vr_args_free(&a);
  /* Usage errors: exit code 2 through VR_ARGS_EXIT_USAGE. */
  char *argv2[] = {"t", "--nope", NULL};
  assert_int_equal(vr_args_parse(&a, "t", "FILE", "", OPTS, 3, 2, argv2), VR_ARGS_EXIT_USAGE);
  char *argv3[] = {"t", "--db", NULL};
  assert_int_equal(vr_args_parse(&a, "t", "FILE", "", OPTS, 3, 2, argv3), VR_ARGS_EXIT_USAGE);
  char *argv4[] = {"t", "--json=yes", NULL};
  assert_int_equal(vr_args_parse(&a, "t", "FILE", "", OPTS, 3, 2, argv4), VR_ARGS_EXIT_USAGE);
  char *argv5[] = {"t", "--angle", "abc", NULL};
  assert_int_equal(vr_args_parse(&a, "t", "FILE", "", OPTS, 3, 3, argv5), VR_ARGS_RUN);
  vr_error err = {0};
  assert_int_equal(vr_args_double(&a, "angle", 0, &v, &err), VR_E_ARG);
  assert_string_equal(err.message, "option --angle: 'abc' is not a finite number");
  vr_args_free(&a);
  /* An empty value is a usage error for every option (issue 35, class 6:
   * --db '' had exited 1 in some tools after doing the work). */
  char *argv6[] = {"t", "--db", "", NULL};
  assert_int_equal(vr_args_parse(&a, "t", "FILE", "", OPTS, 3, 3, argv6), VR_ARGS_EXIT_USAGE);
  char *argv7[] = {"t", "--angle=", NULL};
  assert_int_equal(vr_args_parse(&a, "t", "FILE", "", OPTS, 3, 2, argv7), VR_ARGS_EXIT_USAGE);
}

static void sha256_fips_vectors(void **state) {
  (void)state;
  /* FIPS 180-2 Appendix B test vectors. */
  char hex[65];
  vr_sha256_buffer("abc", 3, hex);
  assert_string_equal(hex, "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  const char *two = "abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq";
  vr_sha256_buffer(two, strlen(two), hex);
  assert_string_equal(hex, "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  /* One million 'a', fed in uneven pieces. */
  vr_sha256 c;
  vr_sha256_init(&c);
  char a[997];
  memset(a, 'a', sizeof a);
  size_t left = 1000000;
  while (left) {
    size_t n = left < sizeof a ? left : sizeof a;
    vr_sha256_update(&c, a, n);
    left -= n;
  }
  vr_sha256_final(&c, hex);
  assert_string_equal(hex, "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
  vr_sha256_buffer("", 0, hex);
  assert_string_equal(hex, "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
}

/* XXH64 of one input three ways: one call, one update, byte by byte. */
static void check_xxh64(const void *data, size_t len, uint64_t seed, uint64_t want) {
  assert_true(vr_hash64_buffer(data, len, seed) == want);
  vr_hash64 h;
  vr_hash64_init(&h, seed);
  vr_hash64_update(&h, data, len);
  assert_true(vr_hash64_final(&h) == want);
  vr_hash64_init(&h, seed);
  for (size_t i = 0; i < len; i++) vr_hash64_update(&h, (const char *)data + i, 1);
  assert_true(vr_hash64_final(&h) == want);
}

static void xxh64_reference_vectors(void **state) {
  (void)state;
  /* xxHash's own sanity check (Cyan4973/xxHash, xxhsum.c, BMK_sanityCheck):
   * a 101-byte buffer from a 32-bit squaring generator, hashed whole and
   * in prefixes of 1 and 14 bytes, with seeds 0 and 2654435761. */
  const uint32_t prime = 2654435761u;
  unsigned char buf[101];
  uint32_t gen = prime;
  for (int i = 0; i < 101; i++) {
    buf[i] = (unsigned char)(gen >> 24);
    gen *= gen;
  }
  check_xxh64(NULL, 0, 0, 0xEF46DB3751D8E999ull);
  check_xxh64(NULL, 0, prime, 0xAC75FDA2929B17EFull);
  check_xxh64(buf, 1, 0, 0x4FCE394CC88952D8ull);
  check_xxh64(buf, 1, prime, 0x739840CB819FA723ull);
  check_xxh64(buf, 14, 0, 0xCFFA8DB881BC3A3Dull);
  check_xxh64(buf, 14, prime, 0x5B9611585EFCC9CBull);
  check_xxh64(buf, 101, 0, 0x0EAB543384F878ADull);
  check_xxh64(buf, 101, prime, 0xCAA65939306F1E21ull);
  /* Text vectors published with the format (xxhsum of the strings). */
  check_xxh64("abc", 3, 0, 0x44BC2CF5AD770999ull);
  const char *text = "Nobody inspects the spammish repetition";
  check_xxh64(text, strlen(text), 0, 0xFBCEA83C8A378BF1ull);
  /* Any single flipped bit of a 4 KiB block changes the sum: what the
   * geometry cache relies on to refuse a damaged file. */
  static unsigned char block[4096];
  for (size_t i = 0; i < sizeof block; i++) block[i] = (unsigned char)(i * 131u + 7u);
  uint64_t base = vr_hash64_buffer(block, sizeof block, 0);
  for (size_t bit = 0; bit < 8 * sizeof block; bit += 37) {
    block[bit / 8] ^= (unsigned char)(1u << (bit % 8));
    assert_true(vr_hash64_buffer(block, sizeof block, 0) != base);
    block[bit / 8] ^= (unsigned char)(1u << (bit % 8));
  }
}

/* An output that is an input of the same run is refused whatever name
 * reaches it (the same name, ./name, a hard link, a symbolic link); a new
 * file beside it is allowed; an empty name, a folder and a missing folder
 * are refused with the option named. */
static void outputs_never_replace_inputs(void **state) {
  (void)state;
  char dir[] = "/tmp/vr_guard_XXXXXX";
  assert_non_null(mkdtemp(dir));
  char data[128], hard[128], sym[128], fresh[128], db[128], wal[128], dotted[160];
  snprintf(data, sizeof data, "%s/data.csv", dir);
  snprintf(hard, sizeof hard, "%s/hard.csv", dir);
  snprintf(sym, sizeof sym, "%s/sym.csv", dir);
  snprintf(fresh, sizeof fresh, "%s/report.txt", dir);
  snprintf(db, sizeof db, "%s/m.db", dir);
  snprintf(wal, sizeof wal, "%s/m.db-wal", dir);
  snprintf(dotted, sizeof dotted, "%s/./data.csv", dir);
  FILE *f = fopen(data, "w");
  assert_non_null(f);
  fputs("x\n", f);
  fclose(f);
  f = fopen(db, "w");
  fclose(f);
  f = fopen(wal, "w");
  fclose(f);
  assert_int_equal(link(data, hard), 0);
  assert_int_equal(symlink(data, sym), 0);
  vr_out_guard g;
  vr_out_guard_init(&g);
  vr_out_guard_input(&g, data, "the measurement");
  vr_out_guard_database(&g, db);
  vr_error err = {0};
  const char *same[] = {data, dotted, hard, sym};
  for (int i = 0; i < 4; i++) {
    assert_int_equal(vr_out_guard_check(&g, same[i], "--report", &err), VR_E_ARG);
    assert_non_null(strstr(err.message, "--report"));
    assert_non_null(strstr(err.message, "the measurement"));
  }
  assert_int_equal(vr_out_guard_check(&g, db, "-o", &err), VR_E_ARG);
  assert_non_null(strstr(err.message, "the material database"));
  assert_int_equal(vr_out_guard_check(&g, wal, "-o", &err), VR_E_ARG);
  /* The journal names that do not exist now are the database's too, by
   * any path to it (SQLite makes and deletes them). */
  char shm[200], journal_rel[200];
  snprintf(shm, sizeof shm, "%s-shm", db);
  assert_int_equal(access(shm, F_OK), -1);
  assert_int_equal(vr_out_guard_check(&g, shm, "-o", &err), VR_E_ARG);
  assert_non_null(strstr(err.message, "journal of this run"));
  snprintf(journal_rel, sizeof journal_rel, "%s/../%s/%s-journal", dir, strrchr(dir, '/') + 1,
           strrchr(db, '/') + 1);
  assert_int_equal(vr_out_guard_check(&g, journal_rel, "-o", &err), VR_E_ARG);
  /* A database this run will make: its journal names by place and name. */
  char newdb[200], newwal[200];
  snprintf(newdb, sizeof newdb, "%s/new.db", dir);
  snprintf(newwal, sizeof newwal, "%s/./new.db-wal", dir);
  vr_out_guard g2;
  vr_out_guard_init(&g2);
  vr_out_guard_database(&g2, newdb);
  assert_int_equal(vr_out_guard_check(&g2, newwal, "-o", &err), VR_E_ARG);
  assert_int_equal(vr_out_guard_check(&g2, fresh, "-o", &err), VR_OK);
  assert_int_equal(vr_out_guard_check(&g, fresh, "--report", &err), VR_OK);
  assert_int_equal(vr_out_guard_check(&g, "-", "-o", &err), VR_OK);
  assert_int_equal(vr_out_guard_check(&g, "", "--db", &err), VR_E_ARG);
  assert_non_null(strstr(err.message, "--db"));
  assert_int_equal(vr_out_guard_check(&g, dir, "-o", &err), VR_E_ARG);
  assert_non_null(strstr(err.message, "is a folder"));
  char missing[160];
  snprintf(missing, sizeof missing, "%s/no/such/out.csv", dir);
  assert_int_equal(vr_out_guard_check(&g, missing, "-o", &err), VR_E_IO);
  assert_non_null(strstr(err.message, "does not exist"));
  assert_int_equal(vr_out_guard_distinct(fresh, "--csv", fresh, "--json", &err), VR_E_ARG);
  assert_int_equal(vr_out_guard_distinct(data, "--csv", hard, "--json", &err), VR_E_ARG);
  assert_int_equal(vr_out_guard_distinct(data, "--csv", fresh, "--json", &err), VR_OK);
  unlink(data), unlink(hard), unlink(sym), unlink(db), unlink(wal);
  rmdir(dir);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(error_messages),
      cmocka_unit_test(atomic_files_appear_whole_or_not_at_all),
      cmocka_unit_test(outputs_never_replace_inputs),
      cmocka_unit_test(progress_line),
      cmocka_unit_test(arguments),
      cmocka_unit_test(sha256_fips_vectors),
      cmocka_unit_test(xxh64_reference_vectors),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
