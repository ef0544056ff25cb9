/* Radiance pictures (image/src/rgbe.c, vr/rgbe.h) against Radiance itself:
 *   - three pictures Radiance 6.1 wrote (tests/data/radiance, README.md
 *     there): a ramp from `pvalue -r` (run-length encoded rows of 24, runs
 *     and literal chunks, a blank-padded resolution line), the
 *     same through `pfilt -1 -e 2` (EXPOSURE=2), and an angular fisheye
 *     from `rpict -vta` (VIEW=, PRIMARIES=).  Each pixel read must equal
 *     what Radiance's own `pvalue` printed for it (its 4 significant
 *     digits: within 5e-4 relative, or 1e-6 absolute near zero), the
 *     exposure and view as the header says;
 *   - our writer: a picture written and read back gives every pixel's
 *     largest component within 2^-8 relative (an 8-bit mantissa, Ward
 *     1991) and the others within 2^-8 of that largest; rows of 8 or more
 *     pixels are run-length encoded (smaller than 4 bytes a pixel for a
 *     flat image), narrower rows flat;
 *   - refusals: a NaN or infinite pixel (nothing written), another FORMAT,
 *     another orientation, the old run-length encoding, a cut file, no
 *     #?RADIANCE line, each naming the file and the line or scanline. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>

#include "vr/rgbe.h"

static char g_path[256];

static void data_path(char *out, size_t n, const char *name) {
  snprintf(out, n, "%s/radiance/%s", VR_TEST_DATA, name);
}

/* Every line of pvalue's "x y R G B" (y from the bottom) against img. */
static void against_pvalue(const vr_image *img, const char *txt, double scale) {
  char path[512];
  data_path(path, sizeof path, txt);
  FILE *f = fopen(path, "r");
  assert_non_null(f);
  int x, y, n = 0;
  double v[3];
  while (fscanf(f, "%d %d %lf %lf %lf", &x, &y, &v[0], &v[1], &v[2]) == 5) {
    assert_true(x >= 0 && x < img->width && y >= 0 && y < img->height);
    const float *p = img->data + 3 * ((size_t)(img->height - 1 - y) * (size_t)img->width + (size_t)x);
    for (int c = 0; c < 3; c++) {
      double got = p[c] * scale;
      if (!(fabs(got - v[c]) <= 5e-4 * fabs(v[c]) + 1e-6))
        fail_msg("%s: pixel (%d, %d) channel %d: %.6g, pvalue %.6g", txt, x, y, c, got, v[c]);
    }
    n++;
  }
  fclose(f);
  assert_int_equal(n, img->width * img->height);
}

static void test_radiance_wrote_these(void **state) {
  (void)state;
  char path[512];
  vr_image img;
  vr_rgbe_info info;
  data_path(path, sizeof path, "ramp.hdr");
  assert_int_equal(vr_rgbe_read(path, &img, &info, NULL), VR_OK);
  assert_int_equal(img.width, 24);
  assert_int_equal(img.height, 3);
  assert_true(info.exposure == 1.0 && !info.has_primaries && !info.view[0]);
  against_pvalue(&img, "ramp.pvalue.txt", 1.0);
  vr_image_free(&img);

  data_path(path, sizeof path, "ramp_e2.hdr");
  assert_int_equal(vr_rgbe_read(path, &img, &info, NULL), VR_OK);
  assert_true(info.exposure == 2.0);
  against_pvalue(&img, "ramp_e2.pvalue.txt", 1.0);          /* pvalue without -o: as stored */
  against_pvalue(&img, "ramp.pvalue.txt", 1.0 / info.exposure); /* the exposure undone */
  vr_image_free(&img);

  data_path(path, sizeof path, "rpict_vta.hdr");
  assert_int_equal(vr_rgbe_read(path, &img, &info, NULL), VR_OK);
  assert_int_equal(img.width, 32);
  assert_string_equal(info.view, " -vta -vp 0 0 0 -vd 0 1 0 -vu 0 0 1 -vh 180 -vv 180 -vo 0 -va 0 -vs 0 -vl 0");
  assert_true(info.has_primaries && info.primaries[0] == 0.64 && info.primaries[7] == 0.3333);
  against_pvalue(&img, "rpict_vta.pvalue.txt", 1.0);
  vr_image_free(&img);
}

static void write_read(const vr_image *src, vr_image *back, long *bytes) {
  vr_rgbe_header h = {.exposure = 1.0, .view = " -vtv -vh 60 -vv 45"};
  assert_int_equal(vr_rgbe_write(g_path, src, &h, NULL), VR_OK);
  struct stat sb;
  assert_int_equal(stat(g_path, &sb), 0);
  *bytes = (long)sb.st_size;
  vr_rgbe_info info;
  assert_int_equal(vr_rgbe_read(g_path, back, &info, NULL), VR_OK);
  assert_string_equal(info.view, " -vtv -vh 60 -vv 45");
}

