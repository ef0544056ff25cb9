/* Camera calibration from one photo of a ColorChecker Classic under a known
 * light: the tone curve of each channel (encoded value -> linear response)
 * and the three spectral sensitivities, with a smoothness prior.  The result
 * becomes a camera material (matdb kind "camera", roles r, g, b) that a
 * capture manifest uses through "camera db:NAME".
 *
 * Data: the 24 patch means as read from the photo, in chart order (the
 * BabelColor reference reflectances of vr/colorchecker.h, or the caller's),
 * values on a full scale of 1 (8-bit files are v/255).  A channel of a patch
 * is used only inside the domain (black, clip) of the encoded value, by
 * default (0.5/255, 0.999): values at or above clip are saturated, values at
 * or below black carry no information; such patches, and those the caller
 * flags, are left out of that channel and counted as clipped.
 *
 * 1. Linearisation, per channel, from the six neutral patches (19-24,
 *    white 9.5 to black 2).  A neutral of reflectance r_i gives the linear
 *    response y_i = k sum_l S(l) s(l) r_i(l), so y_i / y_white-of-flat-1 =
 *    rho_i = sum S s r_i / sum S s.  With a flat r_i this ratio does not
 *    depend on the unknown sensitivity s; the chart's neutrals are flat only
 *    to within a few per cent, so the first pass takes s flat over the grid
 *    (rho_i = sum S r_i / sum S, the light-weighted mean reflectance) and a
 *    second pass recomputes rho_i with the first pass's sensitivities (the
 *    tests measure the error of the flat assumption and of the result).
 *    Three curves f with f(v) = a rho_i are fitted by least squares in the
 *    encoded value (a free per channel: the exposure):
 *      linear   f(v) = v
 *      srgb     f(v) = the IEC 61966-2-1 decoding (vr_srgb_decode)
 *      gamma    f(v) = v^gamma, gamma fitted (0.3 to 5)
 *    and the one with the least BIC, k ln(RSS/k) + p ln k over the k usable
 *    neutrals (p = 1, 1, 2 parameters), is chosen: with all six a power law
 *    must fit about 26 % better in RSS than a fixed curve to win.  An RMS
 *    below 0.001 (a quarter of an 8-bit code) counts as 0.001: no evidence
 *    either way.  Each pass refits the curve.
 *
 * 2. Sensitivities.  On a wavelength grid (default 400-700 nm every 10 nm)
 *    each channel's sensitivity s is linear between the samples and zero
 *    outside (the measured-camera model of vr/camera.h), so a patch's linear
 *    response is y_p = sum_j A_pj s_j with
 *      A_pj = sum_l S(l) r_p(l) hat_j(l) / sum_l S(l) [grid range],
 *    summed at 1 nm over 360-830 nm (reflectances held at their end values).
 *    Per channel, over the usable patches,
 *      minimise ||A s - y||^2 + lambda ||D2 s||^2  subject to  s >= 0,
 *    D2 the second differences.  lambda is chosen by the modified GCV of Kim
 *    and Gu (weight rho = 1.4 on the trace, the same criterion as the
 *    regularised recovery, see recover_regularised.c) on the problem
 *    without the bound; the bound is then imposed at that lambda by the
 *    active-set solver of the bounded recovery on the stacked system
 *    [A; sqrt(lambda) D2] s ~ [y; 0] (non-negative least squares).  Every
 *    patch counts equally (uniform weights in the linear response).  Where
 *    the light has no power, or A is singular, the prior fills in: the
 *    penalised problem has a unique solution whenever A separates the
 *    straight lines (D2's null space).
 *    Reported per channel: lambda, the effective degrees of freedom (trace
 *    of the influence matrix of the final fit, on the samples the bound
 *    leaves free), the RMS residual in linear units, the GCV score; and the
 *    condition number of A (all 24 rows).
 *    Scale: one exposure fixes neither the exposure nor the light's absolute
 *    power, so the overall scale of the sensitivities is not identifiable;
 *    they are divided by the green peak (green peak = 1).  The channels'
 *    ratios are identifiable and kept (a camera's own white balance).
 *
 * Limits: one light, one chart.  24 patches of which the chart's spectra
 * span about 8 independent directions constrain 31 unknowns per channel:
 * the prior decides the rest, so fine structure (a sharp cut-on edge of a
 * filter) comes out smoothed.  All functions are thread-safe. */
#ifndef VR_CALIBRATE_H
#define VR_CALIBRATE_H

#include <stdbool.h>
#include <stddef.h>
#include "vr/error.h"
#include "vr/material.h"
#include "vr/spectrum.h"

