/* Photometry: luminous efficacy against sums over the CIE 1931 ybar table
 * (CIE 015:2018), against colour-science's own test vector (FL2, 
 * colour/colorimetry/tests/test_photometry.py), and against the core's
 * absolute tristimulus integration; unit conversions and point lights
 * (isotropic I = Phi / 4 pi, Lambertian Phi = pi I0). */
#include "vr_test.h"
#include "vr/colour.h"
#include "vr/photometry.h"

#define PI 3.14159265358979323846

static vr_spectrum *flat(double lo, double hi) {
  double nm[2] = {lo, hi}, v[2] = {1.0, 1.0};
  return vr_spectrum_create(2, nm, v, NULL);
}

/* int ybar over [lo, hi] (whole nm) by the trapezoid rule on the table,
 * exact for the linearly interpolated table. */
static double ybar_integral(int lo, int hi) {
  size_t rows;
  const double *t = vr_cmf_table(VR_CIE1931_2DEG, &rows);
  double sum = 0.0;
  for (size_t i = 0; i < rows; i++) {
    int nm = (int)t[i * 4];
    if (nm < lo || nm > hi) continue;
    double w = (nm == lo || nm == hi) ? 0.5 : 1.0;
    sum += w * t[i * 4 + 2];
  }
  return sum;
}

static void equal_energy(void **state) {
  (void)state;
  vr_spectrum *e = flat(300.0, 900.0);
  double K;
  assert_int_equal(vr_photometry_efficacy(e, 360.0, 830.0, &K, NULL), VR_OK);
  double expected = VR_KM * ybar_integral(360, 830) / 470.0;
  print_message("equal-energy spectrum, 360-830 nm: K = %.6f lm/W (683.002 x %.6f / 470)\n", K,
                ybar_integral(360, 830));
  assert_rel(K, expected, 1e-12);
  /* The narrower band the renderer may carry: both integrals shrink. */
  assert_int_equal(vr_photometry_efficacy(e, 400.0, 700.0, &K, NULL), VR_OK);
  assert_rel(K, VR_KM * ybar_integral(400, 700) / 300.0, 1e-12);
  /* A band with fractional ends: ybar linear between rows. */
  assert_int_equal(vr_photometry_efficacy(e, 554.5, 555.5, &K, NULL), VR_OK);
  double y[3];
  double v554, v555, v556;
  vr_cmf_eval(VR_CIE1931_2DEG, 554.0, y), v554 = y[1];
  vr_cmf_eval(VR_CIE1931_2DEG, 555.0, y), v555 = y[1];
  vr_cmf_eval(VR_CIE1931_2DEG, 556.0, y), v556 = y[1];
  /* Trapezoids on [554.5, 555] and [555, 555.5], V(554.5) and V(555.5)
   * being the midpoints of the rows around them. */
  double v5545 = 0.5 * (v554 + v555), v5555 = 0.5 * (v555 + v556);
  double exact = 0.25 * (v5545 + v555) + 0.25 * (v555 + v5555);
  assert_rel(K, VR_KM * exact, 1e-12);
  vr_spectrum_destroy(e);
}

static void near_monochromatic(void **state) {
  (void)state;
  /* A triangle 554-555-556 nm: with V linear between rows the exact ratio
   * is (V554 + 4 V555 + V556) / 6; ybar(555) = 1, so K is just below Km. */
  double nm[3] = {554, 555, 556}, v[3] = {0, 1, 0};
  vr_spectrum *s = vr_spectrum_create(3, nm, v, NULL);
  double K, y[3], V[3];
  for (int i = 0; i < 3; i++) vr_cmf_eval(VR_CIE1931_2DEG, nm[i], y), V[i] = y[1];
  assert_int_equal(vr_photometry_efficacy(s, 540.0, 570.0, &K, NULL), VR_OK);
  assert_rel(K, VR_KM * (V[0] + 4 * V[1] + V[2]) / 6, 1e-12);
  assert_true(K > 682.9 && K <= VR_KM);
  vr_spectrum_destroy(s);
}

