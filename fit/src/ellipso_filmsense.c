/* J.A. Woollam Film Sense (FS-1 family) exports: a multi-wavelength LED
 * ellipsometer that measures, per LED, the normalised Stokes-like values
 * N, C, S, the degree of polarisation P and the intensity I.  Layout, read
 * from refellips' test files (tests/data/ellipsometry/real/README.md):
 *
 *   Film_Sense_Data                 (static)  or  Film_Sense_Dyn_Data (kinetic)
 *   NWL <tab> NREC <tab> AOI <tab> ...          (AOI written negative: its
 *                                                magnitude is the angle)
 *   NWL rows, one per LED: wavelength (nm) and calibration numbers
 *   static:  NWL rows  N C S P I
 *   kinetic: a header "Time UV_N UV_C UV_S UV_P UV_I Blue_N ..." (five
 *            columns per LED in LED order, then alignment, temperature and
 *            the instrument's own fit), then NREC rows, one per time
 *   then the instrument's own fit results (static), which are not read.
 *
 * Per point: Ψ = ½ acos N, Δ = atan2(S, C) (Woollam's convention:
 * N = cos 2Ψ, C = sin 2Ψ cos Δ, S = sin 2Ψ sin Δ for a non-depolarising
 * sample; refellips' loader gives the same Ψ, Δ to its test's 1e-3), the
 * depolarisation 100 (1 - P) percent, and N, C, S kept.  A kinetic file is
 * one record per time: the caller chooses which (options.record). */
#include "vr/file.h"
#include "ellipso_read.h"
#include "vr/csv.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* Film Sense exports start with "Film_Sense_Data" or "Film_Sense_Dyn_Data". */
int vr_ellipso_sniff_filmsense(const char *text, size_t len) {
  return (len >= 15 && !strncmp(text, "Film_Sense_Data", 15)) ||
         (len >= 19 && !strncmp(text, "Film_Sense_Dyn_Data", 19));
}

#define MAXF 512

/* Tab-separated fields, each with trailing CR and blanks removed. */
static size_t split(char *s, char **tok, size_t max) {
  size_t n = vr_ellipso_split_tabs(s, tok, max);
  for (size_t i = 0; i < n; i++) {
    size_t l = strlen(tok[i]);
    while (l && (tok[i][l - 1] == '\r' || tok[i][l - 1] == ' ')) tok[i][--l] = '\0';
  }
  return n;
}

typedef struct reader {
  char *next;
  long line;
  const char *name;
  vr_error *err;
} reader;

/* The next line split at tabs; NULL at the end of the text. */
static size_t next_row(reader *r, char **tok, char **raw) {
  char *s = r->next;
  if (!s || !*s) return 0;
  char *nl = strchr(s, '\n');
  if (nl) *nl++ = '\0';
  r->next = nl;
  r->line++;
  if (raw) *raw = s;
  return split(s, tok, MAXF);
}

static vr_status number(reader *r, char **tok, size_t n, size_t i, const char *field, double *v) {
  if (i >= n) return vr_error_at(r->err, VR_E_PARSE, r->name, r->line, 0, "field '%s' missing", field);
  int rc = vr_parse_double(tok[i], v);
  if (rc)
    return vr_error_at(r->err, rc == -2 ? VR_E_RANGE : VR_E_PARSE, r->name, r->line, 0, "field '%s': %s '%s'", field,
                       rc == -2 ? "not a finite number:" : "expected a number, got", tok[i]);
  return VR_OK;
}

/* One point from N, C, S, P at a wavelength. */
static vr_status point(reader *r, vr_ellipso_data *d, double nm, double aoi, const double ncsp[4]) {
  vr_ellipso_point *p = &d->p[d->n];
  vr_ellipso_point_init(p);
  p->line = r->line;
  p->aoi_deg = aoi;
  double N = ncsp[0], C = ncsp[1], S = ncsp[2], P = ncsp[3];
  if (!(fabs(N) <= 1.0 + 1e-3) || !(hypot(C, S) <= 1.0 + 1e-3))
    return vr_error_at(r->err, VR_E_RANGE, r->name, r->line, 0,
                       "N %g, C %g, S %g: normalised values must lie within [-1, 1]", N, C, S);
  p->psi_deg = 0.5 * acos(fmax(-1.0, fmin(1.0, N))) * 180.0 / M_PI;
  p->delta_deg = atan2(S, C) * 180.0 / M_PI;
  p->sigma_psi = p->sigma_delta = VR_ELLIPSO_DEFAULT_SIGMA_DEG;
  p->depolarisation = 100.0 * (1.0 - P);
  p->N = N, p->C = C, p->S = S;
  p->has_ncs = 1;
  vr_status st = vr_ellipso_point_finish(p, nm, "nm", r->name, r->err);
  if (!st) d->n++;
  return st;
}

