/* Prints what the domain decomposition costs and saves (docs/ddm.md).
 * Every render is the real vr-render, run as a child process and read
 * back through its --stats JSON and its RGB EXR, so the figures are the
 * tool's own, end to end.
 *
 * (1) The large scene: a hotel floor from vr-hotel (samples/hotel; 24
 *     rooms, 20.5 million triangles by default), 16 sub-domains, 2 threads,
 *     two views (inside a room, down the corridor).  For each view:
 *       - no budget: wall time, peak RSS P, the time spent loading;
 *       - budgets of P/2, P/4 and P/8: wall time, peak RSS, loads, unloads,
 *         bytes read, time loading, rays spilled, and the largest difference
 *         of the image from the unbudgeted one (relative, per value);
 *     then, for the room view, a cap on the address space (prlimit --as,
 *     2/3 of P) that the unbudgeted render cannot stay under, with both
 *     outcomes: without a budget it fails, with a budget of P/4 it renders.
 * (2) The sample room (samples/room.scn, its own settings, 1 thread):
 *     S = 8 against S = 1, best of three.
 * (3) Memory per worker at S = 8 with two cells loaded against the
 *     replicated scene (S = 1), measured by loading cells in this process
 *     (their arrays plus what Embree's memory monitor counts).
 *
 *     build/bench/bench_ddm out/materials.db [--rooms N] [--detail D]
 *                           [--dir DIR] [--skip-large] [--skip-room]
 *
 * The database is the one the main job fills (scripts/main-job.sh).  The
 * hotel is written to DIR (default build/bench-ddm) unless it is there. */
#define _GNU_SOURCE
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <spawn.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "bench_child.h"
#include "vr/domains.h"
#include "vr/file.h"
#include "vr/image.h"
#include "vr/models.h"
#include "vr/scene.h"

#define now bench_now
#define die bench_die
#define run bench_run
#define json_num bench_json_num
#define pass_seconds bench_pass_seconds
#define image_diff bench_image_diff

typedef struct outcome {
  int status;
  double wall, total, camera, load_s, rss, cells, queues, spilled;
  double loads, unloads, bytes, crossings;
  char msg[512];
} outcome;

static outcome render(const char *vr_render, const char *scene, const char *db, const char *cache,
                      const char *prefix, int S, int threads, long long budget, long long cap,
                      const char *spp) {
  char stats[4200], log[4200], asopt[64];
  snprintf(stats, sizeof stats, "%s.json", prefix);
  snprintf(log, sizeof log, "%s.log", prefix);
  snprintf(asopt, sizeof asopt, "--as=%lld", cap);
  char *argv[32];
  int n = 0;
  if (cap > 0) argv[n++] = "prlimit", argv[n++] = asopt;
  bench_render_opts ro = {.vr_render = vr_render, .scene = scene, .db = db, .prefix = prefix,
                          .stats = stats, .cache = cache, .spp = spp, .subdomains = S,
                          .threads = threads, .budget = budget};
  n = bench_render_args(argv, n, &ro);
  argv[n] = NULL;
  unlink(stats);
  outcome o = {0};
  o.status = bench_run_timed(argv, log, &o.wall);
  char *text = NULL;
  size_t len;
  bench_log_reason(log, o.msg, sizeof o.msg);
  if (o.status == 0 && !vr_read_file(stats, 0, &text, &len, NULL)) {
    o.total = json_num(text, "seconds_total");
    o.camera = pass_seconds(text, "camera");
    o.rss = json_num(text, "peak_rss_bytes");
    o.loads = json_num(text, "loads");
    o.unloads = json_num(text, "unloads");
    o.bytes = json_num(text, "bytes_read");
    o.load_s = json_num(text, "load_seconds");
    o.cells = json_num(text, "peak_cells_bytes");
    o.queues = json_num(text, "peak_queue_bytes");
    o.spilled = json_num(text, "rays_spilled");
    o.crossings = json_num(text, "crossings");
    free(text);
  }
  return o;
}

static double mib(double b) { return b / 1048576.0; }

