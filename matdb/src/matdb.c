/* The material database on SQLite: opening (with schema creation, version
 * checks and seeding), and whole-transaction saves and loads of materials.
 *
 * Schema version 1.  Spectra are stored one sample per row (material, role,
 * index, nm, value) so that any SQLite client can inspect them; REAL columns
 * keep every bit of a double.  SQLite stores NaN as NULL, which is how
 * "unknown" (a residual, an uncertainty, a text-only property) is kept. */
#include "matdb_internal.h"
#include "vr/out_guard.h"
#include "utf8.h"
#include "vr/chromogenic.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

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

/* How long a writer waits for another's lock before giving up. */
#define BUSY_TIMEOUT_MS 15000

/* What a user can do about the last failure of h, or "". */
static const char *sql_hint(sqlite3 *h, char *buf, size_t cap) {
  if (!h) return "";
  int code = sqlite3_extended_errcode(h) & 0xff, sys = sqlite3_system_errno(h);
  if (code == SQLITE_BUSY || code == SQLITE_LOCKED) {
    snprintf(buf, cap,
             " (another process held the database for %d s: an import or save still running, "
             "or an open sqlite3 shell in a transaction; let it finish or close it, then run "
             "again; nothing was written)", BUSY_TIMEOUT_MS / 1000);
    return buf;
  }
  if (code == SQLITE_FULL || sys == ENOSPC)
    return " (the disk holding it is full: free some space and run again; nothing was written)";
  if (sys == EDQUOT) return " (your disk quota is used up: free some space and run again; nothing was written)";
  if (code == SQLITE_READONLY || sys == EROFS)
    return " (the file or its file system is read-only; nothing was written)";
  return "";
}

vr_status vr_matdb_sql_error(vr_matdb *db, vr_error *err, const char *what) {
  char buf[256];
  return vr_error_set(err, VR_E_DB, "%s: %s: %s%s", db->path, what, sqlite3_errmsg(db->db),
                      sql_hint(db->db, buf, sizeof buf));
}

