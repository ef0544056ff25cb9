/* Textures through the renderer (render/src/textures, world/textures.c).
 *
 * Outside references:
 *   - the ColorChecker's 8-bit sRGB (BabelColor 2012 averages,
 *     tests/data/colorchecker_babelcolor2012_srgb.csv) as a texture, lit
 *     by CIE D65 (the point light's default spectrum) and seen head on,
 *     comes back as its own colour: IEC 61966-2-1 decoding, D65 white,
 *     within Delta E00 1 (the just-noticeable difference: Sharma et al.
 *     2005, CIE 142-2001) of each patch, the white cell of the texture
 *     being the image's white;
 *   - a mip level is the box average of the texels it covers: a 1-texel
 *     black/white checker (linear 0 and 1) seen at 8 texels a pixel reads
 *     level 3, whose every texel is exactly 1/2, so each pixel is the
 *     pixel of a plain reflectance 0.5 rendered with the same numbers;
 *   - a real RGBA-type file (CMake's SmallLogo.png, grey + alpha, Debian's
 *     cmake-data, tests/data/images/README.md) over an emitter of
 *     100 cd/m2: alpha=blend lets through 1 - mean(alpha) of it, and the
 *     mean over the image of a bilinear interpolation over a whole period
 *     is the texels' mean, 153.882/900 = 0.170980 (the alpha values
 *     summed by an independent PNG decoder: Python's zlib and the PNG 1.2
 *     row filters); alpha=mask cuts where the bilinear alpha is below 0.5:
 *     0.824225 of the area, integrated by the same independent script on
 *     a 40 x 40 grid per texel (684 of the 900 texels are below 0.5; the
 *     bilinear contour rounds their corners and widens the holes between
 *     the logo's thin, anti-aliased strokes); two blend layers let through
 *     the mean of (1 - alpha)^2, 0.750584 (same integration);
 *   - Lambert's cosine law through a normal map: a 16-bit map of the
 *     constant tangent-space normal (sin 40°, 0, cos 40°) on a rect lit
 *     along its geometric normal makes every pixel cos 40° = 0.76604 of
 *     the rect without a map (within 0.1 %); a map of (0, 0, 1), and the
 *     tilted map at normal_scale=0, leave the image as it is (1e-4);
 *   - vertex colours of a real PLY file (Assimp's test model
 *     float-color.ply, written by MeshLab's VCGLIB: one triangle whose
 *     three vertices are blue, (0, 0, 1)) render as sRGB blue under D65:
 *     within Delta E00 1 of IEC 61966-2-1's blue, the white being the same
 *     triangle as a white reflector;
 *   - an OBJ opacity map (MTL map_d): Crytek Sponza's chain material,
 *     verbatim, with its 1-bit mask (tests/data/models/sponza_chain), on a
 *     quad over the whole texture in front of an emitter, lets through the
 *     share of the quad where the bilinear mask is below 0.5: 0.516067,
 *     computed by an independent script (Python's zlib and the PNG row
 *     filters to decode the mask, then per cell between four texel centres,
 *     wrapped, the exact area below 0.5 of the bilinear of its corners:
 *     1 with no white corner, 1 - (1 - ln 2) / 2 with one, 1/2 with two,
 *     (1 - ln 2) / 2 with three, 0 with four); 51.61 % of the texels are
 *     black. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "render_test_util.h"
#include "vr/colour.h"
#include "vr/image.h"

static char dir[] = "/tmp/vr-texture-test-XXXXXX";

static int setup(void **state) {
  (void)state;
  return mkdtemp(dir) ? 0 : -1;
}

static int teardown(void **state) {
  (void)state;
  char cmd[256];
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
  return system(cmd) == 0 ? 0 : -1;
}

/* A head-on view of a size x size rect at the origin (normal -y), filling
 * an N x N image exactly; the scene's other lines in extra. */
