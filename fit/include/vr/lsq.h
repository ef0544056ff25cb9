/* Non-linear least squares for the fitting tools: a small C API over Ceres
 * Solver (Levenberg-Marquardt, trust region), so that nothing else in the
 * project includes Ceres or C++.
 *
 * The problem: minimise 1/2 sum_i rho(f_i(p)^2) over the parameter vector p
 * (n values), with f the residual vector (m values) computed by a callback,
 * optional bounds per parameter, parameters held fixed, and an optional
 * robust loss rho.  The callback may supply the Jacobian (row-major m x n,
 * d f_i / d p_j) or leave it to central finite differences.
 *
 * After a solve, vr_lsq_covariance gives the covariance of the free
 * parameters, (J^T J)^-1 at the solution, optionally scaled by the reduced
 * chi-square sum f_i^2 / (m - n_free) (use that scaling when the residuals
 * are not already divided by trustworthy standard deviations).  Fixed
 * parameters get zero rows and columns.  A rank-deficient Jacobian is
 * reported (VR_E_NUMERIC), never hidden.
 *
 * A handle is not thread-safe; separate handles are independent.  The
 * callback is always called from the thread that called vr_lsq_solve or
 * vr_lsq_covariance, once per point (num_threads only spreads Ceres' own
 * linear algebra). */
#ifndef VR_LSQ_H
#define VR_LSQ_H

#include <stdbool.h>
#include <stddef.h>
#include "vr/error.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Fills residuals[m]; when jacobian is not NULL also fills jacobian[m * n]
 * (only asked for when the problem was created with analytic_jacobian).
 * Returns 0 on success, non-zero if the parameters are outside the model's
 * domain (the solver then backs off; a finite difference then uses the
 * other side).  Non-finite residuals count as a failure. */
typedef int (*vr_lsq_residual_fn)(const double *params, double *residuals, double *jacobian,
                                  void *user);

typedef enum vr_lsq_loss {
  VR_LOSS_NONE = 0,   /* plain least squares */
  VR_LOSS_HUBER,      /* rho(s) = s for s <= a^2, 2 a sqrt(s) - a^2 beyond */
  VR_LOSS_SOFT_L1,    /* rho(s) = 2 a^2 (sqrt(1 + s / a^2) - 1) */
  VR_LOSS_CAUCHY      /* rho(s) = a^2 log(1 + s / a^2) */
} vr_lsq_loss;

typedef struct vr_lsq_options {
  int max_iterations;          /* default 200 */
  double function_tolerance;   /* default 1e-12: relative change of the cost */
  double gradient_tolerance;   /* default 1e-12 */
  double parameter_tolerance;  /* default 1e-12: relative step */
  vr_lsq_loss loss;            /* default VR_LOSS_NONE */
  double loss_scale;           /* a in the formulas above; default 1 */
  int num_threads;             /* default 1 */
} vr_lsq_options;

/* The defaults above. */
vr_lsq_options vr_lsq_default_options(void);

typedef enum vr_lsq_termination {
  VR_LSQ_CONVERGED = 0,        /* a tolerance was met */
  VR_LSQ_NO_CONVERGENCE,       /* iteration limit reached */
  VR_LSQ_FAILURE               /* the callback failed or the solver gave up */
} vr_lsq_termination;

typedef struct vr_lsq_summary {
  vr_lsq_termination termination;
  int iterations;              /* Levenberg-Marquardt iterations, all rounds */
  int residual_evaluations;    /* calls of the callback, finite differences
                                  and the final chi2 included */
  double initial_cost;         /* 1/2 sum f^2 at the start (with the loss) */
  double final_cost;
  double chi2;                 /* sum f_i^2 at the solution (without the loss) */
  size_t free_parameters;
  double seconds;
  char message[256];           /* what the solver said about why it stopped */
} vr_lsq_summary;

typedef struct vr_lsq vr_lsq;

vr_lsq *vr_lsq_create(size_t nparams, size_t nresiduals, vr_lsq_residual_fn fn, void *user,
                      bool analytic_jacobian, vr_error *err);
void vr_lsq_destroy(vr_lsq *p);

/* Bounds (use -INFINITY / INFINITY for none), closed, with lower < upper
 * (hold a parameter with vr_lsq_set_fixed instead); the start value must
 * lie inside.  Errors name the parameter index.  A parameter that ends on
 * a bound with the cost pushing outwards is held there and the others are
 * solved again, so the rest of the solution is optimal given the bound;
 * the summary message then names it. */
vr_status vr_lsq_set_bounds(vr_lsq *p, size_t index, double lower, double upper, vr_error *err);
/* Holds parameter index at its start value. */
vr_status vr_lsq_set_fixed(vr_lsq *p, size_t index, bool fixed, vr_error *err);
/* Relative step for finite differences of this parameter, in (0, 1)
 * (default 1e-6).  The step is relative_step * max(|p|, 1e-3 |p_start|)
 * (1e-3 replacing |p_start| when the start is 0), central, and one-sided
 * within a step of a bound or where the callback fails on one side. */
vr_status vr_lsq_set_step(vr_lsq *p, size_t index, double relative_step, vr_error *err);
/* One-sided (forward) finite differences instead of central ones: half the
 * residual evaluations per Jacobian, O(h) instead of O(h^2) truncation error
 * (use a relative step near sqrt(machine epsilon), ~1e-8, with it).  The
 * covariance is always computed from central differences. */
vr_status vr_lsq_set_forward_differences(vr_lsq *p, bool forward, vr_error *err);

/* Solves in place: params holds the start on entry and the solution on
 * return (also on VR_LSQ_NO_CONVERGENCE, which is not an error).  options
 * may be NULL for the defaults.  VR_E_ARG for a start that is not finite,
 * outside its bounds or outside the callback's domain, or fewer residuals
 * than free parameters; VR_E_NUMERIC when the solver fails
 * (VR_LSQ_FAILURE), leaving params at the start.  The summary (may be
 * NULL) is filled in every case. */
vr_status vr_lsq_solve(vr_lsq *p, double *params, const vr_lsq_options *options,
                       vr_lsq_summary *summary, vr_error *err);

/* Covariance (n x n, row-major) of the parameters at params (normally the
 * solution).  scale_by_reduced_chi2: multiply by sum f^2 / (m - n_free)
 * (VR_E_ARG when m == n_free).  J is the plain Jacobian of the residuals,
 * also after a robust fit (the loss is not applied here); a parameter that
 * ended on a bound counts as free unless it is fixed.  VR_E_NUMERIC, with
 * the parameters at fault named, when the reciprocal condition number of
 * J^T J (columns scaled to unit norm, so units do not matter) is below
 * 1e-14, or when the callback fails at params. */
vr_status vr_lsq_covariance(vr_lsq *p, const double *params, bool scale_by_reduced_chi2,
                            double *covariance, vr_error *err);

#ifdef __cplusplus
}
#endif
#endif
