/* Adaptive sampling (render/src/integrators/adaptive.c) against scenes
 * whose answer is known at every pixel: a Lambertian floor under the CIE
 * uniform sky (below: 500 / pi cd/m2 everywhere), so each pixel's true
 * error is known.  (Not the white furnace: next-event estimation into its
 * corners has a near-infinite variance, and even fixed-spp images of it
 * read 0.8 % low at 1024 samples, 4.7 of their standard errors.)
 *
 *   - the image's mean stays within K_SE standard errors of 500 / pi
 *     (the standard error from the pixels' own variance layer; K_SE = 6:
 *     P(|z| > 6) = 2e-9 for a normal mean of 768 pixels);
 *   - the variance layer is honest: the pixels' squared true errors and
 *     their reported variances estimate the same sum; each sum over n
 *     pixels of a squared, roughly normal error has a relative standard
 *     deviation of sqrt(2 / n) (5.1 % at n = 768) and their ratio
 *     sqrt(4 / n) = 7.2 %, so the ratio is held to 1 +- 4 x 7.2 % = [0.71,
 *     1.29] (path lengths give heavier tails than normal: 4, not 6);
 *   - the target holds: the root-mean-square true relative error over the
 *     pixels is at most the target (a pixel stops with its estimate at or
 *     below it, after a round that halved its variance);
 *   - where there is no noise (a black emitter seen directly, under
 *     spectral=bins: no random number changes its pixels), pixels stop
 *     after the first round with a variance of exactly 0, while lit
 *     diffuse pixels take more samples;
 *   - a time limit shorter than the first round stops after it, with the
 *     reason;
 *   - the image and the sample counts are the same for any sub-domains,
 *     threads and image space (decisions come from the summed film);
 *   - the 95 % intervals the layer gives to image regions hold the truth
 *     in 90-98 % of cases over 20 seeds (below);
 *   - path sensors take rounds to the target too (below). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "render_test_util.h"

#define K_SE 6.0

/* A Lambertian floor of reflectance 0.5 under the CIE uniform sky (CIE
 * S 011/E:2003 type 5) of 1000 lx, with no ground glow and nothing else:
 * the floor's luminance is rho E_h / pi = 500 / pi = 159.155 cd/m2 at
 * every pixel, its noise that of the sky's sampling and the wavelengths'. */
static const char FLOOR[] =
    "material floor lambert reflectance=0.5\n"
    "rect center=0,0,0 normal=0,0,1 size=2000,2000 material=floor\n"
    "sky cie type=5 illuminance=1000 ground=0\n"
    "camera pinhole from=0,0,1 to=0,0.5,0 up=0,0,1 fov=60 resolution=32x24\n"
    "render integrator=path depth=3 spp=8 seed=7\n";
static const double FLOOR_Y = 500.0 / M_PI;

static vr_render_result *render_adaptive(const char *text, double target, double limit,
                                         int max_spp, int S, int P, bool image_space) {
  vr_scene *s = parse_text(text, "adaptive.scn");
  vr_render_options o;
  vr_render_options_default(&o);
  o.subdomains = S;
  o.threads = P;
  o.image_space = image_space;
  o.target_error = target;
  o.time_limit_s = limit;
  o.max_spp = max_spp;
  vr_render_result *r = render_scene_opt(s, NULL, &o);
  vr_scene_destroy(s);
  assert_non_null(r->pixel_samples);
  assert_non_null(r->pixel_variance);
  return r;
}

static void test_floor_unbiased_and_honest(void **state) {
  (void)state;
  const double want = FLOOR_Y, target = 0.005;
  vr_render_result *r = render_adaptive(FLOOR, target, 0, 4096, 1, 2, false);
  size_t n = (size_t)r->width * (size_t)r->height;
  double sum = 0, var_sum = 0, err2 = 0, rel2 = 0;
  for (size_t p = 0; p < n; p++) {
    double Y = r->xyz[3 * p + 1];
    sum += Y;
    var_sum += r->pixel_variance[p];
    err2 += (Y - want) * (Y - want);
    rel2 += (Y - want) * (Y - want) / (want * want);
  }
  double mean = sum / n, se = sqrt(var_sum) / n, ratio = err2 / var_sum, rms = sqrt(rel2 / n);
  print_message("    floor: mean Y %.3f cd/m2 +- %.3f (expected %.1f); spp %u-%u mean %.1f in %d "
                "rounds (%s); squared errors / reported variances %.3f; rms relative error "
                "%.4f (target %.3f), %.1f %% converged\n",
                mean, se, want, r->adaptive.spp_min, r->adaptive.spp_max, r->adaptive.spp_mean,
                r->adaptive.rounds, r->adaptive.stop, ratio, rms, target, 100 * r->adaptive.converged_share);
  if (!(fabs(mean - want) <= K_SE * se))
    fail_msg("floor mean %.3f, expected %.1f within %.0f standard errors (%.3f)", mean, want,
             K_SE, se);
  /* The error bar must be small, or the check above would pass anything. */
  assert_true(se < 0.01 * want);
  if (!(ratio >= 0.71 && ratio <= 1.29))
    fail_msg("the variance layer: squared true errors / reported variances = %.3f, expected 1 "
             "within [0.71, 1.29]", ratio);
  if (!(rms <= target)) fail_msg("rms relative error %.4f above the target %.3f", rms, target);
  /* The target was reached, not the cap, at nearly every pixel (a few
   * pixels' estimates, from nine pixels' halves, stay above it by chance
   * until the cap). */
  assert_true(r->adaptive.converged_share >= 0.9);
  assert_true(r->adaptive.rounds >= 2);
  vr_render_result_destroy(r);
}

