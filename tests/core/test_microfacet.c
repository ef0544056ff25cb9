/* GGX microfacet BSDFs against published identities: the normalisations of D
 * and of the visible normals, reciprocity, the smooth-surface limit (the
 * Fresnel equations of vr/optics.h), energy bounds, and the sampler checked
 * against quadrature.  Quadratures here are written independently of the
 * library: they only call its evaluation functions. */
#include "vr_test.h"
#include "vr/microfacet.h"
#include "vr/optics.h"

#define DEG (M_PI / 180.0)

static double dot3(vr_vec3 a, vr_vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static vr_vec3 lin(vr_vec3 a, double s, vr_vec3 b, double t) {
  return (vr_vec3){s * a.x + t * b.x, s * a.y + t * b.y, s * a.z + t * b.z};
}
static vr_vec3 polar(double theta, double phi) {
  return (vr_vec3){sin(theta) * cos(phi), sin(theta) * sin(phi), cos(theta)};
}

/* splitmix64 (Steele, Lea, Flood 2014), a fixed seed per test. */
static double rnd(uint64_t *s) {
  uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return (double)((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
}

/* Integral of g(m) over the upper hemisphere of normals, midpoint rule in
 * (u, phi) with tan(theta_m) = alpha tan(pi u / 2), which crowds the nodes
 * where a distribution of width alpha has its mass. */
typedef double (*normal_fn)(vr_vec3 m, const void *ctx);
static double integrate_normals(double alpha, int nu, int nphi, normal_fn g, const void *ctx) {
  double sum = 0.0;
  for (int i = 0; i < nu; i++) {
    double t = tan(0.5 * M_PI * (i + 0.5) / nu), th = atan(alpha * t);
    double jac = 0.5 * M_PI * alpha * (1.0 + t * t) / (1.0 + alpha * alpha * t * t);
    for (int j = 0; j < nphi; j++)
      sum += g(polar(th, 2.0 * M_PI * (j + 0.5) / nphi), ctx) * sin(th) * jac;
  }
  return sum * 2.0 * M_PI / ((double)nu * nphi);
}

typedef struct ctx {
  double alpha, eta;
  vr_complex N;
  vr_vec3 wo;
  int kind;
  vr_transport mode;
} ctx;
enum { MIRROR, CONDUCTOR, DIEL_R, DIEL_T, VIS_NORMAL, VNDF_PDF, VNDF_X, ACCEPT };

/* Integrands over the microfacet normal m (turned to face wo's side): the
 * scattered direction is the mirror or Snell image of wo at m, and
 * d wi = |d wi / d m| d m with 4 |wo.m| for reflection and
 * (n_o wo.m + n_i wi.m)^2 / (n_i^2 |wi.m|) for refraction (Walter 2007). */
static double scatter_fn(vr_vec3 m, const void *p) {
  const ctx *c = p;
  double a = c->alpha;
  vr_vec3 wo = c->wo, mm = wo.z > 0.0 ? m : lin(m, -1.0, m, 0.0);
  double co = dot3(wo, mm);
  if (c->kind == VIS_NORMAL) return vr_ggx_D(a, m.z) * vr_ggx_G1(a, wo, m) * fmax(0.0, co);
  if (c->kind == VNDF_PDF) return vr_ggx_vndf_pdf(a, wo, m);
  if (c->kind == VNDF_X) return m.x * vr_ggx_vndf_pdf(a, wo, m);
  if (co <= 0.0) return 0.0;
  vr_vec3 r = lin(mm, 2.0 * co, wo, -1.0);
  double no = wo.z > 0.0 ? 1.0 : c->eta, ni = wo.z > 0.0 ? c->eta : 1.0, e = ni / no;
  double sin2 = (1.0 - co * co) / (e * e);
  vr_vec3 t = lin(wo, -1.0 / e, mm, co / e - sqrt(fmax(0.0, 1.0 - sin2)));
  double ct = dot3(t, mm), jt = (no * co + ni * ct) * (no * co + ni * ct) / (ni * ni * fabs(ct));
  switch (c->kind) {
  case MIRROR: return vr_ggx_reflection(a, r, wo) * fabs(r.z) * 4.0 * co;
  case CONDUCTOR: return vr_ggx_conductor_brdf(a, c->N, r, wo) * fabs(r.z) * 4.0 * co;
  case DIEL_R: return vr_ggx_dielectric_brdf(a, c->eta, r, wo) * fabs(r.z) * 4.0 * co;
  case DIEL_T:
    return sin2 >= 1.0 ? 0.0 : vr_ggx_dielectric_btdf(a, c->eta, t, wo, c->mode) * fabs(t.z) * jt;
  default: { /* probability that the sampler keeps the ray */
    vr_fresnel f;
    vr_fresnel_interface(no, ni, acos(co), &f);
    double F = 0.5 * (f.Rs + f.Rp), keep = F * (r.z * wo.z > 0.0);
    if (sin2 < 1.0) keep += (1.0 - F) * (t.z * wo.z < 0.0);
    /* The sampler works with wo mirrored above (z -> -z). */
    vr_vec3 wu = {wo.x, wo.y, fabs(wo.z)}, mu = {mm.x, mm.y, fabs(mm.z)};
    return keep * vr_ggx_vndf_pdf(a, wu, mu);
  }
  }
}

static double quad(ctx c, int nu, int nphi) { return integrate_normals(c.alpha, nu, nphi, scatter_fn, &c); }

static double d_fn(vr_vec3 m, const void *p) { return vr_ggx_D(*(const double *)p, m.z) * m.z; }

static void d_projected_area_is_one(void **state) {
  (void)state;
  /* Walter et al. 2007 eq. 4: the projected area of the microfacets is the
   * macro area, integral of D(m) cos(theta_m) d omega_m = 1. */
  double alphas[] = {1e-4, 1e-3, 0.05, 0.3, 1.0, 3.0};
  for (size_t i = 0; i < sizeof alphas / sizeof *alphas; i++)
    assert_near(integrate_normals(alphas[i], 4000, 4, d_fn, &alphas[i]), 1.0, 1e-7);
  /* Walter eq. 33 at the pole and at grazing: 1 / (pi alpha^2), alpha^2 / pi. */
  assert_rel(vr_ggx_D(0.2, 1.0), 1.0 / (M_PI * 0.04), 1e-14);
  assert_rel(vr_ggx_D(0.2, 0.0 + 1e-300), 0.04 / M_PI, 1e-14);
  assert_true(vr_ggx_D(0.2, 0.0) == 0.0 && vr_ggx_D(0.2, -0.3) == 0.0);
}

static void visible_normals_project_to_cos(void **state) {
  (void)state;
  /* Heitz 2014 eq. 2: the visible projected area of the microfacets equals
   * the projected macro area, integral of G1(v,m) max(0,v.m) D(m) = cos v. */
  double alphas[] = {0.05, 0.3, 1.0, 2.0}, thetas[] = {0, 20, 45, 70, 85};
  for (size_t i = 0; i < 4; i++)
    for (size_t j = 0; j < 5; j++) {
      ctx c = {.alpha = alphas[i], .wo = polar(thetas[j] * DEG, 0.3), .kind = VIS_NORMAL};
      assert_near(quad(c, 400, 400), cos(thetas[j] * DEG), 2e-5);
    }
  /* Heitz 2014 eq. 86, GGX: Lambda = (sqrt(1 + alpha^2 tan^2) - 1) / 2, so
   * alpha = 1 at 60 deg gives Lambda = 1/2 and G1 = 2/3. */
  vr_vec3 z = {0, 0, 1};
  assert_near(vr_ggx_G1(1.0, polar(60 * DEG, 1.0), z), 2.0 / 3.0, 1e-15);
  assert_true(vr_ggx_lambda(0.5, z) == 0.0);
  assert_true(isinf(vr_ggx_lambda(0.5, (vr_vec3){1, 0, 0})));
  assert_true(vr_ggx_G1(0.5, (vr_vec3){1, 0, 0}, z) == 0.0);
}

static void vndf_sampling_matches_its_pdf(void **state) {
  (void)state;
  /* The pdf integrates to 1 (Heitz 2018, D_wo is a density), and the
   * sampler's moments match those of the pdf. */
  uint64_t seed = 42;
  double alphas[] = {0.1, 0.5, 1.0}, thetas[] = {0, 40, 80};
  for (size_t i = 0; i < 3; i++)
    for (size_t j = 0; j < 3; j++) {
      ctx c = {.alpha = alphas[i], .wo = polar(thetas[j] * DEG, 0.0), .kind = VNDF_PDF};
      assert_near(quad(c, 400, 400), 1.0, 2e-5);
      c.kind = VNDF_X;
      double mx = quad(c, 400, 400), sx = 0.0;
      const int n = 1 << 18;
      for (int k = 0; k < n; k++) {
        vr_vec3 m = vr_ggx_sample_vndf(c.alpha, c.wo, rnd(&seed), rnd(&seed));
        assert_true(m.z >= 0.0 && dot3(m, c.wo) >= -1e-15);
        sx += m.x;
      }
      assert_near(sx / n, mx, 4e-3);
    }
}

static void reciprocity(void **state) {
  (void)state;
  /* Helmholtz reciprocity for reflection, and for refraction the
   * generalised form f(i->o) / n_o^2 = f(o->i) / n_i^2 (Veach 1997, thesis
   * ch. 5), with the adjoint (importance) BSDF f*(i,o) = f(o,i). */
  uint64_t seed = 7;
  vr_complex gold = 0.27 + 2.78 * I;
  for (int k = 0; k < 2000; k++) {
    double a = 0.05 + rnd(&seed), eta = 1.5;
    vr_vec3 u = polar(acos(rnd(&seed)), 2 * M_PI * rnd(&seed));
    vr_vec3 v = polar(acos(rnd(&seed)), 2 * M_PI * rnd(&seed));
    assert_rel(vr_ggx_conductor_brdf(a, gold, u, v), vr_ggx_conductor_brdf(a, gold, v, u), 1e-12);
    assert_rel(vr_ggx_dielectric_brdf(a, eta, u, v), vr_ggx_dielectric_brdf(a, eta, v, u), 1e-12);
    vr_vec3 d = {u.x, u.y, -u.z}, dv = {v.x, v.y, -v.z};
    assert_rel(vr_ggx_dielectric_brdf(a, eta, d, dv), vr_ggx_dielectric_brdf(a, eta, dv, d), 1e-12);
    /* d inside (index 1.5), v outside (index 1). */
    double in_out = vr_ggx_dielectric_btdf(a, eta, d, v, VR_TRANSPORT_RADIANCE);
    double out_in = vr_ggx_dielectric_btdf(a, eta, v, d, VR_TRANSPORT_RADIANCE);
    /* (the two half vectors are computed from opposite sides: 1e-9) */
    assert_rel(in_out / 1.0, out_in / (eta * eta), 1e-9);
    assert_rel(vr_ggx_dielectric_btdf(a, eta, d, v, VR_TRANSPORT_IMPORTANCE), out_in, 1e-9);
  }
}

static void smooth_limit_is_fresnel(void **state) {
  (void)state;
  /* alpha = 1e-3: directional R and T albedos equal the flat-interface
   * Fresnel R and T (vr_fresnel_interface, unpolarised), from both sides;
   * past the critical angle 41.81 deg from inside, R = 1.  In radiance mode
   * T is scaled by (n_o / n_i)^2. */
  double eta = 1.5, th[] = {0, 30, 60, 80, 0, 30, 40, 50, 70};
  for (int k = 0; k < 9; k++) {
    int inside = k >= 4;
    vr_vec3 wo = polar(th[k] * DEG, 0.7);
    if (inside) wo.z = -wo.z;
    vr_fresnel f;
    vr_fresnel_interface(inside ? eta : 1.0, inside ? 1.0 : eta, th[k] * DEG, &f);
    ctx c = {.alpha = 1e-3, .eta = eta, .wo = wo, .kind = DIEL_R};
    double R = quad(c, 400, 64);
    c.kind = DIEL_T;
    c.mode = VR_TRANSPORT_IMPORTANCE;
    double T = quad(c, 400, 64);
    c.mode = VR_TRANSPORT_RADIANCE;
    double Trad = quad(c, 400, 64), ratio = inside ? eta * eta : 1.0 / (eta * eta);
    assert_near(R, 0.5 * (f.Rs + f.Rp), 1e-2);
    assert_near(T, 0.5 * (f.Ts + f.Tp), 1e-2);
    assert_near(Trad, ratio * 0.5 * (f.Ts + f.Tp), 1e-2 * ratio);
  }
}

static void conductor_energy(void **state) {
  (void)state;
  /* Single-scattering albedo E(mu) of a perfect reflector (F = 1).  It
   * cannot exceed 1 since G2 <= G1 and D_wo integrates to 1 (Heitz 2014),
   * and it tends to 1 as alpha -> 0.
   * Exact value for alpha = 1: D = 1/pi (Walter eq. 33), Lambda(w) =
   * (1/cos - 1)/2 (Heitz 2014 eq. 86) and G2 = 1/(1 + Lambda_i + Lambda_o)
   * (eq. 99) reduce the integral of f cos over the hemisphere to
   * int_0^1 x/(x + mu) dx = 1 - mu ln(1 + 1/mu); at normal incidence
   * 1 - ln 2 = 0.3069: the loss is largest at normal incidence for this
   * roughness, not at grazing. */
  double alphas[] = {1e-3, 0.05, 0.1, 0.2, 0.4, 0.6, 0.8, 1.0}, mus[] = {1.0, 0.8, 0.5, 0.3, 0.1};
  double E[8][5];
  for (int i = 0; i < 8; i++)
    for (int j = 0; j < 5; j++) {
      ctx c = {.alpha = alphas[i], .wo = polar(acos(mus[j]), 0.0), .kind = MIRROR};
      E[i][j] = quad(c, 400, 200);
      assert_true(E[i][j] <= 1.0 + 1e-5);
      if (i == 0) assert_true(E[i][j] > 0.9999);
      /* Monotone decrease with roughness away from grazing; near grazing
       * it is not (0.911, 0.883, 0.891 at mu = 0.1 for alpha = 0.05, 0.1,
       * 0.2): rougher lobes spread the reflection out of the shadowed
       * grazing band. */
      if (i > 0 && mus[j] >= 0.3) assert_true(E[i][j] < E[i - 1][j]);
    }
  for (int j = 0; j < 5; j++) assert_near(E[7][j], 1.0 - mus[j] * log(1.0 + 1.0 / mus[j]), 1e-4);
}

/* Monte Carlo albedo from the sampler, with a check of each sample's pdf and
 * weight against the evaluation functions. */
static void mc_albedo(const ctx *c, int n, uint64_t *seed, double *albedo, double *kept) {
  double sum = 0.0;
  int nk = 0;
  for (int k = 0; k < n; k++) {
    vr_ggx_sample s;
    double u1 = rnd(seed), u2 = rnd(seed), u3 = rnd(seed);
    int ok = c->kind == CONDUCTOR ? vr_ggx_conductor_sample(c->alpha, c->N, c->wo, u1, u2, &s)
                                  : vr_ggx_dielectric_sample(c->alpha, c->eta, c->wo, u1, u2, u3,
                                                             c->mode, &s);
    if (!ok) continue;
    nk++;
    sum += s.weight;
    assert_rel(dot3(s.wi, s.wi), 1.0, 1e-12);
    double f, pdf;
    if (c->kind == CONDUCTOR) {
      f = vr_ggx_conductor_brdf(c->alpha, c->N, s.wi, c->wo);
      pdf = vr_ggx_reflection_pdf(c->alpha, c->wo, s.wi);
    } else {
      f = s.transmitted ? vr_ggx_dielectric_btdf(c->alpha, c->eta, s.wi, c->wo, c->mode)
                        : vr_ggx_dielectric_brdf(c->alpha, c->eta, s.wi, c->wo);
      pdf = vr_ggx_dielectric_pdf(c->alpha, c->eta, c->wo, s.wi);
      assert_int_equal(s.transmitted, s.wi.z * c->wo.z < 0.0);
    }
    assert_rel(s.pdf, pdf, 1e-6);
    assert_rel(s.weight, f * fabs(s.wi.z) / pdf, 1e-6);
  }
  *albedo = sum / n;
  *kept = (double)nk / n;
}

static void sampling_agrees_with_quadrature(void **state) {
  (void)state;
  uint64_t seed = 2024;
  double th[] = {45, 30, 60, 85};
  for (int k = 0; k < 4; k++)
    for (int mode = 0; mode < 2; mode++) {
      vr_vec3 wo = polar(th[k] * DEG, 1.1);
      if (k == 1 || k == 2) wo.z = -wo.z; /* from inside; 60 deg is past critical */
      ctx c = {.alpha = 0.3, .eta = 1.5, .wo = wo, .kind = DIEL_R, .mode = (vr_transport)mode};
      double q = quad(c, 400, 400);
      c.kind = DIEL_T;
      q += quad(c, 400, 400);
      c.kind = ACCEPT;
      double keep = quad(c, 400, 400), mc, kept;
      mc_albedo(&c, 1 << 18, &seed, &mc, &kept);
      assert_near(mc, q, 1e-2);
      assert_near(kept, keep, 1e-2);
      if (mode == VR_TRANSPORT_IMPORTANCE) assert_true(q <= 1.0 + 1e-6);
    }
  ctx c = {.alpha = 0.6, .N = 0.27 + 2.78 * I, .wo = polar(70 * DEG, 0.2), .kind = CONDUCTOR};
  double mc, kept;
  mc_albedo(&c, 1 << 18, &seed, &mc, &kept);
  assert_near(mc, quad(c, 400, 400), 1e-2);
}

static void edge_cases(void **state) {
  (void)state;
  vr_vec3 z = {0, 0, 1}, graze = {1, 0, 0}, below = {0.6, 0, -0.8}, up = polar(40 * DEG, 2.0);
  vr_ggx_sample s;
  /* alpha = 0 (and NaN) are raised to VR_GGX_ALPHA_MIN. */
  assert_true(vr_ggx_D(0.0, 1.0) == vr_ggx_D(VR_GGX_ALPHA_MIN, 1.0));
  assert_true(vr_ggx_D(NAN, 1.0) == vr_ggx_D(VR_GGX_ALPHA_MIN, 1.0));
  assert_true(isfinite(vr_ggx_reflection(0.0, up, up)));
  /* Grazing wo: nothing scattered, no NaN, no sample. */
  assert_true(vr_ggx_reflection(0.5, up, graze) == 0.0);
  assert_true(vr_ggx_dielectric_brdf(0.5, 1.5, up, graze) == 0.0);
  assert_true(vr_ggx_dielectric_btdf(0.5, 1.5, below, graze, VR_TRANSPORT_RADIANCE) == 0.0);
  assert_int_equal(vr_ggx_dielectric_sample(0.5, 1.5, graze, 0.3, 0.3, 0.3, 0, &s), 0);
  assert_int_equal(vr_ggx_conductor_sample(0.5, 2 + I, graze, 0.3, 0.3, &s), 0);
  /* Conductors are one-sided. */
  assert_true(vr_ggx_conductor_brdf(0.5, 2 + I, below, up) == 0.0);
  assert_int_equal(vr_ggx_conductor_sample(0.5, 2 + I, below, 0.3, 0.3, &s), 0);
  /* Total internal reflection from inside at 60 deg (critical 41.8 deg). */
  uint64_t seed = 3;
  vr_vec3 in60 = polar(120 * DEG, 0.4);
  for (int k = 0; k < 1000; k++) {
    assert_int_equal(vr_ggx_dielectric_sample(1e-3, 1.5, in60, rnd(&seed), rnd(&seed),
                                              rnd(&seed), 0, &s), 1);
    assert_true(!s.transmitted && s.wi.z < 0.0 && s.weight > 0.999 && s.weight <= 1.0);
  }
  /* eta = 1: no interface, the ray goes straight on. */
  assert_int_equal(vr_ggx_dielectric_sample(0.5, 1.0, below, 0.2, 0.9, 0.5, 0, &s), 1);
  assert_true(s.transmitted && s.weight == 1.0 && isinf(s.pdf));
  assert_near(s.wi.x, -0.6, 1e-15);
  assert_near(s.wi.z, 0.8, 1e-15);
  assert_true(vr_ggx_dielectric_btdf(0.5, 1.0, (vr_vec3){-0.6, 0, 0.8}, below, 0) == 0.0);
  /* Invalid eta gives nothing. */
  assert_int_equal(vr_ggx_dielectric_sample(0.5, -1.0, up, 0.2, 0.9, 0.5, 0, &s), 0);
  assert_true(vr_ggx_dielectric_brdf(0.5, NAN, up, up) == 0.0);
  /* No NaN or negative value anywhere, near-grazing and near-index-matched
   * included. */
  double alphas[] = {0.0, 1e-4, 1e-3, 0.5, 5.0}, etas[] = {1.5, 1.0 / 1.5, 1.0 + 1e-9, 1.0};
  double zs[] = {1.0, 0.5, 1e-8, 1e-200, 0.0, -1e-200, -1e-8, -0.5, -1.0};
  for (int a = 0; a < 5; a++)
    for (int e = 0; e < 4; e++)
      for (int i = 0; i < 9; i++)
        for (int o = 0; o < 9; o++) {
          double al = alphas[a], et = etas[e];
          vr_vec3 wi = {sqrt(1 - zs[i] * zs[i]), 0, zs[i]};
          vr_vec3 wo = {-0.6 * sqrt(1 - zs[o] * zs[o]), 0.8 * sqrt(1 - zs[o] * zs[o]), zs[o]};
          double v[] = {vr_ggx_dielectric_brdf(al, et, wi, wo),
                        vr_ggx_dielectric_btdf(al, et, wi, wo, 0),
                        vr_ggx_dielectric_btdf(al, et, wi, wo, 1),
                        vr_ggx_dielectric_pdf(al, et, wo, wi),
                        vr_ggx_conductor_brdf(al, 0.2 + 3 * I, wi, wo),
                        vr_ggx_reflection_pdf(al, wo, wi), vr_ggx_G2(al, wi, wo, z)};
          for (int q = 0; q < 7; q++) assert_true(isfinite(v[q]) && v[q] >= 0.0);
          if (vr_ggx_dielectric_sample(al, et, wo, 0.3, 0.7, 0.5, 0, &s))
            assert_true(isfinite(s.weight) && s.weight >= 0.0 && s.pdf > 0.0);
        }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(d_projected_area_is_one),
      cmocka_unit_test(visible_normals_project_to_cos),
      cmocka_unit_test(vndf_sampling_matches_its_pdf),
      cmocka_unit_test(reciprocity),
      cmocka_unit_test(smooth_limit_is_fresnel),
      cmocka_unit_test(conductor_energy),
      cmocka_unit_test(sampling_agrees_with_quadrature),
      cmocka_unit_test(edge_cases),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
