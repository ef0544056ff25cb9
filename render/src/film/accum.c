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

#include "film/accum.h"
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

vr_status vr_accum_create(vr_accum *a, int width, int height, size_t nbins, double bin_lo,
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
  a->sensor_parts = zeros(npoints * VR_SENSOR_PARTS);
  a->sensor_patches = zeros(npoints * VR_SENSOR_PATCHES);
  a->texel_uv = zeros(ntexels);
  a->texel_patches = zeros(ntexels * VR_SENSOR_PATCHES);
  if (!a->xyz || !a->bins || !a->sensor_lx || !a->sensor_bins || !a->sensor_parts ||
      !a->sensor_patches || !a->texel_uv || !a->texel_patches) {
    vr_accum_destroy(a);
    return vr_error_set(err, VR_E_NOMEM, "film of %d x %d x %zu bins: out of memory", width,
                        height, nbins);
  }
  return VR_OK;
}

double *vr_accum_take_mean(_Atomic uint64_t **cells, size_t n, double by) {
  _Atomic uint64_t *c = *cells;
  /* Allocated storage takes the type of what is stored in it: each slot is
   * read as its bits, then written back as a double (both 8 bytes). */
  _Static_assert(sizeof(_Atomic uint64_t) == sizeof(double), "a sum's slot holds a double");
  double *d = (double *)(void *)c;
  for (size_t i = 0; i < n; i++) {
    double v = vr_atomic_get(&c[i]) / by;
    memcpy(&d[i], &v, sizeof v);
  }
  *cells = NULL;
  return d;
}

void vr_accum_destroy(vr_accum *a) {
  free(a->xyz);
  free(a->bins);
  free(a->half_xyz);
  free(a->feat);
  free(a->pixel_patches);
  free(a->sensor_lx);
  free(a->sensor_bins);
  free(a->sensor_parts);
  free(a->sensor_patches);
  free(a->texel_uv);
  free(a->texel_patches);
  free(a->cmf_avg);
  memset(a, 0, sizeof *a);
}

vr_status vr_accum_set_bins(vr_accum *a, double lo, double hi, int n, vr_error *err) {
  free(a->cmf_avg);
  a->cmf_avg = calloc((size_t)(n > 0 ? n : 1), sizeof *a->cmf_avg);
  if (!a->cmf_avg) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  a->cmf_lo = lo;
  a->cmf_step = (hi - lo) / n;
  a->cmf_n = n;
  for (int b = 0; b < n; b++) {
    /* Midpoint rule on 0.1 nm steps inside the bin. */
    int m = (int)ceil(a->cmf_step / 0.1);
    double h = a->cmf_step / m;
    for (int i = 0; i < m; i++) {
      double c[3];
      vr_cmf_eval(VR_CIE1931_2DEG, lo + b * a->cmf_step + (i + 0.5) * h, c);
      for (int k = 0; k < 3; k++) a->cmf_avg[b][k] += c[k] / m;
    }
  }
  return VR_OK;
}

/* The CMFs a wavelength sample is weighted by. */
static void cmf(const vr_accum *a, double nm, double c[3]) {
  if (a->cmf_avg) {
    long b = (long)floor((nm - a->cmf_lo) / a->cmf_step);
    if (b >= 0 && b < a->cmf_n) {
      memcpy(c, a->cmf_avg[b], sizeof a->cmf_avg[b]);
      return;
    }
  }
  vr_cmf_eval(VR_CIE1931_2DEG, nm, c);
}

static long bin_of(const vr_accum *a, double nm) {
  double x = (nm - a->bin_lo) / a->bin_step;
  if (x < 0 || x >= (double)a->nbins) return -1;
  return (long)x;
}

vr_status vr_accum_keep_halves(vr_accum *a, vr_error *err) {
  if (a->half_xyz) return VR_OK;
  a->half_xyz = zeros((size_t)a->width * (size_t)a->height * 3);
  if (!a->half_xyz)
    return vr_error_set(err, VR_E_NOMEM, "film halves of %d x %d pixels: out of memory", a->width,
                        a->height);
  return VR_OK;
}

vr_status vr_accum_keep_features(vr_accum *a, vr_error *err) {
  if (a->feat) return VR_OK;
  a->feat = zeros((size_t)a->width * (size_t)a->height * VR_FEATURES);
  if (!a->feat)
    return vr_error_set(err, VR_E_NOMEM, "film features of %d x %d pixels: out of memory",
                        a->width, a->height);
  return VR_OK;
}

vr_status vr_accum_keep_patches(vr_accum *a, vr_error *err) {
  if (a->pixel_patches) return VR_OK;
  a->pixel_patches = zeros((size_t)a->width * (size_t)a->height * VR_PIXEL_SOURCES);
  if (!a->pixel_patches)
    return vr_error_set(err, VR_E_NOMEM, "film sky patches of %d x %d pixels: out of memory",
                        a->width, a->height);
  return VR_OK;
}

