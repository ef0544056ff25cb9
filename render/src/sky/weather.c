/* EnergyPlus .epw and Radiance/Daysim .wea weather files (vr/weather.h). */
#define _GNU_SOURCE
#include "vr/weather.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct vr_weather_reader {
  const char *path;
  FILE *f;
  char *line;
  size_t cap;
  long n; /* current line number */
  vr_error *err;
} vr_weather_reader;

/* Next line without its end (CR LF or LF); a UTF-8 byte-order mark on the
 * first line is skipped.  false at the end of the file. */
static bool next_line(vr_weather_reader *r) {
  ssize_t len = getline(&r->line, &r->cap, r->f);
  if (len < 0) return false;
  r->n++;
  while (len > 0 && (r->line[len - 1] == '\n' || r->line[len - 1] == '\r')) r->line[--len] = '\0';
  if (r->n == 1 && (unsigned char)r->line[0] == 0xEF && (unsigned char)r->line[1] == 0xBB &&
      (unsigned char)r->line[2] == 0xBF)
    memmove(r->line, r->line + 3, (size_t)len - 2);
  return true;
}

static vr_status bad(vr_weather_reader *r, const char *field, const char *fmt, const char *val) {
  char msg[160];
  snprintf(msg, sizeof msg, fmt, val);
  return vr_error_at(r->err, VR_E_PARSE, r->path, r->n, 0, "%s: %s", field, msg);
}

static bool number(const char *s, double *v) {
  while (*s == ' ' || *s == '\t') s++;
  if (!*s) return false;
  char *end;
  errno = 0;
  *v = strtod(s, &end);
  while (*end == ' ' || *end == '\t') end++;
  return *end == '\0' && errno == 0 && isfinite(*v);
}

/* Splits s at commas in place into at most max fields. */
static int split_commas(char *s, char **f, int max) {
  int n = 0;
  f[n++] = s;
  for (char *c = s; *c && n < max; c++)
    if (*c == ',') *c = '\0', f[n++] = c + 1;
  return n;
}

static vr_status grow(vr_weather_reader *r, vr_weather *w, size_t *cap) {
  if (w->nrecords < *cap) return VR_OK;
  size_t nc = *cap ? *cap * 2 : 1024;
  vr_weather_record *p = realloc(w->records, nc * sizeof *p);
  if (!p) return vr_error_set(r->err, VR_E_NOMEM, "%s: out of memory for weather records", r->path);
  w->records = p, *cap = nc;
  return VR_OK;
}

static void copy_place(vr_weather *w, const char *s) {
  snprintf(w->place, sizeof w->place, "%s", s);
}

/* EPW: LOCATION header, 7 more header lines, then records. */
static vr_status read_epw(vr_weather_reader *r, vr_weather *w) {
  char *f[40];
  char *copy = strdup(r->line);
  if (!copy) return vr_error_set(r->err, VR_E_NOMEM, "out of memory");
  int n = split_commas(copy, f, 40);
  vr_status st = VR_OK;
  double v[4];
  static const char *const LOC[4] = {"latitude", "longitude", "time zone", "elevation"};
  if (n < 10) {
    st = bad(r, "LOCATION", "%s", "needs 10 fields (LOCATION,city,state,country,source,WMO,"
                                  "latitude,longitude,time zone,elevation)");
  } else {
    copy_place(w, f[1]);
    for (int i = 0; i < 4 && !st; i++)
      if (!number(f[6 + i], &v[i])) st = bad(r, LOC[i], "\"%s\" is not a number", f[6 + i]);
  }
  free(copy);
  if (st) return st;
  if (!(v[0] >= -90 && v[0] <= 90)) return bad(r, "latitude", "%s", "must be in [-90, 90]");
  if (!(v[1] >= -180 && v[1] <= 180)) return bad(r, "longitude", "%s", "must be in [-180, 180]");
  if (!(v[2] >= -12 && v[2] <= 14)) return bad(r, "time zone", "%s", "must be in [-12, 14] hours");
  w->latitude_deg = v[0], w->longitude_deg = v[1], w->timezone_h = v[2], w->elevation_m = v[3];
  for (int i = 0; i < 7; i++)
    if (!next_line(r))
      return vr_error_at(r->err, VR_E_PARSE, r->path, r->n, 0,
                         "the file ends inside the EPW header (8 lines expected)");
  size_t cap = 0;
  static const struct {
    int idx;
    const char *name;
  } F[] = {{0, "year"}, {1, "month"}, {2, "day"}, {3, "hour"}, {4, "minute"}, {7, "dew point"},
           {14, "direct normal radiation"}, {15, "diffuse horizontal radiation"}};
  while (next_line(r)) {
    if (!r->line[0]) continue;
    n = split_commas(r->line, f, 40);
    if (n < 16)
      return vr_error_at(r->err, VR_E_PARSE, r->path, r->n, 0,
                         "an EPW record needs at least 16 fields (up to diffuse horizontal "
                         "radiation), this one has %d",
                         n);
    double x[8];
    for (int i = 0; i < 8; i++)
      if (!number(f[F[i].idx], &x[i]))
        return bad(r, F[i].name, "\"%s\" is not a number", f[F[i].idx]);
    if (x[1] < 1 || x[1] > 12 || x[1] != floor(x[1])) return bad(r, "month", "%s", "must be 1..12");
    if (x[2] < 1 || x[2] > 31 || x[2] != floor(x[2])) return bad(r, "day", "%s", "must be 1..31");
    if (x[3] < 1 || x[3] > 24 || x[3] != floor(x[3])) return bad(r, "hour", "%s", "must be 1..24");
    if ((st = grow(r, w, &cap))) return st;
    vr_weather_record *rec = &w->records[w->nrecords];
    rec->year = (int)x[0], rec->month = (int)x[1], rec->day = (int)x[2];
    /* Hourly files: the record ending at hour h covers [h-1, h).  The minute
     * field of sub-hourly files gives the end within the hour (0 or 60 is
     * the full hour). */
    double minute = x[4] >= 60 || x[4] <= 0 ? 60 : x[4];
    rec->end_h = x[3] - 1 + minute / 60.0;
    rec->start_h = w->nrecords && w->records[w->nrecords - 1].month == rec->month &&
                           w->records[w->nrecords - 1].day == rec->day &&
                           w->records[w->nrecords - 1].end_h < rec->end_h
                       ? w->records[w->nrecords - 1].end_h
                       : rec->end_h - (minute < 60 ? minute / 60.0 : 1.0);
    rec->dew_point_c = x[5] >= 99.9 ? NAN : x[5];
    rec->direct_normal_w_m2 = x[6] >= 9999 ? NAN : x[6];
    rec->diffuse_horizontal_w_m2 = x[7] >= 9999 ? NAN : x[7];
    if (x[6] < 0 || x[7] < 0) return bad(r, x[6] < 0 ? F[6].name : F[7].name, "%s", "is negative");
    rec->line = r->n;
    w->nrecords++;
  }
  return VR_OK;
}

