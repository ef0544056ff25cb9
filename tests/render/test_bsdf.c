/* vr_bsdf, kind by kind: the clear pane against the thick-slab formula
 * (reference figures of the issue: n = 1.52, k = 0 transmits 0.9183 at
 * normal incidence and 0.4560 at 80 deg, T = (1 - R)^2 / (1 - R^2) per
 * polarisation, averaged), gold and silver mirrors against core's
 * vr_fresnel_interface with the database's n, k (Johnson and Christy 1972),
 * the Lambertian sampler, GGX furnace tests, sample weights against
 * eval cos / pdf, dispersion of N-BK7 (Schott formula), the chromogenic
 * state law T(s) = T0 10^(-s dOD) (vr/chromogenic.h), errors naming the
 * scene line, and concurrent use. */
#include "bsdf_test_util.h"

#include <pthread.h>

#include "vr/chromogenic.h"

static const vr_vec3 Z = {0.0, 0.0, 1.0};

/* (1 - R) / (1 + R) per polarisation, averaged: a lossless slab. */
static double lossless_T(double n, double theta) {
  vr_fresnel f;
  vr_fresnel_interface(1.0, n, theta, &f);
  return 0.5 * ((1 - f.Rs) / (1 + f.Rs) + (1 - f.Rp) / (1 + f.Rp));
}

static void test_clear_pane(void **state) {
  (void)state;
  vr_material *m = flat_nk("clear", VR_KIND_DIELECTRIC, 1.52, 0.0);
  vr_scene_material sm = test_sm("clear");
  sm.thickness_m = 0.004;
  vr_bsdf *b = make_bsdf(&sm, m, NULL);
  assert_true(vr_bsdf_is_thin(b));
  assert_false(vr_bsdf_dispersive(b));
  assert_int_equal(vr_bsdf_lobes(b), VR_LOBE_SPECULAR_R | VR_LOBE_STRAIGHT);
  double nm[3] = {550.0, 400.5, 700.25}, T[3];
  assert_true(vr_bsdf_straight_transmittance(b, NAN, 1.0, 3, nm, T));
  for (int w = 0; w < 3; w++) assert_near(T[w], 0.9183, 1e-3);
  assert_near(T[0], lossless_T(1.52, 0.0), 1e-9);
  assert_true(vr_bsdf_straight_transmittance(b, NAN, cos(80 * DEG), 3, nm, T));
  for (int w = 0; w < 3; w++) assert_near(T[w], 0.4560, 1e-3);
  assert_near(T[0], lossless_T(1.52, 80 * DEG), 2e-5);
  /* From behind: the same pane. */
  double Tb[3];
  assert_true(vr_bsdf_straight_transmittance(b, NAN, -cos(80 * DEG), 3, nm, Tb));
  assert_near(Tb[0], T[0], 1e-15);
  /* Sampling: transmission straight through, reflection mirrored, the
   * expectation over the lobe choice is R and T. */
  vr_vec3 wo = dir_at(30 * DEG, 0.7);
  double R, Tt, A;
  vr_bsdf_rta(b, NAN, wo.z, 550.0, &R, &Tt, &A);
  vr_bsdf_sample s;
  assert_true(vr_bsdf_sample_dir(b, NAN, Z, wo, 1, nm, VR_TRANSPORT_RADIANCE, 0.1, 0.2, 0.999, &s));
  assert_int_equal(s.lobe, VR_LOBE_STRAIGHT);
  assert_near(s.wi.x, -wo.x, 1e-15);
  assert_near(s.wi.z, -wo.z, 1e-15);
  assert_near(s.pdf * s.weight[0], Tt, 1e-12);
  assert_near(s.eta, 1.0, 0);
  assert_true(vr_bsdf_sample_dir(b, NAN, Z, wo, 1, nm, VR_TRANSPORT_RADIANCE, 0.1, 0.2, 0.0, &s));
  assert_int_equal(s.lobe, VR_LOBE_SPECULAR_R);
  assert_near(s.wi.z, wo.z, 1e-15);
  assert_near(s.wi.x, -wo.x, 1e-15);
  assert_near(s.pdf * s.weight[0], R, 1e-12);
  /* Delta lobes only: eval gives nothing. */
  double f[1] = {-1}, pdf = -1;
  vr_bsdf_eval(b, NAN, Z, wo, s.wi, 1, nm, VR_TRANSPORT_RADIANCE, f, &pdf);
  assert_true(f[0] == 0.0 && pdf == 0.0);
  vr_bsdf_destroy(b);
  vr_material_destroy(m);
}

