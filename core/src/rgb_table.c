/* The RGB-to-sigmoid table (vr/rgb_table.h).
 *
 * Building: per largest component l, the (x, y) plane is walked from grey
 * (x = y = 1, an exact flat spectrum) outwards, each node's fit starting
 * from its already-fitted neighbour at the middle z (saturated colours need
 * large coefficients that a start at grey does not reach); then each (x, y)
 * column is walked up and down z from the middle, every fit warm-started
 * from the node before.  Warm starts need a few Levenberg-Marquardt steps;
 * a node that misses by more than VR_RGB_SPECTRUM_MAX_DE is fitted again
 * by continuation from its neighbour's colour. */
#include "vr/rgb_table.h"

#include <math.h>
#include <pthread.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "rgb_fit.h"
#include "vr/rgb_spectrum.h"

#define R VR_RGB_TABLE_RES
#define CAP 1e4 /* |c| at most: S(+-1e4) is within 2.5e-9 of 1 or 0 */
#define UMAX 60.0 /* the inner z nodes span S(-60) .. S(60): 7e-5 .. 1 - 7e-5 */

struct vr_rgb_table {
  double z[R], u[R];           /* the z nodes, and S^-1 of each */
  float c[3][R][R][R][3];      /* [l][zi][yi][xi] -> c0, c1, c2 */
  double worst;
  long over;
};

/* The sigmoid's argument that gives the flat spectrum z: S^-1(z). */
static double s_inverse(double z) {
  double y = 2 * z - 1;
  if (!(y > -1)) return -CAP;
  if (!(y < 1)) return CAP;
  return fmax(-CAP, fmin(CAP, y / sqrt(1 - y * y)));
}

/* The fractions x, y have nodes (1 - cos(pi i / (R - 1))) / 2, dense near
 * 0 (saturated colours) and 1 (near-greys, whose coefficients change fast
 * near black and white); frac_pos is the node position of a fraction. */
static double frac_node(int i) { return 0.5 - 0.5 * cos(M_PI * i / (R - 1)); }
static float frac_pos(float f) {
  f = f < 0 ? 0 : f > 1 ? 1 : f;
  return (float)(acos(1.0 - 2.0 * f) / M_PI * (R - 1));
}

static void rgb_of(int l, double z, double x, double y, double rgb[3]) {
  rgb[l] = z;
  rgb[(l + 1) % 3] = x * z;
  rgb[(l + 2) % 3] = y * z;
}

/* Fits node (l, zi, yi, xi) from c (updated). */
static double fit_node(vr_rgb_table *t, const vr_rgbfit_w *W, int l, int zi, int yi, int xi,
                       double c[3]) {
  double rgb[3], goal[3];
  rgb_of(l, t->z[zi], frac_node(xi), frac_node(yi), rgb);
  if (rgb[0] == rgb[1] && rgb[1] == rgb[2]) {
    c[0] = c[1] = 0;
    c[2] = s_inverse(rgb[0]);
    return 0;
  }
  vr_rgbfit_goal(W, rgb, goal);
  double keep[3] = {c[0], c[1], c[2]};
  double de = vr_rgbfit_step(W, goal, c, 12);
  if (de > VR_RGB_SPECTRUM_MAX_DE) {
    /* Continuation from the neighbour's own colour. */
    double c2[3] = {keep[0], keep[1], keep[2]}, start[3];
    vr_rgbfit_lab(W, c2, start);
    double d2 = 0;
    for (int s = 1; s <= 8; s++) {
      double g[3];
      for (int k = 0; k < 3; k++) g[k] = start[k] + (goal[k] - start[k]) * s / 8.0;
      d2 = vr_rgbfit_step(W, g, c2, 30);
    }
    if (d2 < de) memcpy(c, c2, sizeof c2), de = d2;
  }
  for (int k = 0; k < 3; k++) c[k] = fmax(-CAP, fmin(CAP, c[k]));
  return de;
}

typedef struct job {
  vr_rgb_table *t;
  const vr_rgbfit_w *W;
  int l;
  double worst;
  long over;
} job;

static void store(job *j, int zi, int yi, int xi, const double c[3], double de) {
  for (int k = 0; k < 3; k++) j->t->c[j->l][zi][yi][xi][k] = (float)c[k];
  if (de > j->worst) j->worst = de;
  if (de > VR_RGB_SPECTRUM_MAX_DE) j->over++;
}

