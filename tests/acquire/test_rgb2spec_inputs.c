/* vr-rgb2spec's checks of a photo once read (acquire/tools/rgb2spec_inputs.c):
 * refusal of transparent pixels, the note for an opaque alpha channel, and
 * the warnings for JPEG and for 16-bit photos decoded as sRGB by default, on
 * images read from real files (tests/data/images/README.md) and on images
 * whose fields are set by hand. */
#include "vr_test.h"
#include "rgb2spec_inputs.h"

#define IMAGES VR_TEST_DATA "/images/"

/* Runs rg_check_photo with its notes captured; returns the status. */
static vr_status check(const vr_capture *cap, const vr_capture_photo *p, const vr_image *img,
                       char *notes, size_t size, vr_error *err) {
  FILE *f = tmpfile();
  assert_non_null(f);
  vr_status st = rg_check_photo(cap, p, img, f, err);
  rewind(f);
  size_t n = fread(notes, 1, size - 1, f);
  notes[n] = '\0';
  fclose(f);
  return st;
}

static int count_lines(const char *s) {
  int n = 0;
  for (; *s; s++) n += *s == '\n';
  return n;
}

static vr_capture capture(void) {
  vr_capture c = {0};
  c.path = (char *)"/captures/manifest.txt";
  return c;
}

static vr_capture_photo photo(const char *path, long line) {
  vr_capture_photo p = {0};
  p.path = (char *)path;
  p.line = line;
  p.scale = 1;
  return p;
}

/* A real icon with 567 pixels below opaque (README): refused, the message
 * naming the file, the count and what to do. */
static void transparent_png_is_refused(void **state) {
  (void)state;
  vr_capture cap = capture();
  vr_capture_photo p = photo(IMAGES "gdalicon.png", 2);
  vr_image img;
  vr_error err = {0};
  assert_int_equal(vr_image_read(p.path, &img, &err), VR_OK);
  char notes[2048];
  assert_int_equal(check(&cap, &p, &img, notes, sizeof notes, &err), VR_E_ARG);
  assert_contains(err.message, "gdalicon.png");
  assert_contains(err.message, "567 of 1024 pixels are not fully opaque");
  assert_contains(err.message, "flatten the photo onto the scene");
  assert_contains(err.message, "remove its alpha channel");
  assert_string_equal(notes, "");
  vr_image_free(&img);
}

/* OpenEXR: the message says the colour is premultiplied by alpha. */
static void transparent_exr_says_premultiplied(void **state) {
  (void)state;
  vr_capture cap = capture();
  vr_capture_photo p = photo("/captures/hdr.exr", 4);
  vr_image img;
  vr_error err = {0};
  assert_int_equal(vr_image_alloc(&img, 4, 2, &err), VR_OK);
  img.format = VR_IMAGE_FORMAT_EXR;
  img.alpha = 1;
  img.transparent = 3;
  char notes[2048];
  assert_int_equal(check(&cap, &p, &img, notes, sizeof notes, &err), VR_E_ARG);
  assert_contains(err.message, "/captures/hdr.exr: 3 of 8 pixels are not fully opaque");
  assert_contains(err.message, "premultiplied by alpha");
  vr_image_free(&img);
}

/* An alpha channel with every pixel opaque: one note line, accepted. */
static void opaque_alpha_is_noted(void **state) {
  (void)state;
  vr_capture cap = capture();
  vr_capture_photo p = photo("/captures/d65.png", 2);
  vr_image img;
  vr_error err = {0};
  assert_int_equal(vr_image_alloc(&img, 4, 2, &err), VR_OK);
  img.format = VR_IMAGE_FORMAT_PNG;
  img.bit_depth = 8;
  img.alpha = 1;
  char notes[2048];
  assert_int_equal(check(&cap, &p, &img, notes, sizeof notes, &err), VR_OK);
  assert_string_equal(notes, "vr-rgb2spec: note: /captures/d65.png: has an alpha channel, every "
                             "pixel opaque: it is ignored\n");
  /* No notes stream: nothing written, same verdict. */
  assert_int_equal(rg_check_photo(&cap, &p, &img, NULL, &err), VR_OK);
  vr_image_free(&img);
}

