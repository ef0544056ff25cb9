/* Camera calibration from a ColorChecker under a known light (the model and
 * its assumptions are in vr/calibrate.h).  The linear algebra is the
 * recovery's: the GCV standard-form solve and the smoothness operator of
 * recover_regularised.c and recover_linalg.c, and the active-set solver of
 * recover_qp.c for the non-negativity, here on sensitivities instead of
 * reflectances.  calibration_material.c stores the result as a material. */
#include "vr/calibrate.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "recover_gcv.h"
#include "recover_linalg.h"
#include "recover_qp.h"
#include "vr/camera.h"
#include "vr/colorchecker.h"
#include "vr/colour.h"

#define NP VR_CALIBRATION_PATCHES
#define NEUTRALS 6
#define FIRST_NM 360.0
#define ROWS 471 /* 360..830 nm at 1 nm, where every colorimetric sum of the project runs */
/* RMS below this (encoded units, a quarter of an 8-bit code) is no evidence
 * for one tone curve over another. */
#define TONE_FLOOR 1e-3
/* A channel whose brightest usable patch is below this encoded value has
 * (almost) no light to work with. */
#define DIM_LIMIT 0.02
#define MAX_SAMPLES 1024

static const char *const CHANNEL[3] = {"red", "green", "blue"};

/* ---- tone curves --------------------------------------------------------- */

double vr_tone_decode(vr_tone tone, double gamma, double v) {
  switch (tone) {
    case VR_TONE_SRGB: return vr_srgb_decode(v);
    case VR_TONE_GAMMA: return copysign(pow(fabs(v), gamma), v);
    default: return v;
  }
}

double vr_tone_encode(vr_tone tone, double gamma, double linear) {
  switch (tone) {
    case VR_TONE_SRGB: return vr_srgb_encode(linear);
    case VR_TONE_GAMMA: return copysign(pow(fabs(linear), 1.0 / gamma), linear);
    default: return linear;
  }
}

void vr_tone_format(vr_tone tone, double gamma, char *buf, size_t size) {
  switch (tone) {
    case VR_TONE_SRGB: snprintf(buf, size, "srgb"); break;
    case VR_TONE_GAMMA: snprintf(buf, size, "gamma %.4g", gamma); break;
    case VR_TONE_AUTO: snprintf(buf, size, "auto"); break;
    default: snprintf(buf, size, "linear"); break;
  }
}

vr_status vr_tone_parse(const char *text, bool allow_auto, vr_tone *tone, double *gamma,
                        vr_error *err) {
  const char *s = text ? text : "";
  while (isspace((unsigned char)*s)) s++;
  size_t len = strlen(s);
  while (len && isspace((unsigned char)s[len - 1])) len--;
  if (len == 6 && !strncasecmp(s, "linear", 6)) {
    *tone = VR_TONE_LINEAR;
    *gamma = 1.0;
    return VR_OK;
  }
  if (len == 4 && !strncasecmp(s, "srgb", 4)) {
    *tone = VR_TONE_SRGB;
    *gamma = NAN;
    return VR_OK;
  }
  if (allow_auto && len == 4 && !strncasecmp(s, "auto", 4)) {
    *tone = VR_TONE_AUTO;
    *gamma = NAN;
    return VR_OK;
  }
  if (len > 5 && !strncasecmp(s, "gamma", 5) && (s[5] == ' ' || s[5] == '=' || s[5] == ':')) {
    char buf[64];
    size_t k = len - 6 < sizeof buf - 1 ? len - 6 : sizeof buf - 1;
    memcpy(buf, s + 6, k);
    buf[k] = '\0';
    char *end;
    double g = strtod(buf, &end);
    while (isspace((unsigned char)*end)) end++;
    if (end != buf && !*end && g >= 0.2 && g <= 10.0) {
      *tone = VR_TONE_GAMMA;
      *gamma = g;
      return VR_OK;
    }
  }
  return vr_error_set(err, VR_E_PARSE,
                      "tone curve \"%s\": expected linear, srgb%s or gamma G (0.2 <= G <= 10)",
                      text ? text : "", allow_auto ? ", auto" : "");
}

/* ---- fitting the tone curve on the neutrals --------------------------------- */

