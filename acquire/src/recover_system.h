/* The recovery system's layout (built in recover.c, read by the methods
 * and by recover_pixel.c) and the methods that solve on it.  Kept apart
 * from the solvers' headers (recover_linalg.h, recover_qp.h, recover_gcv.h)
 * so that they, and the camera calibration, need not see it. */
#ifndef VR_RECOVER_SYSTEM_H
#define VR_RECOVER_SYSTEM_H

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
