/* RGB colours as materials (docs/scene-format.md, "material"):
 * `lambert color=#RRGGBB` and `lambert rgb=R,G,B [space=srgb|linear]`.
 *
 *   - #808080 is the grey 0.2158605 (IEC 61966-2-1 decoding), so it gives
 *     the same sensor readings as `reflectance=0.2158605` (1e-9);
 *   - a coloured plane lit by a D65 lamp and seen by the camera has the
 *     chromaticity of its colour: the image's summed XYZ against the sRGB
 *     colour's (IEC 61966-2-1 matrix, white D65), within 0.002 in x and y
 *     (the spectral noise of 16 spp over the frame);
 *   - rgb=R,G,B in sRGB is color=# of the same 8-bit values; space=linear
 *     takes the numbers as linear;
 *   - a mesh line without material= waits for vr_scene_load_models: the
 *     renderer refuses it before;
 *   - refusals, each naming the option: both colour forms, a colour and
 *     reflectance=, space= with color=, bad hex, a component outside
 *     [0, 1], an unknown space. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "render_test_util.h"
#include "vr/colour.h"

static const char *plane_scene =
    "material m %s\n"
    "rect center=0,0,0 normal=0,0,1 size=40,40 material=m\n"
    "light point position=0,0,3 intensity=1000cd\n"
    "sensor a point position=0,0,2 normal=0,0,-1\n"
    "camera pinhole from=0,0,2 to=0,0,0 up=0,1,0 fov=40 resolution=32x32\n"
    "render integrator=path spp=16 sensor_samples=64 depth=1\n";

static vr_render_result *render_material(const char *material, bool camera) {
  char text[1024];
  snprintf(text, sizeof text, plane_scene, material);
  return render_text_with(text, 1, 2, !camera);
}

static void test_grey_hex(void **state) {
  (void)state;
  vr_render_result *a = render_material("lambert color=#808080", false);
  vr_render_result *b = render_material("lambert reflectance=0.2158605", false);
  double ea = a->readings[0].illuminance_lx, eb = b->readings[0].illuminance_lx;
  if (fabs(ea - eb) > 1e-6 * eb) fail_msg("#808080: %.9g lx, reflectance=0.2158605: %.9g lx", ea, eb);
  vr_render_result_destroy(a);
  vr_render_result_destroy(b);
}

/* The image's chromaticity against the colour's. */
static void expect_chromaticity(const char *material, const double rgb_linear[3]) {
  vr_render_result *r = render_material(material, true);
  double sum[3] = {0, 0, 0}, want[3];
  for (size_t i = 0; i < (size_t)r->width * (size_t)r->height; i++)
    for (int k = 0; k < 3; k++) sum[k] += r->xyz[3 * i + k];
  vr_srgb_linear_to_xyz(rgb_linear, want);
  double ws = want[0] + want[1] + want[2], gs = sum[0] + sum[1] + sum[2];
  double dx = sum[0] / gs - want[0] / ws, dy = sum[1] / gs - want[1] / ws;
  if (fabs(dx) > 0.002 || fabs(dy) > 0.002)
    fail_msg("%s: chromaticity off by (%.4f, %.4f)", material, dx, dy);
  vr_render_result_destroy(r);
}

static void test_colours(void **state) {
  (void)state;
  double c[3] = {vr_srgb_decode(200 / 255.0), vr_srgb_decode(180 / 255.0), vr_srgb_decode(154 / 255.0)};
  expect_chromaticity("lambert color=#c8b49a", c);
  expect_chromaticity("lambert rgb=0.784313725,0.705882353,0.603921569", c);
  const double saturated[3] = {0.6, 0.05, 0.1};
  expect_chromaticity("lambert rgb=0.6,0.05,0.1 space=linear", saturated);
}

static void refused(const char *material, const char *want) {
  char text[1024];
  snprintf(text, sizeof text, plane_scene, material);
  vr_scene *s = NULL;
  vr_error err = {0};
  vr_status st = vr_scene_parse(text, strlen(text), "colour.scn", &s, &err);
  if (st == VR_OK) fail_msg("%s: accepted", material);
  if (!strstr(err.message, want)) fail_msg("%s: '%s' lacks '%s'", material, err.message, want);
  if (!strstr(err.message, "colour.scn:1:")) fail_msg("%s: '%s' names no line", material, err.message);
}

static void test_refusals(void **state) {
  (void)state;
  refused("lambert color=#808080 rgb=0.5,0.5,0.5", "not both");
  refused("lambert color=#808080 reflectance=0.5", "not both");
  refused("lambert color=#808080 space=linear", "space=");
  refused("lambert color=#80808g", "#RRGGBB");
  refused("lambert color=808080", "#RRGGBB");
  refused("lambert rgb=0.5,1.2,0.5", "[0, 1]");
  refused("lambert rgb=0.5,0.5", "3 numbers");
  refused("lambert rgb=0.5,0.5,0.5 space=xyz", "space");
  refused("lambert reflectance=0.5 space=linear", "space=");
}

/* A mesh line without material= parses (its materials are its file's),
 * and the renderer refuses the scene until vr_scene_load_models ran. */
static void test_models_pending(void **state) {
  (void)state;
  const char *text = "mesh model.obj\ncamera pinhole from=0,-1,0 to=0,0,0\n";
  vr_scene *s = parse_text(text, "pending.scn");
  assert_int_equal(s->objects[0].material, -1);
  vr_render_options o;
  vr_render_options_default(&o);
  vr_render_result *r = NULL;
  vr_error err = {0};
  assert_int_equal(vr_render_scene(s, NULL, &o, &r, &err), VR_E_ARG);
  assert_non_null(strstr(err.message, "vr_scene_load_models"));
  assert_null(r);
  vr_scene_destroy(s);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_models_pending),
      cmocka_unit_test(test_grey_hex),
      cmocka_unit_test(test_colours),
      cmocka_unit_test(test_refusals),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
