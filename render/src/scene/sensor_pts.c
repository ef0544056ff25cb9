/* Radiance's sensor points files (.pts): one point a line, "x y z dx dy
 * dz", the position (in metres, the scene's unit) and the direction the
 * sensor faces, as rtrace reads them and as Honeybee, DIVA and `cnt |
 * rcalc` write them.  Split by the project's delimited-text reader
 * (vr/csv.h: blanks, tabs or commas, '#' comment lines, blank lines, CRLF
 * and a UTF-8 BOM).  Every field must be a finite number and the direction
 * not zero (it is made unit); a line of more or fewer than six fields, a
 * NaN, an empty file are refused naming the file, the line and the field. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scene/scene_parse.h"
#include "vr/csv.h"

#define PTS_MAX 1000000 /* points a file may hold */

static const char *const FIELD[6] = {"x", "y", "z", "dx", "dy", "dz"};

/* Row r of csv as a point: six finite numbers, the direction made unit. */
static vr_status point_of(const vr_csv *csv, size_t r, double v[6], vr_error *err) {
  const char *path = vr_csv_name(csv);
  long line = vr_csv_line(csv, r);
  size_t n = vr_csv_cols(csv, r);
  if (n > 6) return vr_error_set(err, VR_E_PARSE, "%s:%ld: more than six fields (x y z dx dy dz)", path, line);
  if (n < 6)
    return vr_error_set(err, VR_E_PARSE, "%s:%ld: %zu fields, six expected (x y z dx dy dz): field %zu (%s) "
                        "is missing", path, line, n, n + 1, FIELD[n]);
  for (size_t f = 0; f < 6; f++) {
    const char *s = vr_csv_field(csv, r, f);
    char *end;
    v[f] = strtod(s, &end);
    if (end == s || *end || !isfinite(v[f]))
      return vr_error_set(err, VR_E_PARSE, "%s:%ld: field %zu (%s): \"%s\" is not a finite number",
                          path, line, f + 1, FIELD[f], s);
  }
  /* Scaled by the largest component first: 1e200 1e200 0 and 1e-170 0 0
   * are directions too. */
  double big = fmax(fabs(v[3]), fmax(fabs(v[4]), fabs(v[5]))), l = 0;
  if (big > 0) {
    for (int a = 3; a < 6; a++) v[a] /= big;
    l = sqrt(v[3] * v[3] + v[4] * v[4] + v[5] * v[5]);
  }
  if (!(l > 0) || !isfinite(l))
    return vr_error_set(err, VR_E_PARSE, "%s:%ld: fields 4-6 (dx dy dz): a zero direction", path, line);
  for (int a = 3; a < 6; a++) v[a] /= l;
  return VR_OK;
}

vr_status scn_read_pts(const char *path, double **out, int *n, vr_error *err) {
  *out = NULL;
  *n = 0;
  vr_csv *csv = NULL;
  vr_status st = vr_csv_read(path, &csv, err);
  if (st) return st;
  size_t rows = vr_csv_rows(csv);
  double *pts = NULL;
  if (!rows)
    st = vr_error_set(err, VR_E_PARSE, "%s: no point (a line x y z dx dy dz)", path);
  else if (rows > PTS_MAX)
    st = vr_error_set(err, VR_E_RANGE, "%s:%ld: more than %d points", path,
                      vr_csv_line(csv, PTS_MAX), PTS_MAX);
  else if (!(pts = malloc(rows * 6 * sizeof *pts)))
    st = vr_error_set(err, VR_E_NOMEM, "%s: out of memory", path);
  for (size_t r = 0; !st && r < rows; r++) st = point_of(csv, r, pts + 6 * r, err);
  vr_csv_destroy(csv);
  if (st) {
    free(pts);
    return st;
  }
  *out = pts;
  *n = (int)rows;
  return VR_OK;
}
