/* Reading the material database: loading one material (newest or a named
 * version), listing, history, removal and the integrity check. */
#include "matdb_internal.h"
#include "vr/csv.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static vr_status sql_error(vr_matdb *db, vr_error *err, const char *what) {
  return vr_matdb_sql_error(db, err, what);
}

static const char *col_text(sqlite3_stmt *s, int i) { return (const char *)sqlite3_column_text(s, i); }
static double col_real_or_nan(sqlite3_stmt *s, int i) {
  return sqlite3_column_type(s, i) == SQLITE_NULL ? NAN : sqlite3_column_double(s, i);
}

static vr_status set(char **field, const char *text, vr_error *err) {
  return vr_material_set_text(field, text, err);
}

/* Reads the rows of one role into a new spectrum. */
static vr_status load_spectra(vr_matdb *db, sqlite3_int64 id, vr_material *m, vr_error *err) {
  sqlite3_stmt *s;
  if (sqlite3_prepare_v2(db->db,
                         "SELECT role, nm, value FROM sample WHERE material_id = ? ORDER BY role, idx",
                         -1, &s, NULL) != SQLITE_OK)
    return sql_error(db, err, "cannot prepare a statement");
  sqlite3_bind_int64(s, 1, id);
  vr_status st = VR_OK;
  size_t n = 0, cap = 0;
  double *nm = NULL, *v = NULL;
  char *role = NULL;
  int rc;
  for (;;) {
    rc = sqlite3_step(s);
    const char *r = rc == SQLITE_ROW ? col_text(s, 0) : NULL;
    if (role && (!r || strcmp(r, role))) {
      vr_spectrum *sp = vr_spectrum_create(n, nm, v, err);
      if (!sp || (st = vr_material_add_spectrum(m, role, sp, err))) {
        if (!sp) st = err ? err->status : VR_E_DB;
        break;
      }
      free(role);
      role = NULL;
      n = 0;
    }
    if (rc != SQLITE_ROW) break;
    if (!role && !(role = strdup(r))) {
      st = vr_error_set(err, VR_E_NOMEM, "out of memory");
      break;
    }
    if (n == cap) {
      cap = cap ? 2 * cap : 256;
      double *a = realloc(nm, cap * sizeof *a), *b = a ? realloc(v, cap * sizeof *b) : NULL;
      if (a) nm = a;
      if (b) v = b;
      if (!a || !b) {
        st = vr_error_set(err, VR_E_NOMEM, "out of memory");
        break;
      }
    }
    nm[n] = sqlite3_column_double(s, 1);
    v[n] = sqlite3_column_double(s, 2);
    n++;
  }
  if (!st && rc != SQLITE_DONE) st = sql_error(db, err, "cannot read spectra");
  free(role);
  free(nm);
  free(v);
  sqlite3_finalize(s);
  return st;
}