/* Half the view a black emitter (exact under spectral=bins: nothing random
 * changes its pixels), half a white wall lit by the CIE uniform sky (noisy:
 * the sky's directions are sampled). */
static void test_noise_free_pixels_stop_first(void **state) {
  (void)state;
  const char *scn =
      "material black lambert reflectance=0\n"
      "material white lambert reflectance=0.8\n"
      "rect center=-0.5,2,0 normal=0,-1,0 size=1,2 material=black emission=50cd/m2\n"
      "rect center=0.5,2,0 normal=0,-1,0 size=1,2 material=white\n"
      "sky cie type=5 illuminance=10000 ground=0\n"
      "camera pinhole from=0,0,0 to=0,2,0 fov=40 resolution=24x16\n"
      "render integrator=path spp=8 spectral=bins depth=4 seed=3\n";
  vr_render_result *r = render_adaptive(scn, 0.02, 0, 1024, 1, 2, false);
  int W = r->width;
  /* The left quarter sees the emitter only, the right quarter the wall. */
  double left_max = 0, right_min = 1e30;
  for (int y = 2; y < r->height - 2; y++) {
    for (int x = 1; x < W / 4; x++) {
      size_t p = (size_t)y * W + x;
      /* The first round: two halves of the scene's spp = 8. */
      assert_int_equal(r->pixel_samples[p], 16);
      /* Identical samples: the halves' means differ by rounding alone. */
      assert_true(r->pixel_variance[p] <= 1e-20 * 50.0 * 50.0);
      if (fabs(r->xyz[3 * p + 1] - 50.0) > left_max) left_max = fabs(r->xyz[3 * p + 1] - 50.0);
    }
    for (int x = 3 * W / 4; x < W - 1; x++) {
      size_t p = (size_t)y * W + x;
      if (r->pixel_samples[p] < right_min) right_min = r->pixel_samples[p];
    }
  }
  print_message("    emitter pixels: %u samples, |Y - 50| <= %.2e; lit wall pixels: at least %.0f "
                "samples\n",
                r->adaptive.spp_first, left_max, right_min);
  /* Its luminance is what the emission line says, 50 cd/m2, to the fixed
   * bins' quadrature of D65 against the CMFs (0.45 % here, within 1 %). */
  assert_true(left_max < 0.01 * 50.0);
  assert_true(right_min > r->adaptive.spp_first);
  vr_render_result_destroy(r);
}

static void test_time_limit_stops_after_first_round(void **state) {
  (void)state;
  vr_render_result *r = render_adaptive(FLOOR, 0, 0.001, 0, 1, 2, false);
  size_t n = (size_t)r->width * (size_t)r->height;
  assert_int_equal(r->adaptive.rounds, 1);
  /* The first round: two halves of the scene's spp = 8. */
  assert_int_equal(r->adaptive.spp_first, 16);
  for (size_t p = 0; p < n; p++) assert_int_equal(r->pixel_samples[p], 16);
  assert_non_null(strstr(r->adaptive.stop, "time limit"));
  vr_render_result_destroy(r);
}

static void test_same_image_any_decomposition(void **state) {
  (void)state;
  vr_render_result *a = render_adaptive(FLOOR, 0.05, 0, 512, 1, 1, false);
  vr_render_result *b = render_adaptive(FLOOR, 0.05, 0, 512, 4, 2, false);
  vr_render_result *c = render_adaptive(FLOOR, 0.05, 0, 512, 1, 2, true);
  size_t n = (size_t)a->width * (size_t)a->height;
  const vr_render_result *o[2] = {b, c};
  for (int k = 0; k < 2; k++) {
    assert_int_equal(a->adaptive.rounds, o[k]->adaptive.rounds);
    for (size_t p = 0; p < n; p++) {
      assert_int_equal(a->pixel_samples[p], o[k]->pixel_samples[p]);
      assert_true(fabs(a->xyz[3 * p + 1] - o[k]->xyz[3 * p + 1]) <= 1e-6 * a->xyz[3 * p + 1]);
    }
  }
  vr_render_result_destroy(a);
  vr_render_result_destroy(b);
  vr_render_result_destroy(c);
}

