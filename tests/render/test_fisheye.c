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
 *   evaluation", Building Simulation 2009), and its low-light factor;
 * - DGP = 5.87e-5 E_v + 9.18e-2 log10(1 + sum L^2 w / (E_v^1.87 P^2)) +
 *   0.16 (Wienold & Christoffersen, Energy and Buildings 38, 2006), with
 *   Guth's position index (IES Lighting Handbook) and Iwata's below the
 *   line of sight, worked by hand in the comments. */
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

/* The sun's disc in view: a camera sees it (its radiance the normal
 * illuminance over the disc's solid angle 2 pi (1 - cos r)), so the image
 * of a sun of normal illuminance E_n, apparent radius r, theta0 from the
 * line of sight, over a black ground and no sky, gives at the lens
 *   E_v = E_n cos(theta0) (1 + cos r) / 2
 * (the mean of the direction over a spherical cap of half-angle r is its
 * axis times (1 + cos r) / 2).  A large disc (r = 10 deg) keeps the pixels
 * its rim cuts few beside those it covers. */
static void sun_disc_in_view(void **state) {
  (void)state;
  const double En = 10000, r = 10, theta0 = 40;
  for (int p = 0; p < 2; p++) {
    char scn[1024];
    snprintf(scn, sizeof scn,
             "material black lambert reflectance=0\n"
             "rect center=0,0,-1 normal=0,0,1 size=20,20 material=black\n"
             "light sun altitude=%g azimuth=180 illuminance=%glx radius=%g spectrum=D65\n"
             "camera fisheye from=0,0,0 to=0,-1,0 resolution=128x128 projection=%s\n"
             "render integrator=path spp=64\n",
             theta0, En, r, p ? "angular" : "equisolid");
    vr_render_result *res = render_text_with(scn, 1, 2, false);
    double want = En * cos(theta0 * M_PI / 180) * (1 + cos(r * M_PI / 180)) / 2;
    /* The noise is the rim's: each pixel it cuts holds a share f of the
     * disc estimated from n = 64 samples, variance at most 1 / (4 n) of
     * its full value L w cos.  With w about (pi / 128)^2 sr (180 degrees
     * over 128 pixels), at most 2 pi r / (180 / 128) x 2 = 90 pixels on
     * the rim, the disc's w = 2 pi (1 - cos r): sigma / E_v <= (w_px /
     * w_disc) sqrt(90 / (4 x 64)) = 0.0052 (independent samples; the
     * sampler stratifies, so less).  Bound: 4 sigma. */
    double wpx = pow(M_PI / 128, 2), wdisc = 2 * M_PI * (1 - cos(r * M_PI / 180));
    double sigma = wpx / wdisc * sqrt(90.0 / (4 * 64));
    print_message("  %s: E_v %.2f lx, expected %.2f (%+.3f %%, bound %.2f %%)\n",
                  p ? "angular  " : "equisolid", res->eye_illuminance_lx, want,
                  100 * (res->eye_illuminance_lx / want - 1), 400 * sigma);
    assert_near(res->eye_illuminance_lx, want, 4 * sigma * want);
    vr_render_result_destroy(res);
  }
}

static void position_index(void **state) {
  (void)state;
  /* On the line of sight P = 1.  30 deg straight above it (tau = 0):
   * ln P = (35.2 - 1.22) 1e-3 * 30 + 21e-5 * 900 = 1.20840, P = 3.34812
   * (Guth's formula, IES Lighting Handbook).  Below it, Iwata & Osterhaus
   * (CIE 2010) as evalglare 3 converts it (its get_posindex): beta =
   * atan(tan sigma sqrt(1 + 0.3225 cos^2 tau)), ln P = 6.49e-3 beta +
   * 21e-5 beta^2.  20 deg straight below (cos^2 tau = 1): tan beta =
   * 0.36397 x 1.15 = 0.41857, beta = 22.7125 deg, P = 1.29141; 40 deg
   * below: tan beta = 0.96497, beta = 43.9785 deg, P = 1.99688.  89 deg to the
   * side (tau = 90): ln P = (35.2 - 28.7001) 1e-3 * 89 + (21 + 24.0003 -
   * 24.0003) 1e-5 * 7921 = 2.24194, P = 9.4112.  Behind the eye: 16. */
  double ahead[3] = {0, 0, 1};
  assert_near(vr_guth_position_index(ahead), 1.0, 1e-12);
  double up30[3] = {0, sin(30 * M_PI / 180), cos(30 * M_PI / 180)};
  assert_near(vr_guth_position_index(up30), 3.34812, 1e-4);
  double down20[3] = {0, -sin(20 * M_PI / 180), cos(20 * M_PI / 180)};
  assert_near(vr_guth_position_index(down20), 1.29141, 1e-4);
  double down40[3] = {0, -sin(40 * M_PI / 180), cos(40 * M_PI / 180)};
  assert_near(vr_guth_position_index(down40), 1.99688, 1e-4);
  double side89[3] = {sin(89 * M_PI / 180), 0, cos(89 * M_PI / 180)};
  assert_near(vr_guth_position_index(side89), 9.4112, 1e-3);
  double behind[3] = {0, 0, -1};
  assert_near(vr_guth_position_index(behind), 16.0, 0);
}