static void fl2_colour_science(void **state) {
  (void)state;
  /* colour-science's test: luminous_efficacy(FL2 normalised) = 336.83937176
   * lm/W, i.e. 683 x 0.49317624 (its Km is 683), the trapezoid rule on
   * FL2's 5 nm grid over 380-780 nm with V sampled at those wavelengths.
   * Our integral treats S as linear between its 5 nm samples and V at its
   * 1 nm rows; for FL2's mercury lines (single 5 nm samples) the two
   * quadratures differ by a few parts in 1e4. */
  vr_spectrum *f2 = vr_illuminant("F2", NULL);
  assert_non_null(f2);
  double K;
  assert_int_equal(vr_photometry_efficacy(f2, 380.0, 780.0, &K, NULL), VR_OK);
  double ours_683 = K * 683.0 / VR_KM;
  print_message("FL2, 380-780 nm: K = %.6f lm/W (Km 683.002); with Km = 683: %.6f, colour-science "
                "336.83937 (relative %.2e)\n",
                K, ours_683, (ours_683 - 336.83937176) / 336.83937176);
  assert_rel(ours_683, 336.83937176, 1e-3);
  /* Reproducing colour-science's quadrature exactly from the same data. */
  double num = 0.0, den = 0.0, y0[3], y1[3];
  for (size_t i = 0; i + 1 < f2->n; i++) {
    double a = f2->nm[i], b = f2->nm[i + 1];
    if (a < 380.0 || b > 780.0) continue;
    vr_cmf_eval(VR_CIE1931_2DEG, a, y0);
    vr_cmf_eval(VR_CIE1931_2DEG, b, y1);
    num += 0.5 * (b - a) * (y0[1] * f2->value[i] + y1[1] * f2->value[i + 1]);
    den += 0.5 * (b - a) * (f2->value[i] + f2->value[i + 1]);
  }
  assert_near(num / den, 0.49317624, 5e-8);
  vr_spectrum_destroy(f2);
}

static void d65_against_core(void **state) {
  (void)state;
  /* D65 over 360-830 nm: K from this module and from the core's absolute
   * Y (vr_xyz_emitter: Km sum L ybar over the 1 nm rows) must agree.  The
   * core sums the product at the rows (the trapezoid rule on L ybar), this
   * module integrates the product of the two linear interpolants; per 1 nm
   * interval they differ by dL dybar / 6, about 2e-6 of the total for the
   * jagged 1 nm D65 table. */
  vr_spectrum *d65 = vr_illuminant("D65", NULL);
  double K, xyz[3];
  assert_int_equal(vr_photometry_efficacy(d65, 360.0, 830.0, &K, NULL), VR_OK);
  vr_xyz_emitter(d65, VR_CIE1931_2DEG, xyz);
  double band = vr_photometry_band_integral(d65, 360.0, 830.0);
  print_message("D65, 360-830 nm: K = %.4f lm/W (core: %.4f); 380-780 nm: ", K, xyz[1] / band);
  assert_rel(K, xyz[1] / band, 1e-5);
  double K2;
  assert_int_equal(vr_photometry_efficacy(d65, 380.0, 780.0, &K2, NULL), VR_OK);
  print_message("%.4f lm/W\n", K2);
  assert_true(K2 > K); /* less infrared and ultraviolet in the band */
  vr_spectrum_destroy(d65);
}

