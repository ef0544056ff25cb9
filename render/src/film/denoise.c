/* The display denoiser (vr/denoise.h): non-local means on the colour,
 * guided by the albedo, normal and nearness the camera pass recorded, after
 * Rousselle, Knaus & Zwicker (2012, "Adaptive rendering with non-local
 * means filtering") for the colour term and Rousselle, Manzi & Zwicker
 * (2013, "Robust denoising using feature and color information") for the
 * features.  A pixel p becomes the weighted mean of the pixels q of its
 * (2r + 1)^2 window, with weight min(w_c, w_f):
 *
 *   w_c = exp(-max(0, d_c)), d_c the mean over the (2f + 1)^2 patches
 *         around p and q and over X, Y, Z of
 *           [(u_p - u_q)^2 - (v_p + min(v_p, v_q))] / (eps + k_c^2 (v_p + v_q)),
 *         u a pixel's mean and v its variance (from the two halves of its
 *         samples, averaged over the pixels of its 3 x 3 with its
 *         features): two pixels whose difference is what their noise
 *         explains are alike;
 *   w_f = exp(-max(0, max_j Phi_j)) over the feature groups j (albedo,
 *         normal, nearness), with
 *           Phi_j = [|f_p - f_q|^2 - (V_p + min(V_p, V_q))] / (k_f^2 max(tau, V_p, |grad f_p|^2)),
 *         V a feature's variance over the pixel's samples (large where a
 *         pixel straddles an edge): pixels across a geometric or texture
 *         edge are not mixed whatever their colours.
 *
 * Why this method: it needs nothing but the film (no trained network, no
 * library Debian lacks), its weights come from the estimates' own variances
 * (so a converged pixel is left alone: its variance is zero), and the
 * features keep edges that the noise would otherwise hide.  Its cost is
 * (2r + 1)^2 passes over the image (r = 8: 289), each a few tens of
 * operations a pixel, on bands of rows in parallel.
 *
 * The parameters (vr_denoise_params: r = 8, f = 2, k_c = 0.9, k_f = 0.4,
 * tau = 1e-3) were chosen on the Cornell box at 8 samples a pixel against
 * a reference of 2048 (bench/bench_denoise.c; docs/vr-render.md,
 * "Denoising"), from Rousselle, Manzi & Zwicker's 10, 3, 0.45, 0.6 and
 * 1e-3, which left 36 % more error.  Their selection among filters of
 * three strengths by Stein's unbiased risk estimate was tried and left
 * out: with path tracing's heavy-tailed noise the estimate ranked the
 * filters in the wrong order.
 *
 * Domain: finite, non-negative-variance inputs; pixels outside the image
 * are not used (the patches clamp at the border). */
#include <math.h>
#include <pthread.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "vr/denoise.h"

typedef struct shared {
  int W, H, r, f;
  double kc2, kf2, tau;
  const double *u;    /* xyz */
  double *v;          /* per pixel and channel: smoothed variance of the mean */
  const double *feat; /* VR_DENOISE_FEATURES per pixel */
  const double *fvar; /* VR_DENOISE_GROUPS per pixel */
  double *fnorm;      /* VR_DENOISE_GROUPS per pixel: k_f^2 max(tau, V, |grad f|^2) */
  double eps[3];
  double *out;
} shared;

typedef struct band {
  const shared *s;
  int y0, y1;
  int failed;
} band;

static const int GROUP_FIRST[VR_DENOISE_GROUPS + 1] = {0, 3, 6, 7};

static int clampi(int v, int lo, int hi) { return v < lo ? lo : v > hi ? hi : v; }

/* The colour term of pixel (x, y) against its partner at the offset
 * (clamped into the image). */
