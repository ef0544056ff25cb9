/* Photon sensors and the sky's ground (issue 18): light the ground below
 * the horizon reflects must reach the photon maps as it reaches paths.
 *
 * The issue: in a bare daylit room (a window, no outdoor ground geometry)
 * photon sensors read the same with the sky's ground=0 and ground=0.2,
 * ceilings 21-35 % too dark and a reading of 2657 lx where paths read
 * 3944 lx, unchanged at 8 M photons: the ground glow was missing from the
 * photon maps.  It is emitted now (lights.c, the ground glow branches of
 * vr_light_emit_photon and vr_light_emit_portal_photon, stored in the
 * global map by photons.c); this test keeps it so.
 *
 * Where the expected values come from: the path estimator (sensors=path),
 * the renderer's reference, checked against CIE 171:2006 test cases 5.2
 * and 5.8 (test_render_analytic.c) and, for the sky's ground seen through
 * a window, against configuration factors (Howell's catalogue, case B-3:
 * ERC = 100 rho F, test_daylight.c).  Photon sensors end the same paths
 * (same seed, same sample count) in the maps at their first diffuse
 * vertex, so the two differ only by what the maps hold, and the change
 * from ground=0 to ground=0.2 is read with the noise of both renders
 * largely cancelled.
 *
 * The room of issue 17 (daylit_room.h's shell: 4 x 4 x 3 m, a 2 x 1.2 m
 * window in the south wall, sun at 35 degrees in the south, CIE clear
 * sky 15 000 lx) with no outdoor ground: sensors on the shaded floor in
 * the back corners, on the ceiling looking down (it sees no sky, only the ground
 * through the window and the room) and on a shaded work plane in mid-air
 * (0.8 m).  Measured while writing this (2 M photons, 4096 paths a point):
 * ceiling points 2027-2409 lx with ground=0 and 2840-3108 lx with
 * ground=0.2, within 2.7 % of paths at every point; with the ground glow's
 * photons removed, the work plane rose by 29 lx from ground=0 to 0.2
 * where paths rise by 252 lx.  The test runs smaller maps (they must stay
 * cheap under AddressSanitizer) and checks both ways of emitting photons:
 * from the scene's bounding disc, and through the window as a portal. */
#include "vr_test.h"

#include "daylit_room.h"
#include "render_test_util.h"

#define NPOINTS 8

/* The sensors: the shaded floor's back corners, the ceiling (which sees
 * no sky) and a shaded work plane. */
#define POINTS                                                                                     \
  "sensor floorW point position=0.5,3.5,0.001 normal=0,0,1\n"                                     \
  "sensor floorE point position=3.5,3.5,0.001 normal=0,0,1\n"                                     \
  "sensor ceiling grid origin=1,1,2.999 u=2,0,0 v=0,2,0 n=2,2 normal=0,0,-1\n"                    \
  "sensor workW point position=1,3,0.8 normal=0,0,1\n"                                            \
  "sensor workE point position=3,3,0.8 normal=0,0,1\n"

/* A printf format: the sky's ground reflectance, then portal lines (or
 * ""), then the render options. */
static const char ROOM[] =
    DAYLIT_ROOM_SHELL
    "light sun altitude=35 azimuth=180 illuminance=80000lx spectrum=D65\n"
    "sky cie type=12 illuminance=15000lx spectrum=D65 ground=%s\n"
    POINTS
    "%s"
    "render sampler=independent %s\n"; /* the tolerances were set on independent samples */

/* The same room on an outdoor ground of 60 x 56 m (outside=yes) of
 * reflectance %s under a sky with no ground of its own: what the ground
 * reflects into the room comes from the ground's geometry.  With portals,
 * a photon the ground scatters is aimed at the window half the time
 * (photon_trace.c, outside_portal_scatter), weighted by the mixture's
 * density; a wrong weight there is a bias in the ground's gain. */
