/* The RGB-to-sigmoid table (core/src/rgb_table.c).
 *
 * Outside references:
 *   - Jakob & Hanika 2019 (CGF 38(2), section 5): every sRGB colour has a
 *     sigmoid reflectance, so the table's nodes inside the gamut must meet
 *     their colours (Delta E*ab 0.01, VR_RGB_SPECTRUM_MAX_DE);
 *   - a looked-up texel must not differ visibly from its colour: Delta E00
 *     under 1, the just-noticeable difference of CIEDE2000 (Sharma, Wu and
 *     Dalal, Color Res. Appl. 30(1), 2005, and CIE 142-2001), over the
 *     23 in-gamut ColorChecker colours (BabelColor's measured spectra under
 *     D65) and 4096 random colours of the gamut;
 *   - a grey g is the flat spectrum g; black is 0 and white 1. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include <cmocka.h>

#include "vr/colorchecker.h"
#include "vr/colour.h"
#include "vr/rgb_table.h"

static const vr_rgb_table *T;
static vr_spectrum *d65;
static double white[3];

/* Delta E00 between a linear sRGB colour and its looked-up spectrum's
 * colour under D65 (1 nm, the library's tristimulus code). */
static double lookup_de(const double rgb[3]) {
  float in[3] = {(float)rgb[0], (float)rgb[1], (float)rgb[2]}, c[3];
  vr_rgb_table_lookup(T, in, c);
  double nm[471], v[471], xyz[3], want[3], got[3];
  for (int i = 0; i < 471; i++) {
    nm[i] = 360 + i, v[i] = vr_rgb_coef_eval(c, nm[i]);
    assert_true(v[i] >= 0 && v[i] <= 1);
  }
  vr_error e = {0};
  vr_spectrum *r = vr_spectrum_create(471, nm, v, &e);
  vr_xyz_reflectance(r, d65, VR_CIE1931_2DEG, xyz);
  vr_spectrum_destroy(r);
  vr_xyz_to_lab(xyz, white, got);
  vr_srgb_linear_to_xyz(rgb, xyz);
  vr_xyz_to_lab(xyz, white, want);
  return vr_delta_e2000(want, got);
}

static int setup(void **state) {
  (void)state;
  vr_error e = {0};
  struct timespec a, b;
  clock_gettime(CLOCK_MONOTONIC, &a);
  T = vr_rgb_table_get(&e);
  clock_gettime(CLOCK_MONOTONIC, &b);
  if (!T) return -1;
  long over;
  double worst = vr_rgb_table_worst(T, &over);
  printf("# table %d^3 x 3 built in %.2f s; worst node Delta E*ab %.3g, %ld nodes over 0.01\n",
         VR_RGB_TABLE_RES, (b.tv_sec - a.tv_sec) + 1e-9 * (b.tv_nsec - a.tv_nsec), worst, over);
  d65 = vr_illuminant("D65", &e);
  vr_xyz_white(d65, VR_CIE1931_2DEG, white);
  return d65 ? 0 : -1;
}

static int teardown(void **state) {
  (void)state;
  vr_spectrum_destroy(d65);
  return 0;
}

static void test_colorchecker(void **state) {
  (void)state;
  vr_error e = {0};
  double worst = 0;
  for (size_t i = 0; i < VR_COLORCHECKER_PATCHES; i++) {
    vr_spectrum *p = vr_colorchecker_patch(i, &e);
    double xyz[3], rgb[3];
    vr_xyz_reflectance(p, d65, VR_CIE1931_2DEG, xyz);
    vr_xyz_to_srgb_linear(xyz, rgb);
    vr_spectrum_destroy(p);
    if (rgb[0] < 0 || rgb[1] < 0 || rgb[2] < 0) continue; /* cyan, outside sRGB */
    double de = lookup_de(rgb);
    if (!(de < 1)) fail_msg("%s: Delta E00 %g", vr_colorchecker_name(i), de);
    worst = fmax(worst, de);
  }
  printf("# ColorChecker through the table: worst Delta E00 %.3g\n", worst);
}

static void test_random(void **state) {
  (void)state;
  srand(7);
  double worst = 0, sum = 0;
  int n = 4096, over_jnd = 0;
  for (int k = 0; k < n; k++) {
    double rgb[3];
    for (int j = 0; j < 3; j++) rgb[j] = (double)rand() / RAND_MAX;
    double de = lookup_de(rgb);
    worst = fmax(worst, de), sum += de;
    over_jnd += !(de < 1);
  }
  printf("# %d random colours: mean Delta E00 %.3g, worst %.3g\n", n, sum / n, worst);
  assert_int_equal(over_jnd, 0);
}

static void test_edges(void **state) {
  (void)state;
  float c[3];
  const float black[3] = {0, 0, 0}, whitec[3] = {1, 1, 1}, nan3[3] = {NAN, -5, 7};
  vr_rgb_table_lookup(T, black, c);
  for (double nm = 360; nm <= 830; nm += 47) assert_true(vr_rgb_coef_eval(c, nm) < 1e-8);
  vr_rgb_table_lookup(T, whitec, c);
  for (double nm = 360; nm <= 830; nm += 47) assert_true(vr_rgb_coef_eval(c, nm) > 1 - 1e-8);
  /* NaN -> 0, -5 -> 0, 7 -> 1: the colour (0, 0, 1). */
  float c2[3];
  const float blue[3] = {0, 0, 1};
  vr_rgb_table_lookup(T, nan3, c);
  vr_rgb_table_lookup(T, blue, c2);
  for (int k = 0; k < 3; k++) assert_true(c[k] == c2[k]);
  const double greys[] = {0.01, 0.18, 0.5, 0.9};
  for (size_t g = 0; g < 4; g++) {
    float in[3] = {(float)greys[g], (float)greys[g], (float)greys[g]};
    vr_rgb_table_lookup(T, in, c);
    for (double nm = 360; nm <= 830; nm += 47)
      assert_true(fabs(vr_rgb_coef_eval(c, nm) - greys[g]) < 2e-3);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_colorchecker),
      cmocka_unit_test(test_random),
      cmocka_unit_test(test_edges),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
