/* Numerical edge cases of the spectral recovery that must stay stable:
 * nearly identical and identical lights (an ill-conditioned or singular
 * Matrix R), narrow-band LEDs, a black patch, clipped channels, responses no
 * reflectance can give, and non-finite input.
 *
 * Spectra: the BabelColor ColorChecker averages (vr/colorchecker.h) on the
 * default camera grid, camera the CIE 1931 observer with sRGB primaries.
 * 8-bit input is the rendered linear response clipped to [0, 1], sRGB-encoded
 * (IEC 61966-2-1), rounded to a code and decoded back; codes 0 and 255 are
 * marked clipped.  Exposures put each light's brightest white channel at 1. */
#include "vr_test.h"
#include "vr/colorchecker.h"
#include "vr/colour.h"
#include "vr/recover.h"

#define PATCHES VR_COLORCHECKER_PATCHES
#define N 31

static vr_spectrum *patch_on_grid(const vr_camera *cam, size_t p) {
  vr_error err = {0};
  vr_spectrum *raw = vr_colorchecker_patch(p, &err);
  vr_spectrum *s = vr_spectrum_resample(raw, N, vr_camera_grid(cam), VR_INTERP_LINEAR, &err);
  vr_spectrum_destroy(raw);
  assert_non_null(s);
  return s;
}

/* A system whose exposures put each light's brightest white channel at 1. */
static vr_recovery_system *exposed(const vr_camera *cam, size_t nl, const vr_spectrum *const *L,
                                   const vr_recovery_options *opt) {
  vr_error err = {0};
  vr_recovery_system *s = vr_recovery_system_create(cam, nl, L, NULL, opt, &err);
  if (!s) fail_msg("%s", err.message);
  double ones[N], w[12], scale[4];
  for (size_t j = 0; j < N; j++) ones[j] = 1.0;
  vr_render_rgb(s, ones, w);
  for (size_t l = 0; l < nl; l++) scale[l] = 1.0 / fmax(w[3 * l], fmax(w[3 * l + 1], w[3 * l + 2]));
  vr_recovery_system_destroy(s);
  s = vr_recovery_system_create(cam, nl, L, scale, opt, &err);
  if (!s) fail_msg("%s", err.message);
  return s;
}

static void quantise8(size_t m, double *c, unsigned char *clip) {
  for (size_t i = 0; i < m; i++) {
    long code = lround(vr_srgb_encode(fmin(fmax(c[i], 0.0), 1.0)) * 255.0);
    c[i] = vr_srgb_decode((double)code / 255.0);
    clip[i] = code == 0 ? VR_CLIP_LOW : code == 255 ? VR_CLIP_HIGH : VR_CLIP_NONE;
  }
}

static double rmse(const double *a, const double *b) {
  double e = 0.0;
  for (size_t j = 0; j < N; j++) e += (a[j] - b[j]) * (a[j] - b[j]);
  return sqrt(e / N);
}

/* Mean spectral RMSE over the patches for 8-bit input; every result finite
 * and (bounded, regularised) within [0, 1]. */
static double mean_rmse8(const vr_camera *cam, const vr_recovery_system *s, vr_recover_method m,
                         unsigned *flags) {
  vr_error err = {0};
  size_t rows = vr_recovery_system_rows(s);
  double sum = 0.0;
  *flags = 0;
  for (size_t p = 0; p < PATCHES; p++) {
    vr_spectrum *truth = patch_on_grid(cam, p);
    double c[12], r[N];
    unsigned char clip[12];
    vr_recover_info info;
    vr_render_rgb(s, truth->value, c);
    quantise8(rows, c, clip);
    assert_int_equal(vr_recover(s, m, c, clip, r, &info, &err), VR_OK);
    for (size_t j = 0; j < N; j++) {
      assert_true(isfinite(r[j]));
      if (m != VR_RECOVER_MATRIX_R) assert_true(r[j] >= 0.0 && r[j] <= 1.0);
    }
    *flags |= info.flags;
    sum += rmse(r, truth->value);
    vr_spectrum_destroy(truth);
  }
  return sum / PATCHES;
}

