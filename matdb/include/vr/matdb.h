/* The material database: one SQLite file that every tool writes to and the
 * renderer reads from.
 *
 * Location: the path given, else $VR_MATDB, else "materials.db" in the
 * working directory.  The first open creates the schema and seeds the
 * built-in library (standard glasses, metals, Si, CIE illuminants, the
 * ASTM G173 solar spectra, the ColorChecker), each with its published
 * source.  Saving a material under an existing name adds a new version;
 * loads take the newest unless a version is named.  Every save is one
 * transaction: a failure or a killed process leaves the file as it was.  The
 * file is in WAL mode, so any number of readers work while one process
 * writes.  A handle is for one thread; open one per thread. */
#ifndef VR_MATDB_H
#define VR_MATDB_H

#include <stdbool.h>
#include <stddef.h>
#include "vr/error.h"
#include "vr/material.h"

#ifdef __cplusplus
extern "C" {
#endif

#define VR_MATDB_SCHEMA_VERSION 1

typedef struct vr_matdb vr_matdb;

enum {
  VR_MATDB_READONLY = 1,
  /* For commands that only read: an explicit path (not NULL) that names no
   * file is refused (VR_E_NOT_FOUND, with how to create one) instead of
   * becoming a new database, so a mistyped --db leaves nothing behind.
   * The default path (NULL) is still created on first use. */
  VR_MATDB_MUST_EXIST = 2
};

/* path NULL: $VR_MATDB or "materials.db" ($VR_MATDB set but empty counts as
 * unset); path "" is refused (VR_E_ARG).  A missing or empty (0-byte, or
 * SQLite without tables) file is a new database: a read-write open creates
 * the schema and seeds it, a read-only open fails.
 *
 * What an existing file is, is checked before anything is written to it:
 * something that is not SQLite, a SQLite file that is not a material
 * database, and a schema newer than this build are refused with a message
 * naming the file, and the file is left byte for byte as it was.
 *
 * flags VR_MATDB_READONLY, or a file or folder this process cannot write:
 * the database is opened for reading only (never switched to WAL, never
 * seeded); reads work, and saves and removals fail with "the material
 * database is read-only (why)".  A WAL-mode file in a folder that cannot be
 * written and has no -wal file beside it is read as immutable (SQLite
 * cannot create the -shm file there). */
vr_status vr_matdb_open(const char *path, int flags, vr_matdb **out, vr_error *err);
/* NULL when writable, else why not ("the file is not writable", "its folder
 * F is not writable", "opened for reading only"). */
const char *vr_matdb_readonly(const vr_matdb *db);
/* VR_OK when writable, else VR_E_DB "PATH: the material database is
 * read-only (why); nothing was written": for tools to refuse a write before
 * doing the work. */
vr_status vr_matdb_require_writable(const vr_matdb *db, vr_error *err);
void vr_matdb_close(vr_matdb *db);
const char *vr_matdb_path(const vr_matdb *db);
/* The path vr_matdb_open(NULL, ...) would use: $VR_MATDB when set and not
 * empty, else "materials.db". */
const char *vr_matdb_default_path(void);
/* Does the text file at path (a model file, a capture manifest) name a
 * database material ("db:NAME" outside '#' comments)?  Tools open the
 * database only then, so a run that needs none leaves no file behind.
 * false when the file cannot be read (its reader reports that). */
bool vr_matdb_named_in(const char *path);

/* Saves m as a new version of m->name; sets m->version and
 * m->prov.created_at.  Validates first: a name, data fitting the kind (n for
 * dielectrics and conductors, "value" for reflectances and illuminants, T,
 * Rf and Rb for glazing), k >= 0, no negative thickness. */
vr_status vr_matdb_save(vr_matdb *db, vr_material *m, vr_error *err);
/* version 0: the newest. */
vr_status vr_matdb_load(vr_matdb *db, const char *name, int version, vr_material **out,
                        vr_error *err);
/* Removes every version of name; VR_E_NOT_FOUND if there is none. */
vr_status vr_matdb_remove(vr_matdb *db, const char *name, int *removed_versions, vr_error *err);

typedef struct vr_matdb_entry {
  const char *name;
  int version;          /* newest (list) or this row's (history) */
  int versions;         /* how many versions exist */
  const char *kind;
  const char *created_at;
  const char *tool;
  const char *tool_version;
  const char *source_path;
  const char *source_sha256;
  const char *model;
  const char *reference;
  const char *note;
  double residual;      /* NAN if none */
} vr_matdb_entry;
typedef int (*vr_matdb_visit)(const vr_matdb_entry *e, void *user); /* non-zero stops */

/* The newest version of every material, by name; kind NULL for all. */
vr_status vr_matdb_list(vr_matdb *db, const char *kind, vr_matdb_visit visit, void *user,
                        vr_error *err);
/* Every version of one material, oldest first. */
vr_status vr_matdb_history(vr_matdb *db, const char *name, vr_matdb_visit visit, void *user,
                           vr_error *err);
/* SQLite's integrity check plus the schema version; ok set to true if sound. */
vr_status vr_matdb_check(vr_matdb *db, bool *ok, char *report, size_t size, vr_error *err);
/* What the database holds, in two numbers that any save or removal
 * changes (the rows of materials and the largest material id): for a tool
 * that created a database to tell whether anyone wrote to it since. */
vr_status vr_matdb_revision(vr_matdb *db, long long *rows, long long *max_id, vr_error *err);

#ifdef __cplusplus
}
#endif
#endif