/* Mirrors of the database's metals against core's Fresnel equations. */
static void check_mirror(vr_matdb *db, const char *name) {
  vr_material *m = db_load(db, name);
  vr_scene_material sm = test_sm(name);
  vr_bsdf *b = make_bsdf(&sm, m, NULL);
  assert_int_equal(vr_bsdf_lobes(b), VR_LOBE_SPECULAR_R);
  assert_false(vr_bsdf_straight_transmittance(b, NAN, 1.0, 1, (double[]){500}, (double[1]){0}));
  double nm[2] = {500.0, 600.0};
  double angles[2] = {0.0, 45.0};
  for (int a = 0; a < 2; a++) {
    vr_vec3 wo = dir_at(angles[a] * DEG, 1.1);
    vr_bsdf_sample s;
    assert_true(vr_bsdf_sample_dir(b, NAN, Z, wo, 2, nm, VR_TRANSPORT_RADIANCE, 0.3, 0.3, 0.3, &s));
    assert_int_equal(s.lobe, VR_LOBE_SPECULAR_R);
    assert_near(s.wi.z, wo.z, 1e-15);
    for (int w = 0; w < 2; w++) {
      double n, k, R, T, A;
      assert_int_equal(vr_material_nk(m, nm[w], false, &n, &k, NULL, NULL), VR_OK);
      vr_fresnel f;
      vr_fresnel_interface(1.0, n + I * k, angles[a] * DEG, &f);
      double expect = 0.5 * (f.Rs + f.Rp);
      assert_near(s.weight[w], expect, 1e-9);
      vr_bsdf_rta(b, NAN, cos(angles[a] * DEG), nm[w], &R, &T, &A);
      assert_near(R, expect, 1e-9);
      assert_true(T == 0.0);
    }
    /* Seen from behind, a metal still reflects. */
    vr_vec3 back = {wo.x, wo.y, -wo.z};
    assert_true(
        vr_bsdf_sample_dir(b, NAN, Z, back, 2, nm, VR_TRANSPORT_RADIANCE, 0.3, 0.3, 0.3, &s));
    assert_near(s.wi.z, back.z, 1e-15);
  }
  vr_bsdf_destroy(b);
  vr_material_destroy(m);
}

static void test_metal_mirrors(void **state) {
  (void)state;
  char path[64];
  vr_matdb *db = temp_db(path, sizeof path);
  check_mirror(db, "Au");
  check_mirror(db, "Ag");
  temp_db_close(db, path);
}

static double grey_ramp(double nm) { return 0.2 + 0.6 * (nm - 300.0) / 600.0; }

