/* What accuracy costs in a daylit room: path-traced and photon-mapped
 * sensors against a long path-traced reference, and the time each needs
 * for a 2 % worst-point error.
 *
 * Scene: the room of issue 17 (tests/render/test_photon_sensors.c): 4 x 4
 * x 3 m, a 2 x 1.2 m opening in the south wall, sun at 35 deg in the south
 * (80 000 lx) and a CIE clear sky (15 000 lx), 16 floor points, 6 on the
 * north wall and a desk point in mid-air; with an outdoor ground of
 * 12 x 8 m or 60 x 56 m (the larger, the fewer photons reach the room).
 * Path tracing runs with and without a portal over the window (the sky's
 * next-event estimation aimed through the opening, portals.c); the
 * reference is without, an independent estimator.
 * For each setting the program prints the wall time of the sensor pass
 * (with --sensors-only, the photon pass included) and the largest and the
 * root-mean-square relative error over the 23 points.
 *
 *   bench_daylight [THREADS] [REFERENCE_PATHS] [ROWS]   (defaults 2, 524288, all)
 *
 * ROWS: all, or photon-portal (the reference and the photon + portal rows
 * alone, the ones the outdoor splitting of photon_trace.c changes).
 *
 * The reference must be well inside 2 %: at 65 536 paths a point the worst
 * point of this room still has 2 % of noise; at 524 288 about 0.7 %. */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "vr/render.h"
#include "vr/scene.h"

#include "../tests/render/daylit_room.h"
#include "bench_sensors.h"

#define NPOINTS DAYLIT_ROOM_POINTS

/* The window's portal: sky samples aimed through the opening. */
static const char PORTAL[] = "portal center=2,0,1.5 normal=0,1,0 size=2,1.2\n";

static double run(int threads, const char *centre, const char *size, bool portal,
                  const char *settings, double lx[NPOINTS], double *share) {
  char text[4096], ground[512];
  snprintf(ground, sizeof ground, "rect center=%s normal=0,0,1 size=%s material=ground outside=yes\n%s",
           centre, size, portal ? PORTAL : "");
  snprintf(text, sizeof text, DAYLIT_ROOM, ground, settings);
  vr_scene *s = NULL;
  vr_error err = {0};
  if (vr_scene_parse(text, strlen(text), "daylight.scn", &s, &err)) {
    fprintf(stderr, "bench_daylight: %s\n", err.message);
    exit(1);
  }
  double t;
  vr_render_result *r = bench_sensors_render(s, NULL, threads, "bench_daylight", &t);
  if (r->nreadings != NPOINTS) {
    fprintf(stderr, "bench_daylight: %zu readings\n", r->nreadings);
    exit(1);
  }
  for (int k = 0; k < NPOINTS; k++) lx[k] = r->readings[k].illuminance_lx;
  if (share) *share = r->sensor_map_share;
  vr_render_result_destroy(r);
  vr_scene_destroy(s);
  return t;
}

static void report(const char *what, double t, const double *m, const double *ref, double share,
                   double *best2) {
  double worst = 0, ss = 0;
  for (int k = 0; k < NPOINTS; k++) {
    double e = m[k] / ref[k] - 1;
    if (fabs(e) > fabs(worst)) worst = e;
    ss += e * e;
  }
  char sh[32] = "";
  if (share >= 0) snprintf(sh, sizeof sh, "%5.1f %%", 100 * share);
  printf("| %-44s | %8.2f | %+7.2f %% | %6.2f %% | %7s |\n", what, t, 100 * worst,
         100 * sqrt(ss / NPOINTS), sh);
  if (fabs(worst) <= 0.02 && t < *best2) *best2 = t;
}

int main(int argc, char **argv) {
  int threads = argc > 1 ? atoi(argv[1]) : 2;
  int ref_paths = argc > 2 ? atoi(argv[2]) : 524288;
  const char *rows = argc > 3 ? argv[3] : "all";
  bool all = !strcmp(rows, "all");
  if (threads < 1 || ref_paths < 1 || (!all && strcmp(rows, "photon-portal"))) {
    fprintf(stderr, "usage: bench_daylight [THREADS] [REFERENCE_PATHS] [all|photon-portal]\n");
    return 2;
  }
  static const char *const grounds[2][3] = {{"2,-4,0", "12,8", "12 x 8 m ground"},
                                            {"2,-28,0", "60,56", "60 x 56 m ground"}};
  for (int g = 0; g < 2; g++) {
    double ref[NPOINTS], m[NPOINTS], share;
    char set[256], what[128];
    snprintf(set, sizeof set, "sensors=path sensor_samples=%d", ref_paths);
    double tref = run(threads, grounds[g][0], grounds[g][1], false, set, ref, NULL);
    printf("\n%s: reference path tracing, %d paths per point, %.1f s, %d threads\n\n",
           grounds[g][2], ref_paths, tref, threads);
    printf("| estimator | seconds | worst point | rms | map share |\n|---|---:|---:|---:|---:|\n");
    double best_path = INFINITY, best_portal = INFINITY, best_photon = INFINITY,
           best_photon_portal = INFINITY;
    for (int paths = 1024; all && paths <= 65536; paths *= 2) {
      snprintf(set, sizeof set, "sensors=path sensor_samples=%d seed=7", paths);
      double t = run(threads, grounds[g][0], grounds[g][1], false, set, m, NULL);
      snprintf(what, sizeof what, "path, %d paths/point", paths);
      report(what, t, m, ref, -1, &best_path);
    }
    for (int paths = 512; all && paths <= 32768; paths *= 2) {
      snprintf(set, sizeof set, "sensors=path sensor_samples=%d seed=7", paths);
      double t = run(threads, grounds[g][0], grounds[g][1], true, set, m, NULL);
      snprintf(what, sizeof what, "path + portal, %d paths/point", paths);
      report(what, t, m, ref, -1, &best_portal);
    }
    static const long photons[] = {2000000, 8000000};
    for (int paths = 4096; all && paths <= 65536; paths *= 4)
      for (int i = 0; i < 2; i++) {
        snprintf(set, sizeof set,
                 "sensors=photon photons=%ld sensor_knn=100 sensor_samples=%d seed=7", photons[i],
                 paths);
        double t = run(threads, grounds[g][0], grounds[g][1], false, set, m, &share);
        snprintf(what, sizeof what, "photon, %ld photons, k = 100, %d paths", photons[i], paths);
        report(what, t, m, ref, share, &best_photon);
      }
    for (int paths = 4096; paths <= 65536; paths *= 4) {
      snprintf(set, sizeof set,
               "sensors=photon photons=2000000 sensor_knn=100 sensor_samples=%d seed=7 "
               "photon_portals=on",
               paths);
      double t = run(threads, grounds[g][0], grounds[g][1], true, set, m, &share);
      snprintf(what, sizeof what, "photon + portal, 2000000 photons, %d paths", paths);
      report(what, t, m, ref, share, &best_photon_portal);
    }
    printf("\ntime to a 2 %% worst-point error: path %.2f s, path + portal %.2f s, photon %.2f s, "
           "photon + portal %.2f s\n",
           best_path, best_portal, best_photon, best_photon_portal);
  }
  return 0;
}
