/* Inverting the thick-slab equations: from the measured transmittance T and
 * reflectance R of an uncoated pane of known thickness d, the complex index
 * N = n + i k of its material, so that its behaviour at any angle and
 * polarisation follows from Fresnel's equations (vr_slab in vr/optics.h).
 *
 * Normal incidence, a pane in air, all internal reflections summed in power:
 *     T = (1 - r)^2 a / (1 - r^2 a^2),   R = r (1 + a T),
 * with r the reflectance of one face and a = exp(-4 pi k d / lambda) the
 * internal transmittance.  Eliminating a gives a quadratic in r whose
 * smaller root is the physical one (the larger exceeds 1 or gives a > 1):
 *     r = (B - sqrt(B^2 - 4 R (2 - R))) / (2 (2 - R)),  B = 2 + T^2 - (1 - R)^2,
 * then a = (R - r) / (r T) and k = -lambda ln(a) / (4 pi d).  The face
 * reflectance fixes n up to two roots,
 *     n = (1 + r)/(1 - r) +- sqrt(4 r / (1 - r)^2 - k^2),
 * of which the + root (n > 1, every glass) is taken; the - root is a
 * medium optically thinner than air and is reported, not used.
 *
 * Domain: 0 < T, 0 < R, T + R <= 1, d > 0.  Where the data allow no slab
 * (discriminant < 0, a > 1 beyond rounding, k^2 > 4 r / (1 - r)^2) the
 * result is flagged, not invented.  Conditioning: k comes from the small
 * difference R - r, so k is ill-determined when R - r is not large against
 * the photometric noise; vr_slab_invert_normal reports d n / d R,
 * d n / d T, d k / d R, d k / d T so callers can propagate their noise. */
#ifndef VR_SLAB_INVERT_H
#define VR_SLAB_INVERT_H

#include <stddef.h>
#include "vr/error.h"

#ifdef __cplusplus
extern "C" {
#endif

/* a may exceed 1 by this much (photometric noise on lossless glass) before
 * the data count as impossible; such points get a = 1, k = 0 and the
 * VR_SLAB_CLAMPED_A flag, n still follows from r. */
#define VR_SLAB_A_EXCESS 0.05

enum {
  VR_SLAB_OK = 0,
  VR_SLAB_NO_ROOT = 1,       /* no slab gives these T and R (T + R > 1, ...) */
  VR_SLAB_CLAMPED_A = 2,     /* a computed > 1 (noise); set to 1, k = 0 */
  VR_SLAB_NO_INDEX = 4       /* k too large for the face reflectance: n undefined */
};

typedef struct vr_slab_nk {
  double n, k;               /* the physical root */
  double n_minus;            /* the other root of n (may be < 1), NAN if none */
  double r, a;               /* face reflectance and internal transmittance */
  double dn_dT, dn_dR, dk_dT, dk_dR; /* sensitivities, by central differences */
  int flags;                 /* VR_SLAB_* bits; 0 when the inversion is clean */
} vr_slab_nk;

/* Normal-incidence inversion at one wavelength (nm) for a pane of thickness
 * d_nm in air.  VR_E_ARG for non-finite input, d <= 0 or lambda <= 0;
 * data no slab can produce come back flagged with n, k = NAN (status OK), so
 * a spectrum can be inverted wavelength by wavelength. */
vr_status vr_slab_invert_normal(double T, double R, double d_nm, double lambda_nm, vr_slab_nk *out,
                                vr_error *err);

/* Measured T and R of the same pane at several angles of incidence (degrees,
 * unpolarised light).  Least squares for n, k over all of them, started from
 * the normal-incidence inversion of the smallest angle; sigma_T, sigma_R the
 * photometric standard deviations (for the uncertainties).  With one
 * angle at 0 this is the analytic result.  n_err, k_err receive standard
 * errors; cond the condition number (1 + |rho|) / (1 - |rho|) of the
 * correlation matrix of n and k (1: independent; large: the data cannot
 * tell n from k, ill-conditioned). */
typedef struct vr_slab_obs {
  double angle_deg, T, R;
} vr_slab_obs;
vr_status vr_slab_invert_angles(const vr_slab_obs *obs, size_t count, double d_nm,
                                double lambda_nm, double sigma_T, double sigma_R, vr_slab_nk *out,
                                double *n_err, double *k_err, double *cond, vr_error *err);

/* T and R (unpolarised, and per polarisation when Ts..Rp are not NULL) of an
 * uncoated pane at an angle after the normal-incidence inversion of T0, R0:
 * the "physical route" for angles.  Flags from the inversion are returned in
 * *flags (may be NULL); VR_E_NUMERIC when there is no root. */
vr_status vr_slab_angular(double T0, double R0, double d_nm, double lambda_nm, double angle_deg,
                          double *T, double *R, double pol[4], int *flags, vr_error *err);

#ifdef __cplusplus
}
#endif
#endif