static void test_lambertian(void **state) {
  (void)state;
  vr_scene_material sm = test_sm(NULL);
  sm.source = VR_MATSRC_LAMBERT_CONST;
  sm.reflectance = 0.6;
  vr_bsdf *b = make_bsdf(&sm, NULL, NULL);
  vr_material *m = vr_material_create("ramp", VR_KIND_REFLECTANCE, NULL);
  vr_material_add_spectrum(m, "value", spectrum_of(grey_ramp), NULL);
  vr_scene_material sm2 = test_sm("ramp");
  vr_bsdf *b2 = make_bsdf(&sm2, m, NULL);
  assert_int_equal(vr_bsdf_lobes(b), VR_LOBE_DIFFUSE);
  vr_vec3 n = {0.6, 0.0, 0.8}; /* a tilted surface */
  double nm[3] = {450.0, 550.0, 650.0};
  for (uint64_t i = 0; i < 2000; i++) {
    vr_vec3 wo = dir_at(acos(u01(1, i, 0)), 2 * M_PI * u01(1, i, 1));
    vr_vec3 wo_w = {0.8 * wo.x + 0.6 * wo.z, wo.y, -0.6 * wo.x + 0.8 * wo.z}; /* into n's frame */
    if (i % 3 == 0) wo_w = (vr_vec3){-wo_w.x, -wo_w.y, -wo_w.z};              /* and from behind */
    vr_bsdf_sample s;
    assert_true(vr_bsdf_sample_dir(b, NAN, n, wo_w, 3, nm, VR_TRANSPORT_RADIANCE, u01(2, i, 0),
                                   u01(2, i, 1), u01(2, i, 2), &s));
    double ci = s.wi.x * n.x + s.wi.y * n.y + s.wi.z * n.z;
    double co = wo_w.x * n.x + wo_w.y * n.y + wo_w.z * n.z;
    assert_true(ci * co > 0.0);
    assert_near(s.wi.x * s.wi.x + s.wi.y * s.wi.y + s.wi.z * s.wi.z, 1.0, 1e-12);
    assert_int_equal(s.lobe, VR_LOBE_DIFFUSE);
    assert_near(s.pdf, fabs(ci) / M_PI, 1e-12);
    for (int w = 0; w < 3; w++) assert_near(s.weight[w], 0.6, 1e-15);
    double f[3], pdf;
    vr_bsdf_eval(b, NAN, n, wo_w, s.wi, 3, nm, VR_TRANSPORT_RADIANCE, f, &pdf);
    assert_near(pdf, s.pdf, 1e-12);
    assert_near(f[1] * fabs(ci) / pdf, s.weight[1], 1e-12);
    assert_true(vr_bsdf_sample_dir(b2, NAN, n, wo_w, 3, nm, VR_TRANSPORT_RADIANCE, u01(2, i, 0),
                                   u01(2, i, 1), u01(2, i, 2), &s));
    for (int w = 0; w < 3; w++) assert_near(s.weight[w], grey_ramp(nm[w]), 1e-12);
  }
  vr_bsdf_destroy(b);
  vr_bsdf_destroy(b2);
  vr_material_destroy(m);
}

/* Mean sample weight at nm[0] = the directional albedo (importance mode:
 * power). */
static double albedo_by_sampling(const vr_bsdf *b, vr_vec3 n, vr_vec3 wo, double nm, long count) {
  double sum = 0.0;
  for (long i = 0; i < count; i++) {
    vr_bsdf_sample s;
    if (vr_bsdf_sample_dir(b, NAN, n, wo, 1, &nm, VR_TRANSPORT_IMPORTANCE, u01(7, i, 0),
                           u01(7, i, 1), u01(7, i, 2), &s))
      sum += s.weight[0];
  }
  return sum / count;
}

/* The same by uniform sampling of the sphere through eval only, so a
 * sampler bug cannot hide itself. */
static double albedo_by_eval(const vr_bsdf *b, vr_vec3 n, vr_vec3 wo, double nm, long count) {
  double sum = 0.0;
  for (long i = 0; i < count; i++) {
    double z = 1.0 - 2.0 * u01(9, i, 0), phi = 2 * M_PI * u01(9, i, 1), r = sqrt(1 - z * z);
    vr_vec3 wi = {r * cos(phi), r * sin(phi), z};
    double f;
    vr_bsdf_eval(b, NAN, n, wo, wi, 1, &nm, VR_TRANSPORT_IMPORTANCE, &f, NULL);
    sum += f * fabs(z) * 4 * M_PI;
  }
  return sum / count;
}

