/* Per-pixel recovery (vr/recover_pixel.h) and the noise-aware choice of
 * lambda (vr_recover_noisy, vr_recover_pixel_lambda).
 *
 * References for the numbers:
 *  - the per-pixel result must equal the minimiser of the same convex
 *    problem found by the independent general active-set solver of the
 *    region method (vr_recover_noisy with the same lambda and weights); the
 *    minimiser is unique (H positive definite), and it is also checked
 *    against its Karush-Kuhn-Tucker conditions directly;
 *  - spectra: the BabelColor ColorChecker averages (Pascale 2012,
 *    vr/colorchecker.h) through the CIE 1931 observer with sRGB primaries;
 *  - targets: per-pixel spectral RMSE <= 0.06 against the true reflectance
 *    with 4 lights and sigma = 0.002 per pixel, and a region's patch RMSE
 *    <= 0.02 (16-bit) with the noise given, are the acceptance criteria of
 *    the vr-rgb2spec texture issue; measured values in the comments;
 *  - the 99.9 % point of chi-squared with 12 degrees of freedom is 32.91
 *    (Abramowitz and Stegun, table 26.8). */
#include "vr_test.h"
#include "vr/colorchecker.h"
#include "vr/colour.h"
#include "vr/recover.h"
#include "vr/recover_pixel.h"

#define PATCHES VR_COLORCHECKER_PATCHES
#define N 31
#define M 12
#define SIGMA 0.002

typedef struct fixture {
  vr_camera *cam;
  vr_spectrum *light[4];
  double patch[PATCHES][N];
  vr_recovery_system *sys;
} fixture;

static uint64_t rng = 0x9e3779b97f4a7c15ULL;
static double gauss(void) {
  double u[2];
  for (int k = 0; k < 2; k++) {
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    u[k] = ((double)(rng >> 11) + 0.5) / 9007199254740992.0;
  }
  return sqrt(-2.0 * log(u[0])) * cos(2.0 * M_PI * u[1]);
}

static int setup(void **state) {
  fixture *f = calloc(1, sizeof *f);
  vr_error err = {0};
  static const char *const names[4] = {"D65", "A", "LED-B3", "F2"};
  f->cam = vr_camera_create_srgb(0, NULL, &err);
  if (!f->cam) return -1;
  for (int l = 0; l < 4; l++)
    if (!(f->light[l] = vr_illuminant(names[l], &err))) return -1;
  for (size_t p = 0; p < PATCHES; p++) {
    vr_spectrum *raw = vr_colorchecker_patch(p, &err);
    if (!raw) return -1;
    for (size_t j = 0; j < N; j++)
      f->patch[p][j] = vr_spectrum_eval(raw, vr_camera_grid(f->cam)[j], VR_INTERP_LINEAR);
    vr_spectrum_destroy(raw);
  }
  /* Exposures that put a white's largest channel at 0.95 under each light. */
  vr_recovery_system *s = vr_recovery_system_create(f->cam, 4, (const vr_spectrum *const *)f->light,
                                                    NULL, NULL, &err);
  if (!s) return -1;
  double ones[N], white[M], scale[4];
  for (size_t j = 0; j < N; j++) ones[j] = 1.0;
  vr_render_rgb(s, ones, white);
  for (int l = 0; l < 4; l++)
    scale[l] = 0.95 / fmax(white[3 * l], fmax(white[3 * l + 1], white[3 * l + 2]));
  vr_recovery_system_destroy(s);
  f->sys = vr_recovery_system_create(f->cam, 4, (const vr_spectrum *const *)f->light, scale, NULL,
                                     &err);
  if (!f->sys) return -1;
  *state = f;
  return 0;
}

static int teardown(void **state) {
  fixture *f = *state;
  for (int l = 0; l < 4; l++) vr_spectrum_destroy(f->light[l]);
  vr_recovery_system_destroy(f->sys);
  vr_camera_destroy(f->cam);
  free(f);
  return 0;
}

