/* The fisheye camera (camera fisheye) and the vertical illuminance at its
 * lens.
 *
 * Where the expected values come from:
 * - the projections' definitions (vr/scene.h): equisolid r = sin(theta/2) /
 *   sin(theta_max/2), angular r = theta / theta_max; for a 180 degree
 *   circle the rim is theta = 90 degrees, half the radius is 2 asin(sin(45
 *   deg) / 2) = 41.41 degrees equisolid and 45 degrees angular;
 * - a uniform luminance L all round gives the illuminance pi L on any
 *   plane (the cosine integral over a hemisphere), 314.16 lx for 100 cd/m2:
 *   a fisheye image of an enclosure of emitting black walls must give it,
 *   whatever the projection;
 * - DGPs = 6.22e-5 E_v + 0.184 (Wienold, "Dynamic daylight glare
 *   evaluation", Building Simulation 2009). */
#include "vr_test.h"

#include "render_test_util.h"
#include "vr/fisheye.h"

static void expect_dir(const double *d, double x, double y, double z, double tol) {
  assert_near(d[0], x, tol);
  assert_near(d[1], y, tol);
  assert_near(d[2], z, tol);
}

static void projections(void **state) {
  (void)state;
  vr_scene_camera c = {.model = VR_CAM_FISHEYE, .fov_deg = 180, .width = 200, .height = 100};
  double d[3];
  for (int p = 0; p < 2; p++) {
    c.projection = p ? VR_FISHEYE_ANGULAR : VR_FISHEYE_EQUISOLID;
    /* The circle: centre (100, 50), radius 50. */
    assert_true(vr_fisheye_direction(&c, 100, 50, d));
    expect_dir(d, 0, 0, 1, 1e-15);
    assert_true(vr_fisheye_direction(&c, 150, 50, d)); /* the rim, to the right */
    expect_dir(d, 1, 0, 0, 1e-12);
    assert_true(vr_fisheye_direction(&c, 100, 25, d)); /* half way up */
    double want = p ? 45.0 : 2 * asin(sin(M_PI / 4) / 2) * 180 / M_PI;
    assert_near(acos(d[2]) * 180 / M_PI, want, 1e-9);
    assert_true(d[1] > 0 && fabs(d[0]) < 1e-15);
    assert_false(vr_fisheye_direction(&c, 160, 50, d)); /* outside the circle */
    assert_false(vr_fisheye_direction(&c, 5, 5, d));
  }
}

static void uniform_surround(void **state) {
  (void)state;
  for (int p = 0; p < 2; p++) {
    char scn[2048];
    snprintf(scn, sizeof scn,
             "material black lambert reflectance=0\n"
             "rect center=0,0,-1 normal=0,0,1 size=2,2 material=black emission=100cd/m2\n"
             "rect center=0,0,1 normal=0,0,-1 size=2,2 material=black emission=100cd/m2\n"
             "rect center=-1,0,0 normal=1,0,0 size=2,2 material=black emission=100cd/m2\n"
             "rect center=1,0,0 normal=-1,0,0 size=2,2 material=black emission=100cd/m2\n"
             "rect center=0,-1,0 normal=0,1,0 size=2,2 material=black emission=100cd/m2\n"
             "rect center=0,1,0 normal=0,-1,0 size=2,2 material=black emission=100cd/m2\n"
             "camera fisheye from=0,0,0 to=0,1,0 resolution=96x96 projection=%s\n"
             "render integrator=path spp=16\n",
             p ? "angular" : "equisolid");
    vr_render_result *r = render_text_with(scn, 1, 2, false);
    double ev = r->eye_illuminance_lx;
    print_message("  %s: E_v %.3f lx (pi L = %.3f), DGPs %.4f\n", p ? "angular  " : "equisolid", ev,
                  100 * M_PI, vr_dgps(ev));
    assert_near(ev, 100 * M_PI, 0.002 * 100 * M_PI);
    /* A corner of the picture is outside the circle: black. */
    assert_true(r->xyz[1] == 0.0);
    vr_render_result_destroy(r);
  }
  assert_near(vr_dgps(1000), 0.2462, 1e-12); /* 6.22e-5 x 1000 + 0.184 */
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(projections),
      cmocka_unit_test(uniform_surround),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
