/* The film as a Radiance picture (render/src/film/film_hdr.c):
 *   - Radiance's RGB: the Y row of its RGB-to-XYZ matrix must be the
 *     luminance coefficients of Radiance's src/common/color.h, its macros
 *     CIE_rf, CIE_gf, CIE_bf evaluated for its standard primaries and
 *     equal-energy white (STDPRIMS): 0.265105820, 0.670105820, 0.064788360
 *     (to 1e-8; the comment beside them, .265074126, .670114631,
 *     .064811243, is 3e-5 off its own formula);
 *   - every pixel of a rendered daylit room, read back from PREFIX.hdr, has
 *     the film's luminance by Radiance's definition, 179 (CIE_rf R + CIE_gf
 *     G + CIE_bf B) / EXPOSURE (Radiance's WHTEFFICACY = 179), within the
 *     RGBE format's 8-bit mantissa (2^-7 of the pixel's largest component:
 *     the mantissas are truncated, 2^-8, and the luminance mixes three),
 *     with the camera's exposure (EV 2:
 *     EXPOSURE=4) undone, also where a noisy pixel's colour lies outside
 *     Radiance's RGB (desaturated toward white at its luminance, since the
 *     format holds no negative component);
 *   - the VIEW line is the camera's as Radiance's view options define them
 *     (rpict's -vtv: -vh the horizontal full angle, -vv = 2 atan(tan(vh/2)
 *     H/W); -vta: the angle linear over the picture, the circle's fov over
 *     its smaller side), and an equisolid fisheye, which Radiance cannot
 *     name, writes none.  evalglare's reading of such a picture against
 *     vr-render's DGP is in docs/vr-render.md (not run here: Radiance is
 *     not a dependency). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "render_test_util.h"
#include "vr/colour.h"
#include "vr/film.h"
#include "vr/rgbe.h"

static const double CIE_RGB_Y[3] = {0.26510582010582, 0.67010582010582, 0.06478835978836};

/* Radiance's standard primaries and white (color.h, STDPRIMS). */
static const double PRIMS[8] = {0.640, 0.330, 0.290, 0.600, 0.150, 0.060, 1.0 / 3, 1.0 / 3};

static void test_radiance_primaries(void **state) {
  (void)state;
  double m[9];
  vr_film_radiance_rgb_matrix(m);
  for (int c = 0; c < 3; c++) assert_true(fabs(m[3 + c] - CIE_RGB_Y[c]) < 1e-8);
  /* Each primary's XYZ (a column) has its chromaticity: the X and Z rows. */
  for (int c = 0; c < 3; c++) {
    double X = m[c], Y = m[3 + c], Z = m[6 + c], S = X + Y + Z;
    assert_true(fabs(X / S - PRIMS[2 * c]) < 1e-12 && fabs(Y / S - PRIMS[2 * c + 1]) < 1e-12);
  }
  /* White (1, 1, 1) is the equal-energy white at Y = 1: X = Y = Z = 1. */
  for (int r = 0; r < 3; r++) assert_true(fabs(m[3 * r] + m[3 * r + 1] + m[3 * r + 2] - 1) < 1e-12);
}

static const char *SCENE =
    "material wall lambert reflectance=0.5\n"
    "material floor lambert reflectance=0.3\n"
    "rect center=2,2,0   normal=0,0,1  size=4,4 material=floor\n"
    "rect center=2,2,3   normal=0,0,-1 size=4,4 material=wall\n"
    "rect center=2,4,1.5 normal=0,-1,0 size=4,3 material=wall\n"
    "rect center=0,2,1.5 normal=1,0,0  size=4,3 material=wall\n"
    "rect center=4,2,1.5 normal=-1,0,0 size=4,3 material=wall\n"
    "rect center=2,0,0.45 normal=0,1,0 size=4,0.9 material=wall\n"
    "rect center=2,0,2.55 normal=0,1,0 size=4,0.9 material=wall\n"
    "light sun altitude=35 azimuth=180 illuminance=80000lx spectrum=D65\n"
    "sky cie type=12 illuminance=15000lx spectrum=D65\n"
    "camera fisheye from=2,3,1.2 to=2,0,1.2 resolution=40x32 projection=angular exposure=2\n"
    "render integrator=path spp=4\n";

