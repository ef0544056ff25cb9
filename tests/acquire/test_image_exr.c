/* OpenEXR files that vr_image_write_exr never makes, written here with the
 * OpenEXR core C API itself: a luminance-only (Y) image, RGBA with a data
 * window away from the origin and another compression, and the kinds the
 * reader refuses (tiled, no colour channel, unsigned integers), each with a
 * message naming the file. */
#include "image_test_util.h"

#include <openexr.h>

typedef struct raw_channel {
  const char *name;
  exr_pixel_type_t type;
  const float *plane; /* w*h floats, row-major; UINT channels get zeros */
} raw_channel;

/* Writes a scanline EXR of n channels over the data window
 * (x0, y0)-(x0+w-1, y0+h-1); tiled (one 16 x 16 tile) when tiled != 0. */
static void write_raw_exr(const char *path, const raw_channel *ch, int n, int x0, int y0, int w,
                          int h, exr_compression_t comp, int tiled) {
  exr_context_t ctxt;
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  int part;
  assert_int_equal(exr_start_write(&ctxt, path, EXR_WRITE_FILE_DIRECTLY, &init), 0);
  assert_int_equal(
      exr_add_part(ctxt, NULL, tiled ? EXR_STORAGE_TILED : EXR_STORAGE_SCANLINE, &part), 0);
  exr_attr_box2i_t dw;
  dw.min.x = x0;
  dw.min.y = y0;
  dw.max.x = x0 + w - 1;
  dw.max.y = y0 + h - 1;
  exr_attr_v2f_t centre;
  centre.x = centre.y = 0.0f;
  assert_int_equal(exr_initialize_required_attr(ctxt, part, &dw, &dw, 1.0f, &centre, 1.0f,
                                                EXR_LINEORDER_INCREASING_Y, comp),
                   0);
  for (int k = 0; k < n; k++)
    assert_int_equal(
        exr_add_channel(ctxt, part, ch[k].name, ch[k].type, EXR_PERCEPTUALLY_LINEAR, 1, 1), 0);
  if (tiled)
    assert_int_equal(exr_set_tile_descriptor(ctxt, part, 16, 16, EXR_TILE_ONE_LEVEL,
                                             EXR_TILE_ROUND_DOWN),
                     0);
  assert_int_equal(exr_write_header(ctxt), 0);
  int32_t lines = 16; /* tiled: one 16 x 16 tile, w and h <= 16 */
  if (!tiled) assert_int_equal(exr_get_scanlines_per_chunk(ctxt, part, &lines), 0);
  static const float zeros[64 * 64];
  exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
  for (int y = y0; y < y0 + h; y += lines) {
    exr_chunk_info_t cinfo;
    if (tiled)
      assert_int_equal(exr_write_tile_chunk_info(ctxt, part, 0, 0, 0, 0, &cinfo), 0);
    else
      assert_int_equal(exr_write_scanline_chunk_info(ctxt, part, y, &cinfo), 0);
    if (y == y0)
      assert_int_equal(exr_encoding_initialize(ctxt, part, &cinfo, &enc), 0);
    else
      assert_int_equal(exr_encoding_update(ctxt, part, &cinfo, &enc), 0);
    for (int c = 0; c < enc.channel_count; c++) {
      const raw_channel *rc = NULL;
      for (int k = 0; k < n; k++)
        if (strcmp(ch[k].name, enc.channels[c].channel_name) == 0) rc = &ch[k];
      assert_non_null(rc);
      const float *src = rc->plane ? rc->plane + (size_t)(y - y0) * (size_t)w : zeros;
      enc.channels[c].encode_from_ptr = (const uint8_t *)src;
      enc.channels[c].user_pixel_stride = 4;
      enc.channels[c].user_line_stride = 4 * w;
      enc.channels[c].user_bytes_per_element = 4;
      enc.channels[c].user_data_type = rc->type == EXR_PIXEL_UINT ? EXR_PIXEL_UINT : EXR_PIXEL_FLOAT;
    }
    if (y == y0) assert_int_equal(exr_encoding_choose_default_routines(ctxt, part, &enc), 0);
    assert_int_equal(exr_encoding_run(ctxt, part, &enc), 0);
  }
  exr_encoding_destroy(ctxt, &enc);
  assert_int_equal(exr_finish(&ctxt), 0);
}

