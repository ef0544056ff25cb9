/* Snell's law with complex angles and the Fresnel coefficients of a single
 * interface.  See vr/optics.h for the sign conventions. */
#include "vr/optics.h"

#include <math.h>

vr_complex vr_optics_q(vr_complex N, vr_complex beta) {
  vr_complex q = csqrt(N * N - beta * beta);
  /* csqrt returns Re >= 0; the physical root is the one that decays along
   * the propagation direction (Im q >= 0).  A negative Im here only comes
   * from a -0 imaginary part or rounding on a transparent medium, so the
   * flip changes no propagating wave. */
  if (cimag(q) < 0.0) q = -q;
  return q;
}

vr_complex vr_optics_cos(vr_complex N, vr_complex beta) { return vr_optics_q(N, beta) / N; }

static double sq(double x) { return x * x; }
static double abs2(vr_complex z) { return sq(creal(z)) + sq(cimag(z)); }

void vr_fresnel_interface(vr_complex n1, vr_complex n2, double theta1, vr_fresnel *o) {
  vr_complex beta = n1 * sin(theta1);
  vr_complex q1 = vr_optics_q(n1, beta), q2 = vr_optics_q(n2, beta);
  vr_complex ds = q1 + q2, dp = n2 * n2 * q1 + n1 * n1 * q2;
  vr_complex ns = q1 - q2, np = n2 * n2 * q1 - n1 * n1 * q2;
  o->rs = ns / ds;
  o->ts = 2.0 * q1 / ds;
  o->rp = np / dp;
  o->tp = 2.0 * n1 * n2 * q1 / dp;
  /* |num|^2 / |den|^2 rather than |num/den|^2: past the critical angle the
   * two moduli are computed from the same numbers, so R is exactly 1. */
  o->Rs = abs2(ns) / abs2(ds);
  o->Rp = abs2(np) / abs2(dp);
  double in_s = creal(q1);
  double in_p = creal(n1 * conj(q1 / n1));
  if (in_s <= 0.0) { /* exactly grazing: nothing enters medium 2 */
    o->Ts = o->Tp = 0.0;
    o->Rs = o->Rp = 1.0;
    return;
  }
  o->Ts = abs2(o->ts) * creal(q2) / in_s;
  o->Tp = abs2(o->tp) * creal(n2 * conj(q2 / n2)) / in_p;
}

double vr_optics_brewster(double n1, double n2) { return atan2(n2, n1); }

double vr_optics_critical(double n1, double n2) {
  if (!(n2 < n1) || n2 <= 0.0) return NAN;
  return asin(n2 / n1);
}
