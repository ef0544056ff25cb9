/* Dispersion against answers from outside the renderer's code: a lossless
 * dispersive glass sphere (the N-SF11 Sellmeier index of the SCHOTT
 * catalogue, k = 0) inside a closed box whose black walls emit L_e: by
 * Kirchhoff's law the radiance is L_e everywhere (the furnace argument),
 * so a camera looking through the sphere reads L_e and a sensor E = π L_e;
 * and the scene analysis runs the dispersion pass for it and not for a
 * scene without refraction; with walls of albedo a the radiance is
 * L_e / (1 - a), which photon mapping must find through the sphere too
 * (caustic photons). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "vr/matdb.h"
#include "vr/render.h"
#include "vr/scene.h"
#include "vr/spectrum.h"
#include "render_test_util.h"
#include "extra_harness.h"

/* N-SF11 refractive index, SCHOTT Sellmeier coefficients (SCHOTT optical
 * glass catalogue 2017-01-20, as in matdb/data/nsf11.yml):
 * n² - 1 = Σ B_i λ² / (λ² - C_i), λ in µm. */
static double nsf11_n(double nm) {
  const double B[3] = {1.73759695, 0.313747346, 1.89878101};
  const double C[3] = {0.013188707, 0.0623068142, 155.23629};
  double l2 = (nm * 1e-3) * (nm * 1e-3), n2 = 1;
  for (int i = 0; i < 3; i++) n2 += B[i] * l2 / (l2 - C[i]);
  return sqrt(n2);
}

static int setup(void **state) {
  (void)state;
  if (harness_open("dispersion")) return -1;
  /* A lossless dispersive glass: N-SF11's index with k = 0. */
  double nm[61], n[61], k[61];
  for (int i = 0; i < 61; i++) {
    nm[i] = 300 + 10 * i;
    n[i] = nsf11_n(nm[i]);
    k[i] = 0;
  }
  vr_error err = {0};
  vr_material *m = vr_material_create("sf11-lossless", VR_KIND_DIELECTRIC, &err);
  vr_material_add_spectrum(m, "n", vr_spectrum_create(61, nm, n, NULL), &err);
  vr_material_add_spectrum(m, "k", vr_spectrum_create(61, nm, k, NULL), &err);
  return harness_save(m);
}

/* The six inward-facing 2 x 2 m walls of the furnace, of material M,
 * each emitting 100 cd/m². */
static const char *FURNACE_BLACK =
    "material em black\n"
    FURNACE_WALLS("em");

static void test_dispersive_furnace(void **state) {
  (void)state;
  /* The furnace without the sphere refracts nothing: no dispersion pass,
   * and sensors read E = π L_e (about 0.25 % stderr for the four). */
  char scn[2048];
  snprintf(scn, sizeof scn,
           "%s"
           "sensor s grid origin=-0.3,-0.3,0.75 u=0.6,0,0 v=0,0.6,0 n=2,2 normal=0,0,-1\n"
           "render integrator=path sensor_samples=32768\n",
           FURNACE_BLACK);
  vr_render_result *r = render_text(scn);
  const vr_pass_record *d = pass(r, "dispersion");
  print_message("    no refraction: dispersion pass %s (%s)\n", d->ran ? "ran" : "skipped",
                d->reason);
  assert_false(d->ran);
  expect_mean_lx(r, M_PI * 100.0, 0.01, "sensors in the empty furnace");
  done(r);

  /* With the sphere, the analysis runs the dispersion pass. */
  snprintf(scn, sizeof scn,
           "%s"
           "material glass db:sf11-lossless\n"
           "sphere center=0,0,0 radius=0.5 material=glass\n"
           "camera pinhole from=0,-0.95,0 to=0,0,0 fov=40 resolution=16x12\n"
           "sensor s grid origin=-0.3,-0.3,0.75 u=0.6,0,0 v=0,0.6,0 n=2,2 normal=0,0,-1\n"
           "render integrator=path depth=64 spp=256 sensor_samples=65536\n",
           FURNACE_BLACK);
  r = render_text(scn);
  d = pass(r, "dispersion");
  print_message("    dispersion pass: %s (%s)\n", d->ran ? "ran" : "skipped", d->reason);
  assert_true(d->ran);
  /* Every pixel sees the sphere (half-angle asin(0.5/0.95) = 31.8° > 20°). */
  double sum = 0, sq = 0;
  int n = r->width * r->height;
  for (int y = 0; y < r->height; y++)
    for (int x = 0; x < r->width; x++) {
      sum += Y(r, x, y);
      sq += Y(r, x, y) * Y(r, x, y);
    }
  double mean = sum / n, se = sqrt((sq / n - mean * mean) / (n - 1));
  print_message("    through the sphere: mean Y %.4f cd/m2 (stderr %.3f), expected 100\n", mean,
                se);
  if (fabs(mean - 100) > 1.0)
    fail_msg("through a lossless dispersive sphere: mean Y %.4f (stderr %.3f), the furnace "
             "expects L_e = 100 cd/m2 within 1 %%",
             mean, se);
  /* Sensors above the sphere, looking at it: E = π L_e, read as the mean
   * of four points (about 0.25 % stderr together). */
  expect_mean_lx(r, M_PI * 100.0, 0.01, "sensors facing a lossless dispersive sphere");
  done(r);
}

