/* Reading whole files (vr/file.h). */
#include "vr/file.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

vr_status vr_read_file(const char *path, size_t max_bytes, char **text, size_t *len,
                       vr_error *err) {
  *text = NULL;
  *len = 0;
  FILE *f = fopen(path, "rb");
  if (!f) return vr_error_set(err, VR_E_IO, "%s: cannot open: %s", path, strerror(errno));
  vr_status st = vr_read_stream(f, path, max_bytes, text, len, err);
  fclose(f);
  return st;
}

vr_status vr_read_stream(FILE *f, const char *name, size_t max_bytes, char **text, size_t *len,
                         vr_error *err) {
  *text = NULL;
  *len = 0;
  size_t cap = 1 << 16, n = 0;
  char *buf = malloc(cap + 1);
  vr_status st = buf ? VR_OK : vr_error_set(err, VR_E_NOMEM, "out of memory reading %s", name);
  while (!st) {
    n += fread(buf + n, 1, cap - n, f);
    if (ferror(f)) st = vr_error_set(err, VR_E_IO, "%s: read error", name);
    else if (max_bytes && n > max_bytes)
      st = vr_error_set(err, VR_E_RANGE, "%s: larger than %zu bytes", name, max_bytes);
    else if (n < cap) break;
    else {
      char *grown = realloc(buf, 2 * cap + 1);
      if (!grown) st = vr_error_set(err, VR_E_NOMEM, "out of memory reading %s", name);
      else buf = grown, cap *= 2;
    }
  }
  if (st) {
    free(buf);
    return st;
  }
  buf[n] = '\0';
  *text = buf;
  *len = n;
  return VR_OK;
}
