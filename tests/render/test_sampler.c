/* The samplers behind vr_rng (vr/rng.h, render/src/sampler.c):
 *   - independent is the renderer's hash as it was, bit for bit: the
 *     numbers are recomputed here from the definition (SplitMix64's
 *     finaliser over seed, stream, sample and depth, dimension);
 *   - the first two Sobol dimensions form a (0,2)-sequence in base 2: the
 *     first 2^m points are a (0,m,2)-net, exactly one point in every
 *     elementary interval [a/2^k, (a+1)/2^k) x [b/2^(m-k), (b+1)/2^(m-k))
 *     (Sobol 1967; Niederreiter, Random Number Generation and Quasi-Monte
 *     Carlo Methods, 1992, ch. 4), and so is any aligned block of 2^m;
 *   - the scrambled, padded points vr_rng gives for one pixel keep that
 *     property (Owen 1995: nested scrambling maps nets to nets) for every
 *     2D pair, while the independent sampler's do not;
 *   - stratified puts exactly one sample in each of its nx x ny cells;
 *   - for any one sample every number is uniform on [0, 1) and two pairs
 *     are independent: chi-square over 64 cells at the 0.1 % point;
 *   - rendered: an area light over a diffuse plane, direct light only,
 *     against the analytic irradiance of a parallel rectangle (Howell's
 *     catalogue of configuration factors, B-3): every sampler is unbiased
 *     and sobol's RMSE at equal spp is well below independent's. */
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
#include "vr/rng.h"

