/* Prints how fast the photon map (vr/photon_map.h) stores, builds and
 * answers density estimates, and what it costs: 1e6 photons on the six
 * faces of a 5 x 4 x 3 m room (spread by area, travelling into the face),
 * queried at random points of the faces with k = 50 nearest photons, with
 * a fixed radius holding about as many, on one thread and on every core.
 * Photons come in two kinds: 16 bins over 380-700 nm, all non-zero, in a
 * dense map; and the renderer's kind, 47 bins of 10 nm over 360-830 nm of
 * which 4 hero wavelengths fill at most 4, in a dense map and in sparse maps
 * (vr_photon_map_create_sparse) keeping 4 and 8 pairs.  The photons and
 * queries of one kind are the same for every map, so the checksum of the
 * estimates (the sum of every bin of every k = 50 box estimate) must agree
 * to the last digit.  Resident memory comes from /proc/self/statm (Linux).
 * Figures go to docs/benchmarks.md. */
#include "vr/photon_map.h"

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include <unistd.h>

#define NPHOTONS 1000000
#define MAXBINS 47
#define NQUERIES 200000
#define K 50

/* One map to measure. */
typedef struct config {
  const char *name;
  int nbins;
  double lo, hi;
  int hero;   /* wavelengths a photon carries; 0: every bin has power */
  int max_nz; /* sparse map keeping this many pairs; 0: dense */
} config;

static const config CONFIGS[] = {
    {"16 bins, all non-zero, dense", 16, 380, 700, 0, 0},
    {"47 bins, 4 hero wavelengths, dense", 47, 360, 830, 4, 0},
    {"47 bins, 4 hero wavelengths, sparse (max_nonzero 4)", 47, 360, 830, 4, 4},
    {"47 bins, 4 hero wavelengths, sparse (max_nonzero 8)", 47, 360, 830, 4, 8},
};

static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static uint64_t mix64(uint64_t z) {
  z += 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}
static double u01(uint64_t stream, uint64_t i) {
  return (double)(mix64(mix64(i) ^ (stream * 0xD1B54A32D192ED03ull)) >> 11) * 0x1.0p-53;
}

static const double ROOM[3] = {5, 4, 3};

/* A point on the room's faces, chosen by area, with the face's inward normal. */
static void room_point(uint64_t stream, uint64_t i, double p[3], double n[3]) {
  double area[3] = {ROOM[1] * ROOM[2], ROOM[0] * ROOM[2], ROOM[0] * ROOM[1]};
  double u = u01(stream, 4 * i) * 2 * (area[0] + area[1] + area[2]);
  int face = 0;
  while (face < 5 && u >= area[face / 2]) u -= area[face / 2], face++;
  int ax = face / 2;
  for (int a = 0; a < 3; a++) {
    p[a] = ROOM[a] * u01(stream, 4 * i + 1 + (uint64_t)a);
    n[a] = 0.0;
  }
  p[ax] = face % 2 ? ROOM[ax] : 0.0;
  n[ax] = face % 2 ? -1.0 : 1.0;
}

/* Resident memory in MB, or -1 where /proc/self/statm is missing. */
static double rss_mb(void) {
  FILE *f = fopen("/proc/self/statm", "r");
  long size, resident;
  int ok = f && fscanf(f, "%ld %ld", &size, &resident) == 2;
  if (f) fclose(f);
  return ok ? (double)resident * (double)sysconf(_SC_PAGESIZE) / 1e6 : -1.0;
}

