/* Error reporting shared by every Virtuelium-C library.
 *
 * Functions that can fail return a vr_status and, when given a vr_error,
 * fill it with one human-readable message that names the file, line, column
 * or parameter at fault ("samples/x.csv:12:3: field 'T': expected a number").
 * Libraries never print and never exit; tools print the message and exit. */
#ifndef VR_ERROR_H
#define VR_ERROR_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum vr_status {
  VR_OK = 0,
  VR_E_ARG,         /* a caller passed an invalid argument */
  VR_E_IO,          /* a file could not be opened, read or written */
  VR_E_PARSE,       /* malformed input text */
  VR_E_RANGE,       /* a value outside its physical or tabulated domain */
  VR_E_NOMEM,       /* allocation failed */
  VR_E_NUMERIC,     /* a computation failed (singular matrix, no root, ...) */
  VR_E_DB,          /* material database error */
  VR_E_NOT_FOUND    /* a named thing (material, illuminant, column) is unknown */
} vr_status;

#define VR_ERROR_MESSAGE_MAX 1024

typedef struct vr_error {
  vr_status status;
  char message[VR_ERROR_MESSAGE_MAX];
} vr_error;

/* Records status and a printf-style message; err may be NULL.  Returns status
 * so that callers can write `return vr_error_set(err, VR_E_ARG, "...")`. */
vr_status vr_error_set(vr_error *err, vr_status status, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* Same, prefixed with "file:line:col: " (line or col <= 0 are left out). */
vr_status vr_error_at(vr_error *err, vr_status status, const char *file,
                      long line, long col, const char *fmt, ...)
    __attribute__((format(printf, 6, 7)));

/* Prepends context ("while reading X: ") to an error already set. */
void vr_error_prefix(vr_error *err, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

void vr_error_clear(vr_error *err);

/* Short stable name of a status ("parse error", ...). */
const char *vr_status_name(vr_status status);

#ifdef __cplusplus
}
#endif
#endif
