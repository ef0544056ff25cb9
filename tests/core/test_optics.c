/* Optics of interfaces, thin films and slabs against published values. */
#include "vr_test.h"
#include "vr/optics.h"

#define DEG (M_PI / 180.0)

static void tmm_reference_case(void **state) {
  (void)state;
  /* Byrnes, tmm package, tests.py "basic_test" / examples: n = [1, 2+4i,
   * 3+0.3i, 1+0.1i], d = [inf, 2, 3, inf], th0 = 0.1 rad, lambda = 100,
   * s-polarisation: r = -0.60331226568845775 - 0.093522181653632019i,
   * R = 0.37273208839139516. */
  vr_layer L[4] = {{1.0, 0, 0}, {2.0 + 4.0 * I, 2.0, 0}, {3.0 + 0.3 * I, 3.0, 0}, {1.0 + 0.1 * I, 0, 0}};
  vr_tmm_result r;
  vr_error err = {0};
  assert_int_equal(vr_tmm_coherent(L, 4, 0.1, 100.0, VR_POL_S, &r, NULL, &err), VR_OK);
  assert_near(creal(r.r), -0.60331226568845775, 1e-12);
  assert_near(cimag(r.r), -0.093522181653632019, 1e-12);
  assert_near(r.R, 0.37273208839139516, 1e-12);
}

static void single_interfaces(void **state) {
  (void)state;
  vr_fresnel f;
  /* Normal incidence on n = 1.5: R = ((1.5-1)/(1.5+1))^2 = 0.04. */
  vr_fresnel_interface(1.0, 1.5, 0.0, &f);
  assert_near(f.Rs, 0.04, 1e-15);
  assert_near(f.Rp, 0.04, 1e-15);
  assert_near(f.Ts, 0.96, 1e-15);
  /* N-BK7 at 587.56 nm: n = 1.5168 (SCHOTT datasheet); Brewster angle
   * arctan(1.5168) = 56.60 deg, where Rp vanishes. */
  double b = vr_optics_brewster(1.0, 1.5168);
  assert_near(b / DEG, 56.60, 0.005);
  vr_fresnel_interface(1.0, 1.5168, b, &f);
  assert_true(f.Rp < 1e-30);
  assert_near(f.Rp + f.Tp, 1.0, 1e-15);
  /* Beyond the critical angle (glass to air, 45 deg > 41.81 deg): R = 1 exactly. */
  assert_near(vr_optics_critical(1.5, 1.0) / DEG, 41.8103148957786, 1e-10);
  vr_fresnel_interface(1.5, 1.0, 45 * DEG, &f);
  assert_true(f.Rs == 1.0);
  assert_true(f.Rp == 1.0);
  assert_true(f.Ts == 0.0 && f.Tp == 0.0);
  /* Absorbing: at normal incidence R = ((n-1)^2 + k^2) / ((n+1)^2 + k^2). */
  vr_fresnel_interface(1.0, 0.2 + 3.0 * I, 0.0, &f);
  assert_near(f.Rs, (0.64 + 9.0) / (1.44 + 9.0), 1e-15);
}

static void slab_with_and_without_internal_reflections(void **state) {
  (void)state;
  /* n = 1.52 clear pane, no absorption (issue "Foundation"; the values follow
   * from Fresnel's equations, e.g. Rubin 1985, Sol. Energy Mater. 12:275):
   * normal incidence T = 0.9167 single pass, 0.9183 with all reflections;
   * at 80 deg (unpolarised mean of s and p) 0.3951 and 0.4560. */
  vr_slab_result s;
  vr_error err = {0};
  assert_int_equal(vr_slab(1.0, 1.52, 3e6, 0.0, 550.0, &s, &err), VR_OK);
  assert_near(0.5 * (s.T_single[0] + s.T_single[1]), 0.9167, 5e-5);
  assert_near(0.5 * (s.T[0] + s.T[1]), 0.9183, 5e-5);
  assert_near(s.R[0] + s.T[0], 1.0, 1e-15);
  assert_int_equal(vr_slab(1.0, 1.52, 3e6, 80 * DEG, 550.0, &s, &err), VR_OK);
  assert_near(0.5 * (s.T_single[0] + s.T_single[1]), 0.3951, 5e-5);
  assert_near(0.5 * (s.T[0] + s.T[1]), 0.4560, 5e-5);
  /* Beer-Lambert: k = 1e-6 at 500 nm over 4 mm at normal incidence gives
   * a = exp(-4 pi k d / lambda) = exp(-0.10053). */
  assert_int_equal(vr_slab(1.0, 1.52 + 1e-6 * I, 4e6, 0.0, 500.0, &s, &err), VR_OK);
  assert_near(s.a, exp(-4 * M_PI * 1e-6 * 4e6 / 500.0), 1e-15);
}

