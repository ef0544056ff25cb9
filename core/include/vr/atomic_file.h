/* Output files that appear whole or not at all: written under a temporary
 * name in the same directory, flushed, then renamed over the target. */
#ifndef VR_ATOMIC_FILE_H
#define VR_ATOMIC_FILE_H

#include <stdio.h>
#include "vr/error.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vr_atomic_file {
  FILE *fp;
  char path[4096];
  char tmp[4096 + 32];
} vr_atomic_file;

vr_status vr_atomic_file_open(vr_atomic_file *f, const char *path, vr_error *err);
/* Flushes, syncs and renames; on failure removes the temporary file. */
vr_status vr_atomic_file_commit(vr_atomic_file *f, vr_error *err);
/* Gives up: closes and removes the temporary file, leaves the target as it was. */
void vr_atomic_file_abort(vr_atomic_file *f);

#ifdef __cplusplus
}
#endif
#endif
