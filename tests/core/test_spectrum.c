/* Spectra: construction rules, interpolation, quadrature against analytic
 * integrals, explicit resampling, and the CSV table reader's errors. */
#include "vr_test.h"
#include "vr/colour.h"
#include "vr/spectrum.h"

static void refuses_bad_grids(void **state) {
  (void)state;
  vr_error err = {0};
  double nm[] = {400, 500, 500}, v[] = {1, 2, 3};
  assert_null(vr_spectrum_create(3, nm, v, &err));
  assert_contains(err.message, "#3 (500 nm) follows 500 nm");
  double nm2[] = {400, 390};
  assert_null(vr_spectrum_create(2, nm2, v, &err));
  double nm3[] = {400, 410}, v3[] = {1, NAN};
  assert_null(vr_spectrum_create(2, nm3, v3, &err));
  assert_contains(err.message, "410 nm is not finite");
  assert_null(vr_spectrum_create(0, nm, v, &err));
}

static void interpolation(void **state) {
  (void)state;
  /* Linear data: both schemes are exact (a cubic Hermite reproduces lines). */
  double nm[] = {400, 420, 450, 500, 600}, v[5];
  for (int i = 0; i < 5; i++) v[i] = 0.3 + 0.002 * nm[i];
  vr_spectrum *s = vr_spectrum_create(5, nm, v, NULL);
  for (double x = 400; x <= 600; x += 7.3) {
    assert_near(vr_spectrum_eval(s, x, VR_INTERP_LINEAR), 0.3 + 0.002 * x, 1e-14);
    assert_near(vr_spectrum_eval(s, x, VR_INTERP_CUBIC), 0.3 + 0.002 * x, 1e-14);
  }
  /* End values are held outside the grid (CIE 015:2018 7.2.2). */
  assert_near(vr_spectrum_eval(s, 300, VR_INTERP_CUBIC), v[0], 0);
  assert_near(vr_spectrum_eval(s, 900, VR_INTERP_LINEAR), v[4], 0);
  assert_true(vr_spectrum_covers(s, 400, 600));
  assert_false(vr_spectrum_covers(s, 399, 600));
  vr_spectrum_destroy(s);

  /* A step (a cut-off filter): the monotone cubic never leaves [0, 1]. */
  double snm[] = {400, 410, 420, 430, 440, 450}, sv[] = {0, 0, 0, 1, 1, 1};
  s = vr_spectrum_create(6, snm, sv, NULL);
  for (double x = 400; x <= 450; x += 0.25) {
    double y = vr_spectrum_eval(s, x, VR_INTERP_CUBIC);
    assert_true(y >= 0.0 && y <= 1.0);
  }
  vr_spectrum_destroy(s);

  /* A smooth curve sampled every 10 nm: the cubic is closer to sin() than
   * straight lines are, on average and at worst. */
  double gnm[31], gv[31];
  for (int i = 0; i < 31; i++) {
    gnm[i] = 400 + 10 * i;
    gv[i] = sin(gnm[i] / 40.0);
  }
  s = vr_spectrum_create(31, gnm, gv, NULL);
  double el = 0, ec = 0, sl = 0, sc = 0;
  for (double x = 420; x <= 680; x += 1.0) {
    double dl = fabs(vr_spectrum_eval(s, x, VR_INTERP_LINEAR) - sin(x / 40.0));
    double dc = fabs(vr_spectrum_eval(s, x, VR_INTERP_CUBIC) - sin(x / 40.0));
    el = fmax(el, dl);
    ec = fmax(ec, dc);
    sl += dl;
    sc += dc;
  }
  assert_true(ec < el);
  assert_true(sc < sl / 3.0);
  vr_spectrum_destroy(s);
}

