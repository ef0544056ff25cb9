/* The tube light (light tube, render/src/lights/tube.c) against values
 * from outside the renderer:
 *   - the configuration factor from a differential planar element to an
 *     infinitely long cylinder of radius r whose axis is parallel to the
 *     element and at distance h on its normal, F = r / h (Siegel & Howell,
 *     Thermal Radiation Heat Transfer, configuration factor catalogue;
 *     Modest, Radiative Heat Transfer, appendix D), so a Lambertian tube of
 *     luminance L gives E = pi L r / h there;
 *   - a second, independent integration written here: the midpoint rule
 *     over the finite tube's lateral surface of L cos_x cos_y / d^2, which
 *     also checks that a tube of 40 m is "infinite" to 3e-4 at h = 1 m;
 *   - the path tracer's sensor reading through next-event estimation, the
 *     photon estimator (photons from the tube's emission sampling) against
 *     the path estimator on a room lit by it, and BDPT (light subpaths
 *     from the tube, MIS with its next-event samples) against the path
 *     tracer's image, each within 4 standard errors of the difference;
 *   - the light's own densities: a next-event sample's L times pdf_li of
 *     its direction is the radiance itself (the definition of the
 *     estimate), to rounding (1e-8 / cos at the tube: measured 4e-9 / cos). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "lights/light.h"
#include "vr/vec3.h"
#include "render_test_util.h"

/* E at the origin (normal +z) from a Lambertian tube of radiance L along x
 * at height h, from x = -len/2 to len/2, radius r: sum over the lateral
 * surface of L cos_x cos_y / d^2 dA, n_z x n_phi midpoints. */
static double tube_quadrature(double L, double r, double h, double len, int nz, int nphi) {
  double sum = 0, dz = len / nz, dphi = 2 * M_PI / nphi;
  for (int i = 0; i < nz; i++) {
    double x = -len / 2 + (i + 0.5) * dz;
    for (int j = 0; j < nphi; j++) {
      double ph = (j + 0.5) * dphi, ny = cos(ph), nz_ = sin(ph);
      double p[3] = {x, r * ny, h + r * nz_};
      double d2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2], d = sqrt(d2);
      double cos_x = p[2] / d;                         /* at the element, normal +z */
      double cos_y = -(p[1] * ny + p[2] * nz_) / d;    /* at the tube, normal (0, ny, nz) */
      if (cos_x > 0 && cos_y > 0) sum += L * cos_x * cos_y / d2 * r * dphi * dz;
    }
  }
  return sum;
}

/* The catalogue's F = r / h, and the quadrature of a 40 m tube within 3e-4
 * of it (the finite length's tails are about 1e-4). */
static void test_quadrature_is_the_catalogue(void **state) {
  (void)state;
  double L = 1000, r = 0.05, h = 1.0;
  double E = tube_quadrature(L, r, h, 40.0, 40000, 720);
  double inf = M_PI * L * r / h;
  printf("quadrature %.6f lx, infinite cylinder %.6f lx (ratio %.6f)\n", E, inf, E / inf);
  assert_true(fabs(E / inf - 1) < 3e-4);
}

#define TUBE_SCENE(RENDER)                                                              \
  "material black lambert reflectance=0\n"                                             \
  "rect center=0,0,-0.01 normal=0,0,1 size=0.1,0.1 material=black\n"                   \
  "light tube from=-20,0,1 to=20,0,1 radius=5cm luminance=1000cd/m2\n"                 \
  "sensor under point position=0,0,0 normal=0,0,1\n" RENDER

/* The path tracer's reading: next-event samples of the tube's surface. */
static void test_sensor_reads_the_tube(void **state) {
  (void)state;
  vr_render_result *r = render_text_with(TUBE_SCENE("render sensor_samples=1048576\n"), 1, 2, true);
  double ref = tube_quadrature(1000, 0.05, 1.0, 40.0, 40000, 720);
  double E = r->readings[0].illuminance_lx, se = r->readings[0].stderr_lx;
  printf("path sensor %.3f +- %.3f lx, reference %.3f lx\n", E, se, ref);
  assert_true(se > 0 && se < 0.01 * ref);
  assert_true(fabs(E - ref) < 4 * se);
  vr_render_result_destroy(r);
}

