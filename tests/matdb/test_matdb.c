/* The material database: creation and seeding, versions, the IGDB importer
 * on NFRC 102 and on Windows-1252 names, refusal of foreign, corrupt and
 * newer files (left untouched), read-only opens, validation. */
#include "vr_test.h"
#include "import.h"
#include "utf8.h"
#include "vr/matdb.h"

#include <sqlite3.h>
#include <sys/stat.h>

static char dbdir[64];

static const char *fresh_path(const char *name) {
  static char path[128];
  if (!dbdir[0]) {
    snprintf(dbdir, sizeof dbdir, "/tmp/vr_matdb_XXXXXX");
    if (!mkdtemp(dbdir)) return NULL;
  }
  snprintf(path, sizeof path, "%s/%s", dbdir, name);
  unlink(path);
  return path;
}

static int count_visit(const vr_matdb_entry *e, void *user) {
  (void)e;
  (*(int *)user)++;
  return 0;
}

static void new_database_is_seeded_with_sources(void **state) {
  (void)state;
  vr_matdb *db;
  vr_error err = {0};
  const char *path = fresh_path("seed.db");
  assert_int_equal(vr_matdb_open(path, 0, &db, &err), VR_OK);
  int n = 0;
  assert_int_equal(vr_matdb_list(db, NULL, count_visit, &n, &err), VR_OK);
  /* 24 refractiveindex.info materials (13 glasses, metals, Si, TiO2 and 11
   * lab layers), 27 CIE + 3 ASTM G173 illuminants, 24 ColorChecker
   * patches. */
  assert_int_equal(n, 24 + 30 + 24);
  n = 0;
  assert_int_equal(vr_matdb_list(db, "conductor", count_visit, &n, &err), VR_OK);
  assert_int_equal(n, 4);
  vr_material *m;
  assert_int_equal(vr_matdb_load(db, "N-BK7", 0, &m, &err), VR_OK);
  assert_contains(m->prov.reference, "SCHOTT");
  assert_int_equal(strlen(m->prov.sha256), 64);
  double nn, k;
  /* SCHOTT N-BK7 datasheet: nd = 1.51680 at 587.56 nm. */
  assert_int_equal(vr_material_nk(m, 587.56, false, &nn, &k, NULL, &err), VR_OK);
  assert_near(nn, 1.516800, 1e-6);
  vr_material_destroy(m);
  /* ASTM G173 AM1.5 global integrates to 1000.4 W/m2 over 280-4000 nm
   * (ASTM G173-03 table totals). */
  assert_int_equal(vr_matdb_load(db, "ASTM-G173-AM1.5G", 0, &m, &err), VR_OK);
  assert_near(vr_spectrum_integrate(vr_material_spectrum(m, "value"), VR_TRAPEZOID), 1000.4, 0.5);
  vr_material_destroy(m);
  vr_matdb_close(db);
  /* Reopening does not seed twice. */
  assert_int_equal(vr_matdb_open(path, VR_MATDB_READONLY, &db, &err), VR_OK);
  n = 0;
  assert_int_equal(vr_matdb_list(db, NULL, count_visit, &n, &err), VR_OK);
  assert_int_equal(n, 24 + 30 + 24);
  vr_matdb_close(db);
}

