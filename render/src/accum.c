/* Accumulators that many workers add into at once: the film (XYZ and
 * spectral bins per pixel), the sensors (illuminance per batch of samples,
 * spectral irradiance) and the photochromic texels (UV irradiance).
 *
 * Sums are doubles updated by compare-and-swap, so no lock is taken and no
 * contribution is lost; the order of additions varies with scheduling, which
 * changes a pixel by a few units in the last place only (about 1e-16
 * relative), far inside the 1e-6 the decomposition-invariance tests allow.
 *
 * Spectral estimates: a path carries nwl wavelengths each with density
 * 1/(lmax - lmin) (hero sampling rotates them through the range), so a
 * radiance sample L(λ_i) contributes L(λ_i) (lmax - lmin) / nwl to the
 * integral of L against anything; wl_weight is that factor. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "render_internal.h"
#include "vr/colour.h"

#define KM VR_KM

void vr_atomic_add(_Atomic uint64_t *cell, double v) {
  if (v == 0.0) return;
  uint64_t old = atomic_load_explicit(cell, memory_order_relaxed), nw;
  do {
    double d;
    memcpy(&d, &old, sizeof d);
    d += v;
    memcpy(&nw, &d, sizeof nw);
  } while (!atomic_compare_exchange_weak_explicit(cell, &old, nw, memory_order_relaxed,
                                                  memory_order_relaxed));
}

double vr_atomic_get(_Atomic uint64_t *cell) {
  uint64_t b = atomic_load(cell);
  double d;
  memcpy(&d, &b, sizeof d);
  return d;
}

static _Atomic uint64_t *zeros(size_t n) {
  /* All-zero bits are +0.0. */
  return calloc(n ? n : 1, sizeof(_Atomic uint64_t));
}

vr_status vr_accum_create(accum *a, int width, int height, size_t nbins, double bin_lo,
                          double bin_step, size_t npoints, int groups, size_t ntexels,
                          vr_error *err) {
  memset(a, 0, sizeof *a);
  a->width = width;
  a->height = height;
  a->nbins = nbins;
  a->bin_lo = bin_lo;
  a->bin_step = bin_step;
  a->npoints = npoints;
  a->groups = groups;
  a->ntexels = ntexels;
  size_t px = (size_t)width * (size_t)height;
  a->xyz = zeros(px * 3);
  a->bins = zeros(px * nbins);
  a->sensor_lx = zeros(npoints * (size_t)groups);
  a->sensor_bins = zeros(npoints * nbins);
  a->texel_uv = zeros(ntexels);
  if (!a->xyz || !a->bins || !a->sensor_lx || !a->sensor_bins || !a->texel_uv) {
    vr_accum_destroy(a);
    return vr_error_set(err, VR_E_NOMEM, "film of %d x %d x %zu bins: out of memory", width,
                        height, nbins);
  }
  return VR_OK;
}

void vr_accum_destroy(accum *a) {
  free(a->xyz);
  free(a->bins);
  free(a->sensor_lx);
  free(a->sensor_bins);
  free(a->texel_uv);
  memset(a, 0, sizeof *a);
}

static long bin_of(const accum *a, double nm) {
  double x = (nm - a->bin_lo) / a->bin_step;
  if (x < 0 || x >= (double)a->nbins) return -1;
  return (long)x;
}

void vr_accum_pixel(accum *a, uint32_t pixel, int nwl, const double *wl, const double *L,
                    double wl_weight) {
  double xyz[3] = {0, 0, 0};
  for (int i = 0; i < nwl; i++) {
    if (L[i] == 0.0) continue;
    double c[3];
    vr_cmf_eval(VR_CIE1931_2DEG, wl[i], c);
    for (int k = 0; k < 3; k++) xyz[k] += KM * c[k] * L[i] * wl_weight;
    long b = bin_of(a, wl[i]);
    if (b >= 0) vr_atomic_add(&a->bins[(size_t)pixel * a->nbins + (size_t)b], L[i] * wl_weight / a->bin_step);
  }
  for (int k = 0; k < 3; k++) vr_atomic_add(&a->xyz[(size_t)pixel * 3 + (size_t)k], xyz[k]);
}

void vr_accum_sensor(accum *a, uint32_t point, uint32_t sample, int nwl, const double *wl,
                     const double *E, double wl_weight) {
  double lx = 0;
  for (int i = 0; i < nwl; i++) {
    if (E[i] == 0.0) continue;
    double c[3];
    vr_cmf_eval(VR_CIE1931_2DEG, wl[i], c);
    lx += KM * c[1] * E[i] * wl_weight;
    long b = bin_of(a, wl[i]);
    if (b >= 0)
      vr_atomic_add(&a->sensor_bins[(size_t)point * a->nbins + (size_t)b],
                    E[i] * wl_weight / a->bin_step);
  }
  vr_atomic_add(&a->sensor_lx[(size_t)point * (size_t)a->groups + sample % (uint32_t)a->groups], lx);
}
