/* The uncoated slab in closed form, for panes known only by their
 * normal-incidence T and R (glazing, chromogenic glass at a state).
 *
 * A pane in air with face reflectance r and internal single-pass
 * transmittance a sums its internal reflections in power:
 *     T = (1 - r)^2 a / (1 - r^2 a^2),   R = r + (1 - r)^2 r a^2 / (1 - r^2 a^2).
 * At normal incidence R = r (1 + a T); eliminating a leaves a quadratic in
 * r whose smaller root is the physical one (fit/src/slab_invert.c derives
 * it; render/ may not include fit/, so the algebra is repeated here, total
 * instead of flagged, without the derivatives):
 *     r = 2 R / (B + sqrt(B^2 - 4 R (2 - R))),  B = 2 + T^2 - (1 - R)^2,
 *     a = (R - r) / (r T),   n = (1 + sqrt r) / (1 - sqrt r).
 * (n from r neglects k, which for any pane that transmits is below 1e-4
 * and changes r by k^2.)  At an angle, each polarisation has its own face
 * reflectance (real Fresnel) and the path inside lengthens to
 * d / cos(theta_t), so a(theta) = a0^(1 / cos(theta_t)): to first order in
 * k this is what vr_slab computes with complex angles. */
#include <math.h>

#include "materials/bsdf_internal.h"

void vr_bsdf_equivalent_slab(double T, double R, double *n, double *a) {
  T = vr_bsdfi_clamp01(T);
  R = vr_bsdfi_clamp01(R);
  double r, at;
  if (!(T > 0.0)) {
    r = R; /* opaque: only the first face is seen */
    at = 0.0;
  } else if (!(R > 0.0)) {
    r = 0.0; /* index-matched to air: all loss is absorption */
    at = T;
  } else {
    double B = 2.0 + T * T - (1.0 - R) * (1.0 - R);
    double disc = fmax(B * B - 4.0 * R * (2.0 - R), 0.0);
    r = 2.0 * R / (B + sqrt(disc));
    at = r > 0.0 ? (R - r) / (r * T) : T;
  }
  /* r = 1 would be a perfect mirror face with an infinite index. */
  r = fmin(r, 0.999999);
  double sr = sqrt(r);
  *n = (1.0 + sr) / (1.0 - sr);
  *a = vr_bsdfi_clamp01(at);
}

/* One polarisation: face reflectance r, internal transmittance a. */
static void series(double r, double a, double *T, double *R) {
  if (r >= 1.0) {
    *T = 0.0;
    *R = 1.0;
    return;
  }
  double den = 1.0 - r * r * a * a;
  *T = (1.0 - r) * (1.0 - r) * a / den;
  *R = r + (1.0 - r) * (1.0 - r) * r * a * a / den;
}

void vr_bsdfi_slab_angular(double n, double a0, double cos_i, double *T, double *R) {
  double c = fmin(fabs(cos_i), 1.0);
  double s2 = 1.0 - c * c;
  double ct = sqrt(fmax(1.0 - s2 / (n * n), 0.0));
  double rs = (c - n * ct) / (c + n * ct), rp = (n * c - ct) / (n * c + ct);
  if (!(c > 0.0)) rs = rp = 1.0; /* grazing: both faces are mirrors */
  double a;
  if (a0 >= 1.0) a = 1.0;
  else if (!(a0 > 0.0) || !(ct > 0.0)) a = 0.0;
  else a = exp(log(a0) / ct);
  double Ts, Rs, Tp, Rp;
  series(rs * rs, a, &Ts, &Rs);
  series(rp * rp, a, &Tp, &Rp);
  *T = 0.5 * (Ts + Tp);
  *R = 0.5 * (Rs + Rp);
}

void vr_bsdfi_match(double Tn, double Rn, double T1, double R1, double *T, double *R) {
  /* T scales (it vanishes at grazing anyway); R moves by the normal
   * incidence offset times (1 - R) / (1 - R1), which keeps R = 1 at grazing
   * and R <= 1 everywhere. */
  double t = T1 > 0.0 ? *T * (Tn / T1) : 0.0;
  double r = R1 < 1.0 ? *R + (Rn - R1) * (1.0 - *R) / (1.0 - R1) : *R;
  t = vr_bsdfi_clamp01(t);
  r = vr_bsdfi_clamp01(r);
  if (r + t > 1.0) {
    double s = 1.0 / (r + t);
    r *= s;
    t *= s;
  }
  *T = t;
  *R = r;
}