static void identical_lights(void **state) {
  (void)state;
  vr_error err = {0};
  vr_camera *cam = vr_camera_create_srgb(0, NULL, &err);
  /* D65 and D65 x 1.0001: the white normalisation makes the two blocks of A
   * equal, so A has rank 3 of 6.  The condition number is reported as huge
   * (or infinite), the pseudo-inverse drops the null directions and says
   * so, and every method still returns the one-light answer. */
  vr_spectrum *d65 = vr_illuminant("D65", &err), *brighter = vr_spectrum_copy(d65, &err);
  vr_spectrum_scale(brighter, 1.0001);
  const vr_spectrum *L[2] = {d65, brighter}, *one[1] = {d65};
  vr_recovery_system *s = vr_recovery_system_create(cam, 2, L, NULL, NULL, &err);
  vr_recovery_system *s1 = vr_recovery_system_create(cam, 1, one, NULL, NULL, &err);
  assert_non_null(s);
  assert_non_null(s1);
  print_message("identical lights: condition %.3g, rank %zu\n", vr_recovery_system_condition(s),
                vr_recovery_system_rank(s));
  assert_true(vr_recovery_system_condition(s) > 1e12);
  assert_int_equal(vr_recovery_system_rank(s), 3);
  for (size_t p = 0; p < PATCHES; p += 3) {
    vr_spectrum *truth = patch_on_grid(cam, p);
    double c[6], c1[3], r[N], r1[N];
    vr_render_rgb(s, truth->value, c);
    vr_render_rgb(s1, truth->value, c1);
    for (int meth = 0; meth < 3; meth++) {
      vr_recover_info info;
      assert_int_equal(vr_recover(s, (vr_recover_method)meth, c, NULL, r, &info, &err), VR_OK);
      assert_int_equal(vr_recover(s1, (vr_recover_method)meth, c1, NULL, r1, NULL, &err), VR_OK);
      if (meth == VR_RECOVER_MATRIX_R) assert_true(info.flags & VR_RECOVER_FLAG_RANK_DEFICIENT);
      /* exact for Matrix R and bounded; the regularised fit trades a
       * little residual for smoothness (measured up to 1e-6) */
      assert_true(info.residual < (meth == VR_RECOVER_REGULARISED ? 1e-4 : 1e-9));
      for (size_t j = 0; j < N; j++) assert_near(r[j], r1[j], meth == 2 ? 1e-4 : 1e-9);
    }
    vr_spectrum_destroy(truth);
  }
  vr_recovery_system_destroy(s);
  vr_recovery_system_destroy(s1);
  vr_spectrum_destroy(d65);
  vr_spectrum_destroy(brighter);
  vr_camera_destroy(cam);
}

static void nearly_identical_lights_8bit(void **state) {
  (void)state;
  vr_error err = {0};
  vr_camera *cam = vr_camera_create_srgb(0, NULL, &err);
  /* D65 (the CIE table, 6504 K) and the daylight of 6450 K: A has full rank
   * but its smallest singular value is 5e-5 (condition 1.3e4).  8-bit
   * quantisation noise along that direction is amplified by Matrix R into
   * spectra far outside [0, 1] (measured mean RMSE 3.7), pushes the data
   * out of gamut for the bounded method (which returns bang-bang spectra,
   * 0.42), while the regularised method stays at the one-light level
   * (measured 0.0601 against 0.0602 for D65 alone). */
  vr_spectrum *d65 = vr_illuminant("D65", &err), *d6450 = vr_illuminant("D6450", &err);
  const vr_spectrum *L[2] = {d65, d6450}, *one[1] = {d65};
  vr_recovery_options opt;
  vr_recovery_options_default(&opt);
  opt.noise = VR_NOISE_SRGB8;
  vr_recovery_system *s = exposed(cam, 2, L, &opt), *s1 = exposed(cam, 1, one, &opt);
  double cond = vr_recovery_system_condition(s);
  assert_true(cond > 1e3 && isfinite(cond));
  assert_int_equal(vr_recovery_system_rank(s), 6);
  unsigned fl_r, fl_b, fl_g, fl_1;
  double mr = mean_rmse8(cam, s, VR_RECOVER_MATRIX_R, &fl_r);
  double bd = mean_rmse8(cam, s, VR_RECOVER_BOUNDED, &fl_b);
  double rg = mean_rmse8(cam, s, VR_RECOVER_REGULARISED, &fl_g);
  double single = mean_rmse8(cam, s1, VR_RECOVER_REGULARISED, &fl_1);
  print_message("D65 + D6450, 8-bit: condition %.3g; mean RMSE Matrix R %.3f, bounded %.3f, "
                "regularised %.4f; D65 alone %.4f\n",
                cond, mr, bd, rg, single);
  assert_true(rg <= single + 0.02);
  assert_true(mr > 10.0 * rg); /* why the regularised method exists */
  assert_true(fl_b & VR_RECOVER_FLAG_OUT_OF_GAMUT);
  assert_false((fl_b | fl_g) & VR_RECOVER_FLAG_MAX_ITER);
  vr_recovery_system_destroy(s);
  vr_recovery_system_destroy(s1);
  vr_spectrum_destroy(d65);
  vr_spectrum_destroy(d6450);
  vr_camera_destroy(cam);
}

