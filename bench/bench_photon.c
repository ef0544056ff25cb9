/* What photon mapping's accuracy costs in time, end to end through the
 * vr-render binary, on the issue-19 comparison scene: the measured Cornell
 * box lit by a point light through a slab of N-BK7
 * (bench/scenes/cornell_bk7.scn; pbrt-v4's copy is cornell_bk7.pbrt).
 *
 *   bench_photon [--threads N] [--reference FILE.exr] [--keep DIR] [--resolution WxH]
 *                [--iterations LIST] [--photons N] [--ref-iterations N]
 *   bench_photon compare A.exr B.exr
 *   bench_photon --rss [--threads N]
 *
 * For each integrator setting it runs vr-render (camera pass, --outputs
 * exr), times the whole run, reads the RGB EXR back and prints the
 * relative RMSE of the luminance Y = 0.2126 R + 0.7152 G + 0.0722 B
 * (IEC 61966-2-1) against the reference: sqrt(mean over pixels of
 * (Y - Yref)^2) / mean(Yref), the measure of the table.  Each run's
 * peak RSS comes from wait4.  Without --reference the reference is rendered
 * first by progressive photon mapping (--ref-iterations, 1M photons each);
 * it is kept in the --keep folder (default a temporary one) for later runs.
 * `compare` prints the same error of A against B, the mean Y of both, and
 * the colour noise ratio: relative RMSE of X and Z over that of Y.
 * `--rss` renders the scene at 16 x 16 pixels with 256 to 16384 samples
 * per pixel (path) or iterations (progressive, 1024 photons each) and
 * prints each run's peak RSS: what the issue asks to be independent of
 * spp within 10 %. */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include "bench_child.h"
#include "vr/image.h"

typedef struct errs {
  double rel_y, rel_x, rel_z, mean, mean_ref;
} errs;

/* CIE XYZ of linear sRGB (IEC 61966-2-1, 4-digit matrix). */
static void to_xyz(const float *p, double xyz[3]) {
  xyz[0] = 0.4124 * p[0] + 0.3576 * p[1] + 0.1805 * p[2];
  xyz[1] = 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
  xyz[2] = 0.0193 * p[0] + 0.1192 * p[1] + 0.9505 * p[2];
}

static int compare(const char *a, const char *b, errs *e) {
  vr_image x = {0}, y = {0};
  vr_error err = {0};
  if (vr_image_read(a, &x, &err) || vr_image_read(b, &y, &err)) {
    fprintf(stderr, "bench_photon: %s\n", err.message);
    vr_image_free(&x);
    return 1;
  }
  if (x.width != y.width || x.height != y.height) {
    fprintf(stderr, "bench_photon: %s and %s differ in size\n", a, b);
    vr_image_free(&x);
    vr_image_free(&y);
    return 1;
  }
  size_t n = (size_t)x.width * (size_t)x.height;
  double sq[3] = {0}, sum[3] = {0}, ref[3] = {0};
  for (size_t i = 0; i < n; i++) {
    double p[3], q[3];
    to_xyz(x.data + 3 * i, p);
    to_xyz(y.data + 3 * i, q);
    for (int c = 0; c < 3; c++) {
      sq[c] += (p[c] - q[c]) * (p[c] - q[c]);
      sum[c] += p[c];
      ref[c] += q[c];
    }
  }
  e->rel_x = sqrt(sq[0] / n) / (ref[0] / n);
  e->rel_y = sqrt(sq[1] / n) / (ref[1] / n);
  e->rel_z = sqrt(sq[2] / n) / (ref[2] / n);
  e->mean = sum[1] / n;
  e->mean_ref = ref[1] / n;
  vr_image_free(&x);
  vr_image_free(&y);
  return 0;
}

/* The scene with the meshes' paths made absolute and its render line's
 * integrator replaced. */
static void write_scene(const char *from, const char *to, const char *integrator) {
  FILE *in = fopen(from, "r"), *out = fopen(to, "w");
  if (!in || !out) bench_die(from);
  char line[2048];
  while (fgets(line, sizeof line, in)) {
    char *m = strstr(line, "../../samples/");
    if (!strncmp(line, "render ", 7)) {
      fprintf(out, "render integrator=%s range=400,700 depth=64\n", integrator);
    } else if (m) {
      fwrite(line, 1, (size_t)(m - line), out);
      fprintf(out, "%s/%s", VR_SOURCE_DIR, m + 6);
    } else {
      fputs(line, out);
    }
  }
  fclose(in);
  if (fclose(out)) bench_die(to);
}

