/* The colour attributes of the EXR writers (vr/image.h vr_exr_colour,
 * vr_image_write_exr_with, vr_spectral_exr_write_with), read back with the
 * OpenEXR core reader itself, not ours.
 *
 * Expected values:
 * - chromaticities of linear sRGB: ITU-R BT.709-6, items 1.3 and 1.4:
 *   red 0.640, 0.330; green 0.300, 0.600; blue 0.150, 0.060; white (D65)
 *   0.3127, 0.3290 (the primaries and white IEC 61966-2-1 adopts);
 * - whiteLuminance: the OpenEXR "Standard Optional Attributes" define it as
 *   the luminance in cd/m² of RGB (1, 1, 1), and tie it with the
 *   chromaticities to CIE XYZ; checked here through that definition: the
 *   XYZ of RGB (1,1,1) from the file's chromaticities has Y = 1 for our
 *   white luminance of 1, and the sRGB matrix of IEC 61966-2-1 (row Y:
 *   0.2126, 0.7152, 0.0722) rebuilt from the chromaticities;
 * - emissiveUnits of spectral radiance: "W.m^-2.sr^-1", as the writer of
 *   the spectral layout's authors writes it (ART's ArfOpenEXRWrapper:
 *   header.insert("emissiveUnits", Imf::StringAttribute("W.m^-2.sr^-1")))
 *   and pbrt-v4's spectral film. */
#include "../acquire/image_test_util.h"

#include <openexr.h>

#include "vr/spectral_exr.h"

static const float BT709[8] = {0.640f, 0.330f, 0.300f, 0.600f, 0.150f, 0.060f, 0.3127f, 0.3290f};

/* The file's chromaticities, whiteLuminance and exposure (NAN when absent),
 * read with the OpenEXR core API. */
typedef struct attrs {
  int has_chroma;
  exr_attr_chromaticities_t chroma;
  float white_luminance, exposure;
  char units[64];
} attrs;

static attrs read_attrs(const char *path) {
  attrs a = {.white_luminance = NAN, .exposure = NAN};
  exr_context_t ctxt = NULL;
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  assert_int_equal(exr_start_read(&ctxt, path, &init), EXR_ERR_SUCCESS);
  a.has_chroma = exr_attr_get_chromaticities(ctxt, 0, "chromaticities", &a.chroma) ==
                 EXR_ERR_SUCCESS;
  float v;
  if (exr_attr_get_float(ctxt, 0, "whiteLuminance", &v) == EXR_ERR_SUCCESS) a.white_luminance = v;
  if (exr_attr_get_float(ctxt, 0, "exposure", &v) == EXR_ERR_SUCCESS) a.exposure = v;
  int32_t len = 0;
  const char *s = NULL;
  if (exr_attr_get_string(ctxt, 0, "emissiveUnits", &len, &s) == EXR_ERR_SUCCESS)
    snprintf(a.units, sizeof a.units, "%s", s);
  assert_int_equal(exr_finish(&ctxt), EXR_ERR_SUCCESS);
  return a;
}

static void expect_bt709(const attrs *a) {
  assert_true(a->has_chroma);
  const float got[8] = {a->chroma.red_x,  a->chroma.red_y,  a->chroma.green_x, a->chroma.green_y,
                        a->chroma.blue_x, a->chroma.blue_y, a->chroma.white_x, a->chroma.white_y};
  for (int i = 0; i < 8; i++) assert_near(got[i], BT709[i], 1e-7);
}

/* Row Y of the RGB -> XYZ matrix the chromaticities and white luminance
 * define (the construction of SMPTE RP 177, as OpenEXR's RGBtoXYZ does):
 * columns C_i = S_i (x_i/y_i, 1, z_i/y_i), S solving sum C_i = white XYZ
 * with Y_white = whiteLuminance. */
