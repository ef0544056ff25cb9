/* More of the renderer against answers from outside its code:
 *   - spot light: E = I cos θ / r² inside the cone, nothing outside
 *     cone + falloff, and the falloff law in between: smoothstep in cos θ
 *     between cos(cone + falloff) and cos(cone), pbrt-v4's SpotLight
 *     (Pharr, Jakob, Humphreys, "Physically Based Rendering", 4th ed.,
 *     2023, section 12.2.1); lumens to candela through the solid angle of
 *     the cone, 2π(1 - cos θ), and with the falloff band half-weighted;
 *   - thin-lens camera: radiance is conserved through an ideal lens (a
 *     uniform emitter filling the view reads its luminance in every pixel),
 *     the circle of confusion of the thin-lens model, blur diameter (in the
 *     plane of focus) 2A |z - f| / z for a point at depth z seen through a
 *     lens of radius A focused at f, and defocus conserves the image's flux;
 *   - fixed wavelength bins and hero sampling both give E = I cos θ / r²
 *     and the CIE 171:2006 case 5.8 indirect illuminance under a strongly
 *     coloured source (CIE illuminant A) and walls of a strongly coloured
 *     reflectance, the energy balance taken per wavelength (fixed bins
 *     against the same balance discretised as the mode defines it: 8 bins,
 *     spectra at the centres, ȳ averaged per bin; that discretisation is
 *     itself 1.6 % above the continuous answer, which the test prints);
 *   (dispersion: test_render_dispersion.c; progressive photon mapping in
 *   the white furnace: test_sppm.c). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "vr/colour.h"
#include "vr/matdb.h"
#include "vr/render.h"
#include "vr/scene.h"
#include "vr/spectrum.h"
#include "render_test_util.h"
#include "extra_harness.h"

/* A strongly coloured reflectance: 0.1 at 360 nm rising linearly to 0.8 at
 * 830 nm, held beyond. */
static double ramp_rho(double nm) {
  if (nm <= 360) return 0.1;
  if (nm >= 830) return 0.8;
  return 0.1 + 0.7 * (nm - 360) / 470.0;
}

static int setup(void **state) {
  (void)state;
  if (harness_open("extra")) return -1;
  double rn[4] = {250, 360, 830, 2500}, rv[4] = {0.1, 0.1, 0.8, 0.8};
  vr_error err = {0};
  vr_material *m = vr_material_create("ramp-red", VR_KIND_REFLECTANCE, &err);
  vr_material_add_spectrum(m, "value", vr_spectrum_create(4, rn, rv, NULL), &err);
  return harness_save(m);
}

/* ---------------------------------------------------------------- spot */

static double deg(double d) { return d * M_PI / 180.0; }

/* The falloff of pbrt-v4's SpotLight::I: smoothstep(cos θ) from
 * cos(cone + falloff) (0) to cos(cone) (1). */
static double smoothstep_cos(double theta, double cone, double falloff) {
  double co = cos(deg(cone + falloff)), ci = cos(deg(cone)), c = cos(deg(theta));
  if (c >= ci) return 1;
  if (c <= co) return 0;
  double x = (c - co) / (ci - co);
  return x * x * (3 - 2 * x);
}

/* A 1000 cd spot 2 m above a black floor, cone 30°, falloff 20°. */
static void test_spot_cone_and_falloff(void **state) {
  (void)state;
  /* Floor points at polar angles θ from the axis: horizontal distance 2 tan θ. */
  const double theta[] = {0, 14, 27, 40, 55, 70};
  char scn[2048];
  int n = snprintf(scn, sizeof scn,
                   "material black black\n"
                   "rect center=0,0,0 normal=0,0,1 size=30,30 material=black\n"
                   "light spot position=0,0,2 direction=0,0,-1 cone=30 falloff=20 "
                   "intensity=1000cd\n");
  for (int i = 0; i < 6; i++) {
    double rho = 2 * tan(deg(theta[i])), az = deg(37.0 * i); /* around the axis */
    n += snprintf(scn + n, sizeof scn - (size_t)n,
                  "sensor s%d point position=%.17g,%.17g,0 normal=0,0,1\n", i, rho * cos(az),
                  rho * sin(az));
  }
  snprintf(scn + n, sizeof scn - (size_t)n, "render integrator=path sensor_samples=64\n");
  vr_render_result *r = render_text(scn);
  assert_int_equal(r->nreadings, 6);
  for (int i = 0; i < 6; i++) {
    double c = cos(deg(theta[i])), r2 = 4.0 / (c * c);
    /* E = I f(θ) cos θ / r² (inverse-square and cosine laws), f the falloff. */
    double want = 1000.0 * smoothstep_cos(theta[i], 30, 20) * c / r2;
    if (theta[i] < 30)
      expect_lx(r, (size_t)i, want, 0.01); /* inside the cone: full intensity */
    else if (theta[i] < 50)
      /* In the falloff band, at its middle angle: 0.5779 of full, where a
       * law linear or smooth in the angle would give 0.5. */
      expect_lx(r, (size_t)i, want, 0.02);
    else if (r->readings[i].illuminance_lx != 0.0) /* outside cone + falloff: nothing */
      fail_msg("sensor %d at %g deg, outside cone + falloff: %.6g lx, expected exactly 0", i,
               theta[i], r->readings[i].illuminance_lx);
  }
  done(r);
}