static void quadrature_against_analytic_integrals(void **state) {
  (void)state;
  /* Irregular grid on [0, 3]; integral of x^2 is 9, of x is 4.5. */
  double x[] = {0.0, 0.4, 0.5, 1.3, 2.0, 2.2, 3.0}, f[7], g[7];
  for (int i = 0; i < 7; i++) {
    f[i] = x[i] * x[i];
    g[i] = x[i];
  }
  vr_spectrum *s = vr_spectrum_create(7, x, f, NULL), *l = vr_spectrum_create(7, x, g, NULL);
  assert_near(vr_spectrum_integrate(s, VR_SIMPSON), 9.0, 1e-13);
  assert_near(vr_spectrum_integrate(l, VR_TRAPEZOID), 4.5, 1e-13);
  vr_spectrum_destroy(s);
  vr_spectrum_destroy(l);
  /* Odd number of irregular intervals (x[0..5], 5 intervals): x^2 on [0, 2.2]. */
  s = vr_spectrum_create(6, x, f, NULL);
  assert_near(vr_spectrum_integrate(s, VR_SIMPSON), 2.2 * 2.2 * 2.2 / 3.0, 1e-13);
  vr_spectrum_destroy(s);
  /* Cubic on a uniform grid with an even number of intervals: exact. */
  s = vr_spectrum_create_uniform(0.0, 0.25, 9, 0.0, NULL);
  for (size_t i = 0; i < s->n; i++) s->value[i] = s->nm[i] * s->nm[i] * s->nm[i];
  assert_near(vr_spectrum_integrate(s, VR_SIMPSON), 4.0, 1e-13);
  vr_spectrum_destroy(s);

  /* Stefan-Boltzmann: pi * integral of Planck's spectral radiance equals
   * sigma T^4, sigma = 5.670374419e-8 W m^-2 K^-4 (CODATA 2018).  Log-spaced
   * grid from 10 nm to 100 um (non-uniform Simpson); the tail beyond 100 um
   * holds < 1e-6 of the total at 5772 K. */
  size_t n = 20001;
  vr_spectrum *p = vr_spectrum_create_uniform(0, 1, n, 0, NULL);
  for (size_t i = 0; i < n; i++) {
    p->nm[i] = 10.0 * pow(1e4, (double)i / (double)(n - 1));
    p->value[i] = M_PI * vr_planck(p->nm[i], 5772.0);
  }
  double sigmaT4 = 5.670374419e-8 * pow(5772.0, 4.0);
  assert_rel(vr_spectrum_integrate(p, VR_SIMPSON), sigmaT4, 2e-6);
  vr_spectrum_destroy(p);
}

static void arithmetic_demands_one_grid(void **state) {
  (void)state;
  vr_error err = {0};
  vr_spectrum *a = vr_spectrum_create_uniform(400, 10, 5, 2.0, NULL);
  vr_spectrum *b = vr_spectrum_create_uniform(400, 10, 5, 3.0, NULL);
  vr_spectrum *c = vr_spectrum_create_uniform(400, 5, 9, 1.0, NULL);
  assert_int_equal(vr_spectrum_mul(a, b, &err), VR_OK);
  assert_near(a->value[2], 6.0, 0);
  assert_int_equal(vr_spectrum_add(a, b, &err), VR_OK);
  assert_near(a->value[4], 9.0, 0);
  vr_spectrum_scale(a, 0.5);
  assert_near(a->value[0], 4.5, 0);
  assert_int_equal(vr_spectrum_add(a, c, &err), VR_E_ARG);
  assert_contains(err.message, "resample");
  vr_spectrum *r = vr_spectrum_resample(c, a->n, a->nm, VR_INTERP_LINEAR, &err);
  assert_non_null(r);
  assert_int_equal(vr_spectrum_add(a, r, &err), VR_OK);
  assert_near(a->value[0], 5.5, 0);
  vr_spectrum_destroy(a);
  vr_spectrum_destroy(b);
  vr_spectrum_destroy(c);
  vr_spectrum_destroy(r);
}

