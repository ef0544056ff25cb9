/* Image I/O of acquire/ on real OpenCV and OpenEXR: round trips through every
 * format, files made by another program (PNGs built byte by byte with
 * Python's zlib, expected values stated next to them), region statistics
 * against hand-computed values, and every way a file can be bad. */
#include "image_test_util.h"

#include <stdint.h>

/* 4 x 2, 8-bit greyscale (PNG colour type 0), rows {0, 1, 1, 2} and
 * {0, 2, 2, 255}; written by Python 3 (struct + zlib.compress). */
static const unsigned char k_grey8_png[75] = {
    0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52,
    0x00, 0x00, 0x00, 0x04, 0x00, 0x00, 0x00, 0x02, 0x08, 0x00, 0x00, 0x00, 0x00, 0x5a, 0xc3, 0x22,
    0xbf, 0x00, 0x00, 0x00, 0x12, 0x49, 0x44, 0x41, 0x54, 0x78, 0xda, 0x63, 0x60, 0x60, 0x64, 0x64,
    0x62, 0x60, 0x60, 0x62, 0xfa, 0x0f, 0x00, 0x01, 0x2e, 0x01, 0x08, 0x51, 0x56, 0x71, 0x14, 0x00,
    0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82,
};
/* 2 x 1, 16-bit greyscale, values 0x1234 = 4660 and 65535; same origin. */
static const unsigned char k_grey16_png[70] = {
    0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52,
    0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x01, 0x10, 0x00, 0x00, 0x00, 0x00, 0x81, 0xd9, 0xfc,
    0x15, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x44, 0x41, 0x54, 0x78, 0xda, 0x63, 0x10, 0x32, 0xf9, 0xff,
    0x1f, 0x00, 0x03, 0xe6, 0x02, 0x45, 0xf1, 0x1c, 0x84, 0x65, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45,
    0x4e, 0x44, 0xae, 0x42, 0x60, 0x82,
};
/* 2 x 1, 8-bit RGBA (colour type 6): (10, 20, 30, alpha 0) and
 * (200, 100, 50, alpha 255); same origin. */
static const unsigned char k_rgba8_png[74] = {
    0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52,
    0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x01, 0x08, 0x06, 0x00, 0x00, 0x00, 0xf4, 0x22, 0x7f,
    0x8a, 0x00, 0x00, 0x00, 0x11, 0x49, 0x44, 0x41, 0x54, 0x78, 0xda, 0x63, 0xe0, 0x12, 0x91, 0x63,
    0x38, 0x91, 0x62, 0xf4, 0x1f, 0x00, 0x07, 0x48, 0x02, 0x9a, 0xb2, 0xfa, 0xc3, 0xe2, 0x00, 0x00,
    0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82,
};

static void round_trip_exact(const char *name, int bits, int top, int expect_depth) {
  vr_image img, back;
  vr_error err = {0};
  make_coded_image(&img, 37, 23, top);
  const char *path = in_dir(name);
  assert_int_equal(vr_image_write(path, &img, bits, &err), VR_OK);
  assert_int_equal(vr_image_read(path, &back, &err), VR_OK);
  assert_int_equal(back.channels, 3);
  assert_int_equal(back.bit_depth, expect_depth);
  /* Codes k/top stored as float come back as the same float k/top. */
  assert_near(max_abs_diff(&img, &back), 0.0, 0.0);
  vr_image_free(&img);
  vr_image_free(&back);
}

static void png8_round_trip(void **state) {
  (void)state;
  round_trip_exact("a8.png", 8, 255, 8);
}

static void png16_round_trip(void **state) {
  (void)state;
  round_trip_exact("a16.png", 16, 65535, 16);
}

static void tiff_round_trips(void **state) {
  (void)state;
  round_trip_exact("a16.tif", 16, 65535, 16);
  round_trip_exact("a8.tiff", 8, 255, 8);
}