/* Photon mapping in the furnace (lambert walls, albedo 0.5, emitting
 * 100 cd/m²) with the lossless dispersive sphere in view: by the same
 * argument the radiance is L_e / (1 - a) = 200 cd/m² everywhere, and what
 * the camera sees through the sphere is lit by caustic photons that crossed
 * it.  The irradiance on every wall is uniform, so a density estimate has
 * no smoothing bias here and each seed's image mean is an unbiased estimate
 * of 200.  A run does not report the variance of its photon estimate, so
 * the bound comes from the seeds themselves: K = 20 seeds, their mean held
 * to T = 5.5 of its standard error s / sqrt(K).  The ratio follows
 * Student's t with 19 degrees of freedom, which exceeds 5.5 with
 * probability 2.6e-5 (two-sided).  The same requires s / sqrt(K) under 1 %
 * of 200, so a noisy run cannot pass. */
static void test_dispersive_furnace_photons(void **state) {
  (void)state;
  enum { K = 20 };
  const double T = 5.5, want = 100.0 / (1 - 0.5); /* L_e / (1 - a) */
  seed_stats m = {0};
  size_t caustic = 0;
  for (int k = 0; k < K; k++) {
    char scn[1024];
    snprintf(scn, sizeof scn,
             "material wall lambert reflectance=0.5\n"
             FURNACE_WALLS("wall")
             "material glass db:sf11-lossless\n"
             "sphere center=0,0,0 radius=0.5 material=glass\n"
             "camera pinhole from=0,-0.95,0 to=0,0,0 fov=20 resolution=16x12\n"
             "render integrator=photon spp=32 photons=50000 caustic_photons=50000 depth=64 "
             "seed=%d\n",
             k + 1);
    vr_render_result *r = render_text(scn);
    assert_true(pass(r, "caustic photons")->ran);
    double s = 0;
    int n = r->width * r->height;
    for (int y = 0; y < r->height; y++)
      for (int x = 0; x < r->width; x++) s += Y(r, x, y);
    seed_add(&m, s / n);
    caustic += r->photons_caustic;
    done(r);
  }
  double mean = seed_mean(&m), se = seed_stderr(&m), sd = se * sqrt((double)K);
  print_message("    photon mapping through the sphere, %d seeds: mean Y %.3f cd/m2 (seed SD %.3f, "
                "stderr %.3f), expected %.1f; %.1f standard errors (%zu caustic photons a run)\n",
                K, mean, sd, se, want, (mean - want) / se, caustic / K);
  if (se > 0.01 * want)
    fail_msg("photon mapping through the sphere: standard error %.3f over 1 %% of %.1f", se,
             want);
  if (fabs(mean - want) > T * se)
    fail_msg("photon mapping through a lossless dispersive sphere: mean Y %.3f over %d seeds, "
             "the furnace expects %.1f within %.1f standard errors (%.3f)",
             mean, K, want, T, T * se);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_dispersive_furnace),
      cmocka_unit_test(test_dispersive_furnace_photons),
  };
  return cmocka_run_group_tests(tests, setup, harness_close);
}