#ifdef __cplusplus
extern "C" {
#endif

#define VR_CALIBRATION_PATCHES 24
#define VR_CALIBRATION_FIRST_NEUTRAL 18 /* patch 19, white 9.5; 24 is black 2 */

/* Tone curves: encoded value v in (0, 1] -> linear response. */
typedef enum vr_tone {
  VR_TONE_LINEAR = 0,
  VR_TONE_SRGB = 1,
  VR_TONE_GAMMA = 2,
  VR_TONE_AUTO = 3 /* options only: choose from the neutrals */
} vr_tone;

/* The linear response of encoded v (sign-symmetric for v < 0). */
double vr_tone_decode(vr_tone tone, double gamma, double v);
/* Its inverse. */
double vr_tone_encode(vr_tone tone, double gamma, double linear);
/* "linear", "srgb" or "gamma 2.213" into buf. */
void vr_tone_format(vr_tone tone, double gamma, char *buf, size_t size);
/* Reads that text back ("gamma=2.2" and "gamma:2.2" are accepted too; auto
 * when allow_auto); VR_E_PARSE naming the text otherwise, or for a gamma
 * outside [0.2, 10]. */
vr_status vr_tone_parse(const char *text, bool allow_auto, vr_tone *tone, double *gamma,
                        vr_error *err);

typedef struct vr_calibration_options {
  vr_tone tone;   /* VR_TONE_AUTO (default), or the curve of every channel */
  double gamma;   /* its exponent when tone is VR_TONE_GAMMA (default 2.2) */
  double clip;    /* encoded values >= clip are saturated (default 0.999) */
  double black;   /* encoded values <= black carry nothing (default 0.5/255) */
  double lambda;  /* < 0: chosen by GCV (default -1); else this weight */
  double gcv_rho; /* GCV trace weight, >= 1 (default 1.4) */
  int passes;     /* 1-10 (default 2): each pass after the first recomputes the
                   * neutrals' rho from the previous pass's sensitivities */
} vr_calibration_options;

void vr_calibration_options_default(vr_calibration_options *opt);

/* What vr_calibrate_camera() did, bit flags in vr_calibration.flags. */
enum {
  VR_CALIBRATION_FLAG_CLIPPED = 1u << 0,     /* some patch channels were left out */
  VR_CALIBRATION_FLAG_GCV_FLAT = 1u << 1,    /* GCV could not choose; smallest lambda */
  VR_CALIBRATION_FLAG_MAX_ITER = 1u << 2,    /* the active set hit its iteration cap */
  VR_CALIBRATION_FLAG_PARTIAL_LIGHT = 1u << 3 /* the light leaves > 10 % of the grid dark */
};

typedef struct vr_calibration {
  size_t n;
  double *grid_nm;  /* n wavelengths */
  double *sens[3];  /* r, g, b on the grid, green peak 1 */
  /* Tone curves. */
  vr_tone tone[3];          /* chosen (or imposed) */
  double gamma[3];          /* the power-law fit's exponent, whichever curve was chosen */
  double tone_rms[3];       /* RMS residual of the chosen curve over the neutrals, encoded units */
  double tone_fit_rms[3][3]; /* [channel][vr_tone]: every candidate's (NAN: not fitted) */
  int neutrals[3];          /* neutrals used per channel */
  /* max_i |rho_i(pass 2) / rho_i(flat) - 1| per channel: how far the flat-
   * neutral assumption of pass 1 was off (0 with one pass). */
  double neutral_correction[3];
  /* Sensitivities. */
  double lambda[3], dof[3], rms[3], gcv[3];
  int at_zero[3];  /* samples held at 0 by the bound */
  double cond;     /* condition number of A (24 x n) */
  int used[3];     /* patches used per channel */
  int used_patches;    /* used in all three channels */
  int clipped_patches; /* left out of at least one channel */
  bool clipped[VR_CALIBRATION_PATCHES];
  double coverage;     /* fraction of grid samples where the light has >= 1 % of its peak */
  unsigned flags;
  vr_calibration_options options; /* as used */
} vr_calibration;

/* Calibrates from the 24 patch means patch_rgb (encoded, as read) of a
 * photo under light.  clipped_or_null: 24 flags (true: leave the patch out,
 * e.g. some of its pixels were saturated).  refl: the 24 reflectances in
 * chart order with the neutrals at 19-24, or NULL for the built-in BabelColor
 * chart.  grid: n strictly increasing wavelengths (n >= 5), or NULL for the
 * default 400-700 nm / 10 nm (n ignored).  opt NULL: defaults.  out is
 * filled only on success (free with vr_calibration_free).
 * VR_E_ARG, naming the channel or patch: a NULL or non-finite input, a bad
 * grid or option, a light without power on the grid; fewer than 3 usable
 * patches in a channel, or (auto tone) fewer than 3 usable neutrals; a
 * channel whose brightest usable patch is below 0.02 (the light has almost
 * no power where that channel responds).  VR_E_NUMERIC if LAPACK fails or
 * green comes out zero; VR_E_NOMEM. */
vr_status vr_calibrate_camera(const double patch_rgb[][3], const bool *clipped_or_null,
                              const vr_spectrum *light, const vr_spectrum *const *refl, size_t n,
                              const double *grid, const vr_calibration_options *opt,
                              vr_calibration *out, vr_error *err);
void vr_calibration_free(vr_calibration *cal);

/* A camera material named name (kind camera): spectra r, g, b on the grid;
 * properties linearisation_r, _g, _b (text as vr_tone_format, value the
 * exponent for gamma curves), tone_rms_r/_g/_b, condition_number,
 * used_patches, clipped_patches; parameters lambda_r/_g/_b and dof_r/_g/_b;
 * provenance model "smooth NNLS, GCV (Kim-Gu rho 1.4), tone <r>/<g>/<b>" and
 * residual the largest channel RMS.  The caller adds the source, tool and
 * note. */
vr_status vr_calibration_to_material(const vr_calibration *cal, const char *name,
                                     vr_material **out, vr_error *err);

/* The linearisation stored in a camera material: present = false (and
 * VR_OK) when it has none (e.g. sensitivities imported from a data sheet);
 * VR_E_PARSE naming the material and property if one is unreadable. */
vr_status vr_calibration_tone_of(const vr_material *m, vr_tone tone[3], double gamma[3],
                                 bool *present, vr_error *err);

#ifdef __cplusplus
}
#endif
#endif
