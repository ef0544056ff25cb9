/* Numerical edge cases of the optics core that must stay finite and right:
 * grazing incidence, the critical angle, vanishing and enormous k, a
 * millimetre of absorbing glass among nanometre films, layers that must
 * vanish. */
#include "vr_test.h"
#include "vr/optics.h"

#define DEG (M_PI / 180.0)

static int finite_result(const vr_tmm_result *r) {
  return isfinite(r->R) && isfinite(r->T) && isfinite(r->A);
}

static void grazing_incidence(void **state) {
  (void)state;
  /* Every Fresnel reflectance tends to 1 as theta -> 90 deg (Born & Wolf
   * 1.5.3); at exactly 90 deg nothing enters the stack. */
  vr_layer L[3] = {{1.0, 0, 0}, {2.0 + 0.01 * I, 100, 0}, {1.5, 0, 0}};
  vr_error err = {0};
  double prev[2] = {0, 0};
  double angles[] = {89.0, 89.9, 89.99, 89.999, 89.9999, 89.99999};
  for (int p = 0; p < 2; p++)
    for (size_t i = 0; i < 6; i++) {
      vr_tmm_result r;
      assert_int_equal(vr_tmm_coherent(L, 3, angles[i] * DEG, 500, (vr_pol)p, &r, NULL, &err), VR_OK);
      assert_true(finite_result(&r));
      assert_true(r.R > prev[p]);
      assert_near(r.R + r.T + r.A, 1.0, 1e-12);
      prev[p] = r.R;
    }
  for (int p = 0; p < 2; p++) {
    vr_tmm_result r;
    assert_int_equal(vr_tmm_coherent(L, 3, M_PI / 2, 500, (vr_pol)p, &r, NULL, &err), VR_OK);
    assert_true(finite_result(&r));
    assert_near(r.R, 1.0, 1e-9);
    assert_near(r.T, 0.0, 1e-9);
    assert_true(prev[p] < 1.0 && prev[p] > 0.999);
  }
  vr_fresnel f;
  vr_fresnel_interface(1.0, 1.5, M_PI / 2, &f);
  assert_true(isfinite(f.Rs) && isfinite(f.Rp) && isfinite(f.Ts) && isfinite(f.Tp));
  assert_near(f.Rs, 1.0, 1e-15);
}

static void critical_angle_and_beyond(void **state) {
  (void)state;
  /* Glass (1.5) to air: the critical angle asin(1/1.5) = 41.8103 deg; at it
   * and past it nothing is transmitted and R = 1. */
  double tc = vr_optics_critical(1.5, 1.0);
  vr_layer L[2] = {{1.5, 0, 0}, {1.0, 0, 0}};
  vr_error err = {0};
  for (int p = 0; p < 2; p++) {
    vr_tmm_result r;
    double angles[] = {tc, tc + 1e-12, tc + 1e-6, 50 * DEG, 89.99 * DEG};
    for (size_t i = 0; i < 5; i++) {
      assert_int_equal(vr_tmm_coherent(L, 2, angles[i], 600, (vr_pol)p, &r, NULL, &err), VR_OK);
      assert_true(finite_result(&r));
      assert_near(r.T, 0.0, 1e-7);
      assert_near(r.R, 1.0, 1e-7);
    }
    /* Just below: still finite, some transmission. */
    assert_int_equal(vr_tmm_coherent(L, 2, tc - 1e-4, 600, (vr_pol)p, &r, NULL, &err), VR_OK);
    assert_true(r.T > 0.0 && r.T < 0.2);
    assert_near(r.R + r.T, 1.0, 1e-12);
    /* Past it with a lossless film in between: frustrated by nothing, R = 1. */
    vr_layer F[3] = {{1.5, 0, 0}, {1.38, 100, 0}, {1.0, 0, 0}};
    assert_int_equal(vr_tmm_coherent(F, 3, 60 * DEG, 600, (vr_pol)p, &r, NULL, &err), VR_OK);
    assert_true(r.R == 1.0 && r.T == 0.0);
  }
  /* A thin air gap past the critical angle tunnels (frustrated TIR): T > 0,
   * and falls with the gap. */
  vr_layer gap[3] = {{1.5, 0, 0}, {1.0, 50, 0}, {1.5, 0, 0}};
  vr_tmm_result a, b;
  assert_int_equal(vr_tmm_coherent(gap, 3, 60 * DEG, 600, VR_POL_S, &a, NULL, &err), VR_OK);
  gap[1].thickness_nm = 500;
  assert_int_equal(vr_tmm_coherent(gap, 3, 60 * DEG, 600, VR_POL_S, &b, NULL, &err), VR_OK);
  assert_true(a.T > b.T && b.T > 0.0);
  assert_near(a.R + a.T, 1.0, 1e-12);
}

