/* Fitting the tint-state model of chromogenic glazing (vr/chromogenic.h)
 * to transmittance (and reflectance) spectra measured at several states.
 *
 * States are written as tokens, one per spectrum:
 *   electrochromic   "12.5" or "12.5mC/cm2"  inserted charge density
 *                    "-1.2V"                 a voltage (a label: the state
 *                                            is then estimated from the data)
 *   photochromic     "E=40[:T=25C]"          steady state under 40 W/m² UV
 *                    "t=60:E=40[:T=298K]"    60 s of UV from the bleached state
 *                    "fade=120:E=40[:T=..]"  120 s of dark after the steady
 *                                            state under E
 * T defaults to 298.15 K; "C" or "K" suffixes, a bare number is kelvin.
 *
 * Optical density OD = -log10 T is linear in the state:
 *   OD_ij = OD0_j + s_i dOD_j  (i spectrum, j wavelength),
 * fitted by weighted least squares with sigma_OD = sigma_T / (T ln 10).
 * Electrochromic with charges: s_i = Q_i / Q_max; per wavelength a straight
 * line, eta_j = dOD_j / Q_max the coloration efficiency.  With voltages: the
 * palest spectrum is s = 0, the darkest s = 1, the others are projected on
 * the difference (a rank-one model).
 * Photochromic: s_i(a, b_ref, Ea) from ds/dt = a E (1 - s) - b(T) s; the
 * rates are found by variable projection (for given rates, OD0 and dOD are
 * the linear least-squares solution at each wavelength; Levenberg-Marquardt
 * through vr/lsq.h on ln a, ln b_ref and Ea).  Steady states alone fix only
 * K = b/a (a is then held, and the result reports K_ref); one temperature
 * alone holds Ea at 0.
 * Uncertainties: the covariance scaled by the pooled reduced chi-square over
 * all wavelengths; 90 % limits with Student's t on those degrees of freedom. */
#ifndef VR_CHROMOGENIC_FIT_H
#define VR_CHROMOGENIC_FIT_H

#include <stdbool.h>
#include <stddef.h>
#include "vr/chromogenic.h"
#include "vr/error.h"
#include "vr/material.h"
#include "vr/spectrum.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum vr_state_kind {
  VR_STATE_CHARGE = 0,
  VR_STATE_VOLTAGE,
  VR_STATE_STEADY,
  VR_STATE_ACTIVATION,
  VR_STATE_FADE
} vr_state_kind;

typedef struct vr_chromo_state {
  vr_state_kind kind;
  double q;      /* mC/cm² (charge) or V (voltage) */
  double E;      /* W/m² UV */
  double T_K;    /* kelvin */
  double t;      /* seconds */
  char label[64];
} vr_chromo_state;

/* One token; errors quote it. */
vr_status vr_chromo_state_parse(const char *token, vr_chromo_state *out, vr_error *err);
/* A comma-separated list (malloc'ed array in *out). */
vr_status vr_chromo_states_parse(const char *list, vr_chromo_state **out, size_t *count,
                                 vr_error *err);

typedef struct vr_chromo_param {
  char name[8];
  char unit[12];
  double value, stderr_, ci90;  /* ci90: half-width of the 90 % interval */
  bool fitted;                  /* false: held (not identifiable from these data) */
} vr_chromo_param;

typedef struct vr_chromo_fit_result {
  vr_chromo_type type;
  size_t nl, ns;                /* wavelengths, spectra */
  double *nm, *T0, *dOD, *dOD_err, *dOD_ci90;
  double *Rf0, *dRf, *Rb0, *dRb; /* NULL when not measured */
  double *s;                    /* per spectrum: the state used or fitted */
  double q_full;                /* electrochromic with charges, else NAN */
  /* Photochromic: the UV irradiances (W/m2, from 0) and temperatures (K)
   * the states span; the model is stored with them and refuses to be
   * evaluated outside unless told to extrapolate.  NAN otherwise. */
  double E_fit_max, T_fit_min, T_fit_max;
  size_t nparams;               /* photochromic: a, b_ref, Ea, K_ref */
  vr_chromo_param params[4];
  double chi2_reduced;
  long dof;
} vr_chromo_fit_result;

/* spectra: ns transmittance spectra (Rf, Rb arrays may be NULL, or hold
 * NULL entries when not measured), all resampled onto the first one's grid
 * (each must cover it: VR_E_RANGE naming the spectrum).  sigma_T: the
 * photometric noise (> 0).  All states must be of one family (charge or
 * voltage; or photochromic kinds), VR_E_ARG otherwise. */
vr_status vr_chromo_fit(size_t ns, const vr_chromo_state *states, const vr_spectrum *const *T,
                        const vr_spectrum *const *Rf, const vr_spectrum *const *Rb,
                        double sigma_T, vr_chromo_fit_result *out, vr_error *err);
void vr_chromo_fit_free(vr_chromo_fit_result *r);

/* The chromogenic material of a fit (roles T0, dOD, dOD_err, eta, Rf0,
 * dRf, Rb0, dRb; parameters with standard errors). */
vr_status vr_chromo_fit_material(const vr_chromo_fit_result *r, const char *name,
                                 double thickness_mm, vr_material **out, vr_error *err);

#ifdef __cplusplus
}
#endif
#endif