/* A real camera JPEG: one warning line on lossy compression. */
static void camera_jpeg_warns(void **state) {
  (void)state;
  vr_capture cap = capture();
  vr_capture_photo p = photo(IMAGES "iphone4s_goexif.jpg", 3);
  vr_image img;
  vr_error err = {0};
  assert_int_equal(vr_image_read(p.path, &img, &err), VR_OK);
  char notes[2048];
  assert_int_equal(check(&cap, &p, &img, notes, sizeof notes, &err), VR_OK);
  assert_int_equal(count_lines(notes), 1);
  assert_contains(notes, "vr-rgb2spec: warning: " IMAGES "iphone4s_goexif.jpg: JPEG is lossy");
  assert_contains(notes, "chroma subsampling");
  assert_contains(notes, "a few pixels inside the patches");
  assert_contains(notes, "16-bit TIFF");
  assert_null(rg_encoding_hint(&cap, &p, &img)); /* 8 bits */
  vr_image_free(&img);
}

/* 16 bits, no encoding=, no tone curves: the warning names the manifest
 * line; each of the three conditions lifted silences it. */
static void sixteen_bit_encoding_hint(void **state) {
  (void)state;
  vr_capture cap = capture();
  vr_capture_photo p = photo("/captures/raw.tif", 7);
  vr_image img;
  vr_error err = {0};
  assert_int_equal(vr_image_alloc(&img, 4, 2, &err), VR_OK);
  img.format = VR_IMAGE_FORMAT_TIFF;
  img.bit_depth = 16;
  char notes[2048];
  assert_int_equal(check(&cap, &p, &img, notes, sizeof notes, &err), VR_OK);
  assert_int_equal(count_lines(notes), 1);
  assert_contains(notes, "vr-rgb2spec: warning: /captures/raw.tif: ");
  assert_contains(notes, "decoded as sRGB");
  assert_contains(notes, "usually linear");
  assert_contains(notes, "add encoding=linear");
  assert_contains(notes, "(/captures/manifest.txt:7)");
  const char *hint = rg_encoding_hint(&cap, &p, &img);
  assert_non_null(hint);
  assert_contains(notes, hint);

  p.encoding = 1; /* encoding=srgb said on purpose */
  assert_null(rg_encoding_hint(&cap, &p, &img));
  p.encoding = 2;
  assert_null(rg_encoding_hint(&cap, &p, &img));
  p.encoding = 0;
  cap.has_tone = true; /* decoded with the camera's curves instead */
  assert_null(rg_encoding_hint(&cap, &p, &img));
  assert_int_equal(check(&cap, &p, &img, notes, sizeof notes, &err), VR_OK);
  assert_string_equal(notes, "");
  cap.has_tone = false;
  img.bit_depth = 32; /* float: linear by default already */
  assert_null(rg_encoding_hint(&cap, &p, &img));
  vr_image_free(&img);
}

/* A plain 8-bit PNG: nothing to say. */
static void plain_png_is_silent(void **state) {
  (void)state;
  vr_capture cap = capture();
  vr_capture_photo p = photo("/captures/d65.png", 2);
  vr_image img;
  vr_error err = {0};
  assert_int_equal(vr_image_alloc(&img, 4, 2, &err), VR_OK);
  img.format = VR_IMAGE_FORMAT_PNG;
  img.bit_depth = 8;
  char notes[2048];
  assert_int_equal(check(&cap, &p, &img, notes, sizeof notes, &err), VR_OK);
  assert_string_equal(notes, "");
  assert_int_equal(rg_check_photo(NULL, &p, &img, NULL, &err), VR_E_ARG);
  vr_image_free(&img);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(transparent_png_is_refused),
      cmocka_unit_test(transparent_exr_says_premultiplied),
      cmocka_unit_test(opaque_alpha_is_noted),
      cmocka_unit_test(camera_jpeg_warns),
      cmocka_unit_test(sixteen_bit_encoding_hint),
      cmocka_unit_test(plain_png_is_silent),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
