/* Pieces of the material database shared between its sources. */
#ifndef VR_MATDB_INTERNAL_H
#define VR_MATDB_INTERNAL_H

#include <sqlite3.h>
#include "vr/matdb.h"

struct vr_matdb {
  sqlite3 *db;
  char *path;
  int readonly;
  char ro_reason[256]; /* why it is read-only; empty when writable */
};

/* Inserts m as a new version inside the caller's transaction. */
vr_status vr_matdb_insert(vr_matdb *db, vr_material *m, vr_error *err);
/* Seeds the built-in library inside the caller's transaction. */
vr_status vr_matdb_seed(vr_matdb *db, vr_error *err);
/* Checks a material before it is written (see vr_matdb_save). */
vr_status vr_matdb_validate(const vr_material *m, vr_error *err);
/* VR_E_DB "PATH: what: SQLite's message", with what to do for the
 * failures a user can act on: a lock held past the busy timeout, a full
 * disk or quota, a read-only file system. */
vr_status vr_matdb_sql_error(vr_matdb *db, vr_error *err, const char *what);

/* Current UTC time as ISO 8601 ("2026-11-21T20:30:00Z"). */
void vr_matdb_now(char buf[32]);

#endif