static void photon(const config *c, const vr_photon_map *m, uint64_t i, double pos[3],
                   double dir[3], double nrm[3], float pw[MAXBINS]) {
  room_point(1, i, pos, nrm);
  /* a direction into the face: cosine-weighted about -n, near enough */
  double z = sqrt(u01(2, i)), phi = 2 * M_PI * u01(3, i), s = sqrt(1 - z * z);
  int ax = nrm[0] != 0 ? 0 : nrm[1] != 0 ? 1 : 2;
  dir[ax] = -z * nrm[ax];
  dir[(ax + 1) % 3] = s * cos(phi);
  dir[(ax + 2) % 3] = s * sin(phi);
  if (!c->hero) {
    for (int b = 0; b < c->nbins; b++)
      pw[b] = (float)(1e-6 * (0.5 + u01(4, i * (uint64_t)c->nbins + (uint64_t)b)));
    return;
  }
  /* hero wavelengths (Wilkie et al. 2014): one uniform, the others evenly
   * spaced from it and wrapped, as the renderer's vr_wavelengths */
  for (int b = 0; b < c->nbins; b++) pw[b] = 0.0f;
  double span = c->hi - c->lo, h = span * u01(5, i);
  for (int w = 0; w < c->hero; w++) {
    double x = h + span * w / c->hero;
    if (x >= span) x -= span;
    int b = vr_photon_map_bin(m, c->lo + x);
    if (b >= 0) pw[b] += (float)(1e-6 * (0.5 + u01(6, i * (uint64_t)c->hero + (uint64_t)w)));
  }
}

typedef struct job {
  const config *c;
  vr_photon_map *m;
  uint64_t lo, hi;
  int k;
  double radius, kc;
  double sink;
  long used;
} job;

static void *store_job(void *arg) {
  job *j = arg;
  for (uint64_t i = j->lo; i < j->hi; i++) {
    double pos[3], dir[3], nrm[3];
    float pw[MAXBINS];
    photon(j->c, j->m, i, pos, dir, nrm, pw);
    if (vr_photon_map_store(j->m, i, pos, dir, nrm, pw, NULL) != VR_OK) j->used++; /* refused */
  }
  return NULL;
}

static void *query_job(void *arg) {
  job *j = arg;
  double out[MAXBINS], r;
  int nb = vr_photon_map_nbins(j->m);
  for (uint64_t i = j->lo; i < j->hi; i++) {
    double x[3], n[3];
    room_point(9, i, x, n);
    int used = vr_photon_map_irradiance(j->m, x, n, j->k, j->radius, j->kc, out, &r);
    j->used += used;
    for (int b = 0; b < nb; b++) j->sink += out[b];
  }
  return NULL;
}

/* Runs fn over [0, count) on nthreads threads; returns the seconds taken,
 * the total of the jobs' counts (photons used, or stores refused) and of
 * their sinks. */
static double run(void *(*fn)(void *), const config *c, vr_photon_map *m, int nthreads,
                  uint64_t count, int k, double radius, double kc, long *used_out,
                  double *sink_out) {
  pthread_t th[64];
  job jobs[64];
  double t0 = now();
  for (int t = 0; t < nthreads; t++) {
    jobs[t] = (job){c, m, count * (uint64_t)t / (uint64_t)nthreads,
                    count * (uint64_t)(t + 1) / (uint64_t)nthreads, k, radius, kc, 0, 0};
    pthread_create(&th[t], NULL, fn, &jobs[t]);
  }
  long used = 0;
  double sink = 0.0;
  for (int t = 0; t < nthreads; t++) {
    pthread_join(th[t], NULL);
    used += jobs[t].used;
    sink += jobs[t].sink;
  }
  double dt = now() - t0;
  if (used_out) *used_out = used;
  if (sink_out) *sink_out = sink;
  return dt;
}

static vr_photon_map *create(const config *c, vr_error *err) {
  return c->max_nz ? vr_photon_map_create_sparse(c->nbins, c->lo, c->hi, c->max_nz, err)
                   : vr_photon_map_create(c->nbins, c->lo, c->hi, err);
}

