/* The renderer against analytic answers, read through illuminance sensors:
 *   - CIE 171:2006 test case 5.2: a Lambertian point source of
 *     I(θ) = 1000 cos θ cd at 3 m above a black 4 x 4 m floor gives
 *     111.11 lx below it, 90.02 lx at (1, 0) and 49.39 lx at (1.5, 1.5);
 *   - an isotropic point source: E = I cos θ / r² (inverse-square and
 *     cosine laws) at several floor points;
 *   - CIE 171:2006 test case 5.8: a 4 m cube of uniform reflectance ρ with
 *     an isotropic 10000 lm source at its centre has a mean indirect
 *     illuminance of ρ Φ / (S_T (1 - ρ)) = 104.2 lx at ρ = 0.5;
 *   - the white furnace: inside a closed box whose walls have albedo a
 *     and emit L_e, the radiance is L_e / (1 - a) everywhere, so a sensor
 *     reads E = π L_e / (1 - a).
 *
 * Two kinds of bound (issue 36):
 *   - deterministic: a point source of the equal-energy spectrum E under
 *     `spectral=bins` has no random number left in its direct light (the
 *     source is a point and the wavelengths are the bins' centres), and
 *     with 8 bins of 59 nm over 360-832 nm it has no quadrature error
 *     either: each bin's colour-matching weight is a midpoint sum on 0.1 nm
 *     steps that never straddle the 1 nm table's points, exact for the
 *     table's linear pieces, and the source's lumens are the trapezoid
 *     over the same points, exact for E x V, linear between them.  The
 *     reading must equal the formula to rounding: DET_REL = 2^-20
 *     (9.5e-7) relative.  Each ray pushed has its origin, direction,
 *     weight and throughput rounded to float (vr_flow_push: a ray is the
 *     same on every rank and goes in few bytes on the wire), 2^-24
 *     relative each; a sensor's direct reading passes two pushes (the
 *     sensor ray and the shadow ray), at most 8 roundings that enter its
 *     value, each entering at most twice (the inverse square of a
 *     distance): 16 x 2^-24 = 2^-20.  (With bins of 58.75 nm over
 *     360-830 nm the steps straddle the table's points and the reading is
 *     9e-8 off: within this bound, no longer told apart.)
 *   - statistical: a Monte Carlo reading must lie within K_SE of its own
 *     standard errors of the expected value.  The standard error comes
 *     from 16 batches of samples, so the ratio follows Student's t with
 *     15 degrees of freedom: P(|t15| > 6) = 2.4e-5, one false failure in
 *     40 000 checks of a correct renderer (4 would give 1.2e-3).  The seeds
 *     are fixed, so a run that passes passes every time.  Each check also
 *     requires the standard error to be small (MAX_SE of the value), or a
 *     noisy run would pass anything.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "render_test_util.h"

#define K_SE 6.0
#define DET_REL 0x1p-20 /* the deterministic cases' bound, above */
#define MAX_SE 0.01

static vr_render_result *render_text(const char *text, int S, int P) {
  return render_text_with(text, S, P, false);
}

/* Deterministic: within rel of want. */
static void expect_lx(const vr_render_result *r, size_t i, double want, double rel) {
  double got = r->readings[i].illuminance_lx;
  if (!(fabs(got - want) <= rel * want))
    fail_msg("sensor %zu: %.9g lx, expected %.9g (+-%.1e relative)", i, got, want, rel);
}

/* Statistical: within K_SE standard errors, and the error itself small. */
static void expect_lx_se(const vr_render_result *r, size_t i, double want) {
  double got = r->readings[i].illuminance_lx, se = r->readings[i].stderr_lx;
  if (!(se <= MAX_SE * want))
    fail_msg("sensor %zu: standard error %.4f lx is over %.0f %% of %.4f lx: too noisy to test", i,
             se, 100 * MAX_SE, want);
  if (!(fabs(got - want) <= K_SE * se))
    fail_msg("sensor %zu: %.4f lx, expected %.4f within %.0f standard errors (%.4f lx)", i, got,
             want, K_SE, se);
}

/* E = I0 cos θ cos θ / r² for a Lambertian point source I(θ) = I0 cos θ
 * at height h over a point (x, y) of the floor. */
static double lambertian_point(double I0, double h, double x, double y) {
  double r2 = x * x + y * y + h * h, c = h / sqrt(r2);
  return I0 * c * c / r2;
}

/* The formula against the CIE 171:2006 table 5.2 itself, so that the
 * renderer is held to the published case: the table's figures are given
 * to 0.01 lx and agree with the formula to 0.02 lx (its 90.02 and 49.39 lx
 * against the formula's 90.000 and 49.383 lx). */
