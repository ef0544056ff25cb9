/* Thin elements against core's optics: the (cos, wavelength) tables of a
 * pane against direct vr_slab (the interpolation error is printed and
 * bounded), the equivalent-slab inversion (round trip through vr_slab, the
 * algebra of fit/src/slab_invert.c), a measured pane (kind glazing) made
 * from a known slab, a btdf table, and a coated pane against vr_stack_solve. */
#include "bsdf_test_util.h"

#include "vr/btdf.h"

/* Largest |table - vr_slab| of T and R over random (cos, wavelength). */
static void table_error(const vr_material *m, double d_nm, double *errT, double *errR) {
  vr_scene_material sm = test_sm(m->name);
  sm.thickness_m = d_nm * 1e-9;
  vr_bsdf *b = make_bsdf(&sm, m, NULL);
  *errT = *errR = 0.0;
  for (uint64_t i = 0; i < 8000; i++) {
    double c = u01(11, i, 0), nm = 360.0 + 470.0 * u01(11, i, 1);
    if (i < 50) c = 1.0 - i * 1e-3; /* near normal */
    else if (i < 100) c = (i - 50) * 2e-4; /* near grazing */
    double n, k, T, R, Tb, Rb, Ab;
    assert_int_equal(vr_material_nk(m, nm, true, &n, &k, NULL, NULL), VR_OK);
    slab_rt(n, k, d_nm, acos(c), nm, &T, &R);
    vr_bsdf_rta(b, NAN, c, nm, &Rb, &Tb, &Ab);
    *errT = fmax(*errT, fabs(Tb - T));
    *errR = fmax(*errR, fabs(Rb - R));
  }
  vr_bsdf_destroy(b);
}

static void test_table_error(void **state) {
  (void)state;
  char path[64];
  vr_matdb *db = temp_db(path, sizeof path);
  const char *names[3] = {"soda-lime-glass", "N-BK7", "fused-silica"};
  double worst = 0.0;
  for (int i = 0; i < 3; i++) {
    vr_material *m = db_load(db, names[i]);
    double eT, eR;
    table_error(m, 4e6, &eT, &eR);
    print_message("pane table vs vr_slab, %s 4 mm: max |dT| %.2e, max |dR| %.2e\n", names[i],
                  eT, eR);
    worst = fmax(worst, fmax(eT, eR));
    vr_material_destroy(m);
  }
  /* A strongly absorbing glass (k = 2e-5: about 0.2 internal
   * transmittance at 500 nm, 10 mm). */
  vr_material *grey = flat_nk("grey", VR_KIND_DIELECTRIC, 1.52, 2e-5);
  double eT, eR;
  table_error(grey, 1e7, &eT, &eR);
  print_message("pane table vs vr_slab, n 1.52 k 2e-5 10 mm: max |dT| %.2e, max |dR| %.2e\n",
                eT, eR);
  worst = fmax(worst, fmax(eT, eR));
  assert_true(worst < 1e-4);
  vr_material_destroy(grey);
  temp_db_close(db, path);
}

static void test_equivalent_slab(void **state) {
  (void)state;
  double ns[4] = {1.33, 1.52, 1.9, 2.4}, ks[4] = {0.0, 1e-7, 3e-6, 2e-5};
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++) {
      double d = 3e6, nm = 550.0, T, R, n, a;
      slab_rt(ns[i], ks[j], d, 0.0, nm, &T, &R);
      vr_bsdf_equivalent_slab(T, R, &n, &a);
      double a_true = exp(-4 * M_PI * ks[j] * d / nm);
      /* n from r neglects k: k^2 / n^2 relative at most. */
      assert_near(n, ns[i], 1e-6);
      assert_near(a, a_true, 1e-9);
    }
  /* Totality: no NaN for data no slab gives. */
  double cases[][2] = {{0, 0.04}, {0.9, 0}, {0, 0}, {0.97, 0.05}, {1, 0}, {0.5, 0.6}, {1, 1}};
  for (size_t c = 0; c < sizeof cases / sizeof *cases; c++) {
    double n, a;
    vr_bsdf_equivalent_slab(cases[c][0], cases[c][1], &n, &a);
    assert_true(isfinite(n) && n >= 1.0);
    assert_true(a >= 0.0 && a <= 1.0);
  }
  double n, a;
  vr_bsdf_equivalent_slab(0.0, 0.04, &n, &a);
  assert_near(a, 0.0, 0);
  assert_near(n, 1.5, 1e-12); /* r = 0.04 is n = 1.5 */
}