static void table_units_and_order(void **state) {
  (void)state;
  vr_spectrum_table t;
  vr_error err = {0};
  const char *um = vr_test_file("# transmittance\nwavelength (um),T,R\n0.40,0.9,0.08\n0.5,0.91,0.07\n");
  assert_int_equal(vr_spectrum_table_read(um, &t, &err), VR_OK);
  assert_int_equal(t.count, 2);
  assert_near(t.spectra[0]->nm[0], 400.0, 1e-12);
  assert_near(vr_spectrum_table_get(&t, "r")->value[1], 0.07, 0);
  vr_spectrum_table_free(&t);
  /* eV files run from high to low wavelength; 1239.84198 eV nm (CODATA). */
  const char *ev = vr_test_file("eV,eps\n1.0,2\n2.0,3\n3.0,4\n");
  assert_int_equal(vr_spectrum_table_read(ev, &t, &err), VR_OK);
  assert_near(t.spectra[0]->nm[0], 1239.84198 / 3.0, 1e-9);
  assert_near(t.spectra[0]->value[0], 4.0, 0);
  vr_spectrum_table_free(&t);
}

static void table_errors_name_line_and_field(void **state) {
  (void)state;
  vr_spectrum_table t;
  vr_error err = {0};
  const char *dup = vr_test_file("nm,T\n400,0.9\n410,0.8\n410,0.7\n");
  assert_int_not_equal(vr_spectrum_table_read(dup, &t, &err), VR_OK);
  assert_contains(err.message, ":4:1: field 'nm': wavelengths must be strictly increasing");
  const char *nan = vr_test_file("nm,T,R\n400,0.9,0.1\n410,NaN,0.1\n");
  assert_int_not_equal(vr_spectrum_table_read(nan, &t, &err), VR_OK);
  assert_contains(err.message, ":3:5: field 'T': 'NaN' is not a finite number");
  const char *missing = vr_test_file("nm,T,R\n400,0.9,0.1\n410,0.8\n");
  assert_int_not_equal(vr_spectrum_table_read(missing, &t, &err), VR_OK);
  assert_contains(err.message, ":3:");
  assert_contains(err.message, "expected 3 fields, found 2");
  const char *one = vr_test_file("nm\n400\n");
  assert_int_not_equal(vr_spectrum_table_read(one, &t, &err), VR_OK);
  assert_contains(err.message, "at least one value column");
  const char *neg = vr_test_file("nm,T\n-400,0.9\n");
  assert_int_not_equal(vr_spectrum_table_read(neg, &t, &err), VR_OK);
  assert_contains(err.message, ":2:1: field 'nm': wavelength must be positive");
}

static void table_round_trip_is_exact(void **state) {
  (void)state;
  vr_spectrum_table t, back;
  vr_error err = {0};
  const char *src = vr_test_file("nm,a,\"b,c\"\n400,0.1,0.30000000000000004\n410.5,1e-300,2\n");
  assert_int_equal(vr_spectrum_table_read(src, &t, &err), VR_OK);
  char out[64];
  snprintf(out, sizeof out, "%s.out.csv", src);
  assert_int_equal(vr_spectrum_table_write(out, &t, &err), VR_OK);
  assert_int_equal(vr_spectrum_table_read(out, &back, &err), VR_OK);
  assert_string_equal(back.names[1], "b,c");
  for (size_t i = 0; i < t.count; i++)
    for (size_t r = 0; r < t.spectra[i]->n; r++) {
      assert_true(back.spectra[i]->nm[r] == t.spectra[i]->nm[r]);
      assert_true(back.spectra[i]->value[r] == t.spectra[i]->value[r]);
    }
  vr_spectrum_table_free(&t);
  vr_spectrum_table_free(&back);
  unlink(out);
  /* A write into a missing directory fails and leaves nothing behind. */
  assert_int_equal(vr_spectrum_table_read(src, &t, &err), VR_OK);
  assert_int_equal(vr_spectrum_table_write("/nonexistent/dir/out.csv", &t, &err), VR_E_IO);
  vr_spectrum_table_free(&t);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(refuses_bad_grids),
      cmocka_unit_test(interpolation),
      cmocka_unit_test(quadrature_against_analytic_integrals),
      cmocka_unit_test(arithmetic_demands_one_grid),
      cmocka_unit_test(table_units_and_order),
      cmocka_unit_test(table_errors_name_line_and_field),
      cmocka_unit_test(table_round_trip_is_exact),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