static void test_cie171_table_formula(void **state) {
  (void)state;
  assert_true(fabs(lambertian_point(1000, 3, 0, 0) - 111.11) <= 0.025);
  assert_true(fabs(lambertian_point(1000, 3, 1, 0) - 90.02) <= 0.025);
  assert_true(fabs(lambertian_point(1000, 3, 1.5, 1.5) - 49.39) <= 0.025);
}

/* CIE 171:2006 section 5.2, Lambertian point source over a black floor. */
static const char *cie171_point =
    "material black black\n"
    "rect center=0,0,0 normal=0,0,1 size=4,4 material=black\n"
    "light point position=0,0,3 intensity=1000cd distribution=lambertian normal=0,0,-1%s\n"
    "sensor a point position=0,0,0 normal=0,0,1\n"
    "sensor b point position=1,0,0 normal=0,0,1\n"
    "sensor c point position=1.5,1.5,0 normal=0,0,1\n"
    "render integrator=path sensor_samples=%d%s\n";
static const double cie171_xy[3][2] = {{0, 0}, {1, 0}, {1.5, 1.5}};

static void test_cie171_point_lambertian(void **state) {
  (void)state;
  char scn[1024];
  /* Hero wavelengths, the default: a Monte Carlo estimate over wavelength. */
  snprintf(scn, sizeof scn, cie171_point, "", 256, "");
  vr_render_result *r = render_text(scn, 1, 2);
  assert_int_equal(r->nreadings, 3);
  for (size_t i = 0; i < 3; i++)
    expect_lx_se(r, i, lambertian_point(1000, 3, cie171_xy[i][0], cie171_xy[i][1]));
  vr_render_result_destroy(r);
  /* The same case made deterministic (see the top of the file). */
  snprintf(scn, sizeof scn, cie171_point, " spectrum=E", 4,
           " spectral=bins wavelengths=8 range=360,832");
  r = render_text(scn, 1, 2);
  for (size_t i = 0; i < 3; i++)
    expect_lx(r, i, lambertian_point(1000, 3, cie171_xy[i][0], cie171_xy[i][1]), DET_REL);
  vr_render_result_destroy(r);
}

/* E = I cos θ / r² for an isotropic 500 cd source 2 m up. */
static const char *inverse_square =
    "material black black\n"
    "rect center=0,0,0 normal=0,0,1 size=20,20 material=black\n"
    "light point position=0,0,2 intensity=500cd%s\n"
    "sensor a point position=0,0,0 normal=0,0,1\n"
    "sensor b point position=2,0,0 normal=0,0,1\n"
    "sensor c point position=3,4,0 normal=0,0,1\n"
    "sensor d point position=-5,1,0 normal=0,0,1\n"
    "render integrator=path sensor_samples=%d%s\n";

static void test_inverse_square_cosine(void **state) {
  (void)state;
  const double pts[4][2] = {{0, 0}, {2, 0}, {3, 4}, {-5, 1}};
  char scn[1024];
  for (int deterministic = 0; deterministic < 2; deterministic++) {
    if (deterministic)
      snprintf(scn, sizeof scn, inverse_square, " spectrum=E", 4,
               " spectral=bins wavelengths=8 range=360,832");
    else
      snprintf(scn, sizeof scn, inverse_square, "", 256, "");
    vr_render_result *r = render_text(scn, 1, 1);
    for (size_t i = 0; i < 4; i++) {
      double r2 = pts[i][0] * pts[i][0] + pts[i][1] * pts[i][1] + 4.0;
      double want = 500.0 * (2.0 / sqrt(r2)) / r2;
      if (deterministic)
        expect_lx(r, i, want, DET_REL);
      else
        expect_lx_se(r, i, want);
    }
    vr_render_result_destroy(r);
  }
}

/* CIE 171:2006 section 5.8: indirect illuminance in a cube.  The formula
 * is an energy balance: every bounce returns the fraction rho of the flux,
 * so the indirect flux reaching the walls is rho Phi / (1 - rho) and its
 * mean over the area S_T is the expected value.  By symmetry each face has
 * that mean, so it is read as the mean over the floor, less the analytic
 * direct part I cos(theta) / r^2 at each point.
 *
 * The mean over a grid of cell centres is the midpoint rule, whose error
 * for a smooth field is c h^2 + O(h^4): on 8 x 8 cells the floor's mean
 * comes out about 0.5 % high, eight times its standard error.  Two grids,
 * 8 x 8 and 16 x 16, give the Richardson extrapolation (4 m16 - m8) / 3,
 * free of the h^2 term, with variance (16 se16^2 + se8^2) / 9; that is
 * held to K_SE of its standard errors.  The field's kink along the walls
 * adds an h^2 log h term that the extrapolation does not remove; measured,
 * what is left is within 1.2 standard errors (104.18 +- 0.05 lx). */
