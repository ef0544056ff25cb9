/* Energy bookkeeping of every kind of vr_bsdf: R + T + A = 1 with each in
 * [0, 1] from normal incidence to grazing (89.999 deg), from both sides,
 * for the hard cases of DESIGN section 8: k = 0, k >> n, total internal
 * reflection from inside a dielectric; and the lobe choice of the delta
 * samplers, whose expectation must be R and T at every wavelength. */
#include "bsdf_test_util.h"

static const double ANGLES[] = {0,  10, 20, 30,   40,     50, 60, 70,
                                80, 85, 89, 89.9, 89.999, 90};

typedef struct kind_case {
  const char *label;
  vr_bsdf *b;
  double state;
} kind_case;

static void check_rta(const kind_case *k) {
  double nm[3] = {380.0, 555.5, 810.0};
  for (size_t a = 0; a < sizeof ANGLES / sizeof *ANGLES; a++)
    for (int side = 0; side < 2; side++)
      for (int w = 0; w < 3; w++) {
        double c = cos(ANGLES[a] * DEG) * (side ? -1.0 : 1.0), R, T, A;
        vr_bsdf_rta(k->b, k->state, c, nm[w], &R, &T, &A);
        if (!(R >= 0 && R <= 1 && T >= 0 && T <= 1 && A >= 0 && A <= 1) ||
            !(fabs(R + T + A - 1.0) <= 1e-12))
          fail_msg("%s at %g deg (%s), %g nm: R %.17g T %.17g A %.17g", k->label, ANGLES[a],
                   side ? "back" : "front", nm[w], R, T, A);
      }
}

/* The sampler's expectation over u3 is R (reflected) and T (transmitted)
 * at each wavelength, for the delta lobes of panes and interfaces. */
static void check_delta_expectation(const kind_case *k) {
  double nm[4] = {400.0, 500.0, 600.0, 700.0};
  for (size_t a = 0; a + 1 < sizeof ANGLES / sizeof *ANGLES; a++)
    for (int side = 0; side < 2; side++) {
      vr_vec3 wo = dir_at(ANGLES[a] * DEG, 0.4);
      if (side) wo.z = -wo.z;
      double eR[4] = {0}, eT[4] = {0};
      const int count = 1000;
      for (int i = 0; i < count; i++) {
        vr_bsdf_sample s;
        if (!vr_bsdf_sample_dir(k->b, k->state, (vr_vec3){0, 0, 1}, wo, 4, nm,
                                VR_TRANSPORT_IMPORTANCE, 0.5, 0.5, (i + 0.5) / count, &s))
          continue;
        bool refl = s.wi.z * wo.z > 0;
        for (int w = 0; w < 4; w++) (refl ? eR : eT)[w] += s.weight[w] / count;
      }
      for (int w = 0; w < 4; w++) {
        double R, T, A;
        vr_bsdf_rta(k->b, k->state, wo.z, nm[w], &R, &T, &A);
        /* A stratified u3 hits each lobe's share to 1 / count. */
        double tol = 2.0 / count;
        if (fabs(eR[w] - R) > tol * (R + T) + 1e-12 || fabs(eT[w] - T) > tol * (R + T) + 1e-12)
          fail_msg("%s at %g deg side %d, %g nm: sampled R %.6f T %.6f, expected %.6f %.6f",
                   k->label, ANGLES[a], side, nm[w], eR[w], eT[w], R, T);
      }
    }
}

static double T0_fn(double nm) { return 0.7 + 0.0 * nm; }
static double dOD_fn(double nm) { return 0.5 + 1.5 * (nm - 300.0) / 600.0; }

