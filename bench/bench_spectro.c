/* Prints how long vr-spectro's computations take on the samples: standard
 * figures of a pane (NFRC 300), the same at 60 deg (physical route), the n,k
 * fit of NFRC 102, the coated-stack table, and the photochromic state-model
 * fit.  Median of repeated runs, one thread.  Figures go to
 * docs/benchmarks.md. */
#include "vr/btdf_table.h"
#include "vr/chromogenic_fit.h"
#include "vr/glazing.h"
#include "vr/spectro_fit.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int cmp(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

static void check(vr_status st, const vr_error *e) {
  if (st) {
    fprintf(stderr, "bench_spectro: %s\n", e->message);
    exit(1);
  }
}

#define RUNS 15
static void report(const char *what, double *t) {
  qsort(t, RUNS, sizeof *t, cmp);
  printf("%-58s %10.3f ms (min %.3f)\n", what, 1e3 * t[RUNS / 2], 1e3 * t[0]);
}

int main(void) {
  vr_error err = {0};
  vr_spectro_data *d, *pc;
  vr_standard *std;
  check(vr_spectro_read(VR_SOURCE_DIR "/samples/glazing/clear_float/CLEAR_3.DAT", &d, &err), &err);
  check(vr_standard_open("nfrc", &std, &err), &err);
  double t[RUNS];
  for (int angle = 0; angle <= 60; angle += 60) {
    for (int r = 0; r < RUNS; r++) {
      double t0 = now();
      vr_pane *p;
      vr_glazing_metrics m;
      check(vr_pane_from_curve(&d->curves[0], d->thickness_nm, angle, VR_ROUTE_AUTO, 0.83, &p, NULL, &err), &err);
      check(vr_glazing_metrics_compute(std, p, &m, &err), &err);
      vr_pane_destroy(p);
      t[r] = now() - t0;
    }
    report(angle ? "metrics NFRC 102, 60 deg (physical route), 111 wl" : "metrics NFRC 102, normal incidence, 111 wl", t);
  }
  for (int r = 0; r < RUNS; r++) {
    double t0 = now();
    vr_spectro_fit_result fr;
    check(vr_spectro_fit(d, d->thickness_nm, NULL, &fr, &err), &err);
    vr_spectro_fit_free(&fr);
    t[r] = now() - t0;
  }
  report("fit n,k of NFRC 102 (111 wl, Sellmeier smoothing)", t);
  vr_sample_model *m;
  check(vr_model_read(VR_SOURCE_DIR "/samples/glazing/lowe/lowe.model", NULL, &m, &err), &err);
  double angles[11], nm[220];
  for (int i = 0; i < 11; i++) angles[i] = i < 9 ? 10.0 * i : (i == 9 ? 85 : 90);
  for (int j = 0; j < 220; j++) nm[j] = 310 + 10.0 * j;
  for (int r = 0; r < RUNS; r++) {
    double t0 = now();
    vr_btdf_table bt;
    check(vr_btdf_from_model(m, angles, 11, nm, 220, &bt, &err), &err);
    vr_btdf_table_free(&bt);
    t[r] = now() - t0;
  }
  report("btdf low-e stack, 11 angles x 220 wl x s,p x front,back", t);
  check(vr_spectro_read(VR_SOURCE_DIR "/samples/glazing/photochromic/pc_states.csv", &pc, &err), &err);
  vr_chromo_state *st;
  size_t ns;
  char tokens[1024] = "";
  for (size_t i = 0; i < pc->ncurves; i++) {
    if (i) strcat(tokens, ",");
    strcat(tokens, pc->curves[i].state);
  }
  check(vr_chromo_states_parse(tokens, &st, &ns, &err), &err);
  vr_spectrum *T[16];
  for (size_t i = 0; i < ns; i++) T[i] = vr_spectro_spectrum(&pc->curves[i], 'T', &err);
  for (int r = 0; r < RUNS; r++) {
    double t0 = now();
    vr_chromo_fit_result cr;
    check(vr_chromo_fit(ns, st, (const vr_spectrum *const *)T, NULL, NULL, 1e-3, &cr, &err), &err);
    vr_chromo_fit_free(&cr);
    t[r] = now() - t0;
  }
  report("photochromic state model, 10 spectra x 111 wl", t);
  for (size_t i = 0; i < ns; i++) vr_spectrum_destroy(T[i]);
  free(st);
  vr_model_destroy(m);
  vr_spectro_destroy(pc);
  vr_spectro_destroy(d);
  vr_standard_destroy(std);
  return 0;
}