/* A 512 x 512 equisolid 180-degree image: a background of luminance Lb and
 * a disc of luminance Ls and angular radius rs (deg) on the line of sight. */
static double *disc_image(const vr_scene_camera *c, double Lb, double Ls, double rs) {
  double *L = malloc((size_t)c->width * (size_t)c->height * sizeof *L);
  assert_non_null(L);
  for (int y = 0; y < c->height; y++)
    for (int x = 0; x < c->width; x++) {
      double d[3];
      bool in = vr_fisheye_direction(c, x + 0.5, y + 0.5, d);
      L[(size_t)y * (size_t)c->width + (size_t)x] =
          !in ? 0 : acos(d[2]) < rs * M_PI / 180 ? Ls : Lb;
    }
  return L;
}

static void glare_probability(void **state) {
  (void)state;
  vr_scene_camera c = {.model = VR_CAM_FISHEYE, .fov_deg = 180, .width = 512, .height = 512,
                       .projection = VR_FISHEYE_EQUISOLID};
  vr_dgp_result g;
  /* A uniform field: E_v = pi L and no glare source, so DGP = 5.87e-5 pi L
   * + 0.16 (Wienold & Christoffersen 2006); at L = 2000 cd/m2, 0.52883. */
  double *L = disc_image(&c, 2000, 2000, 0);
  vr_fisheye_dgp(&c, L, 0, &g);
  assert_near(g.vertical_lx, M_PI * 2000, 0.002 * M_PI * 2000);
  assert_near(g.source_omega_sr, 0.0, 0);
  assert_near(g.dgp, 0.52883, 0.0005);
  free(L);
  /* Dim: L = 100 cd/m2, E_v = 314.16 lx, DGP 0.17844 before Wienold's
   * (2009) low-light factor exp(0.024 E_v - 4) / (1 + exp(...)) = 0.97180:
   * 0.17341. */
  L = disc_image(&c, 100, 100, 0);
  vr_fisheye_dgp(&c, L, 0, &g);
  assert_near(g.dgp, 0.17341, 0.0005);
  free(L);
  /* A bright disc of 5 deg radius, 30 000 cd/m2, ahead, on 500 cd/m2: its
   * solid angle 2 pi (1 - cos 5 deg) = 0.023909 sr, E_v = pi 500 + 29500
   * pi sin^2 5 deg = 2274.8 lx; with P = 1 the contrast term would be
   * 30000^2 0.023909 / 2274.8^1.87 = 11.359 and DGP = 5.87e-5 E_v + 0.0918
   * log10(1 + 11.359) + 0.16 = 0.39377.  The position index of the disc's
   * pixels is 1 at its centre and at most exp(0.175) = 1.19 at its upper
   * edge (Guth at 5 deg), so the term lies in [11.359 / 1.42, 11.359]. */
  L = disc_image(&c, 500, 30000, 5);
  vr_fisheye_dgp(&c, L, 0, &g);
  printf("disc: E_v %.1f lx, source %.5f sr at %.0f cd/m2 (threshold %.0f), contrast %.3f, DGP "
         "%.4f\n",
         g.vertical_lx, g.source_omega_sr, g.source_cd_m2, g.threshold_cd_m2, g.contrast, g.dgp);
  assert_near(g.vertical_lx, 2274.8, 0.005 * 2274.8);
  assert_near(g.source_omega_sr, 0.023909, 0.02 * 0.023909);
  assert_near(g.source_cd_m2, 30000, 1e-9 * 30000);
  assert_true(g.contrast <= 11.359 * 1.02 && g.contrast >= 11.359 / 1.42);
  assert_near(g.dgp, 5.87e-5 * g.vertical_lx + 0.0918 * log10(1 + g.contrast) + 0.16, 1e-12);
  assert_true(g.dgp <= 0.39377 + 0.002 && g.dgp >= 0.39377 - 0.0918 * log10(1.42) - 0.002);
  free(L);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(projections),
      cmocka_unit_test(uniform_surround),
      cmocka_unit_test(sun_disc_in_view),
      cmocka_unit_test(position_index),
      cmocka_unit_test(glare_probability),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