/* Honest intervals over image regions (issue 33, item 4): on the floor
 * above, whose every pixel's true luminance is 500 / pi cd/m2, 20 seeds x
 * 48 regions of 4 x 4 pixels.  A region's mean has the variance
 * sum(var_p) / 16^2 from the layer, each var_p one degree of freedom, so
 * the ratio (mean - truth) / sqrt(variance) follows Student's t with 16
 * degrees of freedom (Satterthwaite, pixels of equal variance): the 95 %
 * interval is +- t(0.975, 16) = 2.120 (any t table) standard errors.  The
 * share of the 960 intervals that hold the truth must lie in [90 %, 98 %]
 * (the target; the binomial standard deviation at 95 % is 0.7 %),
 * for one round (a plain render of 16 samples a pixel: the layer's
 * estimate alone) and for adaptive rounds to 2 % (the stopping rule's
 * choices included). */
static double coverage(double target, double limit, int max_spp) {
  const int seeds = 20, R = 4;
  int inside = 0, total = 0;
  for (int seed = 1; seed <= seeds; seed++) {
    char text[1024];
    snprintf(text, sizeof text, "%.*sseed=%d\n", (int)(strstr(FLOOR, "seed=") - FLOOR), FLOOR,
             seed);
    vr_render_result *r = render_adaptive(text, target, limit, max_spp, 1, 2, false);
    int W = r->width, H = r->height;
    for (int y0 = 0; y0 + R <= H; y0 += R)
      for (int x0 = 0; x0 + R <= W; x0 += R) {
        double m = 0, v = 0;
        for (int y = y0; y < y0 + R; y++)
          for (int x = x0; x < x0 + R; x++) {
            m += r->xyz[3 * ((size_t)y * W + x) + 1] / (R * R);
            v += r->pixel_variance[(size_t)y * W + x] / (R * R * R * R);
          }
        inside += fabs(m - FLOOR_Y) <= 2.120 * sqrt(v);
        total++;
      }
    vr_render_result_destroy(r);
  }
  return (double)inside / total;
}

static void test_region_intervals_cover(void **state) {
  (void)state;
  double one = coverage(0, 0.001, 0), adaptive = coverage(0.02, 0, 1024);
  print_message("    95 %% intervals of 4 x 4 regions holding the truth over 20 seeds: %.1f %% "
                "(one round), %.1f %% (adaptive to 2 %%)\n",
                100 * one, 100 * adaptive);
  assert_true(one >= 0.90 && one <= 0.98);
  assert_true(adaptive >= 0.90 && adaptive <= 0.98);
}

/* Adaptive path sensors over the same floor (CIE uniform sky of 1000 lx,
 * no ground glow): a point 0.5 m above it facing up reads the sky's
 * horizontal illuminance, 1000 lx; facing down it reads pi times the
 * floor's luminance, 500 lx (the 2 km floor misses 2.5e-7 of the
 * hemisphere).  Each reading must lie within K_SE of its stated standard
 * errors (16 batches: Student's t with 15 degrees of freedom, P(|t| > 6) =
 * 2.4e-5), its relative standard error must be at most the target, and it
 * must have taken more paths than sensor_samples (rounds ran) but no more
 * than 64 times as many. */
static void test_path_sensors_adapt(void **state) {
  (void)state;
  const char *scn =
      "material floor lambert reflectance=0.5\n"
      "rect center=0,0,0 normal=0,0,1 size=2000,2000 material=floor\n"
      "sky cie type=5 illuminance=1000 ground=0\n"
      "sensor up point position=0,0,0.5 normal=0,0,1\n"
      "sensor down point position=0,0,0.5 normal=0,0,-1\n"
      "render integrator=path depth=3 seed=9 sensor_samples=256\n";
  vr_scene *s = parse_text(scn, "sensors.scn");
  vr_render_options o;
  vr_render_options_default(&o);
  o.threads = 2;
  o.no_camera = true;
  o.target_error = 0.008;
  vr_render_result *r = render_scene_opt(s, NULL, &o);
  vr_scene_destroy(s);
  const double want[2] = {1000.0, 500.0};
  for (int k = 0; k < 2; k++) {
    const vr_sensor_reading *x = &r->readings[k];
    print_message("    %s: %.3f +- %.3f lx (expected %.0f), %llu paths\n", x->sensor,
                  x->illuminance_lx, x->stderr_lx, want[k], (unsigned long long)x->paths);
    if (!(fabs(x->illuminance_lx - want[k]) <= K_SE * x->stderr_lx))
      fail_msg("%s: %.3f lx, expected %.0f within %.0f standard errors (%.3f)", x->sensor,
               x->illuminance_lx, want[k], K_SE, x->stderr_lx);
    assert_true(x->stderr_lx <= 0.008 * x->illuminance_lx);
    assert_true(x->paths > 256 && x->paths < 64 * 256); /* rounds ran; the target, not the cap, stopped them */
  }
  vr_render_result_destroy(r);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_floor_unbiased_and_honest),
      cmocka_unit_test(test_noise_free_pixels_stop_first),
      cmocka_unit_test(test_time_limit_stops_after_first_round),
      cmocka_unit_test(test_same_image_any_decomposition),
      cmocka_unit_test(test_region_intervals_cover),
      cmocka_unit_test(test_path_sensors_adapt),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