/* The nodes of one largest component l. */
static void *build_l(void *arg) {
  job *j = arg;
  vr_rgb_table *t = j->t;
  int l = j->l;
  const int mid = R / 2; /* mid grey */
  double(*plane)[R][3] = malloc(sizeof(double[R][R][3]));
  if (!plane) return arg;
  /* The middle z plane, from grey outwards. */
  double c[3] = {0, 0, 0};
  for (int yi = R - 1; yi >= 0; yi--) {
    if (yi < R - 1) memcpy(c, plane[yi + 1][R - 1], sizeof c);
    for (int xi = R - 1; xi >= 0; xi--) {
      double de = fit_node(t, j->W, l, mid, yi, xi, c);
      memcpy(plane[yi][xi], c, sizeof c);
      store(j, mid, yi, xi, c, de);
    }
  }
  /* Each column up and down z. */
  for (int yi = 0; yi < R; yi++)
    for (int xi = 0; xi < R; xi++) {
      memcpy(c, plane[yi][xi], sizeof c);
      for (int zi = mid + 1; zi < R; zi++) store(j, zi, yi, xi, c, fit_node(t, j->W, l, zi, yi, xi, c));
      memcpy(c, plane[yi][xi], sizeof c);
      for (int zi = mid - 1; zi >= 0; zi--) store(j, zi, yi, xi, c, fit_node(t, j->W, l, zi, yi, xi, c));
    }
  free(plane);
  return NULL;
}

static vr_status build(vr_rgb_table *t, vr_error *err) {
  vr_rgbfit_w W;
  vr_status st = vr_rgbfit_weights(&W, err);
  if (st) return st;
  /* z nodes: S(u) for u uniform in asinh(u) over [-asinh(UMAX), asinh(UMAX)]
   * inside, and the flat 0 and 1 (u = -CAP, CAP) at the ends. */
  for (int i = 1; i < R - 1; i++) t->u[i] = sinh(asinh(UMAX) * (2.0 * (i - 1) / (R - 3) - 1));
  t->u[0] = -CAP, t->u[R - 1] = CAP;
  for (int i = 0; i < R; i++) t->z[i] = 0.5 + t->u[i] / (2 * sqrt(1 + t->u[i] * t->u[i]));
  /* One thread per largest component. */
  job jobs[3];
  pthread_t th[3];
  bool started[3] = {false, false, false};
  for (int l = 0; l < 3; l++) {
    jobs[l] = (job){t, &W, l, 0, 0};
    started[l] = pthread_create(&th[l], NULL, build_l, &jobs[l]) == 0;
  }
  bool failed = false;
  for (int l = 0; l < 3; l++) {
    void *r = NULL;
    if (started[l]) pthread_join(th[l], &r);
    else r = build_l(&jobs[l]);
    failed |= r != NULL;
    if (jobs[l].worst > t->worst) t->worst = jobs[l].worst;
    t->over += jobs[l].over;
  }
  if (failed) return vr_error_set(err, VR_E_NOMEM, "out of memory for the RGB-to-spectrum table");
  return VR_OK;
}

static pthread_once_t once = PTHREAD_ONCE_INIT;
static vr_rgb_table *table;
static vr_error build_err;

static void build_once(void) {
  vr_rgb_table *t = calloc(1, sizeof *t);
  if (!t) {
    vr_error_set(&build_err, VR_E_NOMEM, "out of memory for the RGB-to-spectrum table");
    return;
  }
  if (build(t, &build_err)) {
    free(t);
    return;
  }
  table = t;
}

const vr_rgb_table *vr_rgb_table_get(vr_error *err) {
  pthread_once(&once, build_once);
  if (!table && err) *err = build_err;
  return table;
}

static float clamp01(float v) { return v > 0 ? (v < 1 ? v : 1) : 0; }

void vr_rgb_table_lookup(const vr_rgb_table *t, const float in[3], float c[3]) {
  float rgb[3] = {clamp01(in[0]), clamp01(in[1]), clamp01(in[2])};
  int l = rgb[0] >= rgb[1] ? (rgb[0] >= rgb[2] ? 0 : 2) : (rgb[1] >= rgb[2] ? 1 : 2);
  float z = rgb[l];
  if (!(z > 0)) {
    c[0] = c[1] = 0, c[2] = (float)-CAP;
    return;
  }
  float x = frac_pos(rgb[(l + 1) % 3] / z), y = frac_pos(rgb[(l + 2) % 3] / z);
  int xi = (int)x, yi = (int)y;
  if (xi > R - 2) xi = R - 2;
  if (yi > R - 2) yi = R - 2;
  float fx = x - xi, fy = y - yi;
  /* The z cell, and the fraction across it in u = S^-1(z), in which the
   * greys' c2 is linear (exact), and the colours' nearly so. */
  double u = s_inverse(z);
  int lo = 0, hi = R - 1;
  while (hi - lo > 1) {
    int m = (lo + hi) / 2;
    if (t->u[m] <= u) lo = m;
    else hi = m;
  }
  float fz = (float)((u - t->u[lo]) / (t->u[lo + 1] - t->u[lo]));
  fz = fz < 0 ? 0 : fz > 1 ? 1 : fz;
  for (int k = 0; k < 3; k++) {
    float v = 0;
    for (int dz = 0; dz < 2; dz++)
      for (int dy = 0; dy < 2; dy++)
        for (int dx = 0; dx < 2; dx++)
          v += (dz ? fz : 1 - fz) * (dy ? fy : 1 - fy) * (dx ? fx : 1 - fx) *
               t->c[l][lo + dz][yi + dy][xi + dx][k];
    c[k] = v;
  }
}

double vr_rgb_table_worst(const vr_rgb_table *t, long *over) {
  if (over) *over = t->over;
  return t->worst;
}