/* RSS in the encoded value of v_i = encode(a rho_i). */
static double rss_scaled(vr_tone t, double gamma, const double *rho, const double *v, size_t k,
                         double a) {
  double r = 0.0;
  for (size_t i = 0; i < k; i++) {
    double d = vr_tone_encode(t, gamma, a * rho[i]) - v[i];
    r += d * d;
  }
  return r;
}

/* Golden-section minimum of f over [lo, hi]. */
typedef double (*objective)(double x, const void *ctx);

static double golden(objective f, const void *ctx, double lo, double hi, double *fmin_out) {
  const double phi = 0.5 * (sqrt(5.0) - 1.0);
  double x1 = hi - phi * (hi - lo), x2 = lo + phi * (hi - lo);
  double f1 = f(x1, ctx), f2 = f(x2, ctx);
  for (int it = 0; it < 200 && hi - lo > 1e-12 * (1.0 + fabs(lo)); it++) {
    if (f1 <= f2) {
      hi = x2;
      x2 = x1;
      f2 = f1;
      x1 = hi - phi * (hi - lo);
      f1 = f(x1, ctx);
    } else {
      lo = x1;
      x1 = x2;
      f1 = f2;
      x2 = lo + phi * (hi - lo);
      f2 = f(x2, ctx);
    }
  }
  *fmin_out = fmin(f1, f2);
  return f1 <= f2 ? x1 : x2;
}

typedef struct tone_ctx {
  vr_tone t;
  const double *rho, *v;
  size_t k;
} tone_ctx;

static double rss_log_a(double x, const void *p) {
  const tone_ctx *c = p;
  return rss_scaled(c->t, 1.0, c->rho, c->v, c->k, exp(x));
}

/* v = a' rho^(1/gamma): for a fixed gamma the best a' is linear least
 * squares, so only gamma is searched (over its logarithm). */
static double rss_power(double lg, const void *p) {
  const tone_ctx *c = p;
  double e = exp(-lg), num = 0.0, den = 0.0;
  for (size_t i = 0; i < c->k; i++) {
    double q = pow(c->rho[i], e);
    num += c->v[i] * q;
    den += q * q;
  }
  double a = den > 0.0 ? num / den : 0.0, r = 0.0;
  for (size_t i = 0; i < c->k; i++) {
    double d = a * pow(c->rho[i], e) - c->v[i];
    r += d * d;
  }
  return r;
}

/* The RSS of curve t at its best exposure a; gamma receives the fitted
 * exponent for VR_TONE_GAMMA. */
static double fit_tone(vr_tone t, const double *rho, const double *v, size_t k, double *gamma) {
  tone_ctx c = {t, rho, v, k};
  if (t == VR_TONE_LINEAR) {
    double num = 0.0, den = 0.0;
    for (size_t i = 0; i < k; i++) {
      num += v[i] * rho[i];
      den += rho[i] * rho[i];
    }
    return rss_scaled(t, 1.0, rho, v, k, num / den);
  }
  if (t == VR_TONE_SRGB) {
    double la = 0.0;
    for (size_t i = 0; i < k; i++) la += log(vr_srgb_decode(v[i]) / rho[i]) / (double)k;
    double best;
    golden(rss_log_a, &c, la - 1.5, la + 1.5, &best);
    return best;
  }
  /* Power law: a coarse scan over log gamma in [0.3, 5], then golden
   * section between the best point's neighbours. */
  enum { SCAN = 121 };
  double lo = log(0.3), hi = log(5.0), step = (hi - lo) / (SCAN - 1), best = INFINITY;
  int at = 0;
  for (int i = 0; i < SCAN; i++) {
    double r = rss_power(lo + step * i, &c);
    if (r < best) {
      best = r;
      at = i;
    }
  }
  double a = lo + step * (at > 0 ? at - 1 : 0), b = lo + step * (at < SCAN - 1 ? at + 1 : at), r;
  double lg = golden(rss_power, &c, a, b, &r);
  *gamma = r <= best ? exp(lg) : exp(lo + step * at);
  return fmin(r, best);
}

/* BIC of a fit with p parameters on k points, RSS floored (see TONE_FLOOR). */
static double bic(double rss, size_t k, int p) {
  double floor2 = (double)k * TONE_FLOOR * TONE_FLOOR;
  return (double)k * log(fmax(rss, floor2) / (double)k) + p * log((double)k);
}

