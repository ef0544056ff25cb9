/* EN 673's U and EN 410's secondary heat transfer (vr/glazing_en673.h)
 * against the standards' own equations, written out here for the cases
 * where they close by hand, and the declared values the glass trade
 * publishes for the common double glazings.
 *
 * Sources of the numbers:
 *  - EN 673:2011 (and :1997) equations (1)-(10), its gas table at 10 C
 *    (air: rho 1.232 kg/m3, mu 1.761e-5 kg/(m s), lambda 2.496e-2 W/(m K),
 *    c 1008 J/(kg K); argon 1.699, 2.164e-5, 1.684e-2, 519), Tm = 283 K,
 *    dT = 15 K, A = 0.035 and n = 0.38 for vertical glazing, the film
 *    coefficients he 25 / hi 3.6 + 4.1 e/0.837 (2011) and 23 / 3.6 + 4.4
 *    e/0.837 (1997), U declared to one decimal;
 *  - EN 410:2011 section 5.4.3-5.4.6: q_i for single, double and triple
 *    glazing in closed form;
 *  - the declared U of 4-16-4 double glazing: 2.7 with air, 2.6 with
 *    argon, 1.1 with argon and a coating of corrected emissivity 0.03 on
 *    face 3 (the values glass makers print for these build-ups). */
#include "vr_test.h"
#include "vr/glazing_en673.h"

static vr_en673_system double_glazing(const char *gas, double gap_mm, double e3) {
  vr_en673_system s = {0};
  s.n = 2;
  for (int i = 0; i < 2; i++)
    s.pane[i] = (vr_en673_pane){0.004, 1.0, {VR_EN673_UNCOATED, VR_EN673_UNCOATED}, 0.0};
  s.pane[1].emis[0] = e3;
  s.gap_m[0] = gap_mm * 1e-3;
  vr_error err = {0};
  assert_int_equal(vr_gas_parse(gas, &s.gas[0], &err), VR_OK);
  return s;
}

/* EN 673 for one gap, written out: the gap's hr and hg at dT = 15 K. */
static double by_hand(double rho, double mu, double lambda, double c, double s, double e1,
                      double e2, double d_glass, double he, double hi) {
  const double sigma = 5.67e-8, Tm = 283.0;
  double hr = 4 * sigma * pow(1 / e1 + 1 / e2 - 1, -1) * Tm * Tm * Tm;
  double Gr = 9.81 * s * s * s * 15.0 * rho * rho / (Tm * mu * mu);
  double Pr = mu * c / lambda;
  double Nu = 0.035 * pow(Gr * Pr, 0.38);
  if (Nu < 1) Nu = 1;
  double hs = hr + Nu * lambda / s;
  return 1 / (1 / he + d_glass + 1 / hs + 1 / hi);
}

