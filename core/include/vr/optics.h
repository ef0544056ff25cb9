/* Plane-wave optics of flat interfaces, thin films and thick slabs.
 *
 * Conventions (docs/conventions.md has the long form):
 *  - complex refractive index N = n + i k, k >= 0 absorbing; fields vary as
 *    exp(i (k.r - w t)), so a wave decays along its path when k > 0;
 *  - wavelengths and thicknesses in nm, angles in radians here (the tools
 *    speak degrees);
 *  - amplitude coefficients follow Byrnes' tmm package ("Multilayer optical
 *    calculations", arXiv:1603.02720): r_p = (n2 cos t1 - n1 cos t2) /
 *    (n2 cos t1 + n1 cos t2), so r_p = r_s at normal incidence;
 *  - the ellipsometric ratio rho = tan(Psi) exp(i Delta) is reported in the
 *    ellipsometers' exp(+i w t) phase convention (Woollam, Nebraska), that is
 *    rho = conj(r_p / r_s) of the amplitudes above: bare Si at 70 deg and
 *    633 nm gives Psi = 10.6, Delta = 179.3 deg, Delta < 180 below the
 *    principal angle for absorbing substrates;
 *  - every layer is described by q = N cos(theta) = sqrt(N^2 - beta^2), with
 *    beta = n0 sin(theta0) conserved across the stack (Snell's law with
 *    complex angles) and the root chosen with Im q >= 0, so evanescent and
 *    absorbed waves decay forward.
 *
 * Domain: 0 <= theta0 <= pi/2; any k >= 0 (1e-12 to 1e3 tested); the
 * ambient medium should be transparent (k = 0) for R and T to be the usual
 * power ratios.  Thin-film recursion is written with decaying exponentials
 * only (Rouard's method), so it neither overflows for thick absorbing layers
 * nor needs a thickness cut-off. */
#ifndef VR_OPTICS_H
#define VR_OPTICS_H

#include <complex.h>
#include <stddef.h>
#include "vr/error.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef double _Complex vr_complex;

typedef enum vr_pol { VR_POL_S = 0, VR_POL_P = 1 } vr_pol;

/* q = N cos(theta) inside a medium of index N for the invariant beta. */
vr_complex vr_optics_q(vr_complex N, vr_complex beta);
/* cos(theta) in that medium: Snell's law with complex angles. */
vr_complex vr_optics_cos(vr_complex N, vr_complex beta);

/* One interface, light coming from medium 1 at angle theta1 (radians). */
typedef struct vr_fresnel {
  vr_complex rs, rp, ts, tp;   /* amplitude coefficients */
  double Rs, Rp, Ts, Tp;       /* power reflectance and transmittance */
} vr_fresnel;
void vr_fresnel_interface(vr_complex n1, vr_complex n2, double theta1, vr_fresnel *out);

/* Angle (radians) at which Rp = 0 between transparent media. */
double vr_optics_brewster(double n1, double n2);
/* Critical angle from n1 into n2 < n1, or NAN when n2 >= n1. */
double vr_optics_critical(double n1, double n2);

/* One layer of a stack.  The first and last entries are the semi-infinite
 * ambient and exit media (their thickness is ignored).  incoherent marks an
 * inner layer thick enough, compared with the coherence length of the light,
 * that its internal reflections add in power, not amplitude (a glass pane
 * under a spectrophotometer). */
typedef struct vr_layer {
  vr_complex n;
  double thickness_nm;
  int incoherent;
} vr_layer;

typedef struct vr_tmm_result {
  vr_complex r, t;   /* amplitude coefficients (coherent stacks only) */
  double R, T, A;    /* reflectance, transmittance, absorptance */
} vr_tmm_result;

/* Coherent solve of the whole stack for one polarisation.  absorbed, when
 * not NULL, receives count entries: the fraction of incident power absorbed
 * in each layer, from the Poynting flux at its two faces (0 for the ambient;
 * the exit medium gets T).  Fails (VR_E_ARG, naming the layer) on negative
 * or non-finite thickness, k < 0, a non-finite index, theta0 outside
 * [0, pi/2] or lambda <= 0. */
vr_status vr_tmm_coherent(const vr_layer *layers, size_t count, double theta0, double lambda_nm,
                          vr_pol pol, vr_tmm_result *res, double *absorbed, vr_error *err);

/* The same solve on the Snell invariant beta = n0 sin(theta0) instead of an
 * angle, for callers that start inside a medium where the angle may be
 * complex (light coming back up from a substrate).  No argument validation:
 * callers pass stacks already checked (or built by vr_tmm_coherent's rules). */
vr_status vr_tmm_coherent_beta(const vr_layer *layers, size_t count, vr_complex beta,
                               double lambda_nm, vr_pol pol, vr_tmm_result *res, double *absorbed,
                               vr_error *err);

/* Ellipsometric angles of a coherent stack: Psi in [0, 90], Delta in
 * [0, 360) degrees, rho = conj(r_p / r_s) = tan(Psi) e^{i Delta} (see the
 * convention note at the top). */
vr_status vr_tmm_ellipsometry(const vr_layer *layers, size_t count, double theta0,
                              double lambda_nm, double *psi_deg, double *delta_deg,
                              vr_complex *rho, vr_error *err);

/* Power R and T of a stack mixing coherent films and incoherent thick layers
 * (the incoherent flags of inner layers are honoured; a stack without any is
 * solved coherently).  Reflections between groups add in power with the
 * single-pass attenuation exp(-4 pi Im(q) d / lambda) of each incoherent
 * layer.  res->r and res->t are set to NAN when the stack has an incoherent
 * layer, since no amplitude exists then. */
vr_status vr_stack_solve(const vr_layer *layers, size_t count, double theta0, double lambda_nm,
                         vr_pol pol, vr_tmm_result *res, vr_error *err);

/* A thick slab of index N and thickness d in a transparent ambient n0 (air is
 * 1), both faces bare.  For each polarisation (index VR_POL_S, VR_POL_P):
 *   R1        reflectance of one face,
 *   T_single  the directly transmitted beam only, T12 a T21,
 *   R, T      with all internal reflections summed (geometric series),
 * where a = exp(-4 pi Im(q) d / lambda) is the internal single-pass
 * transmittance (Beer-Lambert along the refracted path). */
typedef struct vr_slab_result {
  double R1[2], T_single[2], R[2], T[2], a;
} vr_slab_result;
vr_status vr_slab(double n0, vr_complex N, double d_nm, double theta0, double lambda_nm,
                  vr_slab_result *out, vr_error *err);

#ifdef __cplusplus
}
#endif
#endif