/* ---- the per-channel solve ----------------------------------------------- */

typedef struct channel_fit {
  double lambda, gcv, dof, rms;
  int at_zero;
  unsigned flags;
} channel_fit;

/* min ||A_u s - y_u||^2 + lambda ||D2 s||^2, s >= 0, over the mu rows in
 * rows[]; s receives the n samples. */
static vr_status solve_channel(const double *A, const double *y, const size_t *rows, size_t mu,
                               size_t n, const double *d2, const double *lpinv, const double *nl,
                               const vr_calibration_options *opt, double *s, channel_fit *out,
                               vr_error *err) {
  size_t p = n - 2, mg = mu + p;
  double *au = malloc(mu * n * sizeof *au), *cu = malloc(mu * sizeof *cu);
  double *g = malloc(mg * n * sizeof *g), *h = calloc(mg, sizeof *h);
  double *lo = malloc(n * sizeof *lo), *hi = malloc(n * sizeof *hi);
  double *bf = malloc(mg * n * sizeof *bf), *u = malloc(mg * n * sizeof *u),
         *sv = malloc(n * sizeof *sv);
  vr_status st = VR_OK;
  memset(out, 0, sizeof *out);
  if (!au || !cu || !g || !h || !lo || !hi || !bf || !u || !sv) {
    st = vr_error_set(err, VR_E_NOMEM, "camera calibration: out of memory");
    goto done;
  }
  for (size_t i = 0; i < mu; i++) {
    memcpy(au + i * n, A + rows[i] * n, n * sizeof *au);
    cu[i] = y[rows[i]];
  }
  vr_gcv_problem q = {.m = mu, .n = n, .a = au, .c = cu, .lpinv = lpinv, .nl = nl,
                      .rank_tol = 1e-10, .rho = opt->gcv_rho, .lambda = opt->lambda,
                      .what = "camera calibration"};
  vr_gcv_result res;
  if ((st = vr_recover_gcv_solve(&q, s, &res, err)) != VR_OK) goto done;
  out->lambda = res.lambda;
  out->gcv = res.gcv;
  if (res.flat) out->flags |= VR_CALIBRATION_FLAG_GCV_FLAT;
  double sl = sqrt(res.lambda);
  memcpy(g, au, mu * n * sizeof *g);
  for (size_t i = 0; i < p * n; i++) g[mu * n + i] = sl * d2[i];
  memcpy(h, cu, mu * sizeof *h);
  bool negative = false;
  for (size_t j = 0; j < n; j++) negative |= s[j] < 0.0;
  if (negative) {
    /* Non-negative least squares on the stacked system at the same lambda. */
    for (size_t j = 0; j < n; j++) {
      lo[j] = 0.0;
      hi[j] = INFINITY;
      s[j] = fmax(s[j], 0.0);
    }
    vr_rqp rq = {.n = n, .mg = mg, .g = g, .h = h, .me = 0, .lo = lo, .hi = hi,
                 .rank_tol = 1e-12, .e_ref = 1.0, .max_iter = 0};
    int iterations = 0;
    vr_rqp_result r = vr_recover_rqp(&rq, s, &iterations);
    if (r < 0) {
      st = r == VR_RQP_NOMEM ? vr_error_set(err, VR_E_NOMEM, "camera calibration: out of memory")
                             : vr_error_set(err, VR_E_NUMERIC,
                                            "camera calibration: LAPACK failed in the bound");
      goto done;
    }
    if (r == VR_RQP_MAX_ITER) out->flags |= VR_CALIBRATION_FLAG_MAX_ITER;
  }
  /* Degrees of freedom: with the free samples F, the fit is the projection
   * of [y; 0] onto the range of B = [A_F; sqrt(lambda) D2_F], so the
   * influence matrix on the data is the top-left block of U U^T. */
  size_t nf = 0;
  for (size_t j = 0; j < n; j++) {
    if (s[j] <= 0.0) {
      out->at_zero++;
      continue;
    }
    for (size_t i = 0; i < mg; i++) bf[i * n + nf] = g[i * n + j];
    nf++;
  }
  if (nf > 0) {
    /* bf holds mg x nf with row stride n: compact it. */
    for (size_t i = 0; i < mg; i++) memmove(bf + i * nf, bf + i * n, nf * sizeof *bf);
    size_t qd = mg < nf ? mg : nf;
    int info = vr_recover_svd(mg, nf, bf, u, sv, NULL);
    if (info != 0) {
      st = info == -1000 ? vr_error_set(err, VR_E_NOMEM, "camera calibration: out of memory")
                         : vr_error_set(err, VR_E_NUMERIC,
                                        "camera calibration: LAPACK failed (info %d)", info);
      goto done;
    }
    size_t kept = 0;
    while (kept < qd && sv[kept] > 1e-12 * sv[0]) kept++;
    for (size_t i = 0; i < mu; i++)
      for (size_t k = 0; k < kept; k++) out->dof += u[i * qd + k] * u[i * qd + k];
  }
  double rss = 0.0;
  for (size_t i = 0; i < mu; i++) {
    double v = -cu[i];
    for (size_t j = 0; j < n; j++) v += au[i * n + j] * s[j];
    rss += v * v;
  }
  out->rms = sqrt(rss / (double)mu);
done:
  free(au);
  free(cu);
  free(g);
  free(h);
  free(lo);
  free(hi);
  free(bf);
  free(u);
  free(sv);
  return st;
}