static void test_ggx_furnace(void **state) {
  (void)state;
  /* A conductor with |N| huge reflects everything: R = 1 - 4n/|N|^2. */
  vr_material *mirror = flat_nk("white-metal", VR_KIND_CONDUCTOR, 1e-3, 1e3);
  vr_material *glass = flat_nk("glass", VR_KIND_DIELECTRIC, 1.5, 0.0);
  double alphas[3] = {0.02, 0.2, 0.6};
  for (int a = 0; a < 3; a++) {
    vr_scene_material sm = test_sm("white-metal");
    sm.roughness = alphas[a];
    vr_bsdf *b = make_bsdf(&sm, mirror, NULL);
    assert_int_equal(vr_bsdf_lobes(b), VR_LOBE_GLOSSY_R);
    for (int t = 0; t < 3; t++) {
      vr_vec3 wo = dir_at((double[]){0, 45, 75}[t] * DEG, 0.3);
      double es = albedo_by_sampling(b, Z, wo, 550, 40000);
      /* (too narrow a lobe for uniform sampling below alpha 0.1) */
      double ee = alphas[a] < 0.1 ? NAN : albedo_by_eval(b, Z, wo, 550, 400000);
      double R, T, A;
      vr_bsdf_rta(b, NAN, wo.z, 550, &R, &T, &A);
      print_message("GGX conductor alpha %.2f theta %2.0f: sampled %.5f, quadrature %.5f, "
                    "eval-uniform %.4f (nan: not run)\n",
                    alphas[a], acos(wo.z) / DEG, es, R, ee);
      assert_true(es <= 1.0 + 1e-12);
      assert_true(R <= 1.0 + 1e-12);
      if (alphas[a] < 0.1) assert_true(es > 0.99 && R > 0.99);
      else assert_near(ee, es, 0.02);
      assert_near(R, es, 0.01);
    }
    vr_bsdf_destroy(b);
    sm = test_sm("glass");
    sm.roughness = alphas[a];
    b = make_bsdf(&sm, glass, NULL);
    assert_int_equal(vr_bsdf_lobes(b), VR_LOBE_GLOSSY_R | VR_LOBE_GLOSSY_T);
    for (int t = 0; t < 3; t++) {
      for (int side = 0; side < 2; side++) {
        vr_vec3 wo = dir_at((double[]){0, 45, 75}[t] * DEG, 0.3);
        if (side) wo.z = -wo.z;
        double es = albedo_by_sampling(b, Z, wo, 550, 40000);
        double R, T, A;
        vr_bsdf_rta(b, NAN, wo.z, 550, &R, &T, &A);
        assert_true(es <= 1.0 + 1e-12);
        assert_true(R + T <= 1.0 + 1e-12);
        assert_near(R + T, es, 0.01);
        if (alphas[a] < 0.1 && t < 2) assert_true(es > 0.99);
      }
    }
    vr_bsdf_destroy(b);
  }
  vr_material_destroy(mirror);
  vr_material_destroy(glass);
}

/* weight = f cos / pdf from eval, for every sample of a glossy lobe. */
static void check_weights(const vr_bsdf *b, int nwl, const double *nm, bool dispersive) {
  vr_vec3 n = {0.0, 0.6, 0.8};
  int checked = 0;
  for (uint64_t i = 0; i < 3000; i++) {
    vr_vec3 wo = dir_at(acos(2 * u01(3, i, 0) - 1), 2 * M_PI * u01(3, i, 1));
    vr_transport mode = i & 1 ? VR_TRANSPORT_IMPORTANCE : VR_TRANSPORT_RADIANCE;
    vr_bsdf_sample s;
    if (!vr_bsdf_sample_dir(b, NAN, n, wo, nwl, nm, mode, u01(4, i, 0), u01(4, i, 1),
                            u01(4, i, 2), &s))
      continue;
    double f[VR_BSDF_MAX_WAVELENGTHS], pdf;
    vr_bsdf_eval(b, NAN, n, wo, s.wi, nwl, nm, mode, f, &pdf);
    double ci = fabs(s.wi.x * n.x + s.wi.y * n.y + s.wi.z * n.z);
    assert_rel(pdf, s.pdf, 1e-7);
    bool ended = dispersive && s.lobe == VR_LOBE_GLOSSY_T;
    assert_true(s.terminate_secondary == ended);
    for (int w = 0; w < nwl; w++) {
      double expect = f[w] * ci / pdf;
      if (ended) expect = w == 0 ? expect * nwl : 0.0;
      if (expect > 1e-300) assert_rel(s.weight[w], expect, 1e-6);
      else assert_near(s.weight[w], 0.0, 1e-12);
    }
    checked++;
  }
  assert_true(checked > 2000);
}