static void large(const char *bin, const char *db, const char *dir, int rooms, int detail) {
  char scene[8192], corridor[8192], cache[8192], vr_render[8192], vr_hotel[8192];
  snprintf(vr_render, sizeof vr_render, "%s/render/vr-render", bin);
  snprintf(vr_hotel, sizeof vr_hotel, "%s/samples/hotel/vr-hotel", bin);
  snprintf(scene, sizeof scene, "%s/hotel.scn", dir);
  snprintf(corridor, sizeof corridor, "%s/hotel_corridor.scn", dir);
  snprintf(cache, sizeof cache, "%s/cache", dir);
  if (access(scene, R_OK)) {
    char r[32], d[32], log[9000];
    snprintf(r, sizeof r, "%d", rooms);
    snprintf(d, sizeof d, "%d", detail);
    snprintf(log, sizeof log, "%s.log", scene);
    mkdir(dir, 0755);
    char *argv[] = {vr_hotel, "--rooms", r, "--detail", d, (char *)dir, NULL};
    if (run(argv, log)) die("vr-hotel failed");
  }
  printf("## (1) The large scene: %s (vr-hotel --rooms %d --detail %d), 16 sub-domains, 2 threads, 8 spp\n\n",
         dir, rooms, detail);
  /* The cache first, once, so that no line below pays for building it. */
  char prefix[9000];
  snprintf(prefix, sizeof prefix, "%s/warm", dir);
  double t0 = now();
  outcome w = render(vr_render, scene, db, cache, prefix, 16, 2, 0, 0, "1");
  if (w.status) die(w.msg);
  printf("cache ready (%.1f s incl. a 1-spp render)\n\n", now() - t0);
  const char *views[2] = {scene, corridor}, *names[2] = {"room", "corridor"};
  for (int v = 0; v < 2; v++) {
    printf("view: %s\n\n", names[v]);
    printf("| budget | wall time | x unbudgeted | peak RSS | loads | unloads | read | loading | rays spilled | image vs unbudgeted |\n");
    printf("|---|---|---|---|---|---|---|---|---|---|\n");
    char ref[9000];
    snprintf(ref, sizeof ref, "%s/%s-none", dir, names[v]);
    outcome u = render(vr_render, views[v], db, cache, ref, 16, 2, 0, 0, NULL);
    if (u.status) die(u.msg);
    printf("| none | %.1f s | 1 | %.0f MiB | %.0f | %.0f | %.0f MiB | %.1f s | %.0f | - |\n", u.wall,
           mib(u.rss), u.loads, u.unloads, mib(u.bytes), u.load_s, u.spilled);
    char refexr[9200];
    snprintf(refexr, sizeof refexr, "%s.exr", ref);
    for (int k = 2; k <= 8; k *= 2) {
      long long b = (long long)(u.rss / k);
      char pre[9000], exr[9200];
      snprintf(pre, sizeof pre, "%s/%s-%d", dir, names[v], k);
      snprintf(exr, sizeof exr, "%s.exr", pre);
      outcome o = render(vr_render, views[v], db, cache, pre, 16, 2, b, 0, NULL);
      if (o.status) {
        printf("| P/%d = %.0f MiB | failed: %s |\n", k, mib((double)b), o.msg);
        continue;
      }
      printf("| P/%d = %.0f MiB | %.1f s | %.2f | %.0f MiB | %.0f | %.0f | %.0f MiB | %.1f s | %.0f | %.1e |\n",
             k, mib((double)b), o.wall, o.wall / u.wall, mib(o.rss), o.loads, o.unloads,
             mib(o.bytes), o.load_s, o.spilled, image_diff(refexr, exr));
    }
    printf("\n");
    if (v == 0) {
      long long cap = (long long)(u.rss * 2 / 3), b = (long long)(u.rss / 4);
      setenv("MALLOC_ARENA_MAX", "2", 1);
      char pre[9000];
      snprintf(pre, sizeof pre, "%s/capped-none", dir);
      outcome c0 = render(vr_render, views[v], db, cache, pre, 16, 2, 0, cap, NULL);
      snprintf(pre, sizeof pre, "%s/capped-budget", dir);
      outcome c1 = render(vr_render, views[v], db, cache, pre, 16, 2, b, cap, NULL);
      unsetenv("MALLOC_ARENA_MAX");
      char exr[9200];
      snprintf(exr, sizeof exr, "%s.exr", pre);
      printf("Under `prlimit --as=%lld` (%.0f MiB of address space, 2/3 of the unbudgeted peak RSS; MALLOC_ARENA_MAX=2):\n",
             cap, mib((double)cap));
      printf("- no budget: exit %d, %s\n", c0.status, c0.status ? c0.msg : "rendered (the cap did not bite)");
      if (c1.status)
        printf("- budget %.0f MiB: exit %d, %s\n\n", mib((double)b), c1.status, c1.msg);
      else
        printf("- budget %.0f MiB: exit 0, %.1f s, peak RSS %.0f MiB, image vs unbudgeted %.1e\n\n",
               mib((double)b), c1.wall, mib(c1.rss), image_diff(refexr, exr));
    }
  }
}