/* ---- the design matrix --------------------------------------------------- */

/* A (NP x n), normalised so that a flat sensitivity of 1 gives a perfect
 * white the response 1; white (n) the perfect white's row; coverage. */
static vr_status design(const vr_spectrum *light, const vr_spectrum *const *refl, size_t n,
                        const double *grid, double *A, double *white, double *coverage,
                        vr_error *err) {
  memset(A, 0, NP * n * sizeof *A);
  memset(white, 0, n * sizeof *white);
  double *peak = calloc(n, sizeof *peak), smax = 0.0;
  if (!peak) return vr_error_set(err, VR_E_NOMEM, "camera calibration: out of memory");
  size_t j = 0;
  for (size_t i = 0; i < ROWS; i++) {
    double nm = FIRST_NM + (double)i;
    if (nm < grid[0] || nm > grid[n - 1]) continue; /* the sensitivity is zero there */
    double S = vr_spectrum_eval(light, nm, VR_INTERP_LINEAR);
    while (j + 2 < n && nm >= grid[j + 1]) j++;
    double t = (nm - grid[j]) / (grid[j + 1] - grid[j]);
    double w0 = 1.0 - t, w1 = t;
    white[j] += w0 * S;
    white[j + 1] += w1 * S;
    smax = fmax(smax, S);
    if (w0 > 0.0) peak[j] = fmax(peak[j], S);
    if (w1 > 0.0) peak[j + 1] = fmax(peak[j + 1], S);
    for (size_t p = 0; p < NP; p++) {
      double v = S * vr_spectrum_eval(refl[p], nm, VR_INTERP_LINEAR);
      A[p * n + j] += w0 * v;
      A[p * n + j + 1] += w1 * v;
    }
  }
  double total = 0.0;
  for (size_t k = 0; k < n; k++) total += white[k];
  size_t lit = 0;
  for (size_t k = 0; k < n; k++) lit += peak[k] >= 0.01 * smax && smax > 0.0;
  free(peak);
  if (!(total > 0.0) || !isfinite(total))
    return vr_error_set(err, VR_E_ARG, "camera calibration: the light has no power on the grid "
                                       "%g-%g nm", grid[0], grid[n - 1]);
  for (size_t k = 0; k < NP * n; k++) A[k] /= total;
  for (size_t k = 0; k < n; k++) white[k] /= total;
  *coverage = (double)lit / (double)n;
  return VR_OK;
}

/* ---- the entry point ----------------------------------------------------- */

void vr_calibration_options_default(vr_calibration_options *opt) {
  opt->tone = VR_TONE_AUTO;
  opt->gamma = 2.2;
  opt->clip = 0.999;
  opt->black = 0.5 / 255.0;
  opt->lambda = -1.0;
  opt->gcv_rho = 1.4;
  opt->passes = 2;
}

void vr_calibration_free(vr_calibration *cal) {
  if (!cal) return;
  free(cal->grid_nm);
  for (int c = 0; c < 3; c++) free(cal->sens[c]);
  memset(cal, 0, sizeof *cal);
}