static void test_glossy_weights(void **state) {
  (void)state;
  char path[64];
  vr_matdb *db = temp_db(path, sizeof path);
  vr_material *au = db_load(db, "Au"), *bk7 = db_load(db, "N-BK7");
  vr_material *glass = flat_nk("glass", VR_KIND_DIELECTRIC, 1.5, 1e-6);
  double nm[4] = {480.0, 530.5, 610.0, 700.0};
  vr_scene_material sm = test_sm("Au");
  sm.roughness = 0.3;
  vr_bsdf *b = make_bsdf(&sm, au, NULL);
  check_weights(b, 4, nm, false);
  vr_bsdf_destroy(b);
  sm = test_sm("glass");
  sm.roughness = 0.25;
  b = make_bsdf(&sm, glass, NULL);
  assert_false(vr_bsdf_dispersive(b));
  check_weights(b, 4, nm, false);
  vr_bsdf_destroy(b);
  sm = test_sm("N-BK7");
  sm.roughness = 0.25;
  b = make_bsdf(&sm, bk7, NULL);
  assert_true(vr_bsdf_dispersive(b));
  check_weights(b, 4, nm, true);
  vr_bsdf_destroy(b);
  vr_material_destroy(au);
  vr_material_destroy(bk7);
  vr_material_destroy(glass);
  temp_db_close(db, path);
}

static void test_dispersion(void **state) {
  (void)state;
  char path[64];
  vr_matdb *db = temp_db(path, sizeof path);
  vr_material *bk7 = db_load(db, "N-BK7");
  vr_scene_material sm = test_sm("N-BK7");
  vr_bsdf *b = make_bsdf(&sm, bk7, NULL); /* no thickness: an interface */
  assert_true(vr_bsdf_dispersive(b));
  assert_int_equal(vr_bsdf_lobes(b), VR_LOBE_SPECULAR_R | VR_LOBE_SPECULAR_T);
  assert_true(vr_bsdf_medium_sigma_a(b, 400.0) >= 0.0);
  double nm[4] = {450.0, 520.0, 600.0, 680.0};
  vr_vec3 wo = dir_at(40 * DEG, 0.0);
  vr_bsdf_sample s;
  /* u3 near 1: refraction. */
  assert_true(vr_bsdf_sample_dir(b, NAN, Z, wo, 4, nm, VR_TRANSPORT_RADIANCE, 0.5, 0.5, 0.999, &s));
  assert_int_equal(s.lobe, VR_LOBE_SPECULAR_T);
  assert_true(s.terminate_secondary);
  double n0, k0;
  vr_material_nk(bk7, 450.0, false, &n0, &k0, NULL, NULL);
  assert_near(s.eta, n0, 1e-6);
  /* Snell with the hero's index. */
  double sin_t = sqrt(s.wi.x * s.wi.x + s.wi.y * s.wi.y);
  assert_near(sin_t * n0, sin(40 * DEG), 1e-6);
  assert_true(s.wi.z < 0.0);
  for (int w = 1; w < 4; w++) assert_true(s.weight[w] == 0.0);
  double R, T, A;
  vr_bsdf_rta(b, NAN, wo.z, 450.0, &R, &T, &A);
  double sr = 0, st = 0;
  for (int w = 0; w < 4; w++) {
    double r, t, a;
    vr_bsdf_rta(b, NAN, wo.z, nm[w], &r, &t, &a);
    sr += r;
    st += t;
  }
  double pt = st / (sr + st);
  assert_near(s.pdf, pt, 1e-12);
  assert_rel(s.weight[0], T / pt / (n0 * n0) * 4, 1e-9);
  /* u3 near 0: reflection keeps every wavelength. */
  assert_true(vr_bsdf_sample_dir(b, NAN, Z, wo, 4, nm, VR_TRANSPORT_RADIANCE, 0.5, 0.5, 0.0, &s));
  assert_int_equal(s.lobe, VR_LOBE_SPECULAR_R);
  assert_false(s.terminate_secondary);
  for (int w = 0; w < 4; w++) assert_true(s.weight[w] > 0.0);
  /* Importance: no (n_o / n_i)^2. */
  assert_true(
      vr_bsdf_sample_dir(b, NAN, Z, wo, 4, nm, VR_TRANSPORT_IMPORTANCE, 0.5, 0.5, 0.999, &s));
  assert_rel(s.weight[0], T / pt * 4, 1e-9);
  vr_bsdf_destroy(b);
  /* The same glass as a thin pane does not refract: not dispersive. */
  sm.thickness_m = 0.006;
  b = make_bsdf(&sm, bk7, NULL);
  assert_false(vr_bsdf_dispersive(b));
  vr_bsdf_destroy(b);
  /* A flat index is not dispersive either, and its refraction keeps all. */
  vr_material *flat15 = flat_nk("flat", VR_KIND_DIELECTRIC, 1.5, 0.0);
  sm = test_sm("flat");
  b = make_bsdf(&sm, flat15, NULL);
  assert_false(vr_bsdf_dispersive(b));
  assert_true(vr_bsdf_sample_dir(b, NAN, Z, wo, 4, nm, VR_TRANSPORT_RADIANCE, 0.5, 0.5, 0.999, &s));
  assert_false(s.terminate_secondary);
  for (int w = 1; w < 4; w++) assert_near(s.weight[w], s.weight[0], 1e-15);
  /* From inside beyond the critical angle: reflection only. */
  vr_vec3 inside = dir_at(50 * DEG, 0.0);
  inside.z = -inside.z;
  for (int i = 0; i < 10; i++) {
    assert_true(vr_bsdf_sample_dir(b, NAN, Z, inside, 4, nm, VR_TRANSPORT_RADIANCE, 0.5, 0.5,
                                   i / 10.0 + 0.05, &s));
    assert_int_equal(s.lobe, VR_LOBE_SPECULAR_R);
    assert_near(s.weight[0], 1.0, 0);
  }
  vr_bsdf_destroy(b);
  vr_material_destroy(flat15);
  vr_material_destroy(bk7);
  temp_db_close(db, path);
}

