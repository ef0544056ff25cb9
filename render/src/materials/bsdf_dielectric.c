/* One interface between air (the +z side) and a dielectric (the -z side):
 * smooth (Fresnel with complex N from outside, real n from inside, Snell,
 * total internal reflection) or rough (GGX, Walter et al. 2007, through
 * vr/microfacet.h).  Absorption inside the medium is the path's business
 * (vr_bsdf_medium_sigma_a), so the interface itself conserves energy:
 * T = 1 - R whenever a refracted ray exists.
 *
 * Dispersion (pbrt-v4's hero-wavelength convention): a reflection sends
 * every wavelength the same way, each with its own Fresnel weight; a
 * refraction follows the hero's index, so when n varies with wavelength
 * only the hero survives, its weight multiplied by the number of
 * wavelengths, and terminate_secondary is set. */
#include <math.h>

#include "materials/bsdf_internal.h"

static vr_vec3 v3(double x, double y, double z) { return (vr_vec3){x, y, z}; }

static double n_at(const vr_bsdf *b, double nm) {
  return vr_bsdfi_lerp(b->n, vr_bsdfi_at(b, nm));
}

/* R and T = (1 - R when a refracted ray exists) of the smooth interface for
 * light arriving at cos_i (> 0 from outside); *ct the refracted cosine. */
static void smooth_rt(const vr_bsdf *b, double cos_i, double nm, double *R, double *T,
                      double *ct) {
  vr_bsdf_at l = vr_bsdfi_at(b, nm);
  double c = 0.0;
  *R = vr_bsdfi_fresnel(vr_bsdfi_lerp(b->n, l), vr_bsdfi_lerp(b->k, l), cos_i < 0.0, cos_i, &c);
  *T = c > 0.0 ? 1.0 - *R : 0.0;
  if (ct) *ct = c;
}

/* The refracted direction of wo (unit, on the side sign(wo.z)) through
 * relative index eta = n_wi_side / n_wo_side, with refracted cosine ct. */
static vr_vec3 refract(vr_vec3 wo, double eta, double ct) {
  double side = wo.z > 0.0 ? 1.0 : -1.0;
  double ci = fabs(wo.z);
  double a = -1.0 / eta, c = ci / eta - ct;
  return v3(a * wo.x, a * wo.y, a * wo.z + side * c);
}

static bool smooth_sample(const vr_bsdf *b, vr_vec3 wo, int nwl, const double *nm,
                          vr_transport mode, double u3, vr_bsdf_sample *out) {
  double R[VR_BSDF_MAX_WAVELENGTHS], T[VR_BSDF_MAX_WAVELENGTHS], ct0 = 0, sr = 0, st = 0;
  for (int w = 0; w < nwl; w++) {
    smooth_rt(b, wo.z, nm[w], &R[w], &T[w], w == 0 ? &ct0 : NULL);
    sr += R[w];
    st += T[w];
  }
  if (!(sr + st > 0.0)) return false;
  double pr = sr / (sr + st);
  out->terminate_secondary = false;
  if (u3 < pr) {
    out->wi = v3(-wo.x, -wo.y, wo.z);
    out->pdf = pr;
    out->lobe = VR_LOBE_SPECULAR_R;
    out->eta = 1.0;
    for (int w = 0; w < nwl; w++) out->weight[w] = R[w] / pr;
    return true;
  }
  if (!(ct0 > 0.0)) return false; /* the hero is totally reflected; the others end here */
  double pt = 1.0 - pr, n0 = n_at(b, nm[0]);
  double eta = wo.z > 0.0 ? n0 : 1.0 / n0;
  double radiance = mode == VR_TRANSPORT_RADIANCE ? 1.0 / (eta * eta) : 1.0;
  out->wi = refract(wo, eta, ct0);
  out->pdf = pt;
  out->lobe = VR_LOBE_SPECULAR_T;
  out->eta = eta;
  if (b->dispersive) {
    out->terminate_secondary = true;
    out->weight[0] = T[0] / pt * radiance * nwl;
    for (int w = 1; w < nwl; w++) out->weight[w] = 0.0;
  } else {
    for (int w = 0; w < nwl; w++) out->weight[w] = T[w] / pt * radiance;
  }
  return true;
}

