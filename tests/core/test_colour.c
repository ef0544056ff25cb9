/* Colorimetry against the CIE tables, IEC 61966-2-1, Sharma's CIEDE2000
 * test data and the BabelColor ColorChecker. */
#include "vr_test.h"
#include "vr/colorchecker.h"
#include "vr/colour.h"
#include "vr/csv.h"

static void xy_of(const char *name, vr_observer obs, double xy[2]) {
  vr_error err = {0};
  vr_spectrum *s = vr_illuminant(name, &err);
  if (!s) fail_msg("%s", err.message);
  double w[3], xyy[3];
  vr_xyz_white(s, obs, w);
  vr_xyz_to_xyy(w, w, xyy);
  xy[0] = xyy[0];
  xy[1] = xyy[1];
  vr_spectrum_destroy(s);
}

static void d65_white_point(void **state) {
  (void)state;
  /* CIE 015:2004 Table T.3 / ASTM E308: D65, 2 deg: X = 95.047, Z = 108.883
   * (Y = 100); 10 deg: X = 94.811, Z = 107.304. */
  vr_spectrum *d65 = vr_illuminant("D65", NULL);
  double w[3];
  vr_xyz_white(d65, VR_CIE1931_2DEG, w);
  assert_near(w[0], 0.95047, 1e-4);
  assert_near(w[1], 1.0, 1e-15);
  assert_near(w[2], 1.08883, 1e-4);
  vr_xyz_white(d65, VR_CIE1964_10DEG, w);
  assert_near(w[0], 0.94811, 1e-4);
  assert_near(w[2], 1.07304, 1e-4);
  vr_spectrum_destroy(d65);
}

static void illuminant_chromaticities(void **state) {
  (void)state;
  /* CIE 015:2004 Tables T.3 and T.8, CIE 015:2018 Table 10.4 (LEDs), as
   * collected in colour-science's chromaticity_coordinates.py. */
  struct { const char *name; double x, y, tol; } ref[] = {
      {"A", 0.44757, 0.40745, 5e-5},      {"D65", 0.31272, 0.32903, 5e-5},
      {"D50", 0.34567, 0.35851, 5e-5},    {"D55", 0.33243, 0.34744, 5e-5},
      {"D75", 0.29903, 0.31488, 5e-5},    {"E", 1.0 / 3, 1.0 / 3, 5e-5},
      {"F2", 0.3721, 0.3751, 5e-4},       {"F7", 0.3129, 0.3292, 5e-4},
      {"F11", 0.3805, 0.3769, 5e-4},      {"LED-B1", 0.4560, 0.4078, 5e-4},
      {"LED-B5", 0.3118, 0.3236, 5e-4},   {"LED-RGB1", 0.4557, 0.4211, 5e-4},
      {"LED-V1", 0.4548, 0.4044, 5e-4},   {"LED-V2", 0.3781, 0.3775, 5e-4},
  };
  for (size_t i = 0; i < sizeof ref / sizeof ref[0]; i++) {
    double xy[2];
    xy_of(ref[i].name, VR_CIE1931_2DEG, xy);
    if (fabs(xy[0] - ref[i].x) > ref[i].tol || fabs(xy[1] - ref[i].y) > ref[i].tol)
      fail_msg("%s: xy = (%.5f, %.5f), CIE gives (%.5f, %.5f)", ref[i].name, xy[0], xy[1],
               ref[i].x, ref[i].y);
  }
  /* 10 deg observer, CIE 015:2004 Table T.3: A (0.45117, 0.40594), D65
   * (0.31382, 0.33100). */
  double xy[2];
  xy_of("A", VR_CIE1964_10DEG, xy);
  assert_near(xy[0], 0.45117, 5e-5);
  assert_near(xy[1], 0.40594, 5e-5);
  xy_of("D65", VR_CIE1964_10DEG, xy);
  assert_near(xy[0], 0.31382, 5e-5);
  assert_near(xy[1], 0.33100, 5e-5);
}

