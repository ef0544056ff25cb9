/* How vr-rgb2spec's choice of smoothing copes with noisy photos: the 24
 * ColorChecker patches (BabelColor averages) rendered through the CIE 1931
 * observer with sRGB primaries (400-700 nm / 10 nm) under 2 or 4 lights,
 * Gaussian noise of sigma = 0.002 added to every pixel's linear response,
 * then quantised as a 16-bit linear or an 8-bit sRGB file would store it.
 *
 * Two sizes of region, each drawn 20 times per patch:
 *   - a single pixel (the noise as it is, sigma_pixel from
 *     vr_recover_pixel_sigma);
 *   - a region of 900 pixels (a 30 x 30 sampled patch square), whose mean
 *     and standard deviation are what the tool measures, its noise from
 *     vr_recover_mean_sigma.
 * Rules compared, all with the regularised method and the bounds:
 *   gcv     the previous default (modified GCV, rho 1.4, no noise given)
 *   discr   Morozov's discrepancy principle with the noise given
 *   upre    unbiased predictive risk with the noise given (the default of
 *           vr_recover_noisy, which the tool calls)
 *   oracle  the best single fixed lambda for the whole set (a scan using the
 *           true spectra: not available to the tool, a yardstick)
 * Printed: mean spectral RMSE over patches and draws, and the share of
 * recoveries flagged as missing their photo (VR_RECOVER_FLAG_MISFIT). */
#include "vr/colorchecker.h"
#include "vr/colour.h"
#include "vr/recover.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PATCHES VR_COLORCHECKER_PATCHES
#define DRAWS 20
#define MAXL 4
#define SIGMA 0.002

static void die(const vr_error *err) {
  fprintf(stderr, "bench_rgb2spec_noise: %s\n", err->message);
  exit(1);
}

static uint64_t rng_state = 0x2545f4914f6cdd1dULL;
static double uniform(void) {
  rng_state ^= rng_state << 13;
  rng_state ^= rng_state >> 7;
  rng_state ^= rng_state << 17;
  return ((double)(rng_state >> 11) + 0.5) / 9007199254740992.0;
}
static double gauss(void) { return sqrt(-2.0 * log(uniform())) * cos(2.0 * M_PI * uniform()); }

enum { IN16 = 0, IN8 = 1 };

/* Stored value, decoded back to linear, of one noisy pixel; the clip mark
 * of the code; the size of one code step in linear units at that level. */
static double store(int kind, double lin, unsigned char *clip, double *step) {
  double v = fmin(fmax(lin, 0.0), 1.0);
  long top = kind == IN16 ? 65535 : 255, code;
  double out;
  if (kind == IN16) {
    code = lround(v * 65535.0);
    out = (double)code / 65535.0;
    *step = 1.0 / 65535.0;
  } else {
    code = lround(vr_srgb_encode(v) * 255.0);
    out = vr_srgb_decode((double)code / 255.0);
    double e = (double)code / 255.0;
    double slope = e <= 0.04045 ? 1.0 / 12.92 : 2.4 / 1.055 * pow((e + 0.055) / 1.055, 1.4);
    *step = slope / 255.0;
  }
  *clip = code == 0 ? VR_CLIP_LOW : code == top ? VR_CLIP_HIGH : VR_CLIP_NONE;
  return out;
}

typedef struct sample {
  double c[3 * MAXL], sigma[3 * MAXL];
  unsigned char clip[3 * MAXL];
} sample;

/* One region: npix noisy pixels of patch p, averaged as the tool does. */
static void draw(const vr_recovery_system *s, const double *truth, int kind, long npix,
                 sample *out) {
  size_t m = vr_recovery_system_rows(s);
  double clean[3 * MAXL];
  vr_render_rgb(s, truth, clean);
  for (size_t i = 0; i < m; i++) {
    double sum = 0.0, sum2 = 0.0, step = 0.0;
    long clipped_hi = 0, clipped_lo = 0;
    for (long k = 0; k < npix; k++) {
      unsigned char mark;
      double v = store(kind, clean[i] + SIGMA * gauss(), &mark, &step);
      sum += v;
      sum2 += v * v;
      clipped_hi += mark == VR_CLIP_HIGH;
      clipped_lo += mark == VR_CLIP_LOW;
    }
    double mean = sum / (double)npix;
    double sd = npix > 1 ? sqrt(fmax(0.0, (sum2 - sum * mean) / (double)(npix - 1))) : SIGMA;
    unsigned char mark;
    (void)store(kind, mean, &mark, &step); /* the code step at the mean's level */
    out->c[i] = mean;
    /* The tool marks a channel clipped when its pixels reach the ends. */
    out->clip[i] = clipped_hi * 2 > npix ? VR_CLIP_HIGH : clipped_lo * 2 > npix ? VR_CLIP_LOW : VR_CLIP_NONE;
    out->sigma[i] = npix > 1 ? vr_recover_mean_sigma(sd, npix, step) : vr_recover_pixel_sigma(sd, step);
  }
}

typedef struct score {
  double rmse;
  double misfit_share;
} score;

static score run_method(const vr_recovery_system *s, const double *const *truth,
                        const sample *data, int with_sigma, vr_recover_method method) {
  vr_error err = {0};
  size_t n = vr_recovery_system_samples(s);
  score sc = {0, 0};
  for (size_t p = 0; p < PATCHES; p++)
    for (int d = 0; d < DRAWS; d++) {
      const sample *x = &data[p * DRAWS + (size_t)d];
      double r[64];
      vr_recover_info info;
      if (vr_recover_noisy(s, method, x->c, with_sigma ? x->sigma : NULL, x->clip,
                           r, &info, &err))
        die(&err);
      double e2 = 0.0;
      for (size_t j = 0; j < n; j++) e2 += (r[j] - truth[p][j]) * (r[j] - truth[p][j]);
      sc.rmse += sqrt(e2 / (double)n);
      if (info.flags & VR_RECOVER_FLAG_MISFIT) sc.misfit_share += 1.0;
    }
  sc.rmse /= PATCHES * DRAWS;
  sc.misfit_share /= PATCHES * DRAWS;
  return sc;
}