static void test_round_trip(void **state) {
  (void)state;
  for (int w = 1; w <= 40; w += 13) { /* 1, 14, 27, 40: flat and run-length rows */
    vr_image img;
    assert_int_equal(vr_image_alloc(&img, w, 5, NULL), VR_OK);
    unsigned s = 7;
    for (size_t i = 0; i < (size_t)w * 5 * 3; i++) {
      s = s * 1103515245u + 12345u;
      double e = (double)(s >> 8 & 0xFFFF) / 65536.0 * 40 - 20; /* 1e-6 .. 1e6 */
      img.data[i] = (float)pow(10, e / 6.67);
    }
    img.data[0] = 0.0f, img.data[1] = -3.0f; /* a black channel, a negative one (as 0) */
    vr_image back;
    long bytes;
    write_read(&img, &back, &bytes);
    assert_int_equal(back.width, w);
    for (size_t p = 0; p < (size_t)w * 5; p++) {
      const float *a = img.data + 3 * p, *b = back.data + 3 * p;
      double m = fmax(fmax(a[0], a[1]), a[2]);
      for (int c = 0; c < 3; c++) {
        double want = a[c] > 0 ? a[c] : 0.0;
        if (!(fabs(b[c] - want) <= 0x1p-8 * m))
          fail_msg("width %d, pixel %zu, channel %d: %.7g back as %.7g", w, p, c, want, b[c]);
      }
    }
    vr_image_free(&img);
    vr_image_free(&back);
  }
  /* A flat image of 64 x 4: each row's four components in runs of 64, a
   * few bytes a row, not 256. */
  vr_image img, back;
  assert_int_equal(vr_image_alloc(&img, 64, 4, NULL), VR_OK);
  for (size_t i = 0; i < 64 * 4 * 3; i++) img.data[i] = 0.25f;
  long bytes;
  write_read(&img, &back, &bytes);
  assert_true(bytes < 200 + 4 * 12); /* header + 4 x (4 + 4 x 2) */
  assert_true(back.data[100] == 0.2509765625f); /* (128 + 0.5) 2^-9: Ward's decode */
  vr_image_free(&img);
  vr_image_free(&back);
}

static void write_bytes(const char *text, size_t n) {
  FILE *f = fopen(g_path, "wb");
  assert_non_null(f);
  fwrite(text, 1, n, f);
  fclose(f);
}

static void expect_refused(const char *what, const char *needle) {
  vr_image img;
  vr_error err = {0};
  if (vr_rgbe_read(g_path, &img, NULL, &err) == VR_OK) {
    vr_image_free(&img);
    fail_msg("%s: read, not refused", what);
  }
  if (!strstr(err.message, needle) || !strstr(err.message, g_path))
    fail_msg("%s: message \"%s\" does not name the file and \"%s\"", what, err.message, needle);
}

static void test_refusals(void **state) {
  (void)state;
  vr_image img;
  assert_int_equal(vr_image_alloc(&img, 4, 2, NULL), VR_OK);
  memset(img.data, 0, 4 * 2 * 3 * sizeof(float));
  img.data[3 * 5 + 1] = NAN;
  unlink(g_path);
  vr_error err = {0};
  assert_int_equal(vr_rgbe_write(g_path, &img, NULL, &err), VR_E_RANGE);
  assert_non_null(strstr(err.message, "pixel (1, 1)"));
  assert_int_not_equal(access(g_path, F_OK), 0); /* nothing written */
  img.data[3 * 5 + 1] = INFINITY;
  assert_int_equal(vr_rgbe_write(g_path, &img, NULL, &err), VR_E_RANGE);
  vr_image_free(&img);

  /* Each file's bytes (the last pixels raw), what it is, what the message must say. */
#define CASE(bytes, what, needle) {bytes, sizeof bytes - 1, what, needle}
  static const struct {
    const char *bytes;
    size_t n;
    const char *what, *needle;
  } bad[] = {
      CASE("#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 1 +X 1\n\x80\x80\x80\x81", "XYZE",
           ":2: FORMAT=32-bit_rle_xyze"),
      CASE("#?RADIANCE\n\n+Y 1 +X 1\n\x80\x80\x80\x81", "orientation", ":3: resolution"),
      CASE("#?RADIANCE\n\n-Y 1 +X 2\n\x80\x80\x80\x81\x01\x01\x01\x01", "old RLE",
           "scanline 0: old-style run-length"),
      CASE("#?RADIANCE\n\n-Y 2 +X 1\n\x80\x80\x80\x81", "cut", "scanline 1: the file ends here"),
      CASE("#?RADIANCE\n\n-Y 1 +X 8\n\x02\x02\x00\x08\xff\x01", "run past the row",
           "scanline 0: a run goes past"),
      CASE("P6\n1 1\n255\n\0\0\0", "not a picture", ":1: not a Radiance picture"),
      CASE("#?RADIANCE\nEXPOSURE=-2\n\n-Y 1 +X 1\n\x80\x80\x80\x81", "exposure",
           ":2: EXPOSURE=-2"),
      CASE("#?RADIANCE\n\n-Y 60000 +X 60000\n\x80\x80\x80\x81", "a huge header",
           ":3: a picture of 60000 x 60000 pixels"),
  };
#undef CASE
  for (size_t k = 0; k < sizeof bad / sizeof *bad; k++) {
    write_bytes(bad[k].bytes, bad[k].n);
    expect_refused(bad[k].what, bad[k].needle);
  }
  unlink(g_path);
}

int main(void) {
  snprintf(g_path, sizeof g_path, "/tmp/vr_test_rgbe_%d.hdr", (int)getpid());
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_radiance_wrote_these),
      cmocka_unit_test(test_round_trip),
      cmocka_unit_test(test_refusals),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
