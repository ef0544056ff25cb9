/* Reflectance spectra from camera responses under several known lights, after
 * Cohen and Kappauf ("Metameric color stimuli, fundamental metamers, and
 * Wyszecki's metameric blacks", Am. J. Psychol. 95, 1982; "Color mixture and
 * fundamental metamers: theory, algebra, application", Am. J. Psychol. 98,
 * 1985).
 *
 * A reflectance sampled at N wavelengths is a vector r.  Under L lights the
 * camera records c = A r, A the stacked (3L x N) matrix of vr_camera_response()
 * blocks, each times its light's exposure.  The projector R = A^T (A A^T)^-1 A
 * ("Matrix R") splits every r into its fundamental metamer r* = R r, which
 * depends on the data only (r* = A^T (A A^T)^-1 c), and a metameric black
 * b = (I - R) r with A b = 0.  Three methods choose a spectrum with the
 * recorded responses:
 *
 *   VR_RECOVER_MATRIX_R      r* itself, through the SVD pseudo-inverse: an
 *                            exact round trip, may leave [0, 1].
 *   VR_RECOVER_BOUNDED       the smoothest spectrum (least ||D2 r||^2, D2 the
 *                            second differences) with A r = c and 0 <= r <= 1;
 *                            if no spectrum in [0, 1] has the responses c, the
 *                            smoothest of those that come closest (least
 *                            ||A r - c|| within the bounds), flagged.
 *   VR_RECOVER_REGULARISED   least ||W (A r - c)||^2 + lambda ||D2 r||^2 with
 *                            lambda from generalised cross-validation, then
 *                            the bounds; for noisy data such as 8-bit photos.
 *
 * Conventions: rows are ordered light by light, R G B within a light (row
 * 3l + ch).  Responses c are linear (decode sRGB first with vr_srgb_decode()).
 * A system is immutable once created; vr_recover() and the accessors may be
 * called from several threads on one system. */
#ifndef VR_RECOVER_H
#define VR_RECOVER_H

#include <stddef.h>
#include "vr/camera.h"
#include "vr/error.h"
#include "vr/spectrum.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vr_recovery_system vr_recovery_system;

typedef enum vr_recover_method {
  VR_RECOVER_MATRIX_R = 0,
  VR_RECOVER_BOUNDED = 1,
  VR_RECOVER_REGULARISED = 2
} vr_recover_method;

/* Noise model that sets the weights W of the regularised method. */
typedef enum vr_noise_model {
  /* Equal noise on every channel in the units of c (16-bit linear data:
   * W = I). */
  VR_NOISE_UNIFORM = 0,
  /* 8-bit sRGB-encoded pixels decoded to linear c: the quantisation step
   * 1/255 of the encoded value maps to sigma_i = decode'(encode(c_i)) /
   * (255 sqrt 12) in c, and W = diag(1 / sigma_i). */
  VR_NOISE_SRGB8 = 1
} vr_noise_model;

/* How the regularised method chooses lambda. */
typedef enum vr_lambda_rule {
  /* Unbiased predictive risk when the caller gives the noise of each
   * observation (vr_recover_noisy), generalised cross-validation when not
   * (bench_rgb2spec_noise and docs/vr-rgb2spec.md compare the rules). */
  VR_LAMBDA_AUTO = 0,
  VR_LAMBDA_GCV = 1,
  /* Morozov: the smoothest spectrum whose weighted misfit, with W =
   * 1 / sigma, is within discrepancy_tau times the number of observations. */
  VR_LAMBDA_DISCREPANCY = 2,
  /* Unbiased predictive risk (Mallows' C_L) with W = 1 / sigma. */
  VR_LAMBDA_UPRE = 3
} vr_lambda_rule;

typedef struct vr_recovery_options {
  /* Singular values below rank_tol times the largest are treated as zero
   * (pseudo-inverse, constraint reduction).  Default 1e-10. */
  double rank_tol;
  /* Bounded method: the data count as reachable by a spectrum in [0, 1] when
   * min over 0 <= r <= 1 of ||A_n r - c_n|| <= feas_tol * max(1, ||c_n||),
   * in exposure-normalised units (white = 1).  Default 1e-9. */
  double feas_tol;
  vr_noise_model noise; /* default VR_NOISE_UNIFORM */
  /* Regularised method: lambda < 0 chooses it by GCV (default -1), else
   * this fixed value. */
  double lambda;
  /* Regularised method: weight rho of trace H in the GCV denominator,
   * (m - rho tr H)^2; 1 is classical GCV, the default 1.4 the modified GCV
   * of Kim and Gu (2004), which resists GCV's undersmoothing with few
   * observations (see recover_regularised.c).  Must be >= 1. */
  double gcv_rho;
  vr_lambda_rule lambda_rule; /* default VR_LAMBDA_AUTO */
  double discrepancy_tau;     /* default 1; must be > 0 */
  /* Cap on active-set iterations per solve; 0 means 10 n + 50, n the
   * unknowns (N samples plus one slack per clipped observation). */
  int max_iter;
} vr_recovery_options;