static void energy_balance_over_angles(void **state) {
  (void)state;
  /* R + T + A = 1 with A from the Poynting flux in each layer (not from
   * 1 - R - T), for a lossless and a lossy stack, 0 to 89.99 degrees. */
  vr_layer lossless[5] = {{1.0, 0, 0}, {1.38, 99.6, 0}, {2.35, 58.5, 0}, {1.46, 120, 0}, {1.52, 0, 0}};
  vr_layer lossy[5] = {{1.0, 0, 0}, {2.0 + 0.1 * I, 80, 0}, {0.05 + 3.4 * I, 12, 0},
                       {1.9 + 0.02 * I, 40, 0}, {3.9 + 0.02 * I, 0, 0}};
  double angles[] = {0, 10, 30, 45, 60, 75, 85, 89, 89.9, 89.99};
  vr_error err = {0};
  for (int pol = 0; pol < 2; pol++)
    for (size_t i = 0; i < sizeof angles / sizeof angles[0]; i++) {
      vr_tmm_result r;
      double abs_layers[5];
      assert_int_equal(vr_tmm_coherent(lossless, 5, angles[i] * DEG, 550, (vr_pol)pol, &r,
                                       abs_layers, &err), VR_OK);
      assert_near(r.R + r.T + r.A, 1.0, 1e-12);
      assert_near(r.A, 0.0, 1e-12);
      assert_int_equal(vr_tmm_coherent(lossy, 5, angles[i] * DEG, 633, (vr_pol)pol, &r, abs_layers,
                                       &err), VR_OK);
      assert_near(r.R + r.T + r.A, 1.0, 1e-12);
      for (int j = 1; j < 4; j++) assert_true(abs_layers[j] >= -1e-15);
      assert_true(r.A > 0.0);
    }
}

static void bare_silicon_ellipsometry(void **state) {
  (void)state;
  /* Bare Si at 70 deg, 632.8 nm: Psi ~ 10.58 deg, Delta ~ 179.2 deg in
   * Woollam's convention (issue "vr-ellipso"; J.A. Woollam, "Ellipsometry
   * tutorial").  Si N = 3.879 + 0.016444 i (Green 2008 at 630 nm). */
  vr_layer L[2] = {{1.0, 0, 0}, {3.879 + 0.016444 * I, 0, 0}};
  double psi, delta;
  vr_error err = {0};
  assert_int_equal(vr_tmm_ellipsometry(L, 2, 70 * DEG, 632.8, &psi, &delta, NULL, &err), VR_OK);
  assert_near(psi, 10.58, 0.05);
  assert_near(delta, 179.2, 0.3);
}

static void incoherent_substrate(void **state) {
  (void)state;
  vr_error err = {0};
  vr_tmm_result r;
  /* A quarter-wave film of n = sqrt(1.52) on a thick n = 1.52 pane cancels
   * the front reflection at its design wavelength; what remains is the bare
   * back face, R = ((1.52-1)/(1.52+1))^2 (Macleod, Thin-Film Optical
   * Filters, ch. 3 quarter-wave AR coating). */
  double nf = sqrt(1.52), lam = 550.0;
  vr_layer L[4] = {{1.0, 0, 0}, {nf, lam / (4 * nf), 0}, {1.52, 3e6, 1}, {1.0, 0, 0}};
  assert_int_equal(vr_stack_solve(L, 4, 0.0, lam, VR_POL_S, &r, &err), VR_OK);
  double R2 = pow(0.52 / 2.52, 2);
  assert_near(r.R, R2, 1e-14);
  assert_near(r.T, 1 - R2, 1e-14);
  /* The incoherent stack of a bare pane is the slab formula. */
  vr_layer bare[3] = {{1.0, 0, 0}, {1.52 + 2e-7 * I, 3e6, 1}, {1.0, 0, 0}};
  vr_slab_result s;
  for (double a = 0; a < 90; a += 15) {
    assert_int_equal(vr_slab(1.0, 1.52 + 2e-7 * I, 3e6, a * DEG, lam, &s, &err), VR_OK);
    for (int p = 0; p < 2; p++) {
      assert_int_equal(vr_stack_solve(bare, 3, a * DEG, lam, (vr_pol)p, &r, &err), VR_OK);
      assert_near(r.R, s.R[p], 1e-14);
      assert_near(r.T, s.T[p], 1e-14);
    }
  }
}

static void bad_arguments_name_the_layer(void **state) {
  (void)state;
  vr_error err = {0};
  vr_tmm_result r;
  vr_layer neg[3] = {{1.0, 0, 0}, {1.5, -10, 0}, {1.0, 0, 0}};
  assert_int_equal(vr_tmm_coherent(neg, 3, 0, 500, VR_POL_S, &r, NULL, &err), VR_E_ARG);
  assert_contains(err.message, "layer 1: thickness -10 nm");
  vr_layer gain[3] = {{1.0, 0, 0}, {1.5 - 0.1 * I, 10, 0}, {1.0, 0, 0}};
  assert_int_equal(vr_tmm_coherent(gain, 3, 0, 500, VR_POL_S, &r, NULL, &err), VR_E_ARG);
  assert_contains(err.message, "layer 1: extinction coefficient k = -0.1 is negative");
  vr_layer nan[3] = {{1.0, 0, 0}, {NAN, 10, 0}, {1.0, 0, 0}};
  assert_int_equal(vr_tmm_coherent(nan, 3, 0, 500, VR_POL_S, &r, NULL, &err), VR_E_ARG);
  assert_int_equal(vr_tmm_coherent(neg, 3, 100 * DEG, 500, VR_POL_S, &r, NULL, &err), VR_E_ARG);
  assert_int_equal(vr_tmm_coherent(neg, 1, 0, 500, VR_POL_S, &r, NULL, &err), VR_E_ARG);
  assert_int_equal(vr_stack_solve(neg, 3, 0, 500, VR_POL_S, &r, &err), VR_E_ARG);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(tmm_reference_case),
      cmocka_unit_test(single_interfaces),
      cmocka_unit_test(slab_with_and_without_internal_reflections),
      cmocka_unit_test(energy_balance_over_angles),
      cmocka_unit_test(bare_silicon_ellipsometry),
      cmocka_unit_test(incoherent_substrate),
      cmocka_unit_test(bad_arguments_name_the_layer),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
