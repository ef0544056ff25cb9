/* Chromogenic state models: round trips of electrochromic and photochromic
 * models through noisy synthetic spectra (the fitted values must fall inside
 * the reported 90 % limits about as often as 90 % promises), the stored
 * material's evaluation, and state-token errors. */
#include "vr_test.h"
#include "vr/chromogenic.h"
#include "vr/chromogenic_fit.h"

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#define NL 125
static double grid[NL];

/* Clear glass: T0 between 0.80 and 0.90 over 380-1000 nm. */
static double t0_true(double nm) { return 0.80 + 0.10 * (nm - 380) / 620; }

/* WO3 coloration efficiency: 78 cm2/C at 632.8 nm and 125 cm2/C at 950 nm
 * (literature values gathered in samples/glazing/README.md); a Gaussian
 * band in photon energy through both, centred at 1.2 eV. */
static double eta_true(double nm) {
  const double c = 1.2, e1 = 1239.84198 / 632.8, e2 = 1239.84198 / 950;
  /* exp(-((e1-c)^2 - (e2-c)^2) / (2 w^2)) = 78/125 fixes the width. */
  double two_w2 = ((e1 - c) * (e1 - c) - (e2 - c) * (e2 - c)) / log(125.0 / 78.0);
  double e = 1239.84198 / nm;
  return 125.0 * exp(-((e - c) * (e - c) - (e2 - c) * (e2 - c)) / two_w2);
}

static vr_spectrum *spectrum_of(double (*f)(double, const void *), const void *ctx, gsl_rng *rng,
                                double sigma) {
  double v[NL];
  for (int j = 0; j < NL; j++) v[j] = fmax(f(grid[j], ctx) + gsl_ran_gaussian(rng, sigma), 0);
  return vr_spectrum_create(NL, grid, v, NULL);
}

static double ec_T(double nm, const void *ctx) {
  double q = *(const double *)ctx; /* mC/cm2 */
  return t0_true(nm) * pow(10, -eta_true(nm) * q * 1e-3);
}

static void electrochromic_round_trip(void **state) {
  (void)state;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 11);
  const double q[5] = {0, 3, 6, 9, 12}, sigma = 1e-3;
  vr_chromo_state st[5];
  vr_spectrum *T[5];
  char tok[32];
  for (int i = 0; i < 5; i++) {
    snprintf(tok, sizeof tok, "%gmC/cm2", q[i]);
    assert_int_equal(vr_chromo_state_parse(tok, &st[i], NULL), VR_OK);
    T[i] = spectrum_of(ec_T, &q[i], rng, sigma);
  }
  vr_chromo_fit_result r;
  vr_error err = {0};
  assert_int_equal(vr_chromo_fit(5, st, (const vr_spectrum *const *)T, NULL, NULL, sigma, &r, &err),
                   VR_OK);
  assert_int_equal(r.type, VR_CHROMO_ELECTRO);
  assert_near(r.q_full, 12, 0);
  /* Coverage of the 90 % limits of dOD over the wavelengths. */
  int inside = 0;
  for (int j = 0; j < NL; j++) {
    double truth = eta_true(grid[j]) * 12e-3;
    inside += fabs(r.dOD[j] - truth) <= r.dOD_ci90[j];
  }
  double cover = (double)inside / NL;
  assert_true(cover >= 0.80 && cover <= 0.98);
  vr_material *m;
  assert_int_equal(vr_chromo_fit_material(&r, "ec-test", 6.0, &m, &err), VR_OK);
  double s, Tm, eta;
  assert_int_equal(vr_chromo_state_of_charge(m, 6, &s, &err), VR_OK);
  assert_near(s, 0.5, 1e-12);
  /* Outside the fitted charges (0 to Q_full = 12 mC/cm2, the charges of the
   * synthetic states above) there is no state: refused, never clamped. */
  double s_end;
  assert_int_equal(vr_chromo_state_of_charge(m, 12, &s_end, &err), VR_OK);
  assert_near(s_end, 1.0, 1e-12);
  assert_int_equal(vr_chromo_state_of_charge(m, 12.5, &s_end, &err), VR_E_RANGE);
  assert_non_null(strstr(err.message, "outside the calibrated range"));
  assert_int_equal(vr_chromo_state_of_charge(m, -5, &s_end, &err), VR_E_RANGE);
  assert_int_equal(vr_chromo_eval(m, s, 632.8, &Tm, NULL, NULL, &err), VR_OK);
  double q6 = 6;
  assert_near(Tm, ec_T(632.8, &q6), 3e-3);
  /* Coloration efficiency at 632.8 nm back within 5 % (noise 1e-3). */
  assert_int_equal(vr_material_eval(m, "eta", 632.8, false, &eta, NULL, &err), VR_OK);
  assert_rel(eta, 78.0, 0.05);
  assert_int_equal(vr_chromo_eval(m, 1.5, 632.8, &Tm, NULL, NULL, &err), VR_E_RANGE);
  assert_int_equal(vr_chromo_steady_state(m, 10, 298, 0, &s, &err), VR_E_ARG);
  vr_material_destroy(m);
  vr_chromo_fit_free(&r);
  for (int i = 0; i < 5; i++) vr_spectrum_destroy(T[i]);
  gsl_rng_free(rng);
}