/* --resolution (and --rss): every run at this resolution instead of the
 * scene's. */
static const char *g_resolution;

/* Runs vr-render on the scene with extra options; its wall time and peak
 * RSS (MiB). */
static int render(const char *dir, const char *scene, const char *prefix, int threads,
                  const char *integrator, long iterations, long photons, double *wall,
                  double *rss_mib) {
  char t[16], spp[32], ph[32], pre[1100], db[1100], cache[1100], log[1200], scn[1200];
  snprintf(t, sizeof t, "%d", threads);
  snprintf(spp, sizeof spp, "%ld", iterations);
  snprintf(ph, sizeof ph, "%ld", photons);
  snprintf(pre, sizeof pre, "%s/%s", dir, prefix);
  snprintf(scn, sizeof scn, "%s/%s.scn", dir, integrator);
  write_scene(scene, scn, integrator);
  snprintf(db, sizeof db, "%s/materials.db", dir);
  snprintf(cache, sizeof cache, "%s/cache", dir);
  snprintf(log, sizeof log, "%s/%s.log", dir, prefix);
  char *argv[] = {VR_BINARY_DIR "/render/vr-render", scn, "-o", pre, "--db", db,
                  "--cache", cache, "--threads", t, "--spp", spp, "--photons", ph,
                  "--outputs", "exr", "--quiet", NULL, NULL, NULL};
  if (g_resolution) {
    argv[17] = "--resolution";
    argv[18] = (char *)g_resolution;
  }
  fflush(stdout); /* or the child's freopen writes our buffered lines again */
  double t0 = bench_now();
  pid_t pid = fork();
  if (pid < 0) bench_die("fork");
  if (pid == 0) {
    FILE *f = freopen(log, "w", stdout);
    if (!f || dup2(fileno(stdout), 2) < 0) _exit(127);
    execv(argv[0], argv);
    _exit(127);
  }
  int status;
  struct rusage ru;
  if (wait4(pid, &status, 0, &ru) < 0) bench_die("wait4");
  *wall = bench_now() - t0;
  *rss_mib = ru.ru_maxrss / 1024.0;
  if (!WIFEXITED(status) || WEXITSTATUS(status)) {
    char why[512];
    bench_log_reason(log, why, sizeof why);
    fprintf(stderr, "bench_photon: vr-render %s failed: %s\n", prefix, why);
    return 1;
  }
  return 0;
}

static void import_spectra(const char *dir) {
  static const char *names[4][3] = {{"cornell_white.csv", "cornell-white", "reflectance"},
                                    {"cornell_red.csv", "cornell-red", "reflectance"},
                                    {"cornell_green.csv", "cornell-green", "reflectance"},
                                    {"cornell_light.csv", "cornell-light", "illuminant"}};
  char db[1100], csv[1100], log[1100];
  snprintf(db, sizeof db, "%s/materials.db", dir);
  snprintf(log, sizeof log, "%s/import.log", dir);
  for (int i = 0; i < 4; i++) {
    snprintf(csv, sizeof csv, "%s/samples/cornell/%s", VR_SOURCE_DIR, names[i][0]);
    char *argv[] = {VR_BINARY_DIR "/matdb/vr-matdb", "--db", db, "import", csv, "--name",
                    (char *)names[i][1], "--kind", (char *)names[i][2], NULL};
    if (bench_run(argv, log)) bench_die("vr-matdb import (see the log in the --keep folder)");
  }
}