static vr_status check_options(const vr_calibration_options *o, vr_error *err) {
  if ((int)o->tone < (int)VR_TONE_LINEAR || (int)o->tone > (int)VR_TONE_AUTO)
    return vr_error_set(err, VR_E_ARG, "camera calibration: unknown tone curve %d", (int)o->tone);
  if (o->tone == VR_TONE_GAMMA && !(o->gamma >= 0.2 && o->gamma <= 10.0))
    return vr_error_set(err, VR_E_ARG, "camera calibration: gamma %g, need 0.2 to 10", o->gamma);
  if (!(o->clip > 0.0 && o->clip <= 1.0) || !(o->black >= 0.0 && o->black < o->clip))
    return vr_error_set(err, VR_E_ARG,
                        "camera calibration: need 0 <= black < clip <= 1 (black %g, clip %g)",
                        o->black, o->clip);
  if (isnan(o->lambda) || isinf(o->lambda) || !(o->gcv_rho >= 1.0 && o->gcv_rho < 10.0) ||
      o->passes < 1 || o->passes > 10)
    return vr_error_set(err, VR_E_ARG,
                        "camera calibration: need a finite lambda, 1 <= gcv_rho < 10 and "
                        "passes 1 to 10");
  return VR_OK;
}

typedef struct work {
  double *grid, *A, *white, *d2, *lpinv, *nl, *sv, *s[3];
  vr_spectrum *chart[NP];
} work;

static void work_free(work *w) {
  free(w->grid);
  free(w->A);
  free(w->white);
  free(w->d2);
  free(w->lpinv);
  free(w->nl);
  free(w->sv);
  for (int c = 0; c < 3; c++) free(w->s[c]);
  for (size_t p = 0; p < NP; p++) vr_spectrum_destroy(w->chart[p]);
}

/* The caller's data checked before any allocation, so that a bad argument
 * is named rather than met halfway through the fit. */
static vr_status check_inputs(const double patch_rgb[][3], const vr_spectrum *const *refl,
                              size_t n, const double *grid, vr_error *err) {
  if (n < 5 || n > MAX_SAMPLES)
    return vr_error_set(err, VR_E_ARG, "camera calibration: %zu grid samples, need 5 to %d", n,
                        MAX_SAMPLES);
  for (size_t j = 0; grid && j < n; j++)
    if (!isfinite(grid[j]) || (j > 0 && !(grid[j] > grid[j - 1])))
      return vr_error_set(err, VR_E_ARG,
                          "camera calibration: grid sample %zu (%g nm) is not finite and "
                          "increasing", j, grid[j]);
  for (size_t p = 0; p < NP; p++)
    for (int c = 0; c < 3; c++)
      if (!isfinite(patch_rgb[p][c]))
        return vr_error_set(err, VR_E_ARG, "camera calibration: patch %zu %s value is not finite",
                            p + 1, CHANNEL[c]);
  if (refl)
    for (size_t p = 0; p < NP; p++)
      if (!refl[p])
        return vr_error_set(err, VR_E_ARG, "camera calibration: reflectance of patch %zu is NULL",
                            p + 1);
  return VR_OK;
}

/* The work arrays, the grid (the caller's or the default one) and the
 * chart's reflectances (the caller's, else the BabelColor ones, kept in w
 * to be freed); *R receives the reflectances to use.  On failure the
 * caller frees w. */
static vr_status work_alloc(work *w, size_t n, const double *grid, const vr_spectrum *const *refl,
                            const vr_spectrum *const **R, vr_error *err) {
  size_t p2 = n - 2;
  w->grid = malloc(n * sizeof *w->grid);
  w->A = malloc(NP * n * sizeof *w->A);
  w->white = malloc(n * sizeof *w->white);
  w->d2 = malloc(p2 * n * sizeof *w->d2);
  w->lpinv = malloc(n * p2 * sizeof *w->lpinv);
  w->nl = malloc(n * 2 * sizeof *w->nl);
  w->sv = malloc(n * sizeof *w->sv);
  for (int c = 0; c < 3; c++) w->s[c] = malloc(n * sizeof *w->s[c]);
  if (!w->grid || !w->A || !w->white || !w->d2 || !w->lpinv || !w->nl || !w->sv || !w->s[0] ||
      !w->s[1] || !w->s[2])
    return vr_error_set(err, VR_E_NOMEM, "camera calibration: out of memory");
  for (size_t j = 0; j < n; j++)
    w->grid[j] = grid ? grid[j] : VR_CAMERA_DEFAULT_START_NM + VR_CAMERA_DEFAULT_STEP_NM * (double)j;
  *R = refl;
  if (!refl) {
    for (size_t p = 0; p < NP; p++)
      if (!(w->chart[p] = vr_colorchecker_patch(p, err))) return err ? err->status : VR_E_NOMEM;
    *R = (const vr_spectrum *const *)w->chart;
  }
  return VR_OK;
}