/* The lambda the tool would use: median over the patches of the pixel
 * risk's choice. */
static double pixel_lambda(const fixture *f, const double *sigma) {
  double lam[PATCHES];
  vr_error err = {0};
  for (size_t p = 0; p < PATCHES; p++) {
    double c[M];
    vr_render_rgb(f->sys, f->patch[p], c);
    assert_int_equal(vr_recover_pixel_lambda(f->sys, c, sigma, NULL, &lam[p], &err), VR_OK);
  }
  for (size_t i = 1; i < PATCHES; i++)
    for (size_t k = i; k > 0 && lam[k] < lam[k - 1]; k--) {
      double t = lam[k];
      lam[k] = lam[k - 1];
      lam[k - 1] = t;
    }
  return 0.5 * (lam[PATCHES / 2 - 1] + lam[PATCHES / 2]);
}

/* Every pixel equals the general solver's answer for the same problem, and
 * dark patches (which noise pushes below 0) go through the bounded
 * correction. */
static void pixel_equals_general_solver(fixture *f);

/* Both kernels: AVX2/FMA where the processor has it, and SSE2. */
static void test_pixel_equals_general_solver(void **state) {
  pixel_equals_general_solver(*state);
  setenv("VR_NO_AVX2", "1", 1);
  pixel_equals_general_solver(*state);
  unsetenv("VR_NO_AVX2");
}

static void pixel_equals_general_solver(fixture *f) {
  vr_error err = {0};
  double sigma[M];
  for (int i = 0; i < M; i++) sigma[i] = SIGMA;
  double lambda = pixel_lambda(f, sigma);
  vr_pixel_recovery *p = vr_pixel_recovery_create(f->sys, sigma, lambda, NULL, &err);
  assert_non_null(p);
  vr_pixel_workspace *w = vr_pixel_workspace_create(p, &err);
  assert_non_null(w);
  vr_recovery_options o;
  vr_recovery_options_default(&o);
  o.lambda = lambda;
  /* Same exposures as f->sys. */
  double ones[N], white[M], scale[4];
  for (size_t j = 0; j < N; j++) ones[j] = 1.0;
  vr_recovery_system *raw = vr_recovery_system_create(f->cam, 4, (const vr_spectrum *const *)f->light, NULL, NULL, &err);
  vr_render_rgb(raw, ones, white);
  vr_recovery_system_destroy(raw);
  for (int l = 0; l < 4; l++) scale[l] = 0.95 / fmax(white[3 * l], fmax(white[3 * l + 1], white[3 * l + 2]));
  vr_recovery_system *fixed = vr_recovery_system_create(f->cam, 4, (const vr_spectrum *const *)f->light, scale, &o, &err);
  assert_non_null(fixed);
  int bounded = 0;
  double worst = 0.0;
  for (size_t p0 = 0; p0 < PATCHES; p0++)
    for (int d = 0; d < 10; d++) {
      double c[M], r[N];
      float cf[M], rf[N], x2;
      vr_render_rgb(f->sys, f->patch[p0], c);
      for (int i = 0; i < M; i++) {
        c[i] += SIGMA * gauss();
        cf[i] = (float)c[i];
        c[i] = cf[i]; /* both solvers see the same numbers */
      }
      unsigned flags = vr_pixel_recover(w, cf, NULL, rf, NULL, &x2);
      vr_recover_info info;
      assert_int_equal(vr_recover_noisy(fixed, VR_RECOVER_REGULARISED, c, sigma, NULL, r, &info, &err), VR_OK);
      if (flags & VR_PIXEL_BOUNDED) bounded++;
      assert_false(flags & VR_PIXEL_FALLBACK);
      for (size_t j = 0; j < N; j++) {
        assert_true(rf[j] >= 0.0f && rf[j] <= 1.0f);
        worst = fmax(worst, fabs(rf[j] - r[j]));
      }
      /* The misfit agrees with the solver's chi2. */
      assert_near(x2, info.chi2, 1e-3 * fmax(1.0, info.chi2));
    }
  /* Measured: largest difference 2e-7 (float output), 31 of 240 pixels
   * through the bounded correction. */
  assert_true(worst < 1e-5);
  assert_true(bounded > 0);
  vr_recovery_system_destroy(fixed);
  vr_pixel_workspace_destroy(w);
  vr_pixel_recovery_destroy(p);
}

