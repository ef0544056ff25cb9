/* Parameter coupling in model files ("param film2.A = 2*film1.A + 0.1"):
 * the coupled value follows through a fit, the arithmetic is the stated
 * linear rule, and bad couplings are refused naming file and line. */
#include "vr_test.h"
#include "vr/ellipso_fit.h"

static vr_status parse(const char *text, vr_sample_model **m, vr_error *err) {
  return vr_model_parse(text, strlen(text), "c.model", VR_SOURCE_DIR, NULL, m, err);
}

static double value(vr_sample_model *m, const char *name) {
  long k = vr_model_param_index(m, name);
  assert_true(k >= 0);
  return vr_model_param_get(m, (size_t)k);
}

static void follows(void **state) {
  (void)state;
  vr_sample_model *m = NULL;
  vr_error err = {0};
  const char *text = "layer film1 cauchy thickness=50 A=1.5\n"
                     "layer film2 cauchy thickness=10 A=1.7\n"
                     "param film2.A = film1.A\n"
                     "param film2.thickness = 2 * film1.thickness + 1\n"
                     "param film2.B = film1.B*0.5 - 0.001\n"
                     "substrate file:samples/ellipsometry/Si_Aspnes.yml\n";
  if (parse(text, &m, &err)) fail_msg("%s", err.message);
  assert_near(value(m, "film2.A"), 1.5, 0);
  assert_near(value(m, "film2.thickness"), 101, 1e-12);
  /* Changing the parameters followed moves the followers on evaluation. */
  *vr_model_param_value(m, (size_t)vr_model_param_index(m, "film1.A")) = 1.6;
  *vr_model_param_value(m, (size_t)vr_model_param_index(m, "film1.thickness")) = 30;
  *vr_model_param_value(m, (size_t)vr_model_param_index(m, "film1.B")) = 0.01;
  double psi, delta;
  if (vr_model_psi_delta(m, 600, 70, &psi, &delta, NULL, &err)) fail_msg("%s", err.message);
  assert_near(value(m, "film2.A"), 1.6, 0);
  assert_near(value(m, "film2.thickness"), 61, 1e-12);
  assert_near(value(m, "film2.B"), 0.004, 1e-15);
  /* The same Ψ, Δ as the uncoupled model written out. */
  vr_sample_model *u = NULL;
  if (parse("layer film1 cauchy thickness=30 A=1.6 B=0.01\nlayer film2 cauchy thickness=61 A=1.6 B=0.004\n"
            "substrate file:samples/ellipsometry/Si_Aspnes.yml\n",
            &u, &err))
    fail_msg("%s", err.message);
  double psi2, delta2;
  if (vr_model_psi_delta(u, 600, 70, &psi2, &delta2, NULL, &err)) fail_msg("%s", err.message);
  assert_near(psi, psi2, 1e-12);
  assert_near(delta, delta2, 1e-12);
  vr_model_destroy(u);
  vr_model_destroy(m);
}

/* Two films of one material (same A) fitted as one: data simulated with
 * A = 1.55 for both; the fit frees film1.A only and recovers it. */
static void fitted_together(void **state) {
  (void)state;
  vr_sample_model *truth = NULL, *m = NULL;
  vr_error err = {0};
  if (parse("layer film1 cauchy thickness=80 A=1.55\nlayer film2 cauchy thickness=40 A=1.55\n"
            "substrate file:samples/ellipsometry/Si_Aspnes.yml\n",
            &truth, &err))
    fail_msg("%s", err.message);
  vr_ellipso_data d = {0};
  d.p = calloc(2 * 50, sizeof *d.p);
  d.source = strdup("simulated");
  for (int a = 0; a < 2; a++)
    for (int i = 0; i < 50; i++) {
      vr_ellipso_point *p = &d.p[d.n++];
      p->nm = 400 + 8 * i, p->aoi_deg = a ? 70 : 60, p->sigma_psi = p->sigma_delta = 1;
      p->depolarisation = p->sigma_depolarisation = p->bandwidth_nm = NAN;
      if (vr_model_psi_delta(truth, p->nm, p->aoi_deg, &p->psi_deg, &p->delta_deg, NULL, &err))
        fail_msg("%s", err.message);
    }
  if (parse("layer film1 cauchy thickness=80 A=1.45\nlayer film2 cauchy thickness=40 A=1.45\n"
            "param film1.A = 1.45 fit min=1.3 max=1.8\nparam film2.A = film1.A\n"
            "substrate file:samples/ellipsometry/Si_Aspnes.yml\n",
            &m, &err))
    fail_msg("%s", err.message);
  vr_fit_options opt = vr_fit_default_options();
  vr_fit_result r = {0};
  if (vr_ellipso_fit(m, &d, &opt, &r, &err)) fail_msg("%s", err.message);
  assert_int_equal(r.nfree, 1);
  assert_near(value(m, "film1.A"), 1.55, 1e-8);
  assert_near(value(m, "film2.A"), 1.55, 1e-8);
  vr_fit_result_free(&r);
  vr_model_destroy(m);
  vr_model_destroy(truth);
  vr_ellipso_data_free(&d);
}

static void refused(void **state) {
  (void)state;
  struct {
    const char *text, *expect;
  } cases[] = {
      {"layer f cauchy thickness=5\nparam f.A = g.A\nsubstrate constant\n", "c.model:2: parameter f.A follows an unknown parameter 'g.A'"},
      {"layer f cauchy thickness=5\nparam f.A = f.A\nsubstrate constant\n", "c.model:2: parameter f.A cannot follow itself"},
      {"layer f cauchy thickness=5\nlayer g cauchy thickness=5\nparam f.A = g.A fit\nsubstrate constant\n", "c.model:3: parameter f.A follows another: it cannot also be fitted"},
      {"layer f cauchy thickness=5\nlayer g cauchy thickness=5\nlayer h cauchy thickness=5\nparam g.A = f.A\nparam h.A = g.A\nsubstrate constant\n", "c.model:5: parameter h.A follows g.A, which itself follows another"},
      {"layer f cauchy thickness=5\nlayer g cauchy thickness=5\nparam g.thickness = f.thickness - 10\nsubstrate constant\n", "c.model:3: coupled parameter g.thickness = -5 is outside its domain"},
      {"layer f cauchy thickness=5\nparam f.A = 2*\nsubstrate constant\n", "c.model:2: parameter f.A: '2*' is neither a number nor a coupling"},
      {"layer f cauchy thickness=5\nlayer g cauchy thickness=5\nparam g.A = f.A + x\nsubstrate constant\n", "c.model:3: parameter g.A: no number after the sign"},
  };
  for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
    vr_sample_model *m = NULL;
    vr_error err = {0};
    if (parse(cases[i].text, &m, &err) == VR_OK) fail_msg("case %zu parsed", i);
    assert_contains(err.message, cases[i].expect);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {cmocka_unit_test(follows), cmocka_unit_test(fitted_together),
                                     cmocka_unit_test(refused)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
