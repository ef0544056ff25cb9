/* Capture manifests: the grammar, resolution of lights and references,
 * errors that name the manifest, line and column, and manifests read from a
 * pipe, a FIFO or standard input (whose relative paths are the working
 * directory's, vr/manifest.h). */
#include "vr_test.h"
#include "vr/colour.h"
#include "vr/manifest.h"
#include "vr/matdb.h"
#include "vr/sha256.h"

#include <errno.h>
#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <sys/stat.h>

static vr_status parse(const char *text, vr_capture **c, vr_error *err) {
  return vr_capture_parse(text, strlen(text), "/photos/capture.txt", NULL, c, err);
}

static void good_manifest(void **state) {
  (void)state;
  vr_capture *c;
  vr_error err = {0};
  assert_int_equal(parse("# a capture\ncamera cie1931-srgb\ngrid 380 730 10\n"
                         "photo d65.png light=D65\nphoto a.png light=A scale=0.5 encoding=linear clip=0.95\n"
                         "chart grid=10,20,610,420\nregion wall rect=5,5,20,10\n", &c, &err), VR_OK);
  assert_int_equal(c->nphotos, 2);
  assert_string_equal(c->photos[0].path, "/photos/d65.png");
  /* CIE D65 at 560 nm is 100.0 by definition of its normalisation (CIE 015:2018 Table 5). */
  assert_near(vr_spectrum_eval(c->photos[0].light, 560, VR_INTERP_LINEAR), 100.0, 1e-9);
  assert_near(c->photos[1].scale, 0.5, 0);
  assert_int_equal(c->photos[1].encoding, 2);
  assert_int_equal(c->nregions, 25);
  assert_string_equal(c->regions[0].name, "patch-01");
  assert_non_null(c->regions[23].reference);
  assert_int_equal(c->regions[24].w, 20);
  assert_near(c->grid[0], 380, 0);
  assert_non_null(vr_capture_find_photo(c, "elsewhere/a.png"));
  assert_null(vr_capture_find_photo(c, "b.png"));
  vr_capture_destroy(c);
}

/* A UTF-8 byte-order mark, as Windows editors write one, is skipped; the
 * hash is still that of the bytes as read. */
static void byte_order_mark(void **state) {
  (void)state;
  const char text[] = "\xEF\xBB\xBF" "photo d65.png light=D65\nregion wall rect=5,5,20,10\n";
  vr_capture *c = NULL;
  vr_error err = {0};
  assert_int_equal(vr_capture_parse(text, strlen(text), "/photos/capture.txt", NULL, &c, &err), VR_OK);
  assert_int_equal(c->nphotos, 1);
  assert_string_equal(c->photos[0].path, "/photos/d65.png");
  char hex[65];
  vr_sha256_buffer(text, strlen(text), hex);
  assert_string_equal(c->sha256, hex);
  vr_capture_destroy(c);
  /* Only at the start: elsewhere it is an unknown statement, as before. */
  const char later[] = "photo d65.png light=D65\n\xEF\xBB\xBF" "region wall rect=5,5,20,10\n";
  assert_int_not_equal(vr_capture_parse(later, strlen(later), "/photos/capture.txt", NULL, &c, &err), VR_OK);
  assert_contains(err.message, "capture.txt:2:1: unknown statement");
}

static void errors(void **state) {
  (void)state;
  vr_capture *c = NULL;
  vr_error err = {0};
  assert_int_not_equal(parse("photo d65.png light=D99x\n", &c, &err), VR_OK);
  assert_contains(err.message, "capture.txt:1:15");
  assert_contains(err.message, "unknown light");
  assert_int_not_equal(parse("photo d65.png\n", &c, &err), VR_OK);
  assert_contains(err.message, "no light=");
  assert_int_not_equal(parse("photo a.png light=A\nphoto a.png light=D65\n", &c, &err), VR_OK);
  assert_contains(err.message, "listed twice");
  assert_int_not_equal(parse("photo a.png light=A\nregion x rect=1,2,3\n", &c, &err), VR_OK);
  assert_contains(err.message, "capture.txt:2:10");
  assert_int_not_equal(parse("photo a.png light=A\nregion x label=3\n", &c, &err), VR_OK);
  assert_contains(err.message, "labels FILE");
  assert_int_not_equal(parse("photo a.png light=db:X\n", &c, &err), VR_OK);
  assert_contains(err.message, "--db");
  assert_int_not_equal(parse("phot a.png\n", &c, &err), VR_OK);
  assert_contains(err.message, "unknown statement");
  assert_int_not_equal(parse("camera cie1931-srgb\n", &c, &err), VR_OK);
  assert_contains(err.message, "no 'photo' lines");
  /* Found by fuzz_manifest: a repeated key leaked the first value. */
  assert_int_not_equal(parse("photo a.png light=A light=D65\n", &c, &err), VR_OK);
  assert_contains(err.message, "capture.txt:1:21");
  assert_contains(err.message, "twice");
  assert_int_not_equal(parse("photo a.png light=A scale=-1\n", &c, &err), VR_OK);
  assert_contains(err.message, "scale=-1");
  assert_null(c);
}

