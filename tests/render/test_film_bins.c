/* The camera film keeps its spectral bins only when an output needs them
 * (vr_render_options.film_without_bins, which vr-render sets when --outputs
 * leaves out the spectral EXR):
 *   - the XYZ image is the same, bit for bit, with or without the bins:
 *     the bins are a second tally of the same samples, never read back;
 *   - the film's sums take 8 bytes x 3 a pixel instead of 8 x (3 + bins),
 *     the arithmetic of its layout (XYZ and one value per bin, doubles);
 *   - the same holds for progressive photon mapping, whose own film of
 *     visible points' sums follows the camera film's bins;
 *   - with several sub-domains and threads the image is the one of one
 *     sub-domain on one thread (the decomposition's invariance, to 1e-6). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "render_test_util.h"

static const char *SCENE =
    "material wall lambert reflectance=0.6\n"
    "box min=-2,-1.5,0 max=2,1.5,2.5 material=wall\n"
    "light point position=0.5,0.3,2.0 intensity=200cd\n"
    "camera pinhole from=-1.8,-1.3,1.4 to=1,1,0.6 fov=70 resolution=40x30\n"
    "render integrator=%s spp=8 photons=20000 depth=8 seed=3\n";

static vr_render_result *render(const char *integrator, bool without_bins, int S, int P) {
  char text[1024];
  snprintf(text, sizeof text, SCENE, integrator);
  vr_scene *s = parse_text(text, "bins.scn");
  vr_render_options o;
  vr_render_options_default(&o);
  o.subdomains = S;
  o.threads = P;
  o.film_without_bins = without_bins;
  vr_render_result *r = render_scene_opt(s, NULL, &o);
  vr_scene_destroy(s);
  return r;
}

static void same_image(const char *integrator) {
  vr_render_result *with = render(integrator, false, 1, 1), *without = render(integrator, true, 1, 1);
  size_t px = (size_t)with->width * (size_t)with->height;
  assert_int_equal(with->nbins, 30); /* the default film: 400-700 nm by 10 nm */
  assert_non_null(with->spectral);
  assert_null(without->spectral);
  assert_int_equal(without->nbins, with->nbins); /* the sensors keep theirs */
  assert_true(with->film_bytes == px * (3 + 30) * sizeof(double));
  assert_true(without->film_bytes == px * 3 * sizeof(double));
  assert_memory_equal(with->xyz, without->xyz, px * 3 * sizeof(double));
  double sum = 0;
  for (size_t i = 0; i < px; i++) sum += with->xyz[3 * i + 1];
  assert_true(sum > 0); /* an image, not a black frame */
  /* Several sub-domains and threads, without bins: the same image. */
  vr_render_result *split = render(integrator, true, 4, 2);
  for (size_t i = 0; i < px * 3; i++)
    if (!(fabs(split->xyz[i] - with->xyz[i]) <= 1e-6 * fabs(with->xyz[i]) + 1e-300))
      fail_msg("%s: value %zu is %.17g on 4 sub-domains and 2 threads, %.17g on one", integrator,
               i, split->xyz[i], with->xyz[i]);
  vr_render_result_destroy(split);
  vr_render_result_destroy(with);
  vr_render_result_destroy(without);
}

static void path_tracing(void **state) {
  (void)state;
  same_image("path");
}

static void progressive_photon_mapping(void **state) {
  (void)state;
  same_image("progressive");
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(path_tracing),
      cmocka_unit_test(progressive_photon_mapping),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