/* The design matrix under the light, its condition and the smoothness
 * operator: what every channel's solve shares. */
static vr_status build_design(work *w, const vr_spectrum *light, const vr_spectrum *const *R,
                              size_t n, vr_calibration *cal, vr_error *err) {
  vr_status st = design(light, R, n, w->grid, w->A, w->white, &cal->coverage, err);
  if (st) return st;
  if (cal->coverage < 0.9) cal->flags |= VR_CALIBRATION_FLAG_PARTIAL_LIGHT;
  int info = vr_recover_svd(NP, n, w->A, NULL, w->sv, NULL);
  if (info == 0) info = vr_recover_smoothness(n, w->grid, w->d2, w->lpinv, w->nl);
  if (info != 0)
    return info == -1000 ? vr_error_set(err, VR_E_NOMEM, "camera calibration: out of memory")
                         : vr_error_set(err, VR_E_NUMERIC,
                                        "camera calibration: LAPACK failed (info %d)", info);
  size_t q = NP < n ? NP : n;
  cal->cond = w->sv[q - 1] > 0.0 ? w->sv[0] / w->sv[q - 1] : INFINITY;
  return VR_OK;
}

/* Which patch channels are data (inside (black, clip) and not flagged):
 * use[p][c], and per channel the mu[c] patches in rows[c].  Refuses a
 * channel with too few patches, too little light, or too few neutrals to
 * choose its tone curve, before any fit is spent on it. */
static vr_status select_patches(const double patch_rgb[][3], const bool *clipped_or_null,
                                const vr_calibration_options *opt, vr_calibration *cal,
                                bool use[NP][3], size_t rows[3][NP], size_t mu[3], vr_error *err) {
  for (size_t p = 0; p < NP; p++) {
    bool any_out = false;
    for (int c = 0; c < 3; c++) {
      double v = patch_rgb[p][c];
      use[p][c] = !(clipped_or_null && clipped_or_null[p]) && v > opt->black && v < opt->clip;
      if (use[p][c]) rows[c][mu[c]++] = p;
      else any_out = true;
    }
    cal->clipped[p] = any_out;
    if (any_out) cal->clipped_patches++;
    else cal->used_patches++;
  }
  if (cal->clipped_patches) cal->flags |= VR_CALIBRATION_FLAG_CLIPPED;
  for (int c = 0; c < 3; c++) {
    cal->used[c] = (int)mu[c];
    if (mu[c] < 3)
      return vr_error_set(err, VR_E_ARG,
                          "camera calibration: only %zu usable patches in the %s channel (need 3; "
                          "the others are clipped, flagged or at or below the black level %g)",
                          mu[c], CHANNEL[c], opt->black);
    double brightest = 0.0;
    for (size_t i = 0; i < mu[c]; i++) brightest = fmax(brightest, patch_rgb[rows[c][i]][c]);
    if (brightest < DIM_LIMIT)
      return vr_error_set(err, VR_E_ARG,
                          "camera calibration: the %s channel's brightest usable patch is %g: the "
                          "light has almost no power where that channel responds, so its "
                          "sensitivity cannot be estimated under this light",
                          CHANNEL[c], brightest);
    cal->neutrals[c] = 0;
    for (size_t i = 0; i < NEUTRALS; i++)
      cal->neutrals[c] += use[VR_CALIBRATION_FIRST_NEUTRAL + i][c];
    if (opt->tone == VR_TONE_AUTO && cal->neutrals[c] < 3)
      return vr_error_set(err, VR_E_ARG,
                          "camera calibration: only %d of the six neutral patches (19-24) are "
                          "usable in the %s channel: the tone curve cannot be chosen (impose one)",
                          cal->neutrals[c], CHANNEL[c]);
  }
  return VR_OK;
}

