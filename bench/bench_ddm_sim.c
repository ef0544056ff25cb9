/* The paper's Table 1 by a calibrated, checked simulation (issue 31): the
 * discrete-event model of the ray flow (bench/sim/sim_flow.h) driven by
 * what real runs of vr-render record (--flow-profile), then checked
 * against real runs of 1 and 2 ranks on this machine before it predicts
 * the machines this one cannot be.
 *
 *   build/bench/bench_ddm_sim out/materials.db [--hotel DIR]
 *
 * Each measured figure is the median of REPS (3) runs; a first render is
 * not used.
 * 1. Profiles: the hotel floor's room view (vr-hotel into DIR, default
 *    build/bench-ddm, unless there) rendered alone, 1 thread, with
 *    --flow-profile at 1, 2, 4, 8 and 16 sub-domains: each cell's bytes,
 *    load time, rays and cost per ray, and where its rays go.  The cost of
 *    the profile's own clock reads (measured here) is taken off each ray;
 *    the loads' total is that of plain runs (no profile) at the same S.
 * 2. The machine, measured apart from the runs the model is checked on:
 *    two independent one-process renders at once against one alone give
 *    how much a busy core slows another's loads and tracing, at 16
 *    sub-domains and at 1 (the whole floor in one build, as image space
 *    and 1 sub-domain load it).
 * 3. The check: the model against real runs here (2 cores): 1 rank, 2
 *    ranks, 2 ranks in image space, 1 rank with 2 threads (16
 *    sub-domains), the render's own time (--stats seconds_total).
 * 4. The prediction: 1, 2, 4, 8 sub-domains x 16, 32, 64, 128 threads on
 *    4 nodes x 4 cores and on 16 nodes x 8 cores (a rank a node, 10 Gbit/s
 *    Ethernet between nodes: 50 us, 1.25 GB/s), image space beside; the
 *    same view at 64 spp on 16 x 8; and a scene 4 x larger than a node's
 *    memory (each rank's budget a quarter of the floor's cells), where
 *    image space cannot run. */
#define _GNU_SOURCE
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <stdatomic.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <ftw.h>
#include <time.h>
#include <unistd.h>

#include "bench_child.h"
#include "sim/sim_flow.h"
#include "sim/sim_profile.h"
#include "vr/file.h"

static const char *db;
static char vr_render[4300], dir[4200], hscene[4300], cache[4400];

typedef struct run_out {
  double seconds, load_s, camera_s;
} run_out;

/* One real render of the hotel floor; its statistics' text in *text. */
static run_out render(const char *name, int ranks, int threads, int S, bool image_space,
                      bool profile, char **text) {
  char prefix[4400], stats[4500], log[4500], r[16];
  snprintf(prefix, sizeof prefix, "%s/%s", dir, name);
  snprintf(stats, sizeof stats, "%s.json", prefix);
  snprintf(log, sizeof log, "%s.log", prefix);
  snprintf(r, sizeof r, "%d", ranks);
  char *argv[48];
  int n = 0;
  if (ranks > 1) {
    argv[n++] = "mpirun", argv[n++] = "--oversubscribe";
    if (!geteuid()) argv[n++] = "--allow-run-as-root";
    argv[n++] = "-np", argv[n++] = r;
  }
  bench_render_opts ro = {.vr_render = vr_render, .scene = hscene, .db = db, .prefix = prefix,
                          .stats = stats, .cache = cache, .subdomains = S, .threads = threads};
  n = bench_render_args(argv, n, &ro);
  if (image_space) argv[n++] = "--image-space";
  if (profile) argv[n++] = "--flow-profile";
  argv[n++] = "--outputs", argv[n++] = "exr";
  argv[n] = NULL;
  double wall;
  if (bench_run_timed(argv, log, &wall)) {
    char why[512];
    bench_log_reason(log, why, sizeof why);
    fprintf(stderr, "bench_ddm_sim: %s: %s\n", name, why);
    bench_die("a render failed");
  }
  size_t len;
  char *t = NULL;
  if (vr_read_file(stats, 0, &t, &len, NULL)) bench_die("no statistics");
  run_out o = {bench_json_num(t, "seconds_total"), bench_json_num(t, "load_seconds"),
               bench_pass_seconds(t, "camera")};
  if (text) *text = t;
  else free(t);
  return o;
}

/* The mean cost of what --flow-profile adds to each ray: two clock reads
 * and two relaxed atomic additions. */
