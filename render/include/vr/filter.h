/* The pixel filter of the camera (camera ... filter=NAME [filter_radius=R]
 * [filter_sigma=S], docs/scene-format.md): how much a camera sample at
 * offset (dx, dy) pixels from its pixel's centre counts in that pixel.
 *
 * The filters and their defaults are pbrt-v4's (Pharr, Jakob & Humphreys,
 * Physically Based Rendering, 4th ed., 2023, section 8.8), all separable,
 * f(x, y) = f1(x) f1(y), zero beyond the radius R:
 *   box       f1 = 1                                        R = 0.5
 *   tent      f1 = R - |x|   (pbrt's "triangle")            R = 2
 *   gaussian  f1 = G(x) - G(R), G the normal density        R = 1.5, sigma 0.5
 *   mitchell  f1 = M(2|x| / R), Mitchell & Netravali's      R = 2
 *             cubic with B = C = 1/3 (SIGGRAPH 1988), negative for
 *             8/7 < 2|x|/R < 2.
 *
 * Samples are placed by filter importance sampling, as pbrt-v4 does: the
 * offset is drawn in proportion to |f| and the sample weighs
 * sign(f) times a constant, so no sample is wasted on a small weight.
 * Without a running sum of weights in the film, the constant is what makes
 * the pixel's estimate right: for box, tent and gaussian (f >= 0) every
 * weight is exactly 1.  For mitchell, of the n samples of a pixel in a pass
 * exactly k fall in the negative lobes (k = n q rounded, kept in [1, n-1];
 * q = F-/(F+ + F-) the share of |f| there, F+ and F- the integrals of f's
 * positive and negative parts), the rest in the positive ones, each set
 * drawn from its part of |f|; weights n F+/((n-k) F) and -n F-/(k F) with
 * F = F+ - F- make the estimate unbiased and sum to n exactly, so a
 * uniformly lit image stays exact (stratified sampling of the sign).  With
 * n = 1 the sign is drawn with probability q and the weight is
 * sign (F+ + F-)/F: unbiased, not exact.
 *
 * A zeroed vr_filter is the default box of radius 0.5, which draws the
 * sample uniformly over its pixel, the renderer's behaviour before filters
 * existed (bit for bit: the offset is u - 0.5). */
#ifndef VR_FILTER_H
#define VR_FILTER_H

#include <stdbool.h>
#include <stdint.h>

#include "vr/rng.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum vr_filter_kind {
  VR_FILTER_BOX = 0,
  VR_FILTER_TENT,
  VR_FILTER_GAUSSIAN,
  VR_FILTER_MITCHELL
} vr_filter_kind;

#define VR_FILTER_MAX_RADIUS 16.0

typedef struct vr_filter {
  vr_filter_kind kind;
  double radius;    /* pixels, both axes; 0 (zeroed): box 0.5 */
  double sigma;     /* gaussian: standard deviation in pixels */
  /* Set by vr_filter_init: */
  double g_r;       /* gaussian: G(R), subtracted so that f1 reaches 0 at R */
  double pos, neg;  /* integrals of f1's positive part and of |negative part| over [-R, R] */
  double q;         /* 2D: F- / (F+ + F-), the share of |f| in the negative lobes */
  double f_pos, f_neg, f_all; /* 2D: F+, F-, F = F+ - F- */
  /* Gaussian and Mitchell: the offset |x| at which the integral of the
   * positive [0] and negative [1] part of f1 reaches i/64 of its whole,
   * brackets and first guesses for the exact inversion. */
  double inv[2][65];
} vr_filter;

/* The name of a kind ("box", "tent", "gaussian", "mitchell"); the kind of a
 * name (pbrt's "triangle" is a tent), false if unknown. */
const char *vr_filter_name(vr_filter_kind kind);
bool vr_filter_kind_of(const char *name, vr_filter_kind *kind);

/* Fills f for kind with radius R (<= 0: the kind's default) and, for a
 * gaussian, sigma (<= 0: 0.5).  False for a radius above
 * VR_FILTER_MAX_RADIUS or a gaussian whose sigma is not positive. */
bool vr_filter_init(vr_filter *f, vr_filter_kind kind, double radius, double sigma);

/* f1(x) and f(x, y) as defined above (not normalised). */
double vr_filter_eval_1d(const vr_filter *f, double x);
double vr_filter_eval(const vr_filter *f, double x, double y);

/* The offset (dx, dy) of sample `index` of the `count` samples its pixel
 * takes in this pass, drawn from u1, u2 (the sampler's pixel dimensions),
 * and its weight (above).  v, uniform in [0, 1) and the same for every
 * sample of the pixel in the pass, decides which samples take the negative
 * lobes.  Box: dx = R (2 u1 - 1). */
double vr_filter_sample_u(const vr_filter *f, double u1, double u2, double v, uint32_t index,
                          uint32_t count, double *dx, double *dy);

/* The same with the numbers of a camera sample's key: u1, u2 are its
 * PIXEL_X and PIXEL_Y numbers; index is the sample's place in the pass
 * (key->sample - index is the pass's first sample, which keys v). */
double vr_filter_sample(const vr_filter *f, const vr_rng_key *key, uint32_t index, uint32_t count,
                        double *dx, double *dy);

#ifdef __cplusplus
}
#endif

#endif
