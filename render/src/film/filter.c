/* Pixel filters by filter importance sampling (vr/filter.h): each filter's
 * f1 on the half line t >= 0, its integral from 0 (cum), and the inverse of
 * that integral, which turns a uniform number into an offset distributed
 * as |f1|.  The inverse is closed-form for box and tent; for the gaussian
 * and Mitchell it is solved by Newton's method kept inside a bracket, on
 * the exact integrals (erf, and the cubic's quartic antiderivative), so the
 * offsets follow |f| itself, not a tabulated stand-in. */
#include <math.h>
#include <string.h>

#include "vr/filter.h"

/* Mitchell & Netravali's cubic for B = C = 1/3 on x = 2|t|/R in [0, 2]:
 *   x <= 1:  (7 x^3 - 12 x^2 + 16/3) / 6
 *   x <= 2:  (-7/3 x^3 + 12 x^2 - 20 x + 32/3) / 6 = -(x - 2)^2 (7 x - 8) / 18,
 * negative on (8/7, 2).  Its integral from 0 to x is mcum below; over the
 * whole line the cubic integrates to 1. */
static const double MITCHELL_SPLIT = 8.0 / 7.0;

static double mitchell(double x) {
  x = fabs(x);
  if (x <= 1) return (7 * x * x * x - 12 * x * x + 16.0 / 3.0) / 6;
  if (x <= 2) return (-7.0 / 3.0 * x * x * x + 12 * x * x - 20 * x + 32.0 / 3.0) / 6;
  return 0;
}

static double mcum_outer(double x) {
  return (-7.0 / 12.0 * x * x * x * x + 4 * x * x * x - 10 * x * x + 32.0 / 3.0 * x) / 6;
}

static double mcum(double x) {
  if (x <= 0) return 0;
  if (x <= 1) return (7.0 / 4.0 * x * x * x * x - 4 * x * x * x + 16.0 / 3.0 * x) / 6;
  double at1 = (7.0 / 4.0 - 4 + 16.0 / 3.0) / 6; /* 37/72 */
  if (x > 2) x = 2;
  return at1 + mcum_outer(x) - mcum_outer(1);
}

static double gauss(double x, double sigma) {
  return exp(-x * x / (2 * sigma * sigma)) / (sigma * sqrt(2 * M_PI));
}

static double radius_of(const vr_filter *f) { return f->radius > 0 ? f->radius : 0.5; }

double vr_filter_eval_1d(const vr_filter *f, double x) {
  double R = radius_of(f), t = fabs(x);
  if (t > R) return 0;
  switch (f->kind) {
  case VR_FILTER_TENT: return R - t;
  case VR_FILTER_GAUSSIAN: return fmax(0.0, gauss(t, f->sigma) - f->g_r);
  case VR_FILTER_MITCHELL: return mitchell(2 * t / R);
  default: return 1;
  }
}

double vr_filter_eval(const vr_filter *f, double x, double y) {
  return vr_filter_eval_1d(f, x) * vr_filter_eval_1d(f, y);
}

/* The integral of f1 from 0 to t, t in [0, R]. */
static double cum(const vr_filter *f, double t) {
  double R = radius_of(f);
  switch (f->kind) {
  case VR_FILTER_TENT: return R * t - t * t / 2;
  case VR_FILTER_GAUSSIAN: return 0.5 * erf(t / (f->sigma * M_SQRT2)) - t * f->g_r;
  case VR_FILTER_MITCHELL: return R / 2 * mcum(2 * t / R);
  default: return t;
  }
}

/* The t in [lo, hi] (within [a, b]) where the integral of |f1| from a
 * reaches the share w of its integral over [a, b]; sign is +1 where
 * f1 >= 0 on [a, b], -1 where f1 <= 0.  Newton steps on the exact
 * integral, bisection when a step would leave the bracket. */
