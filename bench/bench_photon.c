/* What photon mapping's accuracy costs in time, end to end through the
 * vr-render binary, on the issue-19 comparison scene: the measured Cornell
 * box lit by a point light through a slab of N-BK7
 * (bench/scenes/cornell_bk7.scn; pbrt-v4's copy is cornell_bk7.pbrt), or,
 * with --room, on the sample hotel room (samples/room.scn: sun, sky and a
 * lamp through a clear and an electrochromic window) with the main job's
 * database.
 *
 *   bench_photon [--threads N] [--reference FILE.exr] [--keep DIR] [--resolution WxH]
 *                [--iterations LIST] [--photons N] [--ref-iterations N]
 *                [--room --db out/materials.db] [--seeds] [--only INTEGRATOR]
 *   bench_photon compare A.exr B.exr
 *   bench_photon --rss [--threads N]
 *
 * For each integrator setting it runs vr-render (camera pass, --outputs
 * exr), times the whole run, reads the RGB EXR back and prints the
 * relative RMSE of the luminance Y = 0.2126 R + 0.7152 G + 0.0722 B
 * (IEC 61966-2-1) against the reference: sqrt(mean over pixels of
 * (Y - Yref)^2) / mean(Yref), the measure of the table.  Each run's
 * peak RSS comes from wait4.  Without --reference the reference is rendered
 * first by progressive photon mapping (--ref-iterations, 1M photons each,
 * seed 1000, the runs' seed being 1); it is kept in the --keep folder
 * (default a temporary one) for later runs.  --seeds renders each setting
 * again with seed 2 and prints the estimator's own noise, the relative RMSE
 * between the two over sqrt(2), which needs no reference.
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

/* The reference's seed; the runs use 1 (and 2 with --seeds). */
#define REF_SEED 1000

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

/* Which scene: the Cornell box with its slab (its spectra imported into the
 * --keep folder's database), or the sample hotel room of samples/room.scn
 * with the main job's database (--db out/materials.db: its materials are
 * the ones the main job fits and recovers). */
static bool g_room;
static const char *g_db;

/* The scene with the meshes' relative paths made absolute and its render
 * line replaced: the integrator, and what each scene needs (the Cornell
 * box its 400-700 nm and depth 64; the room its Jensen gather of 400
 * photons, as samples/room.scn has it). */
