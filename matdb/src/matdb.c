/* The material database on SQLite: opening (with schema creation, version
 * checks and seeding), and whole-transaction saves and loads of materials.
 *
 * Schema version 1.  Spectra are stored one sample per row (material, role,
 * index, nm, value) so that any SQLite client can inspect them; REAL columns
 * keep every bit of a double.  SQLite stores NaN as NULL, which is how
 * "unknown" (a residual, an uncertainty, a text-only property) is kept. */
#include "matdb_internal.h"
#include "vr/chromogenic.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#define APPLICATION_ID 0x5652444d /* "VRDM" */

static const char *SCHEMA_V1[] = {
    "CREATE TABLE material ("
    " id INTEGER PRIMARY KEY, name TEXT NOT NULL, version INTEGER NOT NULL,"
    " kind TEXT NOT NULL, description TEXT, created_at TEXT NOT NULL,"
    " source_path TEXT, source_sha256 TEXT, tool TEXT NOT NULL, tool_version TEXT NOT NULL,"
    " model TEXT, reference TEXT, note TEXT, residual REAL,"
    " UNIQUE (name, version))",
    "CREATE TABLE formula ("
    " material_id INTEGER PRIMARY KEY REFERENCES material(id) ON DELETE CASCADE,"
    " type INTEGER NOT NULL, coefficients TEXT NOT NULL, min_nm REAL NOT NULL, max_nm REAL NOT NULL)",
    "CREATE TABLE sample ("
    " material_id INTEGER NOT NULL REFERENCES material(id) ON DELETE CASCADE,"
    " role TEXT NOT NULL, idx INTEGER NOT NULL, nm REAL NOT NULL, value REAL NOT NULL,"
    " PRIMARY KEY (material_id, role, idx)) WITHOUT ROWID",
    "CREATE TABLE property ("
    " material_id INTEGER NOT NULL REFERENCES material(id) ON DELETE CASCADE,"
    " idx INTEGER NOT NULL, key TEXT NOT NULL, text TEXT, value REAL, unit TEXT,"
    " PRIMARY KEY (material_id, idx)) WITHOUT ROWID",
    "CREATE TABLE parameter ("
    " material_id INTEGER NOT NULL REFERENCES material(id) ON DELETE CASCADE,"
    " idx INTEGER NOT NULL, name TEXT NOT NULL, value REAL NOT NULL, stderr REAL, unit TEXT,"
    " PRIMARY KEY (material_id, idx)) WITHOUT ROWID",
    "CREATE INDEX material_kind ON material(kind)",
    NULL};

/* Migrations: MIGRATIONS[v] brings a schema at version v to v + 1.  Version 0
 * is an empty file. */
static const char **const MIGRATIONS[VR_MATDB_SCHEMA_VERSION] = {SCHEMA_V1};

static vr_status sql_error(vr_matdb *db, vr_error *err, const char *what) {
  return vr_error_set(err, VR_E_DB, "%s: %s: %s", db->path, what, sqlite3_errmsg(db->db));
}

static int exec(vr_matdb *db, const char *sql) { return sqlite3_exec(db->db, sql, NULL, NULL, NULL); }

static int pragma_int(vr_matdb *db, const char *sql, int *out) {
  sqlite3_stmt *st;
  int rc = sqlite3_prepare_v2(db->db, sql, -1, &st, NULL);
  if (rc != SQLITE_OK) return rc;
  rc = sqlite3_step(st);
  if (rc == SQLITE_ROW) {
    *out = sqlite3_column_int(st, 0);
    rc = SQLITE_OK;
  }
  sqlite3_finalize(st);
  return rc;
}

const char *vr_matdb_default_path(void) {
  const char *env = getenv("VR_MATDB");
  return env && *env ? env : "materials.db";
}

const char *vr_matdb_path(const vr_matdb *db) { return db->path; }

void vr_matdb_now(char buf[32]) {
  time_t t = time(NULL);
  struct tm tm;
  gmtime_r(&t, &tm);
  strftime(buf, 32, "%Y-%m-%dT%H:%M:%SZ", &tm);
}