/* Photochromic truth: a = 2e-3 m2/(W s); b_ref = ln 2 / 56 s (the 56 s
 * half-fade at 25 C of Caurant et al.'s silver-halide glass); Ea = 0.44 eV
 * = 42.45 kJ/mol (same source); darkened band over 400-700 nm. */
static const double A_TRUE = 2e-3, B_TRUE = 0.6931471805599453 / 56, EA_TRUE = 42453;

static double pc_state(const vr_chromo_state *q) {
  double b = B_TRUE * exp(-(EA_TRUE / VR_GAS_CONSTANT) * (1 / q->T_K - 1 / 298.15));
  double ss = A_TRUE * q->E / (A_TRUE * q->E + b);
  if (q->kind == VR_STATE_STEADY) return ss;
  if (q->kind == VR_STATE_ACTIVATION) return ss * (1 - exp(-(A_TRUE * q->E + b) * q->t));
  return ss * exp(-b * q->t);
}

static double pc_T(double nm, const void *ctx) {
  double s = *(const double *)ctx;
  double dod = 0.7 * exp(-pow((nm - 550) / 120, 2));
  return 0.88 * pow(10, -s * dod);
}

static void photochromic_round_trip(void **state) {
  (void)state;
  const char *tokens = "E=0,E=2,E=5,E=10,E=20,E=40,t=20:E=20,t=60:E=20,fade=60:E=20,"
                       "E=10:T=10C,E=10:T=40C";
  vr_chromo_state *st;
  size_t ns;
  vr_error err = {0};
  assert_int_equal(vr_chromo_states_parse(tokens, &st, &ns, &err), VR_OK);
  assert_int_equal(ns, 11);
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  const int draws = 100;
  int inside[3] = {0, 0, 0};
  for (int d = 0; d < draws; d++) {
    gsl_rng_set(rng, 100 + (unsigned long)d);
    vr_spectrum *T[11];
    for (size_t i = 0; i < ns; i++) {
      double s = pc_state(&st[i]);
      T[i] = spectrum_of(pc_T, &s, rng, 2e-3);
    }
    vr_chromo_fit_result r;
    assert_int_equal(vr_chromo_fit(ns, st, (const vr_spectrum *const *)T, NULL, NULL, 2e-3, &r, &err),
                     VR_OK);
    const double truth[3] = {A_TRUE, B_TRUE, EA_TRUE};
    for (int k = 0; k < 3; k++) {
      assert_true(r.params[k].fitted);
      inside[k] += fabs(r.params[k].value - truth[k]) <= r.params[k].ci90;
    }
    if (d == 0) {
      /* The stored material's steady state is a E / (a E + b) of the fitted
       * rates (issue "vr-spectro"), and near the truth. */
      vr_material *m;
      assert_int_equal(vr_chromo_fit_material(&r, "pc-test", 4.0, &m, &err), VR_OK);
      double s, a = r.params[0].value, b = r.params[1].value;
      assert_int_equal(vr_chromo_steady_state(m, 30, 298.15, 0, &s, &err), VR_OK);
      assert_near(s, a * 30 / (a * 30 + b), 1e-12);
      vr_chromo_state q = {.kind = VR_STATE_STEADY, .E = 30, .T_K = 298.15};
      assert_near(s, pc_state(&q), 0.02);
      /* Warmer glass fades faster, so it is paler in the same sun. */
      double s_hot;
      assert_int_equal(vr_chromo_steady_state(m, 30, 308.15, 0, &s_hot, &err), VR_OK);
      assert_true(s_hot < s);
      /* Activation from bleached approaches the steady state. */
      double s_t;
      assert_int_equal(vr_chromo_state_after(m, 30, 298.15, 0, 0, 1e4, &s_t, &err), VR_OK);
      assert_near(s_t, s, 1e-9);
      /* The states span 0-40 W/m2 and 10-40 C (the tokens above): outside
       * that the model is refused unless asked to extrapolate (issue 35),
       * and then it is the same formula. */
      double s_x;
      assert_int_equal(vr_chromo_steady_state(m, 60, 298.15, 0, &s_x, &err), VR_E_RANGE);
      assert_contains(err.message, "0 to 40 W/m2");
      assert_int_equal(vr_chromo_steady_state(m, 40, 298.15, 0, &s_x, &err), VR_OK);
      assert_int_equal(vr_chromo_steady_state(m, 30, 273.15 + 50, 0, &s_x, &err), VR_E_RANGE);
      assert_contains(err.message, "283.15 to 313.15 K");
      assert_int_equal(vr_chromo_steady_state(m, 30, 273.15, 0, &s_x, &err), VR_E_RANGE);
      assert_int_equal(vr_chromo_state_after(m, 60, 298.15, 0, 0, 10, &s_x, &err), VR_E_RANGE);
      assert_int_equal(vr_chromo_steady_state(m, 60, 298.15, VR_CHROMO_EXTRAPOLATE, &s_x, &err),
                       VR_OK);
      assert_near(s_x, a * 60 / (a * 60 + b), 1e-12);
      vr_material_destroy(m);
    }
    vr_chromo_fit_free(&r);
    for (size_t i = 0; i < ns; i++) vr_spectrum_destroy(T[i]);
  }
  for (int k = 0; k < 3; k++) {
    double cover = (double)inside[k] / draws;
    print_message("photochromic parameter %d: 90%% limits held %d of %d\n", k, inside[k], draws);
    if (cover < 0.80 || cover > 0.97) fail_msg("parameter %d: 90%% limits held %d of %d", k, inside[k], draws);
  }
  free(st);
  gsl_rng_free(rng);
}