/* intensity=...lm: the flux spreads over the cone's solid angle 2π(1 - cos θ);
 * with a falloff band, smoothstep in cos θ integrates to half the band, so
 * Ω = 2π(1 - (cos θ_in + cos θ_out) / 2). */
static void test_spot_lumens(void **state) {
  (void)state;
  /* Two spots 10 m apart, each seen by the other's sensor at 78.7° from
   * its axis: outside both cones. */
  const char *scn =
      "material black black\n"
      "rect center=5,0,0 normal=0,0,1 size=30,10 material=black\n"
      "light spot position=0,0,2 direction=0,0,-1 cone=30 intensity=1000lm\n"
      "light spot position=10,0,2 direction=0,0,-1 cone=20 falloff=30 intensity=1000lm\n"
      "sensor a point position=0,0,0 normal=0,0,1\n"
      "sensor b point position=10,0,0 normal=0,0,1\n"
      "render integrator=path sensor_samples=64\n";
  vr_render_result *r = render_text(scn);
  double I1 = 1000.0 / (2 * M_PI * (1 - cos(deg(30)))); /* Φ / 2π(1 - cos θ) = 1187.9 cd */
  double I2 = 1000.0 / (2 * M_PI * (1 - 0.5 * (cos(deg(20)) + cos(deg(50)))));
  expect_lx(r, 0, I1 / 4.0, 0.01); /* on the axis, 2 m below: E = I / r² */
  expect_lx(r, 1, I2 / 4.0, 0.01);
  done(r);
}

/* ---------------------------------------------------------- thin lens */

/* A black emitter of 100 cd/m² filling the view: Y = 100 cd/m² in every
 * pixel, pinhole or lens (radiance is invariant along rays and an ideal lens
 * only redirects them), with no fall-off towards the edges of the 60° field
 * (no cos⁴ vignetting: the film records radiance, not irradiance). */
static void test_lens_uniform_emitter(void **state) {
  (void)state;
  const char *models[2] = {"pinhole", "thinlens aperture=5cm focus=3"};
  for (int m = 0; m < 2; m++) {
    char scn[1024];
    snprintf(scn, sizeof scn,
             "camera %s from=0,0,0 to=0,1,0 fov=60 resolution=16x12\n"
             "material black black\n"
             "rect center=0,3,0 normal=0,-1,0 size=100,100 material=black emission=100cd/m2\n"
             "render integrator=path spp=32\n",
             models[m]);
    vr_render_result *r = render_text(scn);
    double sum = 0, sq = 0, lo = INFINITY, hi = -INFINITY, col[16] = {0};
    assert_int_equal(r->width, 16);
    for (int y = 0; y < r->height; y++)
      for (int x = 0; x < r->width; x++) {
        double v = Y(r, x, y);
        sum += v;
        sq += (v - 100) * (v - 100);
        col[x] += v / r->height;
        lo = fmin(lo, v);
        hi = fmax(hi, v);
      }
    int n = r->width * r->height;
    double mean = sum / n, sd = sqrt(sq / n);
    print_message("    %s: mean Y %.4f cd/m2, pixels %.3f..%.3f (sd %.3f), edge columns %.3f "
                  "%.3f\n",
                  models[m], mean, lo, hi, sd, col[0], col[15]);
    /* The pixels scatter by wavelength sampling only (sd about 0.7 %):
     * the mean within 1 %, every pixel within 4 %, every column (12 pixels)
     * within 1.5 %. */
    if (fabs(mean - 100) > 1.0)
      fail_msg("%s: mean Y %.4f, expected 100 within 1 %%", models[m], mean);
    if (lo < 96 || hi > 104)
      fail_msg("%s: pixels from %.3f to %.3f, expected 100 within 4 %%", models[m], lo, hi);
    for (int x = 0; x < 16; x++)
      if (fabs(col[x] - 100) > 1.5)
        fail_msg("%s: column %d has mean Y %.3f, expected 100 within 1.5 %%", models[m], x, col[x]);
    done(r);
  }
}

