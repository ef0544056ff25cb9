/* The glTF 2.0 metallic-roughness BRDF (the glTF 2.0 specification,
 * Appendix B, "BRDF Implementation"), per wavelength:
 *
 *   f = (1 - M) [ (1 - F_d) C / pi + F_d S ] + M F_m S,
 *   F_d = 0.04 + 0.96 (1 - |v.h|)^5            (dielectric, ior 1.5)
 *   F_m = C + (1 - C) (1 - |v.h|)^5            (metal, F0 = the base colour)
 *   S   = D G2 / (4 |n.l| |n.v|)                (GGX, alpha = roughness^2)
 *
 * with C the base colour (a reflectance spectrum, times a texture), M the
 * metallic value and h the half vector of v (wo) and l (wi).  Masking is
 * Smith's height-correlated G2 (vr/microfacet.h), which the specification
 * allows in place of its separable form.  It is symmetric in v and l (v.h
 * = l.h), so photons and camera paths share it.  Below alpha 1e-3 the
 * specular part is a mirror (a delta lobe, its Fresnel factor at the
 * incidence) and only the diffuse part is evaluated: light sampling
 * cannot find a lobe that narrow.
 *
 * Sampling picks the specular lobe (visible GGX normals, or the mirror)
 * with probability P_s and the cosine-weighted diffuse one otherwise; the
 * weight of a rough sample is f |cos| over the mixture's density (one-
 * sample balance heuristic), so both lobes are unbiased for every
 * wavelength.  P_s compares the lobes' albedos at wo for the mean base
 * colour, clamped to [0.1, 0.9] when both lobes are present, so that a
 * wavelength whose base colour is far from the mean keeps a bounded
 * weight.  Domain: wo and wi on the same side (opaque); the dispatcher
 * turns the frame to wo's side. */
#include <math.h>

#include "materials/bsdf_internal.h"

#define PBR_F0 0.04           /* ((1.5 - 1) / (1.5 + 1))^2: glTF's dielectric */
#define PBR_MIRROR_ALPHA 1e-3 /* below: the specular lobe is a mirror */

static double schlick(double f0, double c) {
  double m = 1.0 - fmin(fmax(c, 0.0), 1.0), m2 = m * m;
  return f0 + (1.0 - f0) * m2 * m2 * m;
}

bool vr_bsdfi_pbr_mirror(double alpha) { return !(alpha >= PBR_MIRROR_ALPHA); }

void vr_bsdfi_pbr_setup(const vr_bsdf *b, const vr_bsdf_point *pt, int nwl, const double *nm,
                        vr_bsdfi_pbr *q) {
  double m = pt && isfinite(pt->metallic) ? pt->metallic : b->metallic;
  double r = pt && isfinite(pt->roughness) ? pt->roughness : b->pbr_r;
  q->metallic = vr_bsdfi_clamp01(m);
  r = vr_bsdfi_clamp01(r);
  q->alpha = r * r;
  q->mirror = vr_bsdfi_pbr_mirror(q->alpha);
  q->only = pt && pt->only ? pt->only : ~0u;
  for (int w = 0; w < nwl; w++) {
    double c = vr_bsdfi_lerp(b->refl, vr_bsdfi_at(b, nm[w]));
    if (pt && pt->has_base) c *= pt->base[w];
    q->base[w] = vr_bsdfi_clamp01(c);
  }
  double mean = b->refl_mean * (pt && pt->has_base ? pt->base_mean : 1.0);
  q->base_mean = vr_bsdfi_clamp01(mean);
}

/* Probability of the specular lobe at wo (cos c), from the lobes' albedos
 * for the mean base colour; -1 when neither lobe scatters. */
static double p_specular(const vr_bsdfi_pbr *q, double c) {
  unsigned spec_lobe = q->mirror ? VR_LOBE_SPECULAR_R : VR_LOBE_GLOSSY_R;
  double m = q->metallic, fs = schlick(PBR_F0, c);
  double ws = (q->only & spec_lobe) ? (1.0 - m) * fs + m * schlick(q->base_mean, c) : 0.0;
  double wd = (q->only & VR_LOBE_DIFFUSE) ? (1.0 - m) * q->base_mean * (1.0 - fs) : 0.0;
  if (!(ws + wd > 0.0)) return -1.0;
  if (wd <= 0.0) return 1.0;
  if (ws <= 0.0) return 0.0;
  return fmin(fmax(ws / (ws + wd), 0.1), 0.9);
}