static double T0_fn(double nm) { return 0.8 - 0.1 * (nm - 300.0) / 600.0; }
static double dOD_fn(double nm) { return 0.3 + 1.2 * exp(-pow((nm - 750.0) / 200.0, 2)); }
static double Rf0_fn(double nm) { return 0.08 + 0.0 * nm; }
static double dRf_fn(double nm) { return -0.02 + 0.0 * nm; }

static vr_material *electrochromic(bool with_R) {
  vr_material *m = vr_material_create("ec", VR_KIND_CHROMOGENIC, NULL);
  vr_material_add_spectrum(m, "T0", spectrum_of(T0_fn), NULL);
  vr_material_add_spectrum(m, "dOD", spectrum_of(dOD_fn), NULL);
  if (with_R) {
    vr_material_add_spectrum(m, "Rf0", spectrum_of(Rf0_fn), NULL);
    vr_material_add_spectrum(m, "dRf", spectrum_of(dRf_fn), NULL);
  }
  vr_material_add_property(m, "chromogenic_type", "electrochromic", NAN, NULL, NULL);
  vr_material_add_property(m, "thickness", NULL, 6.0, "mm", NULL);
  vr_material_add_parameter(m, "Q_full", 32.0, NAN, "mC/cm2", NULL);
  return m;
}