static void declared_double_glazing(void **state) {
  (void)state;
  vr_en673_result r;
  vr_error err = {0};
  const double e = VR_EN673_UNCOATED, hi = 3.6 + 4.1;
  /* 4-16-4 air: (Gr Pr) 7.4e3, Nu 1.034, U 2.731: declared 2.7. */
  vr_en673_system s = double_glazing("air", 16, e);
  assert_int_equal(vr_en673_u(&s, &r, &err), VR_OK);
  double want = by_hand(1.232, 1.761e-5, 2.496e-2, 1008, 0.016, e, e, 0.008, 25, hi);
  print_message("4-16-4 air: U %.6f (by hand %.6f), declared %.1f, Nu %.4f\n", r.U, want,
                r.U_declared, r.Nu[0]);
  assert_true(fabs(r.U - want) < 1e-12 * want);
  assert_true(r.U_declared == 2.7);
  assert_true(r.Nu[0] > 1.0); /* convection counts at 16 mm */
  assert_true(fabs(r.he - 25) < 1e-15 && fabs(r.hi - 7.7) < 1e-12);
  /* Argon: 2.6. */
  s = double_glazing("argon", 16, e);
  assert_int_equal(vr_en673_u(&s, &r, &err), VR_OK);
  want = by_hand(1.699, 2.164e-5, 1.684e-2, 519, 0.016, e, e, 0.008, 25, hi);
  print_message("4-16-4 argon: U %.6f, declared %.1f\n", r.U, r.U_declared);
  assert_true(fabs(r.U - want) < 1e-12 * want);
  assert_true(r.U_declared == 2.6);
  /* Argon and a low-e coating of 0.03 on face 3: 1.1. */
  s = double_glazing("argon", 16, 0.03);
  assert_int_equal(vr_en673_u(&s, &r, &err), VR_OK);
  want = by_hand(1.699, 2.164e-5, 1.684e-2, 519, 0.016, e, 0.03, 0.008, 25, hi);
  print_message("4-16Ar-4, e 0.03 on face 3: U %.6f, declared %.1f\n", r.U, r.U_declared);
  assert_true(fabs(r.U - want) < 1e-12 * want);
  assert_true(r.U_declared == 1.1);
  /* A 90 % argon fill: each property by volume between the two gases. */
  s = double_glazing("argon:0.9+air:0.1", 16, 0.03);
  assert_int_equal(vr_en673_u(&s, &r, &err), VR_OK);
  want = by_hand(0.9 * 1.699 + 0.1 * 1.232, 0.9 * 2.164e-5 + 0.1 * 1.761e-5,
                 0.9 * 1.684e-2 + 0.1 * 2.496e-2, 0.9 * 519 + 0.1 * 1008, 0.016, e, 0.03, 0.008,
                 25, hi);
  assert_true(fabs(r.U - want) < 1e-12 * want);
  /* A narrow gap conducts: Nu is held at 1, hg = lambda / s. */
  s = double_glazing("air", 6, e);
  assert_int_equal(vr_en673_u(&s, &r, &err), VR_OK);
  assert_true(r.Nu[0] == 1.0);
  assert_true(fabs(r.hg[0] - 2.496e-2 / 0.006) < 1e-12);
}

/* The 1997 edition's films: he 23, hi 8.0 for uncoated glass; a low-e
 * inner face lowers hi (EN 673 equation (10)). */
static void editions_and_inner_face(void **state) {
  (void)state;
  double he, hi;
  vr_en673_films(VR_EN673_1997, VR_EN673_UNCOATED, &he, &hi);
  assert_true(he == 23 && fabs(hi - 8.0) < 1e-12);
  vr_en673_films(VR_EN673_2011, 0.2, &he, &hi);
  assert_true(he == 25 && fabs(hi - (3.6 + 4.1 * 0.2 / 0.837)) < 1e-15);
  vr_en673_system s = double_glazing("air", 16, VR_EN673_UNCOATED);
  s.pane[1].emis[1] = 0.2;
  vr_en673_result r;
  vr_error err = {0};
  assert_int_equal(vr_en673_u(&s, &r, &err), VR_OK);
  assert_true(fabs(r.hi - hi) < 1e-15);
  /* A single pane: 1/U = 1/he + d/k + 1/hi. */
  vr_en673_system one = {0};
  one.n = 1;
  one.pane[0] = (vr_en673_pane){0.004, 1.0, {VR_EN673_UNCOATED, VR_EN673_UNCOATED}, 0.0};
  assert_int_equal(vr_en673_u(&one, &r, &err), VR_OK);
  assert_true(fabs(r.U - 1 / (1 / 25.0 + 0.004 + 1 / 7.7)) < 1e-12);
  assert_true(r.U_declared == 5.8);
}

/* Triple glazing: the 15 K are shared in proportion to the gaps'
 * resistances (EN 673's iteration), so every gap ends at the same heat
 * flow dT_k hs_k; equal gaps share equally. */
