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

/* Inputs are regular files: VR_E_IO "PATH: cannot open: REASON" when it
 * does not exist or cannot be examined, VR_E_ARG "PATH: is a folder / a
 * named pipe (FIFO) / a character device / a block device / a socket, not a
 * regular file" otherwise (symbolic links followed: a link to /dev/zero is
 * a device). */
vr_status vr_file_check_regular(const char *path, vr_error *err);
/* A text input's encoding: VR_E_PARSE naming it when the bytes start with a
 * UTF-16 or UTF-32 byte-order mark (or look like UTF-16 without one: every
 * other byte of the first line NUL), with what to do (save as UTF-8);
 * VR_OK otherwise (ASCII, UTF-8 with or without its mark). */
vr_status vr_text_check_encoding(const char *buf, size_t len, const char *name, vr_error *err);
/* The bound on a text input read whole when the reader gives none. */
#define VR_TEXT_MAX_BYTES ((size_t)1 << 30)
/* VR_E_IO naming the path when it cannot be opened or read; VR_E_ARG when it
 * is not a regular file (vr_file_check_regular); VR_E_RANGE when it is
 * larger than max_bytes (0: no limit). */
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
