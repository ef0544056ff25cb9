/* What the display denoiser (--denoise, render/src/film/denoise.c) buys:
 * the error of its image against a converged reference, beside raw renders
 * of more samples, and the time each takes, end to end through
 * vr_render_scene (the engine vr-render runs).
 *
 *   build/bench/bench_denoise SCENE.scn DB [--spp N] [--ref-spp M]
 *       [--resolution WxH] [--threads P] [--ref-cache FILE] [--seed S]
 *       [--ref-scene REF.scn]
 *
 * Renders, at the scene's integrator and settings:
 *   - the reference: M samples a pixel of another seed (read from
 *     --ref-cache when it holds this scene's reference, else written
 *     there), rendered with --denoise for its features (its raw film is
 *     the reference), by REF.scn's integrator and settings when given (the
 *     same view path traced, for an integrator with a bias of its own such
 *     as SPPM, whose spp are iterations);
 *   - N samples with --denoise: its raw film (the EXR) and its denoised
 *     image (the PNG's, before tone mapping);
 *   - raw renders of 2N, 4N, 8N and 16N samples.
 * For each: the relative RMSE of luminance against the reference (per
 * pixel |Y - Y_ref| / max(Y_ref, 1 % of the mean), root-mean-square, as
 * vr-test-exr-compare --error), over all pixels and over the edge pixels
 * alone (a pixel whose reference features differ from a 4-neighbour's:
 * albedo by more than 0.1, normal by more than 26 degrees, nearness by
 * more than 10 %: texture and geometry edges, where a filter's blur shows),
 * and
 * the seconds.  The reference's own noise adds to every figure: its
 * squared error is M / N' times smaller than that of a raw render of N'.
 * Figures go to docs/benchmarks.md, "Denoising". */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "vr/matdb.h"
#include "vr/models.h"
#include "vr/render.h"
#include "vr/scene.h"

static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void die(const char *what, const vr_error *err) {
  fprintf(stderr, "bench_denoise: %s: %s\n", what, err ? err->message : "failed");
  exit(1);
}

typedef struct run {
  double *Y, *Yd; /* raw and denoised luminance (Yd NULL without denoising) */
  float *feat;    /* the features (VR_RESULT_FEATURES a pixel) when denoised */
  double seconds, denoise_seconds;
} run;

static run render(const vr_scene *s, vr_matdb *db, int spp, bool denoise, int threads) {
  vr_render_options o;
  vr_render_options_default(&o);
  o.spp = spp;
  o.threads = threads;
  o.denoise = denoise;
  o.film_without_bins = true;
  vr_render_result *r = NULL;
  vr_error err = {0};
  double t0 = now();
  if (vr_render_scene(s, db, &o, &r, &err)) die("render", &err);
  run out = {0};
  out.seconds = now() - t0;
  size_t px = (size_t)r->width * (size_t)r->height;
  out.Y = malloc(px * sizeof *out.Y);
  if (denoise) out.Yd = malloc(px * sizeof *out.Yd);
  if (!out.Y || (denoise && !out.Yd)) die("memory", NULL);
  for (size_t p = 0; p < px; p++) {
    out.Y[p] = r->xyz[3 * p + 1];
    if (denoise) out.Yd[p] = r->xyz_display[3 * p + 1];
  }
  out.denoise_seconds = r->denoise_seconds;
  out.feat = r->features;
  r->features = NULL;
  vr_render_result_destroy(r);
  return out;
}

/* The relative RMSE over all pixels and over the edge pixels; and over
 * 10 x 10 blocks of pixels (each block's luminance sum against the
 * reference's): a reference with fireflies of its own (a path-traced
 * room) puts its noise into every per-pixel figure, far less into the
 * blocks', which show what an integrator's bias does. */
