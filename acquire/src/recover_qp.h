/* The active-set solver for bounded least squares (recover_qp.c), which
 * the bounded and regularised methods and the camera calibration use to
 * impose their bounds. */
#ifndef VR_RECOVER_QP_H
#define VR_RECOVER_QP_H

#include <stddef.h>

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

#endif