/* A glazing material: T, Rf, Rb of the slab (n, k, d) at normal incidence. */
static vr_material *glazing_of(double n, double k, double d_nm, double dRb) {
  double nm[61], T[61], R[61], Rb[61];
  for (int i = 0; i < 61; i++) {
    nm[i] = 300.0 + 10.0 * i;
    slab_rt(n, k, d_nm, 0.0, nm[i], &T[i], &R[i]);
    Rb[i] = R[i] + dRb;
  }
  vr_material *m = vr_material_create("pane", VR_KIND_GLAZING, NULL);
  vr_material_add_spectrum(m, "T", vr_spectrum_create(61, nm, T, NULL), NULL);
  vr_material_add_spectrum(m, "Rf", vr_spectrum_create(61, nm, R, NULL), NULL);
  vr_material_add_spectrum(m, "Rb", vr_spectrum_create(61, nm, Rb, NULL), NULL);
  vr_material_add_property(m, "thickness", NULL, d_nm * 1e-6, "mm", NULL);
  return m;
}

static void test_glazing(void **state) {
  (void)state;
  const double n = 1.523, k = 4e-7, d = 3.048e6;
  vr_material *m = glazing_of(n, k, d, 0.0);
  vr_scene_material sm = test_sm("pane");
  vr_bsdf *b = make_bsdf(&sm, m, NULL);
  assert_true(vr_bsdf_is_thin(b));
  double worst = 0.0;
  for (int a = 0; a <= 89; a += 4)
    for (int w = 0; w < 5; w++) {
      double nm = 400.0 + 100.0 * w, T, R, Tb, Rb, Ab;
      slab_rt(n, k, d, a * DEG, nm, &T, &R);
      vr_bsdf_rta(b, NAN, cos(a * DEG), nm, &Rb, &Tb, &Ab);
      worst = fmax(worst, fmax(fabs(T - Tb), fabs(R - Rb)));
      if (a == 0) {
        assert_near(Tb, T, 1e-12);
        assert_near(Rb, R, 1e-12);
      }
    }
  print_message("glazing (equivalent slab) vs vr_slab with the true n, k: max error %.2e\n", worst);
  assert_true(worst < 1e-4);
  vr_bsdf_destroy(b);
  vr_material_destroy(m);
  /* A coated-looking pane (Rb = Rf - 0.02): each side its own slab, T
   * shared, the measured values at normal incidence exactly. */
  m = glazing_of(n, k, d, -0.02);
  b = make_bsdf(&sm, m, NULL);
  double Rf, Rb, T1, T2, A;
  vr_bsdf_rta(b, NAN, 1.0, 550.0, &Rf, &T1, &A);
  vr_bsdf_rta(b, NAN, -1.0, 550.0, &Rb, &T2, &A);
  assert_near(Rb - Rf, -0.02, 1e-9);
  assert_near(T1, T2, 1e-15);
  vr_bsdf_rta(b, NAN, -cos(70 * DEG), 550.0, &Rb, &T2, &A);
  vr_bsdf_rta(b, NAN, cos(70 * DEG), 550.0, &Rf, &T1, &A);
  assert_true(Rb < Rf);
  assert_near(T1, T2, 1e-15);
  vr_bsdf_destroy(b);
  vr_material_destroy(m);
}

/* A btdf material made of vr_slab values every 5 degrees, 350-850 nm. */
static vr_material *btdf_of(double n, double k, double d_nm) {
  vr_material *m = vr_material_create("tab", VR_KIND_BTDF, NULL);
  const char *q[6] = {"Ts", "Tp", "Rfs", "Rfp", "Rbs", "Rbp"};
  char list[512] = "", role[32];
  for (int a = 0; a <= 90; a += 5) {
    double nm[51], v[6][51];
    for (int i = 0; i < 51; i++) {
      nm[i] = 350.0 + 10.0 * i;
      vr_slab_result s;
      vr_slab(1.0, n + I * k, d_nm, a * DEG, nm[i], &s, NULL);
      for (int p = 0; p < 2; p++) {
        v[0 + p][i] = s.T[p];
        v[2 + p][i] = s.R[p];
        v[4 + p][i] = 0.98 * s.R[p]; /* tell the back from the front */
      }
    }
    for (int j = 0; j < 6; j++) {
      snprintf(role, sizeof role, "%s@%d", q[j], a);
      vr_material_add_spectrum(m, role, vr_spectrum_create(51, nm, v[j], NULL), NULL);
    }
    snprintf(list + strlen(list), sizeof list - strlen(list), "%s%d", a ? "," : "", a);
  }
  vr_material_add_property(m, "angles", list, NAN, "deg", NULL);
  return m;
}

