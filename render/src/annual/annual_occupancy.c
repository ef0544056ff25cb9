/* An occupancy schedule for the annual study (annual occupancy=FILE): which
 * records of the weather file are occupied hours.  Two forms are read, as
 * daylighting tools write them:
 *   - a Daysim occupancy file: '#' header lines, then "month,day,time,
 *     occupancy" rows, time the centre of the hour in local standard time
 *     (0.5 .. 23.5 for hourly steps) and occupancy 1 (present) or 0; each
 *     row is matched to the weather record of that month and day whose
 *     interval holds that time, so the two files need not list the hours in
 *     the same order;
 *   - one value per line, 0 or 1, one line per weather record in the
 *     weather file's order (the schedules Ladybug / Honeybee write).
 * Every weather record must be given a value, and every row must match a
 * record; anything else names the file, the line and the field. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "annual/annual_internal.h"
#include "vr/csv.h"

/* A present/absent value: exactly 0 or 1. */
static vr_status presence(const vr_csv *c, size_t row, size_t col, const char *field, bool *out,
                          vr_error *err) {
  double v;
  vr_status st = vr_csv_number(c, row, col, field, &v, err);
  if (st) return st;
  if (v != 0 && v != 1)
    return vr_error_at(err, VR_E_PARSE, vr_csv_name(c), vr_csv_line(c, row),
                       vr_csv_col_pos(c, row, col),
                       "field '%s': %g is neither 1 (present) nor 0 (absent)", field, v);
  *out = v == 1;
  return VR_OK;
}

/* The record of month/day whose interval [start, end) holds hour t, or -1.
 * The records of a day are contiguous in a weather file; first[] indexes
 * the first record of each month*32+day. */
static long record_at(const vr_weather *w, const long *first, int month, int day, double t) {
  if (month < 1 || month > 12 || day < 1 || day > 31) return -1;
  long i = first[month * 32 + day];
  if (i < 0) return -1;
  for (; (size_t)i < w->nrecords && w->records[i].month == month && w->records[i].day == day; i++)
    if (t >= w->records[i].start_h && t < w->records[i].end_h) return i;
  return -1;
}

static vr_status daysim_rows(const vr_csv *c, const vr_weather *w, bool *occ, vr_error *err) {
  const char *name = vr_csv_name(c);
  long first[13 * 32];
  for (size_t k = 0; k < sizeof first / sizeof *first; k++) first[k] = -1;
  for (size_t i = w->nrecords; i-- > 0;)
    first[w->records[i].month * 32 + w->records[i].day] = (long)i;
  long *row_of = malloc((w->nrecords + 1) * sizeof *row_of);
  if (!row_of) return vr_error_set(err, VR_E_NOMEM, "%s: out of memory", name);
  for (size_t i = 0; i < w->nrecords; i++) row_of[i] = -1;
  vr_status st = VR_OK;
  static const char *const FIELDS[] = {"month", "day", "time", "occupancy"};
  for (size_t r = 0; r < vr_csv_rows(c) && !st; r++) {
    if (vr_csv_cols(c, r) != 4) {
      st = vr_error_at(err, VR_E_PARSE, name, vr_csv_line(c, r), 1,
                       "%zu fields; a Daysim occupancy row is month,day,time,occupancy",
                       vr_csv_cols(c, r));
      break;
    }
    double v[3];
    for (int k = 0; k < 3 && !st; k++) st = vr_csv_number(c, r, (size_t)k, FIELDS[k], &v[k], err);
    bool present = false;
    if (!st) st = presence(c, r, 3, FIELDS[3], &present, err);
    if (st) break;
    if (v[0] != floor(v[0]) || v[1] != floor(v[1]) || !(v[2] >= 0 && v[2] < 24)) {
      st = vr_error_at(err, VR_E_PARSE, name, vr_csv_line(c, r), 1,
                       "month %g, day %g, time %g: not a month, a day and an hour in [0, 24)",
                       v[0], v[1], v[2]);
      break;
    }
    long i = record_at(w, first, (int)v[0], (int)v[1], v[2]);
    if (i < 0) {
      st = vr_error_at(err, VR_E_PARSE, name, vr_csv_line(c, r), 1,
                       "month %g, day %g, time %g: no record of the weather file %s holds this "
                       "hour",
                       v[0], v[1], v[2], w->path);
      break;
    }
    if (row_of[i] >= 0) {
      st = vr_error_at(err, VR_E_PARSE, name, vr_csv_line(c, r), 1,
                       "month %g, day %g, time %g: the weather record at %s:%ld already has its "
                       "occupancy (line %ld)",
                       v[0], v[1], v[2], w->path, w->records[i].line, row_of[i]);
      break;
    }
    row_of[i] = vr_csv_line(c, r);
    occ[i] = present;
  }
  for (size_t i = 0; i < w->nrecords && !st; i++)
    if (row_of[i] < 0)
      st = vr_error_set(err, VR_E_PARSE,
                        "%s: no occupancy row for the weather record at %s:%ld (month %d, day %d, "
                        "%g-%g h)",
                        name, w->path, w->records[i].line, w->records[i].month, w->records[i].day,
                        w->records[i].start_h, w->records[i].end_h);
  free(row_of);
  return st;
}

static vr_status value_rows(const vr_csv *c, const vr_weather *w, bool *occ, vr_error *err) {
  const char *name = vr_csv_name(c);
  size_t n = vr_csv_rows(c);
  for (size_t r = 0; r < n; r++) {
    if (vr_csv_cols(c, r) != 1)
      return vr_error_at(err, VR_E_PARSE, name, vr_csv_line(c, r), 1,
                         "%zu fields; a schedule of one value per weather record has one per "
                         "line",
                         vr_csv_cols(c, r));
    if (r >= w->nrecords)
      return vr_error_at(err, VR_E_PARSE, name, vr_csv_line(c, r), 1,
                         "more values than the %zu records of the weather file %s", w->nrecords,
                         w->path);
    vr_status st = presence(c, r, 0, "occupancy", &occ[r], err);
    if (st) return st;
  }
  if (n != w->nrecords)
    return vr_error_set(err, VR_E_PARSE,
                        "%s: %zu values for the %zu records of the weather file %s (one per "
                        "record, in its order)",
                        name, n, w->nrecords, w->path);
  return VR_OK;
}

vr_status annual_occupancy_read(const char *path, const vr_weather *w, bool *occ, vr_error *err) {
  vr_csv *c = NULL;
  vr_status st = vr_csv_read(path, &c, err);
  if (st) return st;
  if (!vr_csv_rows(c)) st = vr_error_set(err, VR_E_PARSE, "%s: no occupancy values", path);
  else if (vr_csv_cols(c, 0) == 4) st = daysim_rows(c, w, occ, err);
  else st = value_rows(c, w, occ, err);
  vr_csv_destroy(c);
  return st;
}
