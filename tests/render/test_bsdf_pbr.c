/* The glTF metallic-roughness BRDF (material source pbr) against its
 * definition, the glTF 2.0 specification's Appendix B:
 *   - the dielectric's Fresnel factor at normal incidence is 0.04, the
 *     reflectance of an interface of index 1.5, ((1.5 - 1) / (1.5 + 1))^2,
 *     and Schlick's (1 - cos)^5 law away from it;
 *   - a metal's Fresnel factor is Schlick's with F0 the base colour;
 *   - at normal incidence and normal exitance the rough BRDF is
 *     (1 - F0) C / pi + F0 D(0) / 4 with the GGX D(0) = 1 / (pi alpha^2)
 *     (Walter et al. 2007, eq. 33) and alpha = roughness^2;
 * and against physics and the estimator's own definition: Helmholtz
 * reciprocity, a white smooth metal's albedo 1 at every angle, no albedo
 * above 1, sample weights equal to f cos / pdf, the density integrating to
 * 1, the lobes (only=) adding up to the whole, a point's textures
 * (vr_bsdf_point) acting as the factors they replace. */
#include "bsdf_test_util.h"

static const vr_vec3 Z = {0.0, 0.0, 1.0};

static vr_bsdf *pbr(double reflectance, double metallic, double roughness, bool mapped) {
  vr_scene_material sm = test_sm(NULL);
  sm.source = VR_MATSRC_LAMBERT_CONST;
  sm.reflectance = reflectance;
  sm.pbr = true;
  sm.metallic = metallic;
  sm.pbr_roughness = roughness;
  sm.mr_map = mapped ? (char *)"mr.png" : NULL;
  return make_bsdf(&sm, NULL, NULL);
}

static double schlick(double f0, double c) { return f0 + (1 - f0) * pow(1 - c, 5); }

static void test_closed_forms(void **state) {
  (void)state;
  double nm[2] = {550.0, 430.0};
  /* Rough dielectric over a 0.5 base, alpha = 0.5^2. */
  vr_bsdf *b = pbr(0.5, 0.0, 0.5, false);
  assert_true(vr_bsdf_is_pbr(b));
  assert_int_equal(vr_bsdf_lobes(b), VR_LOBE_DIFFUSE | VR_LOBE_GLOSSY_R);
  double f[2], pdf, a = 0.25;
  vr_bsdf_eval(b, NAN, Z, Z, Z, 2, nm, VR_TRANSPORT_RADIANCE, f, &pdf);
  double expect = (1 - 0.04) * 0.5 / M_PI + 0.04 / (M_PI * a * a) / 4;
  assert_rel(f[0], expect, 1e-12);
  assert_rel(f[1], expect, 1e-12);
  /* The same from below (opaque: it reflects on wo's side). */
  vr_vec3 mz = {0, 0, -1};
  vr_bsdf_eval(b, NAN, Z, mz, mz, 2, nm, VR_TRANSPORT_RADIANCE, f, &pdf);
  assert_rel(f[0], expect, 1e-12);
  vr_bsdf_destroy(b);

  /* A smooth black dielectric is a mirror of Schlick's 0.04 law; the
   * probability of its one lobe is 1, so the weight is the factor. */
  b = pbr(0.0, 0.0, 0.0, false);
  assert_int_equal(vr_bsdf_lobes(b), VR_LOBE_DIFFUSE | VR_LOBE_SPECULAR_R);
  double th[3] = {0, 60, 85};
  for (int t = 0; t < 3; t++) {
    vr_vec3 wo = dir_at(th[t] * DEG, 0.4);
    vr_bsdf_sample s;
    assert_true(vr_bsdf_sample_dir(b, NAN, Z, wo, 2, nm, VR_TRANSPORT_RADIANCE, 0.3, 0.6, 0.5, &s));
    assert_int_equal(s.lobe, VR_LOBE_SPECULAR_R);
    assert_near(s.wi.z, wo.z, 1e-15);
    assert_near(s.wi.x, -wo.x, 1e-15);
    assert_rel(s.weight[0], schlick(0.04, cos(th[t] * DEG)), 1e-12);
    if (t == 0) assert_rel(s.weight[0], 0.04, 1e-12);
  }
  vr_bsdf_destroy(b);

  /* A smooth metal: Schlick with F0 = the base colour (0.8): at 60 deg
   * 0.8 + 0.2 / 32. */
  b = pbr(0.8, 1.0, 0.0, false);
  assert_int_equal(vr_bsdf_lobes(b), VR_LOBE_SPECULAR_R);
  vr_bsdf_sample s;
  assert_true(vr_bsdf_sample_dir(b, NAN, Z, dir_at(60 * DEG, 1.0), 1, nm, VR_TRANSPORT_RADIANCE,
                                 0.5, 0.5, 0.99, &s));
  assert_rel(s.weight[0], 0.80625, 1e-12);
  double R, T, A;
  vr_bsdf_rta(b, NAN, cos(60 * DEG), 550, &R, &T, &A);
  assert_rel(R, 0.80625, 1e-12);
  assert_near(T, 0, 0);
  vr_bsdf_destroy(b);
}