/* Quantisation as documented in vr/image.h: clamp to [0,1], round half up.
 * Values chosen so that v*255 is exact in binary: 0.5 -> 127.5 -> 128,
 * 0.25 -> 63.75 -> 64, 0.125 -> 31.875 -> 32; below 0 -> 0, above 1 -> 255. */
static void png_quantisation(void **state) {
  (void)state;
  vr_image img, back;
  vr_error err = {0};
  assert_int_equal(vr_image_alloc(&img, 2, 1, &err), VR_OK);
  const float in[6] = {0.5f, 0.25f, 0.125f, -0.3f, 1.7f, 1.0f};
  const double want8[6] = {128, 64, 32, 0, 255, 255};
  memcpy(img.data, in, sizeof in);
  assert_int_equal(vr_image_write_png(in_dir("q.png"), &img, 8, &err), VR_OK);
  assert_int_equal(vr_image_read(in_dir("q.png"), &back, &err), VR_OK);
  for (int i = 0; i < 6; i++) assert_near(back.data[i] * 255.0, want8[i], 1e-4);
  vr_image_free(&back);
  /* 16 bits: 0.5 * 65535 = 32767.5 -> 32768. */
  assert_int_equal(vr_image_write_png(in_dir("q16.png"), &img, 16, &err), VR_OK);
  assert_int_equal(vr_image_read(in_dir("q16.png"), &back, &err), VR_OK);
  assert_near(back.data[0] * 65535.0, 32768.0, 1e-2);
  vr_image_free(&back);
  vr_image_free(&img);
}

/* JPEG is lossy.  Flat 16 x 16 blocks (one 4:2:0 MCU each) at quality 95
 * carry only DC terms, so the 4 x 4 centre of each block comes back within
 * 2/255 (measured: 1/255 at most, libjpeg-turbo 2.1 of Debian 12).  Near the
 * edges between saturated blocks, chroma subsampling (libjpeg's default
 * 4:2:0, which OpenCV 4.6 cannot change) costs up to 80/255, but the mean
 * over the whole image stays within 0.5/255 (measured 0.09/255). */
static void jpeg_round_trip(void **state) {
  (void)state;
  vr_image img, back;
  vr_error err = {0};
  assert_int_equal(vr_image_alloc(&img, 64, 32, &err), VR_OK);
  for (int y = 0; y < 32; y++)
    for (int x = 0; x < 64; x++) {
      int b = (x / 16) + 4 * (y / 16);
      float *p = px(&img, x, y);
      p[0] = (float)((b * 37) % 256) / 255.0f;
      p[1] = (float)((b * 91 + 40) % 256) / 255.0f;
      p[2] = (float)((b * 53 + 100) % 256) / 255.0f;
    }
  const char *path = in_dir("a.jpg");
  assert_int_equal(vr_image_write(path, &img, 8, &err), VR_OK);
  assert_int_equal(vr_image_read(path, &back, &err), VR_OK);
  assert_int_equal(back.bit_depth, 8);
  for (int b = 0; b < 8; b++) {
    int x0 = (b % 4) * 16 + 6, y0 = (b / 4) * 16 + 6;
    double want[3], got[3];
    assert_int_equal(vr_image_rect_mean(&img, x0, y0, 4, 4, want, NULL, NULL, 2, &err), VR_OK);
    assert_int_equal(vr_image_rect_mean(&back, x0, y0, 4, 4, got, NULL, NULL, 2, &err), VR_OK);
    for (int c = 0; c < 3; c++) assert_near(got[c], want[c], 2.0 / 255);
  }
  double all_in[3], all_out[3];
  assert_int_equal(vr_image_rect_mean(&img, 0, 0, 64, 32, all_in, NULL, NULL, 2, &err), VR_OK);
  assert_int_equal(vr_image_rect_mean(&back, 0, 0, 64, 32, all_out, NULL, NULL, 2, &err), VR_OK);
  for (int c = 0; c < 3; c++) assert_near(all_out[c], all_in[c], 0.5 / 255);
  /* 16-bit JPEG does not exist. */
  assert_int_equal(vr_image_write(path, &img, 16, &err), VR_E_ARG);
  vr_image_free(&img);
  vr_image_free(&back);
}