/* Pixels of the whole chart at sigma = 0.002: spectral RMSE against the
 * BabelColor spectra within the 0.06 target. */
static void test_pixel_rmse_target(void **state) {
  fixture *f = *state;
  vr_error err = {0};
  double sigma[M];
  for (int i = 0; i < M; i++) sigma[i] = SIGMA;
  vr_pixel_recovery *p = vr_pixel_recovery_create(f->sys, sigma, pixel_lambda(f, sigma), NULL, &err);
  assert_non_null(p);
  vr_pixel_workspace *w = vr_pixel_workspace_create(p, &err);
  double sum = 0.0;
  int count = 0, misfit = 0;
  for (size_t p0 = 0; p0 < PATCHES; p0++)
    for (int d = 0; d < 50; d++) {
      double c[M];
      float cf[M], rf[N];
      vr_render_rgb(f->sys, f->patch[p0], c);
      for (int i = 0; i < M; i++) cf[i] = (float)(c[i] + SIGMA * gauss());
      unsigned flags = vr_pixel_recover(w, cf, NULL, rf, NULL, NULL);
      misfit += (flags & VR_PIXEL_MISFIT) != 0;
      double e2 = 0.0;
      for (size_t j = 0; j < N; j++) e2 += (rf[j] - f->patch[p0][j]) * (rf[j] - f->patch[p0][j]);
      sum += sqrt(e2 / N);
      count++;
    }
  double rmse = sum / count;
  print_message("per-pixel RMSE %.4f, %d of %d flagged misfit\n", rmse, misfit, count);
  assert_true(rmse <= 0.06);
  /* A correct noise model flags about 0.1 % of pixels. */
  assert_true(misfit <= count / 50);
  vr_pixel_workspace_destroy(w);
  vr_pixel_recovery_destroy(p);
}

/* Clipped channels: recovered from the others and flagged; with all but
 * one clipped there is nothing to go on. */
static void test_pixel_clipped(void **state) {
  fixture *f = *state;
  vr_error err = {0};
  double sigma[M];
  for (int i = 0; i < M; i++) sigma[i] = SIGMA;
  vr_pixel_recovery *p = vr_pixel_recovery_create(f->sys, sigma, pixel_lambda(f, sigma), NULL, &err);
  vr_pixel_workspace *w = vr_pixel_workspace_create(p, &err);
  double c[M];
  float cf[M], rf[N], ref[N];
  vr_render_rgb(f->sys, f->patch[18], c); /* white */
  for (int i = 0; i < M; i++) cf[i] = (float)c[i];
  vr_pixel_recover(w, cf, NULL, ref, NULL, NULL);
  unsigned char clip[M] = {0};
  clip[0] = VR_CLIP_HIGH; /* red under D65 saturated */
  cf[0] = 0.9f;           /* the stored value says nothing */
  unsigned flags = vr_pixel_recover(w, cf, clip, rf, NULL, NULL);
  assert_true(flags & VR_PIXEL_CLIPPED_HIGH);
  assert_false(flags & VR_PIXEL_NO_DATA);
  double e2 = 0.0;
  for (size_t j = 0; j < N; j++) e2 += (rf[j] - ref[j]) * (rf[j] - ref[j]);
  /* Eleven noise-free channels still pin the white down: measured 0.004. */
  assert_true(sqrt(e2 / N) < 0.02);
  unsigned char all[M];
  for (int i = 0; i < M; i++) all[i] = i == 5 ? VR_CLIP_NONE : VR_CLIP_LOW;
  flags = vr_pixel_recover(w, cf, all, rf, NULL, NULL);
  assert_true(flags & VR_PIXEL_NO_DATA);
  vr_pixel_workspace_destroy(w);
  vr_pixel_recovery_destroy(p);
}