static void conversions(void **state) {
  (void)state;
  vr_spectrum *e = flat(300.0, 900.0);
  double K, out;
  vr_error err = {0};
  assert_int_equal(vr_photometry_efficacy(e, 360.0, 830.0, &K, NULL), VR_OK);
  struct { vr_light_unit p, r; } pairs[4] = {{VR_UNIT_LM, VR_UNIT_W},
                                             {VR_UNIT_CD, VR_UNIT_W_SR},
                                             {VR_UNIT_LX, VR_UNIT_W_M2},
                                             {VR_UNIT_CD_M2, VR_UNIT_W_M2_SR}};
  for (int i = 0; i < 4; i++) {
    assert_int_equal(vr_photometry_counterpart(pairs[i].p), pairs[i].r);
    assert_int_equal(vr_photometry_counterpart(pairs[i].r), pairs[i].p);
    assert_true(vr_photometry_is_photometric(pairs[i].p));
    assert_false(vr_photometry_is_photometric(pairs[i].r));
    assert_int_equal(vr_photometry_convert((vr_quantity){1000.0, pairs[i].p}, pairs[i].r, e,
                                           360.0, 830.0, &out, &err),
                     VR_OK);
    assert_rel(out, 1000.0 / K, 1e-14);
    assert_int_equal(vr_photometry_convert((vr_quantity){2.0, pairs[i].r}, pairs[i].p, e, 360.0,
                                           830.0, &out, &err),
                     VR_OK);
    assert_rel(out, 2.0 * K, 1e-14);
    /* Same unit: identity, no spectrum needed. */
    assert_int_equal(vr_photometry_convert((vr_quantity){5.0, pairs[i].p}, pairs[i].p, NULL, 0, 0,
                                           &out, &err),
                     VR_OK);
    assert_near(out, 5.0, 0);
  }
  assert_int_equal(vr_photometry_convert((vr_quantity){100.0, VR_UNIT_LM}, VR_UNIT_CD, e, 360.0,
                                         830.0, &out, &err),
                   VR_E_ARG);
  assert_contains(err.message, "100 lm in cd");
  assert_int_equal(vr_photometry_convert((vr_quantity){1.0, VR_UNIT_NONE}, VR_UNIT_W, e, 360.0,
                                         830.0, &out, &err),
                   VR_E_ARG);
  assert_int_equal(vr_photometry_convert((vr_quantity){NAN, VR_UNIT_LM}, VR_UNIT_W, e, 360.0,
                                         830.0, &out, &err),
                   VR_E_ARG);

  /* The sun's normal illuminance and a luminance, with the spectral scale. */
  double amount, scale;
  assert_int_equal(vr_photometry_radiometric((vr_quantity){100000.0, VR_UNIT_LX}, VR_UNIT_W_M2, e,
                                             360.0, 830.0, &amount, &scale, &err),
                   VR_OK);
  assert_rel(amount, 100000.0 / K, 1e-14);
  assert_rel(scale, amount / 470.0, 1e-12); /* flat spectrum of 1 over 470 nm */
  assert_int_equal(vr_photometry_radiometric((vr_quantity){10.0, VR_UNIT_CD}, VR_UNIT_W_M2, e,
                                             360.0, 830.0, &amount, &scale, &err),
                   VR_E_ARG);
  assert_contains(err.message, "10 cd: expected W/m2 or lx");
  assert_int_equal(vr_photometry_radiometric((vr_quantity){10.0, VR_UNIT_LX}, VR_UNIT_LX, e,
                                             360.0, 830.0, &amount, &scale, &err),
                   VR_E_ARG);
  vr_spectrum_destroy(e);
}

