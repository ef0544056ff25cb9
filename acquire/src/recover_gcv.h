/* The generalised cross-validation solve in standard form, defined in
 * recover_regularised.c and shared with the camera calibration, which
 * solves the same smooth least squares on sensitivities. */
#ifndef VR_RECOVER_GCV_H
#define VR_RECOVER_GCV_H

#include <stddef.h>
#include "vr/error.h"

/* Least squares with a second-difference penalty, its weight from
 * generalised cross-validation (the standard-form method described in
 * recover_regularised.c):
 *
 *     minimise ||A x - c||^2 + lambda ||D2 x||^2,
 *
 * A (m x n) and c already weighted, no bounds.  lambda >= 0 fixes the weight;
 * < 0 chooses it by GCV with weight rho on trace H ((m - rho tr H)^2 in the
 * denominator; 1 classical, 1.4 Kim and Gu).  what names the caller in
 * messages. */
typedef struct vr_gcv_problem {
  size_t m, n;
  const double *a, *c;
  const double *lpinv, *nl; /* from vr_recover_smoothness */
  double rank_tol, rho, lambda;
  int rule;   /* vr_lambda_rule (AUTO reads GCV here) or VR_LAMBDA_PIXEL_RISK */
  double tau; /* discrepancy factor */
  const char *what;
} vr_gcv_problem;

/* A rule of vr_recover_gcv_solve beside the public ones: the lambda that
 * minimises the expected predictive risk of one pixel of unit noise whose
 * noise-free responses are c (vr_recover_pixel_lambda). */
#define VR_LAMBDA_PIXEL_RISK 100

typedef struct vr_gcv_result {
  double lambda; /* the weight used */
  double gcv;    /* the GCV score at lambda */
  double dof;    /* trace of the influence matrix at lambda */
  int flat;      /* GCV could not choose (fewer than two observations beyond the lines) */
} vr_gcv_result;

vr_status vr_recover_gcv_solve(const vr_gcv_problem *q, double *x, vr_gcv_result *res,
                               vr_error *err);

#endif