static double colour_term(const shared *s, int x, int y, int dx, int dy) {
  int qx = clampi(x + dx, 0, s->W - 1), qy = clampi(y + dy, 0, s->H - 1);
  size_t p = (size_t)y * (size_t)s->W + (size_t)x, q = (size_t)qy * (size_t)s->W + (size_t)qx;
  double d = 0;
  for (int c = 0; c < 3; c++) {
    double vp = s->v[3 * p + (size_t)c], vq = s->v[3 * q + (size_t)c];
    double diff = s->u[3 * p + (size_t)c] - s->u[3 * q + (size_t)c];
    d += (diff * diff - (vp + fmin(vp, vq))) / (s->eps[c] + vp + vq);
  }
  return d / 3;
}

static double feature_weight(const shared *s, size_t p, size_t q) {
  double worst = 0;
  for (int j = 0; j < VR_DENOISE_GROUPS; j++) {
    double d2 = 0;
    for (int k = GROUP_FIRST[j]; k < GROUP_FIRST[j + 1]; k++) {
      double d = s->feat[p * VR_DENOISE_FEATURES + (size_t)k] -
                 s->feat[q * VR_DENOISE_FEATURES + (size_t)k];
      d2 += d * d;
    }
    double vp = s->fvar[p * VR_DENOISE_GROUPS + (size_t)j];
    double vq = s->fvar[q * VR_DENOISE_GROUPS + (size_t)j];
    double phi = (d2 - (vp + fmin(vp, vq))) / s->fnorm[p * VR_DENOISE_GROUPS + (size_t)j];
    if (phi > worst) worst = phi;
  }
  return exp(-worst);
}

static void *run_band(void *arg) {
  band *b = arg;
  const shared *s = b->s;
  int W = s->W, H = s->H, f = s->f;
  int e0 = b->y0 - f < 0 ? 0 : b->y0 - f, e1 = b->y1 + f > H ? H : b->y1 + f;
  int rows = e1 - e0, n = b->y1 - b->y0;
  double *D = malloc((size_t)rows * (size_t)W * sizeof *D);
  double *Hs = malloc((size_t)rows * (size_t)W * sizeof *Hs);
  size_t nb = (size_t)n * (size_t)W;
  double *num = calloc(nb * 3, sizeof *num);
  double *den = calloc(nb, sizeof *den);
  if (!D || !Hs || !num || !den) {
    b->failed = 1;
    goto out;
  }
  for (int dy = -s->r; dy <= s->r; dy++)
    for (int dx = -s->r; dx <= s->r; dx++) {
      /* The colour term on the band and its halo, then its box mean over
       * the patch: rows first, then columns. */
      for (int y = e0; y < e1; y++) {
        double *row = &D[(size_t)(y - e0) * (size_t)W];
        for (int x = 0; x < W; x++) row[x] = colour_term(s, x, y, dx, dy);
        double *hrow = &Hs[(size_t)(y - e0) * (size_t)W];
        double acc = 0;
        int lo = 0, hi = -1;
        for (int x = 0; x < W; x++) {
          int want_lo = x - f < 0 ? 0 : x - f, want_hi = x + f >= W ? W - 1 : x + f;
          while (hi < want_hi) acc += row[++hi];
          while (lo < want_lo) acc -= row[lo++];
          hrow[x] = acc / (hi - lo + 1);
        }
      }
      for (int y = b->y0; y < b->y1; y++) {
        int qy = y + dy;
        if (qy < 0 || qy >= H) continue;
        int lo = (y - f < 0 ? 0 : y - f) - e0, hi = (y + f >= H ? H - 1 : y + f) - e0;
        for (int x = 0; x < W; x++) {
          int qx = x + dx;
          if (qx < 0 || qx >= W) continue;
          double dc = 0;
          for (int k = lo; k <= hi; k++) dc += Hs[(size_t)k * (size_t)W + (size_t)x];
          dc /= (hi - lo + 1) * s->kc2;
          /* Weights under 1e-4 (a distance above 9.2) are left out. */
          if (dc > 9.2) continue;
          size_t p = (size_t)y * (size_t)W + (size_t)x, q = (size_t)qy * (size_t)W + (size_t)qx;
          double w = fmin(dc > 0 ? exp(-dc) : 1.0, feature_weight(s, p, q));
          if (w < 1e-4) continue;
          size_t o = (size_t)(y - b->y0) * (size_t)W + (size_t)x;
          den[o] += w;
          for (int ch = 0; ch < 3; ch++) num[3 * o + (size_t)ch] += w * s->u[3 * q + (size_t)ch];
        }
      }
    }
  for (size_t o = 0; o < nb; o++) {
    size_t p = (size_t)b->y0 * (size_t)W + o;
    for (int ch = 0; ch < 3; ch++)
      s->out[3 * p + (size_t)ch] = den[o] > 0 ? num[3 * o + (size_t)ch] / den[o] : s->u[3 * p + (size_t)ch];
  }
out:
  free(D);
  free(Hs);
  free(num);
  free(den);
  return NULL;
}

