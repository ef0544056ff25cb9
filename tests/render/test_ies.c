/* IES LM-63 reader: the hand-made Lambertian file in tests/data/ies, the
 * horizontal symmetries of LM-63-2002 section 5.10, the closed-form flux
 * against the analytic pi I0 of a cosine distribution, and errors that name
 * the file and line. */
#include "vr_test.h"
#include "vr/ies.h"

#define PI 3.14159265358979323846

/* A type C file with the given angle sets and I(V, H) = i0 cos V g(H) over
 * the lower hemisphere; g = 1 when twoh is 0, else 2 + cos 2H. */
static char *make_ies(int vstep, const double *h, int nh, double i0, int twoh) {
  size_t cap = 1 << 20, len = 0;
  char *t = malloc(cap);
  int nv = 90 / vstep + 1;
  len += (size_t)snprintf(t + len, cap - len,
                          "IESNA:LM-63-1995\n[TEST] generated\nTILT=NONE\n"
                          "1 -1 1 %d %d 1 2 0 0 0\n1 1 0\n",
                          nv, nh);
  for (int i = 0; i < nv; i++) len += (size_t)snprintf(t + len, cap - len, "%d ", i * vstep);
  len += (size_t)snprintf(t + len, cap - len, "\n");
  for (int j = 0; j < nh; j++) len += (size_t)snprintf(t + len, cap - len, "%g ", h[j]);
  len += (size_t)snprintf(t + len, cap - len, "\n");
  for (int j = 0; j < nh; j++) {
    double g = twoh ? 2.0 + cos(2.0 * h[j] * PI / 180.0) : 1.0;
    for (int i = 0; i < nv; i++)
      len += (size_t)snprintf(t + len, cap - len, "%.17g ", i0 * cos(i * vstep * PI / 180.0) * g);
    len += (size_t)snprintf(t + len, cap - len, "\n");
  }
  return t;
}

static vr_ies *parse_ok(const char *text) {
  vr_error err = {0};
  vr_ies *ies = NULL;
  if (vr_ies_parse(text, strlen(text), "mem.ies", &ies, &err) != VR_OK) fail_msg("%s", err.message);
  return ies;
}

static void lambertian_file(void **state) {
  (void)state;
  vr_error err = {0};
  vr_ies *ies = NULL;
  if (vr_ies_read(VR_TEST_DATA "/ies/lambertian.ies", &ies, &err) != VR_OK)
    fail_msg("%s", err.message);
  assert_string_equal(ies->version, "LM-63-2002");
  assert_int_equal(ies->nv, 19);
  assert_int_equal(ies->nh, 1);
  assert_int_equal(ies->symmetry, VR_IES_ROTATIONAL);
  assert_near(ies->multiplier, 2.0, 0);
  assert_near(ies->width_m, 0.1, 1e-15);
  assert_near(ies->input_watts, 20.0, 0);
  /* The file holds 500 cos V at 4 decimals, times the multiplier 2. */
  assert_near(vr_ies_candela(ies, 0.0, 0.0), 1000.0, 1e-9);
  assert_near(vr_ies_candela(ies, 60.0, 123.0), 500.0, 1e-9);
  assert_near(vr_ies_candela(ies, 2.5, 0.0), 0.5 * (1000.0 + 996.1946), 1e-9);
  assert_near(vr_ies_candela(ies, 120.0, 0.0), 0.0, 0);
  assert_near(vr_ies_max_candela(ies), 1000.0, 0);
  double down[3] = {0, 0, -1}, diag[3] = {1, 0, -1}, up[3] = {0, 0, 1};
  assert_near(vr_ies_candela_dir(ies, down), 1000.0, 1e-9);
  assert_near(vr_ies_candela_dir(ies, diag), 2 * 353.5534, 1e-9);
  assert_near(vr_ies_candela_dir(ies, up), 0.0, 0);

  /* Analytic: int I0 cos V 2 pi sin V dV over the lower hemisphere = pi I0.
   * The file samples cos every 5 degrees; linear interpolation between
   * them loses about h^2/12 = 6e-4 of the flux. */
  double lm = vr_ies_lumens(ies);
  print_message("lambertian.ies: %.6f lm, pi I0 = %.6f lm (relative %.2e)\n", lm, PI * 1000.0,
                (lm - PI * 1000.0) / (PI * 1000.0));
  assert_rel(lm, PI * 1000.0, 1e-3);
  /* The closed form against a fine Simpson rule on the same interpolant. */
  int n = 90 * 64;
  double sum = 0.0, h = (PI / 2.0) / n;
  for (int i = 0; i <= n; i++) {
    double v = i * h, w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
    sum += w * vr_ies_candela(ies, v * 180.0 / PI, 0.0) * sin(v);
  }
  assert_rel(lm, 2.0 * PI * sum * h / 3.0, 1e-10);
  vr_ies_destroy(ies);
}