/* A Gaussian LED, FWHM fwhm nm, on 300-830 nm at 1 nm. */
static vr_spectrum *led(double peak, double fwhm) {
  vr_error err = {0};
  double nm[531], v[531], sigma = fwhm / (2.0 * sqrt(2.0 * log(2.0)));
  for (int i = 0; i < 531; i++) {
    nm[i] = 300.0 + i;
    v[i] = exp(-0.5 * pow((nm[i] - peak) / sigma, 2.0));
  }
  vr_spectrum *s = vr_spectrum_create(531, nm, v, &err);
  assert_non_null(s);
  return s;
}

static void narrow_band_leds(void **state) {
  (void)state;
  vr_error err = {0};
  vr_camera *cam = vr_camera_create_srgb(0, NULL, &err);
  /* Three LEDs, 20 nm FWHM at 450, 530 and 630 nm: each sees the
   * reflectance in a narrow band only, A's rows are nearly zero elsewhere
   * and nearly dependent within a light (condition 2.4e6).  Exact data:
   * Matrix R reproduces the responses, the bounded method stays in [0, 1]
   * and reproduces them too (measured mean RMSE: Matrix R 0.24, bounded
   * 0.024, regularised 0.033); 8-bit data (many channels of a saturated LED
   * fall below zero and clip): everything stays finite and bounded
   * (bounded 0.052, regularised 0.089). */
  vr_spectrum *leds[3] = {led(450, 20), led(530, 20), led(630, 20)};
  const vr_spectrum *L[3] = {leds[0], leds[1], leds[2]};
  vr_recovery_options opt;
  vr_recovery_options_default(&opt);
  opt.noise = VR_NOISE_SRGB8;
  vr_recovery_system *s = exposed(cam, 3, L, NULL), *s8 = exposed(cam, 3, L, &opt);
  double cond = vr_recovery_system_condition(s);
  assert_true(cond > 1e4 && isfinite(cond));
  double sum[3] = {0, 0, 0};
  for (size_t p = 0; p < PATCHES; p++) {
    vr_spectrum *truth = patch_on_grid(cam, p);
    double c[9], c2[9], r[N];
    vr_render_rgb(s, truth->value, c);
    for (int meth = 0; meth < 3; meth++) {
      vr_recover_info info;
      assert_int_equal(vr_recover(s, (vr_recover_method)meth, c, NULL, r, &info, &err), VR_OK);
      vr_render_rgb(s, r, c2);
      if (meth != VR_RECOVER_REGULARISED)
        for (int i = 0; i < 9; i++) assert_near(c2[i], c[i], 1e-9);
      if (meth != VR_RECOVER_MATRIX_R)
        for (size_t j = 0; j < N; j++) assert_true(r[j] >= 0.0 && r[j] <= 1.0);
      assert_false(info.flags & (VR_RECOVER_FLAG_OUT_OF_GAMUT | VR_RECOVER_FLAG_MAX_ITER));
      sum[meth] += rmse(r, truth->value) / PATCHES;
    }
    vr_spectrum_destroy(truth);
  }
  unsigned fl_b, fl_g;
  double b8 = mean_rmse8(cam, s8, VR_RECOVER_BOUNDED, &fl_b);
  double g8 = mean_rmse8(cam, s8, VR_RECOVER_REGULARISED, &fl_g);
  print_message("LEDs 450/530/630: condition %.3g; exact data mean RMSE Matrix R %.3f, bounded "
                "%.4f, regularised %.4f; 8-bit bounded %.4f, regularised %.4f\n",
                cond, sum[0], sum[1], sum[2], b8, g8);
  assert_true(sum[1] < 0.05);
  assert_true(g8 < 0.2 && b8 < 0.2);
  assert_false((fl_b | fl_g) & VR_RECOVER_FLAG_MAX_ITER);
  vr_recovery_system_destroy(s);
  vr_recovery_system_destroy(s8);
  for (int i = 0; i < 3; i++) vr_spectrum_destroy(leds[i]);
  vr_camera_destroy(cam);
}