static void steady_only_gives_K(void **state) {
  (void)state;
  /* Steady states alone fix only K = b/a (ISSUE: a, b not separable); one
   * temperature holds Ea. */
  vr_chromo_state *st;
  size_t ns;
  assert_int_equal(vr_chromo_states_parse("E=0,E=5,E=10,E=20,E=40,E=80", &st, &ns, NULL), VR_OK);
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 5);
  vr_spectrum *T[6];
  for (size_t i = 0; i < ns; i++) {
    double s = pc_state(&st[i]);
    T[i] = spectrum_of(pc_T, &s, rng, 1e-3);
  }
  vr_chromo_fit_result r;
  vr_error err = {0};
  assert_int_equal(vr_chromo_fit(ns, st, (const vr_spectrum *const *)T, NULL, NULL, 1e-3, &r, &err),
                   VR_OK);
  assert_false(r.params[0].fitted);
  assert_false(r.params[2].fitted);
  assert_near(r.params[3].value, B_TRUE / A_TRUE, 3 * r.params[3].stderr_);
  vr_material *m;
  assert_int_equal(vr_chromo_fit_material(&r, "pc-k", 0, &m, &err), VR_OK);
  double s;
  assert_int_equal(vr_chromo_state_after(m, 10, 298.15, 0, 0, 10, &s, &err), VR_E_NOT_FOUND);
  assert_contains(err.message, "time series");
  /* Fitted at 25 C only: no activation energy, so 35 C is refused (issue
   * 35), and 25.3 C is the same temperature within rounding. */
  assert_int_equal(vr_chromo_steady_state(m, 10, 308.15, 0, &s, &err), VR_E_RANGE);
  assert_contains(err.message, "activation energy");
  assert_int_equal(vr_chromo_steady_state(m, 10, 298.45, 0, &s, &err), VR_OK);
  assert_int_equal(vr_chromo_steady_state(m, 100, 298.15, 0, &s, &err), VR_E_RANGE);
  vr_material_destroy(m);
  vr_chromo_fit_free(&r);
  for (size_t i = 0; i < ns; i++) vr_spectrum_destroy(T[i]);
  free(st);
  gsl_rng_free(rng);
}

static void state_errors(void **state) {
  (void)state;
  vr_chromo_state s;
  vr_error err = {0};
  assert_int_equal(vr_chromo_state_parse("abc", &s, &err), VR_E_PARSE);
  assert_contains(err.message, "\"abc\"");
  assert_int_equal(vr_chromo_state_parse("-3", &s, &err), VR_E_RANGE);
  assert_int_equal(vr_chromo_state_parse("t=60", &s, &err), VR_E_PARSE);
  assert_contains(err.message, "E=");
  assert_int_equal(vr_chromo_state_parse("E=10:T=hot", &s, &err), VR_E_PARSE);
  assert_int_equal(vr_chromo_state_parse("E=10:x=1", &s, &err), VR_E_PARSE);
  assert_int_equal(vr_chromo_state_parse("E=10:T=25C", &s, &err), VR_OK);
  assert_near(s.T_K, 298.15, 1e-9);
  assert_int_equal(vr_chromo_state_parse("-1.5V", &s, &err), VR_OK);
  assert_int_equal(s.kind, VR_STATE_VOLTAGE);
  /* Mixed kinds are refused. */
  vr_chromo_state mixed[3];
  vr_chromo_state_parse("0", &mixed[0], NULL);
  vr_chromo_state_parse("E=5", &mixed[1], NULL);
  vr_chromo_state_parse("4", &mixed[2], NULL);
  double nm[2] = {400, 500}, v[2] = {0.8, 0.8};
  vr_spectrum *t = vr_spectrum_create(2, nm, v, NULL);
  const vr_spectrum *T[3] = {t, t, t};
  vr_chromo_fit_result r;
  assert_int_equal(vr_chromo_fit(3, mixed, T, NULL, NULL, 1e-3, &r, &err), VR_E_ARG);
  assert_contains(err.message, "different kinds");
  vr_spectrum_destroy(t);
}

int main(void) {
  for (int j = 0; j < NL; j++) grid[j] = 380 + 5.0 * j;
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(electrochromic_round_trip),
      cmocka_unit_test(photochromic_round_trip),
      cmocka_unit_test(steady_only_gives_K),
      cmocka_unit_test(state_errors),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