/* Albedo by sampling (mean weight) at nm. */
static double albedo(const vr_bsdf *b, const vr_bsdf_point *pt, vr_vec3 wo, double nm, long n) {
  double sum = 0;
  for (long i = 0; i < n; i++) {
    vr_bsdf_sample s;
    if (vr_bsdf_sample_at(b, pt, NAN, Z, wo, 1, &nm, VR_TRANSPORT_IMPORTANCE, u01(11, i, 0),
                          u01(11, i, 1), u01(11, i, 2), &s))
      sum += s.weight[0];
  }
  return sum / n;
}

/* The same integral through eval only: a midpoint rule over (cos, phi) of
 * the upper hemisphere (the BRDF is smooth for alpha >= 0.25). */
static double albedo_quadrature(const vr_bsdf *b, vr_vec3 wo, double nm, double *pdf_integral) {
  const int nc = 600, np = 400;
  double sum = 0, psum = 0;
  for (int i = 0; i < nc; i++)
    for (int j = 0; j < np; j++) {
      double z = (i + 0.5) / nc, r = sqrt(1 - z * z), phi = 2 * M_PI * (j + 0.5) / np;
      vr_vec3 wi = {r * cos(phi), r * sin(phi), z};
      double f, pdf;
      vr_bsdf_eval(b, NAN, Z, wo, wi, 1, &nm, VR_TRANSPORT_RADIANCE, &f, &pdf);
      sum += f * z;
      psum += pdf;
    }
  double dw = 2 * M_PI / ((double)nc * np);
  *pdf_integral = psum * dw;
  return sum * dw;
}