static void test_chromogenic(void **state) {
  (void)state;
  for (int with_R = 0; with_R < 2; with_R++) {
    vr_material *m = electrochromic(with_R);
    vr_scene_material sm = test_sm("ec");
    sm.charge_mC_cm2 = 16.0;
    vr_bsdf *b = make_bsdf(&sm, m, NULL);
    assert_true(vr_bsdf_is_chromogenic(b));
    assert_false(vr_bsdf_is_photochromic(b));
    assert_true(vr_bsdf_is_thin(b));
    assert_near(vr_bsdf_default_state(b), 0.5, 1e-15);
    double nm[4] = {400.0, 550.0, 700.0, 812.5}, T[4];
    double states[4] = {NAN, 0.0, 0.8, 1.0};
    for (int i = 0; i < 4; i++) {
      double s = isnan(states[i]) ? 0.5 : states[i];
      assert_true(vr_bsdf_straight_transmittance(b, states[i], 1.0, 4, nm, T));
      for (int w = 0; w < 4; w++) {
        /* The model as matdb evaluates it (linear between the 5 nm samples
         * of T0 and dOD), and the closed form it stands for. */
        double Tm, Rm;
        assert_int_equal(vr_chromo_eval(m, s, nm[w], &Tm, &Rm, NULL, NULL), VR_OK);
        assert_near(T[w], Tm, 1e-12);
        assert_near(T[w], T0_fn(nm[w]) * pow(10.0, -s * dOD_fn(nm[w])), 1e-4);
        double R, Tt, A;
        vr_bsdf_rta(b, states[i], 1.0, nm[w], &R, &Tt, &A);
        if (with_R) assert_near(R, Rm, 1e-12);
        if (with_R) assert_near(R, Rf0_fn(nm[w]) + s * dRf_fn(nm[w]), 1e-12);
        assert_near(R + Tt + A, 1.0, 1e-12);
        /* Darker at an angle, more reflective, a mirror at grazing. */
        double R60, T60, A60;
        vr_bsdf_rta(b, states[i], cos(60 * DEG), nm[w], &R60, &T60, &A60);
        assert_true(T60 < Tt && R60 > R);
        vr_bsdf_rta(b, states[i], 1e-7, nm[w], &R60, &T60, &A60);
        assert_true(R60 > 0.999 && T60 < 1e-3);
      }
    }
    vr_bsdf_destroy(b);
    /* state= wins directly; nothing given is the bleached state. */
    sm = test_sm("ec");
    sm.state = 0.25;
    b = make_bsdf(&sm, m, NULL);
    assert_near(vr_bsdf_default_state(b), 0.25, 0);
    vr_bsdf_destroy(b);
    sm = test_sm("ec");
    b = make_bsdf(&sm, m, NULL);
    assert_near(vr_bsdf_default_state(b), 0.0, 0);
    vr_bsdf_destroy(b);
    vr_material_destroy(m);
  }
  /* Photochromic: the texel passes its state. */
  vr_material *m = vr_material_create("pc", VR_KIND_CHROMOGENIC, NULL);
  vr_material_add_spectrum(m, "T0", spectrum_of(T0_fn), NULL);
  vr_material_add_spectrum(m, "dOD", spectrum_of(dOD_fn), NULL);
  vr_material_add_property(m, "chromogenic_type", "photochromic", NAN, NULL, NULL);
  vr_scene_material sm = test_sm("pc");
  vr_bsdf *b = make_bsdf(&sm, m, NULL);
  assert_true(vr_bsdf_is_photochromic(b));
  double T;
  assert_true(vr_bsdf_straight_transmittance(b, 0.3, 1.0, 1, (double[]){552.0}, &T));
  double Tm;
  assert_int_equal(vr_chromo_eval(m, 0.3, 552.0, &Tm, NULL, NULL, NULL), VR_OK);
  assert_near(T, Tm, 1e-12);
  vr_bsdf_destroy(b);
  sm.charge_mC_cm2 = 3;
  vr_error err = {0};
  assert_int_equal(vr_bsdf_create(&sm, m, NULL, 360, 830, &b, &err), VR_E_ARG);
  assert_contains(err.message, "12:3: material 'obj' (db:pc)");
  vr_material_destroy(m);
}

static void expect_error(const vr_scene_material *sm, const vr_material *m,
                         const vr_material *coating, const char *needle) {
  vr_bsdf *b = (vr_bsdf *)1;
  vr_error err = {0};
  assert_int_not_equal(vr_bsdf_create(sm, m, coating, 360, 830, &b, &err), VR_OK);
  assert_null(b);
  assert_contains(err.message, "12:3: material 'obj'");
  assert_contains(err.message, needle);
}

static void test_errors(void **state) {
  (void)state;
  vr_material *glass = flat_nk("glass", VR_KIND_DIELECTRIC, 1.5, 0.0);
  vr_scene_material sm = test_sm("glass");
  sm.pane = VR_PANE_THIN;
  expect_error(&sm, glass, NULL, "thickness");
  sm = test_sm("glass");
  sm.thickness_m = 0.004;
  sm.pane = VR_PANE_THIN;
  sm.roughness = 0.2;
  expect_error(&sm, glass, NULL, "roughness");
  sm = test_sm("glass");
  sm.state = 0.5;
  expect_error(&sm, glass, NULL, "chromogenic");
  sm = test_sm("glass");
  sm.roughness = -1;
  expect_error(&sm, glass, NULL, "roughness");
  sm = test_sm("glass");
  expect_error(&sm, NULL, NULL, "not resolved");
  sm.coating_db = (char *)"lowe";
  expect_error(&sm, glass, NULL, "coating");
  vr_material *lay = vr_material_create("stack", VR_KIND_LAYERED, NULL);
  sm = test_sm("stack");
  expect_error(&sm, lay, NULL, "btdf");
  sm = test_sm("glass");
  sm.coating_db = (char *)"stack";
  sm.thickness_m = 0.004;
  expect_error(&sm, glass, lay, "btdf table");
  vr_material *film = flat_nk("film", VR_KIND_DIELECTRIC, 2.0, 0.0); /* no thickness */
  sm.coating_db = (char *)"film";
  expect_error(&sm, glass, film, "thickness");
  vr_material *sun = vr_material_create("D65", VR_KIND_ILLUMINANT, NULL);
  sm = test_sm("D65");
  expect_error(&sm, sun, NULL, "not a surface");
  vr_material *refl = vr_material_create("grey", VR_KIND_REFLECTANCE, NULL);
  sm = test_sm("grey");
  expect_error(&sm, refl, NULL, "value");
  sm = test_sm(NULL);
  sm.source = VR_MATSRC_LAMBERT_CONST;
  sm.reflectance = 1.5;
  expect_error(&sm, NULL, NULL, "reflectance");
  vr_bsdf *b = NULL;
  vr_error err = {0};
  sm.reflectance = 0.5;
  assert_int_equal(vr_bsdf_create(&sm, NULL, NULL, 500, 400, &b, &err), VR_E_ARG);
  vr_material_destroy(glass);
  vr_material_destroy(lay);
  vr_material_destroy(film);
  vr_material_destroy(sun);
  vr_material_destroy(refl);
}

