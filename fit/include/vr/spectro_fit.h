/* n(λ), k(λ) of an uncoated pane from its spectrophotometry.
 *
 * 1. Point by point: at each wavelength the slab equations are inverted
 *    (vr/slab_invert.h): analytically at normal incidence, by least squares
 *    over all angles when several were measured.  Each point gets n, k,
 *    their standard errors from the photometric noise, and flags.
 *    A point is ill-conditioned (flagged, and left out of step 2) when the
 *    inversion has no root, or sigma_n > VR_SPECTRO_MAX_SIGMA_N, or
 *    (with angles) the n-k correlation condition exceeds 1e6.
 * 2. Smoothing: a dispersion model for n is fitted to the well-conditioned points, each weighted by
 *    1/sigma_n², through the least-squares layer (vr/lsq.h).  Its
 *    covariance gives the parameters' standard errors and sigma_n(λ) of the
 *    smoothed curve.  The covariance is scaled by the reduced chi-square
 *    when that exceeds 1 (the noise was underestimated), never shrunk.
 * 3. k: with n fixed to the smooth model, k is solved again at every
 *    wavelength from T alone (exact: T fixes the internal transmittance a
 *    once the face reflectance is known), which is the better-conditioned
 *    route for nearly transparent glass.
 *
 * Noise: sigma_T and sigma_R (absolute, default 1e-3, a good double-beam
 * UV-Vis-NIR instrument) set the weights and the reported uncertainties.
 *
 * 4. Verdict: whether the smooth n describes the data.  The smoothing's
 *    chi-square is taken again with the measurement's sigma: the larger of
 *    sigma_T and VR_SPECTRO_VERDICT_SIGMA, the photometric accuracy of a
 *    spectrophotometer (0.005, the tolerance LBNL Optics gives T + R; it is
 *    what the measurement vouches for, where sigma_T is its repeatability,
 *    and it covers the 3-decimal rounding and detector-change steps of real
 *    files).  The fit describes the data when that reduced chi-square is at
 *    most the upper VR_SPECTRO_VERDICT_P quantile of the chi-square
 *    distribution for its degrees of freedom, divided by them (1.24 for 366
 *    degrees of freedom).  Real uncoated glass passes (IGDB NFRC 102: 0.07;
 *    Pilkington Optifloat Clear, NFRC 9803: 0.5); a coated low-e pane, whose
 *    coating is no index of the glass, fails (Pilkington Energy Advantage,
 *    NFRC 9923: about 300). */
#ifndef VR_SPECTRO_FIT_H
#define VR_SPECTRO_FIT_H

#include <stdbool.h>
#include <stddef.h>
#include "vr/error.h"
#include "vr/material.h"
#include "vr/spectro_data.h"

#ifdef __cplusplus
extern "C" {
#endif

#define VR_SPECTRO_MAX_SIGMA_N 0.05
#define VR_SPECTRO_VERDICT_SIGMA 0.005  /* = VR_SPECTRO_TR_TOLERANCE */
#define VR_SPECTRO_VERDICT_P 0.001      /* upper tail of the chi-square test */

/* Models for n (λ and C in µm):
 *   sellmeier    n² = 1 + B1 λ²/(λ² - C1²) - D λ²           (B1, C1, D)
 *   sellmeier2   n² = 1 + Σ_{i=1,2} B_i λ²/(λ² - C_i²) - D λ²  (B1, C1, B2, C2, D)
 *   cauchy       n = A + B/λ² + C/λ⁴                         (A, B, C)
 * The - D λ² term is the tail of the infrared lattice absorption, the form
 * of the older Schott and Herzberger formulas; it stands for an infrared
 * Sellmeier pole far beyond the data, whose B and C alone the data could
 * not separate. */
typedef enum vr_nk_model { VR_NK_SELLMEIER = 0, VR_NK_SELLMEIER2, VR_NK_CAUCHY } vr_nk_model;
/* "sellmeier", "sellmeier2", "cauchy". */
vr_status vr_nk_model_parse(const char *text, vr_nk_model *out, vr_error *err);

typedef struct vr_spectro_fit_options {
  vr_nk_model model;
  double sigma_T, sigma_R;
} vr_spectro_fit_options;

vr_spectro_fit_options vr_spectro_fit_default_options(void);

typedef struct vr_spectro_point_fit {
  double nm, n, k, n_err, k_err; /* step 1 */
  int flags;                     /* VR_SLAB_* bits, plus VR_SPECTRO_ILL below */
  double n_model, n_model_err;   /* step 2 at this wavelength */
  double k_final;                /* step 3 */
} vr_spectro_point_fit;

enum { VR_SPECTRO_ILL = 64 };    /* ill-conditioned: excluded from the smoothing */

typedef struct vr_spectro_fit_result {
  size_t n;
  vr_spectro_point_fit *pt;
  size_t nill;                   /* ill-conditioned points */
  size_t nparams;
  vr_nk_model model;
  char names[6][8];              /* "B1", "C1", ... or "A", "B", "C" */
  char units[6][8];
  double value[6], stderr_[6];
  double covariance[36];         /* nparams x nparams, row-major */
  double chi2_reduced;           /* of the smoothing fit */
  double min_nm, max_nm;         /* of the data used */
  double thickness_nm;
  /* The verdict (step 4). */
  long dof;                      /* good points - parameters */
  double sigma_verdict;          /* the measurement's sigma used */
  double chi2_verdict;           /* reduced chi-square with it */
  double chi2_limit;             /* upper quantile / dof */
  bool describes;
  bool coated;                   /* Rf and Rb differ (VR_COATED_ASYMMETRY-like, 0.01) */
  char verdict[400];
} vr_spectro_fit_result;

/* Fits the normal-incidence or multi-angle curves of d (one state; the
 * curves must share their wavelengths) for a pane of thickness_nm. */
vr_status vr_spectro_fit(const vr_spectro_data *d, double thickness_nm,
                         const vr_spectro_fit_options *opt, vr_spectro_fit_result *out,
                         vr_error *err);
void vr_spectro_fit_free(vr_spectro_fit_result *r);

/* n of the smoothed model at nm, with its standard error (may be NULL). */
double vr_spectro_fit_n(const vr_spectro_fit_result *r, double nm, double *n_err);

/* A dielectric material: n as a refractiveindex.info formula (type 4 for
 * the Sellmeier forms, 5 for Cauchy) valid over the data's range, tabulated k (role
 * "k") and its standard error ("k_err"), the thickness (property, mm), the
 * fitted parameters with standard errors, and the verdict: properties
 * "fit_chi2_reduced" (with the measurement's sigma), "fit_chi2_limit",
 * "fit_describes" (1 or 0) and "fit_forced" (1 when forced, i.e. saved
 * although it does not describe the data), and the verdict's text in the
 * provenance note.  Provenance otherwise is the caller's. */
vr_status vr_spectro_fit_material(const vr_spectro_fit_result *r, const char *name, bool forced,
                                  vr_material **out, vr_error *err);

#ifdef __cplusplus
}
#endif
#endif