static vr_status refuse(vr_matdb *db, vr_error *err, const char *why) {
  vr_error_set(err, VR_E_DB, "%s: %s", db->path, why);
  return VR_E_DB;
}

/* Brings the schema to the current version inside one write transaction;
 * a file created concurrently by another process is re-checked under the
 * lock. */
static vr_status create_or_migrate(vr_matdb *db, vr_error *err) {
  if (exec(db, "BEGIN IMMEDIATE") != SQLITE_OK) return sql_error(db, err, "cannot lock for writing");
  int version = 0, app = 0, tables = 0;
  if (pragma_int(db, "PRAGMA user_version", &version) ||
      pragma_int(db, "PRAGMA application_id", &app) ||
      pragma_int(db, "SELECT count(*) FROM sqlite_master", &tables)) {
    vr_status s = sql_error(db, err, "cannot read the schema");
    exec(db, "ROLLBACK");
    return s;
  }
  vr_status st = VR_OK;
  if (app != APPLICATION_ID && tables > 0) {
    st = refuse(db, err, "a SQLite database, but not a Virtuelium-C material database");
  } else if (version > VR_MATDB_SCHEMA_VERSION) {
    char msg[160];
    snprintf(msg, sizeof msg,
             "written by a newer Virtuelium-C (schema %d; this build knows up to %d)", version,
             VR_MATDB_SCHEMA_VERSION);
    st = refuse(db, err, msg);
  } else {
    int fresh = version == 0;
    for (int v = version; v < VR_MATDB_SCHEMA_VERSION && !st; v++)
      for (const char **sql = MIGRATIONS[v]; *sql && !st; sql++)
        if (exec(db, *sql) != SQLITE_OK) st = sql_error(db, err, "schema migration failed");
    char set[96];
    snprintf(set, sizeof set, "PRAGMA user_version = %d; PRAGMA application_id = %d;",
             VR_MATDB_SCHEMA_VERSION, APPLICATION_ID);
    if (!st && exec(db, set) != SQLITE_OK) st = sql_error(db, err, "cannot set the schema version");
    if (!st && fresh) st = vr_matdb_seed(db, err);
  }
  if (st) {
    exec(db, "ROLLBACK");
    return st;
  }
  if (exec(db, "COMMIT") != SQLITE_OK) {
    st = sql_error(db, err, "cannot commit the schema");
    exec(db, "ROLLBACK");
  }
  return st;
}