vr_status vr_matdb_load(vr_matdb *db, const char *name, int version, vr_material **out,
                        vr_error *err) {
  *out = NULL;
  sqlite3_stmt *s = NULL;
  const char *sql =
      version > 0
          ? "SELECT id, version, kind, description, created_at, source_path, source_sha256, tool,"
            " tool_version, model, reference, note, residual FROM material WHERE name = ?1 AND version = ?2"
          : "SELECT id, version, kind, description, created_at, source_path, source_sha256, tool,"
            " tool_version, model, reference, note, residual FROM material WHERE name = ?1"
            " ORDER BY version DESC LIMIT 1";
  if (sqlite3_prepare_v2(db->db, sql, -1, &s, NULL) != SQLITE_OK)
    return sql_error(db, err, "cannot prepare a statement");
  sqlite3_bind_text(s, 1, name, -1, SQLITE_TRANSIENT);
  if (version > 0) sqlite3_bind_int(s, 2, version);
  /* One read transaction so the material's rows come from one snapshot even
   * while a writer commits a new version. */
  sqlite3_exec(db->db, "BEGIN", NULL, NULL, NULL);
  vr_status st = VR_OK;
  vr_material *m = NULL;
  int rc = sqlite3_step(s);
  if (rc != SQLITE_ROW) {
    if (rc == SQLITE_DONE) {
      if (version > 0)
        st = vr_error_set(err, VR_E_NOT_FOUND, "%s: no version %d of material '%s'", db->path,
                          version, name);
      else
        st = vr_error_set(err, VR_E_NOT_FOUND, "%s: unknown material '%s' (see vr-matdb list)",
                          db->path, name);
    } else {
      st = sql_error(db, err, "cannot read the material");
    }
    goto done;
  }
  vr_material_kind kind;
  if ((st = vr_kind_parse(col_text(s, 2), &kind, err))) goto done;
  if (!(m = vr_material_create(name, kind, err))) {
    st = VR_E_NOMEM;
    goto done;
  }
  sqlite3_int64 id = sqlite3_column_int64(s, 0);
  m->version = sqlite3_column_int(s, 1);
  snprintf(m->prov.created_at, sizeof m->prov.created_at, "%s", col_text(s, 4));
  const char *sha = col_text(s, 6);
  snprintf(m->prov.sha256, sizeof m->prov.sha256, "%s", sha ? sha : "");
  if ((st = set(&m->description, col_text(s, 3), err)) ||
      (st = set(&m->prov.source_path, col_text(s, 5), err)) ||
      (st = set(&m->prov.tool, col_text(s, 7), err)) ||
      (st = set(&m->prov.tool_version, col_text(s, 8), err)) ||
      (st = set(&m->prov.model, col_text(s, 9), err)) ||
      (st = set(&m->prov.reference, col_text(s, 10), err)) ||
      (st = set(&m->prov.note, col_text(s, 11), err)))
    goto done;
  m->prov.residual = col_real_or_nan(s, 12);
  sqlite3_finalize(s);
  s = NULL;

  if (sqlite3_prepare_v2(db->db, "SELECT type, coefficients, min_nm, max_nm FROM formula WHERE material_id = ?",
                         -1, &s, NULL) != SQLITE_OK) {
    st = sql_error(db, err, "cannot prepare a statement");
    goto done;
  }
  sqlite3_bind_int64(s, 1, id);
  if (sqlite3_step(s) == SQLITE_ROW) {
    vr_formula *f = &m->n_formula;
    f->type = sqlite3_column_int(s, 0);
    f->min_nm = sqlite3_column_double(s, 2);
    f->max_nm = sqlite3_column_double(s, 3);
    char *text = strdup(col_text(s, 1)), *save = NULL;
    if (!text) {
      st = vr_error_set(err, VR_E_NOMEM, "out of memory");
      goto done;
    }
    for (char *tok = strtok_r(text, " ", &save); tok && f->ncoeffs < VR_FORMULA_MAX_COEFFS;
         tok = strtok_r(NULL, " ", &save))
      if (vr_parse_double(tok, &f->c[f->ncoeffs++])) st = vr_error_set(err, VR_E_DB, "%s: material '%s': corrupt formula", db->path, name);
    free(text);
    if (st) goto done;
  }
  sqlite3_finalize(s);
  s = NULL;
  if ((st = load_spectra(db, id, m, err))) goto done;

  if (sqlite3_prepare_v2(db->db, "SELECT key, text, value, unit FROM property WHERE material_id = ? ORDER BY idx",
                         -1, &s, NULL) != SQLITE_OK) {
    st = sql_error(db, err, "cannot prepare a statement");
    goto done;
  }
  sqlite3_bind_int64(s, 1, id);
  while ((rc = sqlite3_step(s)) == SQLITE_ROW)
    if ((st = vr_material_add_property(m, col_text(s, 0), col_text(s, 1), col_real_or_nan(s, 2),
                                       col_text(s, 3), err)))
      goto done;
  sqlite3_finalize(s);
  s = NULL;
  if (sqlite3_prepare_v2(db->db, "SELECT name, value, stderr, unit FROM parameter WHERE material_id = ? ORDER BY idx",
                         -1, &s, NULL) != SQLITE_OK) {
    st = sql_error(db, err, "cannot prepare a statement");
    goto done;
  }
  sqlite3_bind_int64(s, 1, id);
  while ((rc = sqlite3_step(s)) == SQLITE_ROW)
    if ((st = vr_material_add_parameter(m, col_text(s, 0), sqlite3_column_double(s, 1),
                                        col_real_or_nan(s, 2), col_text(s, 3), err)))
      goto done;
done:
  sqlite3_finalize(s);
  sqlite3_exec(db->db, "COMMIT", NULL, NULL, NULL);
  if (st) vr_material_destroy(m);
  else *out = m;
  return st;
}