int main(int argc, char **argv) {
  if (argc == 4 && !strcmp(argv[1], "compare")) {
    errs e;
    if (compare(argv[2], argv[3], &e)) return 1;
    printf("relative RMSE Y %.4f  X %.4f  Z %.4f  (colour/Y: X %.2f, Z %.2f)  mean Y %.6g vs %.6g "
           "(%+.3f %%)\n",
           e.rel_y, e.rel_x, e.rel_z, e.rel_x / e.rel_y, e.rel_z / e.rel_y, e.mean, e.mean_ref,
           100 * (e.mean / e.mean_ref - 1));
    return 0;
  }
  int threads = 2;
  bool rss = false;
  long photons = 200000, ref_iterations = 2048;
  const char *reference = NULL, *keep = NULL, *list = "4,8,16,32,64,128,256";
  for (int i = 1; i < argc; i++) {
    if (!strcmp(argv[i], "--threads") && i + 1 < argc) threads = atoi(argv[++i]);
    else if (!strcmp(argv[i], "--reference") && i + 1 < argc) reference = argv[++i];
    else if (!strcmp(argv[i], "--keep") && i + 1 < argc) keep = argv[++i];
    else if (!strcmp(argv[i], "--iterations") && i + 1 < argc) list = argv[++i];
    else if (!strcmp(argv[i], "--photons") && i + 1 < argc) photons = atol(argv[++i]);
    else if (!strcmp(argv[i], "--ref-iterations") && i + 1 < argc) ref_iterations = atol(argv[++i]);
    else if (!strcmp(argv[i], "--rss")) rss = true;
    else if (!strcmp(argv[i], "--resolution") && i + 1 < argc) g_resolution = argv[++i];
    else {
      fprintf(stderr, "usage: bench_photon [--threads N] [--reference FILE.exr] [--keep DIR] "
                      "[--resolution WxH] [--iterations LIST] [--photons N] [--ref-iterations N]\n"
                      "       bench_photon --rss [--threads N]\n"
                      "       bench_photon compare A.exr B.exr\n");
      return 2;
    }
  }
  char dir[1024];
  if (keep) {
    snprintf(dir, sizeof dir, "%s", keep);
  } else {
    snprintf(dir, sizeof dir, "/tmp/bench_photon.XXXXXX");
    if (!mkdtemp(dir)) bench_die("mkdtemp");
  }
  char scene[1100], ref[1200];
  snprintf(scene, sizeof scene, "%s/bench/scenes/cornell_bk7.scn", VR_SOURCE_DIR);
  char dbpath[1100];
  snprintf(dbpath, sizeof dbpath, "%s/materials.db", dir);
  if (access(dbpath, F_OK)) import_spectra(dir);
  double wall, mib;
  if (rss) {
    g_resolution = "16x16";
    static const char *ints[] = {"path", "progressive"};
    static const long spps[] = {256, 1024, 4096, 16384};
    printf("peak RSS of 16 x 16-pixel renders, %d threads\n%-12s %8s %9s %9s\n", threads,
           "integrator", "spp", "time s", "RSS MiB");
    for (int g = 0; g < 2; g++)
      for (int k = 0; k < 4; k++) {
        char prefix[64];
        snprintf(prefix, sizeof prefix, "rss_%s_%ld", ints[g], spps[k]);
        if (render(dir, scene, prefix, threads, ints[g], spps[k], 1024, &wall, &mib)) return 1;
        printf("%-12s %8ld %9.2f %9.1f\n", ints[g], spps[k], wall, mib);
        fflush(stdout);
      }
    return 0;
  }
  if (reference) {
    snprintf(ref, sizeof ref, "%s", reference);
  } else {
    snprintf(ref, sizeof ref, "%s/reference.exr", dir);
    if (access(ref, F_OK)) {
      printf("reference: progressive, %ld iterations of 1000000 photons ...\n", ref_iterations);
      fflush(stdout);
      if (render(dir, scene, "reference", threads, "progressive", ref_iterations, 1000000, &wall,
                 &mib))
        return 1;
      printf("reference: %.1f s\n", wall);
    }
  }
  printf("scene %s, %d threads, reference %s\n", scene, threads, ref);
  printf("%-12s %10s %9s %9s %9s %10s %9s\n", "integrator", "iterations", "photons", "time s",
         "rel RMSE", "colour/Y", "RSS MiB");
  static const char *integrators[] = {"progressive", "photon", "path"};
  for (int g = 0; g < 3; g++) {
    const char *p = list;
    while (*p) {
      long it = strtol(p, (char **)&p, 10);
      if (*p == ',') p++;
      if (it <= 0) break;
      /* Jensen's maps: one pass of spp samples and photons x iterations
       * photons, for the same photon budget; path: spp = iterations x 4. */
      long spp = g == 2 ? it * 4 : it, ph = g == 1 ? photons * it / 16 : photons;
      if (g == 1 && ph < photons) continue;
      char prefix[64];
      snprintf(prefix, sizeof prefix, "%s_%ld", integrators[g], it);
      if (render(dir, scene, prefix, threads, integrators[g], g == 1 ? 16 : spp, ph, &wall, &mib))
        return 1;
      char out[1200];
      snprintf(out, sizeof out, "%s/%s.exr", dir, prefix);
      errs e;
      if (compare(out, ref, &e)) return 1;
      printf("%-12s %10ld %9ld %9.2f %9.4f %10.2f %9.1f\n", integrators[g], g == 1 ? 16 : spp,
             ph, wall, e.rel_y, 0.5 * (e.rel_x + e.rel_z) / e.rel_y, mib);
      fflush(stdout);
    }
  }
  return 0;
}
