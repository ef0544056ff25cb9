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
 *   points near the wall read up to 23 % high and the test fails (5 % plus
 *   3 standard errors of the difference is about 18 % there);
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

#include "daylit_room.h"
#include "render_test_util.h"

static vr_render_result *render_text(const char *text) { return render_text_with(text, 2, 2, true); }

static const char GROUND[] =
    "rect center=2,-4,0 normal=0,0,1 size=12,8 material=ground outside=yes\n";

/* Every photon reading within 5 % of the path reading of the same point,
 * beyond what the two estimates' noise explains: 3 standard errors of
 * their difference.  Both are Monte Carlo estimates of 8192 paths a point
 * (about 3 % standard error each where the room is dim), so a bare 5 %
 * would fail a point that is right by chance; 5 % is the bias allowed.
 * The noise is taken as the path reading's stderr_lx for both, sqrt(2)
 * se_path: a photon reading's stderr_lx also holds its bias estimate,
 * which grows exactly when the maps go wrong, so it must not widen the
 * bound (the photon estimate's own noise is below the path one's: its
 * paths end in the maps).  With the surface rule below switched off, floor
 * point (3, 0) reads 23 % high against an allowance of about 18 %. */
static void agree_within_5pct(const vr_render_result *ph, const vr_render_result *pa) {
  int bad = 0;
  for (size_t i = 0; i < ph->nreadings; i++) {
    const vr_sensor_reading *a = &ph->readings[i], *b = &pa->readings[i];
    double diff = a->illuminance_lx - b->illuminance_lx, dev = diff / b->illuminance_lx;
    double se = sqrt(2.0) * b->stderr_lx;
    print_message("  %-5s (%d, %d): photon %8.1f +- %6.1f lx, path %8.1f +- %6.1f lx, %+5.1f %%\n",
                  a->sensor, a->i, a->j, a->illuminance_lx, a->stderr_lx, b->illuminance_lx,
                  b->stderr_lx, 100 * dev);
    bad += fabs(diff) > 0.05 * b->illuminance_lx + 3 * se;
  }
  if (bad)
    fail_msg("%d of 23 points differ from the path estimator by more than 5 %% + 3 standard "
             "errors", bad);
}

static void compare_room(bool ground, double min_share) {
  char text[4096];
  snprintf(text, sizeof text, DAYLIT_ROOM, ground ? GROUND : "",
           "sensors=photon photons=2000000 knn=200 sensor_samples=8192");
  vr_render_result *ph = render_text(text);
  snprintf(text, sizeof text, DAYLIT_ROOM, ground ? GROUND : "", "sensors=path sensor_samples=8192");
  vr_render_result *pa = render_text(text);
  assert_int_equal(ph->nreadings, 23);
  assert_int_equal(pa->nreadings, 23);
  print_message("  %s ground plane: %.0f %% of the gather vertices read the photon maps\n",
                ground ? "with" : "without", 100 * ph->sensor_map_share);
  assert_true(ph->sensor_map_share >= min_share);
  agree_within_5pct(ph, pa);
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

/* Portals (portals.c): with the window declared a portal, the far sources
 * also emit their photons through it and their usual photons stop where
 * they would enter by it, so more photons land in the room and none is
 * counted twice.  Photon sensors must still agree with paths (paths with
 * the same portal: the portal's sky estimate is checked against analytic
 * daylight factors in test_daylight.c) within 5 % at every point, with the
 * outdoor ground lit (its light enters only through the usual photons),
 * and the maps must serve more of the gather vertices. */
static void daylit_room_portal(void **state) {
  (void)state;
  char text[4096], ground[512];
  snprintf(ground, sizeof ground, "%sportal center=2,0,1.5 normal=0,1,0 size=2,1.2\n", GROUND);
  snprintf(text, sizeof text, DAYLIT_ROOM, ground,
           "sensors=photon photons=2000000 knn=200 sensor_samples=8192 photon_portals=on");
  vr_render_result *ph = render_text(text);
  snprintf(text, sizeof text, DAYLIT_ROOM, ground, "sensors=path sensor_samples=8192");
  vr_render_result *pa = render_text(text);
  snprintf(text, sizeof text, DAYLIT_ROOM, GROUND,
           "sensors=photon photons=2000000 knn=200 sensor_samples=4096");
  vr_render_result *no = render_text(text);
  print_message("  gather vertices reading the maps: %.0f %% with the portal, %.0f %% without\n",
                100 * ph->sensor_map_share, 100 * no->sensor_map_share);
  assert_true(ph->sensor_map_share > no->sensor_map_share + 0.05);
  agree_within_5pct(ph, pa);
  vr_render_result_destroy(ph);
  vr_render_result_destroy(pa);
  vr_render_result_destroy(no);
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
      cmocka_unit_test(daylit_room_portal),
      cmocka_unit_test(cie171_cube_photon_sensors),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