/* The image of a 0.32 m square emitter (100 cd/m²) 2 m in front of the
 * camera, 48 x 48 pixels of 0.01 in tan-space (tan(fov/2) = 0.24): in
 * focus it covers exactly pixels 16..31 on each axis.  Focused at f = 1 m
 * through a lens of radius A = 8 cm, each point spreads over the circle of
 * confusion: in the plane of focus its diameter is 2A |z - f| / z (thin
 * lens; Potmesil and Chakravarty, "A lens and aperture camera model for
 * synthetic image generation", SIGGRAPH 1981), i.e. an angular radius
 * (tan-space) of A |1/f - 1/z| = 0.04 = 4 pixels.  So the lit extent grows
 * from 16 to 16 + 2 x 4 = 24 pixels, the flux-weighted variance across x
 * from 16²/12 by R²/4 (a uniform disc of radius R projected on a line),
 * and the total flux stays Σ Y p² = L_e (s/z)² (p the pixel's tan-space
 * width): the lens moves light, it does not create or remove it. */
typedef struct image_stats {
  double flux;       /* Σ Y, cd/m² x pixels */
  int x0, x1, y0, y1; /* lit extent, inclusive */
  double var_x, var_y; /* flux-weighted variance of pixel centres, pixels² */
} image_stats;

static image_stats image_of_square(const char *lens) {
  char scn[1024];
  double fov = 2 * atan(0.24) * 180 / M_PI;
  snprintf(scn, sizeof scn,
           "camera %s from=0,0,0 to=0,1,0 fov=%.17g resolution=48x48\n"
           "material black black\n"
           "rect center=0,2,0 normal=0,-1,0 size=0.32,0.32 material=black emission=100cd/m2\n"
           "render integrator=path spp=128 seed=7\n",
           lens, fov);
  vr_render_result *r = render_text(scn);
  image_stats s = {0, 1 << 20, -1, 1 << 20, -1, 0, 0};
  double mx = 0, my = 0;
  for (int y = 0; y < r->height; y++)
    for (int x = 0; x < r->width; x++) {
      double v = Y(r, x, y);
      if (v <= 0) continue;
      s.flux += v;
      mx += v * (x + 0.5);
      my += v * (y + 0.5);
      if (x < s.x0) s.x0 = x;
      if (x > s.x1) s.x1 = x;
      if (y < s.y0) s.y0 = y;
      if (y > s.y1) s.y1 = y;
    }
  mx /= s.flux;
  my /= s.flux;
  for (int y = 0; y < r->height; y++)
    for (int x = 0; x < r->width; x++) {
      double v = Y(r, x, y);
      s.var_x += v * (x + 0.5 - mx) * (x + 0.5 - mx);
      s.var_y += v * (y + 0.5 - my) * (y + 0.5 - my);
    }
  s.var_x /= s.flux;
  s.var_y /= s.flux;
  print_message("    %s: flux %.1f, x %d..%d, y %d..%d, var %.3f %.3f, centre %.3f %.3f\n", lens,
                s.flux, s.x0, s.x1, s.y0, s.y1, s.var_x, s.var_y, mx, my);
  done(r);
  return s;
}

