/* Thick layers whose internal reflections add in power: a glass substrate
 * under coherent films, and the bare slab of a window pane.
 *
 * The stack is cut at every incoherent layer into coherent groups.  Each
 * group, seen as a black box between two thick media, has front and back
 * reflectances and transmittances (Rf, Tf, Rb, Tb) from the coherent solver.
 * Working from the exit back to the ambient, with a the single-pass
 * transmittance of the thick layer in between, the combined response is
 *     R = Rf + Tf Tb a^2 R' / (1 - Rb a^2 R'),   T = Tf a T' / (1 - Rb a^2 R'),
 * where R', T' are those of everything behind.  All terms are powers <= 1,
 * so the sum of the geometric series is stable for any thickness (Harbecke,
 * Appl. Phys. B 39, 165 (1986); Centurioni, Appl. Opt. 44, 7532 (2005)). */
#include "vr/optics.h"

#include <math.h>
#include <stdlib.h>

/* Single-pass power transmittance of a thick layer. */
static double single_pass(vr_complex n, vr_complex beta, double d, double lambda) {
  double im = cimag(vr_optics_q(n, beta));
  return exp(-4.0 * M_PI * im * d / lambda);
}

/* R, T from the front and from the back of the coherent group L[a..b]. */
static vr_status group(const vr_layer *L, size_t a, size_t b, vr_complex beta, double lambda,
                       vr_pol pol, double *Rf, double *Tf, double *Rb, double *Tb,
                       vr_error *err) {
  /* Defined on every path, so a caller never reads an unset value (and
   * -O3's -Wmaybe-uninitialized sees that). */
  *Rf = *Tf = *Rb = *Tb = NAN;
  size_t m = b - a + 1;
  vr_layer small[16], *rev = small;
  if (m > 16 && !(rev = malloc(m * sizeof *rev)))
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  vr_tmm_result f, r;
  vr_status st = vr_tmm_coherent_beta(L + a, m, beta, lambda, pol, &f, NULL, err);
  if (!st) {
    for (size_t i = 0; i < m; i++) rev[i] = L[b - i];
    st = vr_tmm_coherent_beta(rev, m, beta, lambda, pol, &r, NULL, err);
  }
  if (rev != small) free(rev);
  if (st) return st;
  *Rf = f.R;
  *Tf = f.T;
  *Rb = r.R;
  *Tb = r.T;
  return VR_OK;
}

vr_status vr_stack_solve(const vr_layer *L, size_t count, double theta0, double lambda,
                         vr_pol pol, vr_tmm_result *res, vr_error *err) {
  int any = 0;
  for (size_t j = 1; j + 1 < count; j++) any |= L[j].incoherent;
  if (!any) return vr_tmm_coherent(L, count, theta0, lambda, pol, res, NULL, err);
  /* Validate through the coherent entry point's rules (cheap, same layers). */
  vr_tmm_result probe;
  vr_layer ends[2] = {L[0], L[count - 1]};
  vr_status st = vr_tmm_coherent(ends, 2, theta0, lambda, pol, &probe, NULL, err);
  if (st) return st;
  for (size_t j = 1; j + 1 < count; j++) {
    if (!(L[j].thickness_nm >= 0.0) || !isfinite(L[j].thickness_nm))
      return vr_error_set(err, VR_E_ARG, "layer %zu: thickness %g nm must be finite and >= 0", j,
                          L[j].thickness_nm);
    if (cimag(L[j].n) < 0.0 || !isfinite(creal(L[j].n)) || !isfinite(cimag(L[j].n)))
      return vr_error_set(err, VR_E_ARG, "layer %zu: index must be finite with k >= 0", j);
  }
  if (theta0 > M_PI / 2) theta0 = M_PI / 2;
  vr_complex beta = L[0].n * sin(theta0);
  /* Walk groups from the back.  b is the bottom medium of the current group. */
  size_t b = count - 1;
  double Rn = 0.0, Tn = 1.0; /* response of what lies behind medium b */
  int first = 1;
  while (1) {
    size_t a = b;
    do a--; while (a > 0 && !L[a].incoherent);
    double Rf, Tf, Rb, Tb;
    if ((st = group(L, a, b, beta, lambda, pol, &Rf, &Tf, &Rb, &Tb, err))) return st;
    if (first) {
      Rn = Rf;
      Tn = Tf;
      first = 0;
    } else {
      double att = single_pass(L[b].n, beta, L[b].thickness_nm, lambda);
      double a2R = att * att * Rn;
      double denom = 1.0 - Rb * a2R;
      double R = Rf + Tf * Tb * a2R / denom;
      double T = Tf * att * Tn / denom;
      Rn = R;
      Tn = T;
    }
    if (a == 0) break;
    b = a;
  }
  res->r = res->t = NAN;
  res->R = Rn;
  res->T = Tn;
  res->A = 1.0 - Rn - Tn;
  return VR_OK;
}

vr_status vr_slab(double n0, vr_complex N, double d, double theta0, double lambda,
                  vr_slab_result *o, vr_error *err) {
  vr_layer L[3] = {{n0, 0, 0}, {N, d, 1}, {n0, 0, 0}};
  if (!(n0 > 0.0) || !isfinite(n0))
    return vr_error_set(err, VR_E_ARG, "ambient index must be positive (got %g)", n0);
  if (!(d >= 0.0) || !isfinite(d))
    return vr_error_set(err, VR_E_ARG, "slab thickness %g nm must be finite and >= 0", d);
  vr_tmm_result probe;
  vr_status st = vr_tmm_coherent(L, 3, theta0, lambda, VR_POL_S, &probe, NULL, err);
  if (st) return st;
  if (theta0 > M_PI / 2) theta0 = M_PI / 2;
  vr_complex beta = n0 * sin(theta0);
  o->a = single_pass(N, beta, d, lambda);
  for (int p = 0; p < 2; p++) {
    /* Outer face from outside (R1, T12) and from inside (R2, T21). */
    double R1, T12, R2, T21;
    if ((st = group(L, 0, 1, beta, lambda, (vr_pol)p, &R1, &T12, &R2, &T21, err))) return st;
    double a = o->a, den = 1.0 - R2 * R2 * a * a;
    o->R1[p] = R1;
    o->T_single[p] = T12 * a * T21;
    o->T[p] = T12 * a * T21 / den;
    o->R[p] = R1 + T12 * T21 * R2 * a * a / den;
  }
  return VR_OK;
}