static double clock_cost(void) {
  _Atomic unsigned long long sink = 0;
  struct timespec a, b;
  int n = 2000000;
  double t0 = bench_now();
  for (int i = 0; i < n; i++) {
    clock_gettime(CLOCK_MONOTONIC, &a);
    clock_gettime(CLOCK_MONOTONIC, &b);
    atomic_fetch_add_explicit(&sink, (unsigned long long)(b.tv_nsec - a.tv_nsec), memory_order_relaxed);
    atomic_fetch_add_explicit(&sink, 1, memory_order_relaxed);
  }
  return (bench_now() - t0) / n;
}

/* Reads every file under a folder once, so that the page cache holds the
 * cells: profiles taken with cold files would charge the disk to the
 * loads, and the checks that follow run warm. */
static long long warm_bytes;
static int warm_one(const char *path, const struct stat *st, int type, struct FTW *ftw) {
  (void)st, (void)ftw;
  if (type != FTW_F) return 0;
  FILE *fp = fopen(path, "rb");
  if (!fp) return 0;
  static char buf[1 << 20];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, fp)) > 0) warm_bytes += (long long)n;
  fclose(fp);
  return 0;
}

static void warm(const char *folder) { nftw(folder, warm_one, 16, FTW_PHYS); }

/* Each measured figure (profiles and checks) is the median of REPS runs:
 * loads vary by 10-20 % from run to run on this machine. */
#define REPS 3

static double median(const double *v, int n) {
  double s[16];
  for (int i = 0; i < n; i++) s[i] = v[i];
  for (int i = 1; i < n; i++)
    for (int j = i; j > 0 && s[j] < s[j - 1]; j--) {
      double t = s[j];
      s[j] = s[j - 1], s[j - 1] = t;
    }
  return n % 2 ? s[n / 2] : 0.5 * (s[n / 2 - 1] + s[n / 2]);
}

/* Two independent one-process renders (1 thread, S sub-domains) at once:
 * their mean load seconds and camera pass. */
static run_out pair(int S) {
  char prefix[2][4400], stats[2][4500], logs[2][4500];
  pid_t pid[2];
  for (int k = 0; k < 2; k++) {
    snprintf(prefix[k], sizeof prefix[k], "%s/pair-s%d-%d", dir, S, k);
    snprintf(stats[k], sizeof stats[k], "%s/pair-s%d-%d.json", dir, S, k);
    snprintf(logs[k], sizeof logs[k], "%s/pair-s%d-%d.log", dir, S, k);
    char *av[40];
    bench_render_opts ro = {.vr_render = vr_render, .scene = hscene, .db = db, .prefix = prefix[k],
                            .stats = stats[k], .cache = cache, .subdomains = S, .threads = 1};
    int n = bench_render_args(av, 0, &ro);
    av[n++] = "--outputs", av[n++] = "exr";
    av[n] = NULL;
    pid[k] = fork();
    if (pid[k] == 0) _exit(bench_run(av, logs[k]));
  }
  run_out both = {0};
  for (int k = 0; k < 2; k++) {
    int st;
    waitpid(pid[k], &st, 0);
    char *t = NULL;
    size_t len;
    if (!WIFEXITED(st) || WEXITSTATUS(st) || vr_read_file(stats[k], 0, &t, &len, NULL))
      bench_die("a concurrent render failed");
    both.load_s += bench_json_num(t, "load_seconds") / 2;
    both.camera_s += bench_pass_seconds(t, "camera") / 2;
    free(t);
  }
  return both;
}

/* One row of a predicted grid: the first nS profiles (1, 2, 4, ...
 * sub-domains) and image space on machine c, as speedups over ref
 * seconds.  The whole floor's build (1 sub-domain, image space) takes its
 * own contention; the others c's. */
static void grid_row(sim_config c, int nS, double ref, const sim_profile *prof, const double *prepare,
                     double whole_contention) {
  double cells_contention = c.load_contention;
  for (int si = 0; si < nS; si++) {
    c.prepare_s = prepare[si];
    c.load_contention = si ? cells_contention : whole_contention;
    sim_result r;
    if (!sim_run(&prof[si], &c, &r)) bench_die("the model stalled");
    printf(" %.1f× (%.1f s) |", ref / r.seconds, r.seconds);
  }
  c.image_space = true, c.prepare_s = prepare[0], c.load_contention = whole_contention;
  sim_result ri;
  sim_run(&prof[0], &c, &ri);
  printf(" %.1f× (%.1f s) |\n", ref / ri.seconds, ri.seconds);
  fflush(stdout);
}

static double pct(double model, double real) { return 100 * (model - real) / real; }

