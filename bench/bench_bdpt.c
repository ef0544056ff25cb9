/* Bidirectional path tracing against the path tracer at equal time, on the
 * measured spectral Cornell box (samples/cornell/cornell.scn: its meshes,
 * spectra, depth 64 and 400-700 nm; integrator and spp replaced, sensors
 * left out), 128 x 128 pixels.
 *
 *   bench_bdpt [--threads N] [--reference FILE] [--ref-spp N]
 *              [--path-spp LIST] [--bdpt-spp LIST] [--repeat N]
 *
 * The reference is a long path-traced image (--ref-spp, default 4096),
 * kept in FILE (raw doubles: width, height, then Y per pixel) and reused
 * when it is there with the same size and sample count.  For each setting
 * the program prints the render's wall time and its CPU time over all
 * threads (vr_render_scene, each the least of --repeat runs with the same
 * seed: on a shared machine the CPU time is the steadier) and the relative
 * RMSE of the
 * luminance against the reference, sqrt(mean (Y - Yref)^2) / mean(Yref)
 * (bench_photon's measure), over the whole image and over the image less
 * the lamp: the lamp, seen directly, is 100 times brighter than the walls,
 * and the pixels its edge crosses carry most of the whole image's squared
 * error whatever the integrator (their noise is the camera samples'
 * coverage of the edge), so the second figure is the noise of the light
 * the walls receive.  "Less the lamp" leaves out every pixel whose
 * reference luminance, or a neighbour's, exceeds 1000 cd/m2.  Also the
 * relative difference of the mean Y (whole image).  The reference's own
 * noise is that of the path tracer at its sample count, estimated from the
 * last path row as RMSE(n) sqrt(n / ref_spp); it adds in quadrature and is
 * printed.  Renders go through the library: no file is written but the
 * reference. */
#include <math.h>
#include <stdbool.h>
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

#define RES 128

static void die(const char *what, const char *msg) {
  fprintf(stderr, "bench_bdpt: %s: %s\n", what, msg);
  exit(1);
}