static const char OUTDOOR[] =
    DAYLIT_ROOM_SHELL
    "material ground lambert reflectance=%s\n"
    "rect center=2,-28,0 normal=0,0,1 size=60,56 material=ground outside=yes\n"
    "light sun altitude=35 azimuth=180 illuminance=80000lx spectrum=D65\n"
    "sky cie type=12 illuminance=15000lx spectrum=D65 ground=0\n"
    POINTS
    "%s"
    "render sampler=independent %s\n";

static const char PORTAL[] = "portal center=2,0,1.5 normal=0,1,0 size=2,1.2\n";

typedef struct readings {
  double lx[NPOINTS], se[NPOINTS], share;
} readings;

static readings render_room(const char *room, const char *ground, bool portal,
                            const char *options) {
  char text[4096];
  snprintf(text, sizeof text, room, ground, portal ? PORTAL : "", options);
  vr_render_result *r = render_text_with(text, 1, 2, true);
  assert_int_equal(r->nreadings, NPOINTS);
  readings out = {.share = r->sensor_map_share};
  for (size_t i = 0; i < NPOINTS; i++) {
    out.lx[i] = r->readings[i].illuminance_lx;
    out.se[i] = r->readings[i].stderr_lx;
  }
  vr_render_result_destroy(r);
  return out;
}

static const char *const NAMES[NPOINTS] = {"floor W",      "floor E",      "ceiling 1,1",
                                           "ceiling 3,1",  "ceiling 1,3",  "ceiling 3,3",
                                           "work plane W", "work plane E"};

/* Photon and path readings with ground=0 and ground=0.2 over K seeds,
 * and the checks:
 *   - the maps serve the gathers (else paths would do the work and the
 *     test would read nothing of the maps);
 *   - every point's photon reading against its path reading, and the
 *     ground's gain, photon(0.2) - photon(0) against path(0.2) - path(0),
 *     summed over each group of points (floor, ceiling, work plane); and
 *     the gain is large for paths (the ceiling gains over a quarter, the
 *     others over 4 %).
 *
 * The bounds.  A run's stderr_lx leaves out the noise of the photon maps,
 * which every gather of the run shares, and the two renders of a gain
 * share their seed, so neither a run's standard errors nor the
 * independent sum of them describes a difference.  The seeds do: each of
 * the K = 12 seeds gives one photon-minus-path difference D_k, and their
 * mean is held to T = 7 of its standard error s_D / sqrt(K) (Student's t,
 * 11 degrees of freedom: 2.3e-5 two-sided, 19 checks a case) plus
 * B = 5 % of the path value.  B is issue 17's accuracy for photon
 * sensors: the maps' density estimate is biased (it smooths the
 * irradiance over each gather's disc, issue 33), and this test asks that
 * the ground's light is in the maps, not that the maps are unbiased.
 * With the ground glow's photons dropped (issue 18's state; checked
 * by making vr_lights_ground_power return 0) the bounding-disc case fails
 * all three gain checks: the floor gained 0.6 lx against the paths' 291,
 * the work plane 2 lx against 497, the ceiling 2453 lx against 2946. */
enum { K = 12 };
static const double T = 7.0, B = 0.05;

typedef struct diff_stats {
  seed_stats d, pa; /* over seeds: D_k, and the path value */
} diff_stats;

static void add(diff_stats *s, double photon, double path) {
  seed_add(&s->d, photon - path), seed_add(&s->pa, path);
}

/* 0 when the mean difference is within T standard errors plus B of the
 * path value, else 1; prints the line. */
static int check(const char *what, const diff_stats *s) {
  double d = seed_mean(&s->d), pa = seed_mean(&s->pa), se = seed_stderr(&s->d);
  double bound = T * se + B * fabs(pa);
  print_message("  %-26s photon - path %+7.1f lx (path %7.1f; seeds' stderr %5.1f, bound %5.1f)%s\n",
                what, d, pa, se, bound, fabs(d) > bound ? "  FAILS" : "");
  return fabs(d) > bound;
}