static void test_cie171_cube_indirect(void **state) {
  (void)state;
  const char *scn =
      "material wall lambert reflectance=0.5\n"
      "box min=-2,-2,0 max=2,2,4 material=wall\n"
      "light point position=0,0,2 intensity=10000lm\n"
      "sensor coarse grid origin=-2,-2,0 u=4,0,0 v=0,4,0 n=8,8 normal=0,0,1\n"
      "sensor fine grid origin=-2,-2,0 u=4,0,0 v=0,4,0 n=16,16 normal=0,0,1\n"
      "render integrator=path depth=64 sensor_samples=4096\n";
  vr_render_result *r = render_text(scn, 2, 2);
  assert_int_equal(r->nreadings, 64 + 256);
  double indirect, se8, se16; /* rho Phi / (S_T (1 - rho)) = 104.17 lx */
  double m8 = cie171_cube_indirect_of(r, 0, 64, 10000.0, 0.5, &indirect, &se8);
  double m16 = cie171_cube_indirect_of(r, 64, 256, 10000.0, 0.5, &indirect, &se16);
  double m = (4 * m16 - m8) / 3, se = sqrt(16 * se16 * se16 + se8 * se8) / 3;
  print_message("    mean indirect: 8 x 8 %.3f lx, 16 x 16 %.3f lx, extrapolated %.3f +- %.3f lx, "
                "CIE 171 %.3f lx\n",
                m8, m16, m, se, indirect);
  assert_true(se <= MAX_SE * indirect);
  if (!(fabs(m - indirect) <= K_SE * se))
    fail_msg("mean indirect illuminance %.3f lx (extrapolated), CIE 171 expects %.3f within %.0f "
             "standard errors (%.3f lx)",
             m, indirect, K_SE, se);
  vr_render_result_destroy(r);
}

/* White furnace: walls of albedo 0.8 emitting 100 cd/m² inwards.  Both
 * points expect the same E, so their mean (independent streams: variance
 * (se1^2 + se2^2) / 4) is held to K_SE standard errors, about 1.6 %. */
static void test_white_furnace(void **state) {
  (void)state;
  const char *scn =
      "material wall lambert reflectance=0.8\n"
      "rect center=0,0,-1 normal=0,0,1 size=2,2 material=wall emission=100cd/m2\n"
      "rect center=0,0,1 normal=0,0,-1 size=2,2 material=wall emission=100cd/m2\n"
      "rect center=-1,0,0 normal=1,0,0 size=2,2 material=wall emission=100cd/m2\n"
      "rect center=1,0,0 normal=-1,0,0 size=2,2 material=wall emission=100cd/m2\n"
      "rect center=0,-1,0 normal=0,1,0 size=2,2 material=wall emission=100cd/m2\n"
      "rect center=0,1,0 normal=0,-1,0 size=2,2 material=wall emission=100cd/m2\n"
      "sensor c point position=0,0,0 normal=0,0,1\n"
      "sensor d point position=0.5,0.3,-0.2 normal=0.6,0,0.8\n"
      "render integrator=path depth=400 sensor_samples=262144\n";
  vr_render_result *r = render_text(scn, 2, 2);
  double want = M_PI * 100.0 / (1 - 0.8); /* E = pi L_e / (1 - a) */
  for (size_t i = 0; i < 2; i++) assert_true(r->readings[i].stderr_lx <= MAX_SE * want);
  double s0 = r->readings[0].stderr_lx, s1 = r->readings[1].stderr_lx;
  double m = 0.5 * (r->readings[0].illuminance_lx + r->readings[1].illuminance_lx);
  double se = 0.5 * sqrt(s0 * s0 + s1 * s1);
  print_message("    furnace: %.3f +- %.3f lx, expected %.3f\n", m, se, want);
  if (!(fabs(m - want) <= K_SE * se))
    fail_msg("furnace: mean of two points %.3f lx, expected %.3f within %.0f standard errors "
             "(%.3f lx)",
             m, want, K_SE, se);
  vr_render_result_destroy(r);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_cie171_table_formula),
      cmocka_unit_test(test_cie171_point_lambertian),
      cmocka_unit_test(test_inverse_square_cosine),
      cmocka_unit_test(test_cie171_cube_indirect),
      cmocka_unit_test(test_white_furnace),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
