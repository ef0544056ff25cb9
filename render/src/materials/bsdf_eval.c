/* Evaluating and sampling a vr_bsdf: the world <-> shading frame change,
 * the Lambertian (small enough to live here) and the dispatch to the
 * conductor, dielectric and thin-element code, each written in the local
 * frame where the normal is +z. */
#include <math.h>

#include "materials/bsdf_internal.h"

static vr_shading_frame vr_shading_frame_of(vr_vec3 n) {
  double a[3] = {n.x, n.y, n.z}, t[3], b[3];
  vr_frame3(a, t, b);
  return (vr_shading_frame){{t[0], t[1], t[2]}, {b[0], b[1], b[2]}, n};
}

/* Opaque reflectors work from wo's side: mirror z when wo is below. */
static vr_vec3 flip(vr_vec3 v) { return (vr_vec3){v.x, v.y, -v.z}; }

static int clamp_nwl(int nwl) {
  return nwl < 0 ? 0 : (nwl > VR_BSDF_MAX_WAVELENGTHS ? VR_BSDF_MAX_WAVELENGTHS : nwl);
}

vr_bsdf_point vr_bsdf_point_plain(void) {
  vr_bsdf_point p = {0};
  p.metallic = p.roughness = NAN;
  return p;
}

void vr_bsdf_eval(const vr_bsdf *b, double state, vr_vec3 n, vr_vec3 wo, vr_vec3 wi, int nwl,
                  const double *nm, vr_transport mode, double *f, double *pdf) {
  vr_bsdf_eval_at(b, NULL, state, n, wo, wi, nwl, nm, mode, f, pdf);
}

void vr_bsdf_eval_at(const vr_bsdf *b, const vr_bsdf_point *pt, double state, vr_vec3 n,
                     vr_vec3 wo, vr_vec3 wi, int nwl, const double *nm, vr_transport mode,
                     double *f, double *pdf) {
  (void)state; /* thin elements and chromogenic glass are all delta lobes */
  nwl = clamp_nwl(nwl);
  for (int w = 0; w < nwl; w++) f[w] = 0.0;
  if (pdf) *pdf = 0.0;
  if (pt && pt->only && !(b->lobes & pt->only)) return;
  if (b->kind == VR_BK_KLEMS) { /* its own frame: the file's azimuths are fixed to up= */
    vr_bsdfi_klems_eval(b, n, wo, wi, nwl, mode, f, pdf);
    return;
  }
  vr_shading_frame fr = vr_shading_frame_of(n);
  vr_vec3 o = vr_bsdfi_to_local(&fr, wo), i = vr_bsdfi_to_local(&fr, wi);
  switch (b->kind) {
  case VR_BK_LAMBERT:
    if (o.z * i.z > 0.0) {
      for (int w = 0; w < nwl; w++) f[w] = vr_bsdfi_lerp(b->refl, vr_bsdfi_at(b, nm[w])) / M_PI;
      if (pdf) *pdf = fabs(i.z) / M_PI;
    }
    break;
  case VR_BK_CONDUCTOR:
    if (o.z < 0.0) {
      o = flip(o);
      i = flip(i);
    }
    vr_bsdfi_conductor_eval(b, o, i, nwl, nm, f, pdf);
    break;
  case VR_BK_TRANSLUCENT:
    vr_bsdfi_translucent_eval(b, pt ? pt->only : 0, o, i, nwl, nm, f, pdf);
    break;
  case VR_BK_INTERFACE:
    vr_bsdfi_dielectric_eval(b, o, i, nwl, nm, mode, f, pdf);
    break;
  case VR_BK_PBR: {
    vr_bsdfi_pbr q;
    vr_bsdfi_pbr_setup(b, pt, nwl, nm, &q);
    if (o.z < 0.0) {
      o = flip(o);
      i = flip(i);
    }
    vr_bsdfi_pbr_eval(&q, o, i, nwl, f, pdf);
    break;
  }
  default:
    break;
  }
}

static bool lambert_sample(const vr_bsdf *b, vr_vec3 wo, int nwl, const double *nm, double u1,
                           double u2, vr_bsdf_sample *out) {
  if (wo.z == 0.0 || !isfinite(wo.z)) return false;
  /* Cosine-weighted hemisphere on wo's side (Malley's method). */
  double r = sqrt(u1), phi = 2.0 * M_PI * u2, z = sqrt(fmax(0.0, 1.0 - u1));
  if (!(z > 0.0)) return false;
  out->wi = (vr_vec3){r * cos(phi), r * sin(phi), wo.z > 0.0 ? z : -z};
  out->pdf = z / M_PI;
  out->lobe = VR_LOBE_DIFFUSE;
  out->eta = 1.0;
  out->terminate_secondary = false;
  for (int w = 0; w < nwl; w++) out->weight[w] = vr_bsdfi_lerp(b->refl, vr_bsdfi_at(b, nm[w]));
  return true;
}