static void compare(const char *room, bool portal, const char *photon_opts,
                    const char *path_opts) {
  diff_stats level[2][NPOINTS], gain[3];
  memset(level, 0, sizeof level), memset(gain, 0, sizeof gain);
  double gain_pa[3] = {0}, level_pa[3] = {0}, share = 1;
  for (int k = 0; k < K; k++) {
    char ph[512], pa[512];
    snprintf(ph, sizeof ph, "%s seed=%d", photon_opts, k + 1);
    snprintf(pa, sizeof pa, "%s seed=%d", path_opts, k + 1);
    readings ph0 = render_room(room, "0", portal, ph), ph2 = render_room(room, "0.2", portal, ph);
    readings pa0 = render_room(room, "0", portal, pa), pa2 = render_room(room, "0.2", portal, pa);
    share = fmin(share, fmin(ph0.share, ph2.share));
    double gp[3] = {0}, ga[3] = {0};
    for (int i = 0; i < NPOINTS; i++) {
      add(&level[0][i], ph0.lx[i], pa0.lx[i]);
      add(&level[1][i], ph2.lx[i], pa2.lx[i]);
      int g = i < 2 ? 0 : i < 6 ? 1 : 2; /* floor, ceiling, work plane */
      gp[g] += ph2.lx[i] - ph0.lx[i];
      ga[g] += pa2.lx[i] - pa0.lx[i];
      level_pa[g] += pa0.lx[i] / K;
    }
    for (int g = 0; g < 3; g++) add(&gain[g], gp[g], ga[g]), gain_pa[g] += ga[g] / K;
  }
  print_message("  %s: at least %.0f %% of the gather vertices read the maps; %d seeds\n",
                portal ? "window as a portal" : "no portal", 100 * share, K);
  assert_true(share >= 0.85);
  int bad = 0;
  char what[64];
  for (int i = 0; i < NPOINTS; i++)
    for (int j = 0; j < 2; j++) {
      snprintf(what, sizeof what, "%s, ground %s", NAMES[i], j ? "0.2" : "0");
      bad += check(what, &level[j][i]);
    }
  static const char *const GROUP[3] = {"shaded floor", "ceiling", "work plane"};
  static const double MIN_GAIN[3] = {0.04, 0.25, 0.04};
  for (int g = 0; g < 3; g++) {
    snprintf(what, sizeof what, "%s, the ground's gain", GROUP[g]);
    bad += check(what, &gain[g]);
    if (!(gain_pa[g] > MIN_GAIN[g] * level_pa[g]))
      fail_msg("%s: ground=0.2 adds only %.1f lx to the path readings' %.1f lx", GROUP[g],
               gain_pa[g], level_pa[g]);
  }
  if (bad)
    fail_msg("%d photon readings or gains differ from the path estimator's by more than %.0f "
             "standard errors of %d seeds plus %.0f %%", bad, T, K, 100 * B);
}

/* The case: photons from the scene's bounding disc. */
static void ground_glow_no_portal(void **state) {
  (void)state;
  compare(ROOM, false, "sensors=photon photons=1000000 knn=50 sensor_samples=1024",
          "sensors=path sensor_samples=1024");
}

/* The window declared a portal: the far sources, the ground glow among
 * them, also emit through it (portals.c). */
static void ground_glow_portal(void **state) {
  (void)state;
  compare(ROOM, true, "sensors=photon photons=200000 knn=50 sensor_samples=2048 photon_portals=on",
          "sensors=path sensor_samples=2048");
}

/* The outdoor ground's reflected light through the portal (OUTDOOR). */
static void outdoor_ground_portal(void **state) {
  (void)state;
  compare(OUTDOOR, true,
          "sensors=photon photons=200000 knn=50 sensor_samples=2048 photon_portals=on",
          "sensors=path sensor_samples=2048");
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(ground_glow_no_portal),
      cmocka_unit_test(ground_glow_portal),
      cmocka_unit_test(outdoor_ground_portal),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
