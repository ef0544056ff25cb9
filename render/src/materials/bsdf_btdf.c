/* A stored btdf material (vr-spectro btdf: T, Rf, Rb per polarisation at a
 * list of angles, vr/btdf.h) resampled onto the pane tables.
 *
 * vr_btdf_eval is the one reader of those tables, but each call parses the
 * angle list and looks two roles up by name, so it is called only at the
 * stored angles (angles x wavelengths x 3 calls); the pane nodes in between
 * interpolate linearly in angle and hold the last angle up to 90 degrees,
 * exactly as vr_btdf_eval does.  Wavelengths beyond the tables hold the
 * end values (vr_btdf_eval refuses them) and mark the bsdf extrapolated. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "materials/bsdf_internal.h"
#include "vr/btdf.h"

#define NC VR_BSDF_PANE_NODES

/* The wavelength range every "Ts@" table covers. */
static void range_of(const vr_material *m, double *lo, double *hi) {
  *lo = -INFINITY;
  *hi = INFINITY;
  for (size_t i = 0; i < m->nspectra; i++) {
    const vr_spectrum *s = m->spectra[i].s;
    if (strncmp(m->spectra[i].role, "Ts@", 3) != 0 || !s || s->n == 0) continue;
    *lo = fmax(*lo, s->nm[0]);
    *hi = fmin(*hi, s->nm[s->n - 1]);
  }
}

static int by_value(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* The "angles" property as numbers, increasing. */
static vr_status angles_of(const vr_material *m, double **out, size_t *count, vr_error *err) {
  const vr_property *p = vr_material_property(m, "angles");
  if (!p || !p->text) return vr_error_set(err, VR_E_ARG, "the btdf material lists no angles");
  size_t cap = 1;
  for (const char *c = p->text; *c; c++) cap += *c == ',';
  double *a = malloc(cap * sizeof *a);
  if (!a) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  size_t n = 0;
  for (const char *s = p->text; *s && n < cap;) {
    char *end;
    double v = strtod(s, &end);
    if (end == s || !(v >= 0.0 && v <= 90.0)) {
      free(a);
      return vr_error_set(err, VR_E_PARSE, "bad angle list '%s'", p->text);
    }
    a[n++] = v;
    s = *end == ',' ? end + 1 : end;
  }
  if (n == 0) {
    free(a);
    return vr_error_set(err, VR_E_PARSE, "empty angle list");
  }
  qsort(a, n, sizeof *a, by_value);
  *out = a;
  *count = n;
  return VR_OK;
}

vr_status vr_bsdfi_table_btdf(vr_bsdf *b, const vr_material *m, vr_error *err) {
  double lo, hi;
  range_of(m, &lo, &hi);
  if (!(lo <= hi))
    return vr_error_set(err, VR_E_ARG, "the btdf material has no transmittance table (Ts@ANGLE)");
  double *ang = NULL;
  size_t na = 0;
  vr_status st = angles_of(m, &ang, &na, err);
  if (st) return st;
  /* Per pane node: the stored angle below (or at) it and the fraction to
   * the next one; held beyond the ends. */
  size_t at[NC];
  double frac[NC];
  for (size_t j = 0; j < NC; j++) {
    double deg = acos(vr_bsdfi_node_cos(j)) * 180.0 / M_PI;
    size_t a = 0;
    while (a + 1 < na && ang[a + 1] <= deg) a++;
    at[j] = a;
    frac[j] = a + 1 < na && deg > ang[a] ? (deg - ang[a]) / (ang[a + 1] - ang[a]) : 0.0;
  }
  double *v = malloc(3 * na * sizeof *v); /* T, Rf, Rb at each stored angle */
  if (!v) st = vr_error_set(err, VR_E_NOMEM, "out of memory");
  if (!st) st = vr_bsdfi_tables_alloc(b, err);
  static const vr_btdf_quantity Q[3] = {VR_BTDF_T, VR_BTDF_RF, VR_BTDF_RB};
  for (size_t i = 0; i < b->nl && !st; i++) {
    double nm = b->lmin + (double)i;
    if (nm < lo || nm > hi) b->extrapolated = true;
    nm = fmin(fmax(nm, lo), hi);
    for (size_t a = 0; a < na && !st; a++)
      for (int q = 0; q < 3 && !st; q++)
        st = vr_btdf_eval(m, Q[q], VR_BTDF_UNPOLARISED, ang[a], nm, &v[3 * a + q], err);
    for (size_t j = 0; j < NC && !st; j++) {
      const double *x = v + 3 * at[j], *y = at[j] + 1 < na ? x + 3 : x;
      double t = frac[j];
      vr_bsdfi_store(b, i, j, x[0] + t * (y[0] - x[0]), x[1] + t * (y[1] - x[1]),
                     x[2] + t * (y[2] - x[2]));
    }
  }
  free(v);
  free(ang);
  return st;
}