static void test_every_kind(void **state) {
  (void)state;
  char path[64];
  vr_matdb *db = temp_db(path, sizeof path);
  vr_material *au = db_load(db, "Au"), *bk7 = db_load(db, "N-BK7"),
              *soda = db_load(db, "soda-lime-glass"), *si = db_load(db, "Si");
  vr_material *clear = flat_nk("clear", VR_KIND_DIELECTRIC, 1.52, 0.0);
  vr_material *metal_like = flat_nk("metal-like", VR_KIND_DIELECTRIC, 0.2, 3.5); /* k >> n */
  vr_material *huge_k = flat_nk("huge-k", VR_KIND_DIELECTRIC, 1.5, 1e3);
  vr_material *film = flat_nk("film", VR_KIND_DIELECTRIC, 2.3, 0.01);
  vr_material_add_property(film, "thickness", NULL, 80.0, "nm", NULL);
  vr_material *ec = vr_material_create("ec", VR_KIND_CHROMOGENIC, NULL);
  vr_material_add_spectrum(ec, "T0", spectrum_of(T0_fn), NULL);
  vr_material_add_spectrum(ec, "dOD", spectrum_of(dOD_fn), NULL);
  vr_material_add_property(ec, "chromogenic_type", "electrochromic", NAN, NULL, NULL);

  kind_case cases[32];
  int n = 0;
  vr_scene_material sm = test_sm(NULL);
  sm.source = VR_MATSRC_BLACK;
  cases[n++] = (kind_case){"black", make_bsdf(&sm, NULL, NULL), NAN};
  sm.source = VR_MATSRC_LAMBERT_CONST;
  sm.reflectance = 0.8;
  cases[n++] = (kind_case){"lambert 0.8", make_bsdf(&sm, NULL, NULL), NAN};
  sm = test_sm("Au");
  cases[n++] = (kind_case){"gold mirror", make_bsdf(&sm, au, NULL), NAN};
  sm.roughness = 0.3;
  cases[n++] = (kind_case){"rough gold", make_bsdf(&sm, au, NULL), NAN};
  sm = test_sm("clear");
  cases[n++] = (kind_case){"interface k=0", make_bsdf(&sm, clear, NULL), NAN};
  sm.roughness = 0.3;
  cases[n++] = (kind_case){"rough interface", make_bsdf(&sm, clear, NULL), NAN};
  sm = test_sm("N-BK7");
  cases[n++] = (kind_case){"N-BK7 interface", make_bsdf(&sm, bk7, NULL), NAN};
  sm = test_sm("metal-like");
  cases[n++] = (kind_case){"interface k>>n", make_bsdf(&sm, metal_like, NULL), NAN};
  sm = test_sm("Si");
  cases[n++] = (kind_case){"Si interface", make_bsdf(&sm, si, NULL), NAN};
  sm = test_sm("clear");
  sm.thickness_m = 0.004;
  cases[n++] = (kind_case){"pane k=0", make_bsdf(&sm, clear, NULL), NAN};
  sm = test_sm("soda-lime-glass");
  sm.thickness_m = 0.006;
  cases[n++] = (kind_case){"soda-lime pane", make_bsdf(&sm, soda, NULL), NAN};
  sm = test_sm("metal-like");
  sm.thickness_m = 0.004;
  cases[n++] = (kind_case){"pane k>>n", make_bsdf(&sm, metal_like, NULL), NAN};
  sm = test_sm("huge-k");
  sm.thickness_m = 0.004;
  cases[n++] = (kind_case){"pane k=1e3", make_bsdf(&sm, huge_k, NULL), NAN};
  sm = test_sm("clear");
  sm.thickness_m = 0.004;
  sm.coating_db = (char *)"film";
  cases[n++] = (kind_case){"coated pane", make_bsdf(&sm, clear, film), NAN};
  sm = test_sm("ec");
  cases[n++] = (kind_case){"electrochromic s=0", make_bsdf(&sm, ec, NULL), 0.0};
  cases[n] = cases[n - 1];
  cases[n++].state = 1.0;
  cases[n] = cases[n - 1];
  cases[n].label = "electrochromic default";
  cases[n++].state = NAN;
  for (int i = 0; i < n; i++) check_rta(&cases[i]);
  for (int i = 0; i < n; i++)
    if (vr_bsdf_lobes(cases[i].b) & (VR_LOBE_STRAIGHT | VR_LOBE_SPECULAR_T))
      if (!vr_bsdf_dispersive(cases[i].b)) check_delta_expectation(&cases[i]);
  /* Each bsdf once (the chromogenic one is shared by three cases). */
  for (int i = 0; i < n; i++)
    if (i == 0 || cases[i].b != cases[i - 1].b) vr_bsdf_destroy(cases[i].b);
  vr_material *ms[] = {au, bk7, soda, si, clear, metal_like, huge_k, film, ec};
  for (size_t i = 0; i < sizeof ms / sizeof *ms; i++) vr_material_destroy(ms[i]);
  temp_db_close(db, path);
}

static void test_hard_cases(void **state) {
  (void)state;
  vr_material *clear = flat_nk("clear", VR_KIND_DIELECTRIC, 1.5, 0.0);
  vr_scene_material sm = test_sm("clear");
  vr_bsdf *b = make_bsdf(&sm, clear, NULL);
  double R, T, A;
  /* Total internal reflection from inside, beyond asin(1 / 1.5) = 41.8 deg. */
  for (double a = 41.9; a < 90; a += 4) {
    vr_bsdf_rta(b, NAN, -cos(a * DEG), 550, &R, &T, &A);
    assert_true(R == 1.0 && T == 0.0 && A == 0.0);
  }
  /* Just below the critical angle some light still leaves. */
  vr_bsdf_rta(b, NAN, -cos(41.7 * DEG), 550, &R, &T, &A);
  assert_true(T > 0.0 && R < 1.0);
  /* Normal incidence both ways: ((n - 1) / (n + 1))^2 = 0.04. */
  vr_bsdf_rta(b, NAN, 1.0, 550, &R, &T, &A);
  assert_near(R, 0.04, 1e-12);
  vr_bsdf_rta(b, NAN, -1.0, 550, &R, &T, &A);
  assert_near(R, 0.04, 1e-12);
  /* Grazing: a mirror. */
  vr_bsdf_rta(b, NAN, cos(89.999 * DEG), 550, &R, &T, &A);
  assert_true(R > 0.999 && R <= 1.0);
  assert_true(vr_bsdf_medium_sigma_a(b, 550) == 0.0);
  vr_bsdf_destroy(b);
  /* A k = 0 pane loses nothing at any angle. */
  sm.thickness_m = 0.004;
  b = make_bsdf(&sm, clear, NULL);
  for (size_t a = 0; a < sizeof ANGLES / sizeof *ANGLES; a++) {
    vr_bsdf_rta(b, NAN, cos(ANGLES[a] * DEG), 550, &R, &T, &A);
    assert_near(A, 0.0, 1e-12);
  }
  vr_bsdf_rta(b, NAN, cos(89.999 * DEG), 550, &R, &T, &A);
  assert_true(T < 1e-3 && R > 0.999);
  vr_bsdf_destroy(b);
  /* sigma_a = 4 pi k / lambda. */
  vr_material *absorbing = flat_nk("abs", VR_KIND_DIELECTRIC, 1.5, 1e-6);
  sm = test_sm("abs");
  b = make_bsdf(&sm, absorbing, NULL);
  assert_rel(vr_bsdf_medium_sigma_a(b, 500.0), 4 * M_PI * 1e-6 / 500e-9, 1e-12);
  vr_bsdf_destroy(b);
  vr_material_destroy(absorbing);
  vr_material_destroy(clear);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_every_kind),
      cmocka_unit_test(test_hard_cases),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
