/* Metals: the Fresnel mirror with complex N = n + i k (unpolarised, the
 * mean of |r_s|^2 and |r_p|^2), and its rough version, the GGX conductor of
 * vr/microfacet.h.  Both are one-sided reflectors seen from whichever side
 * wo is (the dispatcher turns the frame), so a thin metal sheet or a mesh
 * with flipped normals still reflects.
 *
 * Several wavelengths share one sampled microfacet normal m: for the rough
 * metal the sample weight of wavelength w is F_w(wo.m) G2 / G1, the hero's
 * weight with its own Fresnel factor, exactly f_w cos / pdf. */
#include <complex.h>
#include <math.h>

#include "materials/bsdf_internal.h"

static vr_vec3 v3(double x, double y, double z) { return (vr_vec3){x, y, z}; }
static vr_complex index_at(const vr_bsdf *b, double nm) {
  vr_bsdf_at l = vr_bsdfi_at(b, nm);
  return vr_bsdfi_lerp(b->n, l) + I * vr_bsdfi_lerp(b->k, l);
}

double vr_bsdfi_conductor_fresnel(const vr_bsdf *b, double nm, double cos_i) {
  vr_complex N = index_at(b, nm);
  return vr_bsdfi_fresnel(creal(N), cimag(N), false, cos_i, NULL);
}

void vr_bsdfi_conductor_eval(const vr_bsdf *b, vr_vec3 wo, vr_vec3 wi, int nwl, const double *nm,
                             double *f, double *pdf) {
  for (int w = 0; w < nwl; w++) f[w] = 0.0;
  if (pdf) *pdf = 0.0;
  if (!b->rough || !(wo.z >= VR_BSDF_GRAZING) || !(wi.z >= VR_BSDF_GRAZING)) return;
  for (int w = 0; w < nwl; w++)
    f[w] = vr_ggx_conductor_brdf(b->alpha, index_at(b, nm[w]), wi, wo);
  if (pdf) *pdf = vr_ggx_reflection_pdf(b->alpha, wo, wi);
}

bool vr_bsdfi_conductor_sample(const vr_bsdf *b, vr_vec3 wo, int nwl, const double *nm,
                               double u1, double u2, vr_bsdf_sample *out) {
  if (!(wo.z > 0.0)) return false;
  out->eta = 1.0;
  out->terminate_secondary = false;
  if (!b->rough) {
    out->wi = v3(-wo.x, -wo.y, wo.z);
    out->pdf = 1.0;
    out->lobe = VR_LOBE_SPECULAR_R;
    for (int w = 0; w < nwl; w++) out->weight[w] = vr_bsdfi_conductor_fresnel(b, nm[w], wo.z);
    return true;
  }
  if (!(wo.z >= VR_BSDF_GRAZING)) return false;
  vr_ggx_sample s;
  if (!vr_ggx_conductor_sample(b->alpha, index_at(b, nm[0]), wo, u1, u2, &s)) return false;
  vr_vec3 h = v3(wo.x + s.wi.x, wo.y + s.wi.y, wo.z + s.wi.z);
  double len = sqrt(vr_vec3_dot(h, h));
  h = v3(h.x / len, h.y / len, h.z / len);
  double c = vr_vec3_dot(wo, h);
  double g1 = vr_ggx_G1(b->alpha, wo, h);
  double ratio = g1 > 0.0 ? vr_ggx_G2(b->alpha, s.wi, wo, h) / g1 : 0.0;
  out->weight[0] = s.weight;
  for (int w = 1; w < nwl; w++) out->weight[w] = vr_bsdfi_conductor_fresnel(b, nm[w], c) * ratio;
  out->wi = s.wi;
  out->pdf = s.pdf;
  out->lobe = VR_LOBE_GLOSSY_R;
  return true;
}

/* Directional-hemispherical reflectance: the Fresnel value when smooth;
 * rough, the mean sample weight over a stratified grid of visible normals
 * (the estimator is f cos / pdf, so its mean is the integral). */
double vr_bsdfi_conductor_albedo(const vr_bsdf *b, double nm, double cos_i) {
  double c = fmin(fabs(cos_i), 1.0);
  if (!b->rough) return vr_bsdfi_conductor_fresnel(b, nm, c);
  if (!(c >= VR_BSDF_GRAZING)) return 0.0;
  vr_vec3 wo = v3(sqrt(fmax(0.0, 1.0 - c * c)), 0.0, c);
  const int n = 96;
  double sum = 0.0;
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++) {
      vr_bsdf_sample s;
      if (vr_bsdfi_conductor_sample(b, wo, 1, &nm, (i + 0.5) / n, (j + 0.5) / n, &s))
        sum += s.weight[0];
    }
  return sum / (n * n);
}