static void black_patch(void **state) {
  (void)state;
  vr_error err = {0};
  vr_camera *cam = vr_camera_create_srgb(0, NULL, &err);
  /* c = 0: the fundamental metamer is exactly 0; the only reflectance in
   * [0, 1] that is black under a broad light is 0, and under narrow LEDs
   * (which leave most of the spectrum nearly unseen) the smoothest one is
   * still 0. */
  vr_spectrum *d65 = vr_illuminant("D65", &err), *a = vr_illuminant("A", &err);
  vr_spectrum *leds[3] = {led(450, 20), led(530, 20), led(630, 20)};
  const vr_spectrum *broad[2] = {d65, a}, *narrow[3] = {leds[0], leds[1], leds[2]};
  vr_recovery_system *sys[2] = {exposed(cam, 2, broad, NULL), exposed(cam, 3, narrow, NULL)};
  for (int k = 0; k < 2; k++) {
    double c[9] = {0}, r[N];
    for (int meth = 0; meth < 3; meth++) {
      vr_recover_info info;
      for (size_t j = 0; j < N; j++) r[j] = 42.0;
      assert_int_equal(vr_recover(sys[k], (vr_recover_method)meth, c, NULL, r, &info, &err), VR_OK);
      for (size_t j = 0; j < N; j++) {
        if (meth == VR_RECOVER_MATRIX_R)
          assert_true(r[j] == 0.0);
        else
          assert_near(r[j], 0.0, 1e-12);
      }
      assert_false(info.flags & VR_RECOVER_FLAG_OUT_OF_GAMUT);
    }
  }
  for (int k = 0; k < 2; k++) vr_recovery_system_destroy(sys[k]);
  vr_spectrum_destroy(d65);
  vr_spectrum_destroy(a);
  for (int i = 0; i < 3; i++) vr_spectrum_destroy(leds[i]);
  vr_camera_destroy(cam);
}

