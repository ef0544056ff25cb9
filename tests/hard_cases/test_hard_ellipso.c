/* Ellipsometry edge cases that must stay stable: Δ near 0° and 180°, Ψ near
 * 45°, a 2 nm film whose n-d correlation must be reported, an absorbing
 * metal film, data at the Brewster angle, a single angle, a single
 * wavelength, an incoherent substrate with a reflecting back side. */
#include "vr_test.h"
#include "vr/ellipso_fit.h"

static vr_sample_model *model(const char *text) {
  vr_sample_model *m;
  vr_error err = {0};
  if (vr_model_parse(text, strlen(text), "hard.model", VR_SOURCE_DIR, NULL, &m, &err)) fail_msg("%s", err.message);
  return m;
}

/* Noise-free data from m at the given angles and wavelengths. */
static void data_of(vr_sample_model *m, const double *angles, size_t na, double w0, double w1, size_t nw,
                    vr_ellipso_data *d) {
  d->n = na * nw;
  d->p = calloc(d->n, sizeof *d->p);
  d->source = strdup("synthetic");
  size_t k = 0;
  for (size_t i = 0; i < nw; i++)
    for (size_t j = 0; j < na; j++, k++) {
      vr_ellipso_point *p = &d->p[k];
      p->nm = nw > 1 ? w0 + (w1 - w0) * (double)i / (double)(nw - 1) : w0;
      p->aoi_deg = angles[j];
      if (vr_model_psi_delta(m, p->nm, p->aoi_deg, &p->psi_deg, &p->delta_deg, NULL, NULL)) fail_msg("model");
      p->sigma_psi = 0.02;
      p->sigma_delta = 0.1;
      p->line = (long)k + 1;
      p->depolarisation = NAN;
    }
}

static double fitted(const vr_fit_result *r, const char *name) {
  for (size_t j = 0; j < r->nfree; j++)
    if (!strcmp(r->names[j], name)) return r->value[j];
  fail_msg("no parameter %s", name);
  return NAN;
}

static void delta_near_0_and_180(void **state) {
  (void)state;
  /* A 5 nm MgF2-like film (n 1.38) on glass (n 1.52): below the Brewster
   * angle of the glass Delta is near 180 deg, above it near 0/360; the
   * wrapped residual keeps both sides continuous. */
  vr_sample_model *truth = model("layer f constant thickness=5 n=1.38\nsubstrate constant n=1.52\n");
  const double angles[3] = {50, 56.6, 62};
  vr_ellipso_data d;
  data_of(truth, angles, 3, 400, 800, 21, &d);
  int near0 = 0, near180 = 0;
  for (size_t i = 0; i < d.n; i++) {
    near0 += d.p[i].delta_deg < 10 || d.p[i].delta_deg > 350;
    near180 += fabs(d.p[i].delta_deg - 180) < 10;
  }
  assert_true(near0 > 0 && near180 > 0);
  vr_sample_model *m = model("layer f constant thickness=8 fit min=0 max=300 n=1.38\nsubstrate constant n=1.52\n");
  vr_fit_result r;
  vr_error err = {0};
  assert_int_equal(vr_ellipso_fit(m, &d, NULL, &r, &err), VR_OK);
  assert_near(fitted(&r, "f.thickness"), 5.0, 1e-4);
  assert_true(r.mse < 1e-3);
  vr_fit_result_free(&r);
  vr_model_destroy(m);
  vr_model_destroy(truth);
  vr_ellipso_data_free(&d);
}

static void psi_near_45(void **state) {
  (void)state;
  /* Near normal incidence r_p = r_s and Psi -> 45 deg: the fit of a film
   * thickness from 5-10 deg data is poor but must stay finite and report
   * a large uncertainty rather than a spurious precision. */
  vr_sample_model *truth = model("layer f constant thickness=10 n=2.0\nsubstrate constant n=3.9 k=0.02\n");
  const double angles[2] = {5, 10};
  vr_ellipso_data d;
  data_of(truth, angles, 2, 400, 800, 11, &d);
  for (size_t i = 0; i < d.n; i++) assert_near(d.p[i].psi_deg, 45, 2.0);
  vr_sample_model *m = model("layer f constant thickness=12 fit min=0 max=400 n=2.0\nsubstrate constant n=3.9 k=0.02\n");
  vr_fit_result r;
  vr_error err = {0};
  assert_int_equal(vr_ellipso_fit(m, &d, NULL, &r, &err), VR_OK);
  assert_near(fitted(&r, "f.thickness"), 10.0, 1e-3);
  assert_true(isfinite(r.stderr_[0]));
  vr_fit_result_free(&r);
  vr_model_destroy(m);
  vr_model_destroy(truth);
  vr_ellipso_data_free(&d);
}

