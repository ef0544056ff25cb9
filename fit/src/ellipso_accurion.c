/* Accurion (Park Systems) EP4 imaging ellipsometer exports, as the
 * instrument writes them (e.g. "*.ds.dat"): a first line "#" followed by
 * tab-separated column names (Lambda, AOI, Delta, Psi, and others such as
 * Bandwidth, Zone, ROIidx, Time, positions, in any order), a second line
 * "#" with each column's unit, then tab-separated rows.
 *
 * Zones.  A nulling ellipsometer measures each angle in up to four
 * polariser-compensator zones (Zone 1-4); the EP4 adds a row with their
 * average (Zone 0) and one with their spread (Zone 5, whose "Psi" and
 * "Delta" are not angles).  Read from the numbers, not from Accurion's
 * documentation: in refellips' 15-1-1.dat at 50 deg, zones 1-4 give Delta
 * 169.598, 169.785, 169.565, 169.624 and Psi 31.277, 31.291, 31.520,
 * 31.474; zone 0 gives their means, 169.643 and 31.391, and zone 5 their
 * ranges, 0.220 and 0.243.  The zone rows are the
 * measurements and are kept one point each (a least-squares fit over them
 * weighs each angle by its number of zones, as their average would); zone
 * 0 and 5 rows are skipped, as are zones the instrument could not null
 * (NaN), each kind counted for the user.  refellips' reader averages the
 * same zones (its test vector is checked in tests/fit/test_ellipso_files.c).
 * Real files: tests/data/ellipsometry/real/README.md. */
#define _GNU_SOURCE /* strcasestr */
#include "vr/file.h"
#include "ellipso_read.h"
#include "vr/csv.h"

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* Accurion EP4 tables start with "#" and name Lambda, Psi and Delta among
 * tab-separated columns on their first line. */
int vr_ellipso_sniff_accurion(const char *text, size_t len) {
  size_t l = 0;
  while (l < len && text[l] != '\n') l++;
  if (!len || text[0] != '#' || l > 4096) return 0;
  char first[4097];
  memcpy(first, text, l);
  first[l] = '\0';
  return strchr(first, '\t') && strcasestr(first, "Lambda") && strcasestr(first, "Psi") &&
         strcasestr(first, "Delta");
}

#define MAXCOL 64

static void trim(char *s) {
  size_t n = strlen(s);
  while (n && (s[n - 1] == '\r' || s[n - 1] == ' ')) s[--n] = '\0';
}

static long column(char **names, size_t n, const char *want) {
  for (size_t i = 0; i < n; i++)
    if (!strcasecmp(names[i], want)) return (long)i;
  return -1;
}

