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

/* The mean luminance of a small view of a coated floor (grey base, smooth
 * coat) in front of a lit wall, rendered by the given integrator. */
static double view_mean(const char *integrator, int spp) {
  char scn[1024];
  snprintf(scn, sizeof scn,
           "material floor pbr rgb=0.5,0.5,0.5 space=linear metallic=0 roughness=0\n"
           "material wall lambert reflectance=0.9\n"
           "rect center=0,0,0 normal=0,0,1 size=4,4 material=floor\n"
           "rect center=0,2,1 normal=0,-1,0 size=4,2 up=0,0,1 material=wall\n"
           "light point position=0,1.9,1.9 intensity=100cd\n"
           "camera pinhole from=0,-3,1.2 to=0,0.5,0.2 up=0,0,1 fov=50 resolution=24x16\n"
           "render integrator=%s spp=%d photons=60000 depth=6\n",
           integrator, spp);
  vr_render_result *r = render_text_with(scn, 1, 2, false);
  double y = 0;
  for (int i = 0; i < r->width * r->height; i++) y += r->xyz[3 * (size_t)i + 1];
  y /= r->width * r->height;
  vr_render_result_destroy(r);
  print_message("coated floor, %s: mean Y %.4f cd/m2\n", integrator, y);
  return y;
}

/* SPPM keeps one visible point a pixel: on the coated floor it takes the
 * diffuse part, and the path going on by the coat's mirror must not lay a
 * second point (the wall's) over it (which loses most of the floor's
 * light here: the lamp lights the wall, the wall the floor; 19 % of the
 * image).  Path tracing is the reference.  SPPM reads the floor's diffuse
 * part at the mirror direction, its 1 - F factor at the view's incidence
 * (cosines 0.3-0.6 here: 1 - F from 0.80 to 0.93) where the exact term
 * takes F at each photon's half vector (down to F0 = 0.04, 1 - F = 0.96):
 * low by up to 17 % at the most grazing pixels of the floor, a few per
 * cent over the image, plus about 1 % of noise: 5 %. */
static void test_sppm_one_visible_point(void **state) {
  (void)state;
  double path = view_mean("path", 256), sppm = view_mean("progressive", 64);
  assert_near(sppm, path, 0.05 * path);
}

/* The mean XYZ of a head-on view of a glTF quad (tests/data/models/
 * gltf_vertex_colours) lit along its normal. */
static void quad_xyz(const char *file, double xyz[3]) {
  char scn[1024];
  snprintf(scn, sizeof scn,
           "mesh %s/models/gltf_vertex_colours/%s\n"
           "camera pinhole from=0,0,5 to=0,0,0 up=0,1,0 fov=8 resolution=12x12\n"
           "light point position=0,0,50 intensity=1e5cd\n"
           "render integrator=path spp=16 depth=2\n",
           VR_TEST_DATA, file);
  vr_render_result *r = render_text_models(scn, "quad.scn");
  xyz[0] = xyz[1] = xyz[2] = 0;
  for (int i = 0; i < 144; i++)
    for (int c = 0; c < 3; c++) xyz[c] += r->xyz[3 * i + c] / 144;
  vr_render_result_destroy(r);
}

/* glTF 2.0 §3.9.2: the base colour is baseColorFactor times COLOR_0, so a
 * white factor with blue vertex colours renders as a blue factor does
 * (both reach the sigmoid of (0, 0, 1): the RGB table's corner node, within
 * 0.0073 Delta E*ab of its colour, against the scene's own fit). */
static void test_gltf_colour0(void **state) {
  (void)state;
  double a[3], b[3];
  quad_xyz("quad_colour0.gltf", a);
  quad_xyz("quad_base.gltf", b);
  print_message("COLOR_0 blue: XYZ %.4f %.4f %.4f; base colour blue: %.4f %.4f %.4f\n", a[0],
                a[1], a[2], b[0], b[1], b[2]);
  for (int c = 0; c < 3; c++) assert_near(a[c], b[c], 0.01 * b[c]);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_smooth_dielectric_floor),
      cmocka_unit_test(test_smooth_metal_floor),
      cmocka_unit_test(test_photon_sensors_follow_the_coat),
      cmocka_unit_test(test_sppm_one_visible_point),
      cmocka_unit_test(test_gltf_colour0),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