static vr_render_result *view(const char *material, double size, int N, int spp, const char *extra) {
  char scn[2048];
  double d = 5, fov = 2 * atan(size / 2 / d) * 180 / M_PI;
  snprintf(scn, sizeof scn,
           "%s\n"
           "rect center=0,0,0 normal=0,-1,0 size=%g,%g up=0,0,1 material=m\n"
           "camera pinhole from=0,-%g,0 to=0,0,0 up=0,0,1 fov=%.12g resolution=%dx%d\n"
           "%s"
           "render integrator=path spp=%d depth=2\n",
           material, size, size, d, fov, N, N, extra, spp);
  return render_text_with(scn, 1, 2, false);
}

static void lab_of(const double xyz[3], const double white[3], double lab[3]) {
  vr_xyz_to_lab(xyz, white, lab);
}

static void test_colorchecker_round_trip(void **state) {
  (void)state;
  /* The 24 patches and a white cell (255) in a 5 x 5 grid of 8 x 8 texels. */
  FILE *f = fopen(VR_TEST_DATA "/colorchecker_babelcolor2012_srgb.csv", "r");
  assert_non_null(f);
  char line[256];
  int codes[25][3], n = 0;
  while (fgets(line, sizeof line, f) && n < 24) {
    char name[64];
    if (line[0] == '#' || !strncmp(line, "patch", 5)) continue;
    if (sscanf(line, "%63[^,],%d,%d,%d", name, &codes[n][0], &codes[n][1], &codes[n][2]) == 4) n++;
  }
  fclose(f);
  assert_int_equal(n, 24);
  codes[24][0] = codes[24][1] = codes[24][2] = 255;
  vr_image img;
  vr_error e = {0};
  assert_int_equal(vr_image_alloc(&img, 40, 40, &e), VR_OK);
  for (int y = 0; y < 40; y++)
    for (int x = 0; x < 40; x++) {
      int cell = (y / 8) * 5 + x / 8; /* row 0 at the top of the image */
      for (int c = 0; c < 3; c++) img.data[(y * 40 + x) * 3 + c] = (float)(codes[cell][c] / 255.0);
    }
  char path[512], mat[700];
  snprintf(path, sizeof path, "%s/checker.png", dir);
  assert_int_equal(vr_image_write_png(path, &img, 8, &e), VR_OK);
  vr_image_free(&img);
  snprintf(mat, sizeof mat, "material m lambert texture=%s", path);
  /* The light 100 m away on the view axis: irradiance uniform within 1e-4. */
  int N = 100;
  vr_render_result *r = view(mat, 1.0, N, 64, "light point position=0,-100,0 intensity=1e6cd\n");
  double mean[25][3] = {{0}};
  for (int cell = 0; cell < 25; cell++) {
    int cx = cell % 5, cy = cell / 5, cnt = 0;
    /* The inner 12 x 12 pixels of the cell's 20 x 20 (image row 0 at the top). */
    for (int y = cy * 20 + 4; y < cy * 20 + 16; y++)
      for (int x = cx * 20 + 4; x < cx * 20 + 16; x++, cnt++)
        for (int c = 0; c < 3; c++) mean[cell][c] += r->xyz[((size_t)y * N + x) * 3 + c];
    for (int c = 0; c < 3; c++) mean[cell][c] /= cnt;
  }
  double worst = 0;
  for (int k = 0; k < 24; k++) {
    double lin[3], xyz[3], want[3], got[3], d65[3];
    for (int c = 0; c < 3; c++) lin[c] = vr_srgb_decode(codes[k][c] / 255.0);
    vr_srgb_linear_to_xyz(lin, xyz);
    double one[3] = {1, 1, 1};
    vr_srgb_linear_to_xyz(one, d65);
    lab_of(xyz, d65, want);
    lab_of(mean[k], mean[24], got);
    double de = vr_delta_e2000(want, got);
    if (!(de < 1.0)) fail_msg("patch %d: Delta E00 %.3f (Lab %.2f %.2f %.2f, want %.2f %.2f %.2f)", k, de,
                              got[0], got[1], got[2], want[0], want[1], want[2]);
    worst = fmax(worst, de);
  }
  printf("# ColorChecker texture under D65: worst Delta E00 %.3f\n", worst);
  vr_render_result_destroy(r);
}

