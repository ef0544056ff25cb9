/* Daylight factor and its split-flux components (sensor table columns
 * sky_component_lx ... df_internally_reflected_pct) against analytic
 * values.
 *
 * Under a sky of uniform luminance L (CIE standard general sky type 5,
 * ISO 15469:2004: gradation and indicatrix both 1), the unobstructed
 * horizontal illuminance is E_h = pi L, and the illuminance an opening
 * gives a point is L pi F = E_h F, F the configuration factor from the
 * point's plane to the opening.  For a plane element parallel to an a x b
 * rectangle at distance c, its normal through a corner:
 *   F = 1/(2 pi) [X/sqrt(1+X^2) atan(Y/sqrt(1+X^2)) + Y/sqrt(1+Y^2) atan(X/sqrt(1+Y^2))],
 * X = a/c, Y = b/c (J. R. Howell, A Catalog of Radiation Heat Transfer
 * Configuration Factors, case B-3; checked here against a numerical
 * integration of cos cos / (pi r^2), 0.1223597 for 2 x 1 at 1.5).  The
 * sky's ground below the horizon (reflectance rho) has luminance
 * rho E_h / pi with no sun, so what an opening shows of it gives rho E_h F.
 * With black interior surfaces nothing is internally reflected, so
 *   DF = SC + ERC, SC = 100 F(sky part), ERC = 100 rho F(ground part). */
#include "vr_test.h"

#include "render_test_util.h"

static double corner_factor(double a, double b, double c) {
  double X = a / c, Y = b / c, sx = sqrt(1 + X * X), sy = sqrt(1 + Y * Y);
  return (X / sx * atan(Y / sx) + Y / sy * atan(X / sy)) / (2 * M_PI);
}

static void expect_pct(const char *what, double got, double want, double tol) {
  print_message("  %-28s %8.4f %%  (analytic %.4f %%)\n", what, got, want);
  if (!(fabs(got - want) <= tol)) fail_msg("%s: %.4f %%, expected %.4f +- %.3f", what, got, want, tol);
}

/* The black room 4 x 4 x 3 m with a 2 x 1 m opening in the roof (x 0..2,
 * y 0..1 at z = 3); a printf format: the first %s takes portal lines, the
 * second the sensor's position. */
static const char ROOF_ROOM[] =
    "material black lambert reflectance=0\n"
    "rect center=0,0,0 normal=0,0,1 size=4,4 material=black\n"
    "rect center=-2,0,1.5 normal=1,0,0 size=4,3 material=black\n"
    "rect center=2,0,1.5 normal=-1,0,0 size=4,3 material=black\n"
    "rect center=0,-2,1.5 normal=0,1,0 size=4,3 material=black\n"
    "rect center=0,2,1.5 normal=0,-1,0 size=4,3 material=black\n"
    "rect center=-1,0,3 normal=0,0,-1 size=2,4 material=black\n"
    "rect center=1,-1,3 normal=0,0,-1 size=2,2 material=black\n"
    "rect center=1,1.5,3 normal=0,0,-1 size=2,1 material=black\n"
    "%s"
    "sky cie type=5 illuminance=10000lx spectrum=D65\n"
    "sensor p point position=%s normal=0,0,1\n"
    "render sensors=path sensor_samples=%s\n";

/* A black room 4 x 4 x 3 m with a 2 x 1 m opening in the roof; the sensor
 * on the floor under the opening's corner: DF = SC = 100 F(2, 1, 3) =
 * 5.2268 %; no ground is seen, so ERC = 0; nothing reflects, IRC = 0. */