static void planck_and_illuminant_a(void **state) {
  (void)state;
  /* CIE 015:2018 Table 1 (illuminant A): 100 at 560 nm, 0.930483 at 300 nm,
   * 241.675 at 780 nm. */
  vr_spectrum *a = vr_illuminant_a(NULL);
  assert_near(vr_spectrum_eval(a, 560, VR_INTERP_LINEAR), 100.0, 1e-12);
  assert_near(vr_spectrum_eval(a, 300, VR_INTERP_LINEAR), 0.930483, 5e-7);
  assert_near(vr_spectrum_eval(a, 780, VR_INTERP_LINEAR), 241.675, 5e-4);
  vr_spectrum_destroy(a);
  /* Wien's displacement law, b = 2.897771955e-3 m K (CODATA 2018): the
   * spectral radiance of a 5000 K body peaks at 579.55 nm. */
  double best = 0, at = 0;
  for (double nm = 570; nm <= 590; nm += 0.001) {
    double v = vr_planck(nm, 5000.0);
    if (v > best) { best = v; at = nm; }
  }
  assert_near(at, 2.897771955e6 / 5000.0, 0.002);
  /* Unknown names and out-of-range daylight are refused by name. */
  vr_error err = {0};
  assert_null(vr_illuminant("D3000", &err));
  assert_contains(err.message, "4000-25000 K");
  assert_null(vr_illuminant("F13", &err));
  assert_int_equal(err.status, VR_E_NOT_FOUND);
  assert_contains(err.message, "unknown illuminant 'F13'");
}

static void ciede2000_sharma_pairs(void **state) {
  (void)state;
  /* All 34 pairs of Sharma, Wu and Dalal (2005), Table 1, to 1e-4. */
  vr_csv *c;
  vr_error err = {0};
  if (vr_csv_read(VR_TEST_DATA "/ciede2000_sharma2005.csv", &c, &err)) fail_msg("%s", err.message);
  assert_int_equal(vr_csv_rows(c), 35);
  for (size_t r = 1; r < vr_csv_rows(c); r++) {
    double v[8];
    for (int k = 0; k < 8; k++) assert_int_equal(vr_csv_number(c, r, (size_t)k, "x", &v[k], &err), VR_OK);
    double l1[3] = {v[1], v[2], v[3]}, l2[3] = {v[4], v[5], v[6]};
    double de = vr_delta_e2000(l1, l2);
    if (fabs(de - v[7]) > 1e-4) fail_msg("pair %g: dE00 = %.6f, Sharma gives %.4f", v[0], de, v[7]);
    /* Symmetric in its arguments. */
    assert_near(vr_delta_e2000(l2, l1), de, 1e-12);
  }
  vr_csv_destroy(c);
  double lab[3] = {50, 2.5, -3};
  assert_near(vr_delta_e2000(lab, lab), 0.0, 0);
  double lab2[3] = {53, 6.5, 9};
  assert_near(vr_delta_e76(lab, lab2), 13.0, 1e-12);
}

static void lab_and_srgb_definitions(void **state) {
  (void)state;
  double d65[3], lab[3], back[3];
  vr_srgb_white(d65);
  /* The white is L* = 100, a* = b* = 0; the CIE breakpoint (6/29)^3 is
   * continuous: L* = 8 at Y = 8/903.3 (CIE 015:2018 eq. 8.1). */
  vr_xyz_to_lab(d65, d65, lab);
  assert_near(lab[0], 100.0, 1e-12);
  assert_near(lab[1], 0.0, 1e-12);
  assert_near(lab[2], 0.0, 1e-12);
  double grey[3] = {d65[0] * 8 * 27 / 24389.0, 8 * 27 / 24389.0, d65[2] * 8 * 27 / 24389.0};
  vr_xyz_to_lab(grey, d65, lab);
  assert_near(lab[0], 8.0, 1e-12);
  double xyz[3] = {0.2, 0.3, 0.4};
  vr_xyz_to_lab(xyz, d65, lab);
  vr_lab_to_xyz(lab, d65, back);
  for (int i = 0; i < 3; i++) assert_near(back[i], xyz[i], 1e-14);
  /* IEC 61966-2-1: the transfer curve's two pieces meet at 0.0031308 ->
   * 0.04045 (within the standard's 4-digit rounding), and D65 white maps to
   * RGB = 1 within the matrices' 4-digit precision. */
  assert_near(vr_srgb_encode(0.0031308), 0.04045, 1e-5);
  assert_near(vr_srgb_decode(vr_srgb_encode(0.5)), 0.5, 1e-15);
  assert_near(vr_srgb_encode(1.0), 1.0, 1e-15);
  double rgb[3];
  vr_xyz_to_srgb_linear(d65, rgb);
  for (int i = 0; i < 3; i++) assert_near(rgb[i], 1.0, 1e-3);
  int rgb8[3];
  assert_false(vr_xyz_to_srgb8(d65, rgb8));
  assert_int_equal(rgb8[0], 255);
  double green[3] = {0.1, 0.5, 0.05};
  assert_true(vr_xyz_to_srgb8(green, rgb8));
}