/* The scale the texture tests rest on: a white Lambertian rect head on
 * under an I cd source at d m has L = I / (pi d^2) cd/m2 with D65's
 * chromaticity x = 0.31271, y = 0.32902 (CIE 15:2004, table T.3). */
static void test_white_reference(void **state) {
  (void)state;
  vr_render_result *r = view("material m lambert reflectance=1", 1.0, 32, 64,
                             "light point position=0,-100,0 intensity=1e6cd\n");
  double s[3] = {0, 0, 0};
  for (int i = 0; i < 32 * 32; i++)
    for (int c = 0; c < 3; c++) s[c] += r->xyz[3 * i + c] / (32 * 32);
  double want = 1e6 / (M_PI * 100 * 100), x = s[0] / (s[0] + s[1] + s[2]), y = s[1] / (s[0] + s[1] + s[2]);
  printf("# white: Y %.4f cd/m2 (%.4f), x %.5f y %.5f (0.31271 0.32902)\n", s[1], want, x, y);
  assert_true(fabs(s[1] / want - 1) < 0.005);
  assert_true(fabs(x - 0.31271) < 1e-3 && fabs(y - 0.32902) < 1e-3);
  vr_render_result_destroy(r);
}

static void test_mip_footprint(void **state) {
  (void)state;
  vr_image img;
  vr_error e = {0};
  assert_int_equal(vr_image_alloc(&img, 256, 256, &e), VR_OK);
  for (int y = 0; y < 256; y++)
    for (int x = 0; x < 256; x++)
      for (int c = 0; c < 3; c++) img.data[(y * 256 + x) * 3 + c] = (float)((x + y) & 1);
  char path[512], mat[700];
  snprintf(path, sizeof path, "%s/fine.png", dir);
  assert_int_equal(vr_image_write_png(path, &img, 8, &e), VR_OK);
  vr_image_free(&img);
  snprintf(mat, sizeof mat, "material m lambert texture=%s", path);
  const char *light = "light point position=0,-100,0 intensity=1e6cd\n";
  vr_render_result *t = view(mat, 1.0, 32, 4, light);
  vr_render_result *g = view("material m lambert reflectance=0.5", 1.0, 32, 4, light);
  double worst = 0;
  for (size_t i = 0; i < 32 * 32; i++) {
    double a = t->xyz[3 * i + 1], b = g->xyz[3 * i + 1];
    assert_true(b > 0);
    worst = fmax(worst, fabs(a / b - 1));
  }
  printf("# 8 texels a pixel: largest pixel deviation from reflectance 0.5: %.2e\n", worst);
  /* 16-bit codes: 32768/65535 is 1.5e-5 above 1/2. */
  assert_true(worst < 1e-3);
  vr_render_result_destroy(t);
  vr_render_result_destroy(g);
}

/* A w x w 16-bit PNG of one tangent-space normal. */
static void write_normal_map(const char *path, double x, double y, double z) {
  vr_image img;
  vr_error e = {0};
  assert_int_equal(vr_image_alloc(&img, 8, 8, &e), VR_OK);
  for (int i = 0; i < 64; i++) {
    img.data[3 * i] = (float)((x + 1) / 2);
    img.data[3 * i + 1] = (float)((y + 1) / 2);
    img.data[3 * i + 2] = (float)((z + 1) / 2);
  }
  assert_int_equal(vr_image_write_png(path, &img, 16, &e), VR_OK);
  vr_image_free(&img);
}

