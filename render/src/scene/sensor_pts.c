/* Radiance's sensor points files (.pts): one point a line, "x y z dx dy
 * dz", the position (in metres, the scene's unit) and the direction the
 * sensor faces, as rtrace reads
 * them and as Honeybee, DIVA and `cnt | rcalc` write them; blank lines and
 * '#' comments skipped.  Every field must be a finite number and the
 * direction not zero (it is made unit); a line of more or fewer than six
 * fields, a NaN, an empty file are refused naming the file, the line and
 * the field. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scene/scene_parse.h"
#include "vr/file.h"

#define PTS_MAX 1000000 /* points a file may hold */

static const char *const FIELD[6] = {"x", "y", "z", "dx", "dy", "dz"};

vr_status scn_read_pts(const char *path, double **out, int *n, vr_error *err) {
  char *text = NULL;
  size_t len = 0;
  *out = NULL;
  *n = 0;
  vr_status st = vr_read_file(path, (size_t)1 << 28, &text, &len, err);
  if (st) return st;
  size_t cap = 0, k = 0;
  size_t skip = len >= 3 && !memcmp(text, "\xEF\xBB\xBF", 3) ? 3 : 0; /* a UTF-8 BOM */
  double *pts = NULL;
  long line = 0;
  for (char *at = text + skip, *next; at < text + len; at = next) {
    line++;
    char *eol = memchr(at, '\n', (size_t)(text + len - at));
    next = eol ? eol + 1 : text + len;
    if (eol) *eol = 0;
    char *hash = strchr(at, '#');
    if (hash) *hash = 0;
    double v[6];
    int f = 0;
    char *p = at;
    for (;;) {
      while (*p == ' ' || *p == '\t' || *p == '\r' || *p == ',') p++;
      if (!*p) break;
      if (f == 6) {
        st = vr_error_set(err, VR_E_PARSE, "%s:%ld: more than six fields (x y z dx dy dz)", path, line);
        goto fail;
      }
      char *end;
      errno = 0;
      v[f] = strtod(p, &end);
      if (end == p || !isfinite(v[f]) || (*end && !strchr(" \t\r,", *end))) {
        st = vr_error_set(err, VR_E_PARSE, "%s:%ld: field %d (%s): \"%.*s\" is not a finite number",
                          path, line, f + 1, FIELD[f], (int)strcspn(p, " \t\r,"), p);
        goto fail;
      }
      f++;
      p = end;
    }
    if (f == 0) continue;
    if (f < 6) {
      st = vr_error_set(err, VR_E_PARSE, "%s:%ld: %d fields, six expected (x y z dx dy dz): "
                        "field %d (%s) is missing", path, line, f, f + 1, FIELD[f]);
      goto fail;
    }
    /* Scaled by the largest component first: 1e200 1e200 0 and 1e-170 0 0
     * are directions too. */
    double big = fmax(fabs(v[3]), fmax(fabs(v[4]), fabs(v[5]))), l = 0;
    if (big > 0) {
      for (int a = 3; a < 6; a++) v[a] /= big;
      l = sqrt(v[3] * v[3] + v[4] * v[4] + v[5] * v[5]);
    }
    if (!(l > 0) || !isfinite(l)) {
      st = vr_error_set(err, VR_E_PARSE, "%s:%ld: fields 4-6 (dx dy dz): a zero direction", path, line);
      goto fail;
    }
    if (k == PTS_MAX) {
      st = vr_error_set(err, VR_E_RANGE, "%s:%ld: more than %d points", path, line, PTS_MAX);
      goto fail;
    }
    if (k == cap) {
      cap = cap ? 2 * cap : 256;
      double *q = realloc(pts, cap * 6 * sizeof *q);
      if (!q) {
        st = vr_error_set(err, VR_E_NOMEM, "%s: out of memory", path);
        goto fail;
      }
      pts = q;
    }
    for (int a = 0; a < 3; a++) pts[6 * k + (size_t)a] = v[a], pts[6 * k + 3 + (size_t)a] = v[3 + a] / l;
    k++;
  }
  if (!k) {
    st = vr_error_set(err, VR_E_PARSE, "%s: no point (a line x y z dx dy dz)", path);
    goto fail;
  }
  free(text);
  *out = pts;
  *n = (int)k;
  return VR_OK;
fail:
  free(text);
  free(pts);
  return st;
}