vr_status vr_matdb_open(const char *path, int flags, vr_matdb **out, vr_error *err) {
  *out = NULL;
  if (!path) path = vr_matdb_default_path();
  vr_matdb *db = calloc(1, sizeof *db);
  if (!db || !(db->path = strdup(path))) {
    free(db);
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  db->readonly = flags & VR_MATDB_READONLY;
  struct stat sb;
  if (db->readonly && stat(path, &sb) != 0) {
    vr_status s = vr_error_set(err, VR_E_IO, "%s: no material database here: %s", path, strerror(errno));
    free(db->path);
    free(db);
    return s;
  }
  int oflags = db->readonly ? SQLITE_OPEN_READONLY : (SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
  vr_status st = VR_OK;
  if (sqlite3_open_v2(path, &db->db, oflags | SQLITE_OPEN_NOMUTEX, NULL) != SQLITE_OK) {
    st = vr_error_set(err, VR_E_DB, "%s: cannot open: %s", path,
                      db->db ? sqlite3_errmsg(db->db) : "out of memory");
    goto fail;
  }
  sqlite3_busy_timeout(db->db, 15000);
  sqlite3_extended_result_codes(db->db, 1);
  int version = 0, app = 0;
  int rc = pragma_int(db, "PRAGMA user_version", &version);
  if (rc == SQLITE_OK) rc = pragma_int(db, "PRAGMA application_id", &app);
  if ((rc & 0xff) == SQLITE_NOTADB || (rc & 0xff) == SQLITE_CORRUPT) {
    st = refuse(db, err, "not a SQLite database (corrupted, or some other kind of file)");
    goto fail;
  }
  if (rc != SQLITE_OK) {
    st = sql_error(db, err, "cannot read the file");
    goto fail;
  }
  if (!db->readonly) {
    if (exec(db, "PRAGMA journal_mode = WAL") != SQLITE_OK) {
      st = sql_error(db, err, "cannot switch to WAL mode");
      goto fail;
    }
    exec(db, "PRAGMA synchronous = NORMAL");
    if (version != VR_MATDB_SCHEMA_VERSION || app != APPLICATION_ID)
      if ((st = create_or_migrate(db, err))) goto fail;
  } else {
    int tables = 0;
    pragma_int(db, "SELECT count(*) FROM sqlite_master", &tables);
    if (app != APPLICATION_ID) {
      st = refuse(db, err, tables ? "a SQLite database, but not a Virtuelium-C material database"
                                  : "an empty file, not a material database");
      goto fail;
    }
    if (version != VR_MATDB_SCHEMA_VERSION) {
      char msg[160];
      snprintf(msg, sizeof msg, "schema %d, this build reads %d%s", version, VR_MATDB_SCHEMA_VERSION,
               version > VR_MATDB_SCHEMA_VERSION ? " (written by a newer Virtuelium-C)"
                                                 : " (open it read-write once to migrate)");
      st = refuse(db, err, msg);
      goto fail;
    }
  }
  exec(db, "PRAGMA foreign_keys = ON");
  *out = db;
  return VR_OK;
fail:
  vr_matdb_close(db);
  return st;
}

void vr_matdb_close(vr_matdb *db) {
  if (!db) return;
  sqlite3_close_v2(db->db);
  free(db->path);
  free(db);
}

/* ---- saving ------------------------------------------------------------ */

static vr_status check_spectrum_nonneg(const vr_material *m, const char *role, vr_error *err) {
  const vr_spectrum *s = vr_material_spectrum(m, role);
  if (!s) return VR_OK;
  for (size_t i = 0; i < s->n; i++)
    if (s->value[i] < 0.0)
      return vr_error_set(err, VR_E_RANGE, "material '%s': %s = %g at %g nm is negative", m->name,
                          role, s->value[i], s->nm[i]);
  return VR_OK;
}

vr_status vr_matdb_validate(const vr_material *m, vr_error *err) {
  if (!m->name || !*m->name) return vr_error_set(err, VR_E_ARG, "a material needs a name");
  for (const char *p = m->name; *p; p++)
    if ((unsigned char)*p < 0x20)
      return vr_error_set(err, VR_E_ARG, "material name contains a control character");
  if ((unsigned)m->kind >= VR_KIND_COUNT) return vr_error_set(err, VR_E_ARG, "invalid material kind");
  vr_status st;
  switch (m->kind) {
  case VR_KIND_DIELECTRIC:
  case VR_KIND_CONDUCTOR: {
    double lo, hi;
    if ((st = vr_material_nk_range(m, &lo, &hi, err))) return st;
    if (m->n_formula.type && !(m->n_formula.min_nm < m->n_formula.max_nm))
      return vr_error_set(err, VR_E_RANGE, "material '%s': empty formula range", m->name);
    break;
  }
  case VR_KIND_REFLECTANCE:
  case VR_KIND_ILLUMINANT:
    if (!vr_material_spectrum(m, "value"))
      return vr_error_set(err, VR_E_ARG, "material '%s' (%s) needs a 'value' spectrum", m->name,
                          vr_kind_name(m->kind));
    break;
  case VR_KIND_GLAZING:
    if (!vr_material_spectrum(m, "T") || !vr_material_spectrum(m, "Rf") ||
        !vr_material_spectrum(m, "Rb"))
      return vr_error_set(err, VR_E_ARG, "material '%s' (glazing) needs T, Rf and Rb spectra",
                          m->name);
    break;
  case VR_KIND_CHROMOGENIC: {
    vr_chromo_type type;
    if ((st = vr_chromo_type_of(m, &type, err))) return st;
    if (!vr_material_spectrum(m, "T0") || !vr_material_spectrum(m, "dOD"))
      return vr_error_set(err, VR_E_ARG, "material '%s' (chromogenic) needs T0 and dOD spectra",
                          m->name);
    break;
  }
  default:
    if (m->nspectra == 0 && !m->n_formula.type && m->nparams == 0)
      return vr_error_set(err, VR_E_ARG, "material '%s' holds no data", m->name);
  }
  const char *nonneg[] = {"k", "value", "T", "Rf", "Rb", "T0", "Rf0", "Rb0"};
  for (size_t i = 0; i < sizeof nonneg / sizeof nonneg[0]; i++)
    if ((st = check_spectrum_nonneg(m, nonneg[i], err))) return st;
  for (size_t i = 0; i < m->nprops; i++)
    if (strstr(m->props[i].key, "thickness") && isfinite(m->props[i].value) && m->props[i].value < 0)
      return vr_error_set(err, VR_E_RANGE, "material '%s': negative %s (%g)", m->name,
                          m->props[i].key, m->props[i].value);
  return VR_OK;
}

static void bind_text_or_null(sqlite3_stmt *s, int i, const char *t) {
  if (t) sqlite3_bind_text(s, i, t, -1, SQLITE_TRANSIENT);
  else sqlite3_bind_null(s, i);
}

static void bind_real_or_null(sqlite3_stmt *s, int i, double v) {
  if (isfinite(v)) sqlite3_bind_double(s, i, v);
  else sqlite3_bind_null(s, i);
}

#define PREPARE(sql, stmt)                                                          \
  if (sqlite3_prepare_v2(db->db, sql, -1, &stmt, NULL) != SQLITE_OK) {               \
    st = sql_error(db, err, "cannot prepare a statement");                          \
    goto done;                                                                       \
  }
#define STEP_DONE(stmt, what)                                                       \
  if (sqlite3_step(stmt) != SQLITE_DONE) {                                          \
    st = sql_error(db, err, what);                                                  \
    goto done;                                                                       \
  }                                                                                  \
  sqlite3_reset(stmt);

vr_status vr_matdb_insert(vr_matdb *db, vr_material *m, vr_error *err) {
  vr_status st = VR_OK;
  sqlite3_stmt *q = NULL, *ins = NULL, *f = NULL, *smp = NULL, *prop = NULL, *par = NULL;
  int version = 1;
  PREPARE("SELECT COALESCE(MAX(version), 0) + 1 FROM material WHERE name = ?", q);
  sqlite3_bind_text(q, 1, m->name, -1, SQLITE_TRANSIENT);
  if (sqlite3_step(q) == SQLITE_ROW) version = sqlite3_column_int(q, 0);
  vr_matdb_now(m->prov.created_at);
  PREPARE("INSERT INTO material (name, version, kind, description, created_at, source_path,"
          " source_sha256, tool, tool_version, model, reference, note, residual)"
          " VALUES (?,?,?,?,?,?,?,?,?,?,?,?,?)", ins);
  sqlite3_bind_text(ins, 1, m->name, -1, SQLITE_TRANSIENT);
  sqlite3_bind_int(ins, 2, version);
  sqlite3_bind_text(ins, 3, vr_kind_name(m->kind), -1, SQLITE_STATIC);
  bind_text_or_null(ins, 4, m->description);
  sqlite3_bind_text(ins, 5, m->prov.created_at, -1, SQLITE_TRANSIENT);
  bind_text_or_null(ins, 6, m->prov.source_path);
  bind_text_or_null(ins, 7, m->prov.sha256[0] ? m->prov.sha256 : NULL);
  sqlite3_bind_text(ins, 8, m->prov.tool ? m->prov.tool : "unknown", -1, SQLITE_TRANSIENT);
  sqlite3_bind_text(ins, 9, m->prov.tool_version ? m->prov.tool_version : "unknown", -1, SQLITE_TRANSIENT);
  bind_text_or_null(ins, 10, m->prov.model);
  bind_text_or_null(ins, 11, m->prov.reference);
  bind_text_or_null(ins, 12, m->prov.note);
  bind_real_or_null(ins, 13, m->prov.residual);
  STEP_DONE(ins, "cannot insert the material");
  sqlite3_int64 id = sqlite3_last_insert_rowid(db->db);
  if (m->n_formula.type) {
    char coeffs[VR_FORMULA_MAX_COEFFS * 26 + 1] = "";
    size_t used = 0;
    for (size_t i = 0; i < m->n_formula.ncoeffs; i++)
      used += (size_t)snprintf(coeffs + used, sizeof coeffs - used, "%s%.17g", i ? " " : "",
                               m->n_formula.c[i]);
    PREPARE("INSERT INTO formula VALUES (?,?,?,?,?)", f);
    sqlite3_bind_int64(f, 1, id);
    sqlite3_bind_int(f, 2, m->n_formula.type);
    sqlite3_bind_text(f, 3, coeffs, -1, SQLITE_TRANSIENT);
    sqlite3_bind_double(f, 4, m->n_formula.min_nm);
    sqlite3_bind_double(f, 5, m->n_formula.max_nm);
    STEP_DONE(f, "cannot insert the formula");
  }
  PREPARE("INSERT INTO sample VALUES (?,?,?,?,?)", smp);
  for (size_t i = 0; i < m->nspectra; i++) {
    const vr_spectrum *s = m->spectra[i].s;
    for (size_t j = 0; j < s->n; j++) {
      sqlite3_bind_int64(smp, 1, id);
      sqlite3_bind_text(smp, 2, m->spectra[i].role, -1, SQLITE_STATIC);
      sqlite3_bind_int64(smp, 3, (sqlite3_int64)j);
      sqlite3_bind_double(smp, 4, s->nm[j]);
      sqlite3_bind_double(smp, 5, s->value[j]);
      STEP_DONE(smp, "cannot insert a spectrum sample");
    }
  }
  PREPARE("INSERT INTO property VALUES (?,?,?,?,?,?)", prop);
  for (size_t i = 0; i < m->nprops; i++) {
    sqlite3_bind_int64(prop, 1, id);
    sqlite3_bind_int64(prop, 2, (sqlite3_int64)i);
    sqlite3_bind_text(prop, 3, m->props[i].key, -1, SQLITE_STATIC);
    bind_text_or_null(prop, 4, m->props[i].text);
    bind_real_or_null(prop, 5, m->props[i].value);
    bind_text_or_null(prop, 6, m->props[i].unit);
    STEP_DONE(prop, "cannot insert a property");
  }
  PREPARE("INSERT INTO parameter VALUES (?,?,?,?,?,?)", par);
  for (size_t i = 0; i < m->nparams; i++) {
    sqlite3_bind_int64(par, 1, id);
    sqlite3_bind_int64(par, 2, (sqlite3_int64)i);
    sqlite3_bind_text(par, 3, m->params[i].name, -1, SQLITE_STATIC);
    sqlite3_bind_double(par, 4, m->params[i].value);
    bind_real_or_null(par, 5, m->params[i].stderr_);
    bind_text_or_null(par, 6, m->params[i].unit);
    STEP_DONE(par, "cannot insert a parameter");
  }
  m->version = version;
done:
  sqlite3_finalize(q);
  sqlite3_finalize(ins);
  sqlite3_finalize(f);
  sqlite3_finalize(smp);
  sqlite3_finalize(prop);
  sqlite3_finalize(par);
  return st;
}

vr_status vr_matdb_save(vr_matdb *db, vr_material *m, vr_error *err) {
  if (db->readonly) return vr_error_set(err, VR_E_DB, "%s: opened read-only", db->path);
  vr_status st = vr_matdb_validate(m, err);
  if (st) return st;
  if (exec(db, "BEGIN IMMEDIATE") != SQLITE_OK) return sql_error(db, err, "cannot lock for writing");
  st = vr_matdb_insert(db, m, err);
  if (!st && exec(db, "COMMIT") != SQLITE_OK) st = sql_error(db, err, "cannot commit");
  if (st) {
    exec(db, "ROLLBACK");
    m->version = 0;
  }
  return st;
}

bool vr_matdb_named_in(const char *path) {
  FILE *f = fopen(path, "rb");
  if (!f) return false;
  char line[2048];
  bool need = false;
  while (!need && fgets(line, sizeof line, f)) {
    char *hash = strchr(line, '#');
    if (hash) *hash = '\0';
    need = strstr(line, "db:") != NULL;
  }
  fclose(f);
  return need;
}