/* Y only, half: grey expanded to R = G = B; values k/8 are exact in half. */
static void luminance_only_exr_is_grey(void **state) {
  (void)state;
  float y[6 * 5];
  for (int i = 0; i < 30; i++) y[i] = (float)(i - 10) / 8.0f;
  raw_channel ch[1] = {{"Y", EXR_PIXEL_HALF, y}};
  const char *path = in_dir("y.exr");
  write_raw_exr(path, ch, 1, 0, 0, 6, 5, EXR_COMPRESSION_ZIP, 0);
  vr_image img;
  vr_error err = {0};
  assert_int_equal(vr_image_read(path, &img, &err), VR_OK);
  assert_int_equal(img.width, 6);
  assert_int_equal(img.height, 5);
  for (int i = 0; i < 30; i++)
    for (int c = 0; c < 3; c++) assert_near(img.data[3 * i + c], y[i], 0);
  vr_image_free(&img);
}

/* RGBA float with PIZ compression and a data window at (100, -7): the
 * image is the data window, alpha is dropped, each channel in its place. */
static void rgba_exr_with_offset_window(void **state) {
  (void)state;
  enum { w = 33, h = 40 }; /* 40 lines: more than one 32-line PIZ chunk */
  static float r[w * h], g[w * h], b[w * h], a[w * h];
  for (int i = 0; i < w * h; i++) {
    r[i] = (float)i * 0.5f;
    g[i] = -(float)i;
    b[i] = 1e-3f * (float)i;
    a[i] = 0.25f;
  }
  raw_channel ch[4] = {{"A", EXR_PIXEL_FLOAT, a},
                       {"B", EXR_PIXEL_FLOAT, b},
                       {"G", EXR_PIXEL_FLOAT, g},
                       {"R", EXR_PIXEL_FLOAT, r}};
  const char *path = in_dir("rgba.exr");
  write_raw_exr(path, ch, 4, 100, -7, w, h, EXR_COMPRESSION_PIZ, 0);
  vr_image img;
  vr_error err = {0};
  assert_int_equal(vr_image_read(path, &img, &err), VR_OK);
  assert_int_equal(img.width, w);
  assert_int_equal(img.height, h);
  for (int i = 0; i < w * h; i++) {
    assert_near(img.data[3 * i + 0], r[i], 0);
    assert_near(img.data[3 * i + 1], g[i], 0);
    assert_near(img.data[3 * i + 2], b[i], 0);
  }
  /* ... but recorded: every pixel has A = 0.25, below opaque. */
  assert_int_equal(img.format, VR_IMAGE_FORMAT_EXR);
  assert_int_equal(img.alpha, 1);
  assert_int_equal(img.transparent, w * h);
  vr_image_free(&img);
}

/* The A channel of an EXR: 1.0 is opaque, less is not (Technical
 * Introduction to OpenEXR, "Premultiplied vs. Un-Premultiplied Color
 * Channels"); half values 1, 0.5, 0 and 2 are exact.  A NaN alpha is not
 * opaque either, and A beside Y works like A beside R, G, B. */
