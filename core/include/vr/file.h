/* Whole files into memory, for the readers that parse text they hold at
 * once.  The buffer is NUL-terminated (not counted in len) and belongs to
 * the caller (free()). */
#ifndef VR_FILE_H
#define VR_FILE_H

#include <stddef.h>
#include <stdio.h>
#include "vr/error.h"

#ifdef __cplusplus
extern "C" {
#endif

/* VR_E_IO naming the path when it cannot be opened or read; VR_E_RANGE when
 * it is larger than max_bytes (0: no limit). */
vr_status vr_read_file(const char *path, size_t max_bytes, char **text, size_t *len,
                       vr_error *err);

/* The same from an open stream, read to its end and left open (standard
 * input, a pipe); name is used in messages only. */
vr_status vr_read_stream(FILE *f, const char *name, size_t max_bytes, char **text, size_t *len,
                         vr_error *err);

#ifdef __cplusplus
}
#endif
#endif