vr_status vr_ellipso_parse_filmsense(const char *text, size_t len, const char *name,
                                     const vr_ellipso_read_options *o, vr_ellipso_data *d,
                                     vr_error *err) {
  vr_status enc = vr_text_check_encoding(text, len, name, err);
  if (enc) return enc;
  if (memchr(text, '\0', len))
    return vr_error_at(err, VR_E_PARSE, name, 0, 0, "binary data (NUL byte) in a text file");
  char *buf = malloc(len + 1), **tok = malloc(MAXF * sizeof *tok);
  double *wl = NULL;
  if (!buf || !tok) {
    free(buf);
    free(tok);
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  memcpy(buf, text, len);
  buf[len] = '\0';
  reader r = {buf, 0, name, err};
  vr_status st = VR_OK;
  char *raw;
  size_t n = next_row(&r, tok, &raw);
  int kinetic = n && !strcmp(tok[0], "Film_Sense_Dyn_Data");
  d->format = kinetic ? "Film Sense kinetic export" : "Film Sense export";
  double nwl_d = 0, nrec_d = 0, aoi = 0;
  n = next_row(&r, tok, NULL);
  if ((st = number(&r, tok, n, 0, "number of wavelengths", &nwl_d)) ||
      (st = number(&r, tok, n, 1, "number of records", &nrec_d)) || (st = number(&r, tok, n, 2, "angle of incidence", &aoi)))
    goto done;
  if (!(nwl_d >= 1 && nwl_d <= 64 && nwl_d == floor(nwl_d)) || !(nrec_d >= 1 && nrec_d == floor(nrec_d) && nrec_d < 1e7)) {
    st = vr_error_at(err, VR_E_PARSE, name, r.line, 0, "expected the number of wavelengths (1-64) and of records, got '%s' and '%s'",
                     tok[0], n > 1 ? tok[1] : "");
    goto done;
  }
  size_t nwl = (size_t)nwl_d, nrec = (size_t)nrec_d;
  aoi = fabs(aoi);
  if (!(aoi > 0 && aoi < 90)) {
    st = vr_error_at(err, VR_E_RANGE, name, r.line, 0, "field 'angle of incidence': %g deg is outside (0, 90)", aoi);
    goto done;
  }
  if (!(wl = malloc(nwl * sizeof *wl)) || !(d->p = calloc(nwl, sizeof *d->p))) {
    st = vr_error_set(err, VR_E_NOMEM, "out of memory");
    goto done;
  }
  for (size_t i = 0; i < nwl; i++) {
    n = next_row(&r, tok, NULL);
    if (!n) {
      st = vr_error_at(err, VR_E_PARSE, name, r.line + 1, 0, "the file ends before wavelength %zu of %zu", i + 1, nwl);
      goto done;
    }
    if ((st = number(&r, tok, n, 0, "wavelength", &wl[i]))) goto done;
  }
  d->nrecords = nrec;
  if (!kinetic) {
    if (o->record > 1) {
      st = vr_error_at(err, VR_E_ARG, name, 0, 0, "record %zu asked for, but a static export holds one", o->record);
      goto done;
    }
    d->record = 1;
    for (size_t i = 0; i < nwl; i++) {
      n = next_row(&r, tok, NULL);
      if (!n) {
        st = vr_error_at(err, VR_E_PARSE, name, r.line + 1, 0, "field 'N' missing: the file ends before the N, C, S row "
                                                               "of wavelength %zu of %zu", i + 1, nwl);
        goto done;
      }
      double v[4];
      const char *f[4] = {"N", "C", "S", "P"};
      for (int k = 0; k < 4 && !st; k++) st = number(&r, tok, n, (size_t)k, f[k], &v[k]);
      if (st || (st = point(&r, d, wl[i], aoi, v))) goto done;
    }
    goto done;
  }
  /* Kinetic: the column header, then one row per time. */
  n = next_row(&r, tok, NULL);
  if (n < 1 + 5 * nwl || strcasecmp(tok[0], "Time")) {
    st = vr_error_at(err, VR_E_PARSE, name, r.line, 0, "expected a header 'Time' and five columns per wavelength (%zu)", nwl);
    goto done;
  }
  static const char *suffix[5] = {"_N", "_C", "_S", "_P", "_I"};
  for (size_t i = 0; i < nwl; i++)
    for (int k = 0; k < 5; k++) {
      const char *h = tok[1 + 5 * i + (size_t)k];
      size_t l = strlen(h);
      if (l < 2 || strcasecmp(h + l - 2, suffix[k])) {
        st = vr_error_at(err, VR_E_PARSE, name, r.line, 0, "column %zu is '%s', expected a name ending in '%s'",
                         2 + 5 * i + (size_t)k, h, suffix[k]);
        goto done;
      }
    }
  size_t want = o->record;
  if (!want && nrec > 1) {
    st = vr_error_at(err, VR_E_ARG, name, 0, 0,
                     "a kinetic run of %zu records: choose one with --record N (1 to %zu)", nrec, nrec);
    goto done;
  }
  if (!want) want = 1;
  if (want > nrec) {
    st = vr_error_at(err, VR_E_ARG, name, 0, 0, "record %zu asked for, but the file holds %zu", want, nrec);
    goto done;
  }
  for (size_t rec = 1; rec <= want; rec++) {
    n = next_row(&r, tok, NULL);
    if (!n) {
      st = vr_error_at(err, VR_E_PARSE, name, r.line + 1, 0, "the file ends before record %zu of %zu", rec, nrec);
      goto done;
    }
    if (rec < want) continue;
    if ((st = number(&r, tok, n, 0, "Time", &d->record_time_s))) goto done;
    d->record = want;
    for (size_t i = 0; i < nwl && !st; i++) {
      double v[4];
      for (int k = 0; k < 4 && !st; k++) st = number(&r, tok, n, 1 + 5 * i + (size_t)k, suffix[k] + 1, &v[k]);
      if (!st) st = point(&r, d, wl[i], aoi, v);
    }
  }
done:
  free(buf);
  free(tok);
  free(wl);
  return st;
}