/* Region means with the noise given: unbiased predictive risk keeps the
 * 4-light 16-bit patch RMSE within 0.02 with sigma = 0.002 pixels averaged
 * over 900-pixel regions; flags what the noise cannot explain. */
static void test_region_noise_aware(void **state) {
  fixture *f = *state;
  vr_error err = {0};
  double sum = 0.0;
  for (size_t p0 = 0; p0 < PATCHES; p0++) {
    double c[M], sig[M], r[N];
    vr_render_rgb(f->sys, f->patch[p0], c);
    for (int i = 0; i < M; i++) {
      sig[i] = vr_recover_mean_sigma(SIGMA, 900, 1.0 / 65535.0);
      c[i] = round((c[i] + sig[i] * gauss()) * 65535.0) / 65535.0;
    }
    vr_recover_info info;
    assert_int_equal(vr_recover_noisy(f->sys, VR_RECOVER_REGULARISED, c, sig, NULL, r, &info, &err), VR_OK);
    assert_false(info.flags & VR_RECOVER_FLAG_MISFIT);
    assert_near(info.chi2_limit, 32.91, 0.2); /* A&S table 26.8, 12 dof */
    double e2 = 0.0;
    for (size_t j = 0; j < N; j++) e2 += (r[j] - f->patch[p0][j]) * (r[j] - f->patch[p0][j]);
    sum += sqrt(e2 / N);
  }
  print_message("region RMSE %.4f\n", sum / PATCHES);
  assert_true(sum / PATCHES <= 0.02);
  /* Responses no reflectance can give (a channel far above white) are
   * flagged as a misfit. */
  double c[M], sig[M], r[N];
  vr_render_rgb(f->sys, f->patch[18], c);
  c[4] = 3.0;
  for (int i = 0; i < M; i++) sig[i] = 1e-4;
  vr_recover_info info;
  assert_int_equal(vr_recover_noisy(f->sys, VR_RECOVER_REGULARISED, c, sig, NULL, r, &info, &err), VR_OK);
  assert_true(info.flags & VR_RECOVER_FLAG_MISFIT);
  assert_true(info.chi2 > info.chi2_limit);
  /* A non-positive noise is refused, naming the channel. */
  sig[8] = 0.0;
  assert_int_equal(vr_recover_noisy(f->sys, VR_RECOVER_REGULARISED, c, sig, NULL, r, &info, &err), VR_E_ARG);
  assert_non_null(strstr(err.message, "channel B"));
}

/* The noise of a region's mean: scatter averages down as 1/sqrt(n)
 * (sigma/sqrt(n), the standard error of a mean); undithered rounding is a
 * uniform error over one step, standard deviation step/sqrt(12) (Widrow and
 * Kollar, "Quantization Noise", 2008, ch. 4), and does not average down. */
static void test_noise_of_means(void **state) {
  (void)state;
  assert_near(vr_recover_mean_sigma(0.002, 900, 1.0 / 65535), 0.002 / 30.0, 1e-12);
  assert_near(vr_recover_mean_sigma(0.0, 900, 0.01), 0.01 / sqrt(12.0), 1e-12);
  assert_near(vr_recover_pixel_sigma(0.002, 0.0), 0.002, 1e-15);
  assert_near(vr_recover_pixel_sigma(0.001, 0.01), sqrt(1e-6 + 1e-4 / 12.0), 1e-12);
  assert_near(vr_recover_mean_sigma(0.0, 100, 0.0), 1e-6, 0.0); /* the floor */
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_pixel_equals_general_solver),
      cmocka_unit_test(test_pixel_rmse_target),
      cmocka_unit_test(test_pixel_clipped),
      cmocka_unit_test(test_region_noise_aware),
      cmocka_unit_test(test_noise_of_means),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