static void versions_history_and_removal(void **state) {
  (void)state;
  vr_matdb *db;
  vr_error err = {0};
  assert_int_equal(vr_matdb_open(fresh_path("versions.db"), 0, &db, &err), VR_OK);
  for (int v = 1; v <= 3; v++) {
    vr_material *m = vr_material_create("white-paint", VR_KIND_REFLECTANCE, NULL);
    vr_material_add_spectrum(m, "value", vr_spectrum_create_uniform(400, 100, 4, 0.8 + 0.05 * v, NULL), NULL);
    vr_material_add_parameter(m, "albedo", 0.8 + 0.05 * v, NAN, NULL, NULL);
    vr_material_set_text(&m->prov.tool, "test", NULL);
    assert_int_equal(vr_matdb_save(db, m, &err), VR_OK);
    assert_int_equal(m->version, v);
    vr_material_destroy(m);
  }
  vr_material *m;
  assert_int_equal(vr_matdb_load(db, "white-paint", 0, &m, &err), VR_OK);
  assert_int_equal(m->version, 3);
  assert_near(m->spectra[0].s->value[0], 0.95, 1e-15);
  assert_true(isnan(m->params[0].stderr_));
  vr_material_destroy(m);
  assert_int_equal(vr_matdb_load(db, "white-paint", 1, &m, &err), VR_OK);
  assert_near(m->spectra[0].s->value[0], 0.85, 1e-15);
  vr_material_destroy(m);
  assert_int_equal(vr_matdb_load(db, "white-paint", 7, &m, &err), VR_E_NOT_FOUND);
  assert_contains(err.message, "no version 7 of material 'white-paint'");
  int n = 0;
  assert_int_equal(vr_matdb_history(db, "white-paint", count_visit, &n, &err), VR_OK);
  assert_int_equal(n, 3);
  int removed;
  assert_int_equal(vr_matdb_remove(db, "white-paint", &removed, &err), VR_OK);
  assert_int_equal(removed, 3);
  assert_int_equal(vr_matdb_load(db, "white-paint", 0, &m, &err), VR_E_NOT_FOUND);
  assert_contains(err.message, "unknown material 'white-paint'");
  assert_int_equal(vr_matdb_remove(db, "white-paint", &removed, &err), VR_E_NOT_FOUND);
  bool ok;
  char report[256];
  assert_int_equal(vr_matdb_check(db, &ok, report, sizeof report, &err), VR_OK);
  assert_true(ok);
  vr_matdb_close(db);
}

static void igdb_nfrc_102(void **state) {
  (void)state;
  /* NFRC 102 "Generic Clear Glass", CLEAR_3.DAT from LBNL's pyWinCalc
   * examples: 111 rows from 0.300 to 2.500 um, 3.048 mm, emissivity 0.84. */
  vr_material *m;
  vr_error err = {0};
  assert_int_equal(vr_import_file(VR_TEST_DATA "/CLEAR_3.DAT", NULL, NULL, "test", &m, &err), VR_OK);
  assert_string_equal(m->name, "CLEAR_3");
  assert_int_equal(m->kind, VR_KIND_GLAZING);
  const vr_spectrum *T = vr_material_spectrum(m, "T");
  assert_int_equal(T->n, 111);
  assert_near(T->nm[0], 300.0, 1e-9);
  assert_near(T->nm[110], 2500.0, 1e-9);
  assert_int_equal(vr_material_spectrum(m, "Rf")->n, 111);
  assert_int_equal(vr_material_spectrum(m, "Rb")->n, 111);
  assert_near(vr_material_property(m, "thickness")->value, 3.048, 1e-12);
  assert_string_equal(vr_material_property(m, "thickness")->unit, "mm");
  assert_near(vr_material_property(m, "emissivity_front")->value, 0.84, 0);
  assert_near(vr_material_property(m, "emissivity_back")->value, 0.84, 0);
  assert_near(vr_material_property(m, "conductivity")->value, 1.0, 0);
  assert_near(vr_material_property(m, "nfrc_id")->value, 102, 0);
  assert_string_equal(vr_material_property(m, "product_name")->text, "Generic Clear Glass");
  assert_string_equal(vr_material_property(m, "manufacturer")->text, "Generic");
  assert_string_equal(vr_material_property(m, "coated_side")->text, "Neither");
  /* Last row of the file: 2.500 0.8220 0.0680 0.0680. */
  assert_near(T->value[110], 0.8220, 0);
  assert_near(vr_material_spectrum(m, "Rb")->value[110], 0.0680, 0);
  assert_int_equal(strlen(m->prov.sha256), 64);
  /* Stored and loaded back, every field survives. */
  vr_matdb *db;
  assert_int_equal(vr_matdb_open(fresh_path("igdb.db"), 0, &db, &err), VR_OK);
  assert_int_equal(vr_matdb_save(db, m, &err), VR_OK);
  vr_material *back;
  assert_int_equal(vr_matdb_load(db, "CLEAR_3", 0, &back, &err), VR_OK);
  assert_int_equal(back->nprops, m->nprops);
  for (size_t i = 0; i < m->nprops; i++) {
    assert_string_equal(back->props[i].key, m->props[i].key);
    if (m->props[i].text) assert_string_equal(back->props[i].text, m->props[i].text);
    if (isfinite(m->props[i].value)) assert_true(back->props[i].value == m->props[i].value);
  }
  for (size_t j = 0; j < T->n; j++) assert_true(vr_material_spectrum(back, "T")->value[j] == T->value[j]);
  assert_string_equal(back->prov.sha256, m->prov.sha256);
  vr_material_destroy(back);
  vr_material_destroy(m);
  vr_matdb_close(db);
}