static double clock_s(clockid_t id) {
  struct timespec ts;
  clock_gettime(id, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static void import(vr_matdb *db, const char *file, const char *name, const char *kind) {
  char path[1024];
  snprintf(path, sizeof path, "%s/samples/cornell/%s", VR_SOURCE_DIR, file);
  vr_error err = {0};
  vr_material *m = NULL;
  if (vr_import_file(path, name, kind, "bench_bdpt", &m, &err) || vr_matdb_save(db, m, &err))
    die(path, err.message);
  vr_material_destroy(m);
}

/* One render of the box: Y per pixel into Y, wall time returned, the
 * process's CPU time (all threads) in *cpu. */
static double render(vr_matdb *db, vr_integrator integ, int spp, int threads, double *Y,
                     double *cpu) {
  char path[1024];
  snprintf(path, sizeof path, "%s/samples/cornell/cornell.scn", VR_SOURCE_DIR);
  vr_scene *s = NULL;
  vr_error err = {0};
  if (vr_scene_read(path, &s, &err) || vr_scene_load_models(s, &err)) die(path, err.message);
  s->camera.width = s->camera.height = RES;
  s->settings.integrator = integ;
  s->settings.spp = spp;
  size_t nsensors = s->nsensors;
  s->nsensors = 0;
  vr_render_options o;
  vr_render_options_default(&o);
  o.threads = threads;
  vr_render_result *r = NULL;
  double t0 = clock_s(CLOCK_MONOTONIC), c0 = clock_s(CLOCK_PROCESS_CPUTIME_ID);
  if (vr_render_scene(s, db, &o, &r, &err)) die("render", err.message);
  double t = clock_s(CLOCK_MONOTONIC) - t0;
  if (cpu) *cpu = clock_s(CLOCK_PROCESS_CPUTIME_ID) - c0;
  for (size_t i = 0; i < (size_t)RES * RES; i++) Y[i] = r->xyz[3 * i + 1];
  vr_render_result_destroy(r);
  s->nsensors = nsensors;
  vr_scene_destroy(s);
  return t;
}

static bool load_ref(const char *file, int spp, double *Y) {
  FILE *f = fopen(file, "rb");
  if (!f) return false;
  double head[3];
  bool ok = fread(head, sizeof head, 1, f) == 1 && head[0] == RES && head[1] == RES &&
            head[2] == spp && fread(Y, sizeof *Y, (size_t)RES * RES, f) == (size_t)RES * RES;
  fclose(f);
  return ok;
}

static void save_ref(const char *file, int spp, const double *Y) {
  FILE *f = fopen(file, "wb");
  if (!f) die(file, "cannot write the reference");
  double head[3] = {RES, RES, spp};
  fwrite(head, sizeof head, 1, f);
  fwrite(Y, sizeof *Y, (size_t)RES * RES, f);
  if (fclose(f)) die(file, "cannot write the reference");
}

/* Whether pixel i is the lamp or beside it (see above). */
static bool near_lamp(const double *ref, size_t i) {
  int x = (int)(i % RES), y = (int)(i / RES);
  for (int dy = -1; dy <= 1; dy++)
    for (int dx = -1; dx <= 1; dx++) {
      int u = x + dx, v = y + dy;
      if (u >= 0 && u < RES && v >= 0 && v < RES && ref[(size_t)v * RES + u] > 1000) return true;
    }
  return false;
}

/* Relative RMSE of Y over the whole image and less the lamp, and the
 * relative difference of the mean. */
static void errors(const double *Y, const double *ref, double *rmse, double *rmse_walls,
                   double *mean_diff) {
  double sq = 0, sum = 0, sref = 0, sqw = 0, srefw = 0;
  size_t n = (size_t)RES * RES, nw = 0;
  for (size_t i = 0; i < n; i++) {
    double e2 = (Y[i] - ref[i]) * (Y[i] - ref[i]);
    sq += e2;
    sum += Y[i];
    sref += ref[i];
    if (!near_lamp(ref, i)) sqw += e2, srefw += ref[i], nw++;
  }
  *rmse = sqrt(sq / n) / (sref / n);
  *rmse_walls = sqrt(sqw / nw) / (srefw / nw);
  *mean_diff = sum / sref - 1;
}

static int parse_list(const char *s, int *v, int max) {
  int n = 0;
  while (*s && n < max) {
    v[n++] = atoi(s);
    const char *c = strchr(s, ',');
    if (!c) break;
    s = c + 1;
  }
  return n;
}

int main(int argc, char **argv) {
  int threads = 2, ref_spp = 4096, repeat = 1;
  const char *reference = "bench_bdpt_reference.bin";
  const char *path_list = "16,32,64,128,256", *bdpt_list = "4,8,16,32,64,128";
  for (int i = 1; i < argc; i++) {
    if (!strcmp(argv[i], "--threads") && i + 1 < argc) threads = atoi(argv[++i]);
    else if (!strcmp(argv[i], "--reference") && i + 1 < argc) reference = argv[++i];
    else if (!strcmp(argv[i], "--ref-spp") && i + 1 < argc) ref_spp = atoi(argv[++i]);
    else if (!strcmp(argv[i], "--path-spp") && i + 1 < argc) path_list = argv[++i];
    else if (!strcmp(argv[i], "--bdpt-spp") && i + 1 < argc) bdpt_list = argv[++i];
    else if (!strcmp(argv[i], "--repeat") && i + 1 < argc) repeat = atoi(argv[++i]);
    else {
      fprintf(stderr, "usage: bench_bdpt [--threads N] [--reference FILE] [--ref-spp N] "
                      "[--path-spp LIST] [--bdpt-spp LIST] [--repeat N]\n");
      return 2;
    }
  }
  char dbpath[256];
  snprintf(dbpath, sizeof dbpath, "/tmp/vr_bench_bdpt_%d.db", (int)getpid());
  unlink(dbpath);
  vr_matdb *db = NULL;
  vr_error err = {0};
  if (vr_matdb_open(dbpath, 0, &db, &err)) die(dbpath, err.message);
  import(db, "cornell_white.csv", "cornell-white", "reflectance");
  import(db, "cornell_red.csv", "cornell-red", "reflectance");
  import(db, "cornell_green.csv", "cornell-green", "reflectance");
  import(db, "cornell_light.csv", "cornell-light", "illuminant");
  size_t n = (size_t)RES * RES;
  double *ref = malloc(n * sizeof *ref), *Y = malloc(n * sizeof *Y);
  if (!ref || !Y) die("memory", "out of memory");
  if (load_ref(reference, ref_spp, ref)) {
    printf("reference: %s (path, %d spp)\n", reference, ref_spp);
  } else {
    double t = render(db, VR_INT_PATH, ref_spp, threads, ref, NULL);
    save_ref(reference, ref_spp, ref);
    printf("reference: path, %d spp, %.1f s, saved to %s\n", ref_spp, t, reference);
  }
  printf("Cornell box %dx%d, %d threads; relative RMSE of Y against the reference\n", RES, RES,
         threads);
  printf("%-6s %6s %9s %9s %10s %12s %10s\n", "", "spp", "time s", "CPU s", "rel RMSE",
         "less lamp", "mean Y");
  int spp[32];
  double ref_noise = 0, ref_noise_w = 0;
  for (int g = 0; g < 2; g++) {
    int m = parse_list(g ? bdpt_list : path_list, spp, 32);
    for (int i = 0; i < m; i++) {
      double best = INFINITY, best_cpu = INFINITY;
      for (int k = 0; k < repeat; k++) {
        double c, t = render(db, g ? VR_INT_BDPT : VR_INT_PATH, spp[i], threads, Y, &c);
        if (t < best) best = t;
        if (c < best_cpu) best_cpu = c;
      }
      double e, ew, d;
      errors(Y, ref, &e, &ew, &d);
      if (!g) {
        ref_noise = e * sqrt((double)spp[i] / ref_spp);
        ref_noise_w = ew * sqrt((double)spp[i] / ref_spp);
      }
      printf("%-6s %6d %9.2f %9.2f %10.4f %12.4f %+9.2f%%\n", g ? "bdpt" : "path", spp[i], best,
             best_cpu, e, ew, 100 * d);
      fflush(stdout);
    }
  }
  printf("the reference's own relative RMSE, from the last path row: about %.4f (less the lamp "
         "%.4f)\n",
         ref_noise, ref_noise_w);
  free(ref);
  free(Y);
  vr_matdb_close(db);
  unlink(dbpath);
  return 0;
}
