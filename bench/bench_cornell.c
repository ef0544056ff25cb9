/* What accuracy costs on the measured spectral Cornell box: photon-mapped
 * and path-traced sensor illuminance against a long path-traced reference.
 *
 * Scene: samples/cornell/cornell.scn (five patches of 64 sensor points).
 * Materials: the scene's measured spectra, imported into a temporary
 * database.  For each setting the program prints the wall time of the
 * sensor pass, and the largest and the root-mean-square relative error of
 * the five patch means against the reference.
 *
 *   bench_cornell [THREADS] [REFERENCE_PATHS]    (defaults 2 and 16384) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "vr/material_io.h"
#include "vr/matdb.h"
#include "vr/models.h"
#include "vr/render.h"
#include "vr/scene.h"

#include "bench_sensors.h"

#define NPATCH 5
static const char *patches[NPATCH] = {"floor_front", "floor_back", "ceiling", "back_wall",
                                      "green_wall"};

static void die(const char *what, const vr_error *err) {
  fprintf(stderr, "bench_cornell: %s: %s\n", what, err->message);
  exit(1);
}

static void import(vr_matdb *db, const char *file, const char *name, const char *kind) {
  char path[1024];
  snprintf(path, sizeof path, "%s/samples/cornell/%s", VR_SOURCE_DIR, file);
  vr_error err = {0};
  vr_material *m = NULL;
  if (vr_import_file(path, name, kind, "bench_cornell", &m, &err) || vr_matdb_save(db, m, &err))
    die(path, &err);
  vr_material_destroy(m);
}

/* Patch means of one sensor pass, and its time. */
static double run(vr_matdb *db, int threads, vr_sensor_estimator how, long photons, int knn,
                  int paths, double means[NPATCH]) {
  char path[1024];
  snprintf(path, sizeof path, "%s/samples/cornell/cornell.scn", VR_SOURCE_DIR);
  vr_scene *s = NULL;
  vr_error err = {0};
  if (vr_scene_read(path, &s, &err) || vr_scene_load_models(s, &err)) die(path, &err);
  s->settings.sensors = how;
  s->settings.photons = photons;
  s->settings.knn = knn;
  s->settings.sensor_knn = knn;
  s->settings.sensor_samples = paths;
  double t;
  vr_render_result *r = bench_sensors_render(s, db, threads, "bench_cornell", &t);
  for (int i = 0; i < NPATCH; i++) {
    double sum = 0;
    int n = 0;
    for (size_t k = 0; k < r->nreadings; k++)
      if (!strcmp(r->readings[k].sensor, patches[i])) sum += r->readings[k].illuminance_lx, n++;
    means[i] = n ? sum / n : NAN;
  }
  vr_render_result_destroy(r);
  vr_scene_destroy(s);
  return t;
}

static void report(const char *what, double t, const double m[NPATCH], const double ref[NPATCH]) {
  double worst = 0, ss = 0;
  for (int i = 0; i < NPATCH; i++) {
    double e = m[i] / ref[i] - 1;
    if (fabs(e) > fabs(worst)) worst = e;
    ss += e * e;
  }
  printf("| %-46s | %8.2f | %+7.2f %% | %6.2f %% |\n", what, t, 100 * worst,
         100 * sqrt(ss / NPATCH));
}

int main(int argc, char **argv) {
  int threads = argc > 1 ? atoi(argv[1]) : 2;
  int ref_paths = argc > 2 ? atoi(argv[2]) : 16384;
  if (threads < 1 || ref_paths < 1) {
    fprintf(stderr, "usage: bench_cornell [THREADS] [REFERENCE_PATHS]\n");
    return 2;
  }
  char dbpath[256];
  snprintf(dbpath, sizeof dbpath, "/tmp/bench_cornell_%d.db", (int)getpid());
  unlink(dbpath);
  vr_matdb *db = NULL;
  vr_error err = {0};
  if (vr_matdb_open(dbpath, 0, &db, &err)) die(dbpath, &err);
  import(db, "cornell_white.csv", "cornell-white", "reflectance");
  import(db, "cornell_red.csv", "cornell-red", "reflectance");
  import(db, "cornell_green.csv", "cornell-green", "reflectance");
  import(db, "cornell_light.csv", "cornell-light", "illuminant");

  double ref[NPATCH], m[NPATCH];
  double tref = run(db, threads, VR_SENSORS_PATH, 0, 1, ref_paths, ref);
  printf("reference: path tracing, %d paths per point, %.1f s, %d threads\n", ref_paths, tref,
         threads);
  for (int i = 0; i < NPATCH; i++) printf("  %-12s %9.3f lx\n", patches[i], ref[i]);
  printf("\n| estimator | seconds | worst patch | rms |\n|---|---:|---:|---:|\n");
  char what[96];
  for (int paths = 256; paths <= 4096; paths *= 4) {
    double t = run(db, threads, VR_SENSORS_PATH, 0, 1, paths, m);
    snprintf(what, sizeof what, "path, %d paths/point", paths);
    report(what, t, m, ref);
  }
  /* Photon sensors are gather paths ended in the maps (docs/vr-render.md,
   * "Photon sensors"): their error has the gathering's noise (the paths
   * per point) and the maps' bias (the photons).  k grows with the photon
   * count (k ~ N^(4/5) keeps bias and variance shrinking together); 100
   * nearest at 1e6 photons is the scene's sensor_knn. */
  for (int paths = 256; paths <= 1024; paths *= 4)
    for (long n = 62500; n <= 4000000; n *= 4) {
      int k = (int)fmax(20, round(100 * pow(n / 1e6, 0.8)));
      double t = run(db, threads, VR_SENSORS_PHOTON, n, k, paths, m);
      snprintf(what, sizeof what, "photon, %ld photons, k = %d, %d paths", n, k, paths);
      report(what, t, m, ref);
    }
  vr_matdb_close(db);
  unlink(dbpath);
  return 0;
}
