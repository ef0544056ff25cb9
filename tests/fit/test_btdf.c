/* Pane tables for the renderer (exact slab, coated stack, measured pane),
 * their storage and interpolation, and the frosted-glass roughness fit. */
#include "vr_test.h"
#include "vr/btdf.h"
#include "vr/btdf_table.h"
#include "vr/frosted.h"

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

static vr_material *constant_glass(double n) {
  vr_material *m = vr_material_create("glass-1.52", VR_KIND_DIELECTRIC, NULL);
  double nm[2] = {300, 2500}, v[2] = {n, n};
  vr_material_add_spectrum(m, "n", vr_spectrum_create(2, nm, v, NULL), NULL);
  return m;
}

static void clear_pane_sunlight(void **state) {
  (void)state;
  /* A clear pane of n = 1.52 without absorption transmits 0.9183 of normal
   * sunlight and 0.4560 at 80 deg (issue "vr-render", the analytic two-face
   * series (1 - R)/(1 + R) per polarisation). */
  vr_material *m = constant_glass(1.52);
  const double angles[] = {0, 45, 80}, nm[] = {400, 550, 700};
  vr_btdf_table t;
  vr_error err = {0};
  assert_int_equal(vr_btdf_from_material(m, 0, angles, 3, nm, 3, &t, &err), VR_E_ARG);
  assert_contains(err.message, "--thickness");
  assert_int_equal(vr_btdf_from_material(m, 4e6, angles, 3, nm, 3, &t, &err), VR_OK);
  double T0 = 0.5 * (t.q[VR_BT_TS][1] + t.q[VR_BT_TP][1]);
  double T80 = 0.5 * (t.q[VR_BT_TS][2 * 3 + 1] + t.q[VR_BT_TP][2 * 3 + 1]);
  assert_near(T0, 0.9183, 5e-5);
  assert_near(T80, 0.4560, 5e-5);
  for (size_t i = 0; i < 9; i++)
    for (int p = 0; p < 2; p++) assert_near(t.q[VR_BT_TS + p][i] + t.q[VR_BT_RFS + p][i], 1, 1e-12);
  /* Stored and read back; 62.5 deg lies between 45 and 80 (linear). */
  vr_material *b;
  assert_int_equal(vr_btdf_table_material(&t, "pane-table", &b, &err), VR_OK);
  double v, v45, v80;
  assert_int_equal(vr_btdf_eval(b, VR_BTDF_T, VR_BTDF_UNPOLARISED, 80, 550, &v80, &err), VR_OK);
  assert_near(v80, T80, 1e-12);
  assert_int_equal(vr_btdf_eval(b, VR_BTDF_T, VR_BTDF_S, 45, 550, &v45, &err), VR_OK);
  assert_int_equal(vr_btdf_eval(b, VR_BTDF_T, VR_BTDF_S, 62.5, 550, &v, &err), VR_OK);
  assert_near(v, 0.5 * (v45 + t.q[VR_BT_TS][7]), 1e-12);
  assert_int_equal(vr_btdf_eval(b, VR_BTDF_T, VR_BTDF_S, 45, 1000, &v, &err), VR_E_RANGE);
  assert_int_equal(vr_btdf_eval(m, VR_BTDF_T, VR_BTDF_S, 45, 550, &v, &err), VR_E_ARG);
  vr_material_destroy(b);
  vr_btdf_table_free(&t);
  vr_material_destroy(m);
}

static vr_sample_model *model_from(const char *text) {
  vr_sample_model *m;
  vr_error err = {0};
  if (vr_model_parse(text, strlen(text), "pane.model", VR_SOURCE_DIR, NULL, &m, &err))
    fail_msg("%s", err.message);
  return m;
}

static void coated_pane(void **state) {
  (void)state;
  /* A quarter-wave film of n = 1.38 on n = 1.52 glass at 550 nm: the coated
   * face reflects ((1.52 - 1.38^2) / (1.52 + 1.38^2))^2 = 0.012596
   * (Macleod, Thin-Film Optical Filters, quarter-wave antireflection), the
   * bare face ((1.52 - 1)/(1.52 + 1))^2 = 0.042580; without absorption the
   * pane reflects R1 + (1-R1)^2 R2 / (1 - R1 R2) (incoherent sum). */
  vr_sample_model *m = model_from("layer ar constant thickness=99.6376811594 n=1.38\n"
                                  "substrate constant n=1.52 thickness=4 backside\n");
  const double angles[] = {0, 30, 60, 85}, nm[] = {450, 550, 650};
  vr_btdf_table t;
  vr_error err = {0};
  assert_int_equal(vr_btdf_from_model(m, angles, 4, nm, 3, &t, &err), VR_OK);
  double R1 = pow((1.52 - 1.38 * 1.38) / (1.52 + 1.38 * 1.38), 2), R2 = pow(0.52 / 2.52, 2);
  double R = R1 + (1 - R1) * (1 - R1) * R2 / (1 - R1 * R2);
  assert_near(t.q[VR_BT_RFS][1], R, 1e-9);
  assert_near(t.q[VR_BT_RBS][1], R, 1e-9); /* lossless: front and back reflect alike */
  for (size_t i = 0; i < 12; i++)
    for (int p = 0; p < 2; p++) assert_near(t.q[VR_BT_TS + p][i] + t.q[VR_BT_RFS + p][i], 1, 1e-9);
  vr_btdf_table_free(&t);
  vr_model_destroy(m);
  /* No backside substrate: refused with the line to write. */
  m = model_from("substrate constant n=1.52\n");
  assert_int_equal(vr_btdf_from_model(m, angles, 4, nm, 3, &t, &err), VR_E_ARG);
  assert_contains(err.message, "backside");
  vr_model_destroy(m);
}

static void frosted_roundtrip(void **state) {
  (void)state;
  /* Synthetic goniometric BTDF of a pane with one GGX face (alpha 0.3, n
   * 1.5), incidence 0 and 30 deg, outgoing 0-70 deg in and across the plane,
   * 2 % relative noise: the fit returns alpha within 3 standard errors and
   * the scale near 1. */
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 3);
  vr_btdf_sample s[90];
  size_t n = 0;
  for (int ti = 0; ti <= 30; ti += 30)
    for (int to = 0; to <= 70; to += 5)
      for (int ph = 0; ph <= 180; ph += 90) {
        double f = vr_frosted_btdf(0.3, 1.5, 1, ti, to, ph);
        if (!(f > 0)) continue;
        s[n++] = (vr_btdf_sample){ti, to, ph, f * (1 + gsl_ran_gaussian(rng, 0.02)), 0};
      }
  vr_frosted_fit fit;
  vr_error err = {0};
  assert_int_equal(vr_frosted_fit_alpha(s, n, 1.5, 0.02, &fit, &err), VR_OK);
  assert_near(fit.alpha, 0.3, 3 * fit.alpha_err);
  assert_true(fit.alpha_err < 0.01);
  assert_near(fit.scale, 1, 0.03);
  assert_near(fit.rms_rel, 0.02, 0.006);
  gsl_rng_free(rng);
  /* A smooth limit: scattering concentrates around the refracted direction:
   * at normal incidence the BTDF peaks straight through. */
  assert_true(vr_frosted_btdf(0.05, 1.5, 1, 0, 0, 0) > 10 * vr_frosted_btdf(0.05, 1.5, 1, 0, 20, 0));
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(clear_pane_sunlight),
      cmocka_unit_test(coated_pane),
      cmocka_unit_test(frosted_roundtrip),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
