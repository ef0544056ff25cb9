/* The toolchain's own pipeline to the image (issue 32): photos under four
 * lights -> vr-rgb2spec --per-pixel --texture (the real tool, run here) ->
 * the database row and its spectral OpenEXR -> a textured rect in
 * vr_render_scene, lit by CIE D65 and seen head on.
 *
 * Outside references:
 *   - the photo under D65 (samples/photos/d65.png, made by the CIE 1931
 *     observer with sRGB primaries, exposure 0.9, manifest.txt): each
 *     region's mean colour, IEC 61966-2-1 decoded and divided by the
 *     exposure, is the colour the region's spectra must give under D65;
 *   - the white of the render is analytic: a point source of I cd at d m
 *     gives E = I / d^2 lx head on, a white Lambertian surface
 *     L = E / pi cd/m2, with D65's chromaticity (CIE 15:2004);
 *   - the bounds: every rendered region within Delta E00 1 of the photo
 *     (the just-noticeable difference, Sharma et al. 2005), and within
 *     0.25 of the texture's own colour: the region's mean spectrum in the
 *     EXR under D65 through the CIE 1931 observer (CIE 15:2004), the
 *     recovery's round trip without the renderer (the per-pixel texture,
 *     regularised pixel by pixel, is not the region's own fit, whose
 *     Delta E00 vr-rgb2spec --json reports and the test prints), so the
 *     rendered colour is no further from the photo than the texture's
 *     own colour is, plus 0.25 (the renderer's Monte Carlo noise at
 *     64 samples a pixel and its 400-700 nm range); measured: worst
 *     0.28 from the photo, 0.11 from the texture's own colours; where
 *     the photo clipped a channel (the cyan patch lies outside sRGB) the
 *     photo is no reference and the recovery's colour of that region
 *     (its rendered_rgb) is;
 *   - the hash: a texture file changed after the database recorded it
 *     (one byte appended) is refused, naming the file and both hashes. */
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
#include "vr/matdb.h"
#include "vr/spectral_exr.h"

static char dir[] = "/tmp/vr-spectex-test-XXXXXX";
static char dbpath[600], texpath[600], jsonpath[600];

static int setup(void **state) {
  (void)state;
  if (!mkdtemp(dir)) return -1;
  snprintf(dbpath, sizeof dbpath, "%s/m.db", dir);
  snprintf(texpath, sizeof texpath, "%s/tex.exr", dir);
  snprintf(jsonpath, sizeof jsonpath, "%s/rec.json", dir);
  char cmd[4096];
  const char *ph = VR_SOURCE_DIR "/samples/photos";
  snprintf(cmd, sizeof cmd,
           "VR_MATDB='%s' '%s' %s/d65.png %s/a.png %s/led.png %s/f11.png --per-pixel '%s' "
           "--texture photo-tex --json > '%s' 2> /dev/null",
           dbpath, VR_RGB2SPEC, ph, ph, ph, ph, texpath, jsonpath);
  return system(cmd) == 0 ? 0 : -1;
}

static int teardown(void **state) {
  (void)state;
  char cmd[700];
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
  return system(cmd) == 0 ? 0 : -1;
}

/* Renders the texture on a 1.6 x 1.2 m rect filling a W x H image, with a
 * 1e6 cd D65 point source 100 m away on the axis. */
static vr_render_result *render_tex(const char *material_opts, int W, int H, vr_status *st,
                                    vr_error *err) {
  char scn[1024];
  double d = 5, fov = 2 * atan(0.8 / d) * 180 / M_PI;
  snprintf(scn, sizeof scn,
           "material m db:photo-tex %s\n"
           "rect center=0,0,0 normal=0,-1,0 size=1.6,1.2 up=0,0,1 material=m\n"
           "camera pinhole from=0,-%g,0 to=0,0,0 up=0,0,1 fov=%.12g resolution=%dx%d\n"
           "light point position=0,-100,0 intensity=1e6cd\n"
           "render integrator=path spp=64 depth=2 sampler=sobol\n",
           material_opts, d, fov, W, H);
  vr_scene *s = parse_text(scn, "test.scn");
  vr_matdb *db = NULL;
  assert_int_equal(vr_matdb_open(dbpath, 0, &db, err), VR_OK);
  vr_render_options o;
  vr_render_options_default(&o);
  o.threads = 2;
  vr_render_result *r = NULL;
  *st = vr_render_scene(s, db, &o, &r, err);
  vr_matdb_close(db);
  vr_scene_destroy(s);
  return r;
}