static void extreme_extinction(void **state) {
  (void)state;
  vr_error err = {0};
  vr_tmm_result r0, r;
  /* k = 1e-12 is k = 0 to first order. */
  vr_layer clear[3] = {{1.0, 0, 0}, {1.5, 1000, 0}, {1.0, 0, 0}};
  vr_layer faint[3] = {{1.0, 0, 0}, {1.5 + 1e-12 * I, 1000, 0}, {1.0, 0, 0}};
  assert_int_equal(vr_tmm_coherent(clear, 3, 0.3, 500, VR_POL_P, &r0, NULL, &err), VR_OK);
  assert_int_equal(vr_tmm_coherent(faint, 3, 0.3, 500, VR_POL_P, &r, NULL, &err), VR_OK);
  assert_near(r.R, r0.R, 1e-10);
  assert_true(r.A >= 0.0 && r.A < 1e-9);
  assert_near(r.R + r.T + r.A, 1.0, 1e-12);
  /* k = 1e3 (a perfect-conductor limit): R at normal incidence is
   * ((n-1)^2 + k^2)/((n+1)^2 + k^2), and a 100 nm film is opaque. */
  vr_layer metal[2] = {{1.0, 0, 0}, {2.0 + 1e3 * I, 0, 0}};
  assert_int_equal(vr_tmm_coherent(metal, 2, 0.0, 500, VR_POL_S, &r, NULL, &err), VR_OK);
  assert_near(r.R, (1.0 + 1e6) / (9.0 + 1e6), 1e-12);
  vr_layer film[3] = {{1.0, 0, 0}, {2.0 + 1e3 * I, 100, 0}, {1.5, 0, 0}};
  for (int p = 0; p < 2; p++)
    for (double a = 0; a < 90; a += 22.5) {
      assert_int_equal(vr_tmm_coherent(film, 3, a * DEG, 500, (vr_pol)p, &r, NULL, &err), VR_OK);
      assert_true(finite_result(&r));
      assert_near(r.T, 0.0, 1e-300);
      assert_near(r.R + r.A, 1.0, 1e-12);
    }
}

static void thick_absorbing_glass_among_films(void **state) {
  (void)state;
  /* 1 mm of glass between 100 nm films at 500 nm, solved coherently and
   * incoherently, for a clear glass (k = 1e-5, 4 pi k d / lambda = 0.25) and
   * a nearly opaque one (k = 1e-2, 4 pi k d / lambda = 251): no overflow, no
   * NaN; the opaque pane's T is of order exp(-251 / cos(theta_t)) ~ 1e-115,
   * a tiny positive number, not 0 or inf. */
  double ks[2] = {1e-5, 1e-2};
  vr_error err = {0};
  for (int which = 0; which < 2; which++) {
    vr_layer L[5] = {{1.0, 0, 0}, {2.0 + 0.001 * I, 100, 0}, {1.52 + ks[which] * I, 1e6, 0},
                     {1.46, 100, 0}, {1.0, 0, 0}};
    for (int p = 0; p < 2; p++) {
      vr_tmm_result c, inc;
      assert_int_equal(vr_tmm_coherent(L, 5, 0.5, 500, (vr_pol)p, &c, NULL, &err), VR_OK);
      assert_true(finite_result(&c));
      assert_near(c.R + c.T + c.A, 1.0, 1e-12);
      L[2].incoherent = 1;
      assert_int_equal(vr_stack_solve(L, 5, 0.5, 500, (vr_pol)p, &inc, &err), VR_OK);
      L[2].incoherent = 0;
      assert_true(finite_result(&inc));
      assert_true(inc.R > 0.0 && inc.T > 0.0 && inc.A > 0.0);
      if (which == 0) {
        /* Clear: the single-pass attenuation bounds T from above. */
        assert_true(inc.T < exp(-4 * M_PI * 1e-5 * 1e6 / 500) && inc.T > 0.5);
      } else {
        double cos_t = sqrt(1 - pow(sin(0.5) / 1.52, 2));
        double bound = exp(-4 * M_PI * 1e-2 * 1e6 / 500 / cos_t);
        assert_true(inc.T < bound && inc.T > 0.5 * bound);
        assert_true(c.T < 1e-100);
      }
    }
  }
}

static void layers_that_must_vanish(void **state) {
  (void)state;
  vr_error err = {0};
  vr_tmm_result a, b;
  vr_layer base[3] = {{1.0, 0, 0}, {2.1 + 0.05 * I, 73, 0}, {3.9 + 0.02 * I, 0, 0}};
  /* Zero thickness: the layer is not there. */
  vr_layer zero[4] = {{1.0, 0, 0}, {2.1 + 0.05 * I, 73, 0}, {1.7 + 0.3 * I, 0.0, 0}, {3.9 + 0.02 * I, 0, 0}};
  /* A layer identical to the ambient medium: it is ambient. */
  vr_layer same[4] = {{1.0, 0, 0}, {1.0, 250, 0}, {2.1 + 0.05 * I, 73, 0}, {3.9 + 0.02 * I, 0, 0}};
  for (int p = 0; p < 2; p++)
    for (double ang = 0; ang <= 85; ang += 17) {
      assert_int_equal(vr_tmm_coherent(base, 3, ang * DEG, 480, (vr_pol)p, &a, NULL, &err), VR_OK);
      assert_int_equal(vr_tmm_coherent(zero, 4, ang * DEG, 480, (vr_pol)p, &b, NULL, &err), VR_OK);
      assert_near(creal(b.r), creal(a.r), 1e-14);
      assert_near(cimag(b.r), cimag(a.r), 1e-14);
      assert_near(b.T, a.T, 1e-14);
      assert_int_equal(vr_tmm_coherent(same, 4, ang * DEG, 480, (vr_pol)p, &b, NULL, &err), VR_OK);
      /* r is referred to the top of the extra ambient layer: same modulus. */
      assert_near(b.R, a.R, 1e-14);
      assert_near(b.T, a.T, 1e-14);
    }
  /* The same at exact grazing incidence, where both q vanish. */
  assert_int_equal(vr_tmm_coherent(same, 4, M_PI / 2, 480, VR_POL_P, &b, NULL, &err), VR_OK);
  assert_true(finite_result(&b));
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(grazing_incidence),
      cmocka_unit_test(critical_angle_and_beyond),
      cmocka_unit_test(extreme_extinction),
      cmocka_unit_test(thick_absorbing_glass_among_films),
      cmocka_unit_test(layers_that_must_vanish),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
