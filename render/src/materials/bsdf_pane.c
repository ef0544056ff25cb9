/* Thin elements: a pane (bare, coated, measured or tabulated) or a
 * chromogenic glass, each a single surface that reflects specularly and
 * transmits without deflection (the lateral shift inside a few millimetres
 * of glass is below a pixel in a room).  R and T come from the side the
 * light arrives on: Rf from the +n side, Rb from behind; T is the same both
 * ways (reciprocity).
 *
 * Chromogenic glass is not tabulated over its state (a photochromic pane
 * has a different state in every texel): its normal-incidence T(s), Rf(s),
 * Rb(s) come from the per-wavelength model, then the equivalent uncoated
 * slab of bsdf_slab.c carries them to the angle, a few exp/sqrt per
 * wavelength. */
#include <math.h>

#include "materials/bsdf_internal.h"

#define NC VR_BSDF_PANE_NODES

static double table_at(const double *tab, vr_bsdf_at l, size_t j, double u) {
  const double *r0 = tab + l.i * NC, *r1 = r0 + NC;
  double v0 = r0[j] + u * (r0[j + 1] - r0[j]);
  double v1 = r1[j] + u * (r1[j + 1] - r1[j]);
  return v0 + l.t * (v1 - v0);
}

/* An uncoated face of ordinary glass, for chromogenic models that store no
 * reflectance. */
#define NOMINAL_N 1.52

static void chromo_rt(const vr_bsdf *b, double s, double cos_i, double nm, double *R, double *T) {
  vr_bsdf_at l = vr_bsdfi_at(b, nm);
  double Tn = vr_bsdfi_lerp(b->T0, l) * pow(10.0, -s * vr_bsdfi_lerp(b->dOD, l));
  Tn = vr_bsdfi_clamp01(Tn);
  double Rn[2];
  const double *base[2] = {b->Rf0, b->Rb0 ? b->Rb0 : b->Rf0};
  const double *delta[2] = {b->dRf, b->Rb0 ? b->dRb : b->dRf};
  for (int side = 0; side < 2; side++) {
    if (!base[side]) {
      /* Face of NOMINAL_N; its single-pass transmittance a from
       * T = (1 - r)^2 a / (1 - r^2 a^2), the positive root written without
       * cancellation; then R = r (1 + a T). */
      double r = (NOMINAL_N - 1) * (NOMINAL_N - 1) / ((NOMINAL_N + 1) * (NOMINAL_N + 1));
      double q = (1 - r) * (1 - r);
      double a = fmin(2 * Tn / (q + sqrt(q * q + 4 * r * r * Tn * Tn)), 1.0);
      Rn[side] = r * (1 + a * Tn);
    } else {
      double d = delta[side] ? vr_bsdfi_lerp(delta[side], l) : 0.0;
      Rn[side] = vr_bsdfi_clamp01(vr_bsdfi_lerp(base[side], l) + s * d);
    }
  }
  int side = cos_i < 0.0;
  double n, a, T1, R1, t, r;
  /* T from the front slab at any side (reciprocity). */
  vr_bsdf_equivalent_slab(Tn, Rn[0], &n, &a);
  vr_bsdfi_slab_angular(n, a, 1.0, &T1, &R1);
  vr_bsdfi_slab_angular(n, a, cos_i, &t, &r);
  double tt = t, rr = r;
  vr_bsdfi_match(Tn, Rn[0], T1, R1, &tt, &rr);
  *T = tt;
  if (side == 0) {
    *R = rr;
  } else {
    vr_bsdf_equivalent_slab(Tn, Rn[1], &n, &a);
    vr_bsdfi_slab_angular(n, a, 1.0, &T1, &R1);
    vr_bsdfi_slab_angular(n, a, cos_i, &t, &r);
    vr_bsdfi_match(Tn, Rn[1], T1, R1, &t, &r);
    *R = r;
  }
  if (*R + *T > 1.0) *R = 1.0 - *T;
}

void vr_bsdfi_pane_rt(const vr_bsdf *b, double state, double cos_i, double nm, double *R,
                      double *T) {
  if (b->kind == VR_BK_CHROMO) {
    chromo_rt(b, vr_bsdfi_state(b, state), cos_i, nm, R, T);
    return;
  }
  double c = fmin(fabs(cos_i), 1.0);
  if (!(c >= 0.0)) c = 0.0; /* NaN */
  double x = sqrt(c) * (double)(NC - 1);
  size_t j = (size_t)x;
  if (j > NC - 2) j = NC - 2;
  vr_bsdf_at l = vr_bsdfi_at(b, nm);
  double u = x - (double)j;
  *T = table_at(b->T, l, j, u);
  *R = table_at(cos_i < 0.0 ? b->Rb : b->Rf, l, j, u);
}

bool vr_bsdfi_pane_sample(const vr_bsdf *b, double state, vr_vec3 wo, int nwl, const double *nm,
                          double u3, vr_bsdf_sample *out) {
  if (wo.z == 0.0 || !isfinite(wo.z)) return false;
  double R[VR_BSDF_MAX_WAVELENGTHS], T[VR_BSDF_MAX_WAVELENGTHS], sr = 0, st = 0;
  for (int w = 0; w < nwl; w++) {
    vr_bsdfi_pane_rt(b, state, wo.z, nm[w], &R[w], &T[w]);
    sr += R[w];
    st += T[w];
  }
  if (!(sr + st > 0.0)) return false;
  double pr = sr / (sr + st);
  bool reflect = u3 < pr;
  double p = reflect ? pr : 1.0 - pr;
  for (int w = 0; w < nwl; w++) out->weight[w] = (reflect ? R[w] : T[w]) / p;
  out->wi = reflect ? (vr_vec3){-wo.x, -wo.y, wo.z} : (vr_vec3){-wo.x, -wo.y, -wo.z};
  out->pdf = p;
  out->lobe = reflect ? VR_LOBE_SPECULAR_R : VR_LOBE_STRAIGHT;
  out->eta = 1.0;
  out->terminate_secondary = false;
  return true;
}
