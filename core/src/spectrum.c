/* Tabulated spectra: construction, interpolation, resampling, quadrature and
 * arithmetic.  See vr/spectrum.h for the conventions. */
#include "vr/spectrum.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static vr_spectrum *alloc_spectrum(size_t n, vr_error *err) {
  vr_spectrum *s = calloc(1, sizeof *s);
  if (s) {
    s->n = n;
    s->nm = malloc(n * sizeof(double));
    s->value = malloc(n * sizeof(double));
  }
  if (!s || !s->nm || !s->value) {
    vr_spectrum_destroy(s);
    vr_error_set(err, VR_E_NOMEM, "out of memory for a spectrum of %zu samples", n);
    return NULL;
  }
  return s;
}

static vr_status check_grid(size_t n, const double *nm, vr_error *err) {
  if (n == 0) return vr_error_set(err, VR_E_ARG, "a spectrum needs at least one sample");
  for (size_t i = 0; i < n; i++) {
    if (!isfinite(nm[i]))
      return vr_error_set(err, VR_E_RANGE, "wavelength #%zu is not finite", i + 1);
    if (i && !(nm[i] > nm[i - 1]))
      return vr_error_set(err, VR_E_RANGE,
                          "wavelengths must increase strictly: #%zu (%g nm) follows %g nm",
                          i + 1, nm[i], nm[i - 1]);
  }
  return VR_OK;
}

vr_spectrum *vr_spectrum_create(size_t n, const double *nm, const double *value, vr_error *err) {
  if (check_grid(n, nm, err)) return NULL;
  for (size_t i = 0; i < n; i++)
    if (!isfinite(value[i])) {
      vr_error_set(err, VR_E_RANGE, "value at %g nm is not finite", nm[i]);
      return NULL;
    }
  vr_spectrum *s = alloc_spectrum(n, err);
  if (!s) return NULL;
  memcpy(s->nm, nm, n * sizeof(double));
  memcpy(s->value, value, n * sizeof(double));
  return s;
}

vr_spectrum *vr_spectrum_create_uniform(double start, double step, size_t count, double fill,
                                        vr_error *err) {
  if (count == 0 || !(step > 0.0) || !isfinite(start) || !isfinite(step) || !isfinite(fill)) {
    vr_error_set(err, VR_E_ARG, "uniform grid needs count >= 1, a finite start and step > 0");
    return NULL;
  }
  vr_spectrum *s = alloc_spectrum(count, err);
  if (!s) return NULL;
  for (size_t i = 0; i < count; i++) {
    s->nm[i] = start + step * (double)i;
    s->value[i] = fill;
  }
  return s;
}

vr_spectrum *vr_spectrum_copy(const vr_spectrum *s, vr_error *err) {
  return vr_spectrum_create(s->n, s->nm, s->value, err);
}

void vr_spectrum_destroy(vr_spectrum *s) {
  if (!s) return;
  free(s->nm);
  free(s->value);
  free(s);
}

bool vr_spectrum_covers(const vr_spectrum *s, double lo, double hi) {
  return lo >= s->nm[0] && hi <= s->nm[s->n - 1];
}

/* Index i with nm[i] <= x < nm[i+1], for nm[0] <= x < nm[n-1]. */
static size_t bracket(const vr_spectrum *s, double x) {
  size_t lo = 0, hi = s->n - 1;
  while (hi - lo > 1) {
    size_t mid = lo + (hi - lo) / 2;
    if (s->nm[mid] <= x) lo = mid; else hi = mid;
  }
  return lo;
}

static double secant(const vr_spectrum *s, size_t i) {
  return (s->value[i + 1] - s->value[i]) / (s->nm[i + 1] - s->nm[i]);
}

/* Shape-preserving derivative at sample k (Fritsch and Butland 1984 weighted
 * harmonic mean inside; the three-point end formula limited to keep
 * monotonicity at the ends, as in Moler, "Numerical Computing with MATLAB",
 * section 3.6). */
static double pchip_slope(const vr_spectrum *s, size_t k) {
  size_t n = s->n;
  if (n == 2) return secant(s, 0);
  if (k == 0 || k == n - 1) {
    size_t a = k == 0 ? 0 : n - 2, b = k == 0 ? 1 : n - 3;
    double h0 = s->nm[a + 1] - s->nm[a], h1 = s->nm[b + 1] - s->nm[b];
    double d0 = secant(s, a), d1 = secant(s, b);
    double m = ((2.0 * h0 + h1) * d0 - h0 * d1) / (h0 + h1);
    if (m * d0 <= 0.0) return 0.0;
    if (d0 * d1 < 0.0 && fabs(m) > fabs(3.0 * d0)) return 3.0 * d0;
    return m;
  }
  double h0 = s->nm[k] - s->nm[k - 1], h1 = s->nm[k + 1] - s->nm[k];
  double d0 = secant(s, k - 1), d1 = secant(s, k);
  if (d0 * d1 <= 0.0) return 0.0;
  double w1 = 2.0 * h1 + h0, w2 = h1 + 2.0 * h0;
  return (w1 + w2) / (w1 / d0 + w2 / d1);
}