static void two_nm_film_reports_correlation(void **state) {
  (void)state;
  /* For films much thinner than the wavelength Psi, Delta depend on n and d
   * almost only through a product (Drude's thin-film approximation), so
   * fitting both must show |r(n, d)| > 0.95 and wide limits. */
  vr_sample_model *truth = model("layer ox cauchy thickness=2\nparam ox.A = 1.46\nparam ox.B = 0.00354\n"
                                 "substrate file:matdb/data/si_green2008.yml\n");
  const double angles[3] = {65, 70, 75};
  vr_ellipso_data d;
  data_of(truth, angles, 3, 400, 1000, 31, &d);
  vr_sample_model *m = model("layer ox cauchy thickness=2.5 fit min=0 max=50\nparam ox.A = 1.5 fit min=1.2 max=2.5\n"
                             "param ox.B = 0.00354\nsubstrate file:matdb/data/si_green2008.yml\n");
  vr_fit_result r;
  vr_error err = {0};
  assert_int_equal(vr_ellipso_fit(m, &d, NULL, &r, &err), VR_OK);
  if (r.covariance_ok) {
    double c = r.correlation[1];
    print_message("2 nm oxide: r(thickness, A) = %+.5f, d = %.4f +- %.4f nm\n", c, r.value[0], r.stderr_[0]);
    assert_true(fabs(c) > 0.95);
  } else {
    assert_contains(r.covariance_message, "ox");
  }
  vr_fit_result_free(&r);
  vr_model_destroy(m);
  vr_model_destroy(truth);
  vr_ellipso_data_free(&d);
}

static void absorbing_metal_film(void **state) {
  (void)state;
  /* 15 nm of a Drude metal (plasma energy 9 eV, damping 0.1 eV, silver-like)
   * on glass: thickness and plasma energy both recovered. */
  const char *tm = "layer metal genosc:drude thickness=15\nparam metal.Amp1 = 81\nparam metal.Br1 = 0.1\n"
                   "substrate constant n=1.52\n";
  vr_sample_model *truth = model(tm);
  const double angles[2] = {60, 70};
  vr_ellipso_data d;
  data_of(truth, angles, 2, 400, 900, 26, &d);
  vr_sample_model *m = model("layer metal genosc:drude thickness=20 fit min=1 max=60\n"
                             "param metal.Amp1 = 70 fit min=10 max=200\nparam metal.Br1 = 0.1\n"
                             "substrate constant n=1.52\n");
  vr_fit_result r;
  vr_error err = {0};
  assert_int_equal(vr_ellipso_fit(m, &d, NULL, &r, &err), VR_OK);
  assert_near(fitted(&r, "metal.thickness"), 15.0, 1e-3);
  assert_near(fitted(&r, "metal.Amp1"), 81.0, 1e-2);
  vr_fit_result_free(&r);
  vr_model_destroy(m);
  vr_model_destroy(truth);
  vr_ellipso_data_free(&d);
}

static void brewster_angle_data(void **state) {
  (void)state;
  /* Bare glass at its Brewster angle (n 1.5168: 56.60 deg) has Psi = 0 and an
   * undefined Delta; the bulk inversion and the Cauchy fit must neither
   * divide by zero nor return NaN. */
  vr_sample_model *truth = model("substrate cauchy\nparam substrate.A = 1.5046\nparam substrate.B = 0.0042\n");
  const double angles[3] = {55, 56.6, 58};
  vr_ellipso_data d;
  data_of(truth, angles, 3, 400, 800, 21, &d);
  vr_sample_model *bulk;
  vr_fit_result r;
  vr_error err = {0};
  assert_int_equal(vr_ellipso_fit_bulk(&d, NULL, &bulk, &r, &err), VR_OK);
  assert_near(fitted(&r, "substrate.A"), 1.5046, 1e-4);
  assert_near(fitted(&r, "substrate.B"), 0.0042, 1e-4);
  assert_true(isfinite(r.mse));
  vr_fit_result_free(&r);
  vr_model_destroy(bulk);
  vr_model_destroy(truth);
  vr_ellipso_data_free(&d);
}