static void finer_grid_converges(void **state) {
  (void)state;
  double h0 = 0.0;
  char *t = make_ies(1, &h0, 1, 1000.0, 0);
  vr_ies *ies = parse_ok(t);
  double lm = vr_ies_lumens(ies);
  print_message("1 degree grid: %.6f lm (relative %.2e from pi I0)\n", lm,
                (lm - PI * 1000.0) / (PI * 1000.0));
  assert_rel(lm, PI * 1000.0, 3e-5);
  assert_string_equal(ies->version, "LM-63-1995");
  vr_ies_destroy(ies);
  free(t);
}

static void horizontal_symmetries(void **state) {
  (void)state;
  /* I = I0 cos V (2 + cos 2H) is symmetric about both the 0-180 and the
   * 90-270 planes, so the four reduced angle sets of LM-63-2002 5.10 must
   * reproduce the full 0-360 file exactly (10 degree steps: folded angles
   * land on the same grid). */
  double full[37], quad[10], bil[19], bil90[19];
  for (int i = 0; i < 37; i++) full[i] = 10.0 * i;
  for (int i = 0; i < 10; i++) quad[i] = 10.0 * i;
  for (int i = 0; i < 19; i++) bil[i] = 10.0 * i, bil90[i] = 90.0 + 10.0 * i;
  char *tf = make_ies(5, full, 37, 100.0, 1), *tq = make_ies(5, quad, 10, 100.0, 1);
  char *tb = make_ies(5, bil, 19, 100.0, 1), *t9 = make_ies(5, bil90, 19, 100.0, 1);
  vr_ies *f = parse_ok(tf), *q = parse_ok(tq), *b = parse_ok(tb), *b9 = parse_ok(t9);
  assert_int_equal(f->symmetry, VR_IES_NONE);
  assert_int_equal(q->symmetry, VR_IES_QUADRANT);
  assert_int_equal(b->symmetry, VR_IES_BILATERAL);
  assert_int_equal(b9->symmetry, VR_IES_BILATERAL_90);
  double worst = 0.0;
  for (double H = -360.0; H <= 720.0; H += 7.3) {
    for (double V = 0.0; V <= 90.0; V += 6.1) {
      double ref = vr_ies_candela(f, V, H);
      double d = fmax(fabs(vr_ies_candela(q, V, H) - ref),
                      fmax(fabs(vr_ies_candela(b, V, H) - ref), fabs(vr_ies_candela(b9, V, H) - ref)));
      worst = fmax(worst, d);
    }
  }
  assert_near(worst, 0.0, 1e-9);
  /* Exact value at a sample: H = 30 gives g = 2.5. */
  assert_near(vr_ies_candela(q, 0.0, 30.0), 250.0, 1e-9);
  assert_near(vr_ies_candela(q, 0.0, 330.0), 250.0, 1e-9);
  assert_near(vr_ies_candela(b9, 0.0, 210.0), 250.0, 1e-9);
  /* Flux: the H integral of 2 + cos 2H over a full turn is 4 pi (the
   * trapezoid rule is exact for it), twice the 2 pi of a rotational
   * file with the same vertical profile. */
  double h0 = 0.0;
  char *tr = make_ies(5, &h0, 1, 100.0, 0);
  vr_ies *r = parse_ok(tr);
  double lr = vr_ies_lumens(r);
  assert_rel(vr_ies_lumens(f), 2.0 * lr, 1e-12);
  assert_rel(vr_ies_lumens(q), 2.0 * lr, 1e-12);
  assert_rel(vr_ies_lumens(b), 2.0 * lr, 1e-12);
  assert_rel(vr_ies_lumens(b9), 2.0 * lr, 1e-12);
  vr_ies_destroy(f), vr_ies_destroy(q), vr_ies_destroy(b), vr_ies_destroy(b9), vr_ies_destroy(r);
  free(tf), free(tq), free(tb), free(t9), free(tr);
}

static void expect_error(const char *text, vr_status status, const char *needle) {
  vr_error err = {0};
  vr_ies *ies = (vr_ies *)1;
  vr_status st = vr_ies_parse(text, strlen(text), "bad.ies", &ies, &err);
  if (st != status) fail_msg("expected status %d, got %d (%s) for:\n%s", status, st, err.message, text);
  assert_null(ies);
  assert_contains(err.message, needle);
}

