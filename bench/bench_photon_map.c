/* Prints how fast the photon map (vr/photon_map.h) stores, builds and
 * answers density estimates: 1e6 photons with 16 spectral bins on the six
 * faces of a 5 x 4 x 3 m room (spread by area, travelling into the face),
 * queried at random points of the faces with k = 50 nearest photons, with
 * a fixed radius holding about as many, on one thread and on every core.
 * Figures go to docs/benchmarks.md. */
#include "vr/photon_map.h"

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include <unistd.h>

#define NPHOTONS 1000000
#define NBINS 16
#define NQUERIES 200000
#define K 50

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

static void photon(uint64_t i, double pos[3], double dir[3], double nrm[3], float pw[NBINS]) {
  room_point(1, i, pos, nrm);
  /* a direction into the face: cosine-weighted about -n, near enough */
  double z = sqrt(u01(2, i)), phi = 2 * M_PI * u01(3, i), s = sqrt(1 - z * z);
  int ax = nrm[0] != 0 ? 0 : nrm[1] != 0 ? 1 : 2;
  dir[ax] = -z * nrm[ax];
  dir[(ax + 1) % 3] = s * cos(phi);
  dir[(ax + 2) % 3] = s * sin(phi);
  for (int b = 0; b < NBINS; b++) pw[b] = (float)(1e-6 * (0.5 + u01(4, i * NBINS + (uint64_t)b)));
}

typedef struct job {
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
    float pw[NBINS];
    photon(i, pos, dir, nrm, pw);
    if (vr_photon_map_store(j->m, i, pos, dir, nrm, pw, NULL) != VR_OK) j->used = -1;
  }
  return NULL;
}

static void *query_job(void *arg) {
  job *j = arg;
  double out[NBINS], r;
  for (uint64_t i = j->lo; i < j->hi; i++) {
    double x[3], n[3];
    room_point(9, i, x, n);
    int used = vr_photon_map_irradiance(j->m, x, n, j->k, j->radius, j->kc, out, &r);
    j->used += used;
    j->sink += out[0];
  }
  return NULL;
}

/* Runs fn over [0, count) on nthreads threads; returns the seconds taken
 * and the photons used per call. */
static double run(void *(*fn)(void *), vr_photon_map *m, int nthreads, uint64_t count, int k,
                  double radius, double kc, double *mean_used) {
  pthread_t th[64];
  job jobs[64];
  double t0 = now();
  for (int t = 0; t < nthreads; t++) {
    jobs[t] = (job){m, count * (uint64_t)t / (uint64_t)nthreads,
                    count * (uint64_t)(t + 1) / (uint64_t)nthreads, k, radius, kc, 0, 0};
    pthread_create(&th[t], NULL, fn, &jobs[t]);
  }
  long used = 0;
  for (int t = 0; t < nthreads; t++) {
    pthread_join(th[t], NULL);
    used += jobs[t].used;
  }
  double dt = now() - t0;
  if (mean_used) *mean_used = (double)used / (double)count;
  return dt;
}

int main(void) {
  long ncpu = sysconf(_SC_NPROCESSORS_ONLN);
  int nthreads = ncpu < 1 ? 1 : ncpu > 64 ? 64 : (int)ncpu;
  vr_error err;
  printf("photon map: %d photons, %d bins, room %gx%gx%g m, %d core(s)\n", NPHOTONS, NBINS,
         ROOM[0], ROOM[1], ROOM[2], nthreads);

  for (int pass = 0; pass < 2; pass++) {
    vr_photon_map *m = vr_photon_map_create(NBINS, 380, 700, &err);
    if (!m) {
      fprintf(stderr, "bench_photon_map: %s\n", err.message);
      return 1;
    }
    int nt = pass ? nthreads : 1;
    double t_store = run(store_job, m, nt, NPHOTONS, 0, 0, 0, NULL);
    printf("  store, %d thread(s): %.3f s (%.1f M photons/s)\n", nt, t_store,
           NPHOTONS / t_store * 1e-6);
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
    size_t bpp = vr_photon_map_bytes_per_photon(m);
    printf("  build (sort by key + balanced kd-tree): %.3f s\n", t_build);
    printf("  memory: %zu bytes/photon, %.1f MB built\n", bpp, (double)bpp * NPHOTONS / 1e6);

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
    for (size_t i = 0; i < sizeof q / sizeof q[0]; i++)
      for (int threads = 1; threads <= nthreads; threads = threads == nthreads ? threads + 1 : nthreads) {
        double used;
        double dt = run(query_job, m, threads, NQUERIES, q[i].k, q[i].radius, q[i].kc, &used);
        printf("  %-28s %d thread(s): %9.0f queries/s (%.2f us each, %.1f photons used)\n",
               q[i].name, threads, NQUERIES / dt, dt / NQUERIES * 1e6 * threads, used);
      }
    vr_photon_map_destroy(m);
  }
  return 0;
}