static void single_angle_and_single_wavelength(void **state) {
  (void)state;
  vr_sample_model *truth = model("layer ox constant thickness=120 n=1.46\nsubstrate constant n=3.88 k=0.02\n");
  const double one[1] = {70};
  vr_ellipso_data d;
  /* One angle, many wavelengths: the thickness is well determined. */
  data_of(truth, one, 1, 400, 800, 41, &d);
  vr_sample_model *m = model("layer ox constant thickness=100 fit min=0 max=1000 n=1.46\nsubstrate constant n=3.88 k=0.02\n");
  vr_fit_result r;
  vr_error err = {0};
  assert_int_equal(vr_ellipso_fit(m, &d, NULL, &r, &err), VR_OK);
  assert_near(r.value[0], 120, 1e-3);
  vr_fit_result_free(&r);
  vr_model_destroy(m);
  vr_ellipso_data_free(&d);
  /* One wavelength and one angle: two numbers cannot fix three parameters. */
  data_of(truth, one, 1, 633, 633, 1, &d);
  m = model("layer ox constant thickness=100 fit min=0 max=1000\nparam ox.n = 1.5 fit\nparam ox.k = 0.01 fit\n"
            "substrate constant n=3.88 k=0.02\n");
  assert_int_equal(vr_ellipso_fit(m, &d, NULL, &r, &err), VR_E_ARG);
  assert_contains(err.message, "2 data values cannot determine 3 free parameters");
  vr_model_destroy(m);
  vr_ellipso_data_free(&d);
  vr_model_destroy(truth);
}

static void backside_reflection(void **state) {
  (void)state;
  /* A 1 mm glass slide with a reflecting back: the back-side beams add
   * incoherently, Psi moves and depolarisation appears; an absorbing (k =
   * 1e-3) slide kills them and gives back the semi-infinite answer. */
  vr_sample_model *front = model("substrate constant n=1.5\n");
  vr_sample_model *front_dark = model("substrate constant n=1.5 k=0.001\n");
  vr_sample_model *back = model("substrate constant thickness=1 backside n=1.5\n");
  vr_sample_model *dark = model("substrate constant thickness=1 backside n=1.5 k=0.001\n");
  double p0, d0, p1, d1, dp1, p2, d2, dp2;
  double pd, dd;
  vr_model_psi_delta(front, 600, 45, &p0, &d0, NULL, NULL);
  vr_model_psi_delta(front_dark, 600, 45, &pd, &dd, NULL, NULL);
  vr_model_psi_delta(back, 600, 45, &p1, &d1, &dp1, NULL);
  vr_model_psi_delta(dark, 600, 45, &p2, &d2, &dp2, NULL);
  assert_true(fabs(p1 - p0) > 0.5);
  assert_true(isfinite(dp1) && dp1 >= 0 && dp1 < 1);
  assert_near(p2, pd, 1e-6);
  assert_near(dp2, 0.0, 1e-9);
  /* A transparent bare slide keeps Delta at 180 (all beams in phase). */
  assert_near(d1, 180.0, 1e-9);
  vr_model_destroy(front);
  vr_model_destroy(back);
  vr_model_destroy(dark);
  vr_model_destroy(front_dark);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(delta_near_0_and_180),
      cmocka_unit_test(psi_near_45),
      cmocka_unit_test(two_nm_film_reports_correlation),
      cmocka_unit_test(absorbing_metal_film),
      cmocka_unit_test(brewster_angle_data),
      cmocka_unit_test(single_angle_and_single_wavelength),
      cmocka_unit_test(backside_reflection),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
