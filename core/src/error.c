/* vr_error: one message per failure, formatted where the failure is known. */
#include "vr/error.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

static void vformat(vr_error *err, const char *prefix, const char *fmt, va_list ap) {
  size_t used = 0;
  if (prefix) {
    int n = snprintf(err->message, sizeof err->message, "%s", prefix);
    used = n < 0 ? 0 : (size_t)n;
    if (used >= sizeof err->message) used = sizeof err->message - 1;
  }
  vsnprintf(err->message + used, sizeof err->message - used, fmt, ap);
}

vr_status vr_error_set(vr_error *err, vr_status status, const char *fmt, ...) {
  if (!err) return status;
  err->status = status;
  va_list ap;
  va_start(ap, fmt);
  vformat(err, NULL, fmt, ap);
  va_end(ap);
  return status;
}

vr_status vr_error_at(vr_error *err, vr_status status, const char *file,
                      long line, long col, const char *fmt, ...) {
  if (!err) return status;
  char prefix[512];
  if (line > 0 && col > 0)
    snprintf(prefix, sizeof prefix, "%s:%ld:%ld: ", file ? file : "<input>", line, col);
  else if (line > 0)
    snprintf(prefix, sizeof prefix, "%s:%ld: ", file ? file : "<input>", line);
  else
    snprintf(prefix, sizeof prefix, "%s: ", file ? file : "<input>");
  err->status = status;
  va_list ap;
  va_start(ap, fmt);
  vformat(err, prefix, fmt, ap);
  va_end(ap);
  return status;
}

void vr_error_prefix(vr_error *err, const char *fmt, ...) {
  if (!err) return;
  char prefix[512], old[VR_ERROR_MESSAGE_MAX];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(prefix, sizeof prefix, fmt, ap);
  va_end(ap);
  memcpy(old, err->message, sizeof old);
  /* Truncation is acceptable here: the start of a message matters most. */
  size_t lp = strnlen(prefix, sizeof prefix), lo = strnlen(old, sizeof old - 1);
  if (lp > sizeof err->message - 1) lp = sizeof err->message - 1;
  if (lo > sizeof err->message - 1 - lp) lo = sizeof err->message - 1 - lp;
  memcpy(err->message, prefix, lp);
  memcpy(err->message + lp, old, lo);
  err->message[lp + lo] = '\0';
}

void vr_error_clear(vr_error *err) {
  if (!err) return;
  err->status = VR_OK;
  err->message[0] = '\0';
}

const char *vr_status_name(vr_status status) {
  switch (status) {
  case VR_OK: return "ok";
  case VR_E_ARG: return "invalid argument";
  case VR_E_IO: return "i/o error";
  case VR_E_PARSE: return "parse error";
  case VR_E_RANGE: return "out of range";
  case VR_E_NOMEM: return "out of memory";
  case VR_E_NUMERIC: return "numerical failure";
  case VR_E_DB: return "database error";
  case VR_E_NOT_FOUND: return "not found";
  }
  return "unknown error";
}
