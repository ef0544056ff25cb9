/* glTF metallic-roughness surfaces (material source pbr) in the renderer,
 * read through an illuminance sensor against the glTF 2.0 specification
 * (Appendix B): a smooth floor under a large uniform emitter reflects
 * its image with Schlick's Fresnel factor F(mu) = F0 + (1 - F0)(1 - mu)^5,
 * F0 = 0.04 for a dielectric (an interface of index 1.5) and F0 = the base
 * colour for a metal.  A sensor facing the floor at height h under the
 * emitter at height H reads
 *     E = L * integral of F(cos t) cos t dw
 * over the directions whose mirror image reaches the emitter (a square of
 * side S: |x|, |y| <= S/2 at distance (h + H) tan t).  The integral is
 * taken here by a fine midpoint rule; the sensor's paths follow the
 * mirror (a delta lobe, so the emitter's emission counts when reached). */
#include "vr_test.h"

#include "render_test_util.h"

#define L_CD 1000.0 /* emitter luminance, cd/m2 */
#define SIDE 40.0
#define HS 1.0 /* sensor height */
#define HE 2.0 /* emitter height */

static double expected_lx(double f0) {
  const int nt = 4000, np = 720;
  double sum = 0;
  for (int i = 0; i < nt; i++) {
    double t = (i + 0.5) / nt * M_PI / 2, mu = cos(t), rho = (HS + HE) * tan(t);
    double F = f0 + (1 - f0) * pow(1 - mu, 5), part = 0;
    for (int j = 0; j < np; j++) {
      double phi = (j + 0.5) / np * 2 * M_PI;
      part += fabs(rho * cos(phi)) <= SIDE / 2 && fabs(rho * sin(phi)) <= SIDE / 2;
    }
    sum += F * mu * sin(t) * part;
  }
  return L_CD * sum * (M_PI / 2 / nt) * (2 * M_PI / np);
}

/* The floor of material floor_material under the emitter (black, or a
 * grey reflector when grey_emitter), read by one sensor with the given
 * estimator (path or photon) and samples. */
static double sensor_lx(const char *floor_material, const char *sensors, bool grey_emitter,
                        int samples) {
  char scn[1024];
  snprintf(scn, sizeof scn,
           "material floor %s\n"
           "material dark %s\n"
           "rect center=0,0,0 normal=0,0,1 size=%g,%g material=floor\n"
           "rect center=0,0,%g normal=0,0,-1 size=%g,%g material=dark emission=%gcd/m2\n"
           "sensor s point position=0,0,%g normal=0,0,-1\n"
           "render integrator=path sensors=%s sensor_samples=%d photons=400000\n",
           floor_material, grey_emitter ? "lambert reflectance=0.5" : "black", 4 * SIDE,
           4 * SIDE, HE, SIDE, SIDE, L_CD, HS, sensors, samples);
  vr_render_result *r = render_text_with(scn, 1, 2, true);
  assert_int_equal(r->nreadings, 1);
  double e = r->readings[0].illuminance_lx;
  print_message("%s, %s sensors: %.3f lx (stderr %.3f)\n", floor_material, sensors, e,
                r->readings[0].stderr_lx);
  vr_render_result_destroy(r);
  return e;
}

static void test_smooth_dielectric_floor(void **state) {
  (void)state;
  double want = expected_lx(0.04);
  /* An infinite emitter would give pi L (0.04 + 0.96 / 21) = 269.3 lx. */
  print_message("expected %.3f lx\n", want);
  assert_true(want > 200 && want < 269.3);
  const char *m = "pbr color=#000000 metallic=0 roughness=0";
  assert_near(sensor_lx(m, "path", false, 4096), want, 0.01 * want);
}

static void test_smooth_metal_floor(void **state) {
  (void)state;
  /* rgb=0.5,0.5,0.5 space=linear: a grey of reflectance 0.5 at every
   * wavelength (Jakob-Hanika's sigmoid is flat for greys). */
  double want = expected_lx(0.5);
  print_message("expected %.3f lx\n", want);
  const char *m = "pbr rgb=0.5,0.5,0.5 space=linear metallic=1 roughness=0";
  assert_near(sensor_lx(m, "path", false, 4096), want, 0.01 * want);
}

/* A grey base under the smooth coat, the emitter a grey reflector too (so
 * that light interreflects and the global map fills): the floor's diffuse
 * light and the emitter's mirror image.  Photon sensors estimate the
 * diffuse part from the maps and must follow the coat's mirror for the
 * rest, which is the reading of the same floor with a black base (about
 * 10 % of the whole): without it they would read that much low.  The
 * floor is lit almost uniformly (within 1 % over the disc the maps
 * average), where density estimation has no bias, and the diffuse term
 * evaluated at the mirror direction differs from the exact one by under
 * 1 % here, so the two estimates agree within their noise: 65 536 samples
 * give each a standard error under 2 %; 5 % is 2 of their combined
 * standard deviations and half the part a lost lobe would drop. */
static void test_photon_sensors_follow_the_coat(void **state) {
  (void)state;
  const char *m = "pbr rgb=0.5,0.5,0.5 space=linear metallic=0 roughness=0";
  double path = sensor_lx(m, "path", true, 65536), photon = sensor_lx(m, "photon", true, 65536);
  double mirror = sensor_lx("pbr color=#000000 metallic=0 roughness=0", "path", true, 4096);
  assert_true(mirror > 0.08 * path);
  assert_near(photon, path, 0.05 * path);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_smooth_dielectric_floor),
      cmocka_unit_test(test_smooth_metal_floor),
      cmocka_unit_test(test_photon_sensors_follow_the_coat),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