static void rgb_to_y(const attrs *a, double y_row[3]) {
  const exr_attr_chromaticities_t *c = &a->chroma;
  double xs[3] = {c->red_x, c->green_x, c->blue_x}, ys[3] = {c->red_y, c->green_y, c->blue_y};
  double M[3][3];
  for (int i = 0; i < 3; i++) {
    M[0][i] = xs[i] / ys[i];
    M[1][i] = 1.0;
    M[2][i] = (1 - xs[i] - ys[i]) / ys[i];
  }
  double Yw = a->white_luminance;
  double W[3] = {c->white_x / c->white_y * Yw, Yw, (1 - c->white_x - c->white_y) / c->white_y * Yw};
  /* Cramer's rule for M S = W. */
  double det = M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1]) -
               M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0]) +
               M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0]);
  for (int k = 0; k < 3; k++) {
    double A[3][3];
    memcpy(A, M, sizeof A);
    for (int r = 0; r < 3; r++) A[r][k] = W[r];
    double dk = A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) -
                A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) +
                A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]);
    y_row[k] = dk / det; /* M[1][k] = 1 */
  }
}

static void rgb_exr_has_the_attributes(void **state) {
  (void)state;
  vr_image img;
  vr_error err = {0};
  assert_int_equal(vr_image_alloc(&img, 3, 2, &err), VR_OK);
  for (int i = 0; i < 18; i++) img.data[i] = 100.0f * (float)i;
  const char *path = in_dir("colour.exr");
  vr_exr_colour c = vr_exr_colour_srgb(1.0, -6.643856);
  assert_int_equal(vr_image_write_exr_with(path, &img, &c, &err), VR_OK);
  attrs a = read_attrs(path);
  expect_bt709(&a);
  assert_near(a.white_luminance, 1.0, 0);
  assert_near(a.exposure, -6.643856, 1e-6);
  double y[3];
  rgb_to_y(&a, y);
  print_message("  Y row from the file's chromaticities: %.4f %.4f %.4f (sum %.6f)\n", y[0], y[1],
                y[2], y[0] + y[1] + y[2]);
  assert_near(y[0], 0.2126, 5e-5);
  assert_near(y[1], 0.7152, 5e-5);
  assert_near(y[2], 0.0722, 5e-5);
  assert_near(y[0] + y[1] + y[2], 1.0, 1e-6);
  /* The pixels are unchanged and our reader still reads the file. */
  vr_image back;
  assert_int_equal(vr_image_read(path, &back, &err), VR_OK);
  for (int i = 0; i < 18; i++) assert_near(back.data[i], img.data[i], 0);
  vr_image_free(&back);

  /* Without colour (and through vr_image_write_exr): no attribute. */
  path = in_dir("plain.exr");
  assert_int_equal(vr_image_write_exr(path, &img, &err), VR_OK);
  a = read_attrs(path);
  assert_false(a.has_chroma);
  assert_true(isnan(a.white_luminance) && isnan(a.exposure));
  /* whiteLuminance 0 and no exposure: chromaticities alone. */
  c = vr_exr_colour_srgb(0.0, 0.0);
  c.has_exposure = 0;
  assert_int_equal(vr_image_write_exr_with(path, &img, &c, &err), VR_OK);
  a = read_attrs(path);
  expect_bt709(&a);
  assert_true(isnan(a.white_luminance) && isnan(a.exposure));
  vr_image_free(&img);
}

static void spectral_exr_units_and_colour(void **state) {
  (void)state;
  static const double wl[2] = {405.0, 695.0};
  vr_spectral_image sp;
  vr_image rgb;
  vr_error err = {0};
  assert_int_equal(vr_spectral_image_alloc(&sp, 2, 2, 2, wl, VR_SPECTRAL_EMISSIVE, &err), VR_OK);
  assert_int_equal(vr_image_alloc(&rgb, 2, 2, &err), VR_OK);
  assert_string_equal(VR_SPECTRAL_EMISSIVE_UNITS, "W.m^-2.sr^-1");
  const char *path = in_dir("colour.spectral.exr");
  vr_exr_colour c = vr_exr_colour_srgb(1.0, -4.5);
  assert_int_equal(
      vr_spectral_exr_write_with(path, &sp, &rgb, VR_SPECTRAL_EMISSIVE_UNITS, &c, &err), VR_OK);
  attrs a = read_attrs(path);
  assert_string_equal(a.units, "W.m^-2.sr^-1");
  expect_bt709(&a);
  assert_near(a.white_luminance, 1.0, 0);
  assert_near(a.exposure, -4.5, 0);
  vr_spectral_image back;
  assert_int_equal(vr_spectral_exr_read(path, &back, NULL, &err), VR_OK);
  assert_int_equal(back.nbands, 2);
  vr_spectral_image_free(&back);

  /* Colour attributes describe the R, G, B channels: none, refused. */
  const char *none = in_dir("no_rgb.spectral.exr");
  assert_int_equal(vr_spectral_exr_write_with(none, &sp, NULL, "W.m^-2.sr^-1", &c, &err),
                   VR_E_ARG);
  assert_non_null(strstr(err.message, "R, G, B"));
  assert_int_equal(access(none, F_OK), -1);
  vr_spectral_image_free(&sp);
  vr_image_free(&rgb);
}