/* A rectangle of the 640 x 480 photo (x, y, w, h). */
typedef struct region {
  const char *name;
  int x, y, w, h;
} region;

/* The recovery's report of region NAME under D65 (the first light of the
 * JSON): its Delta E00 (-1 when null: a clipped channel, the photo no
 * reference) and the camera RGB of its recovered spectrum (rendered_rgb,
 * with the exposure); false when the region is not in the report. */
static bool json_d65(const char *name, double *de, double rgb[3]) {
  FILE *f = fopen(jsonpath, "r");
  assert_non_null(f);
  static char buf[1 << 20];
  size_t n = fread(buf, 1, sizeof buf - 1, f);
  fclose(f);
  buf[n] = 0;
  char key[80];
  snprintf(key, sizeof key, "\"name\": \"%s\"", name);
  char *at = strstr(buf, key);
  char *pl = at ? strstr(at, "\"per_light\"") : NULL;
  char *rr = pl ? strstr(pl, "\"rendered_rgb\": [") : NULL;
  char *d = pl ? strstr(pl, "\"deltaE00\": ") : NULL;
  if (!rr || !d) return false;
  char *q = strchr(rr, '[') + 1;
  for (int c = 0; c < 3; c++) rgb[c] = strtod(q, &q), q += strspn(q, ", ");
  d = strchr(d, ':') + 2;
  *de = strncmp(d, "null", 4) ? strtod(d, NULL) : -1;
  return true;
}

