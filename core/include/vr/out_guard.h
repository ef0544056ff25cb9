/* Output paths checked before any work: an output never replaces a file the
 * same run reads (its measurement, photo, scene or material database), and
 * an output whose folder is missing or not writable is refused at once, not
 * after an hour of rendering.
 *
 * Inputs are compared by device and inode (stat, following symbolic links),
 * so "./data.csv", a hard link to it and a symbolic link to it are all the
 * same file.  An output that does not exist yet cannot be an input. */
#ifndef VR_OUT_GUARD_H
#define VR_OUT_GUARD_H

#include <stddef.h>

#include "vr/error.h"

#ifdef __cplusplus
extern "C" {
#endif

#define VR_OUT_GUARD_MAX 64

typedef struct vr_out_guard {
  int n;
  /* The material database (vr_out_guard_database), by device and inode,
   * so that its journal names are refused whether or not they exist. */
  int has_db;
  unsigned long long db_dev, db_ino;
  char db_path[4096];
  struct {
    unsigned long long dev, ino;
    char role[48];     /* "the measurement", "the material database", ... */
    char path[512];
  } in[VR_OUT_GUARD_MAX];
} vr_out_guard;

void vr_out_guard_init(vr_out_guard *g);

/* Records an input (role: what it is, for the message).  A path that does
 * not exist is skipped (a database that will be created).  Beyond
 * VR_OUT_GUARD_MAX inputs the rest are not recorded. */
void vr_out_guard_input(vr_out_guard *g, const char *path, const char *role);

/* Records the material database: the file itself and its SQLite companions
 * (PATH-wal, PATH-shm, PATH-journal), these by name whether or not they
 * exist at the moment (SQLite makes and deletes them while the database is
 * open, so an output there would be deleted or corrupt the database): an
 * output whose name is the database's (through any link or relative path)
 * followed by one of the three suffixes is refused. */
void vr_out_guard_database(vr_out_guard *g, const char *db_path);

/* VR_E_ARG when `path` (given by `option`, e.g. "--report") is empty, is a
 * recorded input, or is an existing folder; VR_E_IO when its folder does
 * not exist or cannot be written.  The message names the option, the path
 * and, for an input, what it is. */
vr_status vr_out_guard_check(const vr_out_guard *g, const char *path, const char *option,
                             vr_error *err);

/* Two outputs of one run must differ too (--csv and --json given the same
 * file): VR_E_ARG naming both options when they are the same file or name. */
vr_status vr_out_guard_distinct(const char *a, const char *option_a, const char *b,
                                const char *option_b, vr_error *err);

/* The folder part of a path into dir: "." when it has none, "/" for a
 * file at the root. */
void vr_path_folder(const char *path, char *dir, size_t cap);

#ifdef __cplusplus
}
#endif
#endif