static void bradford_matrix(void **state) {
  (void)state;
  /* Lindbloom, "Chromatic Adaptation" (brucelindbloom.com): Bradford D65 ->
   * D50 with whites (0.95047, 1, 1.08883) and (0.96422, 1, 0.82521):
   * [ 1.0478112  0.0228866 -0.0501270
   *   0.0295424  0.9904844 -0.0170491
   *  -0.0092345  0.0150436  0.7521316 ] */
  const double M[3][3] = {{1.0478112, 0.0228866, -0.0501270},
                          {0.0295424, 0.9904844, -0.0170491},
                          {-0.0092345, 0.0150436, 0.7521316}};
  double w65[3] = {0.95047, 1.0, 1.08883}, w50[3] = {0.96422, 1.0, 0.82521};
  for (int j = 0; j < 3; j++) {
    double e[3] = {0, 0, 0}, out[3];
    e[j] = 1.0;
    vr_bradford(e, w65, w50, out);
    for (int i = 0; i < 3; i++) assert_near(out[i], M[i][j], 1e-7);
  }
}

static void colorchecker_srgb(void **state) {
  (void)state;
  /* BabelColor average spectra under D65 with the 2 deg observer, to sRGB:
   * within one 8-bit step of BabelColor's own sRGB values for the same
   * averages (tests/data/colorchecker_babelcolor2012_srgb.csv names them). */
  vr_csv *c;
  vr_error err = {0};
  if (vr_csv_read(VR_TEST_DATA "/colorchecker_babelcolor2012_srgb.csv", &c, &err))
    fail_msg("%s", err.message);
  assert_int_equal(vr_csv_rows(c), 25);
  vr_spectrum *d65 = vr_illuminant("D65", NULL);
  int worst = 0;
  for (size_t p = 0; p < VR_COLORCHECKER_PATCHES; p++) {
    vr_spectrum *s = vr_colorchecker_patch(p, NULL);
    double xyz[3];
    int rgb[3];
    vr_xyz_reflectance(s, d65, VR_CIE1931_2DEG, xyz);
    vr_xyz_to_srgb8(xyz, rgb);
    assert_string_equal(vr_csv_field(c, p + 1, 0), vr_colorchecker_name(p));
    for (int k = 0; k < 3; k++) {
      double ref;
      assert_int_equal(vr_csv_number(c, p + 1, (size_t)k + 1, "rgb", &ref, &err), VR_OK);
      int d = abs(rgb[k] - (int)ref);
      if (d > worst) worst = d;
      if (d > 1)
        fail_msg("%s: sRGB (%d, %d, %d), published channel %d = %g", vr_colorchecker_name(p), rgb[0],
                 rgb[1], rgb[2], k, ref);
    }
    vr_spectrum_destroy(s);
  }
  print_message("ColorChecker sRGB: worst channel difference %d\n", worst);
  vr_spectrum_destroy(d65);
  vr_csv_destroy(c);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(d65_white_point),
      cmocka_unit_test(illuminant_chromaticities),
      cmocka_unit_test(planck_and_illuminant_a),
      cmocka_unit_test(ciede2000_sharma_pairs),
      cmocka_unit_test(lab_and_srgb_definitions),
      cmocka_unit_test(bradford_matrix),
      cmocka_unit_test(colorchecker_srgb),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
