/* The display denoiser (render/src/film/denoise.c): a feature-guided
 * non-local-means filter for the PNG of a render.  The EXRs and the
 * sensors keep the raw, unbiased estimates; only what the eye sees is
 * filtered.  docs/vr-render.md "Denoising" says which method and why.
 *
 * Inputs per pixel (W x H, row-major, from the top-left):
 *   xyz      the film's mean CIE XYZ (cd/m2);
 *   xyz_b    the mean of the second half of the pixel's samples alone, an
 *            estimate independent of the first half's: (xyz - xyz_b)^2 is
 *            an unbiased estimate of the variance of xyz, channel by
 *            channel;
 *   feat     VR_DENOISE_FEATURES means per pixel: albedo X Y Z relative to
 *            the equal-energy white, shading normal x y z, nearness
 *            1 / (1 + t / 1 m) (0 for the sky);
 *   feat_var the variance of those means (albedo, normal, nearness: one per
 *            group, summed over its components). */
#ifndef VR_DENOISE_H
#define VR_DENOISE_H

#include "vr/error.h"

#ifdef __cplusplus
extern "C" {
#endif

enum { VR_DENOISE_FEATURES = 7, VR_DENOISE_GROUPS = 3 };

typedef struct vr_denoise_params {
  int radius;       /* search window (2 radius + 1)^2; 0: 8 */
  int patch;        /* colour patches (2 patch + 1)^2; 0: 2 */
  double k_colour;  /* colour tolerance in standard errors; 0: 0.9 */
  double k_feature; /* feature tolerance; 0: 0.4 */
  double tau;       /* a feature's smallest normalising variance; 0: 1e-3 */
  int threads;      /* 0: 1 */
} vr_denoise_params;

/* Filters xyz into out (W * H * 3, may not alias the inputs).  A NaN or
 * infinity in the inputs is VR_E_RANGE naming the pixel; W or H below 1
 * is VR_E_ARG. */
vr_status vr_denoise(int W, int H, const double *xyz, const double *xyz_b, const double *feat,
                     const double *feat_var, const vr_denoise_params *params, double *out,
                     vr_error *err);

#ifdef __cplusplus
}
#endif

#endif
