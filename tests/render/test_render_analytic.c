/* The renderer against analytic answers, read through illuminance sensors:
 *   - CIE 171:2006 test case 5.2: a Lambertian point source of
 *     I(θ) = 1000 cos θ cd at 3 m above a black 4 x 4 m floor gives
 *     111.11 lx below it, 90.02 lx at (1, 0) and 49.39 lx at (1.5, 1.5);
 *   - an isotropic point source: E = I cos θ / r² (inverse-square and
 *     cosine laws) at several floor points, within 1 %;
 *   - CIE 171:2006 test case 5.8: a 4 m cube of uniform reflectance ρ with
 *     an isotropic 10000 lm source at its centre has a mean indirect
 *     illuminance of ρ Φ / (S_T (1 - ρ)) = 104.2 lx at ρ = 0.5 (within 2 %);
 *   - the white furnace: inside a closed box whose walls have albedo a
 *     and emit L_e, the radiance is L_e / (1 - a) everywhere, so a sensor
 *     reads E = π L_e / (1 - a) (within 1 %). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "render_test_util.h"

static vr_render_result *render_text(const char *text, int S, int P) {
  return render_text_with(text, S, P, false);
}

static void expect_lx(const vr_render_result *r, size_t i, double want, double rel) {
  double got = r->readings[i].illuminance_lx;
  if (fabs(got - want) > rel * want)
    fail_msg("sensor %zu: %.4f lx, expected %.4f (+-%.1f %%), stderr %.4f", i, got, want,
             rel * 100, r->readings[i].stderr_lx);
}

/* CIE 171:2006 section 5.2, Lambertian point source over a black floor. */
static void test_cie171_point_lambertian(void **state) {
  (void)state;
  const char *scn =
      "material black black\n"
      "rect center=0,0,0 normal=0,0,1 size=4,4 material=black\n"
      "light point position=0,0,3 intensity=1000cd distribution=lambertian normal=0,0,-1\n"
      "sensor a point position=0,0,0 normal=0,0,1\n"
      "sensor b point position=1,0,0 normal=0,0,1\n"
      "sensor c point position=1.5,1.5,0 normal=0,0,1\n"
      "render integrator=path sensor_samples=256\n";
  vr_render_result *r = render_text(scn, 1, 2);
  assert_int_equal(r->nreadings, 3);
  expect_lx(r, 0, 111.11, 0.02); /* CIE 171:2006 table 5.2 */
  expect_lx(r, 1, 90.02, 0.02);
  expect_lx(r, 2, 49.39, 0.02);
  vr_render_result_destroy(r);
}

/* E = I cos θ / r² for an isotropic 500 cd source 2 m up. */
static void test_inverse_square_cosine(void **state) {
  (void)state;
  const char *scn =
      "material black black\n"
      "rect center=0,0,0 normal=0,0,1 size=20,20 material=black\n"
      "light point position=0,0,2 intensity=500cd\n"
      "sensor a point position=0,0,0 normal=0,0,1\n"
      "sensor b point position=2,0,0 normal=0,0,1\n"
      "sensor c point position=3,4,0 normal=0,0,1\n"
      "sensor d point position=-5,1,0 normal=0,0,1\n"
      "render integrator=path sensor_samples=64\n";
  vr_render_result *r = render_text(scn, 1, 1);
  const double pts[4][2] = {{0, 0}, {2, 0}, {3, 4}, {-5, 1}};
  for (size_t i = 0; i < 4; i++) {
    double r2 = pts[i][0] * pts[i][0] + pts[i][1] * pts[i][1] + 4.0;
    expect_lx(r, i, 500.0 * (2.0 / sqrt(r2)) / r2, 0.01);
  }
  vr_render_result_destroy(r);
}

/* CIE 171:2006 section 5.8: indirect illuminance in a cube.  The formula
 * is an energy balance: every bounce returns the fraction rho of the flux,
 * so the indirect flux reaching the walls is rho Phi / (1 - rho) and its
 * mean over the area S_T is the expected value.  By symmetry each face has
 * that mean, so it is read as the mean over an 8 x 8 grid of sensors
 * covering the floor (cell centres), less the analytic direct part
 * I cos(theta) / r^2 at each point. */
static void test_cie171_cube_indirect(void **state) {
  (void)state;
  const char *scn =
      "material wall lambert reflectance=0.5\n"
      "box min=-2,-2,0 max=2,2,4 material=wall\n"
      "light point position=0,0,2 intensity=10000lm\n"
      "sensor floor grid origin=-2,-2,0 u=4,0,0 v=0,4,0 n=8,8 normal=0,0,1\n"
      "render integrator=path depth=64 sensor_samples=4096\n";
  vr_render_result *r = render_text(scn, 2, 2);
  assert_int_equal(r->nreadings, 64);
  double indirect; /* rho Phi / (S_T (1 - rho)) = 104.17 lx */
  double mean = cie171_cube_indirect(r, 10000.0, 0.5, &indirect);
  if (fabs(mean - indirect) > 0.02 * indirect)
    fail_msg("mean indirect illuminance %.2f lx, CIE 171 expects %.2f within 2 %%", mean, indirect);
  vr_render_result_destroy(r);
}

/* White furnace: walls of albedo 0.8 emitting 100 cd/m² inwards. */
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
  expect_lx(r, 0, want, 0.01);
  expect_lx(r, 1, want, 0.01);
  vr_render_result_destroy(r);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_cie171_point_lambertian),
      cmocka_unit_test(test_inverse_square_cosine),
      cmocka_unit_test(test_cie171_cube_indirect),
      cmocka_unit_test(test_white_furnace),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
