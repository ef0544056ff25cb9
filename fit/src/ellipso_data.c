/* Ellipsometry data: dispatch between readers, units, Δ convention, domain
 * checks shared by all formats. */
#include "ellipso_read.h"
#include "vr/dispersion.h"
#include "vr/spectrum.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

double vr_delta_normalise(double d) {
  d = fmod(d, 360.0);
  if (d < 0.0) d += 360.0;
  if (d >= 360.0) d -= 360.0;
  return d;
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

/* Woollam files start with a comment line and then carry "nm", "eV" or
 * "Angstroms" (optionally "TRIG") on a line, or a VASEmethod line, before
 * the rows; Sentech exports start with "; WAVELENGTH". */
static int looks_like_woollam(const char *text, size_t len) {
  size_t lines = 0;
  if (len > 12 && text[0] == ';') return 1;
  for (size_t i = 0; i < len && lines < 12; lines++) {
    size_t j = i;
    while (j < len && text[j] != '\n') j++;
    size_t l = j - i;
    while (l && (text[i + l - 1] == '\r' || text[i + l - 1] == ' ' || text[i + l - 1] == '\t')) l--;
    if ((l >= 2 && !strncasecmp(text + i, "nm", 2) && (l == 2 || text[i + 2] == ' ' || text[i + 2] == '\t')) ||
        (l == 2 && !strncasecmp(text + i, "eV", 2)) ||
        (l == 9 && !strncasecmp(text + i, "Angstroms", 9)) || (l >= 10 && !strncmp(text + i, "VASEmethod", 10)))
      return 1;
    /* A row tag: "E" or "dpolE" followed by a blank (the line is not
     * NUL-terminated, so lengths are checked before comparing). */
    if (l > 2 && text[i] == 'E' && (text[i + 1] == '\t' || text[i + 1] == ' ')) return 1;
    if (l > 6 && !strncmp(text + i, "dpolE", 5) && (text[i + 5] == '\t' || text[i + 5] == ' ')) return 1;
    i = j + 1;
  }
  return 0;
}

vr_status vr_ellipso_parse(const char *text, size_t len, const char *name, const char *unit,
                           vr_ellipso_data *out, vr_error *err) {
  memset(out, 0, sizeof *out);
  if (!(out->source = strdup(name))) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  vr_status st = looks_like_woollam(text, len)
                     ? vr_ellipso_parse_woollam(text, len, name, unit, out, err)
                     : vr_ellipso_parse_csv(text, len, name, unit, out, err);
  if (st) vr_ellipso_data_free(out);
  return st;
}

vr_status vr_ellipso_read(const char *path, const char *unit, vr_ellipso_data *out, vr_error *err) {
  memset(out, 0, sizeof *out);
  FILE *f = fopen(path, "rb");
  if (!f) return vr_error_at(err, VR_E_IO, path, 0, 0, "cannot open: %s", strerror(errno));
  size_t cap = 1 << 16, n = 0;
  char *buf = malloc(cap);
  while (buf) {
    n += fread(buf + n, 1, cap - n, f);
    if (n < cap) break;
    char *b = realloc(buf, cap *= 2);
    if (!b) free(buf);
    buf = b;
  }
  int bad = ferror(f);
  fclose(f);
  if (!buf) return vr_error_set(err, VR_E_NOMEM, "%s: out of memory", path);
  vr_status st = bad ? vr_error_at(err, VR_E_IO, path, 0, 0, "read error")
                     : vr_ellipso_parse(buf, n, path, unit, out, err);
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