static bool rough_sample(const vr_bsdf *b, vr_vec3 wo, int nwl, const double *nm,
                         vr_transport mode, double u1, double u2, double u3,
                         vr_bsdf_sample *out) {
  if (fabs(wo.z) < VR_BSDF_GRAZING) return false;
  double n0 = n_at(b, nm[0]);
  vr_ggx_sample s;
  if (!vr_ggx_dielectric_sample(b->alpha, n0, wo, u1, u2, u3, mode, &s)) return false;
  out->wi = s.wi;
  out->terminate_secondary = false;
  if (isinf(s.pdf)) { /* n = 1: no interface, the ray goes on */
    out->pdf = 1.0;
    out->lobe = VR_LOBE_SPECULAR_T;
    out->eta = 1.0;
    for (int w = 0; w < nwl; w++) out->weight[w] = s.weight;
    return true;
  }
  out->pdf = s.pdf;
  if (s.transmitted) {
    out->lobe = VR_LOBE_GLOSSY_T;
    out->eta = wo.z > 0.0 ? n0 : 1.0 / n0;
    if (b->dispersive) {
      out->terminate_secondary = true;
      out->weight[0] = s.weight * nwl;
      for (int w = 1; w < nwl; w++) out->weight[w] = 0.0;
      return true;
    }
  } else {
    out->lobe = VR_LOBE_GLOSSY_R;
    out->eta = 1.0;
    if (b->dispersive) {
      /* Same direction, each wavelength's own Fresnel: f_w cos / pdf. */
      out->weight[0] = s.weight;
      for (int w = 1; w < nwl; w++)
        out->weight[w] =
            vr_ggx_dielectric_brdf(b->alpha, n_at(b, nm[w]), s.wi, wo) * fabs(s.wi.z) / s.pdf;
      return true;
    }
  }
  /* One real index for all wavelengths: the weights are the hero's. */
  for (int w = 0; w < nwl; w++) out->weight[w] = s.weight;
  return true;
}

bool vr_bsdfi_dielectric_sample(const vr_bsdf *b, vr_vec3 wo, int nwl, const double *nm,
                                vr_transport mode, double u1, double u2, double u3,
                                vr_bsdf_sample *out) {
  if (wo.z == 0.0 || !isfinite(wo.z)) return false;
  return b->rough ? rough_sample(b, wo, nwl, nm, mode, u1, u2, u3, out)
                  : smooth_sample(b, wo, nwl, nm, mode, u3, out);
}

void vr_bsdfi_dielectric_eval(const vr_bsdf *b, vr_vec3 wo, vr_vec3 wi, int nwl,
                              const double *nm, vr_transport mode, double *f, double *pdf) {
  for (int w = 0; w < nwl; w++) f[w] = 0.0;
  if (pdf) *pdf = 0.0;
  if (!b->rough || fabs(wo.z) < VR_BSDF_GRAZING || fabs(wi.z) < VR_BSDF_GRAZING) return;
  bool same = (wo.z > 0.0) == (wi.z > 0.0);
  for (int w = 0; w < nwl; w++) {
    double n = n_at(b, nm[w]);
    f[w] = same ? vr_ggx_dielectric_brdf(b->alpha, n, wi, wo)
                : vr_ggx_dielectric_btdf(b->alpha, n, wi, wo, mode);
  }
  if (pdf) *pdf = vr_ggx_dielectric_pdf(b->alpha, n_at(b, nm[0]), wo, wi);
}

/* Rough interface: R and T (power, importance mode) as the expectation over
 * visible normals on a stratified grid, both branches taken at each normal
 * with their Fresnel weights instead of a random choice. */
static void rough_rt(const vr_bsdf *b, double cos_i, double nm, double *R, double *T) {
  *R = *T = 0.0;
  double c = fmin(fabs(cos_i), 1.0);
  if (!(c >= VR_BSDF_GRAZING)) return;
  double n = n_at(b, nm), e = cos_i > 0.0 ? n : 1.0 / n;
  vr_vec3 wo = v3(sqrt(fmax(0.0, 1.0 - c * c)), 0.0, c); /* mirrored so wo is above */
  const int g = 96;
  double sr = 0.0, st = 0.0;
  for (int i = 0; i < g; i++)
    for (int j = 0; j < g; j++) {
      vr_vec3 m = vr_ggx_sample_vndf(b->alpha, wo, (i + 0.5) / g, (j + 0.5) / g);
      double cm = wo.x * m.x + wo.y * m.y + wo.z * m.z, g1 = vr_ggx_G1(b->alpha, wo, m);
      if (!(cm > 0.0) || !(g1 > 0.0)) continue;
      double ct = 0.0;
      double F = vr_bsdfi_fresnel(e, 0.0, false, cm, &ct);
      if (e < 1.0 && !(ct > 0.0)) F = 1.0;
      vr_vec3 wr = v3(2 * cm * m.x - wo.x, 2 * cm * m.y - wo.y, 2 * cm * m.z - wo.z);
      if (wr.z > 0.0) sr += F * vr_ggx_G2(b->alpha, wr, wo, m) / g1;
      if (F < 1.0 && ct > 0.0) {
        double a = -1.0 / e, k = cm / e - ct;
        vr_vec3 wt = v3(a * wo.x + k * m.x, a * wo.y + k * m.y, a * wo.z + k * m.z);
        double len = sqrt(wt.x * wt.x + wt.y * wt.y + wt.z * wt.z);
        wt = v3(wt.x / len, wt.y / len, wt.z / len);
        if (wt.z < 0.0) st += (1.0 - F) * vr_ggx_G2(b->alpha, wt, wo, m) / g1;
      }
    }
  *R = sr / (g * g);
  *T = st / (g * g);
}

void vr_bsdfi_dielectric_rt(const vr_bsdf *b, double cos_i, double nm, double *R, double *T) {
  if (b->rough) rough_rt(b, cos_i, nm, R, T);
  else smooth_rt(b, cos_i, nm, R, T, NULL);
}