vr_status vr_ellipso_parse_accurion(const char *text, size_t len, const char *name,
                                    const vr_ellipso_read_options *o, vr_ellipso_data *d,
                                    vr_error *err) {
  d->format = "Accurion EP4 table";
  vr_status enc = vr_text_check_encoding(text, len, name, err);
  if (enc) return enc;
  if (memchr(text, '\0', len))
    return vr_error_at(err, VR_E_PARSE, name, 0, 0, "binary data (NUL byte) in a text file");
  char *buf = malloc(len + 1);
  if (!buf) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  memcpy(buf, text, len);
  buf[len] = '\0';
  vr_status st = VR_OK;
  char *names[MAXCOL], *units[MAXCOL], *tok[MAXCOL];
  size_t nn = 0, nu = 0, cap = 0;
  long line = 0, cl = -1, ca = -1, cp = -1, cd = -1, cb = -1, cz = -1;
  const char *wunit = "nm";
  for (char *s = buf, *next; s && *s; s = next) {
    next = strchr(s, '\n');
    if (next) *next++ = '\0';
    line++;
    trim(s);
    if (line == 1) {
      nn = vr_ellipso_split_tabs(s + 1, names, MAXCOL);
      for (size_t i = 0; i < nn; i++) trim(names[i]);
      cl = column(names, nn, "Lambda"), ca = column(names, nn, "AOI");
      cp = column(names, nn, "Psi"), cd = column(names, nn, "Delta");
      cb = column(names, nn, "Bandwidth"), cz = column(names, nn, "Zone");
      const char *missing = cl < 0 ? "Lambda" : ca < 0 ? "AOI" : cp < 0 ? "Psi" : cd < 0 ? "Delta" : NULL;
      if (missing) {
        st = vr_error_at(err, VR_E_PARSE, name, 1, 0, "no '%s' column in the header", missing);
        break;
      }
      continue;
    }
    if (line == 2 && s[0] == '#') {
      /* The units: wavelengths in nm (or as named), angles in degrees. */
      nu = vr_ellipso_split_tabs(s + 1, units, MAXCOL);
      for (size_t i = 0; i < nu; i++) trim(units[i]);
      if ((size_t)cl < nu) {
        wunit = units[cl];
        if (isnan(vr_ellipso_to_nm(1.0, wunit))) {
          st = vr_error_at(err, VR_E_PARSE, name, 2, 0, "field 'Lambda': unknown unit '%s'", wunit);
          break;
        }
      }
      const long ang[3] = {ca, cp, cd};
      for (int k = 0; k < 3; k++)
        if ((size_t)ang[k] < nu && strcasecmp(units[ang[k]], "deg")) {
          st = vr_error_at(err, VR_E_PARSE, name, 2, 0, "field '%s': unit '%s', expected deg",
                           names[ang[k]], units[ang[k]]);
          break;
        }
      if (st) break;
      continue;
    }
    if (!*s || s[0] == '#') continue;
    size_t n = vr_ellipso_split_tabs(s, tok, MAXCOL);
    if (n < nn) {
      st = vr_error_at(err, VR_E_PARSE, name, line, 0, "expected %zu tab-separated fields, found %zu",
                       nn, n);
      break;
    }
    if (cz >= 0) {
      trim(tok[cz]);
      if (!strcmp(tok[cz], "0") || !strcmp(tok[cz], "5")) {
        vr_ellipso_note_skipped(d, tok[cz][0] == '0' ? "Zone 0 (average)" : "Zone 5 (spread)");
        continue;
      }
    }
    trim(tok[cp]);
    trim(tok[cd]);
    if (!strcasecmp(tok[cp], "NaN") || !strcasecmp(tok[cd], "NaN")) {
      vr_ellipso_note_skipped(d, "NaN (not nulled)");
      continue;
    }
    if (d->n == cap) {
      size_t c = cap ? 2 * cap : 256;
      vr_ellipso_point *q = realloc(d->p, c * sizeof *q);
      if (!q) {
        st = vr_error_set(err, VR_E_NOMEM, "out of memory");
        break;
      }
      d->p = q;
      cap = c;
    }
    vr_ellipso_point *p = &d->p[d->n];
    vr_ellipso_point_init(p);
    p->line = line;
    p->sigma_psi = p->sigma_delta = VR_ELLIPSO_DEFAULT_SIGMA_DEG;
    double w, bw = NAN;
    const struct {
      long col;
      double *to;
    } f[] = {{cl, &w}, {ca, &p->aoi_deg}, {cp, &p->psi_deg}, {cd, &p->delta_deg}, {cb, &bw}};
    for (size_t k = 0; k < sizeof f / sizeof *f && !st; k++) {
      if (f[k].col < 0) continue;
      trim(tok[f[k].col]);
      int rc = vr_parse_double(tok[f[k].col], f[k].to);
      if (rc)
        st = vr_error_at(err, rc == -2 ? VR_E_RANGE : VR_E_PARSE, name, line, 0,
                         "field '%s': %s '%s'", names[f[k].col],
                         rc == -2 ? "not a finite number:" : "expected a number, got", tok[f[k].col]);
    }
    if (st || (st = vr_ellipso_point_finish(p, w, o->unit ? o->unit : wunit, name, err))) break;
    /* A bandwidth is kept when it is in nm (the only unit seen). */
    if (bw >= 0 && ((size_t)cb >= nu || !strcasecmp(units[cb], "nm"))) p->bandwidth_nm = bw;
    d->n++;
  }
  free(buf);
  if (!st && !d->n) st = vr_error_at(err, VR_E_PARSE, name, 0, 0, "no data rows");
  return st;
}