static double invert(const vr_filter *f, double a, double b, double sign, double w, double lo,
                     double hi, double t) {
  /* The integrals from 0 to a and over [a, b]: vr_filter_init's pos and
   * neg are twice those of the half line. */
  double ca = a > 0 ? f->pos / 2 : 0, target = w * (a > 0 ? f->neg : f->pos) / 2;
  /* A billionth of the interval: far below what a pixel can show; Newton's
   * step that gets there has left an error far smaller still. */
  double tol = 1e-9 * (b - a);
  for (int it = 0; it < 60; it++) {
    double g = sign * (cum(f, t) - ca) - target;
    if (g == 0) return t;
    if (g > 0) hi = t;
    else lo = t;
    double d = fabs(vr_filter_eval_1d(f, t)), next = d > 0 ? t - g / d : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (fabs(next - t) <= tol || hi - lo <= tol) return next;
    t = next;
  }
  return t;
}

/* The interval [a, b] of |x| that holds part `neg` of f1. */
static void part_range(const vr_filter *f, bool neg, double *a, double *b, double *sign) {
  double R = radius_of(f), split = f->kind == VR_FILTER_MITCHELL ? MITCHELL_SPLIT * R / 2 : R;
  *a = neg ? split : 0;
  *b = neg ? R : split;
  *sign = neg ? -1 : 1;
}

/* The same from the table of vr_filter_init: the knots around w bracket
 * the answer. */
static double invert_part(const vr_filter *f, bool neg, double w) {
  double a, b, sign;
  part_range(f, neg, &a, &b, &sign);
  int i = (int)(w * 64);
  if (i > 63) i = 63;
  if (i < 0) i = 0;
  const double *t = f->inv[neg];
  double guess = t[i] + (w * 64 - i) * (t[i + 1] - t[i]);
  return invert(f, a, b, sign, w, t[i], t[i + 1], guess);
}

static const double BELOW_ONE = 0x1.fffffffffffffp-1;

/* An offset distributed as the positive (neg false) or negative part of
 * f1 over [-R, R], from u in [0, 1): u below 1/2 gives the left half,
 * monotonically, so stratified numbers give stratified offsets. */
static double sample_part(const vr_filter *f, bool neg, double u) {
  double R = radius_of(f), s = 2 * u - 1, w = fabs(s), t;
  if (f->kind == VR_FILTER_TENT) {
    t = R * (1 - sqrt(1 - w));
  } else {
    t = invert_part(f, neg, w);
  }
  return s < 0 ? -t : t;
}

const char *vr_filter_name(vr_filter_kind kind) {
  switch (kind) {
  case VR_FILTER_TENT: return "tent";
  case VR_FILTER_GAUSSIAN: return "gaussian";
  case VR_FILTER_MITCHELL: return "mitchell";
  default: return "box";
  }
}

bool vr_filter_kind_of(const char *name, vr_filter_kind *kind) {
  static const struct {
    const char *name;
    vr_filter_kind kind;
  } NAMES[] = {{"box", VR_FILTER_BOX},
               {"tent", VR_FILTER_TENT},
               {"triangle", VR_FILTER_TENT},
               {"gaussian", VR_FILTER_GAUSSIAN},
               {"mitchell", VR_FILTER_MITCHELL}};
  for (size_t i = 0; i < sizeof NAMES / sizeof NAMES[0]; i++)
    if (!strcmp(name, NAMES[i].name)) return *kind = NAMES[i].kind, true;
  return false;
}