/* Float EXR keeps every float bit: values beyond [0,1], negative, tiny. */
static void exr_float_round_trip(void **state) {
  (void)state;
  vr_image img, back;
  vr_error err = {0};
  assert_int_equal(vr_image_alloc(&img, 19, 21, &err), VR_OK);
  for (size_t i = 0; i < 19 * 21 * 3; i++)
    img.data[i] = (float)(sin((double)i * 0.37) * pow(10.0, (double)(i % 9) - 4.0));
  img.data[5] = 1e-30f;
  img.data[6] = 65504.0f * 4;
  const char *path = in_dir("f.exr");
  assert_int_equal(vr_image_write_exr(path, &img, &err), VR_OK);
  assert_int_equal(vr_image_read(path, &back, &err), VR_OK);
  assert_int_equal(back.bit_depth, 32);
  assert_int_equal(back.width, 19);
  assert_int_equal(back.height, 21);
  assert_near(max_abs_diff(&img, &back), 0.0, 0.0);
  vr_image_free(&back);
  /* Half: values with at most 11 significant bits survive exactly
   * (IEEE 754 binary16), and R, G, B stay in place. */
  for (size_t i = 0; i < 19 * 21 * 3; i++) img.data[i] = (float)((int)(i % 2048) - 1024) / 64.0f;
  assert_int_equal(vr_image_write(in_dir("h.exr"), &img, 16, &err), VR_OK);
  assert_int_equal(vr_image_read(in_dir("h.exr"), &back, &err), VR_OK);
  assert_near(max_abs_diff(&img, &back), 0.0, 0.0);
  vr_image_free(&back);
  vr_image_free(&img);
}

static void grey_and_alpha_pngs_from_another_writer(void **state) {
  (void)state;
  vr_image img;
  vr_error err = {0};
  write_file(in_dir("g8.png"), k_grey8_png, sizeof k_grey8_png);
  assert_int_equal(vr_image_read(in_dir("g8.png"), &img, &err), VR_OK);
  assert_int_equal(img.width, 4);
  assert_int_equal(img.height, 2);
  assert_int_equal(img.bit_depth, 8);
  const int codes[8] = {0, 1, 1, 2, 0, 2, 2, 255};
  for (int i = 0; i < 8; i++)
    for (int c = 0; c < 3; c++) assert_near(img.data[3 * i + c], codes[i] / 255.0, 1e-7);
  vr_image_free(&img);

  write_file(in_dir("g16.png"), k_grey16_png, sizeof k_grey16_png);
  assert_int_equal(vr_image_read(in_dir("g16.png"), &img, &err), VR_OK);
  assert_int_equal(img.bit_depth, 16);
  for (int c = 0; c < 3; c++) {
    assert_near(img.data[c], 4660.0 / 65535.0, 1e-7);
    assert_near(img.data[3 + c], 1.0, 0.0);
  }
  vr_image_free(&img);

  /* Alpha is dropped, colour kept whatever the alpha (even 0). */
  write_file(in_dir("rgba.png"), k_rgba8_png, sizeof k_rgba8_png);
  assert_int_equal(vr_image_read(in_dir("rgba.png"), &img, &err), VR_OK);
  const int rgb[6] = {10, 20, 30, 200, 100, 50};
  for (int i = 0; i < 6; i++) assert_near(img.data[i], rgb[i] / 255.0, 1e-7);
  vr_image_free(&img);
}

/* The size stored in the file itself: PNG's IHDR holds width and height as
 * big-endian 32-bit integers at bytes 16 and 20 (PNG spec, ISO/IEC 15948
 * section 11.2.2), read here without the library. */