/* Double quotes keep a path's spaces and '#' and are dropped (issue 35:
 * a photo named with a space could not be listed); '#' outside them is a
 * comment; columns count in the line as written. */
static void quoted_paths(void **state) {
  (void)state;
  vr_capture *c = NULL;
  vr_error err = {0};
  assert_int_equal(parse("photo \"d65 #1.png\" light=D65 # the first\n"
                         "photo a.png light=A scale=\"0.5\"\nregion wall rect=5,5,20,10\n", &c, &err),
                   VR_OK);
  assert_string_equal(c->photos[0].path, "/photos/d65 #1.png");
  assert_near(c->photos[1].scale, 0.5, 0);
  vr_capture_destroy(c);
  c = NULL;
  /* The column of a word after a quoted one is its column as written. */
  assert_int_not_equal(parse("photo \"a b.png\" light=D99x\n", &c, &err), VR_OK);
  assert_contains(err.message, "capture.txt:1:17");
  assert_int_not_equal(parse("photo \"a b.png light=A\n", &c, &err), VR_OK);
  assert_contains(err.message, "capture.txt:1:7: a double quote opened here is not closed");
  assert_int_not_equal(parse("photo \"\" light=A\n", &c, &err), VR_OK);
  assert_contains(err.message, "capture.txt:1:7: an empty");
  assert_int_not_equal(parse("photo a.png light=A\nregion \"a=b\" rect=1,2,3,4\n", &c, &err), VR_OK);
  assert_contains(err.message, "one word");
  assert_null(c);
}

/* A writer thread feeding a pipe or a FIFO, as a shell's `cat m | ...`
 * does: the reader must take everything up to end of file, whatever the
 * pipe's buffer holds at once (64 KiB on Linux, pipe(7)). */
typedef struct feeder {
  int fd;               /* write end; -1: open fifo first */
  const char *fifo;
  const char *text;
  size_t len;
  size_t written;
  pthread_t thread;
} feeder;