static vr_status sql_error(vr_matdb *db, vr_error *err, const char *what) {
  return vr_matdb_sql_error(db, err, what);
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

/* "file:" URI of a path for sqlite3_open_v2 with SQLITE_OPEN_URI, every
 * byte outside [A-Za-z0-9/._~-] percent-encoded. */
static char *uri_of(const char *path, const char *query) {
  size_t n = strlen(path), cap = 8 + 3 * n + strlen(query) + 1;
  char *u = malloc(cap);
  if (!u) return NULL;
  size_t j = (size_t)snprintf(u, cap, "file:");
  for (size_t i = 0; i < n; i++) {
    unsigned char c = (unsigned char)path[i];
    if ((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') ||
        strchr("/._~-", c))
      u[j++] = (char)c;
    else
      j += (size_t)snprintf(u + j, cap - j, "%%%02X", c);
  }
  snprintf(u + j, cap - j, "?%s", query);
  return u;
}

static void close_handle(vr_matdb *db) {
  if (db->db) sqlite3_close_v2(db->db);
  db->db = NULL;
}

/* Reads what the file says it is, without writing anything. */
typedef struct identity { int version, app, tables; } identity;
static int identify(vr_matdb *db, identity *id) {
  int rc = pragma_int(db, "PRAGMA user_version", &id->version);
  if (rc == SQLITE_OK) rc = pragma_int(db, "PRAGMA application_id", &id->app);
  if (rc == SQLITE_OK) rc = pragma_int(db, "SELECT count(*) FROM sqlite_master", &id->tables);
  return rc;
}

static int open_handle(vr_matdb *db, const char *name, int oflags) {
  int rc = sqlite3_open_v2(name, &db->db, oflags | SQLITE_OPEN_NOMUTEX, NULL);
  if (db->db) {
    sqlite3_busy_timeout(db->db, BUSY_TIMEOUT_MS);
    sqlite3_extended_result_codes(db->db, 1);
  }
  return rc;
}

/* Opens an existing file for reading only and reads its identity.  A WAL
 * database in a folder this process cannot write has no -shm to share with
 * writers and SQLite cannot create one; when no -wal file exists either (no
 * writer has it open, every change is in the main file) the file is read as
 * immutable. */
static vr_status open_reader(vr_matdb *db, bool folder_writable, bool wal_mode, identity *id,
                             int *sqlite_rc, vr_error *err) {
  char wal[4200];
  snprintf(wal, sizeof wal, "%s-wal", db->path);
  struct stat ws;
  bool has_wal = stat(wal, &ws) == 0;
  if (wal_mode && !has_wal) {
    /* Nobody has it open and all of it is in the main file: a first look
     * as immutable creates no -shm or -wal beside a file that may turn out
     * not to be ours.  Ours is then opened the normal way, so that a writer
     * starting meanwhile is seen. */
    char *uri = uri_of(db->path, "immutable=1");
    if (!uri) return vr_error_set(err, VR_E_NOMEM, "out of memory");
    int rc = open_handle(db, uri, SQLITE_OPEN_READONLY | SQLITE_OPEN_URI);
    free(uri);
    if (rc == SQLITE_OK) rc = identify(db, id);
    if (rc == SQLITE_OK && id->app != APPLICATION_ID) return VR_OK;
    close_handle(db);
  }
  int rc = open_handle(db, db->path, SQLITE_OPEN_READONLY);
  if (rc == SQLITE_OK) rc = identify(db, id);
  int base = rc & 0xff;
  if ((base == SQLITE_READONLY || base == SQLITE_CANTOPEN) && !folder_writable) {
    if (!has_wal) {
      close_handle(db);
      char *uri = uri_of(db->path, "immutable=1");
      if (!uri) return vr_error_set(err, VR_E_NOMEM, "out of memory");
      rc = open_handle(db, uri, SQLITE_OPEN_READONLY | SQLITE_OPEN_URI);
      free(uri);
      if (rc == SQLITE_OK) rc = identify(db, id);
      base = rc & 0xff;
    } else if (base != SQLITE_OK) {
      return vr_error_set(err, VR_E_DB,
                          "%s: cannot read the material database: it is in WAL mode with a "
                          "-wal file, and its folder is not writable for the -shm file (%s)",
                          db->path, db->db ? sqlite3_errmsg(db->db) : "out of memory");
    }
  }
  *sqlite_rc = rc;
  if (base == SQLITE_NOTADB || base == SQLITE_CORRUPT)
    return refuse(db, err, "not a SQLite database (corrupted, or some other kind of file); left untouched");
  char hint[256];
  if (rc != SQLITE_OK)
    return vr_error_set(err, VR_E_DB, "%s: cannot read the file: %s%s", db->path,
                        db->db ? sqlite3_errmsg(db->db) : "out of memory",
                        sql_hint(db->db, hint, sizeof hint));
  return VR_OK;
}

/* Opens for writing (creating the file when missing), switches to WAL and
 * brings the schema up to date.  Only called once the file is known to be
 * new, empty or a material database. */
static vr_status open_writer(vr_matdb *db, vr_error *err) {
  char hint[256];
  if (open_handle(db, db->path, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE) != SQLITE_OK)
    return vr_error_set(err, VR_E_DB, "%s: cannot open: %s%s", db->path,
                        db->db ? sqlite3_errmsg(db->db) : "out of memory",
                        sql_hint(db->db, hint, sizeof hint));
  identity id = {0};
  int rc = identify(db, &id);
  if ((rc & 0xff) == SQLITE_NOTADB || (rc & 0xff) == SQLITE_CORRUPT)
    return refuse(db, err, "not a SQLite database (corrupted, or some other kind of file); left untouched");
  if (rc != SQLITE_OK) return sql_error(db, err, "cannot read the file");
  if (id.app != APPLICATION_ID && (id.tables > 0 || id.app != 0))
    return refuse(db, err, "a SQLite database, but not a Virtuelium-C material database; left untouched");
  if (exec(db, "PRAGMA journal_mode = WAL") != SQLITE_OK)
    return sql_error(db, err, "cannot switch to WAL mode");
  exec(db, "PRAGMA synchronous = NORMAL");
  if (id.version != VR_MATDB_SCHEMA_VERSION || id.app != APPLICATION_ID)
    return create_or_migrate(db, err);
  return VR_OK;
}

/* PRAGMA application_id as the SQLite header stores it: 4 bytes, big-endian,
 * at offset 68. */
static int app_id_of(const unsigned char head[100]) {
  return (int)((unsigned)head[68] << 24 | (unsigned)head[69] << 16 | (unsigned)head[70] << 8 |
               (unsigned)head[71]);
}

vr_status vr_matdb_open(const char *path, int flags, vr_matdb **out, vr_error *err) {
  *out = NULL;
  bool explicit_path = path != NULL;
  if (!path) path = vr_matdb_default_path();
  if (!*path)
    return vr_error_set(err, VR_E_ARG,
                        "the material database path is empty: give --db a file name (without "
                        "--db: $VR_MATDB, else ./materials.db)");
  if ((flags & VR_MATDB_MUST_EXIST) && explicit_path && access(path, F_OK) != 0 && errno == ENOENT) {
    char folder[4096];
    struct stat fs;
    vr_path_folder(path, folder, sizeof folder);
    if (stat(folder, &fs) != 0 || !S_ISDIR(fs.st_mode))
      return vr_error_set(err, VR_E_NOT_FOUND,
                          "--db %s: no such material database, and no folder %s (a mistyped "
                          "path?)", path, folder);
    return vr_error_set(err, VR_E_NOT_FOUND,
                        "--db %s: no such material database (a mistyped path? 'vr-matdb --db %s "
                        "init' creates one with the built-in library)", path, path);
  }
  vr_matdb *db = calloc(1, sizeof *db);
  if (!db || !(db->path = strdup(path))) {
    free(db);
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  bool want_ro = flags & VR_MATDB_READONLY;
  char dir[4096];
  vr_path_folder(path, dir, sizeof dir);
  bool folder_writable = access(dir, W_OK | X_OK) == 0;
  vr_status st = VR_OK;
  struct stat sb;
  if (stat(path, &sb) != 0) {
    int e = errno;
    if (e != ENOENT || want_ro) {
      st = vr_error_set(err, VR_E_IO, "%s: no material database here: %s", path, strerror(e));
    } else if (stat(dir, &sb) != 0 || !S_ISDIR(sb.st_mode)) {
      st = vr_error_set(err, VR_E_IO, "%s: cannot create the material database: the folder %s does not exist",
                        path, dir);
    } else if (!folder_writable) {
      st = vr_error_set(err, VR_E_IO, "%s: cannot create the material database: the folder %s is not writable",
                        path, dir);
    } else {
      st = open_writer(db, err);
    }
    goto finish;
  }
  if (S_ISDIR(sb.st_mode)) {
    st = vr_error_set(err, VR_E_IO, "%s: is a folder, not a material database", path);
    goto finish;
  }
  if (want_ro) snprintf(db->ro_reason, sizeof db->ro_reason, "opened for reading only");
  else if (access(path, W_OK) != 0) snprintf(db->ro_reason, sizeof db->ro_reason, "the file is not writable");
  else if (!folder_writable)
    snprintf(db->ro_reason, sizeof db->ro_reason, "its folder %.200s is not writable", dir);
  if (sb.st_size == 0) { /* a new database, created by touch or mktemp */
    if (db->ro_reason[0])
      st = vr_error_set(err, VR_E_DB, "%s: an empty file, not a material database%s%s", path,
                        want_ro ? "" : ", and it cannot be created here: ", want_ro ? "" : db->ro_reason);
    else
      st = open_writer(db, err);
    goto finish;
  }
  /* Anything else must say it is SQLite in its first 16 bytes before SQLite
   * is let near it. */
  unsigned char head[100] = {0};
  FILE *f = fopen(path, "rb");
  if (!f) {
    st = vr_error_set(err, VR_E_IO, "%s: cannot read: %s", path, strerror(errno));
    goto finish;
  }
  size_t got = fread(head, 1, sizeof head, f);
  fclose(f);
  if (got < sizeof head || memcmp(head, "SQLite format 3", 16) != 0) {
    st = refuse(db, err, "not a SQLite database (corrupted, or some other kind of file); left untouched");
    goto finish;
  }
  identity id = {0};
  int probe_rc = SQLITE_OK;
  st = open_reader(db, folder_writable, head[18] == 2, &id, &probe_rc, err);
  if (st && (probe_rc & 0xff) == SQLITE_READONLY && app_id_of(head) == APPLICATION_ID) {
    /* A hot journal or a WAL left by an interrupted writer: only a writable
     * handle may recover it (SQLite does so on the first read).  The header
     * already says the file is ours. */
    close_handle(db);
    if (access(path, W_OK) == 0 && folder_writable) {
      if (open_handle(db, path, SQLITE_OPEN_READWRITE) == SQLITE_OK) identify(db, &id);
      close_handle(db);
      st = open_reader(db, folder_writable, head[18] == 2, &id, &probe_rc, err);
    } else {
      st = vr_error_set(err, VR_E_DB,
                        "%s: an interrupted write left it needing recovery, which needs write "
                        "access (%s)", path, db->ro_reason[0] ? db->ro_reason : "not writable");
    }
  }
  if (st) goto finish;
  if (id.app != APPLICATION_ID && (id.tables > 0 || id.app != 0)) {
    st = refuse(db, err, "a SQLite database, but not a Virtuelium-C material database; left untouched");
    goto finish;
  }
  if (id.version > VR_MATDB_SCHEMA_VERSION) {
    char msg[160];
    snprintf(msg, sizeof msg, "written by a newer Virtuelium-C (schema %d; this build knows up to %d)",
             id.version, VR_MATDB_SCHEMA_VERSION);
    st = refuse(db, err, msg);
    goto finish;
  }
  bool current = id.app == APPLICATION_ID && id.version == VR_MATDB_SCHEMA_VERSION;
  if (!current && db->ro_reason[0]) {
    if (id.app != APPLICATION_ID)
      st = vr_error_set(err, VR_E_DB, "%s: an empty SQLite file, not a material database (%s)", path,
                        db->ro_reason);
    else
      st = vr_error_set(err, VR_E_DB,
                        "%s: schema %d, this build reads %d: it must be migrated, which writes it, "
                        "and it cannot be written here (%s): make the file and its folder writable "
                        "and run 'vr-matdb --db %s init' (it migrates), or copy it to a writable folder and give "
                        "the copy as --db", path, id.version, VR_MATDB_SCHEMA_VERSION, db->ro_reason,
                        path);
    goto finish;
  }
  if (db->ro_reason[0]) {
    db->readonly = 1;
  } else {
    close_handle(db);
    st = open_writer(db, err);
  }
finish:
  if (st) {
    vr_matdb_close(db);
    return st;
  }
  exec(db, "PRAGMA foreign_keys = ON");
  *out = db;
  return VR_OK;
}

const char *vr_matdb_readonly(const vr_matdb *db) { return db->readonly ? db->ro_reason : NULL; }

vr_status vr_matdb_require_writable(const vr_matdb *db, vr_error *err) {
  if (!db->readonly) return VR_OK;
  return vr_error_set(err, VR_E_DB, "%s: the material database is read-only (%s); nothing was written",
                      db->path, db->ro_reason);
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

/* Every text in the database is UTF-8, so that any client (and JSON) can
 * read it; a file path is kept as the file system gives it. */
static vr_status check_text(const vr_material *m, const char *field, const char *text, vr_error *err) {
  size_t bad;
  if (!text || vr_utf8_valid(text, strlen(text), &bad)) return VR_OK;
  char *shown = vr_utf8_sanitize(m->name);
  vr_status st = vr_error_set(err, VR_E_ARG, "material '%s': %s is not valid UTF-8 (byte %zu: 0x%02X)",
                              shown ? shown : "?", field, bad, (unsigned char)text[bad]);
  free(shown);
  return st;
}

static vr_status check_texts(const vr_material *m, vr_error *err) {
  vr_status st;
  if ((st = check_text(m, "the name", m->name, err)) ||
      (st = check_text(m, "the description", m->description, err)) ||
      (st = check_text(m, "the model", m->prov.model, err)) ||
      (st = check_text(m, "the reference", m->prov.reference, err)) ||
      (st = check_text(m, "the note", m->prov.note, err)))
    return st;
  for (size_t i = 0; i < m->nspectra; i++)
    if ((st = check_text(m, "a spectrum's role", m->spectra[i].role, err))) return st;
  for (size_t i = 0; i < m->nprops; i++) {
    char field[160];
    snprintf(field, sizeof field, "property '%.100s'", m->props[i].key);
    if ((st = check_text(m, "a property's key", m->props[i].key, err)) ||
        (st = check_text(m, field, m->props[i].text, err)) ||
        (st = check_text(m, field, m->props[i].unit, err)))
      return st;
  }
  for (size_t i = 0; i < m->nparams; i++)
    if ((st = check_text(m, "a parameter's name", m->params[i].name, err)) ||
        (st = check_text(m, "a parameter's unit", m->params[i].unit, err)))
      return st;
  return VR_OK;
}

vr_status vr_matdb_validate(const vr_material *m, vr_error *err) {
  if (!m->name || !*m->name) return vr_error_set(err, VR_E_ARG, "a material needs a name");
  for (const char *p = m->name; *p; p++)
    if ((unsigned char)*p < 0x20)
      return vr_error_set(err, VR_E_ARG, "material name contains a control character");
  if ((unsigned)m->kind >= VR_KIND_COUNT) return vr_error_set(err, VR_E_ARG, "invalid material kind");
  vr_status st;
  if ((st = check_texts(m, err))) return st;
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
  vr_status st = vr_matdb_require_writable(db, err);
  if (st) return st;
  st = vr_matdb_validate(m, err);
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