static void written_png_has_the_image_size(void **state) {
  (void)state;
  vr_image img;
  vr_error err = {0};
  make_coded_image(&img, 301, 7, 255);
  const char *path = in_dir("size.png");
  int before = test_dir_entries();
  assert_int_equal(vr_image_write_png(path, &img, 8, &err), VR_OK);
  assert_int_equal(test_dir_entries(), before + 1); /* no temporary file left */
  unsigned char head[24];
  FILE *f = fopen(path, "rb");
  assert_non_null(f);
  assert_int_equal(fread(head, 1, 24, f), 24);
  fclose(f);
  uint32_t w = (uint32_t)head[16] << 24 | head[17] << 16 | head[18] << 8 | head[19];
  uint32_t h = (uint32_t)head[20] << 24 | head[21] << 16 | head[22] << 8 | head[23];
  assert_int_equal(w, 301);
  assert_int_equal(h, 7);
  assert_int_equal(head[0], 0x89); /* PNG signature */
  vr_image_free(&img);
}

/* A 2 x 2 rectangle holding R = 0.1, 0.2, 0.3, 0.4: mean 0.25, sample sd
 * sqrt((0.15^2 + 0.05^2 + 0.05^2 + 0.15^2) / 3) = sqrt(0.05/3) = 0.12909944;
 * G constant 0.5 (sd 0); B = 0.9, 1.0, 0.95, 1.0. */
static void rect_mean_and_clipping(void **state) {
  (void)state;
  vr_image img;
  vr_error err = {0};
  assert_int_equal(vr_image_alloc(&img, 5, 4, &err), VR_OK);
  for (size_t i = 0; i < 5 * 4 * 3; i++) img.data[i] = 0.7f; /* outside the rectangle */
  const float r[4] = {0.1f, 0.2f, 0.3f, 0.4f}, b[4] = {0.9f, 1.0f, 0.95f, 1.0f};
  for (int k = 0; k < 4; k++) {
    float *p = px(&img, 2 + k % 2, 1 + k / 2);
    p[0] = r[k];
    p[1] = 0.5f;
    p[2] = b[k];
  }
  double mean[3], sd[3];
  int clipped = -1;
  assert_int_equal(vr_image_rect_mean(&img, 2, 1, 2, 2, mean, sd, &clipped, 1.0, &err), VR_OK);
  assert_near(mean[0], 0.25, 1e-7);
  assert_near(sd[0], sqrt(0.05 / 3), 1e-7);
  assert_near(mean[1], 0.5, 0);
  assert_near(sd[1], 0, 0);
  assert_near(mean[2], 0.9625, 1e-7);
  assert_int_equal(clipped, 2); /* the two B = 1.0 pixels reach clip level 1.0 */
  /* At 0.94 the 0.95 pixel counts too; the 0.7 pixels around never do. */
  assert_int_equal(vr_image_rect_mean(&img, 2, 1, 2, 2, mean, NULL, &clipped, 0.94, &err), VR_OK);
  assert_int_equal(clipped, 3);
  assert_int_equal(vr_image_rect_mean(&img, 0, 0, 5, 4, mean, NULL, &clipped, 0.94, &err), VR_OK);
  assert_int_equal(clipped, 3);
  vr_image_free(&img);
}

/* Labels from a grey PNG made by another writer (k_grey8_png: labels
 * {0,1,1,2 / 0,2,2,255}) on a 4 x 2 photo with R = x/4 + y/8. */