bool vr_bsdf_sample_dir(const vr_bsdf *b, double state, vr_vec3 n, vr_vec3 wo, int nwl,
                        const double *nm, vr_transport mode, double u1, double u2, double u3,
                        vr_bsdf_sample *out) {
  return vr_bsdf_sample_at(b, NULL, state, n, wo, nwl, nm, mode, u1, u2, u3, out);
}

bool vr_bsdf_sample_at(const vr_bsdf *b, const vr_bsdf_point *pt, double state, vr_vec3 n,
                       vr_vec3 wo, int nwl, const double *nm, vr_transport mode, double u1,
                       double u2, double u3, vr_bsdf_sample *out) {
  nwl = clamp_nwl(nwl);
  if (nwl == 0) return false;
  if (b->kind == VR_BK_KLEMS) {
    if (!vr_bsdfi_klems_sample(b, n, wo, nwl, mode, u1, u2, u3, out) ||
        (pt && pt->only && !(out->lobe & pt->only)))
      return false;
    for (int w = nwl; w < VR_BSDF_MAX_WAVELENGTHS; w++) out->weight[w] = 0.0;
    return true;
  }
  vr_shading_frame fr = vr_shading_frame_of(n);
  vr_vec3 o = vr_bsdfi_to_local(&fr, wo);
  bool ok = false;
  switch (b->kind) {
  case VR_BK_BLACK:
    return false;
  case VR_BK_LAMBERT:
    ok = lambert_sample(b, o, nwl, nm, u1, u2, out);
    break;
  case VR_BK_TRANSLUCENT:
    ok = vr_bsdfi_translucent_sample(b, o, nwl, nm, u1, u2, u3, out);
    break;
  case VR_BK_CONDUCTOR: {
    bool below = o.z < 0.0;
    ok = vr_bsdfi_conductor_sample(b, below ? flip(o) : o, nwl, nm, u1, u2, out);
    if (ok && below) out->wi = flip(out->wi);
    break;
  }
  case VR_BK_INTERFACE:
    ok = vr_bsdfi_dielectric_sample(b, o, nwl, nm, mode, u1, u2, u3, out);
    break;
  case VR_BK_PANE:
  case VR_BK_CHROMO:
    ok = vr_bsdfi_pane_sample(b, state, o, nwl, nm, u3, out);
    break;
  case VR_BK_KLEMS: /* handled above */
    return false;
  case VR_BK_PBR: {
    vr_bsdfi_pbr q;
    vr_bsdfi_pbr_setup(b, pt, nwl, nm, &q);
    bool below = o.z < 0.0;
    ok = vr_bsdfi_pbr_sample(&q, below ? flip(o) : o, nwl, u1, u2, u3, out);
    if (ok && below) out->wi = flip(out->wi);
    break;
  }
  }
  if (!ok || (pt && pt->only && !(out->lobe & pt->only))) return false;
  for (int w = nwl; w < VR_BSDF_MAX_WAVELENGTHS; w++) out->weight[w] = 0.0;
  out->wi = vr_bsdfi_to_world(&fr, out->wi);
  return true;
}

bool vr_bsdf_straight_transmittance(const vr_bsdf *b, double state, double cos_theta, int nwl,
                                    const double *nm, double *T) {
  if (b->kind != VR_BK_PANE && b->kind != VR_BK_CHROMO) return false;
  nwl = clamp_nwl(nwl);
  for (int w = 0; w < nwl; w++) {
    double R;
    vr_bsdfi_pane_rt(b, state, cos_theta, nm[w], &R, &T[w]);
  }
  return true;
}

void vr_bsdf_rta(const vr_bsdf *b, double state, double cos_theta, double nm, double *R,
                 double *T, double *A) {
  double r = 0.0, t = 0.0;
  switch (b->kind) {
  case VR_BK_BLACK:
    break;
  case VR_BK_LAMBERT:
    r = vr_bsdfi_lerp(b->refl, vr_bsdfi_at(b, nm));
    break;
  case VR_BK_TRANSLUCENT:
    r = vr_bsdfi_lerp(b->refl, vr_bsdfi_at(b, nm));
    t = vr_bsdfi_lerp(b->trans, vr_bsdfi_at(b, nm));
    break;
  case VR_BK_CONDUCTOR:
    r = vr_bsdfi_conductor_albedo(b, nm, cos_theta);
    break;
  case VR_BK_PBR:
    r = vr_bsdfi_pbr_albedo(b, nm, cos_theta);
    break;
  case VR_BK_INTERFACE:
    vr_bsdfi_dielectric_rt(b, cos_theta, nm, &r, &t);
    break;
  case VR_BK_PANE:
  case VR_BK_CHROMO:
    vr_bsdfi_pane_rt(b, state, cos_theta, nm, &r, &t);
    break;
  case VR_BK_KLEMS:
    vr_bsdfi_klems_rt(b, cos_theta, &r, &t);
    break;
  }
  *R = r;
  *T = t;
  *A = fmax(0.0, 1.0 - r - t);
}

double vr_bsdf_medium_sigma_a(const vr_bsdf *b, double nm) {
  if (b->kind != VR_BK_INTERFACE) return 0.0;
  return vr_bsdfi_lerp(b->sigma_a, vr_bsdfi_at(b, nm));
}
