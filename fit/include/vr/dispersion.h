/* Dispersion models: the complex refractive index N(λ) = n + i k (or the
 * dielectric function ε = N²) of one material as a function of wavelength,
 * from a handful of parameters that a fit can adjust.
 *
 * Every model is a flat vector of named parameters (for the fitter), plus
 * fixed structure (the kind and the number of terms).  Wavelengths are nm;
 * photon energies E = 1239.84198 / λ[nm] in eV.  Oscillator energies and
 * widths are in eV, Cauchy and Sellmeier coefficients in micrometre units as
 * the literature gives them.
 *
 * Kinds and their parameters, in order:
 *   constant       n, k
 *   cauchy         A, B [µm²], C [µm⁴], k_amp, k_exp [1/eV], band_edge [eV]
 *                  n = A + B/λ² + C/λ⁴ (λ in µm);
 *                  k = k_amp exp(k_exp (E - band_edge)) (Urbach tail; k_amp = 0 for none)
 *                  (parameter names "A", "B", "C", "k_amp", "k_exp", "band_edge")
 *   sellmeier      A, then B_i, C_i [µm] per term:   n² = A + Σ B_i λ² / (λ² - C_i²)
 *                  (names "A", "B1", "C1", "B2", ...; the same for sellmeier2)
 *   sellmeier2     A, then B_i, C_i [µm²] per term:  n² = A + Σ B_i λ² / (λ² - C_i)
 *   genosc         eps_inf, then per term its parameters (a sum of terms
 *                  added to ε): each term is one of
 *     lorentz        Amp, En [eV], Br [eV]:  Amp En Br / (En² - E² - i Br E)
 *     drude          Amp [eV²] (plasma energy squared), Br [eV]:  -Amp / (E² + i Br E)
 *     tauc_lorentz   Amp, En, C, Eg (Jellison and Modine, APL 69, 371 (1996);
 *                    ε2 from the product of Tauc gap and Lorentz oscillator,
 *                    ε1 from its closed-form Kramers-Kronig transform)
 *     cody_lorentz   Amp, En, Br, Eg, Ep, Et, Eu (Ferlauto et al., JAP 92, 2424
 *                    (2002)); ε1 by numerical Kramers-Kronig integration
 *     gaussian       Amp, En, Br (Br the full width at half maximum); ε1 in
 *                    closed form with the Dawson function (Kramers-Kronig consistent)
 *   bspline        eps_inf, then ε2 at each knot ("eps2_1", ...): ε2 is the
 *                  cubic spline through those values with not-a-knot ends (a
 *                  cubic B-spline on the knot grid), 0 outside the knots; ε1
 *                  from numerical Kramers-Kronig.  Unless the end values are 0,
 *                  ε2 steps there and ε1 is logarithmically infinite at the end
 *                  knots (VR_E_NUMERIC exactly on them): keep the end knots
 *                  beyond the data or hold their values at 0
 *   tabulated      no parameters: n(λ), k(λ) from tables (material database),
 *                  monotone cubic interpolation, VR_E_RANGE outside the tables
 *
 * genosc terms are numbered from 1 in parameter names ("Amp1", "En1", "C1",
 * "Eg1", "Amp2", ...).  A new term starts at typical values: lorentz 1, 5, 1;
 * drude 1, 0.1; tauc_lorentz 20, 1.5, 1, 1; cody_lorentz 100, 3.6, 2.4, 1.6,
 * 0.8, 1.8, 0.05; gaussian 1, 1, 1.  Every term parameter must be >= 0
 * (Tauc-Lorentz En and C, Cody-Lorentz En and Br > 0); evaluation fails with
 * VR_E_RANGE naming the parameter otherwise.  Br = 0 is allowed where the
 * term has a finite limit (Lorentz and Gaussian vanish, Drude becomes
 * -Amp/E²).  Tauc-Lorentz with C >= 2 En (overdamped, no real closed form)
 * takes ε1 from numerical Kramers-Kronig.
 *
 * The genosc form follows Woollam's "general oscillator" layer: a Tauc-
 * Lorentz film is a genosc with one tauc_lorentz term.  Multi-oscillator
 * Tauc-Lorentz in refellips and in Jellison's papers shares one Eg; here each
 * term has its own Eg (set them equal, or tie them, for that form). */
#ifndef VR_DISPERSION_H
#define VR_DISPERSION_H

#include <stddef.h>
#include "vr/error.h"
#include "vr/optics.h"
#include "vr/spectrum.h"