static void label_means(void **state) {
  (void)state;
  vr_image img;
  vr_error err = {0};
  assert_int_equal(vr_image_alloc(&img, 4, 2, &err), VR_OK);
  for (int y = 0; y < 2; y++)
    for (int x = 0; x < 4; x++) {
      float *p = px(&img, x, y);
      p[0] = (float)x / 4 + (float)y / 8;
      p[1] = 0.25f;
      p[2] = (x == 2 && y == 1) ? 1.0f : 0.5f;
    }
  write_file(in_dir("labels.png"), k_grey8_png, sizeof k_grey8_png);
  vr_label_means m;
  assert_int_equal(vr_image_label_means_file(&img, in_dir("labels.png"), 1.0, &m, &err), VR_OK);
  assert_int_equal(m.count, 3);
  /* label 1: (1,0),(2,0): R = 0.25, 0.5 -> mean 0.375, sd sqrt(0.03125) */
  assert_int_equal(m.regions[0].label, 1);
  assert_int_equal(m.regions[0].pixels, 2);
  assert_near(m.regions[0].rgb[0], 0.375, 1e-12);
  assert_near(m.regions[0].sd[0], sqrt(0.03125), 1e-12);
  assert_near(m.regions[0].rgb[1], 0.25, 0);
  /* label 2: (3,0),(1,1),(2,1): R = 0.75, 0.375, 0.625 -> 0.583333; one clipped B */
  assert_int_equal(m.regions[1].label, 2);
  assert_int_equal(m.regions[1].pixels, 3);
  assert_near(m.regions[1].rgb[0], 1.75 / 3, 1e-12);
  assert_int_equal(m.regions[1].clipped, 1);
  assert_near(m.regions[1].rgb[2], 2.0 / 3, 1e-12);
  /* label 255: (3,1) alone: R = 0.875, sd 0 */
  assert_int_equal(m.regions[2].label, 255);
  assert_int_equal(m.regions[2].pixels, 1);
  assert_near(m.regions[2].rgb[0], 0.875, 0);
  assert_near(m.regions[2].sd[0], 0, 0);
  vr_label_means_free(&m);

  /* The same labels written as an RGB 16-bit PNG by the library. */
  vr_image lab;
  assert_int_equal(vr_image_read(in_dir("labels.png"), &lab, &err), VR_OK);
  for (size_t i = 0; i < 8 * 3; i++) lab.data[i] = lab.data[i] * 255.0f / 65535.0f * 256.0f;
  assert_int_equal(vr_image_write_png(in_dir("labels16.png"), &lab, 16, &err), VR_OK);
  assert_int_equal(vr_image_label_means_file(&img, in_dir("labels16.png"), 1.0, &m, &err), VR_OK);
  assert_int_equal(m.count, 3);
  assert_int_equal(m.regions[0].label, 256); /* 1 * 256 */
  assert_int_equal(m.regions[2].label, 255 * 256);
  vr_label_means_free(&m);
  vr_image_free(&lab);
  vr_image_free(&img);
}

/* The region means of a photo kept as its codes (vr_image_read_codes) are
 * those of the same photo read as floats, bit for bit: a rectangle, the
 * regions of a label image (itself read either way) and a quadrilateral;
 * 8 and 16 bits. */