static void igdb_bad_input(void **state) {
  (void)state;
  vr_error err = {0};
  struct { const char *text, *expect; } cases[] = {
      {"{ Thickness } 3\n0.30 0.5 0.1 0.1\n0.31 0.6 abc 0.1\n", ":3: field 'Rf': expected a number, got 'abc'"},
      {"{ Thickness } -3\n0.30 0.5 0.1 0.1\n", ":1: field 'Thickness': -3 mm must be positive"},
      {"0.30 0.5 0.1 0.1\n", "no '{ Thickness }' header line"},
      {"{ Thickness } 3\n0.30 0.95 0.1 0.1\n", ":2: T + R = 1.05 exceeds 1"},
      {"{ Thickness } 3\n0.30 0.5 0.1 0.1\n0.30 0.5 0.1 0.1\n", ":3: field 'wavelength': 0.3 does not increase"},
      {"{ Thickness } 3\n0.30 0.5 0.1\n", ":2: field 'Rb' is missing"},
      {"{ Thickness } 3\n0.30 nan 0.1 0.1\n", ":2: field 'T': 'nan' is not a finite number"},
      {"{ Thickness } 3\n", "no data rows"},
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
    vr_material *m = vr_material_create("x", VR_KIND_GLAZING, NULL);
    vr_status st = vr_igdb_parse(cases[i].text, strlen(cases[i].text), "bad.DAT", m, &err);
    if (st == VR_OK) fail_msg("case %zu parsed", i);
    assert_contains(err.message, "bad.DAT");
    assert_contains(err.message, cases[i].expect);
    vr_material_destroy(m);
  }
}

static void refuses_foreign_corrupt_and_newer_files(void **state) {
  (void)state;
  vr_matdb *db;
  vr_error err = {0};
  /* Not SQLite at all. */
  const char *garbage = fresh_path("garbage.db");
  FILE *f = fopen(garbage, "wb");
  for (int i = 0; i < 4096; i++) fputc((i * 37) & 0xff, f);
  fclose(f);
  assert_int_equal(vr_matdb_open(garbage, 0, &db, &err), VR_E_DB);
  assert_contains(err.message, "not a SQLite database");
  /* A SQLite file of someone else's. */
  const char *foreign = fresh_path("foreign.db");
  sqlite3 *s;
  sqlite3_open(foreign, &s);
  sqlite3_exec(s, "CREATE TABLE invoices (id INTEGER)", NULL, NULL, NULL);
  sqlite3_close(s);
  assert_int_equal(vr_matdb_open(foreign, 0, &db, &err), VR_E_DB);
  assert_contains(err.message, "not a Virtuelium-C material database");
  assert_int_equal(vr_matdb_open(foreign, VR_MATDB_READONLY, &db, &err), VR_E_DB);
  /* A newer schema. */
  const char *newer = fresh_path("newer.db");
  assert_int_equal(vr_matdb_open(newer, 0, &db, &err), VR_OK);
  vr_matdb_close(db);
  sqlite3_open(newer, &s);
  sqlite3_exec(s, "PRAGMA user_version = 99", NULL, NULL, NULL);
  sqlite3_close(s);
  assert_int_equal(vr_matdb_open(newer, 0, &db, &err), VR_E_DB);
  assert_contains(err.message, "newer Virtuelium-C (schema 99");
  assert_int_equal(vr_matdb_open(newer, VR_MATDB_READONLY, &db, &err), VR_E_DB);
  /* Missing file, read-only. */
  assert_int_equal(vr_matdb_open(fresh_path("missing.db"), VR_MATDB_READONLY, &db, &err), VR_E_IO);
}

