/* What the "extra" renderer tests share (test_render_extra.c,
 * test_render_dispersion.c): a scratch material database, rendering a
 * scene text on 2 threads and 2 sub-domains, and reading its results.
 * Include after render_test_util.h. */
#ifndef EXTRA_HARNESS_H
#define EXTRA_HARNESS_H

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "vr/matdb.h"
#include "vr/render.h"
#include "vr/scene.h"

static vr_matdb *db;
static char dbpath[256];

/* Results not yet released: a failing check jumps out of its test before
 * the test frees them, so the group's teardown frees what is left. */
static vr_render_result *live[8];

static inline void done(vr_render_result *r) {
  for (size_t i = 0; i < sizeof live / sizeof *live; i++)
    if (live[i] == r) live[i] = NULL;
  vr_render_result_destroy(r);
}

/* Opens a fresh database /tmp/vr_test_<tag>_<pid>.db. */
static inline int harness_open(const char *tag) {
  snprintf(dbpath, sizeof dbpath, "/tmp/vr_test_%s_%d.db", tag, (int)getpid());
  unlink(dbpath);
  vr_error err = {0};
  if (vr_matdb_open(dbpath, 0, &db, &err)) {
    fprintf(stderr, "%s\n", err.message);
    return -1;
  }
  return 0;
}

/* Saves m (and destroys it): 0, or -1 with the message on stderr. */
static inline int harness_save(vr_material *m) {
  vr_error err = {0};
  vr_status st = vr_matdb_save(db, m, &err);
  vr_material_destroy(m);
  if (st) fprintf(stderr, "%s\n", err.message);
  return st ? -1 : 0;
}

static inline int harness_close(void **state) {
  (void)state;
  for (size_t i = 0; i < sizeof live / sizeof *live; i++) {
    vr_render_result_destroy(live[i]);
    live[i] = NULL;
  }
  vr_matdb_close(db);
  unlink(dbpath);
  char aux[300];
  snprintf(aux, sizeof aux, "%s-wal", dbpath);
  unlink(aux);
  snprintf(aux, sizeof aux, "%s-shm", dbpath);
  unlink(aux);
  return 0;
}

static inline vr_render_result *render_text(const char *text) {
  vr_scene *s = NULL;
  vr_error err = {0};
  vr_status st = vr_scene_parse(text, strlen(text), "extra.scn", &s, &err);
  if (st) fail_msg("parse: %s", err.message);
  vr_render_options o;
  vr_render_options_default(&o);
  o.subdomains = 2;
  o.threads = 2;
  vr_render_result *r = NULL;
  st = vr_render_scene(s, db, &o, &r, &err);
  vr_scene_destroy(s);
  if (st) fail_msg("render: %s", err.message);
  for (size_t i = 0; i < sizeof live / sizeof *live; i++)
    if (!live[i]) {
      live[i] = r;
      break;
    }
  return r;
}

static inline void expect_lx(const vr_render_result *r, size_t i, double want, double rel) {
  double got = r->readings[i].illuminance_lx;
  print_message("    sensor %zu: %.4f lx (stderr %.4f), expected %.4f\n", i, got,
                r->readings[i].stderr_lx, want);
  if (fabs(got - want) > rel * want)
    fail_msg("sensor %zu: %.4f lx, expected %.4f (+-%.1f %%), stderr %.4f", i, got, want,
             rel * 100, r->readings[i].stderr_lx);
}

/* The mean of all the readings, with its standard error. */
static inline void expect_mean_lx(const vr_render_result *r, double want, double rel, const char *what) {
  double E = 0, var = 0, n = (double)r->nreadings;
  for (size_t i = 0; i < r->nreadings; i++) {
    E += r->readings[i].illuminance_lx / n;
    var += pow(r->readings[i].stderr_lx / n, 2);
  }
  print_message("    %s: mean %.3f lx (stderr %.3f), expected %.3f\n", what, E, sqrt(var), want);
  if (fabs(E - want) > rel * want)
    fail_msg("%s: %.3f lx (stderr %.3f), expected %.3f within %.1f %%", what, E, sqrt(var), want,
             rel * 100);
}

static inline double Y(const vr_render_result *r, int x, int y) {
  return r->xyz[((size_t)y * (size_t)r->width + (size_t)x) * 3 + 1];
}

static inline const vr_pass_record *pass(const vr_render_result *r, const char *name) {
  for (size_t i = 0; i < r->npasses; i++)
    if (!strcmp(r->passes[i].name, name)) return &r->passes[i];
  fail_msg("no pass record '%s'", name);
  return NULL;
}

#endif