static void triple_glazing(void **state) {
  (void)state;
  vr_en673_system s = {0};
  s.n = 3;
  for (int i = 0; i < 3; i++)
    s.pane[i] = (vr_en673_pane){0.004, 1.0, {VR_EN673_UNCOATED, VR_EN673_UNCOATED}, 0.0};
  s.pane[1].emis[0] = 0.05; /* face 3 coated: the two gaps differ */
  vr_error err = {0};
  for (int k = 0; k < 2; k++) {
    assert_int_equal(vr_gas_parse("argon", &s.gas[k], &err), VR_OK);
    s.gap_m[k] = 0.018;
  }
  vr_en673_result r;
  assert_int_equal(vr_en673_u(&s, &r, &err), VR_OK);
  print_message("4-18Ar-4(e 0.05)-18Ar-4: U %.4f, dT %.3f + %.3f K, %d iterations\n", r.U, r.dT[0],
                r.dT[1], r.iterations);
  assert_true(fabs(r.dT[0] + r.dT[1] - 15.0) < 1e-12);
  assert_true(fabs(r.dT[0] * r.hs[0] - r.dT[1] * r.hs[1]) < 1e-9 * r.dT[0] * r.hs[0]);
  assert_true(r.dT[0] > r.dT[1]); /* the coated gap holds the larger share */
  s.pane[1].emis[0] = VR_EN673_UNCOATED;
  assert_int_equal(vr_en673_u(&s, &r, &err), VR_OK);
  assert_true(fabs(r.dT[0] - 7.5) < 1e-12 && fabs(r.dT[1] - 7.5) < 1e-12);
}

/* EN 410's q_i in closed form (section 5.4.3-5.4.6) against the series
 * network: one pane a he/(he + hi) ... */
static void qi_closed_forms(void **state) {
  (void)state;
  const double he = 25, hi = 7.7;
  double a1 = 0.0832, a2 = 0.0519, a3 = 0.0371, L12 = 3.21, L23 = 1.87;
  double a[3] = {a1, a2, a3}, L[2] = {L12, L23};
  assert_true(fabs(vr_en410_qi(1, a, he, hi, NULL) - a1 * hi / (he + hi)) < 1e-16);
  double two = ((a1 + a2) / he + a2 / L12) / (1 / hi + 1 / he + 1 / L12);
  assert_true(fabs(vr_en410_qi(2, a, he, hi, L) - two) < 1e-16);
  double three = ((a1 + a2 + a3) / he + (a2 + a3) / L12 + a3 / L23) /
                 (1 / hi + 1 / he + 1 / L12 + 1 / L23);
  assert_true(fabs(vr_en410_qi(3, a, he, hi, L) - three) < 1e-16);
  /* Nothing absorbed, nothing re-emitted; bad arguments give NAN. */
  double zero[3] = {0};
  assert_true(vr_en410_qi(3, zero, he, hi, L) == 0);
  assert_true(isnan(vr_en410_qi(0, a, he, hi, L)));
  double bad[2] = {1, 0};
  assert_true(isnan(vr_en410_qi(3, a, he, hi, bad)));
}

/* EN 410's Lambda for double glazing runs from the outer face of the
 * outer pane to the inner face of the inner pane: both panes' whole
 * glass resistances and the gap's. */
static void lambda_spans(void **state) {
  (void)state;
  vr_en673_system s = double_glazing("air", 12, VR_EN673_UNCOATED);
  s.pane[0].thickness_m = 0.006;
  vr_en673_result r;
  vr_error err = {0};
  assert_int_equal(vr_en673_u(&s, &r, &err), VR_OK);
  assert_true(fabs(1 / r.Lambda[0] - (0.006 + 1 / r.hs[0] + 0.004)) < 1e-14);
}

static void refusals(void **state) {
  (void)state;
  vr_en673_system s = double_glazing("air", 16, VR_EN673_UNCOATED);
  vr_en673_result r;
  vr_error err = {0};
  s.pane[1].emis[0] = 0;
  assert_int_equal(vr_en673_u(&s, &r, &err), VR_E_RANGE);
  assert_non_null(strstr(err.message, "pane 2: outer emissivity"));
  s = double_glazing("air", 16, VR_EN673_UNCOATED);
  s.gap_m[0] = -0.016;
  assert_int_equal(vr_en673_u(&s, &r, &err), VR_E_RANGE);
  assert_non_null(strstr(err.message, "gap 1"));
  s = double_glazing("air", 16, VR_EN673_UNCOATED);
  s.pane[0].thickness_m = NAN;
  assert_int_equal(vr_en673_u(&s, &r, &err), VR_E_RANGE);
  s.n = 0;
  assert_int_equal(vr_en673_u(&s, &r, &err), VR_E_ARG);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(declared_double_glazing), cmocka_unit_test(editions_and_inner_face),
      cmocka_unit_test(triple_glazing),          cmocka_unit_test(qi_closed_forms),
      cmocka_unit_test(lambda_spans),            cmocka_unit_test(refusals),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