void vr_recovery_options_default(vr_recovery_options *opt);

/* A system for camera cam under lights spd[0..lights-1] with exposures
 * scale[0..lights-1] (NULL: all 1; each finite and > 0).  The camera is
 * copied from and may be destroyed afterwards.  opt NULL means the
 * defaults. */
vr_recovery_system *vr_recovery_system_create(const vr_camera *cam, size_t lights,
                                              const vr_spectrum *const *spd, const double *scale,
                                              const vr_recovery_options *opt, vr_error *err);
void vr_recovery_system_destroy(vr_recovery_system *s);

size_t vr_recovery_system_samples(const vr_recovery_system *s); /* N */
size_t vr_recovery_system_rows(const vr_recovery_system *s);    /* 3L */
size_t vr_recovery_system_lights(const vr_recovery_system *s);  /* L */
const double *vr_recovery_system_grid(const vr_recovery_system *s);
/* A, 3L x N row-major, exposures included. */
const double *vr_recovery_system_matrix(const vr_recovery_system *s);
/* Singular values (descending, min(3L, N) of them) of A with each light's
 * block divided by its exposure, so that every block gives a perfect white a
 * response of 1 in the normalising channel (Y, or green for measured
 * cameras); count receives how many. */
const double *vr_recovery_system_singular_values(const vr_recovery_system *s, size_t *count);
/* Their ratio largest / smallest: INFINITY when the smallest is 0. */
double vr_recovery_system_condition(const vr_recovery_system *s);
/* Singular values above rank_tol * largest. */
size_t vr_recovery_system_rank(const vr_recovery_system *s);

/* Clip marks per observation, in the clipped[] array of vr_recover(). */
#define VR_CLIP_NONE 0 /* a measurement */
#define VR_CLIP_HIGH 1 /* saturated: the true response is >= c_i */
#define VR_CLIP_LOW 2  /* cut at the bottom: the true response is <= c_i */

/* What vr_recover() did, bit flags in vr_recover_info.flags. */
enum {
  /* The pseudo-inverse dropped singular values below rank_tol. */
  VR_RECOVER_FLAG_RANK_DEFICIENT = 1u << 0,
  /* Bounded: no spectrum in [0, 1] has the responses; the result is the
   * smoothest of those whose responses come closest in least squares. */
  VR_RECOVER_FLAG_OUT_OF_GAMUT = 1u << 1,
  /* Some observations were clipped: dropped from the equations (and used as
   * inequalities by the bounded and regularised methods). */
  VR_RECOVER_FLAG_CLIPPED = 1u << 2,
  /* Matrix R ignores clip inequalities; set when its result breaks one. */
  VR_RECOVER_FLAG_CLIP_VIOLATED = 1u << 3,
  /* Matrix R's result leaves [0, 1]. */
  VR_RECOVER_FLAG_OUTSIDE_UNIT = 1u << 4,
  /* The active-set loop hit its iteration cap; the result is feasible but
   * may not be optimal. */
  VR_RECOVER_FLAG_MAX_ITER = 1u << 5,
  /* Every observation was clipped: nothing but inequalities to go on. */
  VR_RECOVER_FLAG_NO_DATA = 1u << 6,
  /* Regularised: fewer than two degrees of freedom beyond the smoothness
   * operator's null space (one light, or clipping left two channels), so
   * GCV cannot choose; lambda is then 1e-6 times the squared scale of the
   * data, which gives the smoothest (near-)exact fit. */
  VR_RECOVER_FLAG_GCV_FLAT = 1u << 7,
  /* vr_recover_noisy: the result misses the unclipped responses by more
   * than their noise explains (chi2 > chi2_limit). */
  VR_RECOVER_FLAG_MISFIT = 1u << 8
};