static void validation_before_writing(void **state) {
  (void)state;
  vr_matdb *db;
  vr_error err = {0};
  assert_int_equal(vr_matdb_open(fresh_path("valid.db"), 0, &db, &err), VR_OK);
  vr_material *m = vr_material_create("bad-glass", VR_KIND_DIELECTRIC, NULL);
  assert_int_equal(vr_matdb_save(db, m, &err), VR_E_NOT_FOUND);
  assert_contains(err.message, "has no refractive index");
  double nm[] = {400, 500}, n[] = {1.5, 1.5}, k[] = {0.0, -1e-3};
  vr_material_add_spectrum(m, "n", vr_spectrum_create(2, nm, n, NULL), NULL);
  vr_material_add_spectrum(m, "k", vr_spectrum_create(2, nm, k, NULL), NULL);
  assert_int_equal(vr_matdb_save(db, m, &err), VR_E_RANGE);
  assert_contains(err.message, "k = -0.001 at 500 nm is negative");
  vr_material_destroy(m);
  m = vr_material_create("pane", VR_KIND_GLAZING, NULL);
  vr_material_add_spectrum(m, "T", vr_spectrum_create(2, nm, n, NULL), NULL);
  assert_int_equal(vr_matdb_save(db, m, &err), VR_E_ARG);
  assert_contains(err.message, "needs T, Rf and Rb");
  vr_material_destroy(m);
  m = vr_material_create("film", VR_KIND_DIELECTRIC, NULL);
  vr_material_add_spectrum(m, "n", vr_spectrum_create(2, nm, n, NULL), NULL);
  vr_material_add_property(m, "thickness", NULL, -5, "nm", NULL);
  assert_int_equal(vr_matdb_save(db, m, &err), VR_E_RANGE);
  assert_contains(err.message, "negative thickness (-5)");
  vr_material_destroy(m);
  int count = 0;
  assert_int_equal(vr_matdb_list(db, "glazing", count_visit, &count, &err), VR_OK);
  assert_int_equal(count, 0);
  vr_matdb_close(db);
}

/* The layers of ellipsometry labs in the built-in library give their
 * authors' values: Sellmeier formulas evaluated here from the published
 * coefficients, tables at one of their rows (matdb/data/SOURCES.md). */
static double sellmeier(double um, const double *b, const double *c, int terms, bool squared) {
  double l2 = um * um, n2 = 1;
  for (int i = 0; i < terms; i++) n2 += b[i] * l2 / (l2 - (squared ? c[i] * c[i] : c[i]));
  return sqrt(n2);
}

static void lab_layers_match_their_sources(void **state) {
  (void)state;
  vr_matdb *db;
  vr_error err = {0};
  assert_int_equal(vr_matdb_open(fresh_path("layers.db"), 0, &db, &err), VR_OK);
  /* Luke et al., Opt. Lett. 40, 4823 (2015), Si3N4 */
  const double luke_b[2] = {3.0249, 40314}, luke_c[2] = {0.1353406, 1239.842};
  /* Malitson & Dodge, JOSA 62, 1405 (1972), sapphire ordinary ray */
  const double mal_b[3] = {1.4313493, 0.65054713, 5.3414021}, mal_c[3] = {0.0726631, 0.1193242, 18.028251};
  /* Daimon & Masumura, Appl. Opt. 46, 3811 (2007), water at 20 °C (C in µm²) */
  const double dai_b[4] = {5.684027565e-1, 1.726177391e-1, 2.086189578e-2, 1.130748688e-1},
               dai_c[4] = {5.101829712e-3, 1.821153936e-2, 2.620722293e-2, 1.069792721e1};
  /* Sultanova et al., Acta Phys. Pol. A 116, 585 (2009), PMMA (C in µm²) */
  const double sul_b[1] = {1.1819}, sul_c[1] = {0.011313};
  const struct {
    const char *name;
    double um, n, k;
  } cases[] = {
      {"Si3N4", 0.6328, sellmeier(0.6328, luke_b, luke_c, 2, true), 0},
      {"Al2O3", 0.6328, sellmeier(0.6328, mal_b, mal_c, 3, true), 0},
      {"water", 0.5893, sellmeier(0.5893, dai_b, dai_c, 4, false), 0},
      {"PMMA", 0.5893, sellmeier(0.5893, sul_b, sul_c, 1, false), 0},
      /* Aspnes, Kelso, Logan & Bhat, J. Appl. Phys. 60, 754 (1986): the
       * row 0.6199 µm: n 3.878, k 0.211 */
      {"GaAs", 0.6199, 3.878, 0.211},
  };
  for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
    vr_material *m = NULL;
    if (vr_matdb_load(db, cases[i].name, 0, &m, &err)) fail_msg("%s", err.message);
    double n, k;
    if (vr_material_nk(m, cases[i].um * 1000, false, &n, &k, NULL, &err)) fail_msg("%s", err.message);
    assert_near(n, cases[i].n, 1e-9);
    assert_near(k, cases[i].k, 1e-12);
    vr_material_destroy(m);
  }
  vr_matdb_close(db);
}