static void *feed(void *arg) {
  feeder *f = arg;
  if (f->fd < 0) f->fd = open(f->fifo, O_WRONLY); /* blocks until the reader opens it */
  while (f->fd >= 0 && f->written < f->len) {
    ssize_t n = write(f->fd, f->text + f->written, f->len - f->written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break; /* EPIPE: the reader stopped early */
    f->written += (size_t)n;
  }
  if (f->fd >= 0) close(f->fd);
  return NULL;
}

/* Starts feeding text into a new pipe; returns the read end. */
static int start_pipe(feeder *f, const char *text, size_t len) {
  int fds[2];
  assert_int_equal(pipe(fds), 0);
  *f = (feeder){.fd = fds[1], .text = text, .len = len};
  assert_int_equal(pthread_create(&f->thread, NULL, feed, f), 0);
  return fds[0];
}

/* A manifest far longer than a pipe's buffer: 4000 comment lines first. */
static char *long_manifest(const char *body, size_t *len) {
  const char *comment = "# padding: the writer must wait for the reader to drain the pipe\n";
  size_t n = 4000 * strlen(comment) + strlen(body);
  char *t = malloc(n + 1), *q = t;
  assert_non_null(t);
  for (int i = 0; i < 4000; i++) q += sprintf(q, "%s", comment);
  strcpy(q, body);
  *len = n;
  return t;
}

static const char PIPE_BODY[] = "camera cie1931-srgb\nphoto d65.png light=D65\n"
                                "photo sub/a.png light=A\nregion w rect=1,2,3,4\n";

static void manifest_from_a_pipe(void **state) {
  (void)state;
  size_t len;
  char *text = long_manifest(PIPE_BODY, &len);
  assert_true(len > 3 * 65536); /* three pipe buffers of Linux (pipe(7)) */
  feeder f;
  int rd = start_pipe(&f, text, len);
  char path[32];
  snprintf(path, sizeof path, "/dev/fd/%d", rd);
  vr_capture *c = NULL;
  vr_error err = {0};
  assert_int_equal(vr_capture_read(path, NULL, &c, &err), VR_OK);
  pthread_join(f.thread, NULL);
  close(rd);
  assert_int_equal(f.written, len);
  assert_int_equal(c->nphotos, 2);
  /* Relative paths stay relative: the working directory's, not /dev/fd's. */
  assert_string_equal(c->photos[0].path, "d65.png");
  assert_string_equal(c->photos[1].path, "sub/a.png");
  assert_string_equal(c->dir, "");
  assert_true(c->stream);
  assert_string_equal(c->path, path);
  /* The hash of the bytes read, all of them. */
  char want[65];
  vr_sha256_buffer(text, len, want);
  assert_string_equal(c->sha256, want);
  assert_int_equal(c->photos[1].line, 4003); /* 4000 comment lines, camera, photo, photo */
  vr_capture_destroy(c);

  /* Errors name the manifest as given, with line and column. */
  static const char bad[] = "camera cie1931-srgb\nphoto d65.png light=D65\nphoto a.png light=Q\n";
  rd = start_pipe(&f, bad, strlen(bad));
  snprintf(path, sizeof path, "/dev/fd/%d", rd);
  assert_int_equal(vr_capture_read(path, NULL, &c, &err), VR_E_NOT_FOUND);
  pthread_join(f.thread, NULL);
  close(rd);
  char where[96];
  snprintf(where, sizeof where, "%s:3:13: unknown light", path);
  assert_contains(err.message, where);
  assert_null(c);
  free(text);
}

/* Makes the read end rd standard input (it may already be fd 0 when the
 * test runs with standard input closed). */
static void as_stdin(int rd) {
  if (rd != 0) {
    assert_int_equal(dup2(rd, 0), 0);
    close(rd);
  }
  clearerr(stdin);
}

/* "-" is standard input, named "<stdin>"; stdin is swapped for a pipe and
 * put back. */
static void manifest_from_stdin(void **state) {
  (void)state;
  int saved = dup(0); /* -1 when run with standard input closed: closed again after */
  feeder f;
  as_stdin(start_pipe(&f, PIPE_BODY, strlen(PIPE_BODY)));
  vr_capture *c = NULL;
  vr_error err = {0};
  vr_status st = vr_capture_read("-", NULL, &c, &err);
  pthread_join(f.thread, NULL);
  static const char bad[] = "photo a.png light=A\nphoto b.png lite=D65\n";
  as_stdin(start_pipe(&f, bad, strlen(bad)));
  vr_capture *c2 = NULL;
  vr_status st2 = vr_capture_read("-", NULL, &c2, &err);
  pthread_join(f.thread, NULL);
  if (saved >= 0) {
    assert_int_equal(dup2(saved, 0), 0);
    close(saved);
  } else {
    close(0);
  }
  clearerr(stdin);
  assert_int_equal(st, VR_OK);
  assert_string_equal(c->path, "<stdin>");
  assert_true(c->stream);
  assert_string_equal(c->photos[1].path, "sub/a.png");
  vr_capture_destroy(c);
  assert_int_not_equal(st2, VR_OK);
  assert_contains(err.message, "<stdin>:2:13:");
}

/* A named FIFO in some folder is still a stream: relative paths are the
 * working directory's.  A regular file next to it keeps its folder. */
static void manifest_from_a_fifo(void **state) {
  (void)state;
  char dir[] = "/tmp/vr_fifo_XXXXXX";
  assert_non_null(mkdtemp(dir));
  char fifo[64], file[64];
  snprintf(fifo, sizeof fifo, "%s/m.fifo", dir);
  snprintf(file, sizeof file, "%s/m.txt", dir);
  assert_int_equal(mkfifo(fifo, 0600), 0);
  feeder f = {.fd = -1, .fifo = fifo, .text = PIPE_BODY, .len = strlen(PIPE_BODY)};
  assert_int_equal(pthread_create(&f.thread, NULL, feed, &f), 0);
  vr_capture *c = NULL;
  vr_error err = {0};
  assert_int_equal(vr_capture_read(fifo, NULL, &c, &err), VR_OK);
  pthread_join(f.thread, NULL);
  assert_string_equal(c->photos[0].path, "d65.png");
  assert_true(c->stream);
  vr_capture_destroy(c);

  FILE *fp = fopen(file, "w");
  assert_non_null(fp);
  fputs(PIPE_BODY, fp);
  fclose(fp);
  assert_int_equal(vr_capture_read(file, NULL, &c, &err), VR_OK);
  char want[80];
  snprintf(want, sizeof want, "%s/sub/a.png", dir);
  assert_string_equal(c->photos[1].path, want);
  assert_false(c->stream);
  vr_capture_destroy(c);
  unlink(fifo);
  unlink(file);
  rmdir(dir);
}

/* The 1 MiB limit holds for a pipe too: the reader stops and says so (the
 * writer then gets EPIPE, hence SIGPIPE ignored). */
static void pipe_size_limit(void **state) {
  (void)state;
  signal(SIGPIPE, SIG_IGN);
  size_t len = (1u << 20) + 4096;
  char *text = malloc(len);
  assert_non_null(text);
  for (size_t i = 0; i < len; i++) text[i] = (i % 64 == 63) ? '\n' : '#';
  feeder f;
  int rd = start_pipe(&f, text, len);
  char path[32];
  snprintf(path, sizeof path, "/dev/fd/%d", rd);
  vr_capture *c = NULL;
  vr_error err = {0};
  assert_int_equal(vr_capture_read(path, NULL, &c, &err), VR_E_RANGE);
  close(rd);
  pthread_join(f.thread, NULL);
  assert_contains(err.message, "larger than 1048576 bytes");
  free(text);
}

/* vr_capture_read_db reads a pipe once and opens the database only when
 * the text names db: (outside comments) or the caller needs it. */
static void read_db_from_a_pipe(void **state) {
  (void)state;
  char dir[] = "/tmp/vr_mdb_XXXXXX";
  assert_non_null(mkdtemp(dir));
  char dbpath[64];
  snprintf(dbpath, sizeof dbpath, "%s/m.db", dir);
  static const char no_db[] = "# not db:X, a comment\nphoto a.png light=A\n";
  feeder f;
  int rd = start_pipe(&f, no_db, strlen(no_db));
  char path[32];
  snprintf(path, sizeof path, "/dev/fd/%d", rd);
  vr_matdb *db = NULL;
  vr_capture *c = NULL;
  vr_error err = {0};
  assert_int_equal(vr_capture_read_db(path, dbpath, 0, false, &db, &c, &err), VR_OK);
  pthread_join(f.thread, NULL);
  close(rd);
  assert_null(db);
  assert_int_equal(access(dbpath, F_OK), -1); /* no database file made */
  vr_capture_destroy(c);

  static const char with_db[] = "photo a.png light=db:no-such-light\n";
  rd = start_pipe(&f, with_db, strlen(with_db));
  snprintf(path, sizeof path, "/dev/fd/%d", rd);
  assert_int_not_equal(vr_capture_read_db(path, dbpath, 0, false, &db, &c, &err), VR_OK);
  pthread_join(f.thread, NULL);
  close(rd);
  /* The database was opened (so the text was seen), the parser then read
   * the same text (the error is at line 1, column 13, not "no 'photo'
   * lines" from an emptied pipe). */
  assert_non_null(db);
  assert_contains(err.message, ":1:13:");
  assert_contains(err.message, "no-such-light");
  assert_null(c);
  vr_matdb_close(db);
  static const char *const suffixes[] = {"", "-journal", "-wal", "-shm"};
  for (size_t i = 0; i < 4; i++) {
    char file[80];
    snprintf(file, sizeof file, "%s%s", dbpath, suffixes[i]);
    unlink(file);
  }
  assert_int_equal(rmdir(dir), 0);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(good_manifest),        cmocka_unit_test(byte_order_mark), cmocka_unit_test(errors),
      cmocka_unit_test(quoted_paths),
      cmocka_unit_test(manifest_from_a_pipe), cmocka_unit_test(manifest_from_stdin),
      cmocka_unit_test(manifest_from_a_fifo), cmocka_unit_test(pipe_size_limit),
      cmocka_unit_test(read_db_from_a_pipe),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