static void test_rendered_luminance(void **state) {
  (void)state;
  vr_scene *s = parse_text(SCENE, "hdr.scn");
  vr_render_result *r = render_scene_with(s, NULL, 1, 2, false, false);
  char path[128];
  snprintf(path, sizeof path, "/tmp/vr_test_film_hdr_%d.hdr", (int)getpid());
  vr_error err = {0};
  assert_int_equal(vr_film_write_hdr(r, &s->camera, path, &err), VR_OK);
  vr_image img;
  vr_rgbe_info info;
  assert_int_equal(vr_rgbe_read(path, &img, &info, &err), VR_OK);
  unlink(path);
  assert_int_equal(img.width, 40);
  assert_int_equal(img.height, 32);
  assert_true(info.exposure == 4.0); /* EV 2 */
  assert_string_equal(info.view, " -vta -vp 2 3 1.2 -vd 0 -1 0 -vu 0 0 1 -vh 225 -vv 180 "
                                 "-vo 0 -va 0 -vs 0 -vl 0");
  /* Pixels whose colour lies outside Radiance's RGB (a negative component
   * by the inverse of the matrix checked above): the desaturated ones. */
  double m[9], inv[9];
  vr_film_radiance_rgb_matrix(m);
  vr_mat3_inverse(m, inv);
  const double *rinv = inv; /* the R row of the inverse */
  size_t lit = 0, outside = 0;
  for (size_t p = 0; p < 40 * 32; p++) {
    const double *xyz = &r->xyz[3 * p];
    outside += rinv[0] * xyz[0] + rinv[1] * xyz[1] + rinv[2] * xyz[2] < 0;
    const float *c = img.data + 3 * p;
    double Y = 179.0 * (CIE_RGB_Y[0] * c[0] + CIE_RGB_Y[1] * c[1] + CIE_RGB_Y[2] * c[2]) / info.exposure;
    double big = 179.0 * fmax(fmax(c[0], c[1]), c[2]) / info.exposure, want = r->xyz[3 * p + 1];
    if (!(fabs(Y - want) <= 0x1p-7 * big + 1e-9))
      fail_msg("pixel %zu: the picture's luminance %.6g cd/m2, the film's %.6g", p, Y, want);
    lit += want > 1;
  }
  assert_true(lit > 600); /* the circle (about 64 % of the picture) is lit */
  printf("pixels with a negative R, desaturated: %zu\n", outside);
  assert_true(outside > 0); /* the luminance check above covered some */
  vr_image_free(&img);
  vr_render_result_destroy(r);
  vr_scene_destroy(s);
}

static void test_views(void **state) {
  (void)state;
  vr_scene_camera c;
  memset(&c, 0, sizeof c);
  c.model = VR_CAM_PINHOLE;
  c.to[1] = 2;
  c.up[2] = 1;
  c.fov_deg = 60;
  char v[512];
  assert_true(vr_film_radiance_view(&c, 320, 240, v, sizeof v));
  /* -vv = 2 atan(tan 30 deg x 240/320) = 46.8264 deg */
  double vv;
  const char *at = strstr(v, "-vv ");
  assert_non_null(at);
  assert_int_equal(sscanf(at, "-vv %lf", &vv), 1);
  assert_true(fabs(vv - 2 * atan(tan(M_PI / 6) * 0.75) * 180 / M_PI) < 1e-6);
  assert_true(fabs(vv - 46.8264) < 1e-4);
  assert_non_null(strstr(v, " -vtv -vp 0 0 0 -vd 0 1 0 -vu 0 0 1 -vh 60 "));
  c.model = VR_CAM_FISHEYE;
  c.fov_deg = 180;
  c.projection = VR_FISHEYE_EQUISOLID;
  assert_false(vr_film_radiance_view(&c, 64, 64, v, sizeof v));
  c.projection = VR_FISHEYE_ANGULAR;
  assert_true(vr_film_radiance_view(&c, 64, 64, v, sizeof v));
  assert_non_null(strstr(v, " -vta ") && strstr(v, "-vh 180 -vv 180 "));
  /* Too small a buffer: false, never a cut line. */
  assert_false(vr_film_radiance_view(&c, 64, 64, v, 20));
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_radiance_primaries),
      cmocka_unit_test(test_rendered_luminance),
      cmocka_unit_test(test_views),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
