/* Per-pixel spectral recovery with the prior and bounds of the regularised
 * method (vr/recover.h), fast enough for 12-megapixel photos.
 *
 * For a fixed lambda and fixed noise weights W = diag(1 / sigma), the
 * regularised estimate without bounds is linear in the responses:
 *
 *     r0 = K c,  K = H^-1 A^T W^2,  H = A^T W^2 A + lambda D2^T D2,
 *
 * so K is computed once and each pixel costs one small matrix product.
 * Only a pixel whose r0 leaves [0, 1] gets the bounded correction: the
 * minimiser of the same objective over 0 <= r <= 1, by a primal-dual active
 * set on the bounds (Hintermueller, Ito and Kunisch, SIAM J. Optim. 13,
 * 2003) written with M = H^-1: with B the bounds held active and b their
 * values, r = r0 + M[:,B] mu, M[B,B] mu = b - r0[B], and mu is the bounds'
 * multiplier (>= 0 at 0, <= 0 at 1 at the optimum).  It is the same
 * problem vr_recover_noisy solves for a region with these weights and
 * lambda, so both give the same spectrum (tests/acquire/test_recover_pixel.c).
 * Should the active set cycle (it is not guaranteed to converge when H is
 * not an M-matrix), the pixel falls back to that general solver, flagged.
 *
 * Clipped channels carry no measurement: a pixel with clipped channels is
 * recovered from the others (K and M for that pattern of clipped channels,
 * computed on first use and cached per workspace) and flagged.  Unlike the
 * region method, the clipped values are not used as inequalities.
 *
 * The products run in 4-float SSE2 vectors, or in 8-float AVX2 fused
 * multiply-adds when the processor has them (at creation; the environment
 * variable VR_NO_AVX2 forces SSE2, for tests): the results differ by float
 * rounding only.
 *
 * A recovery is read-only after creation and shared by threads; each
 * thread needs its own workspace.  The recovery system must outlive both. */
#ifndef VR_RECOVER_PIXEL_H
#define VR_RECOVER_PIXEL_H

#include <stddef.h>
#include <stdint.h>

#include "vr/error.h"
#include "vr/recover.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vr_pixel_recovery vr_pixel_recovery;
typedef struct vr_pixel_workspace vr_pixel_workspace;

/* What vr_pixel_recover did, bit flags (also the values of the "flags"
 * channel vr-rgb2spec writes). */
enum {
  VR_PIXEL_CLIPPED_HIGH = 1u << 0, /* a channel at the file's clip level */
  VR_PIXEL_CLIPPED_LOW = 1u << 1,  /* a channel at code 0 */
  VR_PIXEL_BOUNDED = 1u << 2,      /* the linear estimate left [0, 1]: bounded correction */
  VR_PIXEL_MISFIT = 1u << 3,       /* chi2 beyond the 99.9 % point for its channels */
  VR_PIXEL_NO_DATA = 1u << 4,      /* fewer than two unclipped channels: set to 0 */
  VR_PIXEL_FALLBACK = 1u << 5      /* solved by the general active-set solver */
};

/* lambda in the weighted units of sigma (vr_recover_pixel_lambda);
 * sigma: 3L per-pixel noise standard deviations, finite and > 0;
 * preview: 3 x N row-major map from a spectrum to a preview RGB (e.g. sRGB
 * under D65), or NULL.  VR_E_ARG for bad arguments, VR_E_NUMERIC when H is
 * not positive definite (lambda too small for these lights). */
vr_pixel_recovery *vr_pixel_recovery_create(const vr_recovery_system *s, const double *sigma,
                                            double lambda, const double *preview, vr_error *err);
void vr_pixel_recovery_destroy(vr_pixel_recovery *p);
double vr_pixel_recovery_lambda(const vr_pixel_recovery *p);

vr_pixel_workspace *vr_pixel_workspace_create(const vr_pixel_recovery *p, vr_error *err);
void vr_pixel_workspace_destroy(vr_pixel_workspace *w);

/* Recovers one pixel: c its 3L linear responses (finite), clipped its 3L
 * clip marks (VR_CLIP_*, NULL: none).  r receives N samples in [0, 1],
 * rgb (when not NULL and the recovery has a preview) the preview of r,
 * chi2 (when not NULL) sum ((A r - c) / sigma)^2 over the unclipped
 * channels.  Returns VR_PIXEL_* flags. */
unsigned vr_pixel_recover(vr_pixel_workspace *w, const float *c, const unsigned char *clipped,
                          float *r, float *rgb, float *chi2);

#ifdef __cplusplus
}
#endif
#endif