static double worst_ratio(const vr_render_result *a, const vr_render_result *b, double want) {
  double worst = 0;
  for (int i = 0; i < a->width * a->height; i++) {
    double y = b->xyz[3 * (size_t)i + 1];
    assert_true(y > 0);
    worst = fmax(worst, fabs(a->xyz[3 * (size_t)i + 1] / y / want - 1));
  }
  return worst;
}

static void test_normal_map(void **state) {
  (void)state;
  char flat[512], tilt[512], mat[1200];
  snprintf(flat, sizeof flat, "%s/flat_n.png", dir);
  snprintf(tilt, sizeof tilt, "%s/tilt_n.png", dir);
  double th = 40 * M_PI / 180;
  write_normal_map(flat, 0, 0, 1);
  write_normal_map(tilt, sin(th), 0, cos(th));
  /* The light 10 km away: its direction varies by 5e-5 rad over the rect,
   * 6e-5 of cos 40° through the tilt (at 100 m it was 4e-3). */
  const char *light = "light point position=0,-10000,0 intensity=1e10cd\n";
  vr_render_result *plain = view("material m lambert reflectance=0.5", 1.0, 16, 4, light);
  snprintf(mat, sizeof mat, "material m lambert reflectance=0.5 normal_map=%s", flat);
  vr_render_result *f = view(mat, 1.0, 16, 4, light);
  snprintf(mat, sizeof mat, "material m lambert reflectance=0.5 normal_map=%s", tilt);
  vr_render_result *t = view(mat, 1.0, 16, 4, light);
  snprintf(mat, sizeof mat, "material m lambert reflectance=0.5 normal_map=%s normal_scale=0", tilt);
  vr_render_result *z = view(mat, 1.0, 16, 4, light);
  double wf = worst_ratio(f, plain, 1), wt = worst_ratio(t, plain, cos(th)), wz = worst_ratio(z, plain, 1);
  printf("# normal maps: flat %.2e, tilted 40 deg against cos 40 deg %.2e, scale 0 %.2e\n", wf, wt, wz);
  assert_true(wf < 1e-4);
  assert_true(wt < 1e-3);
  assert_true(wz < 1e-4);
  vr_render_result_destroy(plain);
  vr_render_result_destroy(f);
  vr_render_result_destroy(t);
  vr_render_result_destroy(z);
}

static double mean_y(const vr_render_result *r) {
  double s = 0;
  for (int i = 0; i < r->width * r->height; i++) s += r->xyz[3 * (size_t)i + 1];
  return s / (r->width * r->height);
}

/* The share of a 100 cd/m2 emitter seen through the CMake logo's rect with
 * the given material options (after texture=), behind the extra lines. */
static double through(const char *opts, const char *extra, int spp) {
  char mat[700], lines[1200];
  snprintf(mat, sizeof mat,
           "material m lambert texture=%s/images/cmake_smalllogo_grey_alpha.png %s", VR_TEST_DATA,
           opts);
  snprintf(lines, sizeof lines,
           "material black black\n"
           "rect center=0,1,0 normal=0,-1,0 size=8,8 material=black emission=100cd/m2\n%s",
           extra);
  vr_render_result *r = view(mat, 1.0, 60, spp, lines);
  double t = mean_y(r) / 100;
  vr_render_result_destroy(r);
  return t;
}

