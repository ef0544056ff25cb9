/* Shared by the sensor benchmarks (bench_cornell, bench_daylight): one
 * sensors-only render of a parsed scene on `threads` threads, timed. */
#ifndef VR_BENCH_SENSORS_H
#define VR_BENCH_SENSORS_H

#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "vr/render.h"
#include "vr/scene.h"

static inline double bench_now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* Renders s (materials from db, may be NULL) without the camera pass;
 * exits with the error on failure.  *seconds gets the wall time. */
static inline vr_render_result *bench_sensors_render(const vr_scene *s, vr_matdb *db, int threads,
                                                     const char *who, double *seconds) {
  vr_render_options o;
  vr_render_options_default(&o);
  o.threads = threads;
  o.no_camera = true;
  vr_render_result *r = NULL;
  vr_error err = {0};
  double t0 = bench_now();
  if (vr_render_scene(s, db, &o, &r, &err)) {
    fprintf(stderr, "%s: %s\n", who, err.message);
    exit(1);
  }
  *seconds = bench_now() - t0;
  return r;
}

#endif