static void test_lens_defocus(void **state) {
  (void)state;
  /* L_e (s/z)² / p² = 25600 */
  const double flux = 100.0 * (0.32 / 2.0) * (0.32 / 2.0) / (0.01 * 0.01);
  image_stats pin = image_of_square("pinhole");
  image_stats focus = image_of_square("thinlens aperture=8cm focus=2");
  image_stats blur = image_of_square("thinlens aperture=8cm focus=1");
  const image_stats *in[2] = {&pin, &focus};
  for (int i = 0; i < 2; i++) {
    if (in[i]->x0 != 16 || in[i]->x1 != 31 || in[i]->y0 != 16 || in[i]->y1 != 31)
      fail_msg("in focus: lit x %d..%d, y %d..%d, expected 16..31 on both axes", in[i]->x0,
               in[i]->x1, in[i]->y0, in[i]->y1);
    if (fabs(in[i]->flux - flux) > 0.01 * flux)
      fail_msg("in focus: flux %.1f, expected %.1f within 1 %%", in[i]->flux, flux);
  }
  /* Circle of confusion radius in pixels: A |1/f - 1/z| / p. */
  double R = 0.08 * fabs(1 / 1.0 - 1 / 2.0) / 0.01; /* 4 pixels */
  int lo = (int)lround(16 - R), hi = (int)lround(31 + R); /* 12..35: 24 pixels */
  if (abs(blur.x0 - lo) > 1 || abs(blur.x1 - hi) > 1 || abs(blur.y0 - lo) > 1 ||
      abs(blur.y1 - hi) > 1)
    fail_msg("defocused: lit x %d..%d, y %d..%d, thin lens gives %d..%d within 1 pixel", blur.x0,
             blur.x1, blur.y0, blur.y1, lo, hi);
  /* Flux-weighted variance: the square's 16²/12 (continuous) plus R²/4. */
  double Rx = 2 * sqrt(blur.var_x - 256.0 / 12), Ry = 2 * sqrt(blur.var_y - 256.0 / 12);
  print_message("    circle of confusion radius from the variance: %.3f, %.3f px (thin lens "
                "%.3f)\n",
                Rx, Ry, R);
  /* Sampling scatter of the estimate: about 0.07 pixel at 128 spp. */
  if (fabs(Rx - R) > 0.3 || fabs(Ry - R) > 0.3)
    fail_msg("defocus radius %.3f, %.3f pixels from the image's spread, thin lens %.3f", Rx, Ry, R);
  if (fabs(blur.flux - flux) > 0.02 * flux)
    fail_msg("defocused: flux %.1f, expected %.1f within 2 %% (in focus %.1f)", blur.flux, flux,
             focus.flux);
}

/* ----------------------------------------------------- bins and hero */

/* A 500 cd lamp 2 m above a black floor: E = I cos θ / r² whatever its
 * spectrum and the wavelengths sampled (photometric units), for the
 * strongly coloured CIE illuminant A and for D65 (the lamps' default). */
static void test_spectral_modes_direct(void **state) {
  (void)state;
  /* Both modes as a scene asks for them, with the default 4 wavelengths. */
  const char *spectra[2] = {"A", "D65"};
  const char *modes[2] = {"spectral=hero", "spectral=bins"};
  char failed[1024] = "";
  size_t nf = 0;
  for (int sp = 0; sp < 2; sp++)
    for (int m = 0; m < 2; m++) {
      char scn[1024];
      snprintf(scn, sizeof scn,
               "material black black\n"
               "rect center=0,0,0 normal=0,0,1 size=20,20 material=black\n"
               "light point position=0,0,2 intensity=500cd spectrum=%s\n"
               "sensor o point position=0,0,0 normal=0,0,1\n"
               "sensor a point position=1.5,0,0 normal=0,0,1\n"
               "sensor b point position=2,2,0 normal=0,0,1\n"
               "sensor c point position=-3,1,0 normal=0,0,1\n"
               "render integrator=path sensor_samples=64 %s\n",
               spectra[sp], modes[m]);
      vr_render_result *r = render_text(scn);
      for (size_t i = 0; i < r->nreadings; i++) {
        const double *p = r->readings[i].position;
        double r2 = p[0] * p[0] + p[1] * p[1] + 4.0;
        double want = 500.0 * (2.0 / sqrt(r2)) / r2; /* inverse-square and cosine laws */
        double got = r->readings[i].illuminance_lx;
        print_message("    %-3s %s: sensor %zu %.4f lx (stderr %.4f), expected %.4f (%+.2f %%)\n",
                      spectra[sp], modes[m], i, got, r->readings[i].stderr_lx, want,
                      100 * (got / want - 1));
        if (fabs(got - want) > 0.01 * want && nf < sizeof failed - 128)
          nf += (size_t)snprintf(failed + nf, sizeof failed - nf,
                                 " [%s %s sensor %zu: %.3f lx, expected %.3f]", spectra[sp],
                                 modes[m], i, got, want);
      }
      done(r);
    }
  if (nf) fail_msg("E = I cos(theta) / r^2 within 1 %% fails:%s", failed);
}