static void test_btdf(void **state) {
  (void)state;
  vr_material *m = btdf_of(1.52, 1e-6, 4e6);
  vr_scene_material sm = test_sm("tab");
  vr_bsdf *b = make_bsdf(&sm, m, NULL);
  assert_true(vr_bsdf_is_thin(b));
  double worst = 0.0;
  for (uint64_t i = 0; i < 3000; i++) {
    double deg = 89.9 * u01(5, i, 0), nm = 360.0 + 470.0 * u01(5, i, 1);
    double T, Rf, Rb, Tb, R, A;
    vr_btdf_eval(m, VR_BTDF_T, VR_BTDF_UNPOLARISED, deg, nm, &T, NULL);
    vr_btdf_eval(m, VR_BTDF_RF, VR_BTDF_UNPOLARISED, deg, nm, &Rf, NULL);
    vr_btdf_eval(m, VR_BTDF_RB, VR_BTDF_UNPOLARISED, deg, nm, &Rb, NULL);
    vr_bsdf_rta(b, NAN, cos(deg * DEG), nm, &R, &Tb, &A);
    worst = fmax(worst, fmax(fabs(T - Tb), fabs(R - Rf)));
    vr_bsdf_rta(b, NAN, -cos(deg * DEG), nm, &R, &Tb, &A);
    worst = fmax(worst, fabs(R - Rb));
  }
  print_message("btdf pane vs vr_btdf_eval (5 deg table): max error %.2e\n", worst);
  assert_true(worst < 2e-3);
  assert_false(vr_bsdf_extrapolated(b));
  vr_bsdf_destroy(b);
  /* The same table as the coating of a glass pane stands for the pane. */
  vr_material *glass = flat_nk("glass", VR_KIND_DIELECTRIC, 1.5, 0.0);
  sm = test_sm("glass");
  sm.coating_db = (char *)"tab";
  sm.thickness_m = 0.004;
  b = make_bsdf(&sm, glass, m);
  double T, R, A;
  vr_bsdf_rta(b, NAN, -1.0, 550.0, &R, &T, &A);
  double Ts;
  vr_btdf_eval(m, VR_BTDF_RB, VR_BTDF_UNPOLARISED, 0.0, 550.0, &Ts, NULL);
  assert_near(R, Ts, 1e-12);
  vr_bsdf_destroy(b);
  vr_material_destroy(glass);
  vr_material_destroy(m);
}

static void test_coated(void **state) {
  (void)state;
  vr_material *glass = flat_nk("glass", VR_KIND_DIELECTRIC, 1.52, 1e-7);
  vr_material *film = flat_nk("film", VR_KIND_CONDUCTOR, 0.15, 3.2); /* a silver-like film */
  vr_material_add_property(film, "thickness", NULL, 10.0, "nm", NULL);
  vr_scene_material sm = test_sm("glass");
  sm.coating_db = (char *)"film";
  sm.thickness_m = 0.004;
  vr_bsdf *b = make_bsdf(&sm, glass, film);
  assert_true(vr_bsdf_is_thin(b));
  double nm = 550.0;
  for (int a = 0; a <= 80; a += 20) {
    vr_layer front[4] = {{1.0, 0, 0}, {0.15 + 3.2 * I, 10.0, 0}, {1.52 + 1e-7 * I, 4e6, 1},
                         {1.0, 0, 0}};
    vr_layer back[4] = {front[0], front[2], front[1], front[3]};
    double T = 0, Rf = 0, Rb = 0;
    for (int p = 0; p < 2; p++) {
      vr_tmm_result f, r;
      assert_int_equal(vr_stack_solve(front, 4, a * DEG, nm, (vr_pol)p, &f, NULL), VR_OK);
      assert_int_equal(vr_stack_solve(back, 4, a * DEG, nm, (vr_pol)p, &r, NULL), VR_OK);
      T += 0.5 * f.T;
      Rf += 0.5 * f.R;
      Rb += 0.5 * r.R;
    }
    double R, Tb, A;
    vr_bsdf_rta(b, NAN, cos(a * DEG), nm, &R, &Tb, &A);
    assert_near(Tb, T, 2e-5);
    assert_near(R, Rf, 2e-5);
    vr_bsdf_rta(b, NAN, -cos(a * DEG), nm, &R, &Tb, &A);
    assert_near(R, Rb, 2e-5);
    assert_near(Tb, T, 2e-5);
    if (a == 0) assert_true(fabs(Rf - Rb) > 1e-3); /* an absorbing film: sides differ */
  }
  vr_bsdf_destroy(b);
  vr_material_destroy(glass);
  vr_material_destroy(film);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_table_error), cmocka_unit_test(test_equivalent_slab),
      cmocka_unit_test(test_glazing),     cmocka_unit_test(test_btdf),
      cmocka_unit_test(test_coated),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