static int g_W, g_H;
static void errors(const double *Y, const double *ref, const unsigned char *edge, size_t px,
                   double *all, double *edges, double *blocks) {
  const int B = 10;
  double sb = 0;
  int nb = 0;
  for (int by = 0; by + B <= g_H; by += B)
    for (int bx = 0; bx + B <= g_W; bx += B) {
      double a = 0, r = 0;
      for (int y = by; y < by + B; y++)
        for (int x = bx; x < bx + B; x++) {
          size_t p = (size_t)y * (size_t)g_W + (size_t)x;
          a += Y[p], r += ref[p];
        }
      if (r > 0) sb += (a / r - 1) * (a / r - 1), nb++;
    }
  *blocks = nb ? sqrt(sb / nb) : NAN;
  double mr = 0, s = 0, se = 0;
  size_t ne = 0;
  for (size_t p = 0; p < px; p++) mr += ref[p] / (double)px;
  for (size_t p = 0; p < px; p++) {
    double e = fabs(Y[p] - ref[p]) / fmax(ref[p], 0.01 * mr);
    s += e * e;
    if (edge[p]) se += e * e, ne++;
  }
  *all = sqrt(s / (double)px);
  *edges = ne ? sqrt(se / (double)ne) : NAN;
}

int main(int argc, char **argv) {
  if (argc < 3) {
    fprintf(stderr, "usage: bench_denoise SCENE.scn DB [--spp N] [--ref-spp M] [--resolution WxH] "
                    "[--threads P] [--ref-cache FILE] [--seed S] [--ref-scene REF.scn]\n");
    return 2;
  }
  const char *scene_path = argv[1], *db_path = argv[2], *cache = NULL, *ref_path = NULL;
  int spp = 16, ref_spp = 1024, threads = 2, W = 0, H = 0;
  long seed = -1;
  for (int i = 3; i + 1 < argc; i += 2) {
    if (!strcmp(argv[i], "--spp")) spp = atoi(argv[i + 1]);
    else if (!strcmp(argv[i], "--ref-spp")) ref_spp = atoi(argv[i + 1]);
    else if (!strcmp(argv[i], "--threads")) threads = atoi(argv[i + 1]);
    else if (!strcmp(argv[i], "--ref-cache")) cache = argv[i + 1];
    else if (!strcmp(argv[i], "--seed")) seed = atol(argv[i + 1]);
    else if (!strcmp(argv[i], "--ref-scene")) ref_path = argv[i + 1];
    else if (!strcmp(argv[i], "--resolution")) {
      if (sscanf(argv[i + 1], "%dx%d", &W, &H) != 2) die(argv[i + 1], NULL);
    } else {
      fprintf(stderr, "bench_denoise: unknown option %s\n", argv[i]);
      return 2;
    }
  }
  vr_error err = {0};
  vr_scene *s = NULL;
  vr_matdb *db = NULL;
  if (vr_scene_read(scene_path, &s, &err) || vr_scene_load_models(s, &err)) die(scene_path, &err);
  if (vr_matdb_open(db_path, VR_MATDB_READONLY, &db, &err)) die(db_path, &err);
  if (W > 0) s->camera.width = W, s->camera.height = H;
  W = s->camera.width;
  H = s->camera.height;
  size_t px = (size_t)W * (size_t)H;
  g_W = W, g_H = H;
  printf("scene %s, %d x %d, integrator and settings of its render line, %d threads\n",
         scene_path, W, H, threads);

  /* The reference, from the cache when it is this one. */
  double *ref = malloc(px * sizeof *ref);
  unsigned char *edge = calloc(px, 1);
  float *feat = malloc(px * VR_RESULT_FEATURES * sizeof *feat);
  if (!ref || !edge || !feat) die("memory", NULL);
  bool have = false;
  char key[512];
  if (!ref_path) ref_path = scene_path;
  snprintf(key, sizeof key, "%s %dx%d %d", ref_path, W, H, ref_spp);
  FILE *f = cache ? fopen(cache, "rb") : NULL;
  if (f) {
    char k[512] = {0};
    have = fread(k, 1, sizeof k, f) == sizeof k && !strcmp(k, key) &&
           fread(ref, sizeof *ref, px, f) == px &&
           fread(feat, sizeof *feat, px * VR_RESULT_FEATURES, f) == px * VR_RESULT_FEATURES;
    fclose(f);
  }
  if (!have) {
    /* The reference takes another seed than the runs measured. */
    vr_scene *rsc = s;
    if (ref_path != scene_path) {
      if (vr_scene_read(ref_path, &rsc, &err) || vr_scene_load_models(rsc, &err))
        die(ref_path, &err);
      rsc->camera.width = W, rsc->camera.height = H;
    }
    unsigned long long keep = rsc->settings.seed;
    rsc->settings.seed = keep + 1000003u;
    run r = render(rsc, db, ref_spp, true, threads);
    rsc->settings.seed = keep;
    if (rsc != s) vr_scene_destroy(rsc);
    memcpy(ref, r.Y, px * sizeof *ref);
    memcpy(feat, r.feat, px * VR_RESULT_FEATURES * sizeof *feat);
    free(r.Y);
    free(r.Yd);
    free(r.feat);
    printf("reference: %s, %d spp in %.1f s\n", ref_path, ref_spp, r.seconds);
    if (cache && (f = fopen(cache, "wb"))) {
      char k[512] = {0};
      snprintf(k, sizeof k, "%s", key);
      fwrite(k, 1, sizeof k, f);
      fwrite(ref, sizeof *ref, px, f);
      fwrite(feat, sizeof *feat, px * VR_RESULT_FEATURES, f);
      fclose(f);
    }
  } else {
    printf("reference: %d spp (from %s)\n", ref_spp, cache);
  }
  if (seed >= 0) s->settings.seed = (unsigned long long)seed;
  size_t nedge = 0;
  for (int y = 0; y < H; y++)
    for (int x = 0; x < W; x++) {
      size_t p = (size_t)y * (size_t)W + (size_t)x;
      const int nb[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
      for (int k = 0; k < 4; k++) {
        int i = x + nb[k][0], j = y + nb[k][1];
        if (i < 0 || j < 0 || i >= W || j >= H) continue;
        const float *a = &feat[p * VR_RESULT_FEATURES];
        const float *b = &feat[((size_t)j * (size_t)W + (size_t)i) * VR_RESULT_FEATURES];
        double dalb = 0, dot = 0;
        for (int c = 0; c < 3; c++) dalb = fmax(dalb, fabs(a[c] - b[c])), dot += a[3 + c] * b[3 + c];
        if (dalb > 0.1 || dot < 0.9 || fabs(a[6] - b[6]) > 0.1 * fmax(a[6], b[6])) edge[p] = 1;
      }
      nedge += edge[p];
    }
  printf("edge pixels: %zu of %zu\n\n", nedge, px);
  printf("%-26s %9s %12s %12s %12s\n", "image", "seconds", "rel. RMSE", "at edges", "10x10 blocks");
  run d = render(s, db, spp, true, threads);
  double all, at, blk;
  errors(d.Y, ref, edge, px, &all, &at, &blk);
  printf("raw, %4d spp (halves)     %9.1f %12.4f %12.4f %12.4f\n", spp,
         d.seconds - d.denoise_seconds, all, at, blk);
  errors(d.Yd, ref, edge, px, &all, &at, &blk);
  printf("denoised, %4d spp         %9.1f %12.4f %12.4f %12.4f   (denoising %.2f s)\n", spp,
         d.seconds, all, at, blk, d.denoise_seconds);
  free(d.Y);
  free(d.Yd);
  free(d.feat);
  /* At 8N samples the filter has little noise to remove: where it blurs,
   * its edge error would exceed the raw film's. */
  d = render(s, db, 8 * spp, true, threads);
  errors(d.Yd, ref, edge, px, &all, &at, &blk);
  printf("denoised, %4d spp         %9.1f %12.4f %12.4f %12.4f   (denoising %.2f s)\n", 8 * spp,
         d.seconds, all, at, blk, d.denoise_seconds);
  for (int m = 2; m <= 16; m *= 2) {
    run r = render(s, db, m * spp, false, threads);
    errors(r.Y, ref, edge, px, &all, &at, &blk);
    printf("raw, %4d spp              %9.1f %12.4f %12.4f %12.4f\n", m * spp, r.seconds, all, at,
           blk);
    free(r.Y);
  }
  free(d.Y);
  free(d.Yd);
  free(d.feat);
  free(ref);
  free(edge);
  free(feat);
  vr_matdb_close(db);
  vr_scene_destroy(s);
  return 0;
}