static void write_scene(const char *from, const char *to, const char *integrator) {
  FILE *in = fopen(from, "r"), *out = fopen(to, "w");
  if (!in || !out) bench_die(from);
  const char *slash = strrchr(from, '/');
  int dlen = slash ? (int)(slash - from) : 1;
  const char *dir = slash ? from : ".";
  char line[2048];
  while (fgets(line, sizeof line, in)) {
    if (!strncmp(line, "render ", 7)) {
      if (g_room) fprintf(out, "render integrator=%s depth=64 knn=400\n", integrator);
      else fprintf(out, "render integrator=%s range=400,700 depth=64\n", integrator);
    } else if (!strncmp(line, "mesh ", 5)) {
      const char *path = line + 5;
      while (*path == ' ') path++;
      fwrite(line, 1, (size_t)(path - line), out);
      if (*path != '/') fprintf(out, "%.*s/", dlen, dir);
      fputs(path, out);
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
                  const char *integrator, long iterations, long photons, int seed, double *wall,
                  double *rss_mib) {
  char t[16], spp[32], ph[32], sd[16], pre[1100], db[1100], cache[1100], log[1200], scn[1200];
  snprintf(sd, sizeof sd, "%d", seed);
  snprintf(t, sizeof t, "%d", threads);
  snprintf(spp, sizeof spp, "%ld", iterations);
  snprintf(ph, sizeof ph, "%ld", photons);
  snprintf(pre, sizeof pre, "%s/%s", dir, prefix);
  snprintf(scn, sizeof scn, "%s/%s.scn", dir, integrator);
  write_scene(scene, scn, integrator);
  if (g_db) snprintf(db, sizeof db, "%s", g_db);
  else snprintf(db, sizeof db, "%s/materials.db", dir);
  snprintf(cache, sizeof cache, "%s/cache", dir);
  snprintf(log, sizeof log, "%s/%s.log", dir, prefix);
  char *argv[] = {VR_BINARY_DIR "/render/vr-render", scn, "-o", pre, "--db", db,
                  "--cache", cache, "--threads", t, "--spp", spp, "--photons", ph,
                  "--outputs", "exr", "--quiet", "--seed", sd, NULL, NULL, NULL};
  if (g_resolution) {
    argv[19] = "--resolution";
    argv[20] = (char *)g_resolution;
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

/* render(), the EXR it wrote named in out (1200 bytes). */
static int render_to(const char *dir, const char *scene, const char *prefix, int threads,
                     const char *integrator, long iterations, long photons, int seed, char *out,
                     double *wall, double *rss_mib) {
  snprintf(out, 1200, "%s/%s.exr", dir, prefix);
  return render(dir, scene, prefix, threads, integrator, iterations, photons, seed, wall, rss_mib);
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
  bool rss = false, seeds = false;
  const char *only = NULL;
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
    else if (!strcmp(argv[i], "--room")) g_room = true;
    else if (!strcmp(argv[i], "--db") && i + 1 < argc) g_db = argv[++i];
    else if (!strcmp(argv[i], "--seeds")) seeds = true;
    else if (!strcmp(argv[i], "--only") && i + 1 < argc) only = argv[++i];
    else {
      fprintf(stderr, "usage: bench_photon [--threads N] [--reference FILE.exr] [--keep DIR] "
                      "[--resolution WxH] [--iterations LIST] [--photons N] [--ref-iterations N]\n"
                      "                    [--room --db MAIN_JOB.db] [--seeds] [--only INTEGRATOR]\n"
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
  if (g_room) {
    if (!g_db || access(g_db, R_OK)) {
      fprintf(stderr, "bench_photon: --room needs --db FILE, the main job's database "
                      "(out/materials.db after scripts/main-job.sh)\n");
      return 2;
    }
    snprintf(scene, sizeof scene, "%s/samples/room.scn", VR_SOURCE_DIR);
  } else {
    snprintf(scene, sizeof scene, "%s/bench/scenes/cornell_bk7.scn", VR_SOURCE_DIR);
    char dbpath[1100];
    snprintf(dbpath, sizeof dbpath, "%s/materials.db", dir);
    if (access(dbpath, F_OK)) import_spectra(dir);
  }
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
        if (render(dir, scene, prefix, threads, ints[g], spps[k], 1024, 1, &wall, &mib)) return 1;
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
      /* Its own seed: with the runs' seed its camera samples would be
       * theirs, and its error would hide part of theirs. */
      if (render(dir, scene, "reference", threads, "progressive", ref_iterations, 1000000,
                 REF_SEED, &wall, &mib))
        return 1;
      printf("reference: %.1f s\n", wall);
    }
  }
  printf("scene %s, %d threads, reference %s\n", scene, threads, ref);
  printf("%-12s %10s %9s %9s %9s %10s %9s%s\n", "integrator", "iterations", "photons", "time s",
         "rel RMSE", "colour/Y", "RSS MiB", seeds ? "  own noise" : "");
  static const char *integrators[] = {"progressive", "photon", "path"};
  for (int g = 0; g < 3; g++) {
    if (only && strcmp(only, integrators[g])) continue;
    const char *p = list;
    while (*p) {
      long it = strtol(p, (char **)&p, 10);
      if (*p == ',') p++;
      if (it <= 0) break;
      /* Jensen's maps: one pass of spp samples and photons x iterations
       * photons, for the same photon budget; path: spp = iterations x 4. */
      long spp = g == 2 ? it * 4 : it, ph = g == 1 ? photons * it / 16 : photons;
      if (g == 1 && ph < photons) continue;
      char prefix[64], out[1200];
      snprintf(prefix, sizeof prefix, "%s_%ld", integrators[g], it);
      if (render_to(dir, scene, prefix, threads, integrators[g], g == 1 ? 16 : spp, ph, 1, out,
                    &wall, &mib))
        return 1;
      errs e;
      if (compare(out, ref, &e)) return 1;
      printf("%-12s %10ld %9ld %9.2f %9.4f %10.2f %9.1f", integrators[g], g == 1 ? 16 : spp, ph,
             wall, e.rel_y, 0.5 * (e.rel_x + e.rel_z) / e.rel_y, mib);
      if (seeds) {
        /* The estimator's own noise, without any reference: the same run
         * with another seed; the two differ by sqrt(2) times the noise of
         * one (their bias is common and cancels). */
        char prefix2[80], out2[1200];
        double wall2, mib2;
        snprintf(prefix2, sizeof prefix2, "%s_seed2", prefix);
        if (render_to(dir, scene, prefix2, threads, integrators[g], g == 1 ? 16 : spp, ph, 2, out2,
                      &wall2, &mib2))
          return 1;
        errs e2;
        if (compare(out, out2, &e2)) return 1;
        printf(" %10.4f", e2.rel_y / sqrt(2.0));
      }
      printf("\n");
      fflush(stdout);
    }
  }
  return 0;
}
