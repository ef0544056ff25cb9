/* Instrument offsets as model parameters: data simulated for 104.3 nm of
 * SiO2 (Malitson) on Si (Aspnes) with the angle of incidence 0.3° above its
 * nominal value and Δ shifted by 0.5° are fitted with the thickness and
 * both offsets free; noise-free, the fit must return the simulated values
 * (an analytic truth: the data are the model's). */
#include "vr_test.h"
#include "vr/ellipso_fit.h"

static const char *STACK = "layer oxide file:samples/ellipsometry/SiO2_Malitson.yml thickness=%s\n"
                           "substrate file:samples/ellipsometry/Si_Aspnes.yml\n%s";

static vr_sample_model *model(const char *thick, const char *extra) {
  char text[1024];
  snprintf(text, sizeof text, STACK, thick, extra);
  vr_sample_model *m = NULL;
  vr_error err = {0};
  if (vr_model_parse(text, strlen(text), "offsets.model", VR_SOURCE_DIR, NULL, &m, &err))
    fail_msg("%s", err.message);
  return m;
}

static void offsets_recovered(void **state) {
  (void)state;
  vr_sample_model *truth = model("104.3", "param sample.aoi_offset = 0.3\nparam sample.delta_offset = 0.5\n");
  vr_ellipso_data d = {0};
  d.p = calloc(3 * 66, sizeof *d.p);
  d.source = strdup("simulated");
  const double angles[3] = {65, 70, 75};
  for (int a = 0; a < 3; a++)
    for (int i = 0; i < 66; i++) {
      vr_ellipso_point *p = &d.p[d.n++];
      p->nm = 300 + 8 * i;
      p->aoi_deg = angles[a];
      p->sigma_psi = p->sigma_delta = 1;
      p->depolarisation = p->sigma_depolarisation = p->bandwidth_nm = NAN;
      vr_error err = {0};
      if (vr_model_psi_delta(truth, p->nm, p->aoi_deg, &p->psi_deg, &p->delta_deg, NULL, &err))
        fail_msg("%s", err.message);
    }
  vr_sample_model *m = model("100 fit min=0 max=300", "param sample.aoi_offset = 0 fit min=-2 max=2\n"
                                                      "param sample.delta_offset = 0 fit min=-5 max=5\n");
  vr_fit_options opt = vr_fit_default_options();
  vr_fit_result r = {0};
  vr_error err = {0};
  if (vr_ellipso_fit(m, &d, &opt, &r, &err)) fail_msg("%s", err.message);
  assert_near(m->layers[0].thickness_nm, 104.3, 1e-6);
  assert_near(m->aoi_offset_deg, 0.3, 1e-7);
  assert_near(m->delta_offset_deg, 0.5, 1e-7);
  assert_true(r.describes);
  /* Without the offsets the thickness is pulled away from the truth. */
  vr_sample_model *plain = model("100 fit min=0 max=300", "");
  vr_fit_result q = {0};
  if (vr_ellipso_fit(plain, &d, &opt, &q, &err)) fail_msg("%s", err.message);
  print_message("with offsets: misfit %.3g; without: %.3g (thickness %.3f nm)\n", r.misfit_ratio,
                q.misfit_ratio, plain->layers[0].thickness_nm);
  assert_true(fabs(plain->layers[0].thickness_nm - 104.3) > 0.1);
  vr_fit_result_free(&q);
  vr_fit_result_free(&r);
  vr_model_destroy(plain);
  vr_model_destroy(m);
  vr_model_destroy(truth);
  vr_ellipso_data_free(&d);
}

/* A thickness pinned at its bound is not a fit of it, however small the
 * misfit looks: the data (104.3 nm, noise-free) want it beyond max=104, so
 * the fit ends at 104 and its misfit alone (a few times a 0.001° noise
 * floor) might pass; the verdict says it does not describe the data and
 * names the parameter and bound. */
static void pinned_at_bound(void **state) {
  (void)state;
  vr_sample_model *truth = model("104.3", "");
  vr_ellipso_data d = {0};
  d.p = calloc(66, sizeof *d.p);
  d.source = strdup("simulated");
  for (int i = 0; i < 66; i++) {
    vr_ellipso_point *p = &d.p[d.n++];
    p->nm = 300 + 8 * i;
    p->aoi_deg = 70;
    p->sigma_psi = p->sigma_delta = 1;
    p->depolarisation = p->sigma_depolarisation = p->bandwidth_nm = NAN;
    vr_error err = {0};
    if (vr_model_psi_delta(truth, p->nm, p->aoi_deg, &p->psi_deg, &p->delta_deg, NULL, &err))
      fail_msg("%s", err.message);
  }
  vr_sample_model *m = model("100 fit min=0 max=104", "");
  vr_fit_options opt = vr_fit_default_options();
  vr_fit_result r = {0};
  vr_error err = {0};
  if (vr_ellipso_fit(m, &d, &opt, &r, &err)) fail_msg("%s", err.message);
  assert_int_equal(r.at_bound[0], 1);
  assert_false(r.describes);
  assert_contains(r.verdict, "does NOT describe the data: oxide.thickness at its upper bound 104");
  assert_contains(r.verdict, "rms residual");
  vr_fit_result_free(&r);
  /* With room the same fit is free and describes the data. */
  vr_sample_model *free_m = model("100 fit min=0 max=300", "");
  if (vr_ellipso_fit(free_m, &d, &opt, &r, &err)) fail_msg("%s", err.message);
  assert_int_equal(r.at_bound[0], 0);
  assert_true(r.describes);
  vr_fit_result_free(&r);
  vr_model_destroy(free_m);
  vr_model_destroy(m);
  vr_model_destroy(truth);
  vr_ellipso_data_free(&d);
}

/* An offset that takes an angle out of (0°, 90°) is an error, not a NaN. */
static void offset_domain(void **state) {
  (void)state;
  vr_sample_model *m = model("104.3", "param sample.aoi_offset = 5\n");
  double psi, delta;
  vr_error err = {0};
  assert_int_not_equal(vr_model_psi_delta(m, 600, 87, &psi, &delta, NULL, &err), VR_OK);
  assert_contains(err.message, "outside (0, 90)");
  vr_model_destroy(m);
}

int main(void) {
  const struct CMUnitTest tests[] = {cmocka_unit_test(offsets_recovered), cmocka_unit_test(pinned_at_bound),
                                      cmocka_unit_test(offset_domain)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