/* A white room lit by the tube: the floor's indirect light from the
 * photons the tube emits (photon estimator) against paths. */
#define ROOM(RENDER)                                                                     \
  "material white lambert reflectance=0.7\n"                                           \
  "rect center=0,0,0 normal=0,0,1 size=4,4 material=white\n"                           \
  "rect center=0,0,2.5 normal=0,0,-1 size=4,4 material=white\n"                        \
  "rect center=-2,0,1.25 normal=1,0,0 size=4,2.5 material=white\n"                     \
  "rect center=2,0,1.25 normal=-1,0,0 size=4,2.5 material=white\n"                     \
  "rect center=0,-2,1.25 normal=0,1,0 size=4,2.5 material=white\n"                     \
  "rect center=0,2,1.25 normal=0,-1,0 size=4,2.5 material=white\n"                     \
  "light tube from=-0.6,0.5,2.3 to=0.6,0.5,2.3 radius=13mm flux=2600lm\n"              \
  RENDER

static void test_photons_from_the_tube(void **state) {
  (void)state;
  const char *sensors = "sensor floor grid origin=-1.5,-1.5,0.001 u=3,0,0 v=0,3,0 n=2,2 normal=0,0,1\n";
  char text[4096];
  snprintf(text, sizeof text, ROOM("render sensor_samples=65536 depth=8\n%s"), sensors);
  vr_render_result *path = render_text_with(text, 1, 2, true);
  snprintf(text, sizeof text,
           ROOM("render sensors=photon photons=2000000 sensor_samples=16384 depth=8\n%s"), sensors);
  vr_render_result *photon = render_text_with(text, 1, 2, true);
  for (size_t k = 0; k < path->nreadings; k++) {
    double a = path->readings[k].illuminance_lx, b = photon->readings[k].illuminance_lx;
    double s = sqrt(pow(path->readings[k].stderr_lx, 2) + pow(photon->readings[k].stderr_lx, 2));
    printf("floor %zu: path %.2f +- %.2f, photon %.2f +- %.2f lx\n", k, a,
           path->readings[k].stderr_lx, b, photon->readings[k].stderr_lx);
    assert_true(a > 10);
    assert_true(fabs(a - b) < 4 * s);
  }
  vr_render_result_destroy(path);
  vr_render_result_destroy(photon);
}

/* The image's mean luminance over `seeds` renders with integrator `integ`:
 * their mean and the standard error of that mean. */
static void image_mean(const char *integ, int seeds, double *mean, double *se) {
  double m[8], sum = 0;
  for (int i = 0; i < seeds; i++) {
    char text[4096];
    snprintf(text, sizeof text,
             ROOM("camera pinhole from=0,-1.9,1.2 to=0,0,0.8 fov=70 resolution=24x24\n"
                  "render integrator=%s spp=32 depth=6 sampler=independent seed=%d\n"),
             integ, 11 + i);
    vr_render_result *r = render_text_with(text, 1, 2, false);
    double y = 0;
    for (int p = 0; p < r->width * r->height; p++) y += r->xyz[3 * p + 1];
    m[i] = y / (r->width * r->height);
    sum += m[i];
    vr_render_result_destroy(r);
  }
  *mean = sum / seeds;
  double v = 0;
  for (int i = 0; i < seeds; i++) v += (m[i] - *mean) * (m[i] - *mean);
  *se = sqrt(v / (seeds - 1) / seeds);
}