static void test_energy_and_sampling(void **state) {
  (void)state;
  /* A white smooth metal reflects everything at every angle. */
  vr_bsdf *b = pbr(1.0, 1.0, 0.0, false);
  for (int t = 0; t < 4; t++) {
    double R, T, A;
    vr_bsdf_rta(b, NAN, cos((double[]){0, 40, 80, 89.9}[t] * DEG), 550, &R, &T, &A);
    assert_rel(R, 1.0, 1e-12);
  }
  vr_bsdf_destroy(b);
  double cases[4][3] = {{0.7, 0.0, 0.5}, {0.9, 1.0, 0.6}, {0.4, 0.5, 0.8}, {1.0, 0.0, 1.0}};
  for (int c = 0; c < 4; c++) {
    b = pbr(cases[c][0], cases[c][1], cases[c][2], false);
    for (int t = 0; t < 3; t++) {
      vr_vec3 wo = dir_at((double[]){0, 45, 75}[t] * DEG, 0.2);
      double ip, q = albedo_quadrature(b, wo, 550, &ip), es = albedo(b, NULL, wo, 550, 200000);
      print_message("pbr base %.1f metallic %.1f roughness %.1f theta %2.0f: sampled %.5f, "
                    "quadrature %.5f, density integral %.5f\n",
                    cases[c][0], cases[c][1], cases[c][2], acos(wo.z) / DEG, es, q, ip);
      assert_true(q <= 1.0 + 1e-3);
      assert_true(es <= 1.0 + 1e-2);
      /* 200 000 samples: the weights stay within a few times the mean, so
       * the standard error is under 0.3 %; the quadrature's error is
       * smaller still. */
      assert_near(es, q, 0.01 * q + 1e-4);
      /* The density integrates to 1 less what the mirror reflection of
       * the sampled normals sends below the surface: at normal incidence
       * those are the normals steeper than 45 deg, whose share of GGX's
       * D cos is alpha^2 / (1 + alpha^2) (Walter et al. 2007, eq. 35: tan^2
       * theta_m = alpha^2 u / (1 - u)); for a metal, the integral is
       * 1 / (1 + alpha^2). */
      assert_true(ip <= 1.0 + 2e-3 && ip > 0.8);
      double al = cases[c][2] * cases[c][2];
      if (cases[c][1] == 1.0 && t == 0) assert_near(ip, 1 / (1 + al * al), 2e-3);
    }
    vr_bsdf_destroy(b);
  }
}

static void test_reciprocity_weights_lobes(void **state) {
  (void)state;
  double nm[4] = {450, 520, 600, 680};
  vr_bsdf *b = pbr(0.6, 0.3, 0.45, false);
  vr_vec3 n = {0.0, 0.6, 0.8};
  int checked = 0;
  for (uint64_t i = 0; i < 4000; i++) {
    vr_vec3 wo = dir_at(acos(2 * u01(5, i, 0) - 1), 2 * M_PI * u01(5, i, 1));
    vr_vec3 wi = dir_at(acos(2 * u01(5, i, 2) - 1), 2 * M_PI * u01(5, i, 3));
    double f1[4], f2[4], pdf;
    vr_bsdf_eval(b, NAN, n, wo, wi, 4, nm, VR_TRANSPORT_RADIANCE, f1, &pdf);
    vr_bsdf_eval(b, NAN, n, wi, wo, 4, nm, VR_TRANSPORT_IMPORTANCE, f2, NULL);
    for (int w = 0; w < 4; w++) assert_near(f1[w], f2[w], 1e-12 * (1 + f1[w]));
    /* The lobes add up to the whole. */
    vr_bsdf_point d = vr_bsdf_point_plain(), g = vr_bsdf_point_plain();
    d.only = VR_LOBE_DIFFUSE, g.only = VR_LOBE_GLOSSY_R;
    double fd[4], fg[4];
    vr_bsdf_eval_at(b, &d, NAN, n, wo, wi, 4, nm, VR_TRANSPORT_RADIANCE, fd, NULL);
    vr_bsdf_eval_at(b, &g, NAN, n, wo, wi, 4, nm, VR_TRANSPORT_RADIANCE, fg, NULL);
    for (int w = 0; w < 4; w++) assert_near(fd[w] + fg[w], f1[w], 1e-12 * (1 + f1[w]));
    /* Every sample's weight is f cos / pdf of eval. */
    vr_bsdf_sample s;
    if (!vr_bsdf_sample_dir(b, NAN, n, wo, 4, nm, VR_TRANSPORT_RADIANCE, u01(6, i, 0),
                            u01(6, i, 1), u01(6, i, 2), &s))
      continue;
    double f[4];
    vr_bsdf_eval(b, NAN, n, wo, s.wi, 4, nm, VR_TRANSPORT_RADIANCE, f, &pdf);
    assert_rel(pdf, s.pdf, 1e-9);
    double ci = fabs(vr_vec3_dot(s.wi, n));
    for (int w = 0; w < 4; w++) assert_rel(s.weight[w], f[w] * ci / pdf, 1e-9);
    /* Restricted to the glossy lobe, the sampler never returns a diffuse
     * direction. */
    if (vr_bsdf_sample_at(b, &g, NAN, n, wo, 4, nm, VR_TRANSPORT_RADIANCE, u01(6, i, 0),
                          u01(6, i, 1), u01(6, i, 2), &s))
      assert_int_equal(s.lobe, VR_LOBE_GLOSSY_R);
    checked++;
  }
  assert_true(checked > 1500);
  vr_bsdf_destroy(b);
}

