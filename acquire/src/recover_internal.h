/* Internals of the spectral recovery: the system's layout, the small dense
 * linear-algebra helpers over LAPACKE, and the active-set solver shared by
 * the bounded and regularised methods. */
#ifndef VR_RECOVER_INTERNAL_H
#define VR_RECOVER_INTERNAL_H

#include <stddef.h>
#include "vr/recover.h"

struct vr_recovery_system {
  size_t n;          /* samples N */
  size_t m;          /* rows 3L */
  size_t lights;     /* L */
  double *grid;      /* N wavelengths, nm */
  double *a;         /* m x n, exposures included */
  double *an;        /* m x n, each light's block divided by its exposure */
  double *rowscale;  /* m: the exposure of the row's light */
  double *sv;        /* min(m, n) singular values of an, descending */
  size_t nsv, rank;
  double cond;
  double *p;         /* n x m pseudo-inverse of a (through an) */
  double *d2;        /* (n-2) x n second differences */
  double *lpinv;     /* n x (n-2) pseudo-inverse of d2 */
  double *nl;        /* n x 2 orthonormal basis of d2's null space */
  vr_recovery_options opt;
};

/* Thin SVD of the m x n row-major matrix a (left untouched): u is m x q
 * (row-major, q columns), s has q values, vt is q x n, q = min(m, n); u or
 * vt may be NULL when not wanted.  Returns 0, LAPACK's info, or -1000 when
 * out of memory. */
int vr_recover_svd(size_t m, size_t n, const double *a, double *u, double *s, double *vt);

/* The m x n row-major pseudo-inverse pinv (n x m) of a, singular values
 * below tol * ref dropped (ref <= 0: the largest of a's own); rank receives
 * how many were kept.  Same returns as vr_recover_svd. */
int vr_recover_pinv(size_t m, size_t n, const double *a, double tol, double ref, double *pinv,
                    size_t *rank);

/* The smoothness operator on a strictly increasing grid of n >= 3
 * wavelengths: d2 ((n-2) x n) the second differences (scaled by the mean
 * step squared, so (1, -2, 1) on a uniform grid), lpinv (n x (n-2)) its
 * pseudo-inverse and nl (n x 2) an orthonormal basis of its null space (the
 * straight lines).  Same returns as vr_recover_svd. */
int vr_recover_smoothness(size_t n, const double *grid, double *d2, double *lpinv, double *nl);

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

/* The bounded least-squares problem solved by an active set:
 *
 *     minimise ||G x - h||^2  subject to  E x = e,  lo <= x <= hi
 *
 * from a start x that satisfies the bounds.  Variables at a bound are fixed
 * there (the working set); each step solves the problem on the free
 * variables with the equalities (LAPACKE_dgglse, after the equalities have
 * been reduced to orthonormal rows through an SVD so that dependent rows,
 * e.g. two identical lights, cannot make it singular; LAPACKE_dgelsd for
 * the minimum-norm step when there are no equalities).  A step is cut at the
 * first bound it meets, which then joins the working set; at the minimum of
 * a working set the bound multipliers are computed from the gradient, and
 * the variable with the most wrongly signed one is released.  It stops when
 * every multiplier has the right sign (the KKT point of this convex problem)
 * or after max_iter steps. */
typedef struct vr_rqp {
  size_t n;              /* variables */
  size_t mg;             /* rows of G */
  const double *g, *h;   /* mg x n, mg */
  size_t me;             /* equality rows (0: none) */
  const double *e, *ev;  /* me x n, me */
  const double *lo, *hi; /* n bounds, +-INFINITY allowed */
  double rank_tol;       /* relative threshold for the equalities' singular values */
  double e_ref;          /* ... relative to this (the largest of the full E) */
  int max_iter;
} vr_rqp;

typedef enum vr_rqp_result {
  VR_RQP_OK = 0,
  VR_RQP_MAX_ITER = 1,
  VR_RQP_NOMEM = -1,
  VR_RQP_LAPACK = -2
} vr_rqp_result;

vr_rqp_result vr_recover_rqp(const vr_rqp *q, double *x, int *iterations);

/* The methods, each on validated input. */
vr_status vr_recover_matrix_r(const vr_recovery_system *s, const double *c,
                              const unsigned char *clipped, double *r, vr_recover_info *info,
                              vr_error *err);
vr_status vr_recover_bounded(const vr_recovery_system *s, const double *c,
                             const unsigned char *clipped, double *r, vr_recover_info *info,
                             vr_error *err);
/* sigma: the noise standard deviation of each observation (units of c),
 * or NULL for the system's noise model. */
vr_status vr_recover_regularised(const vr_recovery_system *s, const double *c,
                                 const double *sigma, const unsigned char *clipped, double *r,
                                 vr_recover_info *info, vr_error *err);

/* Slack direction of a clipped observation: row A_i r + sign * s_i = c_i with
 * s_i >= 0 reads A_i r >= c_i for VR_CLIP_HIGH (sign -1) and A_i r <= c_i
 * for VR_CLIP_LOW (sign +1). */
static inline double vr_recover_slack_sign(unsigned char mark) {
  return mark == VR_CLIP_HIGH ? -1.0 : 1.0;
}

/* The 99.9 % point of chi-squared with k degrees of freedom (Wilson and
 * Hilferty's approximation); 0 for k = 0. */
double vr_recover_chi2_limit(size_t k);

/* Fills info's residuals and clip violation for the result r, and with
 * sigma (NULL: NAN) its chi2 over the unclipped rows and chi2_limit for
 * info->used of them. */
void vr_recover_finish_info(const vr_recovery_system *s, const double *c, const double *sigma,
                            const unsigned char *clipped, const double *r, vr_recover_info *info);

#endif