/* The whole content of a file, for before/after comparisons. */
static char *slurp(const char *path, size_t *len) {
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  fseek(f, 0, SEEK_END);
  long n = ftell(f);
  fseek(f, 0, SEEK_SET);
  char *buf = malloc((size_t)n + 1);
  *len = fread(buf, 1, (size_t)n, f);
  fclose(f);
  return buf;
}

static void assert_unchanged(const char *path, const char *before, size_t len) {
  size_t n;
  char *now = slurp(path, &n);
  assert_non_null(now);
  assert_int_equal(n, len);
  assert_memory_equal(now, before, len);
  free(now);
}

/* Issue 18: a file that is not a material database is refused before
 * anything is written to it, whatever its journal mode; its bytes, its
 * journal mode (byte 18 of the SQLite header: 1 rollback, 2 WAL) and its
 * folder stay as they were. */
static void foreign_files_are_left_untouched(void **state) {
  (void)state;
  vr_matdb *db;
  vr_error err = {0};
  const char *modes[] = {"DELETE", "WAL"};
  for (int i = 0; i < 2; i++) {
    char name[32];
    snprintf(name, sizeof name, "foreign_%s.db", modes[i]);
    char path[128];
    snprintf(path, sizeof path, "%s", fresh_path(name));
    sqlite3 *s;
    char sql[160];
    snprintf(sql, sizeof sql,
             "PRAGMA journal_mode = %s; CREATE TABLE invoices (id INTEGER, amount REAL);"
             " INSERT INTO invoices VALUES (1, 2.5);", modes[i]);
    assert_int_equal(sqlite3_open(path, &s), SQLITE_OK);
    assert_int_equal(sqlite3_exec(s, sql, NULL, NULL, NULL), SQLITE_OK);
    sqlite3_close(s);
    size_t len;
    char *before = slurp(path, &len);
    assert_int_equal((unsigned char)before[18], i + 1);
    for (int ro = 0; ro < 2; ro++) {
      assert_int_equal(vr_matdb_open(path, ro ? VR_MATDB_READONLY : 0, &db, &err), VR_E_DB);
      assert_contains(err.message, path);
      assert_contains(err.message, "not a Virtuelium-C material database");
      assert_unchanged(path, before, len);
      /* ... and nothing appears beside it. */
      char side[160];
      struct stat sb;
      snprintf(side, sizeof side, "%s-wal", path);
      assert_int_not_equal(stat(side, &sb), 0);
      snprintf(side, sizeof side, "%s-shm", path);
      assert_int_not_equal(stat(side, &sb), 0);
    }
    free(before);
  }
  /* A CSV file given as the database. */
  const char *csv = fresh_path("spectrum.csv");
  FILE *f = fopen(csv, "wb");
  fputs("nm,value\n400,0.5\n410,0.6\n", f);
  fclose(f);
  size_t len;
  char *before = slurp(csv, &len);
  assert_int_equal(vr_matdb_open(csv, 0, &db, &err), VR_E_DB);
  assert_contains(err.message, "not a SQLite database");
  assert_unchanged(csv, before, len);
  free(before);
  /* The empty path names no file; NULL means the default. */
  assert_int_equal(vr_matdb_open("", 0, &db, &err), VR_E_ARG);
  assert_contains(err.message, "the material database path is empty");
  /* A folder. */
  assert_int_equal(vr_matdb_open(dbdir, 0, &db, &err), VR_E_IO);
  assert_contains(err.message, "is a folder");
}

