/* Ellipsometry data: the table of readers that picks one by its sniff,
 * units, Δ convention, domain checks shared by all formats. */
#include "vr/file.h"
#include "ellipso_read.h"
#include "vr/dispersion.h"
#include "vr/spectrum.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

double vr_delta_normalise(double d) {
  d = fmod(d, 360.0);
  if (d < 0.0) d += 360.0;
  if (d >= 360.0) d -= 360.0;
  return d;
}

double vr_delta_difference(double x) {
  x = fmod(x, 360.0);
  if (x > 180.0) x -= 360.0;
  if (x <= -180.0) x += 360.0;
  return x;
}

double vr_ellipso_to_nm(double w, const char *unit) {
  vr_wl_unit u = vr_wavelength_unit_of(unit);
  return u == VR_UNIT_UNKNOWN ? NAN : vr_wavelength_to_nm(w, u);
}

vr_status vr_ellipso_point_finish(vr_ellipso_point *p, double w, const char *unit, const char *name,
                                  vr_error *err) {
  p->nm = vr_ellipso_to_nm(w, unit);
  if (isnan(p->nm))
    return vr_error_at(err, VR_E_ARG, name, p->line, 0, "unknown wavelength unit '%s' (nm, um, A, eV)", unit);
  if (!(p->nm > 0.0))
    return vr_error_at(err, VR_E_RANGE, name, p->line, 0, "field 'wavelength': %g %s is not positive", w, unit);
  if (!(p->aoi_deg > 0.0 && p->aoi_deg < 90.0))
    return vr_error_at(err, VR_E_RANGE, name, p->line, 0,
                       "field 'aoi': %g degrees is outside (0, 90)", p->aoi_deg);
  if (!(p->psi_deg >= 0.0 && p->psi_deg <= 90.0))
    return vr_error_at(err, VR_E_RANGE, name, p->line, 0, "field 'psi': %g degrees is outside [0, 90]",
                       p->psi_deg);
  if (!(p->sigma_psi > 0.0) || !(p->sigma_delta > 0.0))
    return vr_error_at(err, VR_E_RANGE, name, p->line, 0,
                       "field 'sigma': standard deviations must be positive (%g, %g)", p->sigma_psi,
                       p->sigma_delta);
  p->delta_deg = vr_delta_normalise(p->delta_deg);
  return VR_OK;
}

size_t vr_ellipso_split_tabs(char *s, char **tok, size_t max) {
  size_t n = 0;
  while (n < max) {
    tok[n++] = s;
    char *t = strchr(s, '\t');
    if (!t) break;
    *t = '\0';
    s = t + 1;
  }
  return n;
}

void vr_ellipso_point_init(vr_ellipso_point *p) {
  memset(p, 0, sizeof *p);
  p->depolarisation = p->sigma_depolarisation = p->bandwidth_nm = NAN;
}

void vr_ellipso_note_skipped(vr_ellipso_data *d, const char *tag) {
  for (size_t i = 0; i < d->nskipped; i++)
    if (!strncmp(d->skipped[i].tag, tag, sizeof d->skipped[i].tag - 1)) {
      d->skipped[i].rows++;
      return;
    }
  /* Beyond the table's room the kinds are merged under the last entry. */
  vr_ellipso_skipped *k = &d->skipped[d->nskipped < VR_ELLIPSO_MAX_SKIPPED ? d->nskipped++
                                                                           : VR_ELLIPSO_MAX_SKIPPED - 1];
  if (!k->rows) snprintf(k->tag, sizeof k->tag, "%s", tag);
  k->rows++;
}

/* The readers, in the order their sniffs are tried: the first that accepts
 * the text reads it.  The Film Sense and Accurion sniffs look for one exact
 * header, so they go before the Woollam one, which takes looser signs (a
 * leading ';', a unit line or a row tag among the first lines).  The CSV
 * reader has no sniff: it takes whatever the others leave.  A new format is
 * a file with its sniff and parse, and a line here. */
static const vr_ellipso_reader READERS[] = {
    {"Film Sense", vr_ellipso_sniff_filmsense, vr_ellipso_parse_filmsense},
    {"Accurion EP4", vr_ellipso_sniff_accurion, vr_ellipso_parse_accurion},
    {"Woollam / Sentech", vr_ellipso_sniff_woollam, vr_ellipso_parse_woollam},
    {"CSV", NULL, vr_ellipso_parse_csv},
};

static const vr_ellipso_reader *reader_for(const char *text, size_t len) {
  const vr_ellipso_reader *r = READERS;
  while (r->sniff && !r->sniff(text, len)) r++;
  return r;
}

vr_status vr_ellipso_parse_with(const char *text, size_t len, const char *name,
                                const vr_ellipso_read_options *o, vr_ellipso_data *out,
                                vr_error *err) {
  vr_ellipso_read_options none = {0};
  if (!o) o = &none;
  memset(out, 0, sizeof *out);
  if (!(out->source = strdup(name))) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  out->record_time_s = NAN;
  vr_status st = reader_for(text, len)->parse(text, len, name, o, out, err);
  if (!st && o->record > 0 && !out->nrecords)
    st = vr_error_at(err, VR_E_ARG, name, 0, 0, "a record was chosen (--record) but the file is not a run of records");
  if (!st && o->wavelength_nm > 0 && !strstr(out->format, "wavelength given"))
    st = vr_error_at(err, VR_E_ARG, name, 0, 0,
                     "a wavelength was given (--wavelength) but the file has its own "
                     "wavelengths");
  if (st) vr_ellipso_data_free(out);
  return st;
}

vr_status vr_ellipso_parse(const char *text, size_t len, const char *name, const char *unit,
                           vr_ellipso_data *out, vr_error *err) {
  vr_ellipso_read_options o = {.unit = unit};
  return vr_ellipso_parse_with(text, len, name, &o, out, err);
}

vr_status vr_ellipso_read(const char *path, const char *unit, vr_ellipso_data *out, vr_error *err) {
  vr_ellipso_read_options o = {.unit = unit};
  return vr_ellipso_read_with(path, &o, out, err);
}

vr_status vr_ellipso_read_with(const char *path, const vr_ellipso_read_options *o,
                               vr_ellipso_data *out, vr_error *err) {
  memset(out, 0, sizeof *out);
  char *buf;
  size_t n;
  vr_status st = vr_read_file(path, VR_TEXT_MAX_BYTES, &buf, &n, err);
  if (st) return st;
  st = vr_ellipso_parse_with(buf, n, path, o, out, err);
  free(buf);
  return st;
}

void vr_ellipso_data_free(vr_ellipso_data *d) {
  free(d->p);
  free(d->source);
  memset(d, 0, sizeof *d);
}

size_t vr_ellipso_crop(vr_ellipso_data *d, double lo, double hi) {
  size_t k = 0;
  for (size_t i = 0; i < d->n; i++)
    if (d->p[i].nm >= lo && d->p[i].nm <= hi) d->p[k++] = d->p[i];
  d->n = k;
  return k;
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

size_t vr_ellipso_angles(const vr_ellipso_data *d, double *angles, size_t max) {
  size_t k = 0;
  for (size_t i = 0; i < d->n; i++) {
    int seen = 0;
    for (size_t j = 0; j < k && !seen; j++) seen = fabs(angles[j] - d->p[i].aoi_deg) < 0.01;
    if (!seen && k < max) angles[k++] = d->p[i].aoi_deg;
  }
  qsort(angles, k, sizeof *angles, cmp_double);
  return k;
}