static void test_bdpt_agrees_with_path(void **state) {
  (void)state;
  double mp, sp, mb, sb;
  image_mean("path", 6, &mp, &sp);
  image_mean("bdpt", 6, &mb, &sb);
  double s = sqrt(sp * sp + sb * sb);
  printf("mean luminance: path %.4f +- %.4f, bdpt %.4f +- %.4f cd/m2\n", mp, sp, mb, sb);
  assert_true(mp > 1);
  assert_true(s < 0.02 * mp);
  assert_true(fabs(mp - mb) < 4 * s);
}

static void test_pdf_li_matches_sample_li(void **state) {
  (void)state;
  vr_scene *s = parse_text("sensor s point position=0,0,0 normal=0,0,1\n"
                           "light tube from=-0.6,0.5,2.3 to=0.6,0.5,2.3 radius=13mm "
                           "luminance=1000cd/m2\n",
                           "t.scn");
  vr_light_setup u = {{s->path, NULL, 360, 830}, {0, 0, 0}, 10};
  vr_light l;
  vr_error err = {0};
  assert_int_equal(vr_light_init(&l, &s->lights[0], &u, &err), VR_OK);
  const double x[3] = {0.3, -0.2, 0.1}, wl[1] = {555};
  double Le = vr_rspd_at(&l.spd, 555);
  int n = 0;
  for (uint64_t i = 0; i < 4000; i++) {
    vr_rng_key key = {vr_rng_seed_make(1, VR_SAMPLER_INDEPENDENT, 1), i, 0, 0};
    vr_light_sample ls;
    if (!l.ops->sample_li(&l, x, &key, (vr_light_dims){VR_DIM_LIGHT_V, VR_DIM_LIGHT_W}, 1, wl, &ls))
      continue;
    double pdf = l.ops->pdf_li(&l, x, ls.dir);
    assert_true(pdf > 0);
    /* Rounding: the intersection's quadratic loses digits as the ray
     * grazes the tube, so the agreement goes as 1 / cos at the surface. */
    double cos_y = -vr_dot3(ls.dir, ls.n);
    assert_true(fabs(ls.L[0] * pdf / Le - 1) < 1e-12 + 1e-8 / cos_y);
    n++;
  }
  /* About half the surface faces x. */
  assert_true(n > 1500 && n < 2500);
  vr_light_fini(&l);
  vr_scene_destroy(s);
}

/* Bad lines: no flux nor luminance, both, a zero-length tube. */
static void test_bad_lines(void **state) {
  (void)state;
  static const struct {
    const char *line, *msg;
  } cases[] = {
      {"light tube from=0,0,1 to=1,0,1 radius=1cm\n", "needs flux= (lm or W) or luminance="},
      {"light tube from=0,0,1 to=1,0,1 radius=1cm flux=100lm luminance=5cd/m2\n", "one of them"},
      {"light tube from=0,0,1 to=0,0,1 radius=1cm flux=100lm\n", "the tube has no length"},
      {"light tube from=0,0,1 to=1,0,1 flux=100lm\n", "needs radius="},
      {"light tube from=0,0,1 to=1,0,1 radius=1cm flux=100cd\n", "\"flux=100cd\""},
  };
  for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
    char text[512];
    snprintf(text, sizeof text, "sensor s point position=0,0,0 normal=0,0,1\n%s", cases[i].line);
    vr_scene *s = NULL;
    vr_error err = {0};
    assert_int_equal(vr_scene_parse(text, strlen(text), "t.scn", &s, &err), VR_E_PARSE);
    printf("%s", err.message);
    printf("\n");
    assert_non_null(strstr(err.message, "t.scn:2:"));
    assert_non_null(strstr(err.message, cases[i].msg));
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_quadrature_is_the_catalogue),
      cmocka_unit_test(test_sensor_reads_the_tube),
      cmocka_unit_test(test_photons_from_the_tube),
      cmocka_unit_test(test_bdpt_agrees_with_path),
      cmocka_unit_test(test_pdf_li_matches_sample_li),
      cmocka_unit_test(test_bad_lines),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