/* SplitMix64's finaliser (Steele, Lea & Flood, OOPSLA 2014), written out. */
static uint64_t splitmix(uint64_t z) {
  z += 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

static void test_independent_is_the_hash(void **state) {
  (void)state;
  const uint64_t seeds[] = {0, 1, 7, 18446744073709551615ull};
  for (int s = 0; s < 4; s++)
    for (uint32_t dim = 0; dim < 40; dim += 3) {
      vr_rng_key k = {vr_rng_seed_make(seeds[s], VR_SAMPLER_INDEPENDENT, 16), 12345u + dim,
                      dim * 7u, 1000u + dim};
      uint64_t h = splitmix(seeds[s]);
      h = splitmix(h ^ k.stream);
      h = splitmix(h ^ ((uint64_t)k.sample << 32 | k.depth));
      h = splitmix(h ^ dim);
      double want = (double)(h >> 11) * 0x1.0p-53;
      assert_true(vr_rng(&k, dim) == want);
    }
}

/* Whether the n = 2^m points (x[i], y[i]) hold exactly one point in every
 * elementary interval of area 2^-m; *bad the first k that fails. */
static bool is_net(const double *x, const double *y, int m, int *bad) {
  uint32_t n = 1u << m;
  uint8_t *hit = calloc(n, 1);
  bool ok = true;
  for (int k = 0; k <= m && ok; k++) {
    memset(hit, 0, n);
    for (uint32_t i = 0; i < n; i++) {
      uint32_t a = (uint32_t)(x[i] * (double)(1u << k)), b = (uint32_t)(y[i] * (double)(1u << (m - k)));
      uint32_t cell = a << (m - k) | b;
      if (hit[cell]++) {
        ok = false;
        if (bad) *bad = k;
        break;
      }
    }
  }
  free(hit);
  return ok;
}

static void test_sobol_first_two_dimensions_are_nets(void **state) {
  (void)state;
  enum { M = 14 };
  double *x = malloc(sizeof(double) << M), *y = malloc(sizeof(double) << M);
  for (int m = 0; m <= M; m++) {
    uint32_t n = 1u << m;
    /* The first block, and a later aligned block of the same size. */
    for (uint32_t start = 0; start <= 3 * n; start += 3 * n) {
      for (uint32_t i = 0; i < n; i++) {
        x[i] = vr_sobol_0(start + i) * 0x1.0p-32;
        y[i] = vr_sobol_1(start + i) * 0x1.0p-32;
      }
      int bad = -1;
      if (!is_net(x, y, m, &bad)) fail_msg("Sobol points %u..%u: not a (0,%d,2)-net (k = %d)", start, start + n - 1, m, bad);
      /* Owen-style scrambling with any seed keeps the net. */
      for (uint32_t t = 0, seed = 1; t < 5; t++, seed += 987654321u) {
        for (uint32_t i = 0; i < n; i++) {
          x[i] = vr_owen_scramble(vr_sobol_0(start + i), seed) * 0x1.0p-32;
          y[i] = vr_owen_scramble(vr_sobol_1(start + i), seed ^ 0x9e3779b9u) * 0x1.0p-32;
        }
        if (!is_net(x, y, m, &bad)) fail_msg("scrambled (seed %u), m = %d: not a net (k = %d)", seed, m, bad);
      }
    }
  }
  /* The check can fail: the first dimension against itself is no net. */
  for (uint32_t i = 0; i < 256; i++) x[i] = y[i] = vr_sobol_0(i) * 0x1.0p-32;
  assert_false(is_net(x, y, 8, NULL));
  free(x);
  free(y);
}

static void test_permute_is_a_bijection(void **state) {
  (void)state;
  const uint32_t sizes[] = {1, 2, 3, 7, 16, 100, 1000, 4096};
  uint8_t seen[4096];
  for (int s = 0; s < 8; s++)
    for (uint32_t seed = 0; seed < 50; seed++) {
      uint32_t n = sizes[s];
      memset(seen, 0, n);
      for (uint32_t i = 0; i < n; i++) {
        uint32_t j = vr_permute(i, n, seed * 2654435761u);
        assert_true(j < n);
        assert_int_equal(seen[j]++, 0);
      }
    }
}

/* The points one pixel's samples 0 .. 2^m - 1 (and the next block) give for
 * the pair (dx, dy) at a depth. */
static void pixel_points(vr_sampler_kind kind, uint32_t count, uint64_t seed, uint64_t pixel,
                         uint32_t depth, uint32_t dx, uint32_t dy, uint32_t first, uint32_t n,
                         double *x, double *y) {
  vr_rng_key k = {vr_rng_seed_make(seed, kind, count), pixel, 0, depth};
  for (uint32_t i = 0; i < n; i++) {
    k.sample = first + i;
    x[i] = vr_rng(&k, dx);
    y[i] = vr_rng(&k, dy);
  }
}

static void test_sobol_pixel_pairs_are_nets(void **state) {
  (void)state;
  const uint32_t pairs[][3] = {{VR_DIM_PIXEL_X, VR_DIM_PIXEL_Y, 0},
                               {VR_DIM_LENS_U, VR_DIM_LENS_V, 0},
                               {VR_DIM_DIR_U, VR_DIM_DIR_V, 3},
                               {VR_DIM_LIGHT_V, VR_DIM_LIGHT_W, 1000 * 64 + 1},
                               {VR_DIM_SKY_U, VR_DIM_SKY_V, 1002},
                               {VR_DIM_GATHER + 6, VR_DIM_GATHER + 7, 501}};
  double x[1024], y[1024];
  for (int m = 1; m <= 10; m++) {
    uint32_t n = 1u << m;
    for (int p = 0; p < 6; p++)
      for (uint64_t pixel = 0; pixel < 40; pixel += 13)
        for (uint32_t block = 0; block < 2; block++) {
          pixel_points(VR_SAMPLER_SOBOL, n, 1 + pixel * 31, pixel, pairs[p][2], pairs[p][0],
                       pairs[p][1], block * n, n, x, y);
          int bad = -1;
          if (!is_net(x, y, m, &bad))
            fail_msg("sobol, dims %u,%u, pixel %llu, %u samples (block %u): not a net (k = %d)",
                     pairs[p][0], pairs[p][1], (unsigned long long)pixel, n, block, bad);
        }
  }
  /* Independent numbers are no net (the check can fail). */
  pixel_points(VR_SAMPLER_INDEPENDENT, 256, 1, 5, 0, VR_DIM_PIXEL_X, VR_DIM_PIXEL_Y, 0, 256, x, y);
  assert_false(is_net(x, y, 8, NULL));
  /* Two different pairs of one sample are not one net: padding. */
  double x2[256], y2[256];
  pixel_points(VR_SAMPLER_SOBOL, 256, 1, 5, 0, VR_DIM_PIXEL_X, VR_DIM_PIXEL_Y, 0, 256, x, y);
  pixel_points(VR_SAMPLER_SOBOL, 256, 1, 5, 0, VR_DIM_LENS_U, VR_DIM_LENS_V, 0, 256, x2, y2);
  assert_false(is_net(x, x2, 8, NULL) && is_net(y, y2, 8, NULL));
}

static void test_stratified_cells(void **state) {
  (void)state;
  const uint32_t counts[][3] = {{16, 4, 4}, {32, 4, 8}, {12, 3, 4}, {64, 8, 8}, {7, 1, 7}};
  double x[64], y[64];
  for (int c = 0; c < 5; c++) {
    uint32_t n = counts[c][0], nx = counts[c][1], ny = counts[c][2];
    assert_int_equal(vr_rng_seed_make(1, VR_SAMPLER_STRATIFIED, n).strata_x, nx);
    for (int pair = 0; pair < 2; pair++)
      for (uint64_t pixel = 0; pixel < 20; pixel++) {
        uint32_t dx = pair ? VR_DIM_LENS_U : VR_DIM_PIXEL_X, dy = pair ? VR_DIM_LENS_V : VR_DIM_PIXEL_Y;
        pixel_points(VR_SAMPLER_STRATIFIED, n, 3, pixel, 0, dx, dy, n, n, x, y);
        uint8_t hit[64] = {0};
        for (uint32_t i = 0; i < n; i++) {
          assert_true(x[i] >= 0 && x[i] < 1 && y[i] >= 0 && y[i] < 1);
          hit[(uint32_t)(y[i] * ny) * nx + (uint32_t)(x[i] * nx)]++;
        }
        for (uint32_t j = 0; j < n; j++) assert_int_equal(hit[j], 1);
      }
  }
  /* Other dimensions are the independent sampler's. */
  vr_rng_key a = {vr_rng_seed_make(9, VR_SAMPLER_STRATIFIED, 16), 4, 5, 6};
  vr_rng_key b = {vr_rng_seed_make(9, VR_SAMPLER_INDEPENDENT, 16), 4, 5, 6};
  assert_true(vr_rng(&a, VR_DIM_DIR_U) == vr_rng(&b, VR_DIM_DIR_U));
}

/* Chi-square of counts in 64 equal cells against the uniform law; the
 * 0.1 % point of chi-square with 63 degrees of freedom is 103.4
 * (Abramowitz & Stegun 26.4, Wilson-Hilferty). */
static double chi2_64(const uint32_t *count, uint32_t n) {
  double e = n / 64.0, c = 0;
  for (int i = 0; i < 64; i++) c += (count[i] - e) * (count[i] - e) / e;
  return c;
}

static void test_one_sample_is_uniform(void **state) {
  (void)state;
  for (int kind = 1; kind <= 2; kind++) {
    const uint32_t dims[][2] = {{VR_DIM_PIXEL_X, VR_DIM_PIXEL_Y}, {VR_DIM_DIR_U, VR_DIM_LIGHT_U},
                                {VR_DIM_WAVELENGTH, VR_DIM_LENS_V}, {VR_DIM_PIXEL_X, VR_DIM_LENS_U}};
    for (int d = 0; d < 4; d++) {
      uint32_t c1[64] = {0}, c2[64] = {0};
      const uint32_t N = 64000;
      for (uint32_t s = 0; s < N; s++) {
        /* Sample 5 of 16 of many pixels. */
        vr_rng_key k = {vr_rng_seed_make(11, (vr_sampler_kind)kind, 16), s, 5, 2};
        double u = vr_rng(&k, dims[d][0]), v = vr_rng(&k, dims[d][1]);
        c1[(int)(u * 64)]++;
        c2[(int)(u * 8) * 8 + (int)(v * 8)]++;
      }
      double a = chi2_64(c1, N), b = chi2_64(c2, N);
      if (a > 103.4 || b > 103.4)
        fail_msg("sampler %d, dims %u,%u: chi-square %.1f (1D), %.1f (2D) above 103.4", kind,
                 dims[d][0], dims[d][1], a, b);
    }
  }
}

/* One stream taking many more samples than the seed's count (a sensor
 * point's paths under a camera's spp): the same pair at two depths (a
 * path's first and second bounce) must be independent, or a path's second
 * direction is a function of its first and the estimate converges to a
 * seed-dependent value.  For independent uniforms E[u v] = 1/4 with
 * variance 1/9 - 1/16 = 7/144; the mean over N samples is held to 5
 * standard errors, sqrt(7/144/N).  Also a 64-cell chi-square of (u, v),
 * at the 0.1 % point (103.4). */
static void test_sobol_depths_independent_over_long_streams(void **state) {
  (void)state;
  const uint32_t N = 65536, counts[3] = {1, 16, 12};
  const uint32_t pairs[3][2] = {{VR_DIM_DIR_U, VR_DIM_DIR_U}, {VR_DIM_DIR_V, VR_DIM_LOBE},
                                {VR_DIM_LOBE, VR_DIM_LOBE}};
  for (int c = 0; c < 3; c++)
    for (int d = 0; d < 3; d++) {
      double sum = 0;
      uint32_t cells[64] = {0};
      for (uint32_t s = 0; s < N; s++) {
        vr_rng_key k0 = {vr_rng_seed_make(7, VR_SAMPLER_SOBOL, counts[c]), 42, s, 0};
        vr_rng_key k1 = k0;
        k1.depth = 1;
        double u = vr_rng(&k0, pairs[d][0]), v = vr_rng(&k1, pairs[d][1]);
        sum += u * v;
        cells[(int)(u * 8) * 8 + (int)(v * 8)]++;
      }
      double mean = sum / N, se = sqrt(7.0 / 144.0 / N), x2 = chi2_64(cells, N);
      if (fabs(mean - 0.25) > 5 * se || x2 > 103.4)
        fail_msg("count %u, dims %u@0 and %u@1 over %u samples: E[uv] %.5f (1/4 +- %.5f), "
                 "chi-square %.1f", counts[c], pairs[d][0], pairs[d][1], N, mean, 5 * se, x2);
    }
}

/* The block shuffle keeps distinct samples on distinct Sobol points: a
 * stream of 2^22 samples at spp 1024 (blocks of 2^10 points, so 2^22 of
 * them fit the 32-bit index) gives 2^22 distinct 2D points, as the
 * unshuffled sequence does (a (0,2)-sequence has no repeated point). */
static int cmp_u64(const void *a, const void *b) {
  uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
  return x < y ? -1 : x > y;
}

static void test_sobol_long_streams_distinct(void **state) {
  (void)state;
  const uint32_t N = 1u << 22;
  uint64_t *v = malloc(N * sizeof *v);
  assert_non_null(v);
  for (uint32_t s = 0; s < N; s++) {
    vr_rng_key k = {vr_rng_seed_make(3, VR_SAMPLER_SOBOL, 1024), 7, s, 2};
    uint64_t a = (uint64_t)(vr_rng(&k, VR_DIM_DIR_U) * 4294967296.0);
    uint64_t b = (uint64_t)(vr_rng(&k, VR_DIM_DIR_V) * 4294967296.0);
    v[s] = a << 32 | b;
  }
  qsort(v, N, sizeof *v, cmp_u64);
  uint32_t dup = 0;
  for (uint32_t s = 1; s < N; s++) dup += v[s] == v[s - 1];
  free(v);
  assert_int_equal(dup, 0);
}

/* ---- rendered: an area light over a diffuse plane, direct light only ---- */

/* Configuration factor from a differential area, facing +z, to a parallel
 * rectangle h above it with corners (0,0) and (a,b) relative to the point
 * (Howell, A Catalog of Radiation Heat Transfer Configuration Factors,
 * B-3); odd in a and in b, so rectangles elsewhere are sums of four. */
static double howell_b3(double a, double b, double h) {
  double A = a / h, B = b / h, sa = sqrt(1 + A * A), sb = sqrt(1 + B * B);
  return (A / sa * atan(B / sa) + B / sb * atan(A / sb)) / (2 * M_PI);
}

static double rect_factor(double px, double py, double x1, double x2, double y1, double y2,
                          double h) {
  return howell_b3(x2 - px, y2 - py, h) - howell_b3(x1 - px, y2 - py, h) -
         howell_b3(x2 - px, y1 - py, h) + howell_b3(x1 - px, y1 - py, h);
}

enum { W = 48 };
static const double RHO = 0.5, LV = 1000.0;

/* The pixel's luminance, rho Lv F averaged over its footprint on the plane
 * by 8 x 8 Gauss-Legendre points.  The camera at (0,0,3) looks down with
 * u = +x, v = +y and a 60 degree field: pixel (px, py) sees the plane at
 * x = 3 tan30 (2 px / W - 1), y = 3 tan30 (1 - 2 py / W). */
static void reference(double *ref) {
  static const double g[8] = {-0.9602898564975363, -0.7966664774136267, -0.5255324099163290,
                              -0.1834346424956498, 0.1834346424956498,  0.5255324099163290,
                              0.7966664774136267,  0.9602898564975363};
  static const double gw[8] = {0.1012285362903763, 0.2223810344533745, 0.3137066458778873,
                               0.3626837833783620, 0.3626837833783620, 0.3137066458778873,
                               0.2223810344533745, 0.1012285362903763};
  double t = 3 * tan(M_PI / 6);
  for (int j = 0; j < W; j++)
    for (int i = 0; i < W; i++) {
      double sum = 0;
      for (int a = 0; a < 8; a++)
        for (int b = 0; b < 8; b++) {
          double px = i + 0.5 + 0.5 * g[a], py = j + 0.5 + 0.5 * g[b];
          double x = t * (2 * px / W - 1), y = t * (1 - 2 * py / W);
          /* The lamp: 1 x 1 m centred on (1.8, 0), 1 m up, facing down. */
          sum += gw[a] * gw[b] / 4 * rect_factor(x, y, 1.3, 2.3, -0.5, 0.5, 1.0);
        }
      ref[j * W + i] = RHO * LV * sum;
    }
}

/* Relative RMSE of the image's Y against ref, and its mean ratio. */
static double render_rmse(const char *sampler, const char *spectral, int spp, int seed,
                          const double *ref, double *mean_ratio) {
  char scn[1024];
  snprintf(scn, sizeof scn,
           "camera pinhole from=0,0,3 to=0,0,0 up=0,1,0 fov=60 resolution=%dx%d\n"
           "material grey lambert reflectance=%g\n"
           "material lamp black\n"
           "rect center=0,0,0 normal=0,0,1 size=4,4 material=grey\n"
           "rect center=1.8,0,1 normal=0,0,-1 size=1,1 material=lamp emission=%gcd/m2 "
           "emission_spectrum=E\n"
           "render integrator=path depth=1 spp=%d spectral=%s sampler=%s seed=%d\n",
           W, W, RHO, LV, spp, spectral, sampler, seed);
  vr_render_result *r = render_text_with(scn, 1, 2, false);
  double se = 0, sr = 0, sref = 0;
  for (int p = 0; p < W * W; p++) {
    double y = r->xyz[3 * p + 1];
    se += (y - ref[p]) * (y - ref[p]);
    sr += y;
    sref += ref[p];
  }
  vr_render_result_destroy(r);
  *mean_ratio = sr / sref;
  return sqrt(se / (W * W)) / (sref / (W * W));
}

static void test_sobol_lowers_the_noise(void **state) {
  (void)state;
  double *ref = malloc(W * W * sizeof *ref);
  reference(ref);
  const char *samplers[] = {"independent", "stratified", "sobol"};
  const char *modes[] = {"bins", "hero"};
  const int spps[] = {4, 16, 64};
  double rmse[2][3][3];
  printf("relative RMSE of Y against the analytic image (%dx%d, mean of 4 seeds)\n", W, W);
  printf("%-6s %-12s %10s %10s %10s\n", "mode", "sampler", "4 spp", "16 spp", "64 spp");
  for (int m = 0; m < 2; m++)
    for (int s = 0; s < 3; s++) {
      for (int k = 0; k < 3; k++) {
        double sum = 0, ratio_sum = 0;
        for (int seed = 1; seed <= 4; seed++) {
          double ratio;
          double e = render_rmse(samplers[s], modes[m], spps[k], seed, ref, &ratio);
          sum += e * e;
          ratio_sum += ratio;
        }
        rmse[m][s][k] = sqrt(sum / 4);
        /* Unbiased: the image's mean is the analytic mean, within its
         * noise (the relative RMSE of one pixel over sqrt(pixels)). */
        double tol = 4 * rmse[m][s][k] / sqrt(W * W * 4.0) + 1e-4;
        if (fabs(ratio_sum / 4 - 1) > tol)
          fail_msg("%s %s %d spp: mean %.5f of the analytic (tolerance %.5f)", modes[m],
                   samplers[s], spps[k], ratio_sum / 4, tol);
      }
      printf("%-6s %-12s %10.5f %10.5f %10.5f\n", modes[m], samplers[s], rmse[m][s][0],
             rmse[m][s][1], rmse[m][s][2]);
    }
  /* Direct light of a smooth area light: sobol's error falls faster than
   * 1/sqrt(spp) (measured: see docs/vr-render.md, "Samplers"); the light
   * sampling, not the pixel, makes this noise, so stratified (pixel and
   * lens only) gains little here (test_stratified_antialiases). */
  for (int m = 0; m < 2; m++) {
    assert_true(rmse[m][2][1] < rmse[m][0][1] / 3);
    assert_true(rmse[m][2][2] < rmse[m][0][2] / 5);
    assert_true(rmse[m][1][2] < 1.05 * rmse[m][0][2]);
  }
  free(ref);
}

/* An emitter seen directly: a 1 m square turned 20 degrees, 2 m in front of
 * the camera; a pixel's value is the share of its area the square covers
 * times the luminance, its reference by 128 x 128 midpoints.  The noise is
 * the pixel dimensions' alone: jittered strata (and Sobol nets) cover a
 * pixel far more evenly than independent points. */
static void test_stratified_antialiases(void **state) {
  (void)state;
  enum { N = 32, SUB = 128 };
  double *ref = malloc(N * N * sizeof *ref), t = 2 * tan(M_PI / 6);
  double c = cos(20 * M_PI / 180), s = sin(20 * M_PI / 180);
  for (int j = 0; j < N; j++)
    for (int i = 0; i < N; i++) {
      int in = 0;
      for (int a = 0; a < SUB; a++)
        for (int b = 0; b < SUB; b++) {
          double px = i + (a + 0.5) / SUB, py = j + (b + 0.5) / SUB;
          double x = t * (2 * px / N - 1), y = t * (1 - 2 * py / N);
          double xr = c * x + s * y, yr = -s * x + c * y; /* turned back by 20 degrees */
          in += fabs(xr) <= 0.5 && fabs(yr) <= 0.5;
        }
      ref[j * N + i] = 100.0 * in / (SUB * SUB);
    }
  const char *samplers[] = {"independent", "stratified", "sobol"};
  double rmse[3];
  for (int k = 0; k < 3; k++) {
    double se = 0, sum = 0, sref = 0;
    for (int seed = 1; seed <= 4; seed++) {
      char scn[512];
      snprintf(scn, sizeof scn,
               "camera pinhole from=0,0,2 to=0,0,0 up=0,1,0 fov=60 resolution=%dx%d\n"
               "material lamp black\n"
               "rect center=0,0,0 normal=0,0,1 size=1,1 rotate=0,0,1,20 material=lamp "
               "emission=100cd/m2 emission_spectrum=E\n"
               "render integrator=path depth=1 spp=16 spectral=bins sampler=%s seed=%d\n",
               N, N, samplers[k], seed);
      vr_render_result *r = render_text_with(scn, 1, 2, false);
      for (int p = 0; p < N * N; p++) {
        double y = r->xyz[3 * p + 1];
        se += (y - ref[p]) * (y - ref[p]);
        sum += y;
        sref += ref[p];
      }
      vr_render_result_destroy(r);
    }
    rmse[k] = sqrt(se / (4 * N * N));
    printf("emitter edge, 16 spp, %-11s: RMSE %.4f cd/m2, mean %.5f of the covered share\n",
           samplers[k], rmse[k], sum / sref);
    assert_true(fabs(sum / sref - 1) < 0.01);
  }
  assert_true(rmse[1] < 0.6 * rmse[0]);
  assert_true(rmse[2] < 0.6 * rmse[0]);
  free(ref);
}

/* render sampler=: the three names, independent by default; the renderer
 * keys its numbers with the scene's seed, the sampler and the pixel's spp
 * (--spp included) as the count its points spread over. */
static void test_sampler_option(void **state) {
  (void)state;
  const char *names[] = {"independent", "stratified", "sobol"};
  for (int i = 0; i < 3; i++) {
    char text[256];
    snprintf(text, sizeof text, "camera pinhole from=0,0,0 to=0,1,0\nrender sampler=%s spp=32\n", names[i]);
    vr_scene *s = parse_text(text, "room.scn");
    assert_int_equal(s->settings.sampler, i);
    vr_scene_destroy(s);
  }
  /* The default, as pbrt-v4's (its ZSobol): low discrepancy. */
  vr_scene *s = parse_text("camera pinhole from=0,0,0 to=0,1,0\n", "room.scn");
  assert_int_equal(s->settings.sampler, VR_SAMPLER_SOBOL);
  vr_scene_destroy(s);
  vr_error err = {0};
  const char *bad = "camera pinhole from=0,0,0 to=0,1,0\nrender spp=4 sampler=halton\n";
  assert_int_not_equal(vr_scene_parse(bad, strlen(bad), "room.scn", &s, &err), VR_OK);
  assert_non_null(strstr(err.message, "room.scn:2:14: \"sampler=halton\": expected independent, stratified, sobol"));
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_sampler_option),
      cmocka_unit_test(test_independent_is_the_hash),
      cmocka_unit_test(test_sobol_first_two_dimensions_are_nets),
      cmocka_unit_test(test_permute_is_a_bijection),
      cmocka_unit_test(test_sobol_pixel_pairs_are_nets),
      cmocka_unit_test(test_stratified_cells),
      cmocka_unit_test(test_one_sample_is_uniform),
      cmocka_unit_test(test_sobol_depths_independent_over_long_streams),
      cmocka_unit_test(test_sobol_long_streams_distinct),
      cmocka_unit_test(test_sobol_lowers_the_noise),
      cmocka_unit_test(test_stratified_antialiases),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
