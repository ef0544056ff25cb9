/* GGX microfacet BSDFs: distribution, Smith masking, rough dielectric and
 * conductor, visible-normal sampling.  Conventions are in vr/microfacet.h.
 *
 * The dielectric code works in a frame mirrored (z -> -z) so that wo is
 * always above; the relative index then becomes the index on wi's side of
 * the mirrored interface over wo's side.  Mirroring is an exact symmetry of
 * the isotropic distribution, so no case is written twice. */
#include "vr/microfacet.h"

#include <math.h>

static double sq(double x) { return x * x; }
static double dot(vr_vec3 a, vr_vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static vr_vec3 v3(double x, double y, double z) { return (vr_vec3){x, y, z}; }
static vr_vec3 scale(vr_vec3 a, double s) { return v3(a.x * s, a.y * s, a.z * s); }
static vr_vec3 add(vr_vec3 a, vr_vec3 b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static vr_vec3 mirror(vr_vec3 a) { return v3(a.x, a.y, -a.z); }

/* Unit vector along a; the zero vector stays zero (callers test .z or the
 * length first where that matters). */
static vr_vec3 normalise(vr_vec3 a) {
  double len = sqrt(dot(a, a));
  return len > 0.0 ? scale(a, 1.0 / len) : a;
}

static double clamp_alpha(double alpha) {
  /* fmax also maps NaN to the minimum. */
  return fmax(alpha, VR_GGX_ALPHA_MIN);
}

/* Unpolarised Fresnel reflectance for a ray meeting a microfacet at
 * |cos_i| from the medium of index n1 into n2 (relative index n2/n1 is all
 * that matters for a transparent n1, so n1 = 1). */
static double fresnel(vr_complex n_rel, double cos_i) {
  vr_fresnel f;
  vr_fresnel_interface(1.0, n_rel, acos(fmin(1.0, fabs(cos_i))), &f);
  return 0.5 * (f.Rs + f.Rp);
}

double vr_ggx_D(double alpha, double cos_theta_m) {
  if (!(cos_theta_m > 0.0)) return 0.0;
  double a2 = sq(clamp_alpha(alpha));
  double c2 = fmin(1.0, sq(cos_theta_m));
  /* The form alpha^2 / (pi cos^4 (alpha^2 + tan^2)^2) multiplied out: no
   * tangent, so it stays finite at grazing where tan^2 overflows. */
  return a2 / (M_PI * sq(1.0 + (a2 - 1.0) * c2));
}

double vr_ggx_lambda(double alpha, vr_vec3 w) {
  double z2 = sq(w.z);
  if (z2 == 0.0) return INFINITY;
  double a = sq(clamp_alpha(alpha)) * (sq(w.x) + sq(w.y)) / z2; /* alpha^2 tan^2 */
  if (!isfinite(a)) return INFINITY;
  /* (sqrt(1 + a) - 1) / 2 without the cancellation near the normal. */
  return a / (2.0 * (1.0 + sqrt(1.0 + a)));
}

/* Whether m (upper hemisphere) faces w when seen from w's own side. */
static int faces(vr_vec3 w, vr_vec3 m) { return m.z > 0.0 && dot(w, m) * w.z > 0.0; }

double vr_ggx_G1(double alpha, vr_vec3 w, vr_vec3 m) {
  if (!faces(w, m)) return 0.0;
  return 1.0 / (1.0 + vr_ggx_lambda(alpha, w));
}

/* Euler's Beta function B(a, b) for a, b >= 1, through log-gamma (the
 * reentrant lgamma_r: plain lgamma writes the global signgam). */
static double beta_fn(double a, double b) {
  if (isinf(a) || isinf(b)) return 0.0;
  int sign;
  return exp(lgamma_r(a, &sign) + lgamma_r(b, &sign) - lgamma_r(a + b, &sign));
}

double vr_ggx_G2(double alpha, vr_vec3 wi, vr_vec3 wo, vr_vec3 m) {
  if (!faces(wi, m) || !faces(wo, m)) return 0.0;
  double li = vr_ggx_lambda(alpha, wi), lo = vr_ggx_lambda(alpha, wo);
  if (wi.z * wo.z > 0.0) return 1.0 / (1.0 + li + lo);
  return beta_fn(1.0 + li, 1.0 + lo);
}

double vr_ggx_reflection(double alpha, vr_vec3 wi, vr_vec3 wo) {
  if (!(wi.z > 0.0 && wo.z > 0.0)) return 0.0;
  vr_vec3 h = normalise(add(wi, wo));
  double g = vr_ggx_G2(alpha, wi, wo, h);
  /* G2 is exactly 0 once a cosine is too small for its square (Lambda is
   * infinite); above that the quotients below stay finite. */
  if (g == 0.0) return 0.0;
  return vr_ggx_D(alpha, h.z) * (g / (4.0 * wi.z)) / wo.z;
}

double vr_ggx_conductor_brdf(double alpha, vr_complex N, vr_vec3 wi, vr_vec3 wo) {
  double f = vr_ggx_reflection(alpha, wi, wo);
  if (f == 0.0) return 0.0;
  return fresnel(N, dot(wi, normalise(add(wi, wo)))) * f;
}

/* Mirrors the pair so that wo is above and returns the relative index seen
 * from wo's side; 0 for an invalid eta. */
static double upper_frame(double eta, vr_vec3 *wo, vr_vec3 *wi) {
  if (!(eta > 0.0) || !isfinite(eta)) return 0.0;
  if (wo->z < 0.0) {
    *wo = mirror(*wo);
    *wi = mirror(*wi);
    return 1.0 / eta;
  }
  return eta;
}

double vr_ggx_dielectric_brdf(double alpha, double eta, vr_vec3 wi, vr_vec3 wo) {
  double e = upper_frame(eta, &wo, &wi);
  if (e == 0.0 || !(wi.z > 0.0 && wo.z > 0.0)) return 0.0;
  double f = vr_ggx_reflection(alpha, wi, wo);
  if (f == 0.0) return 0.0;
  return fresnel(e, dot(wo, normalise(add(wi, wo)))) * f;
}

/* Generalised half vector of a refraction between wo (above, index 1) and wi
 * (below, index e), turned towards +z (Walter 2007).  Returns 0 when it
 * does not exist (e == 1 and wi == -wo) or when the microfacet would be
 * back-facing for either ray (it must face each ray from that ray's side). */
static int refraction_half(double e, vr_vec3 wo, vr_vec3 wi, vr_vec3 *h) {
  vr_vec3 v = scale(add(scale(wi, e), wo), -1.0);
  double len = sqrt(dot(v, v));
  if (!(len > 0.0)) return 0;
  *h = scale(v, (v.z < 0.0 ? -1.0 : 1.0) / len);
  return h->z > 0.0 && dot(wo, *h) > 0.0 && dot(wi, *h) < 0.0;
}

double vr_ggx_dielectric_btdf(double alpha, double eta, vr_vec3 wi, vr_vec3 wo,
                              vr_transport mode) {
  double e = upper_frame(eta, &wo, &wi);
  vr_vec3 h;
  if (e == 0.0 || e == 1.0 || !(wo.z > 0.0 && wi.z < 0.0)) return 0.0;
  if (!refraction_half(e, wo, wi, &h)) return 0.0;
  double ci = dot(wi, h), co = dot(wo, h);
  double T = 1.0 - fresnel(e, co);
  double g = vr_ggx_G2(alpha, wi, wo, h);
  if (T <= 0.0 || g == 0.0) return 0.0;
  /* Walter eq. 21 with n_o = 1 (wo's side) and n_i = e: this is the
   * radiance BTDF for light going from wi to wo; the adjoint carries e^2. */
  double f = fabs(ci) * co * T * vr_ggx_D(alpha, h.z) * (g / -wi.z) / (wo.z * sq(e * ci + co));
  return mode == VR_TRANSPORT_IMPORTANCE ? f * e * e : f;
}

vr_vec3 vr_ggx_sample_vndf(double alpha, vr_vec3 wo, double u1, double u2) {
  if (!(wo.z > 0.0)) return v3(0.0, 0.0, 1.0);
  double a = clamp_alpha(alpha);
  /* Stretch the view into the frame where the microsurface is the upper
   * half of a unit sphere; the visible normals there are uniformly
   * distributed over the disc projected along the view. */
  vr_vec3 v = normalise(v3(a * wo.x, a * wo.y, wo.z));
  double len2 = sq(v.x) + sq(v.y);
  vr_vec3 t1 = len2 > 0.0 ? scale(v3(-v.y, v.x, 0.0), 1.0 / sqrt(len2)) : v3(1.0, 0.0, 0.0);
  vr_vec3 t2 = v3(v.y * t1.z - v.z * t1.y, v.z * t1.x - v.x * t1.z, v.x * t1.y - v.y * t1.x);
  /* A uniform point of the disc; the half of it hidden behind the sphere's
   * rim when the view is tilted is squeezed onto the visible ellipse. */
  double r = sqrt(u1), phi = 2.0 * M_PI * u2;
  double p1 = r * cos(phi), p2 = r * sin(phi);
  double s = 0.5 * (1.0 + v.z);
  p2 = (1.0 - s) * sqrt(fmax(0.0, 1.0 - p1 * p1)) + s * p2;
  double p3 = sqrt(fmax(0.0, 1.0 - p1 * p1 - p2 * p2));
  vr_vec3 n = add(add(scale(t1, p1), scale(t2, p2)), scale(v, p3));
  /* Back to the rough frame (normals transform with the inverse stretch). */
  return normalise(v3(a * n.x, a * n.y, fmax(0.0, n.z)));
}

double vr_ggx_vndf_pdf(double alpha, vr_vec3 wo, vr_vec3 m) {
  if (!(wo.z > 0.0) || !(m.z > 0.0)) return 0.0;
  double c = dot(wo, m);
  if (!(c > 0.0)) return 0.0;
  return vr_ggx_G1(alpha, wo, m) * c * vr_ggx_D(alpha, m.z) / wo.z;
}

double vr_ggx_reflection_pdf(double alpha, vr_vec3 wo, vr_vec3 wi) {
  if (!(wo.z > 0.0 && wi.z > 0.0)) return 0.0;
  vr_vec3 h = normalise(add(wi, wo));
  double c = dot(wo, h);
  return c > 0.0 ? vr_ggx_vndf_pdf(alpha, wo, h) / (4.0 * c) : 0.0;
}

int vr_ggx_conductor_sample(double alpha, vr_complex N, vr_vec3 wo, double u1, double u2,
                            vr_ggx_sample *s) {
  if (!(wo.z > 0.0)) return 0;
  vr_vec3 m = vr_ggx_sample_vndf(alpha, wo, u1, u2);
  double c = dot(wo, m), pm = vr_ggx_vndf_pdf(alpha, wo, m);
  if (!(c > 0.0) || !(pm > 0.0)) return 0;
  vr_vec3 wi = add(scale(m, 2.0 * c), scale(wo, -1.0));
  if (!(wi.z > 0.0)) return 0;
  s->wi = wi;
  s->pdf = pm / (4.0 * c);
  s->weight = fresnel(N, c) * vr_ggx_G2(alpha, wi, wo, m) / vr_ggx_G1(alpha, wo, m);
  s->transmitted = 0;
  return 1;
}

int vr_ggx_dielectric_sample(double alpha, double eta, vr_vec3 wo, double u1, double u2,
                             double u3, vr_transport mode, vr_ggx_sample *s) {
  vr_vec3 dummy = wo;
  int below = wo.z < 0.0;
  double e = upper_frame(eta, &wo, &dummy);
  if (e == 0.0 || !(wo.z > 0.0)) return 0;
  if (e == 1.0) { /* index-matched: no interface */
    *s = (vr_ggx_sample){scale(below ? mirror(wo) : wo, -1.0), 1.0, INFINITY, 1};
    return 1;
  }
  vr_vec3 m = vr_ggx_sample_vndf(alpha, wo, u1, u2);
  double c = dot(wo, m), pm = vr_ggx_vndf_pdf(alpha, wo, m);
  if (!(c > 0.0) || !(pm > 0.0)) return 0;
  double F = fresnel(e, c);
  vr_vec3 wi;
  if (u3 < F) {
    wi = add(scale(m, 2.0 * c), scale(wo, -1.0));
    if (!(wi.z > 0.0)) return 0;
    s->pdf = F * pm / (4.0 * c);
    s->weight = vr_ggx_G2(alpha, wi, wo, m) / vr_ggx_G1(alpha, wo, m);
    s->transmitted = 0;
  } else {
    /* Snell at the microfacet; F < 1 here, so the root exists. */
    double sin2_t = (1.0 - c * c) / (e * e);
    if (!(sin2_t < 1.0)) return 0;
    double cos_t = sqrt(1.0 - sin2_t);
    wi = normalise(add(scale(wo, -1.0 / e), scale(m, c / e - cos_t)));
    if (!(wi.z < 0.0)) return 0;
    double ci = dot(wi, m);
    /* |d m / d wi| for refraction (Walter 2007), n_o = 1, n_i = e. */
    s->pdf = (1.0 - F) * pm * e * e * fabs(ci) / sq(e * ci + c);
    s->weight = vr_ggx_G2(alpha, wi, wo, m) / vr_ggx_G1(alpha, wo, m);
    if (mode == VR_TRANSPORT_RADIANCE) s->weight /= e * e;
    s->transmitted = 1;
  }
  if (!(s->weight > 0.0) || !(s->pdf > 0.0)) return 0;
  s->wi = below ? mirror(wi) : wi;
  return 1;
}

double vr_ggx_dielectric_pdf(double alpha, double eta, vr_vec3 wo, vr_vec3 wi) {
  double e = upper_frame(eta, &wo, &wi);
  if (e == 0.0 || e == 1.0 || !(wo.z > 0.0) || wi.z == 0.0) return 0.0;
  if (wi.z > 0.0) {
    vr_vec3 h = normalise(add(wi, wo));
    return fresnel(e, dot(wo, h)) * vr_ggx_reflection_pdf(alpha, wo, wi);
  }
  vr_vec3 h;
  if (!refraction_half(e, wo, wi, &h)) return 0.0;
  double ci = dot(wi, h), co = dot(wo, h);
  double T = 1.0 - fresnel(e, co);
  return T * vr_ggx_vndf_pdf(alpha, wo, h) * e * e * fabs(ci) / sq(e * ci + co);
}