static void clipped_channels(void **state) {
  (void)state;
  vr_error err = {0};
  vr_camera *cam = vr_camera_create_srgb(0, NULL, &err);
  /* Over-exposed: D65 and A at 1.6 x the exposure that puts the white at 1.
   * The light patches saturate (values >= 1 are recorded as 1 and marked
   * VR_CLIP_HIGH).  Those channels must leave the equations (flagged,
   * counted) and bound the answer from below: A_i r >= 1. */
  vr_spectrum *d65 = vr_illuminant("D65", &err), *a = vr_illuminant("A", &err);
  const vr_spectrum *L[2] = {d65, a};
  vr_recovery_system *base = exposed(cam, 2, L, NULL);
  double ones[N], w[6], scale[2];
  for (size_t j = 0; j < N; j++) ones[j] = 1.0;
  vr_render_rgb(base, ones, w);
  for (int l = 0; l < 2; l++) scale[l] = 1.6 / fmax(w[3 * l], fmax(w[3 * l + 1], w[3 * l + 2]));
  vr_recovery_system_destroy(base);
  vr_recovery_system *s = vr_recovery_system_create(cam, 2, L, scale, NULL, &err);
  assert_non_null(s);
  size_t patches_clipped = 0;
  double with_marks = 0.0, face_value = 0.0;
  for (size_t p = 0; p < PATCHES; p++) {
    vr_spectrum *truth = patch_on_grid(cam, p);
    double c[6], r[N], rc[N], cr[6];
    unsigned char clip[6];
    size_t k = 0;
    vr_render_rgb(s, truth->value, c);
    for (int i = 0; i < 6; i++) {
      clip[i] = c[i] >= 1.0 ? VR_CLIP_HIGH : VR_CLIP_NONE;
      if (clip[i]) {
        c[i] = 1.0;
        k++;
      }
    }
    if (k == 0) {
      vr_spectrum_destroy(truth);
      continue;
    }
    patches_clipped++;
    vr_recover_info info;
    assert_int_equal(vr_recover(s, VR_RECOVER_BOUNDED, c, clip, r, &info, &err), VR_OK);
    assert_true(info.flags & VR_RECOVER_FLAG_CLIPPED);
    assert_int_equal(info.clipped, k);
    assert_int_equal(info.used, 6 - k);
    assert_true(info.clip_violation <= 1e-9);
    assert_true(info.residual <= 1e-9);
    vr_render_rgb(s, r, cr);
    for (int i = 0; i < 6; i++) {
      if (clip[i]) assert_true(cr[i] >= 1.0 - 1e-9);
      else assert_near(cr[i], c[i], 1e-9);
    }
    for (size_t j = 0; j < N; j++) assert_true(r[j] >= 0.0 && r[j] <= 1.0);
    /* The same with the clipped values taken at face value: the answer
     * then claims responses of exactly 1 where the truth is brighter. */
    assert_int_equal(vr_recover(s, VR_RECOVER_BOUNDED, c, NULL, rc, NULL, &err), VR_OK);
    print_message("%-13s %zu clipped: RMSE with clip marks %.4f, taken at face value %.4f\n",
                  vr_colorchecker_name(p), k, rmse(r, truth->value), rmse(rc, truth->value));
    with_marks += rmse(r, truth->value);
    face_value += rmse(rc, truth->value);
    /* Regularised: inequalities as one-sided terms, so a small breach is
     * allowed; Matrix R ignores them and says when it breaks one. */
    assert_int_equal(vr_recover(s, VR_RECOVER_REGULARISED, c, clip, r, &info, &err), VR_OK);
    for (size_t j = 0; j < N; j++) assert_true(r[j] >= 0.0 && r[j] <= 1.0);
    assert_true(info.clip_violation < 0.05);
    assert_int_equal(vr_recover(s, VR_RECOVER_MATRIX_R, c, clip, r, &info, &err), VR_OK);
    assert_true(info.flags & VR_RECOVER_FLAG_CLIPPED);
    assert_true(info.residual < 1e-12);
    if (info.clip_violation > 1e-6) assert_true(info.flags & VR_RECOVER_FLAG_CLIP_VIOLATED);
    vr_spectrum_destroy(truth);
  }
  /* Measured: 11 patches clip; mean RMSE 0.070 with the marks, 0.46 when
   * the clipped values are believed. */
  assert_true(patches_clipped >= 4);
  assert_true(with_marks < 0.5 * face_value);
  /* Every channel clipped, at half a white's response: nothing but "at
   * least this bright" to go on.  The bounded method returns a reflectance
   * that is.  (Clip levels of 1 would be unreachable here: over-exposed or
   * not, illuminant A's white gives only 0.3 in blue.) */
  double c[6], r[N], cr[6];
  unsigned char clip[6] = {1, 1, 1, 1, 1, 1};
  vr_recover_info info;
  vr_render_rgb(s, ones, c);
  for (int i = 0; i < 6; i++) c[i] *= 0.5;
  for (int meth = 0; meth < 3; meth++) {
    assert_int_equal(vr_recover(s, (vr_recover_method)meth, c, clip, r, &info, &err), VR_OK);
    assert_true(info.flags & VR_RECOVER_FLAG_NO_DATA);
    assert_int_equal(info.used, 0);
    for (size_t j = 0; j < N; j++) assert_true(isfinite(r[j]));
  }
  assert_int_equal(vr_recover(s, VR_RECOVER_BOUNDED, c, clip, r, &info, &err), VR_OK);
  assert_false(info.flags & VR_RECOVER_FLAG_OUT_OF_GAMUT);
  vr_render_rgb(s, r, cr);
  for (int i = 0; i < 6; i++) assert_true(cr[i] >= c[i] - 1e-9);
  for (size_t j = 0; j < N; j++) assert_true(r[j] >= 0.0 && r[j] <= 1.0);
  vr_recovery_system_destroy(s);
  vr_spectrum_destroy(d65);
  vr_spectrum_destroy(a);
  vr_camera_destroy(cam);
}