/* Whether q's features are those of p within p's own spread: for each
 * group, |f_p - f_q|^2 at most 4 max(tau, V_p). */
static bool alike(const shared *s, size_t p, size_t q) {
  for (int j = 0; j < VR_DENOISE_GROUPS; j++) {
    double d2 = 0;
    for (int k = GROUP_FIRST[j]; k < GROUP_FIRST[j + 1]; k++) {
      double d = s->feat[p * VR_DENOISE_FEATURES + (size_t)k] - s->feat[q * VR_DENOISE_FEATURES + (size_t)k];
      d2 += d * d;
    }
    if (d2 > 4 * fmax(s->tau, s->fvar[p * VR_DENOISE_GROUPS + (size_t)j])) return false;
  }
  return true;
}

static vr_status check_finite(const double *v, size_t n, int per_pixel, int W, const char *what,
                              vr_error *err) {
  for (size_t i = 0; i < n; i++)
    if (!isfinite(v[i])) {
      size_t p = i / (size_t)per_pixel;
      return vr_error_set(err, VR_E_RANGE, "denoise: %s of pixel (%zu, %zu) is %g", what,
                          p % (size_t)W, p / (size_t)W, v[i]);
    }
  return VR_OK;
}

vr_status vr_denoise(int W, int H, const double *xyz, const double *xyz_b, const double *feat,
                     const double *feat_var, const vr_denoise_params *params, double *out,
                     vr_error *err) {
  if (W < 1 || H < 1) return vr_error_set(err, VR_E_ARG, "denoise: image of %d x %d pixels", W, H);
  size_t px = (size_t)W * (size_t)H;
  vr_status st;
  if ((st = check_finite(xyz, px * 3, 3, W, "the XYZ", err)) ||
      (st = check_finite(xyz_b, px * 3, 3, W, "the second half's XYZ", err)) ||
      (st = check_finite(feat, px * VR_DENOISE_FEATURES, VR_DENOISE_FEATURES, W, "a feature", err)) ||
      (st = check_finite(feat_var, px * VR_DENOISE_GROUPS, VR_DENOISE_GROUPS, W,
                         "a feature's variance", err)))
    return st;
  vr_denoise_params p = params ? *params : (vr_denoise_params){0};
  shared s = {.W = W, .H = H, .r = p.radius > 0 ? p.radius : 8, .f = p.patch > 0 ? p.patch : 2,
              .u = xyz, .feat = feat, .fvar = feat_var, .out = out};
  double kc = p.k_colour > 0 ? p.k_colour : 0.9, kf = p.k_feature > 0 ? p.k_feature : 0.4;
  s.kc2 = kc * kc;
  s.kf2 = kf * kf;
  s.tau = p.tau > 0 ? p.tau : 1e-3;
  double *raw = malloc(px * 3 * sizeof *raw);
  s.v = malloc(px * 3 * sizeof *s.v);
  s.fnorm = malloc(px * VR_DENOISE_GROUPS * sizeof *s.fnorm);
  if (!raw || !s.v || !s.fnorm) {
    st = vr_error_set(err, VR_E_NOMEM, "denoise: %d x %d pixels: out of memory", W, H);
    goto out;
  }
  /* Each channel's variance of the mean, (m - b)^2 (one degree of freedom),
   * averaged over the 3 x 3 pixels around (nine). */
  double mean[3] = {0, 0, 0};
  for (size_t i = 0; i < px; i++)
    for (int c = 0; c < 3; c++) {
      double d = xyz[3 * i + (size_t)c] - xyz_b[3 * i + (size_t)c];
      raw[3 * i + (size_t)c] = d * d;
      mean[c] += fabs(xyz[3 * i + (size_t)c]) / (double)px;
    }
  /* eps keeps two noiseless pixels comparable: a millionth of the
   * channel's mean, squared. */
  for (int c = 0; c < 3; c++) s.eps[c] = 1e-12 * mean[c] * mean[c] + 1e-300;
  /* Each feature group's normaliser at each pixel. */
  for (int y = 0; y < H; y++)
    for (int x = 0; x < W; x++) {
      size_t i = (size_t)y * (size_t)W + (size_t)x;
      size_t xl = (size_t)y * (size_t)W + (size_t)(x > 0 ? x - 1 : x);
      size_t xr = (size_t)y * (size_t)W + (size_t)(x + 1 < W ? x + 1 : x);
      size_t yu = (size_t)(y > 0 ? y - 1 : y) * (size_t)W + (size_t)x;
      size_t yd = (size_t)(y + 1 < H ? y + 1 : y) * (size_t)W + (size_t)x;
      for (int j = 0; j < VR_DENOISE_GROUPS; j++) {
        double g2 = 0;
        for (int k = GROUP_FIRST[j]; k < GROUP_FIRST[j + 1]; k++) {
          double gx = (feat[xr * VR_DENOISE_FEATURES + (size_t)k] -
                       feat[xl * VR_DENOISE_FEATURES + (size_t)k]) / 2;
          double gy = (feat[yd * VR_DENOISE_FEATURES + (size_t)k] -
                       feat[yu * VR_DENOISE_FEATURES + (size_t)k]) / 2;
          g2 += gx * gx + gy * gy;
        }
        double V = feat_var[i * VR_DENOISE_GROUPS + (size_t)j];
        s.fnorm[i * VR_DENOISE_GROUPS + (size_t)j] = s.kf2 * fmax(s.tau, fmax(V, g2));
      }
    }
  /* ... averaged over the pixels of the 3 x 3 around that have the same
   * features (a pixel beside an edge takes nothing of the other side's
   * noise, which may be many times its own). */
  for (int y = 0; y < H; y++)
    for (int x = 0; x < W; x++) {
      size_t p0 = (size_t)y * (size_t)W + (size_t)x;
      double sum[3] = {0, 0, 0};
      int k = 0;
      for (int j = y > 0 ? y - 1 : 0; j <= y + 1 && j < H; j++)
        for (int i = x > 0 ? x - 1 : 0; i <= x + 1 && i < W; i++) {
          size_t q = (size_t)j * (size_t)W + (size_t)i;
          if (q != p0 && !alike(&s, p0, q)) continue;
          for (int c = 0; c < 3; c++) sum[c] += raw[3 * q + (size_t)c];
          k++;
        }
      for (int c = 0; c < 3; c++) s.v[3 * p0 + (size_t)c] = sum[c] / k;
    }
  int threads = p.threads > 0 ? p.threads : 1;
  if (threads > H) threads = H;
  if (threads > 64) threads = 64;
  band bands[64];
  pthread_t th[64];
  bool created[64] = {false};
  for (int t = 0; t < threads; t++) {
    bands[t] = (band){&s, (int)((long)H * t / threads), (int)((long)H * (t + 1) / threads), 0};
    created[t] = t < threads - 1 && pthread_create(&th[t], NULL, run_band, &bands[t]) == 0;
    if (!created[t]) run_band(&bands[t]);
  }
  for (int t = 0; t < threads; t++)
    if (created[t]) pthread_join(th[t], NULL);
  for (int t = 0; t < threads; t++)
    if (bands[t].failed) {
      st = vr_error_set(err, VR_E_NOMEM, "denoise: %d x %d pixels: out of memory", W, H);
      goto out;
    }
  st = VR_OK;
out:
  free(raw);
  free(s.v);
  free(s.fnorm);
  return st;
}
