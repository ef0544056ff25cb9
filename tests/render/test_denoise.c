/* The display denoiser (render/src/film/denoise.c, vr/denoise.h) and the
 * features the camera pass records for it (integrators/features.c),
 * against images whose truth is known at every pixel.
 *
 * Synthetic images (vr_denoise alone): a truth, and two halves each the
 * truth plus independent normal noise of variance 2 s^2, so that their
 * mean has variance s^2 per channel, as a film of N samples; a raw render
 * of 8N samples has an RMSE of s / sqrt(8).
 *   - without noise (the halves equal) every pixel is left as it is: its
 *     variance is 0, so no other pixel is alike unless equal;
 *   - two regions of different albedo: the RMSE against the truth is at
 *     most s / sqrt(8) (the "8x the samples"), and the columns on
 *     either side of the edge keep their own region's value: a filter that
 *     mixed across would move them by a large share of the step;
 *   - a step in colour alone (a shadow edge: no feature differs) of 20 s
 *     is kept: the patches' colour distance sees it;
 *   - bad input: NaN names its pixel, an empty image is refused.
 * A render (vr_render_scene --denoise): a floor of two Lambertian halves,
 * reflectances 0.2 and 0.8, under the CIE uniform sky (CIE S 011/E:2003
 * type 5) of 1000 lx with no ground glow: each half's luminance is
 * rho E / pi exactly (an unoccluded plane sees the sky alone), so the
 * error of every pixel is known.
 *   - the features: albedo 0.2 and 0.8 exactly (a Lambertian sample's
 *     weight is its reflectance; flat spectra are their own XYZ ratio),
 *     normal (0, 0, 1), nearness 1 / (1 + t / 1 m) within 1e-3 of that
 *     of the pixel centre's ray (the pixel's samples spread around it);
 *   - the denoised image's RMSE against rho E / pi is at most the raw
 *     film's divided by sqrt(8), and the columns beside the edge stay on
 *     their side;
 *   - the raw film is the same as without --denoise in expectation: its
 *     mean over each half within 6 standard errors of rho E / pi;
 *   - a coloured paint has the same albedo at every pixel (taken at fixed
 *     wavelengths, not at each path's random ones). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "render_test_util.h"
#include "vr/denoise.h"

/* Normal deviates from a fixed-seed generator (splitmix64 and Box-Muller). */
static uint64_t rng_state = 0x5EEDull;
static double uniform01(void) {
  uint64_t z = (rng_state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return ((double)((z ^ (z >> 31)) >> 11) + 0.5) * 0x1.0p-53;
}
static double normal01(void) {
  return sqrt(-2 * log(uniform01())) * cos(2 * M_PI * uniform01());
}

typedef struct synth {
  int W, H;
  double *truth, *mean, *b, *feat, *fvar, *out;
} synth;

/* A W x H image of truth[x] (per column) with albedo feature alb[x], and
 * halves with noise of standard deviation sd * sqrt(2) each (relative to
 * the pixel's value when relative). */
static synth make_synth(int W, int H, double (*value)(int x), double (*albedo)(int x), double sd,
                        bool relative) {
  synth s = {.W = W, .H = H};
  size_t px = (size_t)W * (size_t)H;
  s.truth = malloc(px * 3 * sizeof *s.truth);
  s.mean = malloc(px * 3 * sizeof *s.mean);
  s.b = malloc(px * 3 * sizeof *s.b);
  s.feat = calloc(px * VR_DENOISE_FEATURES, sizeof *s.feat);
  s.fvar = calloc(px * VR_DENOISE_GROUPS, sizeof *s.fvar);
  s.out = malloc(px * 3 * sizeof *s.out);
  assert_true(s.truth && s.mean && s.b && s.feat && s.fvar && s.out);
  for (int y = 0; y < H; y++)
    for (int x = 0; x < W; x++) {
      size_t p = (size_t)y * (size_t)W + (size_t)x;
      for (int c = 0; c < 3; c++) {
        double t = value(x), e = relative ? sd * t : sd;
        double a = t + e * sqrt(2.0) * normal01(), bb = t + e * sqrt(2.0) * normal01();
        s.truth[3 * p + (size_t)c] = t;
        s.mean[3 * p + (size_t)c] = (a + bb) / 2;
        s.b[3 * p + (size_t)c] = bb;
        s.feat[p * VR_DENOISE_FEATURES + (size_t)c] = albedo(x);
      }
      s.feat[p * VR_DENOISE_FEATURES + 5] = 1.0; /* normal (0, 0, 1) */
      s.feat[p * VR_DENOISE_FEATURES + 6] = 0.5; /* nearness */
    }
  return s;
}

static void free_synth(synth *s) {
  free(s->truth);
  free(s->mean);
  free(s->b);
  free(s->feat);
  free(s->fvar);
  free(s->out);
}

/* The mean of channel Y over column x. */
static double column_mean(const double *img, int W, int H, int x) {
  double s = 0;
  for (int y = 0; y < H; y++) s += img[3 * ((size_t)y * (size_t)W + (size_t)x) + 1];
  return s / H;
}

enum { SW = 64, SH = 48 };
static double two_values(int x) { return x < SW / 2 ? 2.0 : 8.0; }
static double two_albedos(int x) { return x < SW / 2 ? 0.2 : 0.8; }
static double one_albedo(int x) {
  (void)x;
  return 0.5;
}
static double smooth_values(int x) { return 1.0 + 0.05 * x; }

static void test_noiseless_unchanged(void **state) {
  (void)state;
  synth s = make_synth(SW, SH, smooth_values, one_albedo, 0.0, false);
  vr_error err = {0};
  assert_int_equal(vr_denoise(SW, SH, s.mean, s.b, s.feat, s.fvar, NULL, s.out, &err), VR_OK);
  for (size_t i = 0; i < (size_t)SW * SH * 3; i++)
    if (fabs(s.out[i] - s.mean[i]) > 1e-12 * s.mean[i])
      fail_msg("value %zu: %.17g, a noiseless pixel must stay %.17g", i, s.out[i], s.mean[i]);
  free_synth(&s);
}

static void test_two_albedos(void **state) {
  (void)state;
  const double sd = 0.1; /* relative: 10 % a pixel, as 8 samples of a noisy render */
  synth s = make_synth(SW, SH, two_values, two_albedos, sd, true);
  vr_error err = {0};
  vr_denoise_params p = {.threads = 2};
  assert_int_equal(vr_denoise(SW, SH, s.mean, s.b, s.feat, s.fvar, &p, s.out, &err), VR_OK);
  size_t n = (size_t)SW * SH * 3;
  /* Relative errors, as the regions differ fourfold. */
  double raw = 0, den = 0;
  for (size_t i = 0; i < n; i++) {
    double t = s.truth[i];
    raw += (s.mean[i] - t) * (s.mean[i] - t) / (t * t);
    den += (s.out[i] - t) * (s.out[i] - t) / (t * t);
  }
  raw = sqrt(raw / (double)n);
  den = sqrt(den / (double)n);
  print_message("    two albedos: relative RMSE raw %.4f, denoised %.4f (8x samples: %.4f)\n", raw,
                den, sd / sqrt(8.0));
  if (!(den <= sd / sqrt(8.0)))
    fail_msg("denoised RMSE %.4f above that of 8x the samples, %.4f", den, sd / sqrt(8.0));
  /* The edge columns: a pixel there has alike patches along its column
   * only, so its column's mean keeps about the raw column's noise, a
   * standard error of sd t / sqrt(SH) (1.4 % here); held to 4 of them.
   * A filter mixing across the edge by a weight share f moves the dark
   * column by f x 300 % and the light one by f x 75 %. */
  double left = column_mean(s.out, SW, SH, SW / 2 - 1), right = column_mean(s.out, SW, SH, SW / 2);
  print_message("    edge columns %.4f and %.4f (truth 2 and 8)\n", left, right);
  assert_true(fabs(left - 2.0) < 4 * sd * 2.0 / sqrt(SH));
  assert_true(fabs(right - 8.0) < 4 * sd * 8.0 / sqrt(SH));
  free_synth(&s);
}

static double shadow_values(int x) { return x < SW / 2 ? 1.0 : 3.0; }

static void test_colour_edge_kept(void **state) {
  (void)state;
  /* A step of 2 against a noise of 0.1 a pixel (20 s), features equal. */
  synth s = make_synth(SW, SH, shadow_values, one_albedo, 0.1, false);
  vr_error err = {0};
  assert_int_equal(vr_denoise(SW, SH, s.mean, s.b, s.feat, s.fvar, NULL, s.out, &err), VR_OK);
  double left = column_mean(s.out, SW, SH, SW / 2 - 1), right = column_mean(s.out, SW, SH, SW / 2);
  print_message("    shadow edge columns %.4f and %.4f (truth 1 and 3)\n", left, right);
  /* A blur across would move them towards 2 by up to 1; held to 4 of
   * the raw column's standard errors (0.1 / sqrt(SH) = 0.014). */
  assert_true(fabs(left - 1.0) < 4 * 0.1 / sqrt(SH));
  assert_true(fabs(right - 3.0) < 4 * 0.1 / sqrt(SH));
  /* And the flat parts are smoothed: 8x the samples' RMSE there. */
  double e = 0;
  size_t k = 0;
  for (int y = 0; y < SH; y++)
    for (int x = 4; x < SW / 2 - 4; x++, k++) {
      double d = s.out[3 * ((size_t)y * SW + (size_t)x) + 1] - 1.0;
      e += d * d;
    }
  e = sqrt(e / (double)k);
  print_message("    flat part RMSE %.4f (8x samples %.4f)\n", e, 0.1 / sqrt(8.0));
  assert_true(e <= 0.1 / sqrt(8.0));
  free_synth(&s);
}

static void test_bad_input(void **state) {
  (void)state;
  synth s = make_synth(8, 8, smooth_values, one_albedo, 0.1, false);
  s.mean[3 * (2 * 8 + 5) + 1] = NAN;
  vr_error err = {0};
  assert_int_equal(vr_denoise(8, 8, s.mean, s.b, s.feat, s.fvar, NULL, s.out, &err), VR_E_RANGE);
  assert_non_null(strstr(err.message, "(5, 2)"));
  assert_int_equal(vr_denoise(0, 8, s.mean, s.b, s.feat, s.fvar, NULL, s.out, &err), VR_E_ARG);
  free_synth(&s);
}

/* The render: two halves of a floor under the uniform sky. */
static const char FLOOR2[] =
    "material dark lambert reflectance=0.2\n"
    "material light lambert reflectance=0.8\n"
    "rect center=-500,0,0 normal=0,0,1 size=1000,2000 material=dark\n"
    "rect center=500,0,0 normal=0,0,1 size=1000,2000 material=light\n"
    "sky cie type=5 illuminance=1000 ground=0\n"
    "camera pinhole from=0,0,1 to=0,0.5,0 up=0,0,1 fov=60 resolution=48x32 filter=box\n"
    "render integrator=path depth=3 spp=8 seed=11\n";

/* A denoised render of scene text on 2 threads; *sc keeps the scene. */
static vr_render_result *render_denoised(const char *text, const char *name, vr_scene **sc) {
  *sc = parse_text(text, name);
  vr_render_options o;
  vr_render_options_default(&o);
  o.threads = 2;
  o.denoise = true;
  return render_scene_opt(*sc, NULL, &o);
}

static void test_render_floor(void **state) {
  (void)state;
  vr_scene *sc;
  vr_render_result *r = render_denoised(FLOOR2, "denoise.scn", &sc);
  assert_non_null(r->features);
  assert_non_null(r->xyz_display);
  int W = r->width, H = r->height;
  double raw = 0, den = 0, sum[2] = {0, 0}, sum2[2] = {0, 0};
  size_t cnt[2] = {0, 0};
  for (int y = 0; y < H; y++)
    for (int x = 0; x < W; x++) {
      size_t p = (size_t)y * (size_t)W + (size_t)x;
      int side = x >= W / 2;
      double rho = side ? 0.8 : 0.2, want = rho * 1000.0 / M_PI;
      const float *f = &r->features[p * VR_RESULT_FEATURES];
      if (x == W / 2) {
        /* The column whose left border is the edge: a sample placed on
         * the border itself (the sampler's 0) lands on either half by
         * rounding.  Its albedo lies between the two; it is left out of
         * the errors. */
        for (int c = 0; c < 3; c++) assert_true(f[c] >= 0.2f - 1e-6f && f[c] <= 0.8f + 1e-6f);
        continue;
      }
      for (int c = 0; c < 3; c++)
        if (fabs(f[c] - rho) > 1e-6) fail_msg("pixel (%d, %d): albedo %g, expected %g", x, y, f[c], rho);
      if (fabs(f[3]) > 1e-9 || fabs(f[4]) > 1e-9 || fabs(f[5] - 1.0) > 1e-9)
        fail_msg("pixel (%d, %d): normal (%g, %g, %g), expected (0, 0, 1)", x, y, f[3], f[4], f[5]);
      /* The centre ray of the pixel (perspective.c: w + sx u + sy v, the
       * camera frame of from=0,0,1 to=0,0.5,0 up=0,0,1: u = (1, 0, 0),
       * w = (0, 1, -2) / sqrt 5, v = (0, 2, 1) / sqrt 5) to the floor. */
      double th = tan(M_PI / 6), sx = (2 * (x + 0.5) / W - 1) * th,
             sy = (1 - 2 * (y + 0.5) / H) * th * H / W;
      double d[3] = {sx, (1 + 2 * sy) / sqrt(5.0), (-2 + sy) / sqrt(5.0)};
      double t = 1.0 / -d[2] * sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      if (fabs(f[6] - 1.0 / (1.0 + t)) > 1e-3)
        fail_msg("pixel (%d, %d): nearness %g, expected 1 / (1 + %g m) = %g", x, y, f[6], t,
                 1.0 / (1.0 + t));
      double Y = r->xyz[3 * p + 1], D = r->xyz_display[3 * p + 1];
      raw += (Y - want) * (Y - want) / (want * want);
      den += (D - want) * (D - want) / (want * want);
      sum[side] += Y;
      sum2[side] += Y * Y;
      cnt[side]++;
    }
  raw = sqrt(raw / (double)(W * H - H));
  den = sqrt(den / (double)(W * H - H));
  print_message("    floor: relative RMSE raw %.4f, denoised %.4f (raw / sqrt 8 = %.4f); denoise "
                "%.3f s\n", raw, den, raw / sqrt(8.0), r->denoise_seconds);
  if (!(den <= raw / sqrt(8.0))) fail_msg("denoised RMSE %.4f above raw / sqrt(8) %.4f", den, raw / sqrt(8.0));
  for (int side = 0; side < 2; side++) {
    double n = (double)cnt[side], m = sum[side] / n;
    double se = sqrt((sum2[side] / n - m * m) / (n - 1));
    double want = (side ? 0.8 : 0.2) * 1000.0 / M_PI;
    print_message("    raw film, %s half: mean %.3f +- %.3f (rho E / pi = %.3f)\n",
                  side ? "light" : "dark", m, se, want);
    assert_true(fabs(m - want) <= 6 * se);
    assert_true(se < 0.01 * want);
  }
  /* The columns beside the edge (left of it, and right of the border
   * column) of the denoised image stay on their side, within 4
   * standard errors of their raw column's mean (the pixel's relative
   * standard deviation, from the raw film's scatter over its half, over
   * sqrt(H)): the light half's value mixed in by a share f moves the dark
   * column by f x 300 %. */
  for (int side = 0; side < 2; side++) {
    double want = (side ? 0.8 : 0.2) * 1000.0 / M_PI, n = (double)cnt[side];
    double m = sum[side] / n, sd = sqrt(sum2[side] / n - m * m) / m;
    double col = column_mean(r->xyz_display, W, H, side ? W / 2 + 1 : W / 2 - 1);
    print_message("    edge column %.3f (truth %.3f, bound %.3f)\n", col, want,
                  4 * sd * want / sqrt(H));
    assert_true(fabs(col - want) < 4 * sd * want / sqrt(H));
  }
  vr_render_result_destroy(r);
  vr_scene_destroy(sc);
}

/* SPPM denoised (integrator=progressive --denoise): two independent
 * chains of spp / 2 iterations, the second the denoiser's second half.
 * The white furnace of test_sppm.c (six walls of L_e = 100 cd/m2 and
 * albedo a = 0.5 about the camera, the view on the middle of one wall):
 * every pixel's exact luminance is L_e / (1 - a) = 200 cd/m2 (the Neumann
 * series in a closed diffuse enclosure), and the uniform photon density
 * leaves no smoothing bias (test_sppm.c holds 4 iterations unbiased).
 * Over K = 12 seeds of 2 chains of 4 iterations:
 *   - the image is the chains' mean: the seeds' mean of the image means is
 *     within T = 5 standard errors of 200 (Student's t, 11 degrees of
 *     freedom: 4e-4 two-sided); adding the chains instead of averaging
 *     them reads 300, the first chain's photon light alone 150;
 *   - the halves are independent estimates of the whole image: each
 *     pixel's variance (u - b)^2 (the EXR's variance.Y) has the
 *     expectation of its squared error about 200, so per seed the mean
 *     squared error less the mean variance, d, has expectation 0: its
 *     seeds' mean is held within T standard errors of 0, the standard
 *     error under 15 % of the mean variance.  A second half that left
 *     out the second chain's photon light gives d about -100^2; chains
 *     that shared their random numbers give a variance of 0;
 *   - the denoised image's RMSE about 200 is at most the raw film's over
 *     sqrt(8) (the "8 x the samples"), in every seed. */
static void test_sppm_chains(void **state) {
  (void)state;
  enum { K = 12 };
  const double T = 5.0, want = 100.0 / (1 - 0.5);
  seed_stats mean = {0}, d = {0}, var = {0};
  for (int k = 0; k < K; k++) {
    char scn[2048];
    snprintf(scn, sizeof scn,
             "material wall lambert reflectance=0.5\n" FURNACE_WALLS("wall")
             "camera pinhole from=0,0,0 to=0,1,0 fov=60 resolution=32x24 filter=box\n"
             "render integrator=progressive spp=8 photons=20000 depth=64 seed=%d\n",
             101 + k);
    vr_scene *sc;
    vr_render_result *r = render_denoised(scn, "sppm_denoise.scn", &sc);
    assert_non_null(r->xyz_display);
    assert_non_null(r->pixel_variance);
    size_t px = (size_t)r->width * (size_t)r->height;
    double sum = 0, se2 = 0, v = 0, den2 = 0;
    for (size_t p = 0; p < px; p++) {
      double Y = r->xyz[3 * p + 1], D = r->xyz_display[3 * p + 1];
      sum += Y;
      se2 += (Y - want) * (Y - want);
      den2 += (D - want) * (D - want);
      v += r->pixel_variance[p];
    }
    double n = (double)px, raw = sqrt(se2 / n) / want, den = sqrt(den2 / n) / want;
    seed_add(&mean, sum / n);
    seed_add(&d, se2 / n - v / n);
    seed_add(&var, v / n);
    if (!(den <= raw / sqrt(8.0)))
      print_error("seed %d: denoised RMSE %.4f above raw %.4f / sqrt(8)\n", 101 + k, den, raw);
    assert_true(den <= raw / sqrt(8.0));
    if (k == 0)
      print_message("    seed 101: relative RMSE raw %.4f, denoised %.4f\n", raw, den);
    vr_render_result_destroy(r);
    vr_scene_destroy(sc);
  }
  double m = seed_mean(&mean), sm = seed_stderr(&mean);
  double dm = seed_mean(&d), sd = seed_stderr(&d), vm = seed_mean(&var);
  print_message("    image mean %.3f +- %.3f (exact %.1f); squared error less variance %.2f +- %.2f "
                "(mean variance %.2f)\n", m, sm, want, dm, sd, vm);
  assert_true(fabs(m - want) <= T * sm);
  assert_true(sm < 0.01 * want);
  assert_true(fabs(dm) <= T * sd);
  assert_true(sd < 0.15 * vm);
}

/* A coloured floor (reflectance rising from 0.1 at 400 nm to 0.9 at 700
 * nm): its albedo is the same at every pixel, whatever wavelengths each
 * sample's path carried (the albedo is taken at fixed wavelengths), and
 * red, not grey. */
static void test_albedo_not_wavelength_noise(void **state) {
  (void)state;
  static const char scn[] =
      "material paint lambert reflectance=[400:0.1,700:0.9]\n"
      "rect center=0,0,0 normal=0,0,1 size=2000,2000 material=paint\n"
      "sky cie type=5 illuminance=1000 ground=0\n"
      "camera pinhole from=0,0,1 to=0,0.5,0 up=0,0,1 fov=60 resolution=16x12\n"
      "render integrator=path depth=2 spp=2 seed=3\n";
  vr_scene *sc = parse_text(scn, "paint.scn");
  vr_render_options o;
  vr_render_options_default(&o);
  o.denoise = true;
  vr_render_result *r = render_scene_opt(sc, NULL, &o);
  const float *f0 = r->features;
  for (size_t p = 1; p < (size_t)r->width * (size_t)r->height; p++)
    for (int c = 0; c < 3; c++)
      if (fabs(r->features[p * VR_RESULT_FEATURES + (size_t)c] - f0[c]) > 1e-6)
        fail_msg("pixel %zu: albedo channel %d %g, pixel 0 %g: the albedo must not carry the "
                 "wavelengths' noise", p, c, r->features[p * VR_RESULT_FEATURES + (size_t)c], f0[c]);
  print_message("    coloured floor: albedo (%.4f, %.4f, %.4f) at every pixel\n", f0[0], f0[1], f0[2]);
  assert_true(f0[0] > f0[2] + 0.2);
  vr_render_result_destroy(r);
  vr_scene_destroy(sc);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_noiseless_unchanged),
      cmocka_unit_test(test_two_albedos),
      cmocka_unit_test(test_colour_edge_kept),
      cmocka_unit_test(test_bad_input),
      cmocka_unit_test(test_render_floor),
      cmocka_unit_test(test_albedo_not_wavelength_noise),
      cmocka_unit_test(test_sppm_chains),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