/* WEA: six "key value" header lines, then "month day hour dni dhi". */
static vr_status read_wea(vr_weather_reader *r, vr_weather *w) {
  static const char *const KEYS[6] = {"place", "latitude", "longitude", "time_zone",
                                      "site_elevation", "weather_data_file_units"};
  double v[6] = {0};
  for (int i = 0; i < 6; i++) {
    if (i && !next_line(r))
      return vr_error_at(r->err, VR_E_PARSE, r->path, r->n, 0,
                         "the file ends inside the .wea header (line \"%s\" expected)", KEYS[i]);
    size_t k = strlen(KEYS[i]);
    if (strncmp(r->line, KEYS[i], k) || (r->line[k] != ' ' && r->line[k] != '\t'))
      return bad(r, KEYS[i], "this line should start with \"%s\"", KEYS[i]);
    const char *val = r->line + k + 1;
    if (i == 0) {
      copy_place(w, val);
      continue;
    }
    if (!number(val, &v[i])) return bad(r, KEYS[i], "\"%s\" is not a number", val);
  }
  if (!(v[1] >= -90 && v[1] <= 90)) return bad(r, "latitude", "%s", "must be in [-90, 90]");
  if (!(v[2] >= -180 && v[2] <= 180)) return bad(r, "longitude", "%s", "must be in [-180, 180]");
  if (!(v[3] >= -210 && v[3] <= 180)) return bad(r, "time_zone", "%s", "must be in [-210, 180] degrees");
  if (v[5] != 1)
    return bad(r, "weather_data_file_units", "%s",
               "only 1 (direct normal and diffuse horizontal irradiance in W/m2) is read");
  w->latitude_deg = v[1], w->longitude_deg = -v[2], w->timezone_h = -v[3] / 15.0;
  w->elevation_m = v[4];
  size_t cap = 0;
  static const char *const NAMES[5] = {"month", "day", "hour", "direct normal irradiance",
                                       "diffuse horizontal irradiance"};
  while (next_line(r)) {
    char *tok[6], *save = NULL;
    int n = 0;
    for (char *t = strtok_r(r->line, " \t", &save); t && n < 6; t = strtok_r(NULL, " \t", &save))
      tok[n++] = t;
    if (n == 0) continue;
    if (n != 5)
      return vr_error_at(r->err, VR_E_PARSE, r->path, r->n, 0,
                         "a .wea record is \"month day hour dni dhi\" (5 fields), this one has %d", n);
    double x[5];
    for (int i = 0; i < 5; i++)
      if (!number(tok[i], &x[i])) return bad(r, NAMES[i], "\"%s\" is not a number", tok[i]);
    if (x[0] < 1 || x[0] > 12 || x[0] != floor(x[0])) return bad(r, "month", "%s", "must be 1..12");
    if (x[1] < 1 || x[1] > 31 || x[1] != floor(x[1])) return bad(r, "day", "%s", "must be 1..31");
    if (!(x[2] >= 0 && x[2] < 24)) return bad(r, "hour", "%s", "must be in [0, 24)");
    if (x[3] < 0 || x[4] < 0) return bad(r, NAMES[x[3] < 0 ? 3 : 4], "%s", "is negative");
    vr_status st = grow(r, w, &cap);
    if (st) return st;
    vr_weather_record *rec = &w->records[w->nrecords];
    rec->year = 0, rec->month = (int)x[0], rec->day = (int)x[1];
    rec->direct_normal_w_m2 = x[3], rec->diffuse_horizontal_w_m2 = x[4];
    rec->dew_point_c = NAN;
    rec->line = r->n;
    /* The hour is the interval's centre; its width is the step to the
     * neighbouring record on the same day (one hour if alone). */
    rec->start_h = rec->end_h = x[2];
    w->nrecords++;
  }
  /* Interval bounds halfway between neighbouring centres on the same day;
   * at a day's first and last record, half the step to its neighbour (one
   * hour for a record alone on its day).  start_h holds the centre here. */
  for (size_t i = 0; i < w->nrecords; i++) {
    vr_weather_record *rc = &w->records[i];
    double c = rc->start_h;
    bool sp = i && w->records[i - 1].month == rc->month && w->records[i - 1].day == rc->day;
    bool sn = i + 1 < w->nrecords && w->records[i + 1].month == rc->month &&
              w->records[i + 1].day == rc->day;
    double prev = sp ? w->records[i - 1].end_h : NAN; /* already the previous interval's end */
    double next = sn ? w->records[i + 1].start_h : NAN; /* still the next centre */
    if (sn && !(next > c))
      return vr_error_at(r->err, VR_E_PARSE, r->path, w->records[i + 1].line, 0,
                         "hour: records of a day must be in increasing time");
    double step = sn ? next - c : sp ? c - (2 * prev - c) : 1.0;
    rc->start_h = sp ? prev : fmax(0.0, c - step / 2);
    rc->end_h = sn ? 0.5 * (c + next) : fmin(24.0, c + step / 2);
  }
  return VR_OK;
}