/* A 0-byte file (touch, mktemp) and a SQLite file without tables are new
 * databases: created and seeded. */
static void empty_files_become_databases(void **state) {
  (void)state;
  vr_matdb *db;
  vr_error err = {0};
  const char *zero = fresh_path("zero.db");
  fclose(fopen(zero, "wb"));
  assert_int_equal(vr_matdb_open(zero, VR_MATDB_READONLY, &db, &err), VR_E_DB);
  assert_contains(err.message, "an empty file, not a material database");
  assert_int_equal(vr_matdb_open(zero, 0, &db, &err), VR_OK);
  int n = 0;
  assert_int_equal(vr_matdb_list(db, NULL, count_visit, &n, &err), VR_OK);
  assert_int_equal(n, 24 + 30 + 24);
  assert_null(vr_matdb_readonly(db));
  vr_matdb_close(db);
  const char *blank = fresh_path("blank.db");
  sqlite3 *s;
  sqlite3_open(blank, &s);
  sqlite3_exec(s, "PRAGMA user_version = 0; VACUUM;", NULL, NULL, NULL);
  sqlite3_close(s);
  assert_int_equal(vr_matdb_open(blank, 0, &db, &err), VR_OK);
  vr_matdb_close(db);
}

/* Read-only opens read, never write: a rollback-journal database stays in
 * rollback mode (header byte 18 = 1), and saves and removals say it is
 * read-only, naming the file. */
static void read_only_open_reads_and_refuses_writes(void **state) {
  (void)state;
  vr_matdb *db;
  vr_error err = {0};
  const char *path = fresh_path("ro.db");
  assert_int_equal(vr_matdb_open(path, 0, &db, &err), VR_OK);
  vr_matdb_close(db);
  sqlite3 *s;
  sqlite3_open(path, &s);
  assert_int_equal(sqlite3_exec(s, "PRAGMA journal_mode = DELETE", NULL, NULL, NULL), SQLITE_OK);
  sqlite3_close(s);
  size_t len;
  char *before = slurp(path, &len);
  assert_int_equal((unsigned char)before[18], 1);
  assert_int_equal(vr_matdb_open(path, VR_MATDB_READONLY, &db, &err), VR_OK);
  assert_string_equal(vr_matdb_readonly(db), "opened for reading only");
  vr_material *m;
  assert_int_equal(vr_matdb_load(db, "N-BK7", 0, &m, &err), VR_OK);
  m->version = 0;
  assert_int_equal(vr_matdb_save(db, m, &err), VR_E_DB);
  assert_contains(err.message, path);
  assert_contains(err.message, "the material database is read-only (opened for reading only)");
  vr_material_destroy(m);
  int removed = -1;
  assert_int_equal(vr_matdb_remove(db, "N-BK7", &removed, &err), VR_E_DB);
  assert_contains(err.message, "is read-only");
  assert_int_equal(removed, 0);
  bool ok;
  char report[256];
  assert_int_equal(vr_matdb_check(db, &ok, report, sizeof report, &err), VR_OK);
  assert_true(ok);
  vr_matdb_close(db);
  assert_unchanged(path, before, len);
  free(before);
}

/* UTF-8 by RFC 3629 and Windows-1252 by the Unicode Consortium's mapping
 * table (MAPPINGS/VENDORS/MICSFT/WINDOWS/CP1252.TXT): 0x80 -> U+20AC,
 * 0x93 -> U+201C, 0x94 -> U+201D, 0xAE -> U+00AE, 0xE9 -> U+00E9; 0x81 is
 * undefined there. */