static void errors(void **state) {
  (void)state;
  const char *head = "IESNA:LM-63-2002\n[TEST] x\n";
  char t[2048];
  snprintf(t, sizeof t, "%sTILT=INCLUDE\n1\n", head);
  expect_error(t, VR_E_PARSE, "bad.ies:3: TILT=INCLUDE is not supported");
  snprintf(t, sizeof t, "%sTILT=lamp.tlt\n", head);
  expect_error(t, VR_E_PARSE, "bad.ies:3: TILT=lamp.tlt");
  expect_error("IESNA:LM-63-2002\n[TEST] x\n", VR_E_PARSE, "bad.ies:2: no TILT= line");
  snprintf(t, sizeof t, "%sTILT=NONE\n1 -1 1 3 1 2 2 0 0 0\n1 1 0\n0 45 90\n0\n1 2 3\n", head);
  expect_error(t, VR_E_PARSE, "bad.ies:4: photometric type B (2) is not supported");
  snprintf(t, sizeof t, "%sTILT=NONE\n1 -1 1 3 1 1 2 0 0 0\n1 1 0\n0 45 90\n0\n1 2\n", head);
  expect_error(t, VR_E_PARSE, "bad.ies:8: file ends before the candela value 3 of horizontal angle 0");
  snprintf(t, sizeof t, "%sTILT=NONE\n1 -1 1 3 1 1 2 0 0 0\n1 1 0\n0 45 90\n0\n1 x2 3\n", head);
  expect_error(t, VR_E_PARSE, "bad.ies:8: the candela value 2 of horizontal angle 0 is not a number: 'x2'");
  snprintf(t, sizeof t, "%sTILT=NONE\n1 -1 1 3 1 1 2 0 0 0\n1 1 0\n0 45 90\n0\n1 2 3\n4\n", head);
  expect_error(t, VR_E_PARSE, "bad.ies:9: unexpected text after the candela values");
  snprintf(t, sizeof t, "%sTILT=NONE\n1 -1 1 3 1 1 2 0 0 0\n1 1 0\n0 90 45\n0\n1 2 3\n", head);
  expect_error(t, VR_E_PARSE, "bad.ies:6: vertical angles must increase: 45 after 90");
  snprintf(t, sizeof t, "%sTILT=NONE\n1 -1 1 3 1 1 2 0 0 0\n1 1 0\n0 45 90\n0\n1 -2 3\n", head);
  expect_error(t, VR_E_PARSE, "bad.ies:8: candela value 2 of horizontal angle 0 is negative");
  snprintf(t, sizeof t,
           "%sTILT=NONE\n1 -1 1 2 2 1 2 0 0 0\n1 1 0\n0 90\n0 270\n1 2\n3 4\n", head);
  expect_error(t, VR_E_PARSE, "bad.ies:7: horizontal angles run 0..270");
  snprintf(t, sizeof t, "%sTILT=NONE\n1 -1 1 3 1 1 2 0 0 0\n1 1 0\n10 45 90\n0\n1 2 3\n", head);
  expect_error(t, VR_E_PARSE, "vertical angles run 10..90");
  snprintf(t, sizeof t, "%sTILT=NONE\n1 -1 0 3 1 1 2 0 0 0\n", head);
  expect_error(t, VR_E_PARSE, "bad.ies:4: the candela multiplier must be > 0");
  snprintf(t, sizeof t, "%sTILT=NONE\n1 -1 1 99999 99999 1 2 0 0 0\n", head);
  expect_error(t, VR_E_PARSE, "bad.ies:4: the number of vertical angles must be a whole number");
  snprintf(t, sizeof t, "%sTILT=NONE\n1 -1 1 3.5 1 1 2 0 0 0\n", head);
  expect_error(t, VR_E_PARSE, "bad.ies:4: the number of vertical angles must be a whole number");

  vr_error err = {0};
  vr_ies *ies = NULL;
  assert_int_equal(vr_ies_read("/nonexistent/x.ies", &ies, &err), VR_E_IO);
  assert_null(ies);
  assert_contains(err.message, "/nonexistent/x.ies");
}

static void old_layouts_and_separators(void **state) {
  (void)state;
  /* LM-63-1986: no version line, free text before TILT; commas as
   * separators and a trailing DOS end-of-file mark are tolerated; feet are
   * converted (1 ft = 0.3048 m). */
  const char *t = "Some lamp, 1986 layout\nTILT=NONE\n1,1000,1,3,1,1,1,2,1,0.5\n0.9,1,10\n"
                  "0,45,90\n0\n100,50,0\n\x1a";
  vr_ies *ies = parse_ok(t);
  assert_string_equal(ies->version, "LM-63-1986");
  assert_near(ies->width_m, 0.6096, 1e-12);
  assert_near(ies->length_m, 0.3048, 1e-12);
  /* Ballast factor 0.9 scales the candela values, as ies2rad does. */
  assert_near(ies->multiplier, 0.9, 1e-15);
  assert_near(vr_ies_candela(ies, 0.0, 0.0), 90.0, 1e-12);
  assert_near(vr_ies_candela(ies, 22.5, 0.0), 67.5, 1e-12);
  vr_ies_destroy(ies);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(lambertian_file),
      cmocka_unit_test(finer_grid_converges),
      cmocka_unit_test(horizontal_symmetries),
      cmocka_unit_test(errors),
      cmocka_unit_test(old_layouts_and_separators),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
