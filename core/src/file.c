/* Reading whole files (vr/file.h). */
#include "vr/file.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

vr_status vr_file_check_regular(const char *path, vr_error *err) {
  struct stat st;
  if (stat(path, &st) != 0) return vr_error_set(err, VR_E_IO, "%s: cannot open: %s", path, strerror(errno));
  const char *what = S_ISREG(st.st_mode)    ? NULL
                     : S_ISDIR(st.st_mode)  ? "a folder"
                     : S_ISFIFO(st.st_mode) ? "a named pipe (FIFO)"
                     : S_ISCHR(st.st_mode)  ? "a character device"
                     : S_ISBLK(st.st_mode)  ? "a block device"
                     : S_ISSOCK(st.st_mode) ? "a socket"
                                            : "not a file";
  if (!what) return VR_OK;
  return vr_error_set(err, VR_E_ARG, "%s: is %s, not a regular file", path, what);
}

vr_status vr_text_check_encoding(const char *buf, size_t len, const char *name, vr_error *err) {
  const unsigned char *b = (const unsigned char *)buf;
  const char *enc = NULL;
  if (len >= 4 && b[0] == 0xFF && b[1] == 0xFE && b[2] == 0 && b[3] == 0) enc = "UTF-32 (little-endian)";
  else if (len >= 4 && b[0] == 0 && b[1] == 0 && b[2] == 0xFE && b[3] == 0xFF) enc = "UTF-32 (big-endian)";
  else if (len >= 2 && b[0] == 0xFF && b[1] == 0xFE) enc = "UTF-16 (little-endian)";
  else if (len >= 2 && b[0] == 0xFE && b[1] == 0xFF) enc = "UTF-16 (big-endian)";
  else if (len >= 8) {
    /* No mark: ASCII text in UTF-16 has a NUL in every other byte. */
    size_t n = len < 64 ? len & ~(size_t)1 : 64, z0 = 0, z1 = 0;
    for (size_t i = 0; i < n; i += 2) z0 += b[i] == 0, z1 += b[i + 1] == 0;
    if (z1 == n / 2 && z0 == 0) enc = "UTF-16 (little-endian, without a byte-order mark)";
    else if (z0 == n / 2 && z1 == 0) enc = "UTF-16 (big-endian, without a byte-order mark)";
  }
  if (!enc) return VR_OK;
  return vr_error_set(err, VR_E_PARSE,
                      "%s: is %s text; save it as UTF-8 or ASCII (\"iconv -f UTF-16 -t UTF-8\", "
                      "or a spreadsheet's \"CSV UTF-8\")",
                      name, enc);
}

vr_status vr_read_file(const char *path, size_t max_bytes, char **text, size_t *len,
                       vr_error *err) {
  *text = NULL;
  *len = 0;
  vr_status rs = vr_file_check_regular(path, err);
  if (rs) return rs;
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
