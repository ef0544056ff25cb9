/* Capture manifests: the grammar, resolution of lights and references, and
 * errors that name the manifest, line and column. */
#include "vr_test.h"
#include "vr/colour.h"
#include "vr/manifest.h"

static vr_status parse(const char *text, vr_capture **c, vr_error *err) {
  return vr_capture_parse(text, strlen(text), "/photos/capture.txt", NULL, c, err);
}

static void good_manifest(void **state) {
  (void)state;
  vr_capture *c;
  vr_error err = {0};
  assert_int_equal(parse("# a capture\ncamera cie1931-srgb\ngrid 380 730 10\n"
                         "photo d65.png light=D65\nphoto a.png light=A scale=0.5 encoding=linear clip=0.95\n"
                         "chart grid=10,20,610,420\nregion wall rect=5,5,20,10\n", &c, &err), VR_OK);
  assert_int_equal(c->nphotos, 2);
  assert_string_equal(c->photos[0].path, "/photos/d65.png");
  /* CIE D65 at 560 nm is 100.0 by definition of its normalisation (CIE 015:2018 Table 5). */
  assert_near(vr_spectrum_eval(c->photos[0].light, 560, VR_INTERP_LINEAR), 100.0, 1e-9);
  assert_near(c->photos[1].scale, 0.5, 0);
  assert_int_equal(c->photos[1].encoding, 2);
  assert_int_equal(c->nregions, 25);
  assert_string_equal(c->regions[0].name, "patch-01");
  assert_non_null(c->regions[23].reference);
  assert_int_equal(c->regions[24].w, 20);
  assert_near(c->grid[0], 380, 0);
  assert_non_null(vr_capture_find_photo(c, "elsewhere/a.png"));
  assert_null(vr_capture_find_photo(c, "b.png"));
  vr_capture_destroy(c);
}

static void errors(void **state) {
  (void)state;
  vr_capture *c = NULL;
  vr_error err = {0};
  assert_int_not_equal(parse("photo d65.png light=D99x\n", &c, &err), VR_OK);
  assert_contains(err.message, "capture.txt:1:15");
  assert_contains(err.message, "unknown light");
  assert_int_not_equal(parse("photo d65.png\n", &c, &err), VR_OK);
  assert_contains(err.message, "no light=");
  assert_int_not_equal(parse("photo a.png light=A\nphoto a.png light=D65\n", &c, &err), VR_OK);
  assert_contains(err.message, "listed twice");
  assert_int_not_equal(parse("photo a.png light=A\nregion x rect=1,2,3\n", &c, &err), VR_OK);
  assert_contains(err.message, "capture.txt:2:10");
  assert_int_not_equal(parse("photo a.png light=A\nregion x label=3\n", &c, &err), VR_OK);
  assert_contains(err.message, "labels FILE");
  assert_int_not_equal(parse("photo a.png light=db:X\n", &c, &err), VR_OK);
  assert_contains(err.message, "--db");
  assert_int_not_equal(parse("phot a.png\n", &c, &err), VR_OK);
  assert_contains(err.message, "unknown statement");
  assert_int_not_equal(parse("camera cie1931-srgb\n", &c, &err), VR_OK);
  assert_contains(err.message, "no 'photo' lines");
  /* Found by fuzz_manifest: a repeated key leaked the first value. */
  assert_int_not_equal(parse("photo a.png light=A light=D65\n", &c, &err), VR_OK);
  assert_contains(err.message, "capture.txt:1:21");
  assert_contains(err.message, "twice");
  assert_int_not_equal(parse("photo a.png light=A scale=-1\n", &c, &err), VR_OK);
  assert_contains(err.message, "scale=-1");
  assert_null(c);
}

int main(void) {
  const struct CMUnitTest tests[] = {cmocka_unit_test(good_manifest), cmocka_unit_test(errors)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