bool vr_filter_init(vr_filter *f, vr_filter_kind kind, double radius, double sigma) {
  static const double DEFAULT_RADIUS[] = {0.5, 2.0, 1.5, 2.0};
  memset(f, 0, sizeof *f);
  if ((unsigned)kind > VR_FILTER_MITCHELL) return false;
  f->kind = kind;
  f->radius = radius > 0 ? radius : DEFAULT_RADIUS[kind];
  if (!(f->radius <= VR_FILTER_MAX_RADIUS)) return false;
  if (kind == VR_FILTER_GAUSSIAN) {
    f->sigma = sigma > 0 ? sigma : 0.5;
    if (!isfinite(f->sigma)) return false;
    f->g_r = gauss(f->radius, f->sigma);
  }
  double R = f->radius;
  if (kind == VR_FILTER_MITCHELL) {
    double split = MITCHELL_SPLIT * R / 2;
    f->pos = 2 * cum(f, split);
    f->neg = 2 * (cum(f, split) - cum(f, R));
  } else {
    f->pos = 2 * cum(f, R);
    f->neg = 0;
  }
  if (!(f->pos > 0)) return false;
  for (int part = 0; part < (f->neg > 0 ? 2 : 1); part++) {
    double a, b, sign;
    part_range(f, part, &a, &b, &sign);
    for (int i = 0; i <= 64; i++)
      f->inv[part][i] = i == 0 ? a : i == 64 ? b : invert(f, a, b, sign, i / 64.0, a, b, (a + b) / 2);
  }
  f->f_pos = f->pos * f->pos + f->neg * f->neg;
  f->f_neg = 2 * f->pos * f->neg;
  f->f_all = f->f_pos - f->f_neg;
  f->q = f->f_neg / (f->f_pos + f->f_neg);
  return true;
}

double vr_filter_sample_u(const vr_filter *f, double u1, double u2, double v, uint32_t index,
                          uint32_t count, double *dx, double *dy) {
  if (f->kind == VR_FILTER_BOX || !(f->radius > 0)) {
    /* 2 u - 1 and its half are exact, so R = 0.5 gives u - 0.5 exactly. */
    double R = radius_of(f);
    *dx = R * (2 * u1 - 1);
    *dy = R * (2 * u2 - 1);
    return 1.0;
  }
  if (!(f->neg > 0)) {
    *dx = sample_part(f, false, u1);
    *dy = sample_part(f, false, u2);
    return 1.0;
  }
  /* Signed filter: which samples take the negative lobes, and the weights
   * that make the pass's estimate unbiased and its weights sum to count. */
  bool negative;
  double w;
  if (count <= 1) {
    negative = v < f->q;
    w = (f->f_pos + f->f_neg) / f->f_all;
  } else {
    double kq = nearbyint(f->q * count);
    uint32_t k = kq < 1 ? 1 : kq > count - 1 ? count - 1 : (uint32_t)kq;
    uint32_t rot = (uint32_t)(v * count);
    if (rot >= count) rot = count - 1;
    negative = (uint32_t)(((uint64_t)(index % count) + rot) % count) < k;
    w = negative ? (double)count * f->f_neg / ((double)k * f->f_all)
                 : (double)count * f->f_pos / ((double)(count - k) * f->f_all);
  }
  if (negative) {
    /* f- = f1+(x) f1-(y) + f1-(x) f1+(y), the two halves of equal mass. */
    bool x_neg = u1 >= 0.5;
    double ux = x_neg ? 2 * u1 - 1 : 2 * u1;
    *dx = sample_part(f, x_neg, fmin(ux, BELOW_ONE));
    *dy = sample_part(f, !x_neg, u2);
    return -w;
  }
  /* f+ = f1+(x) f1+(y) + f1-(x) f1-(y), in proportion pos^2 : neg^2. */
  double a = f->pos * f->pos / f->f_pos;
  bool both_neg = u1 >= a;
  double ux = both_neg ? (u1 - a) / (1 - a) : u1 / a;
  *dx = sample_part(f, both_neg, fmin(ux, BELOW_ONE));
  *dy = sample_part(f, both_neg, u2);
  return w;
}

double vr_filter_sample(const vr_filter *f, const vr_rng_key *key, uint32_t index, uint32_t count,
                        double *dx, double *dy) {
  double u1 = vr_rng(key, VR_DIM_PIXEL_X), u2 = vr_rng(key, VR_DIM_PIXEL_Y), v = 0;
  if (f->neg > 0 && f->radius > 0) {
    /* One number per pixel and pass: the pass's first sample, a depth no
     * path vertex uses. */
    vr_rng_key pk = *key;
    pk.sample = key->sample - index;
    pk.depth = 0x46494C54u; /* "FILT" */
    v = vr_rng_independent(&pk, VR_DIM_PIXEL_X);
  }
  return vr_filter_sample_u(f, u1, u2, v, index, count, dx, dy);
}