static void exr_alpha_counts(void **state) {
  (void)state;
  enum { w = 5, h = 3 };
  float y[w * h], a[w * h];
  for (int i = 0; i < w * h; i++) {
    y[i] = (float)i / 16.0f;
    a[i] = 1.0f;
  }
  raw_channel ya[2] = {{"A", EXR_PIXEL_HALF, a}, {"Y", EXR_PIXEL_HALF, y}};
  const char *path = in_dir("ya_opaque.exr");
  write_raw_exr(path, ya, 2, 0, 0, w, h, EXR_COMPRESSION_ZIP, 0);
  vr_image img;
  vr_error err = {0};
  assert_int_equal(vr_image_read(path, &img, &err), VR_OK);
  assert_int_equal(img.alpha, 1);
  assert_int_equal(img.transparent, 0);
  assert_near(img.data[3 * 7 + 2], 7.0 / 16.0, 0);
  vr_image_free(&img);

  a[0] = 0.5f;
  a[4] = 0.0f;
  a[9] = 2.0f; /* above 1: opaque */
  a[14] = NAN;
  raw_channel rgba[4] = {{"A", EXR_PIXEL_FLOAT, a},
                         {"B", EXR_PIXEL_HALF, y},
                         {"G", EXR_PIXEL_HALF, y},
                         {"R", EXR_PIXEL_HALF, y}};
  path = in_dir("rgba_some.exr");
  write_raw_exr(path, rgba, 4, 0, 0, w, h, EXR_COMPRESSION_NONE, 0);
  assert_int_equal(vr_image_read(path, &img, &err), VR_OK);
  assert_int_equal(img.alpha, 1);
  assert_int_equal(img.transparent, 3);
  vr_image_free(&img);

  /* No A: no alpha. */
  path = in_dir("rgb_only.exr");
  write_raw_exr(path, rgba + 1, 3, 0, 0, w, h, EXR_COMPRESSION_NONE, 0);
  assert_int_equal(vr_image_read(path, &img, &err), VR_OK);
  assert_int_equal(img.alpha, 0);
  assert_int_equal(img.transparent, 0);
  vr_image_free(&img);

  /* An A of unsigned integers is refused like such a colour channel. */
  raw_channel uint_a[4] = {{"A", EXR_PIXEL_UINT, NULL},
                           {"B", EXR_PIXEL_HALF, y},
                           {"G", EXR_PIXEL_HALF, y},
                           {"R", EXR_PIXEL_HALF, y}};
  path = in_dir("uint_a.exr");
  write_raw_exr(path, uint_a, 4, 0, 0, w, h, EXR_COMPRESSION_NONE, 0);
  assert_int_equal(vr_image_read(path, &img, &err), VR_E_PARSE);
  assert_contains(err.message, "channel A holds unsigned integers");
}

static void refused_exr_kinds(void **state) {
  (void)state;
  vr_image img;
  vr_error err = {0};
  float z[4 * 4] = {0};
  raw_channel depth[1] = {{"Z", EXR_PIXEL_FLOAT, z}};
  const char *path = in_dir("z.exr");
  write_raw_exr(path, depth, 1, 0, 0, 4, 4, EXR_COMPRESSION_NONE, 0);
  assert_int_equal(vr_image_read(path, &img, &err), VR_E_PARSE);
  assert_contains(err.message, path);
  assert_contains(err.message, "no R, G and B channels");
  assert_null(img.data);

  raw_channel ids[3] = {{"B", EXR_PIXEL_UINT, NULL},
                        {"G", EXR_PIXEL_UINT, NULL},
                        {"R", EXR_PIXEL_UINT, NULL}};
  path = in_dir("uint.exr");
  write_raw_exr(path, ids, 3, 0, 0, 4, 4, EXR_COMPRESSION_NONE, 0);
  assert_int_equal(vr_image_read(path, &img, &err), VR_E_PARSE);
  assert_contains(err.message, "unsigned integers");

  raw_channel rgb[3] = {{"B", EXR_PIXEL_HALF, z}, {"G", EXR_PIXEL_HALF, z}, {"R", EXR_PIXEL_HALF, z}};
  path = in_dir("tiled.exr");
  write_raw_exr(path, rgb, 3, 0, 0, 4, 4, EXR_COMPRESSION_NONE, 1);
  assert_int_equal(vr_image_read(path, &img, &err), VR_E_PARSE);
  assert_contains(err.message, path);
  assert_contains(err.message, "tiled");

  /* A header cut in the middle: OpenEXR's own message, after the path. */
  path = in_dir("y_cut.exr");
  write_raw_exr(path, rgb, 3, 0, 0, 4, 4, EXR_COMPRESSION_NONE, 0);
  assert_int_equal(truncate(path, 40), 0);
  assert_int_equal(vr_image_read(path, &img, &err), VR_E_PARSE);
  assert_contains(err.message, path);
  assert_contains(err.message, "OpenEXR");
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(luminance_only_exr_is_grey),
      cmocka_unit_test(rgba_exr_with_offset_window),
      cmocka_unit_test(exr_alpha_counts),
      cmocka_unit_test(refused_exr_kinds),
  };
  return cmocka_run_group_tests(tests, make_test_dir, remove_test_dir);
}
