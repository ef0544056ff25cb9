/* The camera samples' feature sums (accum.c, VR_FEAT_*) into the result's
 * per-pixel means and the denoiser's inputs (vr/denoise.h): the features'
 * means and variances, and the mean of each pixel's second half. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "film/film_features.h"
#include "vr/colour.h"
#include "vr/denoise.h"

vr_status vr_film_features(vr_render_result *res, const vr_accum *acc, int spp, int passes,
                           bool display,
                           void (*half_extra)(const void *ctx, double *xyz), const void *ctx,
                           int threads, vr_error *err) {
  size_t px = (size_t)res->width * (size_t)res->height;
  res->features = malloc((px ? px : 1) * VR_RESULT_FEATURES * sizeof *res->features);
  double *feat = malloc((px ? px : 1) * VR_DENOISE_FEATURES * sizeof *feat);
  double *fvar = malloc((px ? px : 1) * VR_DENOISE_GROUPS * sizeof *fvar);
  double *b = display ? malloc((px ? px : 1) * 3 * sizeof *b) : NULL;
  vr_status st = VR_OK;
  if (!res->features || !feat || !fvar || (display && !b)) {
    st = vr_error_set(err, VR_E_NOMEM, "film features of %d x %d pixels: out of memory",
                      res->width, res->height);
    goto out;
  }
  /* The albedo's XYZ is relative to the equal-energy white; its linear
   * sRGB is scaled so that this white is (1, 1, 1). */
  double one[3] = {1, 1, 1}, white[3];
  vr_xyz_to_srgb_linear(one, white);
  for (size_t p = 0; p < px; p++) {
    double s[VR_FEATURES];
    for (int k = 0; k < VR_FEATURES; k++) s[k] = vr_atomic_get(&acc->feat[p * VR_FEATURES + (size_t)k]);
    double w = s[VR_FEAT_WEIGHT], n = res->pixel_samples ? (double)res->pixel_samples[p] : (double)spp;
    double *f = &feat[p * VR_DENOISE_FEATURES], *v = &fvar[p * VR_DENOISE_GROUPS];
    if (!(w > 0)) {
      /* No sample recorded features (every one ended on the way). */
      memset(f, 0, VR_DENOISE_FEATURES * sizeof *f);
      memset(v, 0, VR_DENOISE_GROUPS * sizeof *v);
    } else {
      double a2 = 0, n2 = 0;
      for (int k = 0; k < 3; k++) {
        f[k] = s[VR_FEAT_ALBEDO + k] / w;
        f[3 + k] = s[VR_FEAT_NORMAL + k] / w;
        a2 += f[k] * f[k];
        n2 += f[3 + k] * f[3 + k];
      }
      f[6] = s[VR_FEAT_DEPTH] / w;
      /* A group's variance over the samples, divided by their number: the
       * variance of its mean. */
      double m = n > 1 ? n : 1;
      v[0] = fmax(0.0, s[VR_FEAT_ALBEDO2] / w - a2) / m;
      v[1] = fmax(0.0, s[VR_FEAT_NORMAL2] / w - n2) / m;
      v[2] = fmax(0.0, s[VR_FEAT_DEPTH2] / w - f[6] * f[6]) / m;
    }
    double rgb[3];
    vr_xyz_to_srgb_linear(f, rgb);
    for (int k = 0; k < 3; k++) {
      res->features[p * VR_RESULT_FEATURES + (size_t)k] = (float)(rgb[k] / white[k]);
      res->features[p * VR_RESULT_FEATURES + 3 + (size_t)k] = (float)f[3 + k];
    }
    res->features[p * VR_RESULT_FEATURES + 6] = (float)f[6];
    if (display) {
      double scale = res->pixel_samples ? (n > 0 ? 2.0 / n : 0.0) : 2.0 / (passes > 0 ? passes : 1);
      for (int k = 0; k < 3; k++) b[3 * p + (size_t)k] = scale * vr_atomic_get(&acc->half_xyz[3 * p + (size_t)k]);
    }
  }
  if (display && half_extra) half_extra(ctx, b);
  if (display && !res->pixel_variance) {
    /* The halves' means a and b, the image's u = (a + b) / 2: the variance
     * of u, (a - b)^2 / 4 = (u - b)^2, unbiased with one degree of
     * freedom (adaptive sampling's is the same, render.c). */
    res->pixel_variance = malloc((px ? px : 1) * sizeof *res->pixel_variance);
    if (!res->pixel_variance) {
      st = vr_error_set(err, VR_E_NOMEM, "pixel variances: out of memory");
      goto out;
    }
    for (size_t p = 0; p < px; p++) {
      double d = res->xyz[3 * p + 1] - b[3 * p + 1];
      res->pixel_variance[p] = d * d;
    }
  }
  if (display) {
    res->xyz_display = malloc((px ? px : 1) * 3 * sizeof *res->xyz_display);
    if (!res->xyz_display) {
      st = vr_error_set(err, VR_E_NOMEM, "denoised image: out of memory");
      goto out;
    }
    vr_denoise_params dp = {.threads = threads};
    st = vr_denoise(res->width, res->height, res->xyz, b, feat, fvar, &dp, res->xyz_display, err);
  }
out:
  free(feat);
  free(fvar);
  free(b);
  return st;
}
