/* Fitting a sample model to ellipsometry data: a global search over layer
 * thicknesses (so the periodicity of thickness cannot trap the fit), then
 * Levenberg-Marquardt on all free parameters, then uncertainties.
 *
 * Residuals are r = (Ψ_model - Ψ)/σΨ and (Δ_model - Δ)/σΔ with the Δ
 * difference wrapped into (-180°, 180°], and, when the file gives the
 * depolarisation and the model can produce some (a back side, thickness
 * non-uniformity, bandwidth), (dep_model - dep)/σdep in percent (σdep the
 * file's, else 1 %).  The reported figure of merit is Woollam's mean
 * squared error
 *     MSE = sqrt( Σ r² / (2N + D - M) ),
 * N the number of (Ψ, Δ) pairs, D the depolarisation values fitted, M the
 * number of free parameters.  CompleteEASE's MSE is also reported:
 *     MSE_NCS = 1000 sqrt( Σ [(N_m - N)² + (C_m - C)² + (S_m - S)²] / (3N - M) ),
 * on the file's N, C, S when it gives them (Film Sense), else on those of
 * its Ψ, Δ (and depolarisation).  Standard errors are sqrt(diag(C)) with
 * C = (JᵀJ)⁻¹ · Σ r² / (2N + D - M) (the covariance scaled by the reduced
 * chi-square, so wrong σ do not make them dishonest); 90 % limits are
 * value ± t(0.95, 2N + D - M) · stderr.
 *
 * Several samples (vr_ellipso_fit_samples): one model per data file, all
 * with the same parameter list; a free parameter marked per_sample takes
 * one value per sample (named "layer.thickness[2]" for the second), the
 * others are shared.  Each sample is judged on its own (vr_fit_judge); the
 * fit describes the data only if it describes every sample. */
#ifndef VR_ELLIPSO_FIT_H
#define VR_ELLIPSO_FIT_H

#include <stdbool.h>
#include <stddef.h>
#include "vr/ellipso_data.h"
#include "vr/ellipso_model.h"
#include "vr/lsq.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum vr_fit_residual {
  VR_RESID_PSI_DELTA = 0, /* (Ψ_m - Ψ)/σΨ and wrapped (Δ_m - Δ)/σΔ, in degrees */
  VR_RESID_RHO            /* Re and Im of ρ_m - ρ, unweighted (as pyElli's examples fit) */
} vr_fit_residual;

typedef struct vr_fit_options {
  int grid_points;        /* per free thickness in the global search (default: from the data) */
  int grid_wavelengths;   /* wavelengths kept for the search (default 60) */
  int candidates;         /* grid minima refined by LM (default 3) */
  int max_iterations;     /* LM iterations (default 200) */
  bool global_search;     /* default true */
  vr_fit_residual residual; /* default VR_RESID_PSI_DELTA */
  bool fit_depolarisation;  /* default true: fit it where the file gives it and the model can produce it */
} vr_fit_options;

vr_fit_options vr_fit_default_options(void);

/* One sample of a fit: its data file, its points' place in the result's
 * per-point arrays, its χ² and MSE (over its own Ψ, Δ, no parameter count) and
 * verdict figures. */
typedef struct vr_fit_sample {
  const char *source;     /* borrowed from the data set */
  size_t first, npoints;
  double chi2;            /* Σ of its Ψ, Δ residuals squared */
  double mse, misfit_ratio, noise_psi, noise_delta;
  bool describes;
} vr_fit_sample;

typedef struct vr_fit_result {
  size_t nfree;
  char **names;           /* nfree parameter names */
  double *value, *stderr_, *ci_lo, *ci_hi;
  double *correlation;    /* nfree x nfree, row-major; NAN when undetermined */
  /* -1 / +1: the parameter ended at its lower / upper bound (within 1e-9
   * of the range, or 1e-12 absolute); its stderr and limits are then NAN,
   * since a pinned value is not a free estimate.  0 otherwise. */
  int *at_bound;
  bool covariance_ok;     /* false: the Jacobian is rank deficient (message says why) */
  char covariance_message[256];
  double mse;             /* Woollam's MSE */
  double mse_ncs;         /* CompleteEASE's N, C, S MSE (x 1000); NAN when 3N <= M */
  bool ncs_from_file;     /* mse_ncs used the file's own N, C, S */
  double chi2;            /* Σ r² */
  size_t npoints;         /* N (Ψ, Δ pairs), over all samples */
  size_t ndepol;          /* D: depolarisation values fitted (0: not fitted) */
  int dof;                /* 2N + D - M */
  /* Per data point at the solution, the samples' points one after the
   * other: Ψ, Δ (degrees), depolarisation (0..1). */
  double *psi_model, *delta_model, *depol_model;
  size_t nsamples;
  vr_fit_sample *samples;
  vr_lsq_summary summary;  /* iterations and evaluations summed over all candidate fits */
  int grid_evaluations;
  double seconds;
  /* The verdict (vr_fit_judge): the noise the data show (degrees, per
   * vr_ellipso_noise), the rms residual in units of that noise, and
   * whether the model describes the data (ratio <= VR_FIT_MAX_MISFIT and
   * no free parameter pinned at a bound, vr_fit_judge_bounds). */
  double noise_psi, noise_delta, misfit_ratio;
  bool describes;
  char verdict[640];
  /* Set by vr_ellipso_fit_bulk when no smooth dispersion described the
   * data and n, k come from the exact inversion point by point. */
  bool exact_inversion;
} vr_fit_result;

