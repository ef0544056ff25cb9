/* Sensor points files (render/src/scene/sensor_pts.c), Radiance's .pts as
 * its tools write them: tests/data/radiance/workplane.pts was written by
 * Radiance 6.1's `cnt 2 4 | rcalc -e '$1=$2*0.5+0.25;$2=$1*0.5+0.25;
 * $3=0.76;$4=0;$5=0;$6=1'` (tab-separated, a point a line).
 *   - The file's 8 points are the centres of the cells of a 2 x 1 m grid
 *     of 4 x 2 at 0.76 m (the scene format's grid definition; x and y
 *     exact in binary, 0.76 parsed from the same text), in the grid's
 *     order: the readings of
 *     `sensor desk points file=...` must equal those of the same `sensor
 *     desk grid` bit for bit (the same points, the same random streams);
 *   - each reading of a black floor under a point source is E = I cos(theta) / r^2
 *     (a point source straight above; inverse-square and cosine laws)
 *     within the path sensor's own standard error;
 *   - bad files are refused naming the file, the line and the field. */
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

static const char *SCENE =
    "material floor lambert reflectance=0\n"
    "rect center=1,0.5,0 normal=0,0,1 size=8,8 material=floor\n"
    "light point position=1,0.5,3 intensity=1000cd\n"
    "%s\n"
    "render sensor_samples=64 seed=3\n";

static vr_render_result *sensors_of(const char *sensor_line) {
  char text[2048];
  snprintf(text, sizeof text, SCENE, sensor_line);
  vr_scene *s = parse_text(text, VR_TEST_DATA "/radiance/scene.scn"); /* relative paths from there */
  vr_render_result *r = render_scene_with(s, NULL, 1, 2, true, false);
  vr_scene_destroy(s);
  return r;
}

static void test_points_file_is_the_grid(void **state) {
  (void)state;
  vr_render_result *a = sensors_of("sensor desk points file=workplane.pts");
  vr_render_result *b =
      sensors_of("sensor desk grid origin=0,0,0.76 u=2,0,0 v=0,1,0 n=4,2 normal=0,0,1");
  assert_int_equal(a->nreadings, 8);
  assert_int_equal(b->nreadings, 8);
  for (size_t k = 0; k < 8; k++) {
    const vr_sensor_reading *x = &a->readings[k], *y = &b->readings[k];
    for (int c = 0; c < 3; c++) assert_true(x->position[c] == y->position[c]);
    assert_true(x->illuminance_lx == y->illuminance_lx);
    /* E = I cos^3(theta) / h^2, h = 3 - 0.76 */
    double dx = x->position[0] - 1, dy = x->position[1] - 0.5, h = 3 - 0.76;
    double r2 = dx * dx + dy * dy + h * h, cos_t = h / sqrt(r2), want = 1000 * cos_t / r2;
    if (!(fabs(x->illuminance_lx - want) <= 6 * x->stderr_lx + 1e-9 * want))
      fail_msg("point %zu: %.4f lx, expected %.4f (+- %.4f)", k, x->illuminance_lx, want, x->stderr_lx);
    assert_int_equal(x->i, (int)k); /* a file's points are numbered by line */
  }
  vr_render_result_destroy(a);
  vr_render_result_destroy(b);
}

static void refused(const char *content, const char *needle) {
  char path[128], text[1024];
  snprintf(path, sizeof path, "/tmp/vr_test_pts_%d.pts", (int)getpid());
  FILE *f = fopen(path, "w");
  assert_non_null(f);
  fputs(content, f);
  fclose(f);
  char line[512];
  snprintf(line, sizeof line, "sensor s points file=%s", path);
  snprintf(text, sizeof text, SCENE, line);
  vr_scene *s = NULL;
  vr_error err = {0};
  vr_status st = vr_scene_parse(text, strlen(text), "a.scn", &s, &err);
  unlink(path);
  if (st == VR_OK) {
    vr_scene_destroy(s);
    fail_msg("'%s' was read", content);
  }
  if (!strstr(err.message, needle) || !strstr(err.message, path) || !strstr(err.message, "a.scn:4"))
    fail_msg("'%s': message \"%s\" lacks the scene line, the file or \"%s\"", content, err.message, needle);
}

static void test_bad_files(void **state) {
  (void)state;
  refused("0 0 0 0 0 1\n1 2 3 0 0\n", ":2: 5 fields, six expected (x y z dx dy dz): field 6 (dz) is missing");
  refused("0 0 0 0 0 1 7\n", ":1: more than six fields");
  refused("# a grid\n\n0 0 nan 0 0 1\n", ":3: field 3 (z): \"nan\" is not a finite number");
  refused("0 0 0 0 0 0\n", ":1: fields 4-6 (dx dy dz): a zero direction");
  refused("0 0 0 0 0 1x\n", ":1: field 6 (dz): \"1x\" is not a finite number");
  refused("# nothing\n", "no point");
  /* A missing file. */
  char text[1024];
  snprintf(text, sizeof text, SCENE, "sensor s points file=/nonexistent/grid.pts");
  vr_scene *s = NULL;
  vr_error err = {0};
  assert_int_not_equal(vr_scene_parse(text, strlen(text), "a.scn", &s, &err), VR_OK);
  assert_non_null(strstr(err.message, "/nonexistent/grid.pts"));
  /* points needs file=, and takes nothing else. */
  snprintf(text, sizeof text, SCENE, "sensor s points");
  assert_int_not_equal(vr_scene_parse(text, strlen(text), "a.scn", &s, &err), VR_OK);
  assert_non_null(strstr(err.message, "file"));
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_points_file_is_the_grid),
      cmocka_unit_test(test_bad_files),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