static void roof_opening(void **state) {
  (void)state;
  char scn[2048];
  snprintf(scn, sizeof scn, ROOF_ROOM, "", "0,0,0.0001", "262144");
  vr_render_result *r = render_text_with(scn, 2, 2, true);
  const vr_sensor_reading *p = &r->readings[0];
  double want = 100 * corner_factor(2, 1, 3);
  assert_near(r->sky_horizontal_lx, 10000, 10);
  expect_pct("daylight factor", p->df_pct, want, 0.02 * want);
  expect_pct("sky component", p->df_sc_pct, want, 0.02 * want);
  expect_pct("externally reflected", p->df_erc_pct, 0, 1e-9);
  expect_pct("internally reflected", p->df_irc_pct, 0, 1e-9);
  /* The parts add up to the reading. */
  double sum = 0;
  for (int q = 0; q < VR_SENSOR_PARTS; q++) sum += p->part_lx[q];
  assert_near(sum, p->illuminance_lx, 1e-9 * p->illuminance_lx);
  vr_render_result_destroy(r);
}

/* Sky portals (portals.c) aim the sky's next-event estimation through the
 * openings; the estimate must keep the analytic daylight factor of
 * roof_opening whether the portal covers the opening, half of it (the
 * sky's own share of the samples finds the rest) or a wall where no light
 * enters, and covering the opening must cut the noise.  Same room, a
 * sensor in the roof room 1.5 m from the opening, under its middle. */
static void portals_keep_the_answer(void **state) {
  (void)state;
  /* The opening is x 0..2, y 0..1 at z = 3; the sensor at (1, -1.5): F is
   * the difference of two corner factors along y (1.5 + 1 and 1.5 deep),
   * twice over (x from 0 to 1 and 1 to 2). */
  double want = 100 * 2 * (corner_factor(1, 2.5, 3) - corner_factor(1, 1.5, 3));
  const char *portals[] = {"", "portal center=1,0.5,3 normal=0,0,-1 size=2,1\n",
                           "portal center=0.5,0.5,3 normal=0,0,1 size=1,1\n",
                           "portal center=0,2,1.5 normal=0,-1,0 size=2,2\n"};
  const char *what[] = {"no portal", "portal over the opening", "portal over half of it",
                        "portal on a wall"};
  double err[4];
  for (int i = 0; i < 4; i++) {
    char scn[2048];
    snprintf(scn, sizeof scn, ROOF_ROOM, portals[i], "1,-1.5,0.0001", "65536");
    vr_render_result *r = render_text_with(scn, 1, 2, true);
    const vr_sensor_reading *p = &r->readings[0];
    double sd = 100 * p->stderr_lx / r->sky_horizontal_lx;
    print_message("  %-24s DF %.4f %% +- %.4f (analytic %.4f %%)\n", what[i], p->df_pct, sd, want);
    if (!(fabs(p->df_pct - want) <= fmax(4 * sd, 0.002 * want)))
      fail_msg("%s: DF %.4f %%, analytic %.4f %%, stated error %.4f", what[i], p->df_pct, want, sd);
    err[i] = sd;
    vr_render_result_destroy(r);
  }
  /* Aimed through the opening, 9 samples in 10 find the sky. */
  assert_true(err[1] < 0.5 * err[0]);
}

/* A 4 x 4 x 3 m room (y 0..4) whose wall y = 0 has a 2 x 2 m window,
 * x -1..1, z 0.5..2.5, every surface of material m (a string literal). */
#define FACADE_ROOM(m)                                                                             \
  "rect center=0,2,0 normal=0,0,1 size=4,4 material=" m "\n"                                       \
  "rect center=0,2,3 normal=0,0,-1 size=4,4 material=" m "\n"                                      \
  "rect center=-2,2,1.5 normal=1,0,0 size=4,3 material=" m "\n"                                    \
  "rect center=2,2,1.5 normal=-1,0,0 size=4,3 material=" m "\n"                                    \
  "rect center=0,4,1.5 normal=0,-1,0 size=4,3 material=" m "\n"                                    \
  "rect center=0,0,0.25 normal=0,1,0 size=4,0.5 material=" m "\n"                                  \
  "rect center=0,0,2.75 normal=0,1,0 size=4,0.5 material=" m "\n"                                  \
  "rect center=-1.5,0,1.5 normal=0,1,0 size=1,2 material=" m "\n"                                  \
  "rect center=1.5,0,1.5 normal=0,1,0 size=1,2 material=" m "\n"