/* f of the non-delta lobes (wo, wi above the surface). */
static void pbr_f(const vr_bsdfi_pbr *q, vr_vec3 wo, vr_vec3 wi, int nwl, double *f) {
  vr_vec3 h = {wo.x + wi.x, wo.y + wi.y, wo.z + wi.z};
  double len = sqrt(vr_vec3_dot(h, h));
  double voh = len > 0.0 ? vr_vec3_dot(wo, h) / len : 0.0;
  double fd = schlick(PBR_F0, voh), m = q->metallic;
  double s = !q->mirror && (q->only & VR_LOBE_GLOSSY_R) ? vr_ggx_reflection(q->alpha, wi, wo) : 0.0;
  bool diffuse = (q->only & VR_LOBE_DIFFUSE) != 0;
  for (int w = 0; w < nwl; w++) {
    double c = q->base[w];
    double v = s > 0.0 ? s * ((1.0 - m) * fd + m * schlick(c, voh)) : 0.0;
    if (diffuse) v += (1.0 - m) * (1.0 - fd) * c / M_PI;
    f[w] = v;
  }
}

static double pbr_pdf(const vr_bsdfi_pbr *q, double ps, vr_vec3 wo, vr_vec3 wi) {
  double pd = (1.0 - ps) * wi.z / M_PI;
  if (q->mirror || ps <= 0.0) return pd;
  return ps * vr_ggx_reflection_pdf(q->alpha, wo, wi) + pd;
}

void vr_bsdfi_pbr_eval(const vr_bsdfi_pbr *q, vr_vec3 wo, vr_vec3 wi, int nwl, double *f,
                       double *pdf) {
  for (int w = 0; w < nwl; w++) f[w] = 0.0;
  if (pdf) *pdf = 0.0;
  if (!(wo.z >= VR_BSDF_GRAZING) || !(wi.z >= VR_BSDF_GRAZING)) return;
  double ps = p_specular(q, fmin(wo.z, 1.0));
  if (ps < 0.0) return;
  pbr_f(q, wo, wi, nwl, f);
  if (pdf) *pdf = pbr_pdf(q, ps, wo, wi);
}

bool vr_bsdfi_pbr_sample(const vr_bsdfi_pbr *q, vr_vec3 wo, int nwl, double u1, double u2,
                         double u3, vr_bsdf_sample *out) {
  if (!(wo.z >= VR_BSDF_GRAZING)) return false;
  double c = fmin(wo.z, 1.0), ps = p_specular(q, c);
  if (ps < 0.0) return false;
  out->eta = 1.0;
  out->terminate_secondary = false;
  bool specular = u3 < ps;
  if (specular && q->mirror) {
    out->wi = (vr_vec3){-wo.x, -wo.y, wo.z};
    out->pdf = ps;
    out->lobe = VR_LOBE_SPECULAR_R;
    double m = q->metallic, fs = schlick(PBR_F0, c);
    for (int w = 0; w < nwl; w++) out->weight[w] = ((1.0 - m) * fs + m * schlick(q->base[w], c)) / ps;
    return true;
  }
  vr_vec3 wi;
  if (specular) {
    vr_vec3 mh = vr_ggx_sample_vndf(q->alpha, wo, u1, u2);
    double d = 2.0 * vr_vec3_dot(wo, mh);
    wi = (vr_vec3){d * mh.x - wo.x, d * mh.y - wo.y, d * mh.z - wo.z};
    out->lobe = VR_LOBE_GLOSSY_R;
  } else {
    double r = sqrt(u1), phi = 2.0 * M_PI * u2;
    wi = (vr_vec3){r * cos(phi), r * sin(phi), sqrt(fmax(0.0, 1.0 - u1))};
    out->lobe = VR_LOBE_DIFFUSE;
  }
  if (!(wi.z >= VR_BSDF_GRAZING)) return false;
  double pdf = pbr_pdf(q, ps, wo, wi), f[VR_BSDF_MAX_WAVELENGTHS];
  if (!(pdf > 0.0) || !isfinite(pdf)) return false;
  pbr_f(q, wo, wi, nwl, f);
  out->wi = wi;
  out->pdf = pdf;
  for (int w = 0; w < nwl; w++) out->weight[w] = f[w] * wi.z / pdf;
  return true;
}

/* Directional-hemispherical reflectance at one wavelength: the mean
 * sample weight over a stratified grid of (u1, u2) and of the lobe choice
 * (the estimator is f cos / pdf, delta lobe included). */
double vr_bsdfi_pbr_albedo(const vr_bsdf *b, double nm, double cos_i) {
  double c = fmin(fabs(cos_i), 1.0);
  if (!(c >= VR_BSDF_GRAZING)) return 0.0;
  vr_bsdfi_pbr q;
  vr_bsdfi_pbr_setup(b, NULL, 1, &nm, &q);
  vr_vec3 wo = {sqrt(fmax(0.0, 1.0 - c * c)), 0.0, c};
  const int n = 48, nl = 8;
  double sum = 0.0;
  for (int l = 0; l < nl; l++)
    for (int i = 0; i < n; i++)
      for (int j = 0; j < n; j++) {
        vr_bsdf_sample s;
        if (vr_bsdfi_pbr_sample(&q, wo, 1, (i + 0.5) / n, (j + 0.5) / n, (l + 0.5) / nl, &s))
          sum += s.weight[0];
      }
  return sum / (n * n * nl);
}