static void test_round_trip(void **state) {
  (void)state;
  vr_error e = {0};
  vr_image photo;
  assert_int_equal(vr_image_read(VR_SOURCE_DIR "/samples/photos/d65.png", &photo, &e), VR_OK);
  assert_int_equal(photo.width, 640);
  vr_status st;
  int W = 320, H = 240; /* 2 x 2 texels a pixel */
  vr_render_result *r = render_tex("", W, H, &st, &e);
  if (st) fail_msg("%s", e.message);
  /* The manifest's six material regions and the chart's 24 patches (grid
   * 20,20,410,278: corners (20, 20) and (410, 278), 6 x 4 cells), each
   * read over its central half. */
  region reg[30] = {{"brick", 440, 30, 80, 60},    {"pine", 540, 30, 80, 60},
                    {"cotton", 440, 120, 80, 60},  {"carpet", 540, 120, 80, 60},
                    {"concrete", 440, 210, 80, 60}, {"paint", 540, 210, 80, 60}};
  char names[24][24];
  for (int k = 0; k < 24; k++) {
    double pw = (410.0 - 20) / 6, ph = (278.0 - 20) / 4;
    snprintf(names[k], sizeof names[k], "patch-%02d", k + 1);
    reg[6 + k] = (region){names[k], (int)(20 + (k % 6) * pw), (int)(20 + (k / 6) * ph), (int)pw, (int)ph};
  }
  double Yw = 1e6 / (M_PI * 100 * 100), white[3] = {0.95047 * Yw, Yw, 1.08883 * Yw};
  double wd65[3] = {0.95047, 1, 1.08883};
  vr_spectral_image tex;
  assert_int_equal(vr_spectral_exr_read(texpath, &tex, NULL, &e), VR_OK);
  assert_int_equal(tex.width, 640);
  vr_spectrum *d65 = vr_illuminant("D65", &e);
  double wtex[3];
  vr_xyz_white(d65, VR_CIE1931_2DEG, wtex);
  double worst = 0, worst_tex = 0;
  for (int k = 0; k < 30; k++) {
    const region *g = &reg[k];
    int x0 = g->x + g->w / 4, x1 = g->x + 3 * g->w / 4, y0 = g->y + g->h / 4, y1 = g->y + 3 * g->h / 4;
    double lin[3] = {0, 0, 0}, xyz[3] = {0, 0, 0}, spec[64] = {0};
    int np = 0, nr = 0;
    for (int y = y0; y < y1; y++)
      for (int x = x0; x < x1; x++, np++) {
        for (int c = 0; c < 3; c++) lin[c] += vr_srgb_decode(photo.data[(y * 640 + x) * 3 + c]) / 0.9;
        for (size_t b = 0; b < tex.nbands && b < 64; b++)
          spec[b] += tex.data[((size_t)y * 640 + x) * tex.nbands + b];
      }
    for (int y = y0 / 2; y < y1 / 2; y++)
      for (int x = x0 / 2; x < x1 / 2; x++, nr++)
        for (int c = 0; c < 3; c++) xyz[c] += r->xyz[((size_t)y * W + x) * 3 + c];
    double own = -1, rec[3] = {0, 0, 0}, pxyz[3], want[3], got[3], txyz[3], tlab[3];
    assert_true(json_d65(g->name, &own, rec));
    for (int c = 0; c < 3; c++) lin[c] /= np, xyz[c] /= nr;
    for (size_t b = 0; b < tex.nbands; b++) spec[b] /= np;
    vr_spectrum *ts = vr_spectrum_create(tex.nbands, tex.wavelengths_nm, spec, &e);
    assert_non_null(ts);
    vr_xyz_reflectance(ts, d65, VR_CIE1931_2DEG, txyz);
    vr_spectrum_destroy(ts);
    vr_xyz_to_lab(txyz, wtex, tlab);
    /* A clipped photo is no reference: the recovery's own colour is. */
    bool clipped = own < 0;
    for (int c = 0; c < 3 && clipped; c++) lin[c] = rec[c] / 0.9;
    vr_srgb_linear_to_xyz(lin, pxyz);
    vr_xyz_to_lab(pxyz, wd65, want);
    vr_xyz_to_lab(xyz, white, got);
    double de = vr_delta_e2000(want, got), dt = vr_delta_e2000(tlab, got), dtp = vr_delta_e2000(tlab, want);
    printf("# %-9s rendered vs %s %.3f, vs the texture's own colour %.3f (texture vs %s %.3f; the region's "
           "fit under D65 %.3f)\n", g->name, clipped ? "recovery (photo clipped)" : "photo", de, dt,
           clipped ? "recovery" : "photo", dtp, own);
    if (!(de < 1.0)) fail_msg("%s: Delta E00 %.3f from the photo", g->name, de);
    if (!(dt < 0.25)) fail_msg("%s: Delta E00 %.3f from the texture's own colour", g->name, dt);
    if (!(de <= dtp + 0.25))
      fail_msg("%s: Delta E00 %.3f from the %s, the texture's own %.3f", g->name, de,
               clipped ? "recovery" : "photo", dtp);
    worst_tex = fmax(worst_tex, dt);
    worst = fmax(worst, de);
  }
  printf("# worst %.3f from the photo, %.3f from the texture's own colours\n", worst, worst_tex);
  vr_spectrum_destroy(d65);
  vr_spectral_image_free(&tex);
  vr_render_result_destroy(r);
  vr_image_free(&photo);
}

static void test_changed_file_refused(void **state) {
  (void)state;
  FILE *f = fopen(texpath, "ab");
  assert_non_null(f);
  fputc(0, f);
  fclose(f);
  vr_error e = {0};
  vr_status st;
  vr_render_result *r = render_tex("", 32, 24, &st, &e);
  assert_null(r);
  assert_int_not_equal(st, VR_OK);
  assert_non_null(strstr(e.message, "tex.exr"));
  assert_non_null(strstr(e.message, "SHA-256"));
  assert_non_null(strstr(e.message, "test.scn:1:"));
  /* texture=none: the material's mean spectrum, the file not read. */
  r = render_tex("texture=none", 32, 24, &st, &e);
  if (st) fail_msg("%s", e.message);
  vr_render_result_destroy(r);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_round_trip),
      cmocka_unit_test(test_changed_file_refused),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
