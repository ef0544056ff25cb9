/* RGB colours as sigmoid reflectances (core/src/rgb_spectrum.c).
 *
 * Outside references:
 *   - Jakob & Hanika 2019 (Computer Graphics Forum 38(2), section 5): the
 *     sigmoid space holds the whole sRGB gamut, so every sRGB colour has a
 *     reflectance of this form; the test holds the fit to Delta E00 < 0.01
 *     on the 23 in-gamut ColorChecker colours and the gamut's corners;
 *   - the colours are BabelColor's measured ColorChecker spectra under
 *     CIE D65 (core/data/colorchecker_babelcolor.csv), whose cyan lies
 *     outside sRGB (Pascale, "RGB coordinates of the Macbeth ColorChecker",
 *     BabelColor 2006: its red is negative), which must be refused;
 *   - IEC 61966-2-1 decoding: #808080 is 0.2158605 linear;
 *   - a grey g is the flat spectrum g (the model's S(c2) = g). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>

#include <cmocka.h>

#include "vr/colorchecker.h"
#include "vr/colour.h"
#include "vr/rgb_spectrum.h"

/* The colour of a fit under D65 as a 1 nm spectrum through the library's
 * own tristimulus code (not the fit's 5 nm sums), in Lab. */
static void fit_lab(const vr_rgb_spectrum *s, const vr_spectrum *d65, double lab[3]) {
  double nm[471], v[471], xyz[3], white[3];
  for (int i = 0; i < 471; i++) nm[i] = 360 + i, v[i] = vr_rgb_spectrum_eval(s, nm[i]);
  vr_error e = {0};
  vr_spectrum *r = vr_spectrum_create(471, nm, v, &e);
  assert_non_null(r);
  vr_xyz_reflectance(r, d65, VR_CIE1931_2DEG, xyz);
  vr_xyz_white(d65, VR_CIE1931_2DEG, white);
  vr_xyz_to_lab(xyz, white, lab);
  vr_spectrum_destroy(r);
}

static double round_trip(const double rgb[3], const vr_spectrum *d65) {
  vr_error e = {0};
  vr_rgb_spectrum s;
  if (vr_rgb_spectrum_fit(rgb, &s, &e)) fail_msg("(%g, %g, %g): %s", rgb[0], rgb[1], rgb[2], e.message);
  double xyz[3], white[3], want[3], got[3];
  vr_srgb_linear_to_xyz(rgb, xyz);
  vr_xyz_white(d65, VR_CIE1931_2DEG, white);
  vr_xyz_to_lab(xyz, white, want);
  fit_lab(&s, d65, got);
  for (int i = 0; i < 471; i += 10) {
    double r = vr_rgb_spectrum_eval(&s, 360 + i);
    assert_true(r >= 0 && r <= 1);
  }
  return vr_delta_e2000(want, got);
}

static void test_colorchecker(void **state) {
  (void)state;
  vr_error e = {0};
  vr_spectrum *d65 = vr_illuminant("D65", &e);
  assert_non_null(d65);
  int fitted = 0;
  for (size_t i = 0; i < VR_COLORCHECKER_PATCHES; i++) {
    vr_spectrum *p = vr_colorchecker_patch(i, &e);
    assert_non_null(p);
    double xyz[3], rgb[3];
    vr_xyz_reflectance(p, d65, VR_CIE1931_2DEG, xyz);
    vr_xyz_to_srgb_linear(xyz, rgb);
    vr_spectrum_destroy(p);
    if (rgb[0] < 0 || rgb[1] < 0 || rgb[2] < 0) {
      /* Cyan, outside sRGB: refused, named as out of range. */
      assert_string_equal(vr_colorchecker_name(i), "cyan");
      vr_rgb_spectrum s;
      assert_int_equal(vr_rgb_spectrum_fit(rgb, &s, &e), VR_E_RANGE);
      continue;
    }
    double de = round_trip(rgb, d65);
    if (!(de < 0.01)) fail_msg("%s: Delta E00 %g", vr_colorchecker_name(i), de);
    fitted++;
  }
  assert_int_equal(fitted, 23);
  vr_spectrum_destroy(d65);
}

static void test_gamut_corners(void **state) {
  (void)state;
  vr_error e = {0};
  vr_spectrum *d65 = vr_illuminant("D65", &e);
  const double corners[][3] = {{1, 0, 0},  {0, 1, 0},       {0, 0, 1},      {1, 1, 0},
                               {0, 1, 1},  {1, 0, 1},       {0.99, 0.01, 0}, {0.2, 0.6, 0.9},
                               {1, 0.5, 0}, {0.001, 0.002, 0.001}};
  for (size_t k = 0; k < sizeof corners / sizeof *corners; k++) {
    double de = round_trip(corners[k], d65);
    if (!(de < 0.01)) fail_msg("corner %zu: Delta E00 %g", k, de);
  }
  vr_spectrum_destroy(d65);
}

static void test_greys(void **state) {
  (void)state;
  vr_error e = {0};
  const double g[] = {0, 1e-6, 0.18, 0.5, 0.9, 1};
  for (size_t k = 0; k < sizeof g / sizeof *g; k++) {
    double rgb[3] = {g[k], g[k], g[k]};
    vr_rgb_spectrum s;
    assert_int_equal(vr_rgb_spectrum_fit(rgb, &s, &e), VR_OK);
    assert_true(s.c[0] == 0 && s.c[1] == 0);
    for (double nm = 360; nm <= 830; nm += 47) assert_true(fabs(vr_rgb_spectrum_eval(&s, nm) - g[k]) < 1e-12);
  }
}

static void test_refusals(void **state) {
  (void)state;
  vr_error e = {0};
  vr_rgb_spectrum s;
  const double bad[][3] = {{1.1, 0.5, 0.5}, {0.5, -0.01, 0.5}, {0.5, 0.5, NAN}, {INFINITY, 0, 0}};
  for (size_t k = 0; k < sizeof bad / sizeof *bad; k++)
    assert_int_equal(vr_rgb_spectrum_fit(bad[k], &s, &e), VR_E_RANGE);
}

static void test_hex(void **state) {
  (void)state;
  double rgb[3];
  assert_true(vr_rgb_parse_hex("#FFffFF", rgb));
  assert_true(rgb[0] == 1 && rgb[1] == 1 && rgb[2] == 1);
  assert_true(vr_rgb_parse_hex("#808000", rgb));
  assert_true(fabs(rgb[0] - 0.2158605) < 1e-6 && fabs(rgb[1] - 0.2158605) < 1e-6 && rgb[2] == 0);
  const char *bad[] = {"808080", "#80808", "#8080800", "#GG0000", "#", "", NULL};
  for (int k = 0; bad[k]; k++) assert_false(vr_rgb_parse_hex(bad[k], rgb));
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_colorchecker), cmocka_unit_test(test_gamut_corners),
      cmocka_unit_test(test_greys),        cmocka_unit_test(test_refusals),
      cmocka_unit_test(test_hex),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