static void regions_from_codes(void **state) {
  (void)state;
  enum { w = 53, h = 41 };
  vr_image labels;
  vr_error err = {0};
  assert_int_equal(vr_image_alloc(&labels, w, h, &err), VR_OK);
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++)
      for (int c = 0; c < 3; c++) px(&labels, x, y)[c] = (float)((x / 10 + 6 * (y / 10)) % 7) / 255.0f;
  assert_int_equal(vr_image_write_png(in_dir("rc_labels.png"), &labels, 8, &err), VR_OK);
  vr_image_free(&labels);
  vr_image lf, lc;
  assert_int_equal(vr_image_read(in_dir("rc_labels.png"), &lf, &err), VR_OK);
  assert_int_equal(vr_image_read_codes(in_dir("rc_labels.png"), &lc, &err), VR_OK);
  for (int bits = 8; bits <= 16; bits += 8) {
    vr_image img, f, c;
    make_coded_image(&img, w, h, bits == 8 ? 255 : 65535);
    assert_int_equal(vr_image_write_png(in_dir("rc.png"), &img, bits, &err), VR_OK);
    assert_int_equal(vr_image_read(in_dir("rc.png"), &f, &err), VR_OK);
    assert_int_equal(vr_image_read_codes(in_dir("rc.png"), &c, &err), VR_OK);
    assert_null(c.data);
    assert_int_equal(c.bit_depth, bits);
    double m1[3], m2[3], d1[3], d2[3];
    int k1, k2;
    assert_int_equal(vr_image_rect_mean(&f, 3, 5, 31, 17, m1, d1, &k1, 0.6, &err), VR_OK);
    assert_int_equal(vr_image_rect_mean(&c, 3, 5, 31, 17, m2, d2, &k2, 0.6, &err), VR_OK);
    assert_memory_equal(m1, m2, sizeof m1);
    assert_memory_equal(d1, d2, sizeof d1);
    assert_int_equal(k1, k2);
    assert_true(k1 > 0);
    vr_label_means a, b;
    assert_int_equal(vr_image_label_means(&f, &lf, "labels", 0.6, &a, &err), VR_OK);
    assert_int_equal(vr_image_label_means(&c, &lc, "labels", 0.6, &b, &err), VR_OK);
    assert_int_equal(a.count, b.count);
    assert_int_equal(a.count, 6); /* labels 1 to 6; 0 is background */
    assert_memory_equal(a.regions, b.regions, (size_t)a.count * sizeof *a.regions);
    vr_label_means_free(&a);
    vr_label_means_free(&b);
    const double quad[4][2] = {{2.3, 4.1}, {47.9, 1.2}, {50.2, 38.7}, {6.6, 33.3}};
    vr_region_stats q1, q2;
    assert_int_equal(vr_region_quad_stats(&f, quad, &q1, &err), VR_OK);
    assert_int_equal(vr_region_quad_stats(&c, quad, &q2, &err), VR_OK);
    assert_true(q1.pixels > 1000);
    assert_memory_equal(&q1, &q2, sizeof q1);
    vr_image_free(&img);
    vr_image_free(&f);
    vr_image_free(&c);
  }
  vr_image_free(&lf);
  vr_image_free(&lc);
  unlink(in_dir("rc.png"));
  unlink(in_dir("rc_labels.png"));
}

static void expect_error(vr_status got, vr_status want, const vr_error *err, const char *part1,
                         const char *part2) {
  assert_int_equal(got, want);
  assert_contains(err->message, part1);
  if (part2) assert_contains(err->message, part2);
}

static void bad_files(void **state) {
  (void)state;
  vr_image img, good;
  vr_error err = {0};
  const char *missing = in_dir("missing.png");
  expect_error(vr_image_read(missing, &img, &err), VR_E_IO, &err, missing,
               "No such file or directory");
  assert_null(img.data);

  const char *text = in_dir("text.png");
  write_file(text, "hello, world\n", 13);
  expect_error(vr_image_read(text, &img, &err), VR_E_PARSE, &err, text,
               "not a PNG, TIFF, JPEG or OpenEXR file");

  const char *empty = in_dir("empty.png");
  write_file(empty, "", 0);
  expect_error(vr_image_read(empty, &img, &err), VR_E_PARSE, &err, empty, "empty");

  /* Valid files cut short: PNG, TIFF, JPEG, EXR. */
  make_coded_image(&good, 64, 48, 255);
  const char *names[4] = {"cut.png", "cut.tif", "cut.jpg", "cut.exr"};
  const int bits[4] = {8, 16, 8, 32};
  for (int k = 0; k < 4; k++) {
    const char *path = in_dir(names[k]);
    assert_int_equal(vr_image_write(path, &good, bits[k], &err), VR_OK);
    long n = file_size(path);
    assert_true(n > 200);
    assert_int_equal(truncate(path, n * 2 / 3), 0);
    vr_status st = vr_image_read(path, &img, &err);
    assert_int_equal(st, VR_E_PARSE);
    assert_contains(err.message, path);
    assert_null(img.data);
  }
  vr_image_free(&good);
  expect_error(vr_image_read(in_dir("cut.png"), &img, &err), VR_E_PARSE, &err, "truncated PNG",
               NULL);
  expect_error(vr_image_read(in_dir("cut.jpg"), &img, &err), VR_E_PARSE, &err, "truncated JPEG",
               NULL);

  /* Writing: unknown extension, bad depth, NaN, a directory that does not exist. */
  make_coded_image(&good, 4, 4, 255);
  expect_error(vr_image_write(in_dir("x.bmp"), &good, 8, &err), VR_E_ARG, &err, ".bmp", NULL);
  expect_error(vr_image_write_png(in_dir("x.png"), &good, 12, &err), VR_E_ARG, &err, "12", NULL);
  good.data[7] = NAN;
  expect_error(vr_image_write_png(in_dir("nan.png"), &good, 8, &err), VR_E_RANGE, &err,
               "pixel (2, 0) channel 1 is NaN", NULL);
  good.data[7] = 0;
  expect_error(vr_image_write_png("/nonexistent-dir/x.png", &good, 8, &err), VR_E_IO, &err,
               "/nonexistent-dir/x.png", NULL);
  expect_error(vr_image_write_exr("/nonexistent-dir/x.exr", &good, &err), VR_E_IO, &err,
               "/nonexistent-dir/x.exr", NULL);
  assert_int_equal(access(in_dir("nan.png"), F_OK), -1); /* nothing half-written */
  vr_image_free(&good);
}

