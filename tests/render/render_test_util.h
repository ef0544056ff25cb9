/* Shared by the render tests: a scene from text rendered in one call, the
 * reading of CIE 171:2006 case 5.8 (the cube's indirect illuminance), and
 * the statistics of one figure over seeds.  Include after cmocka.h. */
#ifndef VR_RENDER_TEST_UTIL_H
#define VR_RENDER_TEST_UTIL_H

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "vr/models.h"
#include "vr/render.h"
#include "vr/scene.h"

/* The scene of text, as file `name`; fails the test on a parse error. */
static inline vr_scene *parse_text(const char *text, const char *name) {
  vr_scene *s = NULL;
  vr_error err = {0};
  vr_status st = vr_scene_parse(text, strlen(text), name, &s, &err);
  if (st) fprintf(stderr, "parse: %s\n", err.message);
  assert_int_equal(st, VR_OK);
  return s;
}

/* Renders s with the materials of db (may be NULL) and options o; fails
 * the test on any error. */
static inline vr_render_result *render_scene_opt(vr_scene *s, struct vr_matdb *db,
                                                 const vr_render_options *o) {
  vr_render_result *r = NULL;
  vr_error err = {0};
  vr_status st = vr_render_scene(s, db, o, &r, &err);
  if (st) fprintf(stderr, "render: %s\n", err.message);
  assert_int_equal(st, VR_OK);
  return r;
}

/* Renders s with the materials of db (may be NULL) on S sub-domains and P
 * threads, without the camera pass when sensors_only, in image space when
 * image_space; fails the test on any error. */
static inline vr_render_result *render_scene_with(vr_scene *s, struct vr_matdb *db, int S, int P,
                                                  bool sensors_only, bool image_space) {
  vr_render_options o;
  vr_render_options_default(&o);
  o.subdomains = S;
  o.threads = P;
  o.no_camera = sensors_only;
  o.image_space = image_space;
  return render_scene_opt(s, db, &o);
}

/* Parses text and renders it (render_scene_with, no database). */
static inline vr_render_result *render_text_with(const char *text, int S, int P,
                                                 bool sensors_only) {
  vr_scene *s = parse_text(text, "test.scn");
  vr_render_result *r = render_scene_with(s, NULL, S, P, sensors_only, false);
  vr_scene_destroy(s);
  return r;
}

/* Parses text, reads the materials of its mesh lines' files
 * (vr_scene_load_models, as vr-render does) and renders it on one
 * sub-domain and two threads. */
static inline vr_render_result *render_text_models(const char *text, const char *name) {
  vr_scene *s = parse_text(text, name);
  vr_error e = {0};
  if (vr_scene_load_models(s, &e)) fail_msg("vr_scene_load_models: %s", e.message);
  vr_render_result *r = render_scene_with(s, NULL, 1, 2, false, false);
  vr_scene_destroy(s);
  return r;
}

/* The white furnace's six walls, 2 x 2 m about the origin, material M,
 * each emitting 100 cd/m2 (of D65, the default emission spectrum). */
#define FURNACE_WALLS(M)                                                            \
  "rect center=0,0,-1 normal=0,0,1 size=2,2 material=" M " emission=100cd/m2\n" \
  "rect center=0,0,1 normal=0,0,-1 size=2,2 material=" M " emission=100cd/m2\n" \
  "rect center=-1,0,0 normal=1,0,0 size=2,2 material=" M " emission=100cd/m2\n" \
  "rect center=1,0,0 normal=-1,0,0 size=2,2 material=" M " emission=100cd/m2\n" \
  "rect center=0,-1,0 normal=0,1,0 size=2,2 material=" M " emission=100cd/m2\n" \
  "rect center=0,1,0 normal=0,-1,0 size=2,2 material=" M " emission=100cd/m2\n"

/* CIE 171:2006 case 5.8: a 4 m cube (floor z = 0 centred on the z axis),
 * a point source of flux phi_lm at its centre, reflectance rho.  The mean
 * over the readings (floor points) of the illuminance less the analytic
 * direct part I cos / r^2, and (*expected) the standard's indirect value
 * rho Phi / (S_T (1 - rho)), S_T = 96 m^2. */
static inline double cie171_cube_indirect_of(const vr_render_result *r, size_t first, size_t n,
                                             double phi_lm, double rho, double *expected,
                                             double *stderr_mean) {
  double I = phi_lm / (4 * M_PI), sum = 0, var = 0;
  for (size_t i = first; i < first + n; i++) {
    const double *p = r->readings[i].position;
    double r2 = p[0] * p[0] + p[1] * p[1] + 4.0;
    sum += r->readings[i].illuminance_lx - I * (2.0 / sqrt(r2)) / r2;
    var += r->readings[i].stderr_lx * r->readings[i].stderr_lx;
  }
  *expected = rho * phi_lm / (96.0 * (1 - rho));
  /* The points' estimates are independent (a stream each): the variance
   * of their mean is the sum of their variances over n^2. */
  if (stderr_mean) *stderr_mean = sqrt(var) / (double)n;
  return sum / (double)n;
}

static inline double cie171_cube_indirect(const vr_render_result *r, double phi_lm, double rho,
                                          double *expected) {
  return cie171_cube_indirect_of(r, 0, r->nreadings, phi_lm, rho, expected, NULL);
}

/* One figure over independent seeds, for the bounds a run cannot give
 * (noise every pixel or reading of a run shares): the mean, and its
 * standard error from the seeds' sample standard deviation. */
typedef struct seed_stats {
  int n;
  double sum, sq;
} seed_stats;

static inline void seed_add(seed_stats *s, double v) { s->n++, s->sum += v, s->sq += v * v; }

static inline double seed_mean(const seed_stats *s) { return s->sum / s->n; }

static inline double seed_stderr(const seed_stats *s) {
  double m = seed_mean(s);
  return sqrt(fmax(0, (s->sq - s->n * m * m) / (s->n - 1)) / s->n);
}

#endif