static void sample_room(const char *bin, const char *db) {
  char vr_render[4200], scene[4200], dir[9000];
  snprintf(vr_render, sizeof vr_render, "%s/render/vr-render", bin);
  snprintf(scene, sizeof scene, "%s/samples/room.scn", VR_SOURCE_DIR);
  snprintf(dir, sizeof dir, "%s/bench-ddm-room", bin);
  mkdir(dir, 0755);
  printf("## (2) The sample room at its own settings, 1 thread (best of 3)\n\n");
  printf("| S | whole render | camera pass | crossings |\n|---|---|---|---|\n");
  double best[2] = {INFINITY, INFINITY};
  for (int s = 0; s < 2; s++) {
    int S = s ? 8 : 1;
    double cam = INFINITY, cross = 0;
    for (int i = 0; i < 3; i++) {
      char pre[9200];
      snprintf(pre, sizeof pre, "%s/S%d", dir, S);
      outcome o = render(vr_render, scene, db, dir, pre, S, 1, 0, 0, NULL);
      if (o.status) die(o.msg);
      if (o.total < best[s]) best[s] = o.total, cam = o.camera, cross = o.crossings;
    }
    printf("| %d | %.2f s | %.2f s | %.0f |\n", S, best[s], cam, cross);
  }
  printf("\nS = 8 costs %.3f x S = 1.\n\n", best[1] / best[0]);
}

static void worker_memory(const char *path, const char *cache) {
  vr_scene *s = NULL;
  vr_error err = {0};
  if (vr_scene_read(path, &s, &err) || vr_scene_load_models(s, &err)) die(err.message);
  size_t held[2] = {0};
  for (int k = 0; k < 2; k++) {
    vr_domains_options o;
    vr_domains_options_default(&o);
    o.subdomains = k ? 8 : 1;
    o.cache_dir = cache;
    o.threads = 2;
    vr_domains *d = NULL;
    if (vr_domains_open(s, &o, &d, &err)) die(err.message);
    /* S = 1: the one cell.  S = 8: the two largest cells. */
    int first = 0, second = -1;
    for (int c = 1; c < vr_domains_count(d); c++)
      if (vr_domains_cell_bytes(d, c) > vr_domains_cell_bytes(d, first)) first = c;
    for (int c = 0; k && c < vr_domains_count(d); c++)
      if (c != first && (second < 0 || vr_domains_cell_bytes(d, c) > vr_domains_cell_bytes(d, second)))
        second = c;
    if (vr_domains_load(d, first, &err) || (second >= 0 && vr_domains_load(d, second, &err)))
      die(err.message);
    vr_domains_stats st;
    vr_domains_get_stats(d, &st);
    held[k] = st.geometry_bytes + st.embree_bytes;
    printf("%s: %zu B of arrays + %zu B of Embree = %zu B\n",
           k ? "S = 8, the two largest cells loaded" : "S = 1, the replicated scene",
           st.geometry_bytes, st.embree_bytes, held[k]);
    vr_domains_destroy(d);
  }
  printf("ratio %.3f\n\n", (double)held[1] / (double)held[0]);
  vr_scene_destroy(s);
}

int main(int argc, char **argv) {
  if (argc < 2) die("usage: bench_ddm DATABASE [--rooms N] [--detail D] [--dir DIR] [--skip-large] [--skip-room]");
  const char *db = argv[1], *dir = NULL;
  int rooms = 24, detail = 100;
  bool skip_large = false, skip_room = false;
  for (int i = 2; i < argc; i++) {
    if (!strcmp(argv[i], "--rooms") && i + 1 < argc) rooms = atoi(argv[++i]);
    else if (!strcmp(argv[i], "--detail") && i + 1 < argc) detail = atoi(argv[++i]);
    else if (!strcmp(argv[i], "--dir") && i + 1 < argc) dir = argv[++i];
    else if (!strcmp(argv[i], "--skip-large")) skip_large = true;
    else if (!strcmp(argv[i], "--skip-room")) skip_room = true;
    else die("unknown option");
  }
  char def[4200];
  snprintf(def, sizeof def, "%s/bench-ddm", VR_BINARY_DIR);
  if (!dir) dir = def;
  if (access(db, R_OK)) die("no database: run scripts/main-job.sh first");
  if (!skip_large) large(VR_BINARY_DIR, db, dir, rooms, detail);
  if (!skip_room) sample_room(VR_BINARY_DIR, db);
  printf("## (3) Memory per worker: S = 8 with two cells loaded against S = 1\n\n");
  char room[4200], hotel[9000], cache[9000];
  snprintf(room, sizeof room, "%s/samples/room.scn", VR_SOURCE_DIR);
  printf("samples/room.scn:\n");
  worker_memory(room, NULL);
  snprintf(hotel, sizeof hotel, "%s/hotel.scn", dir);
  snprintf(cache, sizeof cache, "%s/cache", dir);
  if (!access(hotel, R_OK)) {
    printf("%s:\n", hotel);
    worker_memory(hotel, cache);
  }
  return 0;
}