/* CIE 171:2006 case 5.8 per wavelength: a 4 m cube of reflectance ρ(λ), an
 * isotropic source of spectral flux Φ(λ) at its centre: the mean indirect
 * spectral irradiance is ρ(λ) Φ(λ) / (S_T (1 - ρ(λ))), each wavelength
 * balancing its own energy.  Φ(λ) = Φ_v S_A(λ) / (K_m ∫ ȳ S_A) for
 * 10000 lm of CIE illuminant A; the illuminance is K_m ∫ ȳ E(λ) dλ. */
static double cie171_coloured_indirect(void) {
  vr_error err = {0};
  vr_spectrum *A = vr_illuminant("A", &err);
  assert_non_null(A);
  double num = 0, den = 0;
  for (double nm = 360.05; nm < 830; nm += 0.1) {
    double c[3];
    vr_cmf_eval(VR_CIE1931_2DEG, nm, c);
    double s = vr_spectrum_eval(A, nm, VR_INTERP_LINEAR), rho = ramp_rho(nm);
    den += c[1] * s;
    num += c[1] * s * rho / (1 - rho);
  }
  vr_spectrum_destroy(A);
  return 10000.0 / 96.0 * num / den;
}

/* The same balance as fixed bins compute it (docs/scene-format.md,
 * `spectral=bins`): 8 bins of 58.75 nm over 360-830 nm, the spectra taken
 * at each bin's centre and ȳ averaged over the bin, while the lamp's
 * 10000 lm still fixes Φ(λ) by the exact integral K_m ∫ ȳ S_A.  This is
 * the analytic answer of the discretised problem; its gap to the
 * continuous one above is the quadrature error of the mode. */
static double cie171_coloured_indirect_bins(void) {
  vr_error err = {0};
  vr_spectrum *A = vr_illuminant("A", &err);
  assert_non_null(A);
  double den = 0, num = 0, step = 470.0 / 8;
  for (double nm = 360.05; nm < 830; nm += 0.1) {
    double c[3];
    vr_cmf_eval(VR_CIE1931_2DEG, nm, c);
    den += c[1] * vr_spectrum_eval(A, nm, VR_INTERP_LINEAR) * 0.1;
  }
  for (int b = 0; b < 8; b++) {
    double centre = 360 + (b + 0.5) * step, ybar = 0;
    for (int i = 0; i < 5875; i++) {
      double c[3];
      vr_cmf_eval(VR_CIE1931_2DEG, 360 + b * step + (i + 0.5) * 0.01, c);
      ybar += c[1] / 5875;
    }
    double rho = ramp_rho(centre);
    num += ybar * step * vr_spectrum_eval(A, centre, VR_INTERP_LINEAR) * rho / (1 - rho);
  }
  vr_spectrum_destroy(A);
  return 10000.0 / 96.0 * num / den;
}

/* The floor's mean is read on an 8 x 8 grid of cell centres, which stands
 * for the face's mean to about 0.3 % (a 4 x 4 grid reads 1.4 % high, a
 * 16 x 16 grid 0.2 %: the indirect light peaks mid-face). */
static void test_spectral_modes_indirect(void **state) {
  (void)state;
  double wants[2] = {cie171_coloured_indirect(), cie171_coloured_indirect_bins()};
  print_message("  CIE 171 5.8 with ramp reflectance and illuminant A: %.3f lx (8 fixed bins: %.3f, %+.2f %%)\n",
                wants[0], wants[1], 100 * (wants[1] / wants[0] - 1));
  const char *modes[2] = {"spectral=hero", "spectral=bins"};
  char failed[512] = "";
  size_t nf = 0;
  for (int m = 0; m < 2; m++) {
    char scn[1024];
    snprintf(scn, sizeof scn,
             "material wall db:ramp-red\n"
             "box min=-2,-2,0 max=2,2,4 material=wall\n"
             "light point position=0,0,2 intensity=10000lm spectrum=A\n"
             "sensor floor grid origin=-2,-2,0 u=4,0,0 v=0,4,0 n=8,8 normal=0,0,1\n"
             "render integrator=path depth=64 sensor_samples=512 %s\n",
             modes[m]);
    vr_render_result *r = render_text(scn);
    double I = 10000.0 / (4 * M_PI), sum = 0, var = 0;
    for (size_t i = 0; i < r->nreadings; i++) {
      const double *p = r->readings[i].position;
      double r2 = p[0] * p[0] + p[1] * p[1] + 4.0;
      sum += r->readings[i].illuminance_lx - I * (2.0 / sqrt(r2)) / r2;
      var += r->readings[i].stderr_lx * r->readings[i].stderr_lx;
    }
    double n = (double)r->nreadings, mean = sum / n, se = sqrt(var) / n, want = wants[m];
    print_message("  %s: mean indirect %.3f lx (stderr %.3f), expected %.3f\n", modes[m], mean,
                  se, want);
    if (fabs(mean - want) > 0.02 * want)
      nf += (size_t)snprintf(failed + nf, sizeof failed - nf, " [%s: %.3f lx (stderr %.3f)]",
                             modes[m], mean, se);
    done(r);
  }
  if (nf) fail_msg("mean indirect illuminance, CIE 171 per wavelength (%.3f / bins %.3f lx) within 2 %%:%s",
                   wants[0], wants[1], failed);
}

