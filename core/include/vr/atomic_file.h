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
  long long queued; /* bytes handed to the kernel's writeback so far */
} vr_atomic_file;

vr_status vr_atomic_file_open(vr_atomic_file *f, const char *path, vr_error *err);
/* Flushes, syncs and renames; on failure removes the temporary file. */
vr_status vr_atomic_file_commit(vr_atomic_file *f, vr_error *err);
/* For large sequential outputs: once `end` (bytes written so far) is at
 * least 16 MiB past what was last queued, flushes the stream and asks the
 * kernel to start writing those bytes to disk (Linux sync_file_range with
 * SYNC_FILE_RANGE_WRITE, which does not wait).  The disk then works while
 * the program computes, and the fsync of commit has little left to do.  A
 * hint only: failures are ignored here and caught by commit's fsync. */
void vr_atomic_file_writeback(vr_atomic_file *f, long long end);
/* Gives up: closes and removes the temporary file, leaves the target as it was. */
void vr_atomic_file_abort(vr_atomic_file *f);

#ifdef __cplusplus
}
#endif
#endif