vr_status vr_matdb_remove(vr_matdb *db, const char *name, int *removed, vr_error *err) {
  if (removed) *removed = 0;
  vr_status rs = vr_matdb_require_writable(db, err);
  if (rs) return rs;
  if (sqlite3_exec(db->db, "BEGIN IMMEDIATE", NULL, NULL, NULL) != SQLITE_OK)
    return sql_error(db, err, "cannot lock for writing");
  sqlite3_stmt *s;
  vr_status st = VR_OK;
  if (sqlite3_prepare_v2(db->db, "DELETE FROM material WHERE name = ?", -1, &s, NULL) != SQLITE_OK) {
    st = sql_error(db, err, "cannot prepare a statement");
  } else {
    sqlite3_bind_text(s, 1, name, -1, SQLITE_TRANSIENT);
    if (sqlite3_step(s) != SQLITE_DONE) st = sql_error(db, err, "cannot remove");
    sqlite3_finalize(s);
  }
  int n = sqlite3_changes(db->db);
  if (!st && n == 0) st = vr_error_set(err, VR_E_NOT_FOUND, "%s: unknown material '%s'", db->path, name);
  if (!st && sqlite3_exec(db->db, "COMMIT", NULL, NULL, NULL) != SQLITE_OK)
    st = sql_error(db, err, "cannot commit");
  if (st) sqlite3_exec(db->db, "ROLLBACK", NULL, NULL, NULL);
  if (removed) *removed = st ? 0 : n;
  return st;
}

static vr_matdb_entry entry_of(sqlite3_stmt *s) {
  return (vr_matdb_entry){
      .name = col_text(s, 0), .version = sqlite3_column_int(s, 1),
      .versions = sqlite3_column_int(s, 2), .kind = col_text(s, 3),
      .created_at = col_text(s, 4), .tool = col_text(s, 5), .tool_version = col_text(s, 6),
      .source_path = col_text(s, 7), .source_sha256 = col_text(s, 8), .model = col_text(s, 9),
      .reference = col_text(s, 10), .note = col_text(s, 11), .residual = col_real_or_nan(s, 12)};
}

static vr_status visit_rows(vr_matdb *db, sqlite3_stmt *s, vr_matdb_visit visit, void *user,
                            vr_error *err) {
  int rc;
  while ((rc = sqlite3_step(s)) == SQLITE_ROW) {
    vr_matdb_entry e = entry_of(s);
    if (visit(&e, user)) {
      rc = SQLITE_DONE;
      break;
    }
  }
  vr_status st = rc == SQLITE_DONE ? VR_OK : sql_error(db, err, "cannot list");
  sqlite3_finalize(s);
  return st;
}

#define ENTRY_COLUMNS                                                                       \
  "m.name, m.version, (SELECT count(*) FROM material c WHERE c.name = m.name), m.kind,"   \
  " m.created_at, m.tool, m.tool_version, m.source_path, m.source_sha256, m.model,"        \
  " m.reference, m.note, m.residual"