double vr_spectrum_eval(const vr_spectrum *s, double x, vr_interp interp) {
  size_t n = s->n;
  if (n == 1 || x <= s->nm[0]) return s->value[0];
  if (x >= s->nm[n - 1]) return s->value[n - 1];
  size_t i = bracket(s, x);
  double h = s->nm[i + 1] - s->nm[i], t = (x - s->nm[i]) / h;
  double y0 = s->value[i], y1 = s->value[i + 1];
  if (interp == VR_INTERP_LINEAR) return y0 + t * (y1 - y0);
  double m0 = pchip_slope(s, i), m1 = pchip_slope(s, i + 1);
  double t2 = t * t, t3 = t2 * t;
  return (2 * t3 - 3 * t2 + 1) * y0 + (t3 - 2 * t2 + t) * h * m0 + (-2 * t3 + 3 * t2) * y1 +
         (t3 - t2) * h * m1;
}

vr_spectrum *vr_spectrum_resample(const vr_spectrum *s, size_t n, const double *grid,
                                  vr_interp interp, vr_error *err) {
  if (check_grid(n, grid, err)) return NULL;
  vr_spectrum *r = alloc_spectrum(n, err);
  if (!r) return NULL;
  for (size_t i = 0; i < n; i++) {
    r->nm[i] = grid[i];
    r->value[i] = vr_spectrum_eval(s, grid[i], interp);
  }
  return r;
}

double vr_spectrum_integrate(const vr_spectrum *s, vr_quadrature q) {
  const double *x = s->nm, *f = s->value;
  size_t n = s->n;
  if (n < 2) return 0.0;
  double sum = 0.0;
  if (q == VR_TRAPEZOID || n == 2) {
    for (size_t i = 0; i + 1 < n; i++) sum += 0.5 * (x[i + 1] - x[i]) * (f[i] + f[i + 1]);
    return sum;
  }
  size_t intervals = n - 1, i = 0;
  for (; i + 2 <= intervals; i += 2) {
    double h0 = x[i + 1] - x[i], h1 = x[i + 2] - x[i + 1];
    sum += (h0 + h1) / 6.0 *
           ((2.0 - h1 / h0) * f[i] + (h0 + h1) * (h0 + h1) / (h0 * h1) * f[i + 1] +
            (2.0 - h0 / h1) * f[i + 2]);
  }
  if (intervals % 2) {
    /* Last interval from the parabola through the last three samples. */
    double a = x[n - 1] - x[n - 2], b = x[n - 2] - x[n - 3];
    double alpha = (2 * a * a + 3 * a * b) / (6 * (b + a));
    double beta = (a * a + 3 * a * b) / (6 * b);
    double eta = a * a * a / (6 * b * (b + a));
    sum += alpha * f[n - 1] + beta * f[n - 2] - eta * f[n - 3];
  }
  return sum;
}

bool vr_spectrum_same_grid(const vr_spectrum *a, const vr_spectrum *b) {
  return a->n == b->n && memcmp(a->nm, b->nm, a->n * sizeof(double)) == 0;
}

static vr_status grid_mismatch(vr_error *err, const vr_spectrum *a, const vr_spectrum *b) {
  return vr_error_set(err, VR_E_ARG,
                      "spectra on different grids (%zu samples %g-%g nm vs %zu samples %g-%g nm); "
                      "resample one of them first",
                      a->n, a->nm[0], a->nm[a->n - 1], b->n, b->nm[0], b->nm[b->n - 1]);
}

vr_status vr_spectrum_add(vr_spectrum *a, const vr_spectrum *b, vr_error *err) {
  if (!vr_spectrum_same_grid(a, b)) return grid_mismatch(err, a, b);
  for (size_t i = 0; i < a->n; i++) a->value[i] += b->value[i];
  return VR_OK;
}

vr_status vr_spectrum_mul(vr_spectrum *a, const vr_spectrum *b, vr_error *err) {
  if (!vr_spectrum_same_grid(a, b)) return grid_mismatch(err, a, b);
  for (size_t i = 0; i < a->n; i++) a->value[i] *= b->value[i];
  return VR_OK;
}

void vr_spectrum_scale(vr_spectrum *a, double factor) {
  for (size_t i = 0; i < a->n; i++) a->value[i] *= factor;
}
