/* Correlated colour temperature and CIE 13.3 colour rendering against the
 * CIE's published figures for its F illuminants, colour-science's test
 * vectors, and the method's own identities. */
#include "vr_test.h"
#include "vr/colour.h"
#include "vr/cri.h"

#include <math.h>

static vr_cri cri_of(const char *name) {
  vr_error err = {0};
  vr_spectrum *s = vr_illuminant(name, &err);
  if (!s) fail_msg("%s", err.message);
  vr_cri c;
  if (vr_cri_compute(s, &c, &err)) fail_msg("%s: %s", name, err.message);
  vr_spectrum_destroy(s);
  return c;
}

static void f_illuminants_published(void **state) {
  (void)state;
  /* CIE 015:2004 (3rd ed.), the colorimetric data of illuminants F1-F12:
   * correlated colour temperature (to 10 K; F7, F8, F10-F12 to their
   * nominal values) and the general colour rendering index Ra (CIE 13.3,
   * to the nearest unit).  Ra must round to the published unit
   * (|dRa| <= 0.5); the CCT must lie within 0.5 % (the table's 10-50 K
   * rounding). */
  static const struct {
    const char *name;
    double cct;
    int ra;
  } F[] = {{"F1", 6430, 76},  {"F2", 4230, 64},  {"F3", 3450, 57},  {"F4", 2940, 51},
           {"F5", 6350, 72},  {"F6", 4150, 59},  {"F7", 6500, 90},  {"F8", 5000, 95},
           {"F9", 4150, 90},  {"F10", 5000, 81}, {"F11", 4000, 83}, {"F12", 3000, 83}};
  for (size_t i = 0; i < sizeof F / sizeof F[0]; i++) {
    vr_cri c = cri_of(F[i].name);
    print_message("%-4s CCT %7.1f K (CIE %4.0f)  Ra %6.2f (CIE %d)  DC %.5f\n", F[i].name, c.cct,
                  F[i].cct, c.Ra, F[i].ra, c.dc);
    assert_true(fabs(c.cct - F[i].cct) <= 0.005 * F[i].cct);
    if (strcmp(F[i].name, "F8")) {
      assert_true(fabs(c.Ra - F[i].ra) <= 0.5);
      continue;
    }
    /* F8 sits on CIE 13.3's switch of reference at 5000 K: its CCT is
     * 4997.2 K here, and 4997.3 K from its published chromaticity (x, y)
     * = (0.3458, 0.3586) by the same search, so the reference is a
     * Planckian radiator (Ra 95.50); the CIE's 95 is the daylight
     * reference's figure (the table lists F8 at its nominal 5000 K). */
    assert_true(c.planckian);
    vr_error err = {0};
    vr_spectrum *f8 = vr_illuminant("F8", &err), *d5000 = vr_illuminant_d(5000, &err);
    vr_cri cd;
    assert_int_equal(vr_cri_against(f8, d5000, &cd, &err), VR_OK);
    print_message("F8 against D5000: Ra %.2f (CIE %d)\n", cd.Ra, F[i].ra);
    assert_true(fabs(cd.Ra - F[i].ra) <= 0.5);
    vr_spectrum_destroy(f8);
    vr_spectrum_destroy(d5000);
  }
}

static void colour_science_vectors(void **state) {
  (void)state;
  /* colour-science (colour/quality/tests/test_cri.py): Ra of FL1
   * 75.852827992149358, FL2 64.233724121664778 and A 99.996230290506887,
   * and FL1's special indices R1..R14.  colour-science sums at 1 nm after
   * Sprague interpolation of the 5 nm tables and takes the CCT from
   * Robertson's isotemperature lines; CIE 13.3 (and this code) sums the
   * 5 nm tables as published.  How much the summation alone moves the
   * indices was measured with this code summed at 1 nm over linearly
   * interpolated tables: Ra by up to 0.11 (F2: 64.27 against 64.16 at
   * 5 nm; F1 75.88 against 75.82), R_i by up to 0.42 (F1's R9), with
   * colour-science's Sprague sums between the two.  The bounds, 0.15 on
   * Ra and 0.5 on R_i, hold that spread, and are well inside the
   * published rounding of Ra (0.5). */
  static const double FL1_R[14] = {
      69.196992839933557, 83.650754065677816, 92.136090764490675, 72.665649420972784,
      73.890734513517486, 79.619188860052745, 82.272569853644669, 53.390643618905109,
      -47.284477750225903, 61.568336431199967, 67.522241168172485, 74.890093866757994,
      72.771930354944615, 94.884867470552663};
  vr_cri f1 = cri_of("F1"), f2 = cri_of("F2"), a = cri_of("A");
  print_message("F1 Ra %.4f (75.8528)  F2 Ra %.4f (64.2337)  A Ra %.4f (99.9962)\n", f1.Ra,
                f2.Ra, a.Ra);
  assert_near(f1.Ra, 75.852827992149358, 0.15);
  assert_near(f2.Ra, 64.233724121664778, 0.15);
  assert_near(a.Ra, 99.996230290506887, 0.15);
  for (int i = 0; i < 14; i++) {
    print_message("F1 R%-2d %9.4f (%9.4f)\n", i + 1, f1.R[i], FL1_R[i]);
    assert_near(f1.R[i], FL1_R[i], 0.5);
  }
  assert_true(a.planckian);
  assert_false(f1.planckian);
}