vr_status vr_weather_read(const char *path, vr_weather **out, vr_error *err) {
  *out = NULL;
  vr_weather_reader r = {path, fopen(path, "r"), NULL, 0, 0, err};
  if (!r.f) return vr_error_set(err, VR_E_IO, "%s: cannot open weather file: %s", path, strerror(errno));
  vr_weather *w = calloc(1, sizeof *w);
  vr_status st = VR_OK;
  if (!w || !(w->path = strdup(path))) {
    st = vr_error_set(err, VR_E_NOMEM, "out of memory");
  } else if (!next_line(&r)) {
    st = vr_error_at(err, VR_E_PARSE, path, 1, 0, "empty weather file");
  } else if (!strncmp(r.line, "LOCATION,", 9)) {
    w->epw = true;
    st = read_epw(&r, w);
  } else if (!strncmp(r.line, "place ", 6) || !strncmp(r.line, "place\t", 6)) {
    st = read_wea(&r, w);
  } else {
    st = vr_error_at(err, VR_E_PARSE, path, 1, 0,
                     "not a weather file: an EnergyPlus .epw starts with \"LOCATION,\", a "
                     "Radiance .wea with \"place \"");
  }
  if (!st && ferror(r.f)) st = vr_error_set(err, VR_E_IO, "%s: read error", path);
  if (!st && w->nrecords == 0) st = vr_error_at(err, VR_E_PARSE, path, r.n, 0, "no weather records");
  free(r.line);
  fclose(r.f);
  if (st) {
    vr_weather_free(w);
    return st;
  }
  *out = w;
  return VR_OK;
}

void vr_weather_free(vr_weather *w) {
  if (!w) return;
  free(w->records);
  free(w->path);
  free(w);
}

vr_status vr_weather_find(const vr_weather *w, int month, int day, double hour,
                          const vr_weather_record **rec, vr_error *err) {
  *rec = NULL;
  bool date_seen = false;
  for (size_t i = 0; i < w->nrecords; i++) {
    const vr_weather_record *r = &w->records[i];
    if (r->month != month || r->day != day) continue;
    date_seen = true;
    if (hour >= r->start_h && hour < r->end_h) {
      *rec = r;
      return VR_OK;
    }
  }
  if (!date_seen)
    return vr_error_set(err, VR_E_RANGE, "%s: no record for %02d-%02d (the file covers %zu records)",
                        w->path, month, day, w->nrecords);
  return vr_error_set(err, VR_E_RANGE, "%s: no record on %02d-%02d covers %02d:%02d", w->path,
                      month, day, (int)hour, (int)round(fmod(hour, 1.0) * 60));
}

int vr_weather_day_of_year(const vr_weather_record *r) {
  static const int D[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  int y = r->year, n = r->day;
  bool leap = y > 0 && ((y % 4 == 0 && y % 100 != 0) || y % 400 == 0);
  for (int m = 1; m < r->month && m <= 12; m++) n += D[m - 1] + (m == 2 && leap);
  return n;
}