/* A 2 x 2 m window in the wall y = 0, z 0.5 to 2.5; a vertical sensor
 * 1 m in front of its centre at z = 1.5, facing it.  The window's upper
 * half shows sky, its lower half the ground (rho 0.2): SC = 100 F_u,
 * ERC = 100 rho F_l, with F_u = F_l = 2 F(1, 1, 1) = 0.27706.  Then the
 * room's walls made grey: the sky component does not change, an internally
 * reflected component appears. */
static void facade_window(void **state) {
  (void)state;
  char scn[2048];
  const char *fmt =
      "material inside lambert reflectance=%s\n"
      FACADE_ROOM("inside")
      "sky cie type=5 illuminance=10000lx spectrum=D65 ground=0.2\n"
      "sensor p point position=0,1,1.5 normal=0,-1,0\n"
      "render sensors=path sensor_samples=65536 depth=16\n";
  double F = 2 * corner_factor(1, 1, 1);
  snprintf(scn, sizeof scn, fmt, "0");
  vr_render_result *r = render_text_with(scn, 2, 2, true);
  const vr_sensor_reading *p = &r->readings[0];
  expect_pct("sky component (black room)", p->df_sc_pct, 100 * F, 0.02 * 100 * F);
  expect_pct("externally reflected", p->df_erc_pct, 100 * 0.2 * F, 0.03 * 100 * 0.2 * F);
  expect_pct("internally reflected", p->df_irc_pct, 0, 1e-9);
  expect_pct("daylight factor", p->df_pct, 100 * 1.2 * F, 0.02 * 100 * 1.2 * F);
  double sc_black = p->df_sc_pct;
  vr_render_result_destroy(r);
  snprintf(scn, sizeof scn, fmt, "0.5");
  r = render_text_with(scn, 2, 2, true);
  p = &r->readings[0];
  expect_pct("sky component (grey room)", p->df_sc_pct, sc_black, 1e-9);
  print_message("  internally reflected (grey room) %.3f %%\n", p->df_irc_pct);
  assert_true(p->df_irc_pct > 1.0);
  vr_render_result_destroy(r);
}

/* A portal over a facade window seen from above its sill: the sky gives
 * nothing below the horizon, so the portal is sampled only above the
 * sensor's level (portals.c, above_part), its density divided by that
 * part's share.  The facade_window room, black, the sky's ground black
 * (ground=0), the sensor 1 m in front of the window's middle, facing it, at
 * three heights: the sky component is then the window's part above the
 * sensor, 100 x 2 F(1, 2.5 - z, 1), and 0 from above the window's head.  A
 * density that left out the share would read high by 1/share (2 at
 * z = 1.5, 10 at 2.3). */
static void portal_above_the_horizon(void **state) {
  (void)state;
  const char *fmt =
      "material black lambert reflectance=0\n"
      FACADE_ROOM("black")
      "portal center=0,0,1.5 normal=0,1,0 size=2,2\n"
      "sky cie type=5 illuminance=10000lx spectrum=D65 ground=0\n"
      "sensor p point position=0,1,%.2f normal=0,-1,0\n"
      "render sensors=path sensor_samples=16384 depth=1\n";
  const double heights[3] = {1.5, 2.3, 2.6};
  for (int i = 0; i < 3; i++) {
    char scn[2048];
    double z = heights[i];
    snprintf(scn, sizeof scn, fmt, z);
    vr_render_result *r = render_text_with(scn, 1, 2, true);
    const vr_sensor_reading *p = &r->readings[0];
    double want = z < 2.5 ? 100 * 2 * corner_factor(1, 2.5 - z, 1) : 0;
    double sd = 100 * p->stderr_lx / r->sky_horizontal_lx;
    print_message("  sensor at z = %.1f m: SC %.4f %% +- %.4f (analytic %.4f %%)\n", z,
                  p->df_sc_pct, sd, want);
    /* 4 standard errors of 16 batches, or 0.2 % of the value: the
     * estimate's noise, with room for the stated error's own scatter. */
    if (!(fabs(p->df_sc_pct - want) <= fmax(4 * sd, 0.002 * want)))
      fail_msg("z = %.1f: SC %.4f %%, analytic %.4f %%, stated error %.4f", z, p->df_sc_pct, want,
               sd);
    vr_render_result_destroy(r);
  }
}