/* Expected relative responses of the neutrals in channel c: the flat ones
 * on the first pass, then through the previous pass's sensitivity, whose
 * largest change is reported.  rk, vk receive the k usable neutrals'
 * ratios and encoded values, which the tone curve is fitted to. */
static size_t neutral_ratios(const work *w, size_t n, int c, int pass, const double *rho_flat,
                             bool use[NP][3], const double patch_rgb[][3], vr_calibration *cal,
                             double *rk, double *vk) {
  size_t k = 0;
  double ws = 0.0;
  for (size_t j = 0; pass > 0 && j < n; j++) ws += w->white[j] * w->s[c][j];
  cal->neutral_correction[c] = 0.0;
  for (size_t i = 0; i < NEUTRALS; i++) {
    double rho = rho_flat[i];
    size_t p = VR_CALIBRATION_FIRST_NEUTRAL + i;
    if (pass > 0 && ws > 0.0) {
      double v = 0.0;
      for (size_t j = 0; j < n; j++) v += w->A[p * n + j] * w->s[c][j];
      rho = v / ws;
      double change = fabs(rho / rho_flat[i] - 1.0);
      cal->neutral_correction[c] = fmax(cal->neutral_correction[c], change);
    }
    if (use[p][c] && rho > 0.0) {
      rk[k] = rho;
      vk[k++] = patch_rgb[p][c];
    }
  }
  return k;
}

/* The RMS residual of the power law with the imposed exponent (its best
 * exposure only), which is what --tone gamma=G is held to rather than the
 * fitted exponent's. */
static double imposed_gamma_rms(const double *rk, const double *vk, size_t k, double gamma) {
  double num = 0.0, den = 0.0, e = 1.0 / gamma;
  for (size_t i = 0; i < k; i++) {
    num += vk[i] * pow(rk[i], e);
    den += pow(rk[i], 2 * e);
  }
  double a = num / den, rss = 0.0;
  for (size_t i = 0; i < k; i++) rss += pow(a * pow(rk[i], e) - vk[i], 2);
  return sqrt(rss / (double)k);
}

/* Channel c's tone curve: the three curves fitted to the k neutrals and the
 * least BIC chosen, or the imposed one kept with the fits shown beside it. */
static vr_status choose_tone(const double *rk, const double *vk, size_t k, int c,
                             const vr_calibration_options *opt, vr_calibration *cal, vr_error *err) {
  for (int t = 0; t < 3; t++) cal->tone_fit_rms[c][t] = NAN;
  double gfit = NAN, score[3] = {INFINITY, INFINITY, INFINITY};
  if (k >= 3) {
    for (int t = 0; t < 3; t++) {
      double rss = fit_tone((vr_tone)t, rk, vk, k, &gfit);
      cal->tone_fit_rms[c][t] = sqrt(rss / (double)k);
      score[t] = bic(rss, k, t == VR_TONE_GAMMA ? 2 : 1);
    }
  } else if (opt->tone == VR_TONE_AUTO) {
    return vr_error_set(err, VR_E_ARG, "camera calibration: only %zu usable neutrals in the %s "
                                       "channel", k, CHANNEL[c]);
  }
  if (opt->tone == VR_TONE_AUTO) {
    int best = 0;
    for (int t = 1; t < 3; t++)
      if (score[t] < score[best]) best = t;
    cal->tone[c] = (vr_tone)best;
    cal->gamma[c] = gfit;
  } else {
    cal->tone[c] = opt->tone;
    cal->gamma[c] = opt->tone == VR_TONE_GAMMA ? opt->gamma : gfit;
  }
  cal->tone_rms[c] = cal->tone_fit_rms[c][cal->tone[c]];
  if (opt->tone == VR_TONE_GAMMA && k >= 1) cal->tone_rms[c] = imposed_gamma_rms(rk, vk, k, opt->gamma);
  return VR_OK;
}