/* Stores (on one thread, then on every core), builds and queries one map. */
static int bench(const config *c, int nthreads) {
  vr_error err;
  printf("\n%s\n", c->name);
  for (int pass = 0; pass < 2; pass++) {
    double rss0 = rss_mb();
    vr_photon_map *m = create(c, &err);
    if (!m) {
      fprintf(stderr, "bench_photon_map: %s\n", err.message);
      return 1;
    }
    int nt = pass ? nthreads : 1;
    long refused;
    double t_store = run(store_job, c, m, nt, NPHOTONS, 0, 0, 0, &refused, NULL);
    double rss_staged = rss_mb() - rss0;
    printf("  store, %d thread(s): %.3f s (%.1f M photons/s)\n", nt, t_store,
           NPHOTONS / t_store * 1e-6);
    if (refused) {
      fprintf(stderr, "bench_photon_map: %ld photons refused\n", refused);
      return 1;
    }
    if (pass == 0) {
      vr_photon_map_destroy(m);
      continue;
    }
    double t0 = now();
    if (vr_photon_map_build(m, &err) != VR_OK) {
      fprintf(stderr, "bench_photon_map: %s\n", err.message);
      return 1;
    }
    double t_build = now() - t0;
    double rss_built = rss_mb() - rss0;
    size_t bpp = vr_photon_map_bytes_per_photon(m);
    printf("  build (sort by key + balanced kd-tree): %.3f s\n", t_build);
    printf("  memory: %zu bytes/photon, %.1f MB built; resident growth %.0f MB staged, "
           "%.0f MB built\n",
           bpp, (double)bpp * NPHOTONS / 1e6, rss_staged, rss_built);

    /* the fixed radius that holds about K photons on a face */
    double area = 2 * (ROOM[0] * ROOM[1] + ROOM[0] * ROOM[2] + ROOM[1] * ROOM[2]);
    double rK = sqrt(K * area / (M_PI * NPHOTONS));
    struct {
      const char *name;
      int k;
      double radius, kc;
    } q[] = {{"k = 50, box", K, 0.5, 0.0},
             {"k = 50, cone kc = 1.1", K, 0.5, 1.1},
             {"fixed r (~50 photons), box", 0, rK, 0.0}};
    double checksum = 0.0;
    for (size_t i = 0; i < sizeof q / sizeof q[0]; i++)
      for (int threads = 1; threads <= nthreads; threads = threads == nthreads ? threads + 1 : nthreads) {
        long used;
        double sink;
        double dt = run(query_job, c, m, threads, NQUERIES, q[i].k, q[i].radius, q[i].kc, &used,
                        &sink);
        if (i == 0 && threads == 1) checksum = sink;
        printf("  %-28s %d thread(s): %9.0f queries/s (%.2f us each, %.1f photons used)\n",
               q[i].name, threads, NQUERIES / dt, dt / NQUERIES * 1e6 * threads,
               (double)used / NQUERIES);
      }
    printf("  checksum of the k = 50 box estimates: %.17g\n", checksum);
    vr_photon_map_destroy(m);
  }
  return 0;
}

/* Arguments, if any: the numbers (from 0) of the maps to measure, in the
 * order of CONFIGS above; by default all of them. */
int main(int argc, char **argv) {
  long ncpu = sysconf(_SC_NPROCESSORS_ONLN);
  int nthreads = ncpu < 1 ? 1 : ncpu > 64 ? 64 : (int)ncpu;
  int nconf = (int)(sizeof CONFIGS / sizeof CONFIGS[0]);
  printf("photon map: %d photons, room %gx%gx%g m, %d core(s)\n", NPHOTONS, ROOM[0], ROOM[1],
         ROOM[2], nthreads);
  for (int i = argc > 1 ? 1 : 0; i < (argc > 1 ? argc : nconf); i++) {
    int c = argc > 1 ? atoi(argv[i]) : i;
    if (c < 0 || c >= nconf) {
      fprintf(stderr, "bench_photon_map: no map %s (0 to %d)\n", argv[i], nconf - 1);
      return 2;
    }
    if (bench(&CONFIGS[c], nthreads)) return 1;
  }
  return 0;
}