/* An exterior surface marked outside=yes: the light it reflects is
 * externally reflected, and sunlight is kept apart from sky light.  The
 * window of facade_window, black inside, a white ground (0.8) outside,
 * 2 km wide so that only rays within 0.1 deg of the horizon pass it, the
 * sky's own ground hidden (ground=0).  Sun only (50 000 lx at 40 deg in the
 * south, shining in): direct sun on the sensor E cos 40 = 38 302 lx; the
 * sunlit ground, luminance 0.8 E sin 40 / pi, through the window's lower
 * half: 0.8 E sin 40 F_l = 7 124 lx; no sky parts.  Sky only: no sun
 * parts, and the sky component E_h F_u of facade_window. */
static const char OUTSIDE[] =
    "material black lambert reflectance=0\n"
    "material white lambert reflectance=0.8\n"
    FACADE_ROOM("black")
    "rect center=0,-1000,0 normal=0,0,1 size=2000,2000 material=white outside=yes\n"
    "%s"
    "sensor p point position=0,1,1.5 normal=0,-1,0\n"
    "render sensors=path sensor_samples=65536 depth=16\n";

static void outside_surfaces_and_sun(void **state) {
  (void)state;
  char scn[2048];
  snprintf(scn, sizeof scn, OUTSIDE,
           "light sun altitude=40 azimuth=180 illuminance=50000lx spectrum=D65 radius=0\n");
  vr_render_result *r = render_text_with(scn, 2, 2, true);
  const vr_sensor_reading *p = &r->readings[0];
  double s40 = sin(40 * M_PI / 180), c40 = cos(40 * M_PI / 180), F = 2 * corner_factor(1, 1, 1);
  print_message("  sun only: direct %.0f lx (analytic %.0f), ground %.0f lx (analytic %.0f)\n",
                p->part_lx[VR_PART_SUN], 50000 * c40, p->part_lx[VR_PART_ERC_SUN],
                0.8 * 50000 * s40 * F);
  assert_near(p->part_lx[VR_PART_SUN], 50000 * c40, 1e-5 * 50000);
  assert_near(p->part_lx[VR_PART_ERC_SUN], 0.8 * 50000 * s40 * F, 0.04 * 0.8 * 50000 * s40 * F);
  assert_true(p->part_lx[VR_PART_SKY] == 0.0 && p->part_lx[VR_PART_ERC_SKY] == 0.0);
  assert_true(p->part_lx[VR_PART_IRC_SKY] == 0.0 && p->part_lx[VR_PART_IRC_SUN] == 0.0);
  assert_true(isnan(p->df_pct)); /* no sky: no daylight factor */
  vr_render_result_destroy(r);

  snprintf(scn, sizeof scn, OUTSIDE, "sky cie type=5 illuminance=10000lx spectrum=D65 ground=0\n");
  r = render_text_with(scn, 2, 2, true);
  p = &r->readings[0];
  print_message("  sky only: SC %.0f lx (analytic %.0f), ground %.0f lx\n",
                p->part_lx[VR_PART_SKY], 10000 * F, p->part_lx[VR_PART_ERC_SKY]);
  assert_near(p->part_lx[VR_PART_SKY], 10000 * F, 0.02 * 10000 * F);
  assert_true(p->part_lx[VR_PART_SUN] == 0.0 && p->part_lx[VR_PART_ERC_SUN] == 0.0);
  assert_true(p->part_lx[VR_PART_SKY] > 0 && p->part_lx[VR_PART_ERC_SKY] > 0);
  vr_render_result_destroy(r);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(roof_opening),
      cmocka_unit_test(portals_keep_the_answer),
      cmocka_unit_test(portal_above_the_horizon),
      cmocka_unit_test(facade_window),
      cmocka_unit_test(outside_surfaces_and_sun),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