static void out_of_gamut(void **state) {
  (void)state;
  vr_error err = {0};
  vr_camera *cam = vr_camera_create_srgb(0, NULL, &err);
  vr_spectrum *d65 = vr_illuminant("D65", &err), *f2 = vr_illuminant("F2", &err);
  const vr_spectrum *L[2] = {d65, f2};
  vr_recovery_system *s = vr_recovery_system_create(cam, 2, L, NULL, NULL, &err);
  assert_non_null(s);
  double ones[N], white[6], c[6], r[N], cr[6];
  for (size_t j = 0; j < N; j++) ones[j] = 1.0;
  vr_render_rgb(s, ones, white);
  /* 1.5 x a perfect white: brighter than any reflectance can be.  The
   * closest reachable responses are the white's, from r = 1. */
  for (int i = 0; i < 6; i++) c[i] = 1.5 * white[i];
  vr_recover_info info;
  assert_int_equal(vr_recover(s, VR_RECOVER_BOUNDED, c, NULL, r, &info, &err), VR_OK);
  assert_true(info.flags & VR_RECOVER_FLAG_OUT_OF_GAMUT);
  for (size_t j = 0; j < N; j++) assert_near(r[j], 1.0, 1e-9);
  assert_rel(info.residual_white, 0.5 * sqrt(white[0] * white[0] + white[1] * white[1] +
                                             white[2] * white[2] + white[3] * white[3] +
                                             white[4] * white[4] + white[5] * white[5]),
             1e-9);
  /* A spectral colour: the responses of a 10 nm band at 520 nm of height 3
   * (no reflectance reaches them).  Fallback flagged, in [0, 1], and no
   * worse in least squares than a simple admissible candidate, Matrix R's
   * answer clipped to [0, 1]. */
  double spike[N] = {0};
  spike[12] = 3.0;
  vr_render_rgb(s, spike, c);
  assert_int_equal(vr_recover(s, VR_RECOVER_BOUNDED, c, NULL, r, &info, &err), VR_OK);
  assert_true(info.flags & VR_RECOVER_FLAG_OUT_OF_GAMUT);
  for (size_t j = 0; j < N; j++) assert_true(r[j] >= 0.0 && r[j] <= 1.0);
  double rm[N];
  assert_int_equal(vr_recover(s, VR_RECOVER_MATRIX_R, c, NULL, rm, NULL, &err), VR_OK);
  for (size_t j = 0; j < N; j++) rm[j] = fmin(fmax(rm[j], 0.0), 1.0);
  vr_render_rgb(s, rm, cr);
  double res_clip = 0.0;
  for (int i = 0; i < 6; i++) res_clip += (cr[i] - c[i]) * (cr[i] - c[i]);
  print_message("spectral colour: bounded residual %.4f, clipped Matrix R %.4f\n", info.residual,
                sqrt(res_clip));
  assert_true(info.residual <= sqrt(res_clip) + 1e-12);
  assert_false(info.flags & VR_RECOVER_FLAG_MAX_ITER);
  vr_recovery_system_destroy(s);
  vr_spectrum_destroy(d65);
  vr_spectrum_destroy(f2);
  vr_camera_destroy(cam);
}

static void non_finite_input(void **state) {
  (void)state;
  vr_error err = {0};
  vr_camera *cam = vr_camera_create_srgb(0, NULL, &err);
  vr_spectrum *d65 = vr_illuminant("D65", &err);
  const vr_spectrum *L[1] = {d65};
  vr_recovery_system *s = vr_recovery_system_create(cam, 1, L, NULL, NULL, &err);
  double bad[3] = {NAN, -INFINITY, INFINITY};
  for (int k = 0; k < 3; k++)
    for (int meth = 0; meth < 3; meth++) {
      double c[3] = {0.2, 0.2, 0.2}, r[N];
      c[k] = bad[k];
      assert_int_equal(vr_recover(s, (vr_recover_method)meth, c, NULL, r, NULL, &err), VR_E_ARG);
      assert_contains(err.message, "not a finite number");
    }
  vr_recovery_system_destroy(s);
  vr_spectrum_destroy(d65);
  vr_camera_destroy(cam);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(identical_lights),
      cmocka_unit_test(nearly_identical_lights_8bit),
      cmocka_unit_test(narrow_band_leds),
      cmocka_unit_test(black_patch),
      cmocka_unit_test(clipped_channels),
      cmocka_unit_test(out_of_gamut),
      cmocka_unit_test(non_finite_input),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
