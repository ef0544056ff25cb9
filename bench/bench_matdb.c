/* Prints how long the material database takes to create (with its built-in
 * library), to save and load a large tabulated material, and to evaluate n
 * of a formula glass after a load.  Figures go to docs/benchmarks.md. */
#include "vr/matdb.h"

#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include <unistd.h>

static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int main(void) {
  char path[] = "/tmp/vr_bench_matdb_XXXXXX";
  int fd = mkstemp(path);
  if (fd < 0) return 1;
  close(fd);
  unlink(path);
  vr_error err = {0};
  vr_matdb *db;
  double t0 = now();
  if (vr_matdb_open(path, 0, &db, &err)) { fprintf(stderr, "%s\n", err.message); return 1; }
  double t_create = now() - t0;

  const size_t N = 1000000;
  vr_material *m = vr_material_create("big", VR_KIND_REFLECTANCE, NULL);
  vr_spectrum *s = vr_spectrum_create_uniform(300.0, 0.0005, N, 0.5, NULL);
  for (size_t i = 0; i < N; i++) s->value[i] = 0.5 + 0.4 * ((double)(i % 1000) / 1000.0 - 0.5);
  vr_material_add_spectrum(m, "value", s, NULL);
  t0 = now();
  if (vr_matdb_save(db, m, &err)) { fprintf(stderr, "%s\n", err.message); return 1; }
  double t_save = now() - t0;
  vr_material_destroy(m);
  t0 = now();
  if (vr_matdb_load(db, "big", 0, &m, &err)) { fprintf(stderr, "%s\n", err.message); return 1; }
  double t_load = now() - t0;
  vr_material_destroy(m);

  const int L = 200;
  volatile double sink = 0;
  t0 = now();
  for (int i = 0; i < L; i++) {
    vr_material *g;
    double n, k;
    vr_matdb_load(db, "N-BK7", 0, &g, NULL);
    vr_material_nk(g, 400 + i, false, &n, &k, NULL, NULL);
    sink += n;
    vr_material_destroy(g);
  }
  double t_small = (now() - t0) / L;
  vr_matdb_close(db);
  unlink(path);
  char wal[64];
  snprintf(wal, sizeof wal, "%s-wal", path);
  unlink(wal);
  snprintf(wal, sizeof wal, "%s-shm", path);
  unlink(wal);
  printf("operation                                            time\n");
  printf("create database + seed 67 built-in materials     %8.1f ms\n", t_create * 1e3);
  printf("save a 1,000,000-sample spectrum (one transaction) %6.2f s  (%.2f us/sample)\n", t_save, t_save / N * 1e6);
  printf("load it back                                       %6.2f s\n", t_load);
  printf("load N-BK7 (formula + 26 k samples) and eval n   %8.1f us\n", t_small * 1e6);
  return sink == 1.0;
}
