/* Photon-mapped irradiance on the measured spectral Cornell box against the
 * path tracer.
 *
 * The scene is samples/cornell/cornell.scn: the Cornell University Program
 * of Computer Graphics' measured geometry and spectral reflectances (white,
 * red, green) and light spectrum
 * (http://www.graphics.cornell.edu/online/box/data.html).  Its sensors are
 * 8 x 8 (ceiling 16 x 4) grids on five open patches: two on the floor, the
 * ceiling (indirect light only), the back wall and the green wall.
 *
 * The photon estimate (`sensors=photon`: density estimation in the direct,
 * caustic and global maps) is a different estimator of the same integral as
 * the path tracer's (`sensors=path`); both are consistent, so on each patch
 * their mean illuminance, and their mean spectral irradiance in three bands,
 * must agree.  Tolerance: 2 % (the figure).  The statistical error
 * of each patch mean is about 0.5 % for the photon side (600 nearest
 * photons per map per point, 64 points) and 0.4 % for the path side (2048
 * paths per point), so a 2 % disagreement is a bias, not noise. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "vr/material_io.h"
#include "vr/matdb.h"
#include "vr/render.h"
#include "vr/scene.h"
#include "cornell_import.h"

static char dbpath[256];
static vr_matdb *db;

static int setup(void **state) {
  (void)state;
  snprintf(dbpath, sizeof dbpath, "/tmp/vr_test_cornell_%d.db", (int)getpid());
  unlink(dbpath);
  vr_error err = {0};
  if (vr_matdb_open(dbpath, 0, &db, &err)) return -1;
  return cornell_import_all(db);
}

static int teardown(void **state) {
  (void)state;
  vr_matdb_close(db);
  unlink(dbpath);
  return 0;
}

static vr_render_result *render(vr_sensor_estimator how) {
  char path[1024];
  snprintf(path, sizeof path, "%s/samples/cornell/cornell.scn", VR_SOURCE_DIR);
  vr_scene *s = NULL;
  vr_error err = {0};
  if (vr_scene_read(path, &s, &err)) fail_msg("%s", err.message);
  s->settings.sensors = how;
  s->settings.sensor_samples = 2048;
  vr_render_options o;
  vr_render_options_default(&o);
  o.threads = 2;
  o.subdomains = 2;
  o.no_camera = true;
  vr_render_result *r = NULL;
  if (vr_render_scene(s, db, &o, &r, &err)) fail_msg("%s", err.message);
  vr_scene_destroy(s); /* the readings keep their own sensor names */
  return r;
}

/* Mean illuminance and mean spectral irradiance in [lo, hi) nm over the
 * readings of one sensor. */
static double patch_lx(const vr_render_result *r, const char *name) {
  double sum = 0;
  int n = 0;
  for (size_t k = 0; k < r->nreadings; k++)
    if (!strcmp(r->readings[k].sensor, name)) sum += r->readings[k].illuminance_lx, n++;
  assert_true(n > 0);
  return sum / n;
}

static double patch_band(const vr_render_result *r, const char *name, double lo, double hi) {
  double sum = 0;
  int n = 0;
  for (size_t k = 0; k < r->nreadings; k++) {
    if (strcmp(r->readings[k].sensor, name)) continue;
    for (size_t b = 0; b < r->nbins; b++)
      if (r->bin_nm[b] >= lo && r->bin_nm[b] < hi) sum += r->sensor_spectral[k * r->nbins + b], n++;
  }
  assert_true(n > 0);
  return sum / n;
}

static void test_photon_irradiance_matches_path(void **state) {
  (void)state;
  vr_render_result *pm = render(VR_SENSORS_PHOTON), *pt = render(VR_SENSORS_PATH);
  /* The sensor-only results carry the film's bins for the spectra. */
  assert_int_equal(pm->nbins, pt->nbins);
  const char *patches[] = {"floor_front", "floor_back", "ceiling", "back_wall", "green_wall"};
  const double bands[3][2] = {{400, 500}, {500, 600}, {600, 700}};
  for (int i = 0; i < 5; i++) {
    double a = patch_lx(pm, patches[i]), b = patch_lx(pt, patches[i]);
    printf("%-12s photon %8.2f lx  path %8.2f lx  %+.2f %%\n", patches[i], a, b, 100 * (a / b - 1));
    assert_true(b > 50); /* every patch is lit: the comparison is not 0 = 0 */
    if (fabs(a / b - 1) > 0.02) fail_msg("%s: photon %.2f lx vs path %.2f lx", patches[i], a, b);
    for (int k = 0; k < 3; k++) {
      double ea = patch_band(pm, patches[i], bands[k][0], bands[k][1]),
             eb = patch_band(pt, patches[i], bands[k][0], bands[k][1]);
      printf("    %3.0f-%3.0f nm photon %.5g path %.5g W/(m2 nm)  %+.2f %%\n", bands[k][0],
             bands[k][1], ea, eb, 100 * (ea / eb - 1));
      assert_true(eb > 0);
      if (fabs(ea / eb - 1) > 0.02)
        fail_msg("%s %g-%g nm: photon %.5g vs path %.5g", patches[i], bands[k][0], bands[k][1], ea, eb);
    }
  }
  /* Colour bleeding, from the measured spectra: the green wall reflects
   * 0.43-0.48 at 520-550 nm and 0.12 at 650 nm, the red wall 0.06 at 520 nm
   * and 0.61-0.65 past 630 nm; the floor_back patch lies along the green
   * wall, floor_front along the red one, so the green/red band ratio of
   * the irradiance must be higher on floor_back (both estimators). */
  for (int e = 0; e < 2; e++) {
    const vr_render_result *r = e ? pt : pm;
    double gb = patch_band(r, "floor_back", 500, 600) / patch_band(r, "floor_back", 600, 700);
    double gf = patch_band(r, "floor_front", 500, 600) / patch_band(r, "floor_front", 600, 700);
    assert_true(gb > gf);
  }
  vr_render_result_destroy(pm);
  vr_render_result_destroy(pt);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_photon_irradiance_matches_path),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