static void test_black(void **state) {
  (void)state;
  vr_scene_material sm = test_sm(NULL);
  sm.source = VR_MATSRC_BLACK;
  vr_bsdf *b = make_bsdf(&sm, NULL, NULL);
  assert_int_equal(vr_bsdf_lobes(b), 0);
  vr_bsdf_sample s;
  assert_false(vr_bsdf_sample_dir(b, NAN, Z, Z, 1, (double[]){500}, VR_TRANSPORT_RADIANCE, 0.5,
                                  0.5, 0.5, &s));
  double R, T, A;
  vr_bsdf_rta(b, NAN, 1.0, 500, &R, &T, &A);
  assert_true(R == 0 && T == 0 && A == 1);
  vr_bsdf_destroy(b);
}

/* Many threads on one bsdf give what one thread gives. */
typedef struct job {
  const vr_bsdf *b;
  uint64_t seed;
  double sum;
} job;

static void *run(void *arg) {
  job *j = arg;
  double nm[4] = {420, 500, 580, 660};
  for (uint64_t i = 0; i < 20000; i++) {
    vr_vec3 wo = dir_at(acos(2 * u01(j->seed, i, 0) - 1), 2 * M_PI * u01(j->seed, i, 1));
    vr_bsdf_sample s;
    if (vr_bsdf_sample_dir(j->b, 0.4, Z, wo, 4, nm, VR_TRANSPORT_RADIANCE, u01(j->seed, i, 2),
                           u01(j->seed, i, 3), u01(j->seed, i, 4), &s))
      for (int w = 0; w < 4; w++) j->sum += s.weight[w] * (w + 1) + s.wi.x;
  }
  return NULL;
}

static void test_threads(void **state) {
  (void)state;
  vr_material *m = flat_nk("glass", VR_KIND_DIELECTRIC, 1.5, 1e-6);
  vr_scene_material sm = test_sm("glass");
  sm.roughness = 0.2;
  vr_bsdf *b = make_bsdf(&sm, m, NULL);
  job serial[4], par[4];
  pthread_t th[4];
  for (int t = 0; t < 4; t++) {
    serial[t] = par[t] = (job){b, (uint64_t)t + 100, 0.0};
    run(&serial[t]);
  }
  for (int t = 0; t < 4; t++) assert_int_equal(pthread_create(&th[t], NULL, run, &par[t]), 0);
  for (int t = 0; t < 4; t++) pthread_join(th[t], NULL);
  for (int t = 0; t < 4; t++) assert_true(serial[t].sum == par[t].sum);
  vr_bsdf_destroy(b);
  vr_material_destroy(m);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_clear_pane),   cmocka_unit_test(test_metal_mirrors),
      cmocka_unit_test(test_lambertian),   cmocka_unit_test(test_ggx_furnace),
      cmocka_unit_test(test_glossy_weights), cmocka_unit_test(test_dispersion),
      cmocka_unit_test(test_chromogenic),  cmocka_unit_test(test_errors),
      cmocka_unit_test(test_black),        cmocka_unit_test(test_threads),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