static void text_encodings(void **state) {
  (void)state;
  size_t bad = 99;
  const char *good = "Cr\xC3\xA9" "ation \xE2\x82\xAC";
  assert_true(vr_utf8_valid(good, strlen(good), NULL));
  assert_false(vr_utf8_valid("ab\xC0\xAF", 4, &bad)); /* overlong '/' */
  assert_int_equal(bad, 2);
  assert_false(vr_utf8_valid("\xED\xA0\x80", 3, &bad)); /* a surrogate */
  assert_false(vr_utf8_valid("\xF4\x90\x80\x80", 4, &bad)); /* past U+10FFFF */
  assert_false(vr_utf8_valid("x\xC3", 2, &bad)); /* cut short */
  assert_int_equal(bad, 1);
  char *u = vr_cp1252_to_utf8("\x80\x81\x93\x94\xAE\xE9", 6, NULL);
  assert_string_equal(u, "\xE2\x82\xAC\xEF\xBF\xBD\xE2\x80\x9C\xE2\x80\x9D\xC2\xAE\xC3\xA9");
  free(u);
  u = vr_utf8_sanitize("a\xE9z");
  assert_string_equal(u, "a\xEF\xBF\xBDz");
  free(u);
}

/* IGDB product names in Windows-1252 arrive as UTF-8; a UTF-8 file (with a
 * byte-order mark) is kept as it is; the database refuses a text that is
 * not UTF-8. */
static void igdb_windows_1252_names(void **state) {
  (void)state;
  vr_error err = {0};
  static const char *const files[] = {
      "{ Thickness } 3\n{ Product Name: Cr\xE9" "ation\xAE \x93" "Clear\x94 }\n0.30 0.5 0.1 0.1\n"
      "0.40 0.6 0.1 0.1\n0.50 0.7 0.1 0.1\n",
      "\xEF\xBB\xBF{ Thickness } 3\n{ Product Name: Cr\xC3\xA9" "ation\xC2\xAE \xE2\x80\x9C" "Clear\xE2\x80\x9D }\n"
      "0.30 0.5 0.1 0.1\n0.40 0.6 0.1 0.1\n0.50 0.7 0.1 0.1\n"};
  for (int i = 0; i < 2; i++) {
    vr_material *m = vr_material_create("pane", VR_KIND_GLAZING, NULL);
    assert_int_equal(vr_igdb_parse(files[i], strlen(files[i]), "cp.DAT", m, &err), VR_OK);
    assert_string_equal(vr_material_property(m, "product_name")->text,
                        "Cr\xC3\xA9" "ation\xC2\xAE \xE2\x80\x9C" "Clear\xE2\x80\x9D");
    assert_string_equal(m->description, "Cr\xC3\xA9" "ation\xC2\xAE \xE2\x80\x9C" "Clear\xE2\x80\x9D");
    vr_material_destroy(m);
  }
  vr_matdb *db;
  assert_int_equal(vr_matdb_open(fresh_path("utf8.db"), 0, &db, &err), VR_OK);
  vr_material *m = vr_material_create("pane", VR_KIND_REFLECTANCE, NULL);
  double nm[] = {400, 500}, v[] = {0.5, 0.5};
  vr_material_add_spectrum(m, "value", vr_spectrum_create(2, nm, v, NULL), NULL);
  vr_material_add_property(m, "product_name", "Cr\xE9" "ation", NAN, NULL, NULL);
  assert_int_equal(vr_matdb_save(db, m, &err), VR_E_ARG);
  assert_contains(err.message, "material 'pane': property 'product_name' is not valid UTF-8 (byte 2: 0xE9)");
  vr_material_destroy(m);
  m = vr_material_create("Cr\xE9" "ation", VR_KIND_REFLECTANCE, NULL);
  vr_material_add_spectrum(m, "value", vr_spectrum_create(2, nm, v, NULL), NULL);
  assert_int_equal(vr_matdb_save(db, m, &err), VR_E_ARG);
  assert_contains(err.message, "the name is not valid UTF-8 (byte 2: 0xE9)");
  vr_material_destroy(m);
  vr_matdb_close(db);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(new_database_is_seeded_with_sources),
      cmocka_unit_test(lab_layers_match_their_sources),
      cmocka_unit_test(versions_history_and_removal),
      cmocka_unit_test(igdb_nfrc_102),
      cmocka_unit_test(igdb_bad_input),
      cmocka_unit_test(refuses_foreign_corrupt_and_newer_files),
      cmocka_unit_test(validation_before_writing),
      cmocka_unit_test(foreign_files_are_left_untouched),
      cmocka_unit_test(empty_files_become_databases),
      cmocka_unit_test(read_only_open_reads_and_refuses_writes),
      cmocka_unit_test(text_encodings),
      cmocka_unit_test(igdb_windows_1252_names),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