/* ------------------------------------------------------- many emitters */

/* Illuminance at a point facing up from a Lambertian rectangle of
 * luminance L parallel to it, h above, spanning [x0, x1] x [y0, y1]
 * relative to the point: the corner form factor of Howell's catalogue
 * (C-11, plane element parallel to a rectangle with its normal through a
 * corner), E = L/2 [X/sqrt(1+X^2) atan(Y/sqrt(1+X^2)) + Y/sqrt(1+Y^2)
 * atan(X/sqrt(1+Y^2))] with X = a/h, Y = b/h, by superposition of the
 * four corner rectangles. */
static double corner(double x, double y, double h) {
  double X = fabs(x) / h, Y = fabs(y) / h;
  double f = 0.5 * (X / sqrt(1 + X * X) * atan(Y / sqrt(1 + X * X)) +
                    Y / sqrt(1 + Y * Y) * atan(X / sqrt(1 + Y * Y)));
  return copysign(1.0, x) * copysign(1.0, y) * f;
}

static double rect_lx(double L, double x0, double x1, double y0, double y1, double h) {
  return L * (corner(x1, y1, h) - corner(x0, y1, h) - corner(x1, y0, h) + corner(x0, y0, h));
}

/* Two emitting squares of very different size and height over a black
 * floor: each sensor reads the sum of both, as the form factors say,
 * whichever emitter next-event estimation picks (it picks by power over
 * squared distance, so the near one mostly, but the far one too). */
static void test_emitters_by_distance(void **state) {
  (void)state;
  const char *scn =
      "material black black\n"
      "rect center=0,0,1 normal=0,0,-1 size=0.4,0.4 material=black emission=5000cd/m2\n"
      "rect center=3,0,4 normal=0,0,-1 size=2,2 material=black emission=800cd/m2\n"
      "rect center=1.5,0,-0.01 normal=0,0,1 size=20,20 material=black\n"
      "sensor a point position=0,0,0 normal=0,0,1\n"
      "sensor b point position=3,0,0 normal=0,0,1\n"
      "sensor c point position=1.5,0.5,0 normal=0,0,1\n"
      "render integrator=path sensor_samples=65536 depth=2\n";
  vr_render_result *r = render_text(scn);
  const double P[3][2] = {{0, 0}, {3, 0}, {1.5, 0.5}};
  for (int i = 0; i < 3; i++) {
    double x = P[i][0], y = P[i][1];
    double E = rect_lx(5000, -0.2 - x, 0.2 - x, -0.2 - y, 0.2 - y, 1.0) +
               rect_lx(800, 2 - x, 4 - x, -1 - y, 1 - y, 4.0);
    expect_lx(r, (size_t)i, E, 0.01);
    assert_true(fabs(r->readings[i].illuminance_lx - E) < 4 * r->readings[i].stderr_lx + 1e-3 * E);
  }
  done(r);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_spot_cone_and_falloff),
      cmocka_unit_test(test_spot_lumens),
      cmocka_unit_test(test_lens_uniform_emitter),
      cmocka_unit_test(test_emitters_by_distance),
      cmocka_unit_test(test_lens_defocus),
      cmocka_unit_test(test_spectral_modes_direct),
      cmocka_unit_test(test_spectral_modes_indirect),
  };
  return cmocka_run_group_tests(tests, setup, harness_close);
}