static void region_errors(void **state) {
  (void)state;
  vr_image img, lab;
  vr_error err = {0};
  make_coded_image(&img, 10, 8, 255);
  double m[3];
  expect_error(vr_image_rect_mean(&img, 5, 5, 6, 2, m, NULL, NULL, 1, &err), VR_E_RANGE, &err,
               "x=5 y=5 w=6 h=2", "10 x 8");
  expect_error(vr_image_rect_mean(&img, -1, 0, 2, 2, m, NULL, NULL, 1, &err), VR_E_RANGE, &err,
               "not inside", NULL);
  expect_error(vr_image_rect_mean(&img, 0, 0, 0, 2, m, NULL, NULL, 1, &err), VR_E_RANGE, &err,
               "empty", NULL);
  /* A label image of the wrong size, named in the message. */
  make_coded_image(&lab, 9, 8, 255);
  for (size_t i = 0; i < 9 * 8 * 3; i++) lab.data[i] = 0;
  assert_int_equal(vr_image_write_png(in_dir("small_labels.png"), &lab, 8, &err), VR_OK);
  vr_label_means lm;
  expect_error(vr_image_label_means_file(&img, in_dir("small_labels.png"), 1, &lm, &err),
               VR_E_ARG, &err, "small_labels.png", "9 x 8 but the photo is 10 x 8");
  assert_int_equal(lm.count, 0);
  /* A colour pixel in a label image. */
  vr_image_free(&lab);
  make_coded_image(&lab, 10, 8, 255);
  lab.bit_depth = 8;
  expect_error(vr_image_label_means(&img, &lab, "l.png", 1, &lm, &err), VR_E_PARSE, &err,
               "l.png", "not grey");
  /* A float label image. */
  lab.bit_depth = 32;
  expect_error(vr_image_label_means(&img, &lab, NULL, 1, &lm, &err), VR_E_ARG, &err,
               "label image", "bit depth 32");
  vr_image_free(&lab);
  vr_image_free(&img);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(png8_round_trip),
      cmocka_unit_test(png16_round_trip),
      cmocka_unit_test(tiff_round_trips),
      cmocka_unit_test(png_quantisation),
      cmocka_unit_test(jpeg_round_trip),
      cmocka_unit_test(exr_float_round_trip),
      cmocka_unit_test(grey_and_alpha_pngs_from_another_writer),
      cmocka_unit_test(written_png_has_the_image_size),
      cmocka_unit_test(rect_mean_and_clipping),
      cmocka_unit_test(label_means),
      cmocka_unit_test(regions_from_codes),
      cmocka_unit_test(bad_files),
      cmocka_unit_test(region_errors),
  };
  return cmocka_run_group_tests(tests, make_test_dir, remove_test_dir);
}