/* A fit whose rms residual exceeds this many times the data's noise does
 * not describe the data (flagged; vr-ellipso exits 1 and saves only with
 * --force). */
#define VR_FIT_MAX_MISFIT 10.0
/* The noise of Ψ and Δ (degrees) as the data show it: the median absolute
 * third difference along wavelength of each angle's series over
 * 0.6745 sqrt(20) (white noise of standard deviation s gives normal third
 * differences of variance 20 s², whose median magnitude is 0.6745 of
 * their deviation; a smooth spectrum contributes little, and the median
 * ignores the few large differences of a sharp feature or a table's
 * kinks).  Series of fewer than 8
 * wavelengths say nothing; when none says anything the file's σ (median)
 * is used, and when the file gives none, 0.05° (a typical instrument).
 * Never below 0.001°. */
void vr_ellipso_noise(const vr_ellipso_data *d, double *psi_deg, double *delta_deg);
/* Fills r's verdict from its model values against d (limit: the largest
 * misfit ratio that still describes the data). */
void vr_fit_judge(vr_fit_result *r, const vr_ellipso_data *d, double limit);
/* A fit with a free parameter pinned at one of its bounds (r->at_bound) is
 * not a fit of that parameter, whatever its misfit: describes becomes
 * false and the verdict names the parameters and bounds before the misfit
 * figures.  Called by the fits after vr_fit_judge; a no-op without
 * pinned parameters. */
void vr_fit_judge_bounds(vr_fit_result *r);
/* The result of a model with no free parameters (chi2, MSE, model values,
 * verdict). */
vr_status vr_ellipso_evaluate(const vr_sample_model *m, const vr_ellipso_data *d, vr_fit_result *out,
                              vr_error *err);

/* The exact pseudo-optical constants of a bare substrate from one point,
 * with standard deviations propagated from σΨ and σΔ (central differences
 * of the inversion; at Ψ = 0° or 90° one-sided). */
void vr_pseudo_index(const vr_ellipso_point *p, double *n, double *k, double *sigma_n, double *sigma_k);

/* Fits m (its free parameters) to d; m holds the solution on return. */
vr_status vr_ellipso_fit(vr_sample_model *m, const vr_ellipso_data *d, const vr_fit_options *opt,
                         vr_fit_result *out, vr_error *err);
/* Fits ns samples at once: models[s] (copies of one model, with their own
 * start values) to data[s]; every model holds the solution on return. */
vr_status vr_ellipso_fit_samples(vr_sample_model *const *models, const vr_ellipso_data *data, size_t ns,
                                 const vr_fit_options *opt, vr_fit_result *out, vr_error *err);
void vr_fit_result_free(vr_fit_result *r);

/* Pseudo-optical constants of a bulk sample from one (Ψ, Δ) pair:
 * <ε> = sin²θ [1 + tan²θ ((1 - ρ)/(1 + ρ))²]. */
vr_complex vr_pseudo_epsilon(double psi_deg, double delta_deg, double aoi_deg);

/* Without a model: per-wavelength inversion of a bulk sample, then an
 * automatic dispersion fit (Cauchy with an Urbach tail when the pseudo k
 * stays below 0.05, else a Kramers-Kronig consistent B-spline ε2).  Returns
 * the fitted bulk model in *model_out. */
vr_status vr_ellipso_fit_bulk(const vr_ellipso_data *d, const vr_fit_options *opt,
                              vr_sample_model **model_out, vr_fit_result *out, vr_error *err);

#ifdef __cplusplus
}
#endif
#endif