typedef struct vr_recover_info {
  double residual;       /* ||A r - c|| over the unclipped observations, units of c */
  double residual_white; /* the same with each light's block divided by its exposure */
  double clip_violation; /* largest breach of a clip inequality, units of c (0: none) */
  size_t bounds_active;  /* samples of r at 0 or 1 (bounded, regularised) */
  size_t rank;           /* rank used by the pseudo-inverse (Matrix R) */
  size_t used;           /* observations used as equations */
  size_t clipped;        /* observations marked clipped */
  double lambda;         /* regularised: the lambda used */
  double gcv;            /* regularised: the GCV value at lambda */
  int iterations;        /* active-set iterations, all phases */
  /* vr_recover_noisy: sum over unclipped observations of ((A r - c) /
   * sigma)^2, and the 99.9 % point of chi-squared with that many degrees
   * of freedom (Wilson-Hilferty); NAN from vr_recover. */
  double chi2, chi2_limit;
  unsigned flags;        /* VR_RECOVER_FLAG_* */
} vr_recover_info;

/* Recovers r_out (N samples on the system's grid) from c (3L responses).
 * clipped: 3L marks (VR_CLIP_*), or NULL for none.  info may be NULL.
 * VR_E_ARG on a NULL pointer, an unknown method or clip mark, or a
 * non-finite c (the message names the index); VR_E_NUMERIC if LAPACK fails;
 * VR_E_NOMEM. */
vr_status vr_recover(const vr_recovery_system *s, vr_recover_method m, const double *c,
                     const unsigned char *clipped, double *r_out, vr_recover_info *info,
                     vr_error *err);

/* vr_recover with the noise standard deviation sigma[i] > 0 of every
 * response (units of c; for a region's mean, the pixels' standard deviation
 * over the square root of their number, with a floor for quantisation).
 * The regularised method then weighs each response by 1 / sigma and, with
 * lambda_rule AUTO, chooses lambda by unbiased predictive risk; every
 * method reports chi2 and flags VR_RECOVER_FLAG_MISFIT when the result
 * misses the responses by more than the noise explains.  Errors as
 * vr_recover, and VR_E_ARG for a sigma that is not finite and > 0. */
vr_status vr_recover_noisy(const vr_recovery_system *s, vr_recover_method m, const double *c,
                           const double *sigma, const unsigned char *clipped, double *r_out,
                           vr_recover_info *info, vr_error *err);

/* The lambda for recovering single pixels whose responses scatter with
 * standard deviations sigma_pixel about c_mean (a region's mean, taken as
 * noise-free): the one that minimises the expected predictive risk
 * ||(I - H) W c||^2 + trace H^2 of the regularised smoother H with W =
 * 1 / sigma_pixel, over the unclipped rows.  VR_E_ARG when fewer than two
 * rows are unclipped. */
vr_status vr_recover_pixel_lambda(const vr_recovery_system *s, const double *c_mean,
                                  const double *sigma_pixel, const unsigned char *clipped,
                                  double *lambda, vr_error *err);

/* Noise of a single pixel's linear response: sd, the standard deviation of
 * the pixels of a flat region, already holds the quantisation error when the
 * noise dithers it (sd >= step / 2); below that the rounding error,
 * uniform over one step of the file (step: one code in linear units at
 * that level, 0 for float files), adds step^2 / 12. */
double vr_recover_pixel_sigma(double sd, double step);
/* Noise of the mean of `pixels` such pixels: their scatter averages down
 * as 1 / sqrt(pixels); undithered rounding (sd < step / 2) does not, so
 * step / sqrt 12 stays as a floor.  Never below 1e-6 (a float file of a
 * flat synthetic region would otherwise claim no noise at all). */
double vr_recover_mean_sigma(double sd, long pixels, double step);

/* The fundamental-metamer matrix P (N x 3L, row-major) with r* = P c for
 * every pixel: P = A^+, the SVD pseudo-inverse at rank_tol, formed on the
 * exposure-normalised A (which leaves r* unchanged when A has full row
 * rank).  The fast path for per-pixel Matrix R; P A is the projector R. */
vr_status vr_recovery_matrix(const vr_recovery_system *s, double *P);

/* The responses c = A r (3L values) of a spectrum r on the system's grid. */
void vr_render_rgb(const vr_recovery_system *s, const double *r, double *c);

const char *vr_recover_method_name(vr_recover_method m);

#ifdef __cplusplus
}
#endif
#endif