/* Channel c's sensitivity from the patches linearised by its tone curve. */
static vr_status solve_sensitivity(work *w, const double patch_rgb[][3], const size_t *rows,
                                   size_t mu, size_t n, int c, const vr_calibration_options *opt,
                                   vr_calibration *cal, vr_error *err) {
  double y[NP];
  double tg = cal->tone[c] == VR_TONE_GAMMA ? cal->gamma[c] : 1.0;
  for (size_t p = 0; p < NP; p++) y[p] = vr_tone_decode(cal->tone[c], tg, patch_rgb[p][c]);
  channel_fit fit;
  vr_status st = solve_channel(w->A, y, rows, mu, n, w->d2, w->lpinv, w->nl, opt, w->s[c], &fit, err);
  if (st) {
    vr_error_prefix(err, "%s channel: ", CHANNEL[c]);
    return st;
  }
  cal->lambda[c] = fit.lambda;
  cal->gcv[c] = fit.gcv;
  cal->dof[c] = fit.dof;
  cal->rms[c] = fit.rms;
  cal->at_zero[c] = fit.at_zero;
  cal->flags |= fit.flags;
  return VR_OK;
}

/* The sensitivities divided by the green peak: their overall scale is not
 * identifiable from one exposure (vr/calibrate.h), their ratios are. */
static vr_status scale_to_green(work *w, size_t n, vr_error *err) {
  double gmax = 0.0;
  for (size_t j = 0; j < n; j++) gmax = fmax(gmax, w->s[1][j]);
  if (!(gmax > 0.0) || !isfinite(gmax))
    return vr_error_set(err, VR_E_NUMERIC, "camera calibration: the green sensitivity came out zero");
  for (int c = 0; c < 3; c++)
    for (size_t j = 0; j < n; j++) w->s[c][j] /= gmax;
  return VR_OK;
}

vr_status vr_calibrate_camera(const double patch_rgb[][3], const bool *clipped_or_null,
                              const vr_spectrum *light, const vr_spectrum *const *refl, size_t n,
                              const double *grid, const vr_calibration_options *opt_in,
                              vr_calibration *out, vr_error *err) {
  if (!patch_rgb || !light || !out)
    return vr_error_set(err, VR_E_ARG, "camera calibration: NULL argument");
  vr_calibration_options opt;
  vr_calibration_options_default(&opt);
  if (opt_in) opt = *opt_in;
  vr_status st = check_options(&opt, err);
  if (st) return st;
  if (!grid) n = VR_CAMERA_DEFAULT_SAMPLES;
  if ((st = check_inputs(patch_rgb, refl, n, grid, err))) return st;

  work w = {0};
  const vr_spectrum *const *R;
  vr_calibration cal;
  memset(&cal, 0, sizeof cal);
  cal.options = opt;
  bool use[NP][3];
  size_t rows[3][NP], mu[3] = {0, 0, 0};
  if ((st = work_alloc(&w, n, grid, refl, &R, err)) ||
      (st = build_design(&w, light, R, n, &cal, err)) ||
      (st = select_patches(patch_rgb, clipped_or_null, &opt, &cal, use, rows, mu, err)))
    goto fail;

  double rho_flat[NEUTRALS];
  for (size_t i = 0; i < NEUTRALS; i++) {
    double v = 0.0;
    for (size_t j = 0; j < n; j++) v += w.A[(VR_CALIBRATION_FIRST_NEUTRAL + i) * n + j];
    rho_flat[i] = v; /* the white row sums to 1 */
  }
  for (int pass = 0; pass < opt.passes; pass++)
    for (int c = 0; c < 3; c++) {
      double rk[NEUTRALS], vk[NEUTRALS];
      size_t k = neutral_ratios(&w, n, c, pass, rho_flat, use, patch_rgb, &cal, rk, vk);
      if ((st = choose_tone(rk, vk, k, c, &opt, &cal, err)) ||
          (st = solve_sensitivity(&w, patch_rgb, rows[c], mu[c], n, c, &opt, &cal, err)))
        goto fail;
    }
  if ((st = scale_to_green(&w, n, err))) goto fail;

  cal.n = n;
  cal.grid_nm = w.grid;
  w.grid = NULL;
  for (int c = 0; c < 3; c++) {
    cal.sens[c] = w.s[c];
    w.s[c] = NULL;
  }
  work_free(&w);
  *out = cal;
  return VR_OK;
fail:
  work_free(&w);
  return st;
}
