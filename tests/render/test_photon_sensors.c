/* Photon-mapped illuminance sensors (render sensors=photon) against the
 * path estimator and an analytic case.
 *
 * Where the expected values come from:
 * - the path estimator (sensors=path), the reference of the renderer, which
 *   agrees with the CIE 171:2006 cases (test_render_analytic.c) and with
 *   Radiance in daylit rooms; photon sensors must read the same light at
 *   every point within 5 % (issue 17's requirement) in the daylit room of
 *   the issue: 4 x 4 x 3 m, a window, sun and CIE clear sky, with and
 *   without an outdoor ground plane (with it, photons on the sunlit ground
 *   just outside the wall used to be gathered by floor points inside:
 *   back corners read 1975 lx against 211).  The ground here is 12 x 8 m,
 *   small enough that half the sensor paths end in the photon maps, so the
 *   test reads the maps' light; with the surface rule switched off, floor
 *   points near the wall read up to 23 % high and the test fails;
 * - CIE 171:2006 test case 5.8: in a cube of reflectance rho lit by a point
 *   source of flux Phi inside, the mean indirect illuminance on the walls
 *   is rho Phi / (S_T (1 - rho)) (an energy balance), 104.17 lx for the
 *   4 m cube, rho 0.5 and 10 000 lm;
 * - a point in mid-air (a work plane with no surface under it) has no
 *   photons of its own: it must read as with paths, not 5 times low. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "render_test_util.h"

static vr_render_result *render_text(const char *text) { return render_text_with(text, 2, 2, true); }

/* The room of issue 17: south wall y = 0 with a 2 x 1.2 m opening, floor
 * sensors on a 4 x 4 grid, north-wall sensors on 3 x 2, a mid-air point. */
static const char ROOM[] =
    "material wall lambert reflectance=0.5\n"
    "material floor lambert reflectance=0.3\n"
    "material ground lambert reflectance=0.2\n"
    "rect center=2,2,0   normal=0,0,1  size=4,4 material=floor\n"
    "rect center=2,2,3   normal=0,0,-1 size=4,4 material=wall\n"
    "rect center=2,4,1.5 normal=0,-1,0 size=4,3 material=wall\n"
    "rect center=0,2,1.5 normal=1,0,0  size=4,3 material=wall\n"
    "rect center=4,2,1.5 normal=-1,0,0 size=4,3 material=wall\n"
    "rect center=2,0,0.45 normal=0,1,0 size=4,0.9 material=wall\n"
    "rect center=2,0,2.55 normal=0,1,0 size=4,0.9 material=wall\n"
    "rect center=0.5,0,1.5 normal=0,1,0 size=1,1.2 material=wall\n"
    "rect center=3.5,0,1.5 normal=0,1,0 size=1,1.2 material=wall\n"
    "%s"
    "light sun altitude=35 azimuth=180 illuminance=80000lx spectrum=D65\n"
    "sky cie type=12 illuminance=15000lx spectrum=D65\n"
    "sensor floor grid origin=0.05,0.05,0.001 u=3.9,0,0 v=0,3.9,0 n=4,4 normal=0,0,1\n"
    "sensor wall grid origin=0.5,3.999,0.5 u=3,0,0 v=0,0,2 n=3,2 normal=0,-1,0\n"
    "sensor desk point position=3.2,3.1,0.8 normal=0,0,1\n"
    "render %s\n";

static const char GROUND[] = "rect center=2,-4,0 normal=0,0,1 size=12,8 material=ground\n";

static void compare_room(bool ground, double min_share) {
  char text[4096];
  snprintf(text, sizeof text, ROOM, ground ? GROUND : "",
           "sensors=photon photons=2000000 knn=200 sensor_samples=4096");
  vr_render_result *ph = render_text(text);
  snprintf(text, sizeof text, ROOM, ground ? GROUND : "", "sensors=path sensor_samples=4096");
  vr_render_result *pa = render_text(text);
  assert_int_equal(ph->nreadings, 23);
  assert_int_equal(pa->nreadings, 23);
  print_message("  %s ground plane: %.0f %% of the gather vertices read the photon maps\n",
                ground ? "with" : "without", 100 * ph->sensor_map_share);
  assert_true(ph->sensor_map_share >= min_share);
  int bad = 0;
  for (size_t i = 0; i < ph->nreadings; i++) {
    const vr_sensor_reading *a = &ph->readings[i], *b = &pa->readings[i];
    double dev = (a->illuminance_lx - b->illuminance_lx) / b->illuminance_lx;
    print_message("  %-5s (%d, %d): photon %8.1f +- %6.1f lx, path %8.1f +- %6.1f lx, %+5.1f %%\n",
                  a->sensor, a->i, a->j, a->illuminance_lx, a->stderr_lx, b->illuminance_lx,
                  b->stderr_lx, 100 * dev);
    bad += fabs(dev) > 0.05;
  }
  if (bad) fail_msg("%d of 23 points differ from the path estimator by more than 5 %%", bad);
  vr_render_result_destroy(ph);
  vr_render_result_destroy(pa);
}

/* With the ground plane: no floor point may read the ground's photons
 * through the wall. */
static void daylit_room_with_ground(void **state) {
  (void)state;
  compare_room(true, 0.4);
}

/* Without it the maps are dense in the room: most gather vertices end in
 * them, so this compares the photon maps' light itself. */
static void daylit_room_maps_dense(void **state) {
  (void)state;
  compare_room(false, 0.5);
}

/* CIE 171:2006 case 5.8 with photon sensors (see the file comment), the
 * cube as six rects, the floor read on an 8 x 8 grid less the analytic
 * direct part I cos / r^2. */
static void cie171_cube_photon_sensors(void **state) {
  (void)state;
  const char *scn =
      "material wall lambert reflectance=0.5\n"
      "rect center=0,0,0 normal=0,0,1 size=4,4 material=wall\n"
      "rect center=0,0,4 normal=0,0,-1 size=4,4 material=wall\n"
      "rect center=-2,0,2 normal=1,0,0 size=4,4 material=wall\n"
      "rect center=2,0,2 normal=-1,0,0 size=4,4 material=wall\n"
      "rect center=0,-2,2 normal=0,1,0 size=4,4 material=wall\n"
      "rect center=0,2,2 normal=0,-1,0 size=4,4 material=wall\n"
      "light point position=0,0,2 intensity=10000lm\n"
      "sensor floor grid origin=-2,-2,0 u=4,0,0 v=0,4,0 n=8,8 normal=0,0,1\n"
      "render sensors=photon photons=1000000 knn=200 depth=64 sensor_samples=1024\n";
  vr_render_result *r = render_text(scn);
  assert_int_equal(r->nreadings, 64);
  assert_true(r->sensor_map_share > 0.9);
  double indirect; /* CIE 171:2006 5.8: 104.17 lx */
  double mean = cie171_cube_indirect(r, 10000.0, 0.5, &indirect);
  print_message("  mean indirect %.2f lx, CIE 171 %.2f lx\n", mean, indirect);
  if (fabs(mean - indirect) > 0.02 * indirect)
    fail_msg("mean indirect illuminance %.2f lx, CIE 171 expects %.2f within 2 %%", mean, indirect);
  vr_render_result_destroy(r);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(daylit_room_with_ground),
      cmocka_unit_test(daylit_room_maps_dense),
      cmocka_unit_test(cie171_cube_photon_sensors),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