static score run(const vr_recovery_system *s, const double *const *truth, const sample *data,
                 int with_sigma) {
  return run_method(s, truth, data, with_sigma, VR_RECOVER_REGULARISED);
}

static vr_recovery_system *make(const vr_camera *cam, size_t nl, const vr_spectrum *const *lights,
                                const vr_recovery_options *opt) {
  vr_error err = {0};
  vr_recovery_system *s = vr_recovery_system_create(cam, nl, lights, NULL, opt, &err);
  if (!s) die(&err);
  size_t n = vr_recovery_system_samples(s);
  double ones[64], white[3 * MAXL], scale[MAXL];
  for (size_t j = 0; j < n; j++) ones[j] = 1.0;
  vr_render_rgb(s, ones, white);
  for (size_t l = 0; l < nl; l++)
    scale[l] = 0.95 / fmax(white[3 * l], fmax(white[3 * l + 1], white[3 * l + 2]));
  vr_recovery_system_destroy(s);
  if (!(s = vr_recovery_system_create(cam, nl, lights, scale, opt, &err))) die(&err);
  return s;
}

int main(void) {
  vr_error err = {0};
  vr_camera *cam = vr_camera_create_srgb(0, NULL, &err);
  if (!cam) die(&err);
  size_t n = vr_camera_samples(cam);
  const char *names[MAXL] = {"D65", "A", "LED-B3", "F2"};
  vr_spectrum *lights[MAXL];
  for (int i = 0; i < MAXL; i++)
    if (!(lights[i] = vr_illuminant(names[i], &err))) die(&err);
  double *truth[PATCHES];
  for (size_t p = 0; p < PATCHES; p++) {
    vr_spectrum *raw = vr_colorchecker_patch(p, &err);
    if (!raw) die(&err);
    truth[p] = malloc(n * sizeof(double));
    for (size_t j = 0; j < n; j++)
      truth[p][j] = vr_spectrum_eval(raw, vr_camera_grid(cam)[j], VR_INTERP_LINEAR);
    vr_spectrum_destroy(raw);
  }
  sample *data = malloc(PATCHES * DRAWS * sizeof *data);
  printf("ColorChecker, sigma %.3g per pixel, %d draws per patch: mean spectral RMSE "
         "[share flagged misfit]\n", SIGMA, DRAWS);
  printf("%-26s %-16s %-16s %-16s %-16s %-16s\n", "case", "bounded", "gcv (old)", "discrepancy",
         "upre (default)", "oracle lambda");
  static const struct {
    size_t nl;
    int kind;
    long npix;
  } cases[] = {{2, IN8, 1}, {2, IN8, 900}, {4, IN8, 1}, {4, IN8, 900}, {4, IN16, 1}, {4, IN16, 900}};
  for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
    size_t nl = cases[k].nl;
    vr_recovery_options o;
    vr_recovery_options_default(&o);
    if (cases[k].kind == IN8) o.noise = VR_NOISE_SRGB8;
    vr_recovery_system *gcv = make(cam, nl, (const vr_spectrum *const *)lights, &o);
    for (size_t p = 0; p < PATCHES; p++)
      for (int d = 0; d < DRAWS; d++) draw(gcv, truth[p], cases[k].kind, cases[k].npix, &data[p * DRAWS + (size_t)d]);
    score g = run(gcv, (const double *const *)truth, data, 0);
    score bd = run_method(gcv, (const double *const *)truth, data, 1, VR_RECOVER_BOUNDED);
    o.lambda_rule = VR_LAMBDA_DISCREPANCY;
    vr_recovery_system *dp = make(cam, nl, (const vr_spectrum *const *)lights, &o);
    score dsc = run(dp, (const double *const *)truth, data, 1);
    o.lambda_rule = VR_LAMBDA_UPRE;
    vr_recovery_system *up = make(cam, nl, (const vr_spectrum *const *)lights, &o);
    score usc = run(up, (const double *const *)truth, data, 1);
    double best = INFINITY, best_l = 0;
    for (double e = -4; e <= 10.01; e += 0.5) {
      o.lambda = pow(10.0, e);
      vr_recovery_system *fx = make(cam, nl, (const vr_spectrum *const *)lights, &o);
      score f = run(fx, (const double *const *)truth, data, 1);
      if (f.rmse < best) best = f.rmse, best_l = o.lambda;
      vr_recovery_system_destroy(fx);
    }
    char label[64];
    snprintf(label, sizeof label, "%zu lights, %s, %ld px", nl, cases[k].kind == IN8 ? "8-bit sRGB" : "16-bit lin",
             cases[k].npix);
    printf("%-26s %.4f [%4.1f%%]   %.4f [%4.1f%%]   %.4f [%4.1f%%]   %.4f [%4.1f%%]   %.4f (%.0e)\n",
           label, bd.rmse, 100 * bd.misfit_share, g.rmse,
           100 * g.misfit_share, dsc.rmse, 100 * dsc.misfit_share, usc.rmse, 100 * usc.misfit_share,
           best, best_l);
    vr_recovery_system_destroy(gcv);
    vr_recovery_system_destroy(dp);
    vr_recovery_system_destroy(up);
  }
  free(data);
  for (size_t p = 0; p < PATCHES; p++) free(truth[p]);
  for (int i = 0; i < MAXL; i++) vr_spectrum_destroy(lights[i]);
  vr_camera_destroy(cam);
  return 0;
}