vr_status vr_matdb_list(vr_matdb *db, const char *kind, vr_matdb_visit visit, void *user,
                        vr_error *err) {
  if (kind) {
    vr_material_kind k;
    vr_status st = vr_kind_parse(kind, &k, err);
    if (st) return st;
  }
  sqlite3_stmt *s;
  if (sqlite3_prepare_v2(db->db,
                         "SELECT " ENTRY_COLUMNS " FROM material m"
                         " WHERE m.version = (SELECT MAX(version) FROM material x WHERE x.name = m.name)"
                         " AND (?1 IS NULL OR m.kind = ?1) ORDER BY m.kind, m.name",
                         -1, &s, NULL) != SQLITE_OK)
    return sql_error(db, err, "cannot prepare a statement");
  if (kind) sqlite3_bind_text(s, 1, kind, -1, SQLITE_TRANSIENT);
  return visit_rows(db, s, visit, user, err);
}

vr_status vr_matdb_revision(vr_matdb *db, long long *rows, long long *max_id, vr_error *err) {
  sqlite3_stmt *s;
  if (sqlite3_prepare_v2(db->db, "SELECT count(*), coalesce(max(id), 0) FROM material", -1, &s,
                         NULL) != SQLITE_OK)
    return sql_error(db, err, "cannot prepare a statement");
  vr_status st = VR_OK;
  if (sqlite3_step(s) == SQLITE_ROW) {
    *rows = sqlite3_column_int64(s, 0);
    *max_id = sqlite3_column_int64(s, 1);
  } else {
    st = sql_error(db, err, "cannot count the materials");
  }
  sqlite3_finalize(s);
  return st;
}

vr_status vr_matdb_history(vr_matdb *db, const char *name, vr_matdb_visit visit, void *user,
                           vr_error *err) {
  sqlite3_stmt *s;
  if (sqlite3_prepare_v2(db->db, "SELECT " ENTRY_COLUMNS " FROM material m WHERE m.name = ? ORDER BY m.version",
                         -1, &s, NULL) != SQLITE_OK)
    return sql_error(db, err, "cannot prepare a statement");
  sqlite3_bind_text(s, 1, name, -1, SQLITE_TRANSIENT);
  int seen = 0, rc;
  while ((rc = sqlite3_step(s)) == SQLITE_ROW) {
    seen++;
    vr_matdb_entry e = entry_of(s);
    if (visit(&e, user)) break;
  }
  sqlite3_finalize(s);
  if (rc != SQLITE_ROW && rc != SQLITE_DONE) return sql_error(db, err, "cannot read history");
  if (!seen) return vr_error_set(err, VR_E_NOT_FOUND, "%s: unknown material '%s'", db->path, name);
  return VR_OK;
}

vr_status vr_matdb_check(vr_matdb *db, bool *ok, char *report, size_t size, vr_error *err) {
  sqlite3_stmt *s;
  if (sqlite3_prepare_v2(db->db, "PRAGMA integrity_check", -1, &s, NULL) != SQLITE_OK)
    return sql_error(db, err, "cannot run the integrity check");
  size_t used = 0;
  *ok = true;
  report[0] = '\0';
  while (sqlite3_step(s) == SQLITE_ROW) {
    const char *line = col_text(s, 0);
    if (strcmp(line, "ok")) *ok = false;
    used += (size_t)snprintf(report + used, used < size ? size - used : 0, "%s\n", line);
    if (used >= size) used = size;
  }
  sqlite3_finalize(s);
  sqlite3_stmt *fk;
  if (sqlite3_prepare_v2(db->db, "PRAGMA foreign_key_check", -1, &fk, NULL) == SQLITE_OK) {
    if (sqlite3_step(fk) == SQLITE_ROW) {
      *ok = false;
      snprintf(report + used, used < size ? size - used : 0, "dangling rows in %s\n", col_text(fk, 0));
    }
    sqlite3_finalize(fk);
  }
  return VR_OK;
}