static void test_alpha(void **state) {
  (void)state;
  double t = through("alpha=blend", "", 64);
  printf("# alpha=blend: %.4f of the emitter through (1 - 0.170980 = 0.829020)\n", t);
  assert_true(fabs(t - (1 - 153.88235294 / 900)) < 0.005);
  t = through("alpha=mask", "", 16);
  printf("# alpha=mask: %.4f of the emitter through (0.824225)\n", t);
  assert_true(fabs(t - 0.824225) < 0.005);
  /* Two blend layers 1 cm apart: each draws its own number, so the pair
   * lets through the area mean of (1 - alpha)^2, 0.750584 (the same
   * independent integration); one number for both would give 0.829.  The
   * layers are black (the texture times reflectance 0): light the back
   * layer reflected between them would add to what comes through. */
  t = through("alpha=blend reflectance=0",
              "rect center=0,0.01,0 normal=0,-1,0 size=1,1 up=0,0,1 material=m\n", 64);
  printf("# two alpha=blend layers: %.4f through (0.750584)\n", t);
  assert_true(fabs(t - 0.750584) < 0.006);
  /* Without alpha= the same file is opaque: nothing through. */
  assert_true(through("", "", 4) < 1e-9);
}

/* The mean XYZ of a view straight down on the PLY triangle's inside. */
static void ply_view(const char *mesh_options, double xyz[3]) {
  char scn[1024];
  snprintf(scn, sizeof scn,
           "material white lambert reflectance=1\n"
           "mesh %s/models/assimp_ply/float-color.ply %s\n"
           "camera pinhole from=100,66,300 to=100,66,0 up=0,1,0 fov=4 resolution=16x16\n"
           "light point position=100,66,2000 intensity=1e8cd\n"
           "render integrator=path spp=16 depth=2\n",
           VR_TEST_DATA, mesh_options);
  vr_render_result *r = render_text_models(scn, "ply.scn");
  xyz[0] = xyz[1] = xyz[2] = 0;
  for (int i = 0; i < 16 * 16; i++)
    for (int c = 0; c < 3; c++) xyz[c] += r->xyz[3 * i + c] / (16 * 16);
  vr_render_result_destroy(r);
}

static void test_vertex_colours(void **state) {
  (void)state;
  double blue[3], white[3];
  ply_view("", blue);
  ply_view("material=white", white);
  double lin[3] = {0, 0, 1}, xyz[3], d65[3], one[3] = {1, 1, 1}, want[3], got[3];
  vr_srgb_linear_to_xyz(lin, xyz);
  vr_srgb_linear_to_xyz(one, d65);
  lab_of(xyz, d65, want);
  lab_of(blue, white, got);
  double de = vr_delta_e2000(want, got);
  printf("# PLY vertex colours (blue) under D65: Delta E00 %.3f (Lab %.2f %.2f %.2f, want %.2f %.2f %.2f)\n",
         de, got[0], got[1], got[2], want[0], want[1], want[2]);
  assert_true(de < 1.0);
}

/* Sponza's chain: the share of a 100 cd/m2 emitter seen through the quad. */
static void test_map_d(void **state) {
  (void)state;
  char scn[1024];
  /* fov is horizontal: the 16 x 64 image spans the quad's 0.25 x 1 m. */
  double d = 5, fov = 2 * atan(0.125 / d) * 180 / M_PI;
  snprintf(scn, sizeof scn,
           "material black black\n"
           "mesh %s/models/sponza_chain/chain.obj\n"
           "rect center=0,1,0 normal=0,-1,0 size=8,8 material=black emission=100cd/m2\n"
           "camera pinhole from=0,-%g,0 to=0,0,0 up=0,0,1 fov=%.12g resolution=16x64\n"
           "render integrator=path spp=16 depth=2\n",
           VR_TEST_DATA, d, fov);
  vr_render_result *r = render_text_models(scn, "chain.scn");
  double t = mean_y(r) / 100;
  vr_render_result_destroy(r);
  printf("# map_d (Sponza's chain mask): %.4f of the emitter through (0.516067)\n", t);
  assert_true(fabs(t - 0.516067) < 0.005);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_white_reference),
      cmocka_unit_test(test_colorchecker_round_trip),
      cmocka_unit_test(test_mip_footprint),
      cmocka_unit_test(test_alpha),
      cmocka_unit_test(test_normal_map),
      cmocka_unit_test(test_vertex_colours),
      cmocka_unit_test(test_map_d),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
