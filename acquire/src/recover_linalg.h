/* Dense linear algebra over LAPACKE that the recovery methods and the
 * camera calibration share (recover_linalg.c): a thin SVD, a pseudo-inverse
 * and the second-difference smoothness operator.  It depends on no other
 * part of the recovery, so everything else can build on it. */
#ifndef VR_RECOVER_LINALG_H
#define VR_RECOVER_LINALG_H

#include <stddef.h>

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

#endif