static void identities(void **state) {
  (void)state;
  vr_error err = {0};
  /* A source rendered against itself: every R_i is 100 exactly (CIE 13.3:
   * dE = 0 when the test is the reference). */
  vr_spectrum *d65 = vr_illuminant("D65", &err);
  vr_cri c;
  assert_int_equal(vr_cri_against(d65, d65, &c, &err), VR_OK);
  for (int i = 0; i < 14; i++) assert_near(c.R[i], 100.0, 1e-9);
  assert_near(c.dc, 0.0, 1e-15);
  /* A neutral filter (grey glass of any density) changes no colour:
   * EN 410's Ra of D65 transmitted against D65 is 100. */
  vr_spectrum *grey = vr_spectrum_copy(d65, &err);
  vr_spectrum_scale(grey, 0.37);
  assert_int_equal(vr_cri_against(grey, d65, &c, &err), VR_OK);
  assert_near(c.Ra, 100.0, 1e-9);
  /* A Planckian radiator is its own reference below 5000 K: CCT equal to
   * its temperature (to the golden-section search's tolerance in mired,
   * and the 5 nm sums against the 1 nm locus), Ra 100. */
  static const double T[] = {2000, 2700, 3500, 4500};
  for (size_t i = 0; i < 4; i++) {
    vr_spectrum *bb = vr_illuminant_blackbody(T[i], &err);
    assert_int_equal(vr_cri_compute(bb, &c, &err), VR_OK);
    assert_near(c.cct, T[i], 1e-3 * T[i]);
    assert_near(c.Ra, 100.0, 0.05);
    vr_spectrum_destroy(bb);
  }
  /* CIE daylight is its own reference from 5000 K. */
  vr_spectrum *d = vr_illuminant_d(7500, &err);
  assert_int_equal(vr_cri_compute(d, &c, &err), VR_OK);
  assert_near(c.Ra, 100.0, 0.05);
  assert_near(c.cct, 7500, 30); /* CIE daylight sits a little off the locus: Duv +0.003 */
  vr_spectrum_destroy(d);
  vr_spectrum_destroy(grey);
  vr_spectrum_destroy(d65);
}

static void cct_reference_points(void **state) {
  (void)state;
  /* CIE 015:2004: illuminant A is a Planckian radiator of 2856 K (its
   * defining formula uses c2 = 1.435e-2 m K at 2848 K); D65's CCT is
   * about 6504 K. */
  vr_error err = {0};
  vr_spectrum *a = vr_illuminant("A", &err);
  double w[3], uv[2], T, duv;
  vr_xyz_white(a, VR_CIE1931_2DEG, w);
  vr_xyz_to_uv1960(w, uv);
  assert_int_equal(vr_cct_from_uv(uv, &T, &duv, &err), VR_OK);
  print_message("A: %.2f K, Duv %.2e\n", T, duv);
  assert_near(T, 2856, 1.0);
  assert_near(duv, 0.0, 1e-5);
  vr_spectrum_destroy(a);
  vr_spectrum *d65 = vr_illuminant("D65", &err);
  vr_xyz_white(d65, VR_CIE1931_2DEG, w);
  vr_xyz_to_uv1960(w, uv);
  assert_int_equal(vr_cct_from_uv(uv, &T, &duv, &err), VR_OK);
  print_message("D65: %.2f K, Duv %.5f\n", T, duv);
  assert_near(T, 6504, 2.0);
  assert_true(duv > 0.0025 && duv < 0.0035); /* D65 lies above the locus: Duv 0.0032 (Ohno 2014) */
  vr_spectrum_destroy(d65);
}

static void refusals(void **state) {
  (void)state;
  vr_error err = {0};
  double T, uv[2] = {0.30, 0.20};
  /* Far from the locus (a purple): no CCT. */
  assert_int_equal(vr_cct_from_uv(uv, &T, NULL, &err), VR_E_RANGE);
  assert_non_null(strstr(err.message, "no correlated colour temperature"));
  uv[0] = NAN;
  assert_int_equal(vr_cct_from_uv(uv, &T, NULL, &err), VR_E_RANGE);
  /* A spectrum that stops at 700 nm cannot be rendered over 380-780. */
  double nm[2] = {400, 700}, v[2] = {1, 1};
  vr_spectrum *s = vr_spectrum_create(2, nm, v, &err);
  vr_cri c;
  assert_int_equal(vr_cri_compute(s, &c, &err), VR_E_RANGE);
  assert_non_null(strstr(err.message, "380-780 nm"));
  vr_spectrum_destroy(s);
  /* A dark source has no colour rendering. */
  double nm2[2] = {360, 830}, zero[2] = {0, 0};
  s = vr_spectrum_create(2, nm2, zero, &err);
  assert_int_equal(vr_cri_compute(s, &c, &err), VR_E_RANGE);
  assert_non_null(strstr(err.message, "no luminance"));
  vr_spectrum *d65 = vr_illuminant("D65", &err);
  assert_int_equal(vr_cri_against(s, d65, &c, &err), VR_E_RANGE);
  vr_spectrum_destroy(d65);
  vr_spectrum_destroy(s);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(f_illuminants_published), cmocka_unit_test(colour_science_vectors),
      cmocka_unit_test(identities),              cmocka_unit_test(cct_reference_points),
      cmocka_unit_test(refusals),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