int main(int argc, char **argv) {
  if (argc < 2) bench_die("usage: bench_ddm_sim DATABASE [--hotel DIR] (see bench/bench_ddm_sim.c)");
  db = argv[1];
  const char *hotel = NULL;
  for (int i = 2; i < argc; i++) {
    if (!strcmp(argv[i], "--hotel") && i + 1 < argc) hotel = argv[++i];
    else bench_die("unknown option");
  }
  char hdir[4200];
  snprintf(hdir, sizeof hdir, "%s", hotel ? hotel : VR_BINARY_DIR "/bench-ddm");
  snprintf(dir, sizeof dir, "%s/bench-ddm-sim", VR_BINARY_DIR);
  mkdir(dir, 0755);
  snprintf(vr_render, sizeof vr_render, "%s/render/vr-render", VR_BINARY_DIR);
  snprintf(hscene, sizeof hscene, "%s/hotel.scn", hdir);
  snprintf(cache, sizeof cache, "%s/cache", hdir);
  if (access(hscene, R_OK)) {
    char vr_hotel[4300], log[4400];
    snprintf(vr_hotel, sizeof vr_hotel, "%s/samples/hotel/vr-hotel", VR_BINARY_DIR);
    snprintf(log, sizeof log, "%s/vr-hotel.log", dir);
    char *av[] = {vr_hotel, hdir, NULL};
    if (bench_run(av, log)) bench_die("vr-hotel failed");
  }

  /* 1. Profiles. */
  const int Ss[] = {1, 2, 4, 8, 16};
  sim_profile prof[5];
  double prepare[5];
  run_out alone[5];
  double dclock = clock_cost();
  printf("## The decomposition by simulation (hotel floor, room view)\n\n");
  printf("### Profiles (one process, 1 thread, --flow-profile)\n\n");
  /* Every cell file read once first (the cache folders of all S). */
  warm(cache);
  printf("cell files read once before the runs: %.2f GB; each figure the median of %d runs\n\n",
         warm_bytes / 1e9, REPS);
  printf("profile clock cost taken off each ray: %.0f ns\n\n", dclock * 1e9);
  printf("| S | cells loaded | rays | tracing | loads (plain runs) | largest cell's share of the tracing |\n|---|---|---|---|---|---|\n");
  /* A first render, not used: the first after the files were read ran
   * 20-40 % slower in its loads. */
  render("warm-up", 1, 1, 16, false, false, NULL);
  for (int i = 0; i < 5; i++) {
    /* REPS profiles; the cells' load times, the rays' costs and the
     * prepare pass are each the median (the rays are the same each time:
     * the sampler is deterministic). */
    sim_profile rep[REPS];
    double prep[REPS];
    for (int j = 0; j < REPS; j++) {
      char name[32], *text = NULL, msg[256];
      snprintf(name, sizeof name, "profile-s%d-%d", Ss[i], j);
      render(name, 1, 1, Ss[i], false, true, &text);
      if (!sim_profile_read(text, &rep[j], msg, sizeof msg)) bench_die(msg);
      /* The prepare pass of one process without a budget includes loading
       * every cell, which the model does itself. */
      prep[j] = bench_pass_seconds(text, "prepare") - bench_json_num(text, "load_seconds");
      free(text);
      if (rep[j].S != rep[0].S || rep[j].npasses != rep[0].npasses) bench_die("profiles differ in shape");
    }
    prof[i] = rep[0];
    prepare[i] = median(prep, REPS);
    double v[REPS];
    for (int c = 0; c < prof[i].S; c++) {
      for (int j = 0; j < REPS; j++) v[j] = rep[j].load_s[c];
      prof[i].load_s[c] = median(v, REPS);
      for (int k = 0; k < prof[i].npasses; k++) {
        for (int j = 0; j < REPS; j++) v[j] = rep[j].pass[k].cost[c];
        prof[i].pass[k].cost[c] = median(v, REPS);
      }
    }
    for (int j = 1; j < REPS; j++) sim_profile_free(&rep[j]);
    /* Loads: the profile gives each cell's share; the total is the median
     * of REPS plain runs (no profile), which is what the checks and the
     * predictions are about.  (The profiled loads measured 5-20 % slower
     * than plain runs' on this machine, the first run after the cell
     * files were read most: memory the kernel had to reclaim.) */
    double plain[REPS], cam[REPS], pload = 0;
    for (int j = 0; j < REPS; j++) {
      char name[32];
      snprintf(name, sizeof name, "plain-s%d-%d", Ss[i], j);
      run_out o = render(name, 1, 1, Ss[i], false, false, NULL);
      plain[j] = o.load_s, cam[j] = o.camera_s;
    }
    alone[i] = (run_out){0, median(plain, REPS), median(cam, REPS)};
    for (int c = 0; c < prof[i].S; c++) pload += prof[i].load_s[c];
    for (int c = 0; pload > 0 && c < prof[i].S; c++) prof[i].load_s[c] *= alone[i].load_s / pload;
    double load = 0, trace = 0, most = 0;
    for (int c = 0; c < prof[i].S; c++) load += prof[i].load_s[c];
    for (int k = 0; k < prof[i].npasses; k++)
      for (int c = 0; c < prof[i].S; c++) {
        sim_pass *ps = &prof[i].pass[k];
        ps->cost[c] = fmax(0, ps->cost[c] - dclock);
        double t = ps->rays[c] * ps->cost[c];
        trace += t;
        if (t > most) most = t;
      }
    printf("| %d | %d | %.0f | %.2f s | %.2f s (profiled %.2f s) | %.0f %% |\n", Ss[i], prof[i].S,
           sim_pass_rays(&prof[i], 0), trace, load, pload, trace > 0 ? 100 * most / trace : 0);
    fflush(stdout);
  }

  /* 2. The machine: two independent processes at once against one. */
  /* At 16 sub-domains (the checks' cells) and at 1 (image space's whole
   * scene in one Embree build). */
  run_out alone16 = alone[4], both16 = pair(16);
  run_out alone1 = alone[0], both1 = pair(1);
  sim_config base;
  sim_config_default(&base);
  base.load_contention = fmax(0, both16.load_s / alone16.load_s - 1);
  base.trace_contention = fmax(0, both16.camera_s / alone16.camera_s - 1);
  double whole_contention = fmax(0, both1.load_s / alone1.load_s - 1);
  base.ray_overhead = 0.6e-6; /* a ray sent, both ends (docs/ddm.md, measured on ranks) */
  /* Loads on two threads (Embree builds on the rank's threads), at 8
   * sub-domains: the profile's loads on one thread against these. */
  run_out two = render("loads-2threads", 1, 2, 8, false, false, NULL);
  double l1 = 0;
  for (int c = 0; c < prof[3].S; c++) l1 += prof[3].load_s[c];
  base.load_scaling = fmax(0, log2(l1 / two.load_s));
  printf("\n### This machine (2 cores), measured apart from the runs the model is checked on\n\n");
  printf("- one render alone against two at once, 16 sub-domains: loads %.2f s alone, %.2f s each "
         "with another; camera pass %.2f s alone, %.2f s each: a busy core slows another's loads by "
         "%.0f %% and its tracing by %.0f %%\n",
         alone16.load_s, both16.load_s, alone16.camera_s, both16.camera_s, 100 * base.load_contention,
         100 * base.trace_contention);
  printf("- the same with 1 sub-domain (the whole floor, as image space loads it): loads %.2f s "
         "alone, %.2f s each with another: %.0f %%\n",
         alone1.load_s, both1.load_s, 100 * whole_contention);
  printf("- 8 sub-domains loaded on one thread %.2f s, on two %.2f s: a load on T threads runs "
         "T^%.2f times as fast\n\n", l1, two.load_s, base.load_scaling);

  /* 3. The check against real runs here. */
  printf("### The model against real runs (16 sub-domains unless image space; the render's own time)\n\n");
  printf("| run | measured | model | difference |\n|---|---|---|---|\n");
  struct {
    const char *name;
    int ranks, threads;
    bool image;
  } checks[] = {{"1 rank x 1 thread", 1, 1, false},
                {"2 ranks x 1 thread", 2, 1, false},
                {"2 ranks x 1 thread, image space", 2, 1, true},
                {"1 rank x 2 threads", 1, 2, false}};
  double worst = 0;
  for (int k = 0; k < 4; k++) {
    char name[64];
    double t[REPS];
    for (int j = 0; j < REPS; j++) {
      snprintf(name, sizeof name, "check-%d-%d", k, j);
      t[j] = render(name, checks[k].ranks, checks[k].threads, 16, checks[k].image, false, NULL).seconds;
    }
    run_out real = {.seconds = median(t, REPS)};
    sim_config c = base;
    c.nodes = 1, c.cores = 2, c.ranks = checks[k].ranks, c.threads = checks[k].threads;
    c.image_space = checks[k].image;
    if (c.image_space) c.load_contention = whole_contention;
    c.prepare_s = checks[k].image ? prepare[0] : prepare[4];
    sim_result r;
    if (!sim_run(checks[k].image ? &prof[0] : &prof[4], &c, &r)) bench_die("the model stalled");
    double d = pct(r.seconds, real.seconds);
    if (fabs(d) > worst) worst = fabs(d);
    printf("| %s | %.2f s | %.2f s | %+.1f %% |\n", checks[k].name, real.seconds, r.seconds, d);
    fflush(stdout);
  }
  printf("\nlargest difference: %.1f %% (the target: 15 %%)\n\n", worst);

  /* 4. The prediction. */
  const int nodes[] = {4, 16}, cores[] = {4, 8}, totals[] = {16, 32, 64, 128};
  sim_config one = base;
  one.prepare_s = prepare[0];
  one.load_contention = whole_contention;
  sim_result r1;
  if (!sim_run(&prof[0], &one, &r1)) bench_die("the model stalled");
  for (int mi = 0; mi < 2; mi++) {
    printf("### Predicted: %d nodes x %d cores, a rank a node (speedup over 1 thread, 1 sub-domain: %.1f s)\n\n",
           nodes[mi], cores[mi], r1.seconds);
    printf("| threads | 1 sub-domain | 2 | 4 | 8 | image space |\n|---|---|---|---|---|---|\n");
    for (int ti = 0; ti < 4; ti++) {
      sim_config c = base;
      c.nodes = nodes[mi], c.cores = cores[mi], c.ranks = nodes[mi];
      c.threads = totals[ti] / nodes[mi];
      printf("| %d |", totals[ti]);
      grid_row(c, 4, r1.seconds, prof, prepare, whole_contention);
    }
    printf("\n");
  }
  /* The same view at 64 spp: each profile's units eight times over (the
   * loads stay, the tracing grows). */
  for (int i = 0; i < 5; i++)
    for (int k = 0; k < prof[i].npasses; k++) prof[i].pass[k].units *= 8, prof[i].pass[k].gen_s *= 8;
  sim_result r64;
  one.prepare_s = prepare[0];
  if (!sim_run(&prof[0], &one, &r64)) bench_die("the model stalled");
  printf("### Predicted at 64 spp: 16 nodes x 8 cores, a rank a node (speedup over 1 thread, 1 sub-domain: %.1f s)\n\n",
         r64.seconds);
  printf("| threads | 1 sub-domain | 2 | 4 | 8 | 16 | image space |\n|---|---|---|---|---|---|---|\n");
  for (int ti = 0; ti < 4; ti++) {
    sim_config c = base;
    c.nodes = 16, c.cores = 8, c.ranks = 16, c.threads = totals[ti] / 16;
    printf("| %d |", totals[ti]);
    grid_row(c, 5, r64.seconds, prof, prepare, whole_contention);
  }
  printf("\n");
  for (int i = 0; i < 5; i++)
    for (int k = 0; k < prof[i].npasses; k++) prof[i].pass[k].units /= 8, prof[i].pass[k].gen_s /= 8;
  double scene = 0;
  for (int c = 0; c < prof[4].S; c++) scene += prof[4].bytes[c];
  printf("### Predicted: the floor 4 x larger than a node's memory (each rank's budget %.0f MiB, a quarter of its cells)\n\n",
         scene / 4 / 1048576);
  printf("| machine | threads | 8 sub-domains | 16 sub-domains | image space |\n|---|---|---|---|---|\n");
  for (int mi = 0; mi < 2; mi++)
    for (int ti = 0; ti < 4; ti++) {
      sim_config c = base;
      c.nodes = nodes[mi], c.cores = cores[mi], c.ranks = nodes[mi];
      c.threads = totals[ti] / nodes[mi];
      c.budget = scene / 4;
      printf("| %d x %d | %d |", nodes[mi], cores[mi], totals[ti]);
      const int pi[] = {3, 4};
      for (int k = 0; k < 2; k++) {
        c.prepare_s = prepare[pi[k]];
        sim_result r;
        if (!sim_run(&prof[pi[k]], &c, &r)) printf(" stalls |");
        else printf(" %.1f× (%.1f s, %.0f loads) |", r1.seconds / r.seconds, r.seconds, r.loads);
      }
      c.image_space = true, c.load_contention = whole_contention;
      sim_result ri;
      sim_run(&prof[0], &c, &ri);
      printf(" %s |\n", ri.refused ? "does not fit" : "runs");
      fflush(stdout);
    }
  printf("\n");
  for (int i = 0; i < 5; i++) sim_profile_free(&prof[i]);
  return 0;
}