static void test_point_textures(void **state) {
  (void)state;
  double nm[3] = {450, 550, 650};
  /* A map can lower roughness and metallic per point: every lobe. */
  vr_bsdf *b = pbr(1.0, 1.0, 1.0, true);
  assert_int_equal(vr_bsdf_lobes(b), VR_LOBE_DIFFUSE | VR_LOBE_SPECULAR_R | VR_LOBE_GLOSSY_R);
  vr_bsdf *ref = pbr(0.3, 0.25, 0.5, false);
  /* base 1 times a texture of 0.3, factors times 0.25 and 0.5. */
  vr_bsdf_point pt = vr_bsdf_point_plain();
  pt.has_base = true;
  for (int w = 0; w < 3; w++) pt.base[w] = 0.3;
  pt.base_mean = 0.3;
  pt.metallic = 0.25, pt.roughness = 0.5;
  for (uint64_t i = 0; i < 500; i++) {
    vr_vec3 wo = dir_at(acos(u01(8, i, 0)), 2 * M_PI * u01(8, i, 1));
    vr_vec3 wi = dir_at(acos(u01(8, i, 2)), 2 * M_PI * u01(8, i, 3));
    double f[3], fr[3], p1, p2;
    vr_bsdf_eval_at(b, &pt, NAN, Z, wo, wi, 3, nm, VR_TRANSPORT_RADIANCE, f, &p1);
    vr_bsdf_eval(ref, NAN, Z, wo, wi, 3, nm, VR_TRANSPORT_RADIANCE, fr, &p2);
    for (int w = 0; w < 3; w++) assert_near(f[w], fr[w], 1e-12 * (1 + fr[w]));
    assert_near(p1, p2, 1e-12 * (1 + p2));
  }
  /* A point the map makes smooth is a mirror there. */
  pt.roughness = 0;
  vr_bsdf_sample s;
  assert_true(vr_bsdf_sample_at(b, &pt, NAN, Z, Z, 3, nm, VR_TRANSPORT_RADIANCE, 0.5, 0.5, 0.0, &s));
  assert_int_equal(s.lobe, VR_LOBE_SPECULAR_R);
  vr_bsdf_destroy(b);
  vr_bsdf_destroy(ref);
  /* Factors outside [0, 1] are refused, naming the line. */
  vr_scene_material sm = test_sm(NULL);
  sm.source = VR_MATSRC_LAMBERT_CONST;
  sm.reflectance = 0.5;
  sm.pbr = true;
  sm.metallic = 1.5;
  sm.pbr_roughness = 0.5;
  vr_bsdf *bad = NULL;
  vr_error err = {0};
  assert_int_equal(vr_bsdf_create(&sm, NULL, NULL, 360, 830, &bad, &err), VR_E_RANGE);
  assert_non_null(strstr(err.message, "metallic 1.5 outside [0, 1]"));
  assert_non_null(strstr(err.message, "12:3"));
  sm.metallic = 0.5, sm.pbr_roughness = NAN;
  assert_int_equal(vr_bsdf_create(&sm, NULL, NULL, 360, 830, &bad, &err), VR_E_RANGE);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_closed_forms),
      cmocka_unit_test(test_energy_and_sampling),
      cmocka_unit_test(test_reciprocity_weights_lobes),
      cmocka_unit_test(test_point_textures),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
