/* The tint-state model of chromogenic glazing (DESIGN §4), as stored in a
 * material of kind "chromogenic", for every tool that reads one (vr-spectro
 * writes it, vr-render evaluates it).
 *
 * State s in [0, 1], 0 bleached, 1 fully coloured.  Optical density is
 * linear in the concentration of colour centres, hence in s:
 *     T(λ, s)  = T0(λ) · 10^(-s · dOD(λ))          (Beer-Lambert)
 *     Rf(λ, s) = Rf0(λ) + s · dRf(λ),  Rb likewise  (first order in s)
 * Roles: "T0", "Rf0", "Rb0", "dOD", "dRf", "dRb" (the R roles optional).
 * Property "chromogenic_type": "electrochromic" or "photochromic";
 * property "thickness" (mm) when known.
 *
 * Electrochromic: s = Q / Q_full, Q the inserted charge density; parameter
 * "Q_full" (mC/cm²).  The coloration efficiency is
 * eta(λ) = dOD(λ) / Q_full, in cm²/C after the unit change (role "eta").
 * Photochromic: ds/dt = a E (1 - s) - b(T) s, E the UV irradiance (W/m²),
 * b(T) = b_ref exp(-(Ea / R) (1/T - 1/T_ref)) (Arrhenius); parameters "a"
 * (m²/(W s)), "b_ref" (1/s), "Ea" (J/mol), "T_ref" (K); or, when only
 * steady states were measured, "K_ref" = b_ref / a (W/m²) without a, b_ref.
 * Steady state: s = a E / (a E + b(T)) = E / (E + K(T)).
 * Fitted domain (parameters written by vr-spectro's fit): "E_fit_max"
 * (W/m², the largest UV irradiance of the states; 0 to it is the range),
 * "T_fit_min", "T_fit_max" (K).  A model without them (older databases)
 * has no stated domain. */
#ifndef VR_CHROMOGENIC_H
#define VR_CHROMOGENIC_H

#include "vr/material.h"

#ifdef __cplusplus
extern "C" {
#endif

#define VR_GAS_CONSTANT 8.314462618 /* J/(mol K), CODATA 2018 (exact) */

typedef enum vr_chromo_type { VR_CHROMO_ELECTRO = 0, VR_CHROMO_PHOTO = 1 } vr_chromo_type;

/* Type of a chromogenic material; VR_E_ARG for other kinds or a missing
 * or unknown "chromogenic_type". */
vr_status vr_chromo_type_of(const vr_material *m, vr_chromo_type *type, vr_error *err);

/* T, Rf, Rb (any may be NULL) at state s in [0, 1] and wavelength nm.
 * VR_E_RANGE for s outside [0, 1] or nm outside the tables (no
 * extrapolation); Rf, Rb are NAN when not stored. */
vr_status vr_chromo_eval(const vr_material *m, double s, double nm, double *T, double *Rf,
                         double *Rb, vr_error *err);

/* Electrochromic: the state of a charge density (mC/cm²), clamped to [0, 1]. */
vr_status vr_chromo_state_of_charge(const vr_material *m, double q_mC_cm2, double *s,
                                    vr_error *err);

/* Flags of the photochromic evaluations: without VR_CHROMO_EXTRAPOLATE a
 * UV irradiance above E_fit_max or a temperature more than
 * VR_CHROMO_T_SLACK_K outside [T_fit_min, T_fit_max] is VR_E_RANGE, the
 * message naming the material, the value and the fitted range.  (A model
 * fitted at one temperature has no activation energy: any other
 * temperature is an extrapolation.) */
#define VR_CHROMO_EXTRAPOLATE 1u
/* The UV irradiance is a Monte Carlo estimate (a render's UV pass, an
 * annual study's sampled coefficients): up to VR_CHROMO_E_SLACK above
 * E_fit_max is the estimate's noise, not a state outside the domain. */
#define VR_CHROMO_ESTIMATE 2u
#define VR_CHROMO_E_SLACK 0.05
#define VR_CHROMO_T_SLACK_K 0.5 /* rounding of "25C" and the like */

/* Whether (E_uv, T_K) lies in the fitted domain (flags: VR_CHROMO_ESTIMATE
 * or 0); VR_OK also for a model with no stated domain. */
vr_status vr_chromo_check_domain(const vr_material *m, double E_uv, double T_K, unsigned flags,
                                 vr_error *err);

/* Photochromic steady state under UV irradiance E (W/m², >= 0) at T_K
 * (kelvin, > 0), inside the fitted domain unless flags say extrapolate. */
vr_status vr_chromo_steady_state(const vr_material *m, double E_uv, double T_K, unsigned flags,
                                 double *s, vr_error *err);

/* Photochromic state after t seconds at constant E and T from state s0:
 * s(t) = s_ss + (s0 - s_ss) exp(-(a E + b) t).  Needs a and b_ref
 * (VR_E_NOT_FOUND when the material only knows K_ref); the domain and
 * flags as above. */
vr_status vr_chromo_state_after(const vr_material *m, double E_uv, double T_K, unsigned flags,
                                double s0, double t_s, double *s, vr_error *err);

#ifdef __cplusplus
}
#endif
#endif