static void point_lights(void **state) {
  (void)state;
  vr_spectrum *d65 = vr_illuminant("D65", NULL);
  double K;
  assert_int_equal(vr_photometry_efficacy(d65, 360.0, 830.0, &K, NULL), VR_OK);
  vr_point_radiometry r;
  vr_error err = {0};
  /* Isotropic: I = Phi / (4 pi). */
  double omega = vr_photometry_solid_angle(VR_DIST_ISOTROPIC);
  assert_near(omega, 4 * PI, 1e-15);
  assert_int_equal(vr_photometry_point_light((vr_quantity){1000.0, VR_UNIT_LM}, omega, d65, 360.0,
                                             830.0, &r, &err),
                   VR_OK);
  assert_rel(r.power_w, 1000.0 / K, 1e-14);
  assert_rel(r.intensity_w_sr, 1000.0 / K / (4 * PI), 1e-14);
  assert_rel(r.efficacy_lm_per_w, K, 0);
  assert_rel(r.intensity_scale * vr_photometry_band_integral(d65, 360.0, 830.0), r.intensity_w_sr,
             1e-12);
  /* Lambertian point source, I = I0 cos theta: Phi = pi I0. */
  omega = vr_photometry_solid_angle(VR_DIST_LAMBERTIAN);
  assert_near(omega, PI, 1e-15);
  assert_int_equal(vr_photometry_point_light((vr_quantity){100.0, VR_UNIT_CD}, omega, d65, 360.0,
                                             830.0, &r, &err),
                   VR_OK);
  assert_rel(r.intensity_w_sr, 100.0 / K, 1e-14);
  assert_rel(r.power_w * K, PI * 100.0, 1e-14);
  /* Radiometric amounts need no efficacy but keep it reported. */
  assert_int_equal(vr_photometry_point_light((vr_quantity){2.0, VR_UNIT_W}, 4 * PI, d65, 360.0,
                                             830.0, &r, &err),
                   VR_OK);
  assert_rel(r.intensity_w_sr, 2.0 / (4 * PI), 1e-15);
  assert_true(isnan(vr_photometry_solid_angle(VR_DIST_GONIOMETRIC)));
  /* Units that do not describe a point light. */
  assert_int_equal(vr_photometry_point_light((vr_quantity){500.0, VR_UNIT_LX}, 4 * PI, d65, 360.0,
                                             830.0, &r, &err),
                   VR_E_ARG);
  assert_contains(err.message, "500 lx");
  assert_int_equal(vr_photometry_point_light((vr_quantity){500.0, VR_UNIT_CD_M2}, 4 * PI, d65,
                                             360.0, 830.0, &r, &err),
                   VR_E_ARG);
  assert_contains(err.message, "cd/m2");
  assert_int_equal(vr_photometry_point_light((vr_quantity){500.0, VR_UNIT_LM}, 0.0, d65, 360.0,
                                             830.0, &r, &err),
                   VR_E_ARG);
  vr_spectrum_destroy(d65);
}

static void efficacy_errors(void **state) {
  (void)state;
  vr_spectrum *e = flat(300.0, 900.0);
  double K;
  vr_error err = {0};
  assert_int_equal(vr_photometry_efficacy(e, 700.0, 400.0, &K, &err), VR_E_ARG);
  assert_contains(err.message, "700..400");
  assert_int_equal(vr_photometry_efficacy(NULL, 400.0, 700.0, &K, &err), VR_E_ARG);
  double nm[2] = {300, 900}, zero[2] = {0, 0};
  vr_spectrum *z = vr_spectrum_create(2, nm, zero, NULL);
  assert_int_equal(vr_photometry_efficacy(z, 400.0, 700.0, &K, &err), VR_E_RANGE);
  assert_contains(err.message, "no power");
  /* Infrared only: K = 0, so lumens cannot be turned into watts. */
  double ir_nm[2] = {900, 1000}, one[2] = {1, 1};
  vr_spectrum *ir = vr_spectrum_create(2, ir_nm, one, NULL);
  double out;
  assert_int_equal(vr_photometry_efficacy(ir, 850.0, 1000.0, &K, &err), VR_OK);
  assert_near(K, 0.0, 0);
  assert_int_equal(vr_photometry_convert((vr_quantity){1.0, VR_UNIT_LM}, VR_UNIT_W, ir, 850.0,
                                         1000.0, &out, &err),
                   VR_E_RANGE);
  assert_string_equal(vr_photometry_unit_name(VR_UNIT_W_M2_SR), "W/(m2 sr)");
  vr_spectrum_destroy(e), vr_spectrum_destroy(z), vr_spectrum_destroy(ir);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(equal_energy),       cmocka_unit_test(near_monochromatic),
      cmocka_unit_test(fl2_colour_science), cmocka_unit_test(d65_against_core),
      cmocka_unit_test(conversions),        cmocka_unit_test(point_lights),
      cmocka_unit_test(efficacy_errors),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