#ifdef __cplusplus
extern "C" {
#endif

#define VR_HC_EV_NM 1239.84198

typedef enum vr_disp_kind {
  VR_DISP_CONSTANT = 0,
  VR_DISP_CAUCHY,
  VR_DISP_SELLMEIER,
  VR_DISP_SELLMEIER2,
  VR_DISP_GENOSC,
  VR_DISP_BSPLINE,
  VR_DISP_TABULATED
} vr_disp_kind;

typedef enum vr_osc_kind {
  VR_OSC_LORENTZ = 0,
  VR_OSC_DRUDE,
  VR_OSC_TAUC_LORENTZ,
  VR_OSC_CODY_LORENTZ,
  VR_OSC_GAUSSIAN
} vr_osc_kind;

typedef struct vr_dispersion vr_dispersion;

/* A model of the given kind with its parameters at neutral defaults
 * (constant: n = 1, k = 0; cauchy: A = 1.5, others 0; sellmeier and
 * sellmeier2: A = 1, no terms; genosc and bspline: eps_inf = 1, no terms or
 * knots).  Tabulated models come from vr_dispersion_tabulated (VR_E_ARG here). */
vr_dispersion *vr_dispersion_create(vr_disp_kind kind, vr_error *err);
/* Sellmeier: adds one (B, C) = (0, 0) term (osc is ignored).  genosc: adds
 * one oscillator term.  VR_E_ARG for other kinds. */
vr_status vr_dispersion_add_term(vr_dispersion *d, vr_osc_kind osc, vr_error *err);
/* B-spline: sets the knot energies (eV, > 0, strictly increasing, >= 4
 * knots); the ε2 values at the knots become parameters, reset to 0
 * (eps_inf is kept). */
vr_status vr_dispersion_set_knots(vr_dispersion *d, size_t n, const double *energies_ev,
                                  vr_error *err);
/* Tabulated from n and k spectra (copied); k may be NULL (k = 0). */
vr_dispersion *vr_dispersion_tabulated(const vr_spectrum *n, const vr_spectrum *k, vr_error *err);
vr_dispersion *vr_dispersion_copy(const vr_dispersion *d, vr_error *err);
void vr_dispersion_destroy(vr_dispersion *d);

vr_disp_kind vr_dispersion_kind(const vr_dispersion *d);
size_t vr_dispersion_nparams(const vr_dispersion *d);
/* Parameter names: "A", "B", "eps_inf", "Amp1", "En1", "Br1", "Eg1", ... */
const char *vr_dispersion_param_name(const vr_dispersion *d, size_t i);
/* Index of a named parameter, or -1. */
long vr_dispersion_param_index(const vr_dispersion *d, const char *name);
/* The parameter vector, read and write. */
double *vr_dispersion_params(vr_dispersion *d);
const double *vr_dispersion_params_const(const vr_dispersion *d);

/* ε and N at a wavelength.  Domain errors (a Sellmeier pole: VR_E_NUMERIC;
 * Sellmeier n² <= 0 or Cauchy n <= 0, a tabulated wavelength outside the
 * table: VR_E_RANGE) name the model and the wavelength; a parameter outside
 * its domain (negative k, k_amp or oscillator parameter) gives VR_E_RANGE
 * naming the parameter.  Thread-safe: evaluation only reads the model. */
vr_status vr_dispersion_eps(const vr_dispersion *d, double nm, vr_complex *eps, vr_error *err);
vr_status vr_dispersion_index(const vr_dispersion *d, double nm, vr_complex *N, vr_error *err);

/* N = √ε, principal branch: n >= 0, and k >= 0 whenever Im ε >= 0 (a zero
 * imaginary part counts as +0, so ε = -4 - 0i gives 2i).  A gain medium
 * (Im ε < 0) keeps n >= 0 and gets k < 0. */
vr_complex vr_eps_to_index(vr_complex eps);

/* Effective-medium approximations for a mixture with volume fraction f of
 * component b in a.  Bruggeman: the root of f (eb - e)/(eb + 2e) + (1-f)
 * (ea - e)/(ea + 2e) = 0 with Im e >= 0; when both roots qualify (lossless
 * components), the one that tends to ea as f -> 0.  Exactly ea at f = 0 and
 * eb at f = 1.  Maxwell-Garnett: inclusions b in host a.  Both return NaN
 * for f outside [0, 1]. */
vr_complex vr_ema_bruggeman(vr_complex eps_a, vr_complex eps_b, double f);
vr_complex vr_ema_maxwell_garnett(vr_complex eps_host, vr_complex eps_incl, double f);

#ifdef __cplusplus
}
#endif
#endif
