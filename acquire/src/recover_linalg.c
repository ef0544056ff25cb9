/* Dense linear algebra over LAPACKE for the recovery and the camera
 * calibration (declared in recover_linalg.h): a thin SVD, the
 * pseudo-inverse built on it, and the second-difference smoothness
 * operator with its pseudo-inverse and null space. */
#include "recover_linalg.h"

#include <lapacke.h>
#include <stdlib.h>
#include <string.h>

int vr_recover_svd(size_t m, size_t n, const double *a, double *u, double *s, double *vt) {
  size_t q = m < n ? m : n;
  if (q == 0) return 0;
  double *copy = malloc(m * n * sizeof *copy);
  double *superb = malloc((q > 1 ? q : 2) * sizeof *superb);
  double *ub = u ? NULL : malloc(m * q * sizeof *ub);
  double *vb = vt ? NULL : malloc(q * n * sizeof *vb);
  int info = -1000;
  if (copy && superb && (u || ub) && (vt || vb)) {
    memcpy(copy, a, m * n * sizeof *copy);
    info = LAPACKE_dgesvd(LAPACK_ROW_MAJOR, u ? 'S' : 'N', vt ? 'S' : 'N', (lapack_int)m,
                          (lapack_int)n, copy, (lapack_int)n, s, u ? u : ub, (lapack_int)q,
                          vt ? vt : vb, (lapack_int)n, superb);
  }
  free(copy);
  free(superb);
  free(ub);
  free(vb);
  return info;
}

int vr_recover_pinv(size_t m, size_t n, const double *a, double tol, double ref, double *pinv,
                    size_t *rank) {
  size_t q = m < n ? m : n;
  memset(pinv, 0, n * m * sizeof *pinv);
  if (rank) *rank = 0;
  if (q == 0) return 0;
  double *u = malloc(m * q * sizeof *u), *s = malloc(q * sizeof *s), *vt = malloc(q * n * sizeof *vt);
  int info = -1000;
  if (u && s && vt) info = vr_recover_svd(m, n, a, u, s, vt);
  if (info == 0) {
    double cut = tol * (ref > 0.0 ? ref : s[0]);
    size_t k = 0;
    while (k < q && s[k] > cut) k++;
    /* pinv = V_k S_k^-1 U_k^T */
    for (size_t i = 0; i < k; i++) {
      double inv = 1.0 / s[i];
      for (size_t row = 0; row < n; row++) {
        double v = vt[i * n + row] * inv;
        if (v == 0.0) continue;
        for (size_t col = 0; col < m; col++) pinv[row * m + col] += v * u[col * q + i];
      }
    }
    if (rank) *rank = k;
  }
  free(u);
  free(s);
  free(vt);
  return info;
}

/* Second differences on the grid, scaled by the mean step squared so that
 * on a uniform grid each row is (1, -2, 1); on an uneven grid the rows are
 * the divided second differences 2/(h0(h0+h1)), -2/(h0 h1), 2/(h1(h0+h1)). */
static void second_differences(size_t n, const double *g, double *d2) {
  memset(d2, 0, (n - 2) * n * sizeof *d2);
  double hbar = (g[n - 1] - g[0]) / (double)(n - 1), h2 = hbar * hbar;
  for (size_t i = 0; i + 2 < n; i++) {
    double h0 = g[i + 1] - g[i], h1 = g[i + 2] - g[i + 1];
    d2[i * n + i] = h2 * 2.0 / (h0 * (h0 + h1));
    d2[i * n + i + 1] = -h2 * 2.0 / (h0 * h1);
    d2[i * n + i + 2] = h2 * 2.0 / (h1 * (h0 + h1));
  }
}

/* D2 = U S V^T (full V): D2^+ = V_p S^-1 U^T, null space = the last two
 * rows of V^T (the linear functions on the grid). */
int vr_recover_smoothness(size_t n, const double *grid, double *d2, double *lpinv, double *nl) {
  second_differences(n, grid, d2);
  size_t p = n - 2;
  double *u = malloc(p * p * sizeof *u), *sd = malloc(p * sizeof *sd),
         *vt = malloc(n * n * sizeof *vt), *copy = malloc(p * n * sizeof *copy),
         *superb = malloc((p > 1 ? p : 2) * sizeof *superb);
  int info = -1000;
  if (u && sd && vt && copy && superb) {
    memcpy(copy, d2, p * n * sizeof *copy);
    info = LAPACKE_dgesvd(LAPACK_ROW_MAJOR, 'A', 'A', (lapack_int)p, (lapack_int)n, copy,
                          (lapack_int)n, sd, u, (lapack_int)p, vt, (lapack_int)n, superb);
  }
  if (info == 0) {
    memset(lpinv, 0, n * p * sizeof *lpinv);
    for (size_t i = 0; i < p; i++)
      for (size_t row = 0; row < n; row++)
        for (size_t col = 0; col < p; col++)
          lpinv[row * p + col] += vt[i * n + row] / sd[i] * u[col * p + i];
    for (size_t row = 0; row < n; row++) {
      nl[row * 2] = vt[(n - 2) * n + row];
      nl[row * 2 + 1] = vt[(n - 1) * n + row];
    }
  }
  free(u);
  free(sd);
  free(vt);
  free(copy);
  free(superb);
  return info;
}