void vr_accum_features(vr_accum *a, uint32_t pixel, double w, int nwl, const double *wl,
                       const double *albedo, const double n[3], double depth) {
  if (!a->feat || !(w > 0)) return;
  double num[3] = {0, 0, 0}, den[3] = {0, 0, 0};
  for (int i = 0; i < nwl; i++) {
    double c[3];
    cmf(a, wl[i], c);
    for (int k = 0; k < 3; k++) num[k] += c[k] * albedo[i], den[k] += c[k];
  }
  double f[VR_FEATURES] = {0};
  for (int k = 0; k < 3; k++) {
    f[VR_FEAT_ALBEDO + k] = den[k] > 0 ? num[k] / den[k] : 0.0;
    f[VR_FEAT_NORMAL + k] = n[k];
    f[VR_FEAT_ALBEDO2] += f[VR_FEAT_ALBEDO + k] * f[VR_FEAT_ALBEDO + k];
    f[VR_FEAT_NORMAL2] += n[k] * n[k];
  }
  f[VR_FEAT_DEPTH] = depth;
  f[VR_FEAT_DEPTH2] = depth * depth;
  f[VR_FEAT_WEIGHT] = 1.0;
  _Atomic uint64_t *cell = &a->feat[(size_t)pixel * VR_FEATURES];
  for (int k = 0; k < VR_FEATURES; k++) vr_atomic_add(&cell[k], w * f[k]);
}

void vr_accum_pixel(vr_accum *a, uint32_t pixel, int nwl, const double *wl, const double *L,
                    double wl_weight) {
  vr_accum_pixel_half(a, pixel, false, nwl, wl, L, wl_weight);
}

void vr_accum_pixel_half(vr_accum *a, uint32_t pixel, bool second_half, int nwl,
                         const double *wl, const double *L, double wl_weight) {
  double xyz[3] = {0, 0, 0};
  for (int i = 0; i < nwl; i++) {
    if (L[i] == 0.0) continue;
    double c[3];
    cmf(a, wl[i], c);
    for (int k = 0; k < 3; k++) xyz[k] += KM * c[k] * L[i] * wl_weight;
    long b = bin_of(a, wl[i]);
    if (b >= 0) vr_atomic_add(&a->bins[(size_t)pixel * a->nbins + (size_t)b], L[i] * wl_weight / a->bin_step);
  }
  for (int k = 0; k < 3; k++) vr_atomic_add(&a->xyz[(size_t)pixel * 3 + (size_t)k], xyz[k]);
  if (a->half_xyz && second_half)
    for (int k = 0; k < 3; k++) vr_atomic_add(&a->half_xyz[(size_t)pixel * 3 + (size_t)k], xyz[k]);
}

void vr_accum_pixel_patch(vr_accum *a, uint32_t pixel, int patch, int nwl, const double *wl,
                          const double *L, double wl_weight) {
  if (!a->pixel_patches || patch < 0 || patch >= VR_PIXEL_SOURCES) return;
  double Y = 0;
  for (int i = 0; i < nwl; i++) {
    if (L[i] == 0.0) continue;
    double c[3];
    cmf(a, wl[i], c);
    Y += KM * c[1] * L[i] * wl_weight;
  }
  vr_atomic_add(&a->pixel_patches[(size_t)pixel * VR_PIXEL_SOURCES + (size_t)patch], Y);
}

/* The illuminance of E, in lx. */
static double illuminance(vr_accum *a, int nwl, const double *wl, const double *E, double wl_weight) {
  double lx = 0;
  for (int i = 0; i < nwl; i++) {
    if (E[i] == 0.0) continue;
    double c[3];
    cmf(a, wl[i], c);
    lx += KM * c[1] * E[i] * wl_weight;
  }
  return lx;
}

void vr_accum_sensor_part_lx(vr_accum *a, uint32_t point, int part, double lx) {
  if (part >= 0 && part < VR_SENSOR_PARTS)
    vr_atomic_add(&a->sensor_parts[(size_t)point * VR_SENSOR_PARTS + (size_t)part], lx);
}

void vr_accum_sensor_patch_lx(vr_accum *a, uint32_t point, int patch, double lx) {
  if (patch >= 0 && patch < VR_SENSOR_PATCHES)
    vr_atomic_add(&a->sensor_patches[(size_t)point * VR_SENSOR_PATCHES + (size_t)patch], lx);
}

void vr_accum_sensor_part(vr_accum *a, uint32_t point, int part, int nwl, const double *wl,
                          const double *E, double wl_weight) {
  vr_accum_sensor_part_lx(a, point, part, illuminance(a, nwl, wl, E, wl_weight));
}

/* The illuminance of E (and, with spectrum, its spectrum into point's
 * bins) into slot `slot` of point. */
static double sensor_add(vr_accum *a, uint32_t point, uint32_t slot, int nwl, const double *wl,
                         const double *E, double wl_weight, bool spectrum) {
  for (int i = 0; spectrum && i < nwl; i++) {
    long b = E[i] != 0.0 ? bin_of(a, wl[i]) : -1;
    if (b >= 0)
      vr_atomic_add(&a->sensor_bins[(size_t)point * a->nbins + (size_t)b],
                    E[i] * wl_weight / a->bin_step);
  }
  double lx = illuminance(a, nwl, wl, E, wl_weight);
  vr_atomic_add(&a->sensor_lx[(size_t)point * (size_t)a->groups + slot], lx);
  return lx;
}

double vr_accum_sensor(vr_accum *a, uint32_t point, uint32_t sample, int nwl, const double *wl,
                       const double *E, double wl_weight) {
  return sensor_add(a, point, sample % (uint32_t)a->groups, nwl, wl, E, wl_weight, true);
}

void vr_accum_sensor_lx(vr_accum *a, uint32_t point, uint32_t slot, int nwl, const double *wl,
                        const double *E, double wl_weight) {
  if (slot < (uint32_t)a->groups) (void)sensor_add(a, point, slot, nwl, wl, E, wl_weight, false);
}

