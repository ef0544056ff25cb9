/* The ISO 15099 heat balance (vr/glazing_thermal.h) against what physics
 * fixes whatever the correlations: with no radiation (every emissivity 0)
 * a pane is three resistances in series, q = dT / (1/h_out + d/k + 1/h_in)
 * (Fourier's law and Newton's law of cooling); with sun, what the panes
 * absorb leaves by the two faces (the first law); and the edges of its
 * domain: perfectly reflecting faces, a black pane in full sun, and what
 * it refuses (WinCalc's figures for real glazings:
 * tests/cli/test_vr_spectro_thermal.sh). */
#include "vr_test.h"
#include "vr/glazing_thermal.h"

static vr_thermal_system one_pane(double emis) {
  vr_thermal_system s = {0};
  s.n = 1;
  s.height_m = 1;
  s.tilt_deg = 90;
  s.pane[0] = (vr_thermal_pane){0.006, 1.0, {emis, emis}, 0.0, 0.0};
  return s;
}

static vr_thermal_system two_panes(double e_in, double a0, double a1) {
  vr_thermal_system s = one_pane(0.84);
  s.n = 2;
  s.pane[0].absorptance = a0;
  s.pane[0].emis[1] = e_in;
  s.pane[1] = (vr_thermal_pane){0.004, 1.0, {e_in, 0.84}, 0.0, a1};
  vr_error err = {0};
  assert_int_equal(vr_gas_parse("argon:0.9+air:0.1", &s.gap[0].gas, &err), VR_OK);
  s.gap[0].thickness_m = 0.016;
  s.gap[0].pressure_pa = 101325;
  return s;
}

/* No radiation: the film coefficients the solver reports are its
 * convective ones, and the flow through the pane is the series law's. */
static void series_resistances(void **state) {
  (void)state;
  vr_thermal_system s = one_pane(0.0);
  vr_thermal_state o;
  vr_error err = {0};
  assert_int_equal(vr_thermal_solve(&s, &VR_ENV_NFRC_U, 0, &o, &err), VR_OK);
  const vr_thermal_env *e = &VR_ENV_NFRC_U;
  double want = (e->T_in - e->T_out) / (1 / o.h_out + 0.006 / 1.0 + 1 / o.h_in);
  /* Radiation left: the emissivity floor's 4e-6 sigma T^3, about 4e-6. */
  assert_near(o.h_out, 4 + 4 * e->wind_ms, 1e-5);
  assert_true(fabs(o.q_in - want) < 1e-7 * want);
  /* And the glass's drop (inner face warmer) is the flow times d/k. */
  print_message("    drop across the glass %.9f K, q d/k %.9f K\n", o.T[1] - o.T[0],
                o.q_in * 0.006 / 1.0);
  assert_true(fabs((o.T[1] - o.T[0]) - o.q_in * 0.006 / 1.0) < 1e-7);
}

/* With sun: absorbed = heat to the outside + heat to the room. */
static void first_law(void **state) {
  (void)state;
  vr_thermal_system s = two_panes(0.04, 0.30, 0.05);
  vr_thermal_state o;
  vr_error err = {0};
  const vr_thermal_env *e = &VR_ENV_NFRC_SHGC;
  assert_int_equal(vr_thermal_solve(&s, e, 1, &o, &err), VR_OK);
  double sg = VR_SIGMA, J_out = sg * pow(e->T_out, 4);
  double q_out = (o.J[0] - J_out) + (4 + 4 * e->wind_ms) * (o.T[0] - e->T_out);
  double absorbed = (0.30 + 0.05) * e->solar_wm2;
  print_message("    absorbed %.6f W/m2, out %.6f, in %.6f\n", absorbed, q_out, -o.q_in);
  assert_true(fabs(absorbed - (q_out - o.q_in)) < 1e-5);
}

/* Edges: facing faces that are perfect mirrors (emissivity 0) leave only
 * the gas to carry heat, so U falls below that of clear faces (and the
 * system, singular as written, is still solved); a black pane in full sun
 * converges; a pane of zero emissivity alone too. */
static void edges(void **state) {
  (void)state;
  vr_thermal_figures clear, mirror, black;
  vr_error err = {0};
  vr_thermal_system s = two_panes(0.84, 0.1, 0.05);
  assert_int_equal(vr_thermal_nfrc(&s, 0.7, &clear, &err), VR_OK);
  s = two_panes(0.0, 0.1, 0.05);
  assert_int_equal(vr_thermal_nfrc(&s, 0.7, &mirror, &err), VR_OK);
  print_message("    U clear faces %.4f, mirror faces %.4f\n", clear.U, mirror.U);
  assert_true(mirror.U < clear.U - 1.0);
  s = one_pane(1.0);
  s.pane[0].absorptance = 1.0;
  assert_int_equal(vr_thermal_nfrc(&s, 0.0, &black, &err), VR_OK);
  /* All of the sun is absorbed; some of it reaches the room, not all. */
  assert_true(black.SHGC > 0 && black.SHGC < 1);
  s = one_pane(0.0);
  assert_int_equal(vr_thermal_nfrc(&s, 0.9, &black, &err), VR_OK);
}

static void refusals(void **state) {
  (void)state;
  vr_thermal_state o;
  vr_error err = {0};
  vr_thermal_system s = two_panes(0.84, 0.1, 0.1);
  s.gap[0].pressure_pa = 1.0; /* vacuum glazing */
  assert_int_equal(vr_thermal_solve(&s, &VR_ENV_NFRC_U, 0, &o, &err), VR_E_ARG);
  assert_non_null(strstr(err.message, "vacuum"));
  s = two_panes(0.84, 0.1, 0.1);
  s.pane[1].thickness_m = -0.004;
  assert_int_equal(vr_thermal_solve(&s, &VR_ENV_NFRC_U, 0, &o, &err), VR_E_ARG);
  assert_non_null(strstr(err.message, "pane 2"));
  s = one_pane(0.9);
  s.pane[0].tir = 0.2; /* emissivity + IR transmittance > 1 */
  assert_int_equal(vr_thermal_solve(&s, &VR_ENV_NFRC_U, 0, &o, &err), VR_E_ARG);
  s = one_pane(0.84);
  s.pane[0].absorptance = NAN;
  assert_int_equal(vr_thermal_solve(&s, &VR_ENV_NFRC_U, 0, &o, &err), VR_E_ARG);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(series_resistances),
      cmocka_unit_test(first_law),
      cmocka_unit_test(edges),
      cmocka_unit_test(refusals),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