static vr_status zero_rows(void *user, int thread, int y0, int y1, float *spectra, float *rgb,
                           uint32_t *flags, vr_error *err) {
  (void)user, (void)thread, (void)spectra, (void)rgb, (void)flags, (void)err, (void)y0, (void)y1;
  return VR_OK;
}

static void bad_colour_is_refused(void **state) {
  (void)state;
  vr_image img;
  vr_error err = {0};
  assert_int_equal(vr_image_alloc(&img, 1, 1, &err), VR_OK);
  const char *path = in_dir("bad.exr");
  vr_exr_colour c = vr_exr_colour_srgb(1.0, 0.0);
  c.chromaticities[3] = 1.5f;
  assert_int_equal(vr_image_write_exr_with(path, &img, &c, &err), VR_E_ARG);
  assert_non_null(strstr(err.message, "green y = 1.5"));
  c = vr_exr_colour_srgb(1.0, 0.0);
  c.chromaticities[7] = 0.0f;
  assert_int_equal(vr_image_write_exr_with(path, &img, &c, &err), VR_E_ARG);
  assert_non_null(strstr(err.message, "white y = 0"));
  c = vr_exr_colour_srgb(-1.0, 0.0);
  assert_int_equal(vr_image_write_exr_with(path, &img, &c, &err), VR_E_ARG);
  assert_non_null(strstr(err.message, "whiteLuminance"));
  c = vr_exr_colour_srgb(1.0, NAN);
  assert_int_equal(vr_image_write_exr_with(path, &img, &c, &err), VR_E_ARG);
  assert_non_null(strstr(err.message, "exposure"));
  assert_int_equal(access(path, F_OK), -1);

  /* A streaming layout's string attribute may not take a colour
   * attribute's name. */
  static const double wl[1] = {550.0};
  static const char *const names[1] = {"whiteLuminance"}, *const values[1] = {"1"};
  vr_spectral_exr_layout L = {.width = 1, .height = 1, .nbands = 1, .wavelengths_nm = wl,
                              .kind = VR_SPECTRAL_EMISSIVE, .rgb = 1, .nattrs = 1,
                              .attr_names = names, .attr_values = values, .threads = 1};
  assert_int_equal(vr_spectral_exr_write_rows(path, &L, zero_rows, NULL, &err), VR_E_ARG);
  assert_non_null(strstr(err.message, "colour attribute"));
  /* Nor a layout give colour without R, G, B. */
  vr_exr_colour ok = vr_exr_colour_srgb(1.0, 0.0);
  L.nattrs = 0, L.rgb = 0, L.colour = &ok;
  assert_int_equal(vr_spectral_exr_write_rows(path, &L, zero_rows, NULL, &err), VR_E_ARG);
  assert_non_null(strstr(err.message, "layout.colour"));
  assert_int_equal(access(path, F_OK), -1);
  vr_image_free(&img);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(rgb_exr_has_the_attributes),
      cmocka_unit_test(spectral_exr_units_and_colour),
      cmocka_unit_test(bad_colour_is_refused),
  };
  return cmocka_run_group_tests(tests, make_test_dir, remove_test_dir);
}
