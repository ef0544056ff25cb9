/* Spectral OpenEXR (vr/spectral_exr.h) in the layout of Fichet, Pacanowski
 * and Wilkie, JCGT 10(3) 2021.  The expected channel names are those of the
 * authors' reference code, github.com/afichet/spectral-exr,
 * lib/EXRBiSpectralImage.cpp at commit 1e4bc4714e144fec143251eb49f8631b0755f6a9:
 * getEmissiveChannelName(0, 550.0) = "S" "0" "." + std::to_string(550.0)
 * ("550.000000", '.' turned into ',') + "nm" = "S0.550,000000nm", the name
 * the paper and DESIGN.md cite, and getReflectiveChannelName(550.0) =
 * "T.550,000000nm"; attribute names from lib/include/EXRBiSpectralImage.h
 * at commit bf3f605149d5a3c9304e1c6e75c8684871798ea1 (spectralLayoutVersion
 * "1.0", emissiveUnits).  Files in the layout that our writer never makes
 * (half channels, scrambled order, other units, an offset data window) are
 * written here with the OpenEXR core C API itself. */
#include "../acquire/image_test_util.h"

#include <openexr.h>
#include <pthread.h>
#include <sys/stat.h>

#include "vr/spectral_exr.h"

typedef struct raw_channel {
  const char *name;
  exr_pixel_type_t type;
  const float *plane; /* w*h floats, row-major; NULL gives zeros */
} raw_channel;

typedef struct raw_attr {
  const char *name, *value; /* string attributes */
} raw_attr;

/* A scanline EXR of n channels over (x0, y0)-(x0+w-1, y0+h-1), w*h <= 4096,
 * with string attributes, written with the core API directly. */
static void write_raw_exr(const char *path, const raw_channel *ch, int n, int x0, int y0, int w,
                          int h, exr_compression_t comp, const raw_attr *attrs, int nattrs) {
  exr_context_t ctxt;
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  int part;
  assert_int_equal(exr_start_write(&ctxt, path, EXR_WRITE_FILE_DIRECTLY, &init), 0);
  assert_int_equal(exr_add_part(ctxt, NULL, EXR_STORAGE_SCANLINE, &part), 0);
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
  for (int k = 0; k < nattrs; k++)
    assert_int_equal(exr_attr_set_string(ctxt, part, attrs[k].name, attrs[k].value), 0);
  assert_int_equal(exr_write_header(ctxt), 0);
  int32_t lines = 0;
  assert_int_equal(exr_get_scanlines_per_chunk(ctxt, part, &lines), 0);
  static const float zeros[4096];
  exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
  for (int y = y0; y < y0 + h; y += lines) {
    exr_chunk_info_t cinfo;
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
      enc.channels[c].user_data_type = EXR_PIXEL_FLOAT;
    }
    if (y == y0) assert_int_equal(exr_encoding_choose_default_routines(ctxt, part, &enc), 0);
    assert_int_equal(exr_encoding_run(ctxt, part, &enc), 0);
  }
  exr_encoding_destroy(ctxt, &enc);
  assert_int_equal(exr_finish(&ctxt), 0);
}

/* Values that a float keeps but a half would not, of both signs, tiny and
 * huge, with +infinity (kept by the writer) at one sample. */
static void fill_spectral(vr_spectral_image *img) {
  size_t n = (size_t)img->width * (size_t)img->height * img->nbands;
  for (size_t i = 0; i < n; i++)
    img->data[i] = (float)((double)i * 0.1234567 - 3.0) * ((i % 7 == 0) ? 1e-30f : 1.0f);
  img->data[n / 2] = 3.4e38f;
  img->data[n / 3] = INFINITY;
  img->data[n - 1] = 1e-45f; /* a subnormal float */
}

static void fill_rgb(vr_image *rgb) {
  for (size_t i = 0; i < (size_t)rgb->width * (size_t)rgb->height * 3; i++)
    rgb->data[i] = (float)i / 3.0f - 1.0f;
}

static void round_trip_kind(vr_spectral_kind kind, int with_rgb, const char *file) {
  static const double wl[5] = {380.0, 412.5, 550.0, 700.25, 1000.0};
  vr_spectral_image img, back;
  vr_image rgb, rgb_back;
  vr_error err = {0};
  assert_int_equal(vr_spectral_image_alloc(&img, 7, 5, 5, wl, kind, &err), VR_OK);
  fill_spectral(&img);
  if (with_rgb) {
    assert_int_equal(vr_image_alloc(&rgb, 7, 5, &err), VR_OK);
    fill_rgb(&rgb);
  }
  const char *path = in_dir(file);
  const char *units = kind == VR_SPECTRAL_EMISSIVE ? "W.m^-2.sr^-1.nm^-1" : NULL;
  assert_int_equal(vr_spectral_exr_write(path, &img, with_rgb ? &rgb : NULL, units, &err), VR_OK);
  assert_int_equal(vr_spectral_exr_read(path, &back, &rgb_back, &err), VR_OK);
  assert_int_equal(back.width, 7);
  assert_int_equal(back.height, 5);
  assert_int_equal(back.nbands, 5);
  assert_int_equal(back.kind, kind);
  for (int b = 0; b < 5; b++) assert_true(back.wavelengths_nm[b] == wl[b]);
  /* Bit for bit: float channels, lossless ZIP. */
  assert_memory_equal(back.data, img.data, 7 * 5 * 5 * sizeof(float));
  if (with_rgb) {
    assert_non_null(rgb_back.data);
    assert_memory_equal(rgb_back.data, rgb.data, 7 * 5 * 3 * sizeof(float));
    vr_image_free(&rgb);
  } else {
    assert_null(rgb_back.data);
    assert_int_equal(rgb_back.width, 0);
  }
  vr_image_free(&rgb_back);
  vr_spectral_image_free(&back);
  vr_spectral_image_free(&img);
}

static void round_trip_is_exact(void **state) {
  (void)state;
  int before = test_dir_entries();
  round_trip_kind(VR_SPECTRAL_EMISSIVE, 1, "emissive.exr");
  round_trip_kind(VR_SPECTRAL_REFLECTIVE, 1, "reflective.exr");
  round_trip_kind(VR_SPECTRAL_EMISSIVE, 0, "emissive_no_rgb.exr");
  /* Exactly the three files: no temporary file left beside them. */
  assert_int_equal(test_dir_entries(), before + 3);
}

/* The whole file, for the memory entry point; *n gets its size. */
static unsigned char *slurp(const char *path, size_t *n) {
  long size = file_size(path);
  assert_true(size > 0);
  *n = (size_t)size;
  unsigned char *buf = malloc(*n);
  assert_non_null(buf);
  FILE *f = fopen(path, "rb");
  assert_non_null(f);
  assert_int_equal(fread(buf, 1, *n, f), *n);
  fclose(f);
  return buf;
}

/* The same bytes through the memory entry point, and the name it is given
 * in messages. */
static void read_from_memory(void **state) {
  (void)state;
  static const double wl[3] = {450.0, 550.0, 650.0};
  vr_spectral_image img, back;
  vr_error err = {0};
  assert_int_equal(vr_spectral_image_alloc(&img, 3, 2, 3, wl, VR_SPECTRAL_REFLECTIVE, &err), VR_OK);
  for (int i = 0; i < 18; i++) img.data[i] = (float)i / 17.0f;
  const char *path = in_dir("mem.exr");
  assert_int_equal(vr_spectral_exr_write(path, &img, NULL, NULL, &err), VR_OK);
  size_t n;
  unsigned char *buf = slurp(path, &n);
  assert_int_equal(vr_spectral_exr_read_memory(buf, n, "film", &back, NULL, &err), VR_OK);
  assert_memory_equal(back.data, img.data, 18 * sizeof(float));
  vr_spectral_image_free(&back);
  assert_int_equal(vr_spectral_exr_read_memory(buf, n / 2, "film", &back, NULL, &err),
                   VR_E_PARSE);
  assert_contains(err.message, "film");
  assert_null(back.data);
  assert_int_equal(vr_spectral_exr_read_memory(buf, 3, NULL, &back, NULL, &err), VR_E_PARSE);
  assert_contains(err.message, "memory");
  free(buf);
  vr_spectral_image_free(&img);
}

/* Channel names, pixel types, compression and attributes, read back with
 * the OpenEXR core API rather than our reader. */
static void check_written_header(const char *path, const char *const *expected, int n,
                                 const char *units) {
  exr_context_t ctxt;
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  assert_int_equal(exr_start_read(&ctxt, path, &init), 0);
  const exr_attr_chlist_t *ch = NULL;
  assert_int_equal(exr_get_channels(ctxt, 0, &ch), 0);
  assert_int_equal(ch->num_channels, n);
  for (int k = 0; k < n; k++) {
    int found = 0;
    for (int i = 0; i < ch->num_channels; i++)
      if (strcmp(ch->entries[i].name.str, expected[k]) == 0) {
        found = 1;
        assert_int_equal(ch->entries[i].pixel_type, EXR_PIXEL_FLOAT);
      }
    if (!found) fail_msg("channel %s missing from %s", expected[k], path);
  }
  exr_compression_t comp;
  assert_int_equal(exr_get_compression(ctxt, 0, &comp), 0);
  assert_int_equal(comp, EXR_COMPRESSION_ZIP);
  int32_t len = 0;
  const char *s = NULL;
  assert_int_equal(exr_attr_get_string(ctxt, 0, "spectralLayoutVersion", &len, &s), 0);
  assert_string_equal(s, "1.0");
  if (units) {
    assert_int_equal(exr_attr_get_string(ctxt, 0, "emissiveUnits", &len, &s), 0);
    assert_string_equal(s, units);
  } else {
    const exr_attribute_t *a = NULL;
    assert_int_not_equal(exr_get_attribute_by_name(ctxt, 0, "emissiveUnits", &a), 0);
  }
  assert_int_equal(exr_finish(&ctxt), 0);
}

static void channel_names_follow_reference(void **state) {
  (void)state;
  /* 400.5 and 1000 check the decimal part and a fourth integer digit; a
   * std::to_string of a double prints six decimals. */
  static const double wl[3] = {400.5, 550.0, 1000.0};
  vr_spectral_image img;
  vr_image rgb;
  vr_error err = {0};
  assert_int_equal(vr_spectral_image_alloc(&img, 2, 2, 3, wl, VR_SPECTRAL_EMISSIVE, &err), VR_OK);
  assert_int_equal(vr_image_alloc(&rgb, 2, 2, &err), VR_OK);
  const char *path = in_dir("names_s.exr");
  assert_int_equal(vr_spectral_exr_write(path, &img, &rgb, "W.m^-2.sr^-1", &err), VR_OK);
  static const char *const emissive[] = {"R", "G", "B", "S0.400,500000nm", "S0.550,000000nm",
                                         "S0.1000,000000nm"};
  check_written_header(path, emissive, 6, "W.m^-2.sr^-1");

  img.kind = VR_SPECTRAL_REFLECTIVE;
  path = in_dir("names_t.exr");
  assert_int_equal(vr_spectral_exr_write(path, &img, NULL, NULL, &err), VR_OK);
  static const char *const reflective[] = {"T.400,500000nm", "T.550,000000nm",
                                           "T.1000,000000nm"};
  check_written_header(path, reflective, 3, NULL);
  vr_image_free(&rgb);
  vr_spectral_image_free(&img);
}

/* Reflective channels written by hand in scrambled order, half and float,
 * other units of the layout's grammar, with an offset data window, alpha
 * and a layer called T whose channel is not spectral. */
static void reads_hand_written_layout(void **state) {
  (void)state;
  enum { w = 5, h = 19 }; /* 19 lines: two ZIP chunks of 16 */
  static float p[6][w * h], alpha[w * h];
  for (int b = 0; b < 6; b++)
    for (int i = 0; i < w * h; i++)
      p[b][i] = (float)(b * 100 + i) / 16.0f; /* < 2^11 sixteenths: exact in half */
  for (int i = 0; i < w * h; i++) alpha[i] = 1.0f;
  /* Expected order after sorting: 400, 0,45um = 450, 500, 5,5E2nm = 550,
   * 600, 700 nm; the planes say which is which. */
  raw_channel ch[9] = {
      {"T.700,000000nm", EXR_PIXEL_HALF, p[5]}, {"T.400,000000nm", EXR_PIXEL_FLOAT, p[0]},
      {"T.5,5E2nm", EXR_PIXEL_FLOAT, p[3]},     {"T.600nm", EXR_PIXEL_HALF, p[4]},
      {"T.0,45um", EXR_PIXEL_FLOAT, p[1]},      {"A", EXR_PIXEL_HALF, alpha},
      {"T.500,000000nm", EXR_PIXEL_HALF, p[2]}, {"T.R", EXR_PIXEL_FLOAT, alpha},
      {"S1.Z", EXR_PIXEL_FLOAT, NULL}};
  raw_attr version = {"spectralLayoutVersion", "1.0"};
  const char *path = in_dir("by_hand.exr");
  write_raw_exr(path, ch, 9, -3, 7, w, h, EXR_COMPRESSION_ZIP, &version, 1);
  vr_spectral_image img;
  vr_image rgb;
  vr_error err = {0};
  assert_int_equal(vr_spectral_exr_read(path, &img, &rgb, &err), VR_OK);
  assert_null(rgb.data); /* no R, G, B in this file */
  assert_int_equal(img.kind, VR_SPECTRAL_REFLECTIVE);
  assert_int_equal(img.width, w);
  assert_int_equal(img.height, h);
  assert_int_equal(img.nbands, 6);
  static const double expected_nm[6] = {400, 450, 500, 550, 600, 700};
  for (int b = 0; b < 6; b++) assert_near(img.wavelengths_nm[b], expected_nm[b], 1e-12);
  for (int i = 0; i < w * h; i++)
    for (int b = 0; b < 6; b++) assert_near(img.data[(size_t)i * 6 + (size_t)b], p[b][i], 0);
  vr_spectral_image_free(&img);
}

/* Emissive channels by frequency (THz) and in micrometres: c / f with
 * c = 299792458 m/s, as the reference's Util::strToNanometers. */
static void reads_frequencies_and_prefixes(void **state) {
  (void)state;
  static float a[4] = {1, 2, 3, 4}, b[4] = {5, 6, 7, 8}, c[4] = {9, 10, 11, 12};
  raw_channel ch[4] = {{"S0.599,584916THz", EXR_PIXEL_FLOAT, a},
                       {"S0.0,55um", EXR_PIXEL_FLOAT, b},
                       {"S0.6,5e-7m", EXR_PIXEL_FLOAT, c},
                       {"S2.0,55um", EXR_PIXEL_FLOAT, NULL}}; /* polarisation: skipped */
  const char *path = in_dir("freq.exr");
  write_raw_exr(path, ch, 4, 0, 0, 2, 2, EXR_COMPRESSION_NONE, NULL, 0);
  vr_spectral_image img;
  vr_error err = {0};
  assert_int_equal(vr_spectral_exr_read(path, &img, NULL, &err), VR_OK);
  assert_int_equal(img.kind, VR_SPECTRAL_EMISSIVE);
  assert_int_equal(img.nbands, 3);
  assert_near(img.wavelengths_nm[0], 500.0, 1e-9); /* 299792458 / 599.584916e12 m */
  assert_near(img.wavelengths_nm[1], 550.0, 1e-9);
  assert_near(img.wavelengths_nm[2], 650.0, 1e-9);
  for (int i = 0; i < 4; i++) {
    assert_near(img.data[i * 3 + 0], a[i], 0);
    assert_near(img.data[i * 3 + 1], b[i], 0);
    assert_near(img.data[i * 3 + 2], c[i], 0);
  }
  vr_spectral_image_free(&img);
}

/* A NaN (or -infinity) anywhere: VR_E_RANGE naming pixel and band, and no
 * file at all, not even a temporary one. */
static void nan_pixel_writes_nothing(void **state) {
  (void)state;
  static const double wl[4] = {400, 500, 600, 700};
  vr_spectral_image img;
  vr_error err = {0};
  assert_int_equal(vr_spectral_image_alloc(&img, 4, 3, 4, wl, VR_SPECTRAL_EMISSIVE, &err), VR_OK);
  img.data[(1 * 4 + 2) * 4 + 3] = NAN; /* pixel (2, 1), band 3 */
  int before = test_dir_entries();
  const char *path = in_dir("nan.exr");
  assert_int_equal(vr_spectral_exr_write(path, &img, NULL, NULL, &err), VR_E_RANGE);
  assert_contains(err.message, path);
  assert_contains(err.message, "pixel (2, 1), band 3");
  assert_contains(err.message, "S0.700,000000nm");
  assert_contains(err.message, "NaN");
  struct stat sb;
  assert_int_not_equal(stat(path, &sb), 0);
  assert_int_equal(test_dir_entries(), before);

  img.data[(1 * 4 + 2) * 4 + 3] = -INFINITY;
  assert_int_equal(vr_spectral_exr_write(path, &img, NULL, NULL, &err), VR_E_RANGE);
  assert_contains(err.message, "-infinity");
  img.data[(1 * 4 + 2) * 4 + 3] = 0;

  /* The RGB preview is checked as well. */
  vr_image rgb;
  assert_int_equal(vr_image_alloc(&rgb, 4, 3, &err), VR_OK);
  rgb.data[(2 * 4 + 0) * 3 + 1] = NAN;
  assert_int_equal(vr_spectral_exr_write(path, &img, &rgb, NULL, &err), VR_E_RANGE);
  assert_contains(err.message, "pixel (0, 2), channel G");
  assert_int_not_equal(stat(path, &sb), 0);
  assert_int_equal(test_dir_entries(), before);
  vr_image_free(&rgb);
  vr_spectral_image_free(&img);
}

static void write_refuses_bad_arguments(void **state) {
  (void)state;
  vr_spectral_image img;
  vr_error err = {0};
  static const double down[3] = {500, 400, 600};
  assert_int_equal(vr_spectral_image_alloc(&img, 2, 2, 3, down, VR_SPECTRAL_EMISSIVE, &err),
                   VR_E_ARG);
  assert_contains(err.message, "increase strictly");
  assert_null(img.data);
  /* Two wavelengths that differ below the 6 decimals of a name. */
  static const double close[2] = {500.0000001, 500.0000002};
  assert_int_equal(vr_spectral_image_alloc(&img, 2, 2, 2, close, VR_SPECTRAL_EMISSIVE, &err),
                   VR_OK);
  const char *path = in_dir("close.exr");
  assert_int_equal(vr_spectral_exr_write(path, &img, NULL, NULL, &err), VR_E_ARG);
  assert_contains(err.message, "S0.500,000000nm");
  vr_spectral_image_free(&img);

  static const double wl[2] = {500, 600};
  assert_int_equal(vr_spectral_image_alloc(&img, 2, 2, 2, wl, VR_SPECTRAL_REFLECTIVE, &err), VR_OK);
  assert_int_equal(vr_spectral_exr_write(path, &img, NULL, "W.m^-2.sr^-1", &err), VR_E_ARG);
  assert_contains(err.message, "reflective");
  vr_image rgb;
  assert_int_equal(vr_image_alloc(&rgb, 3, 2, &err), VR_OK);
  assert_int_equal(vr_spectral_exr_write(path, &img, &rgb, NULL, &err), VR_E_ARG);
  assert_contains(err.message, "3 x 2");
  struct stat sb;
  assert_int_not_equal(stat(path, &sb), 0);
  vr_image_free(&rgb);
  vr_spectral_image_free(&img);
}

static void truncated_file_fails(void **state) {
  (void)state;
  static const double wl[2] = {500, 600};
  vr_spectral_image img, back;
  vr_error err = {0};
  enum { w = 40, h = 40 }; /* three ZIP chunks */
  assert_int_equal(vr_spectral_image_alloc(&img, w, h, 2, wl, VR_SPECTRAL_EMISSIVE, &err), VR_OK);
  for (size_t i = 0; i < (size_t)w * h * 2; i++) img.data[i] = (float)(i * 2654435761u % 1000);
  const char *path = in_dir("cut.exr");
  assert_int_equal(vr_spectral_exr_write(path, &img, NULL, NULL, &err), VR_OK);
  long n = file_size(path);
  /* Cut in the pixel data, then inside the header. */
  assert_int_equal(truncate(path, n - 100), 0);
  assert_int_equal(vr_spectral_exr_read(path, &back, NULL, &err), VR_E_PARSE);
  assert_contains(err.message, path);
  assert_null(back.data);
  assert_int_equal(truncate(path, 40), 0);
  assert_int_equal(vr_spectral_exr_read(path, &back, NULL, &err), VR_E_PARSE);
  assert_contains(err.message, path);
  assert_contains(err.message, "OpenEXR");
  assert_null(back.data);
  vr_spectral_image_free(&img);
}

static void rgb_exr_has_no_spectral_channels(void **state) {
  (void)state;
  vr_image rgb;
  vr_error err = {0};
  assert_int_equal(vr_image_alloc(&rgb, 3, 3, &err), VR_OK);
  const char *path = in_dir("plain_rgb.exr");
  assert_int_equal(vr_image_write_exr(path, &rgb, &err), VR_OK);
  vr_spectral_image img;
  vr_image back;
  assert_int_equal(vr_spectral_exr_read(path, &img, &back, &err), VR_E_PARSE);
  assert_contains(err.message, path);
  assert_contains(err.message, "no spectral channels");
  assert_null(img.data);
  assert_null(back.data);
  vr_image_free(&rgb);

  path = vr_test_file("not an EXR at all\n");
  assert_int_equal(vr_spectral_exr_read(path, &img, NULL, &err), VR_E_PARSE);
  assert_contains(err.message, "not an OpenEXR file");
  unlink(path);
  assert_int_equal(vr_spectral_exr_read(in_dir("absent.exr"), &img, NULL, &err), VR_E_IO);
}

/* A file with one bad channel among good ones; the message names both the
 * file and what is wrong. */
static void expect_refused(const char *file, const raw_channel *ch, int n, const raw_attr *attrs,
                           int nattrs, const char *what) {
  const char *path = in_dir(file);
  write_raw_exr(path, ch, n, 0, 0, 2, 2, EXR_COMPRESSION_NONE, attrs, nattrs);
  vr_spectral_image img;
  vr_image rgb;
  vr_error err = {0};
  assert_int_equal(vr_spectral_exr_read(path, &img, &rgb, &err), VR_E_PARSE);
  assert_contains(err.message, path);
  assert_contains(err.message, what);
  assert_null(img.data);
  assert_null(rgb.data);
}

static void malformed_layouts_are_refused(void **state) {
  (void)state;
  raw_channel two_commas[2] = {{"S0.500,000000nm", EXR_PIXEL_FLOAT, NULL},
                               {"S0.550,0,0nm", EXR_PIXEL_FLOAT, NULL}};
  expect_refused("commas.exr", two_commas, 2, NULL, 0, "channel 'S0.550,0,0nm'");
  raw_channel no_unit[1] = {{"T.550,000000", EXR_PIXEL_FLOAT, NULL}};
  expect_refused("no_unit.exr", no_unit, 1, NULL, 0, "channel 'T.550,000000'");
  raw_channel bad_prefix[1] = {{"T.550xm", EXR_PIXEL_HALF, NULL}};
  expect_refused("prefix.exr", bad_prefix, 1, NULL, 0, "channel 'T.550xm'");
  raw_channel zero[1] = {{"T.0,000000nm", EXR_PIXEL_HALF, NULL}};
  expect_refused("zero.exr", zero, 1, NULL, 0, "channel 'T.0,000000nm'");
  raw_channel mixed[2] = {{"S0.500,000000nm", EXR_PIXEL_FLOAT, NULL},
                          {"T.500,000000nm", EXR_PIXEL_FLOAT, NULL}};
  expect_refused("mixed.exr", mixed, 2, NULL, 0, "both emissive (S0.500,000000nm) and reflective");
  raw_channel twice[2] = {{"T.550nm", EXR_PIXEL_FLOAT, NULL},
                          {"T.550,000000nm", EXR_PIXEL_FLOAT, NULL}};
  expect_refused("twice.exr", twice, 2, NULL, 0, "same wavelength");
  raw_channel ints[1] = {{"T.550,000000nm", EXR_PIXEL_UINT, NULL}};
  expect_refused("uint.exr", ints, 1, NULL, 0, "unsigned integers");
  raw_channel ok[1] = {{"T.550,000000nm", EXR_PIXEL_FLOAT, NULL}};
  raw_attr v2 = {"spectralLayoutVersion", "2.0"};
  expect_refused("v2.exr", ok, 1, &v2, 1, "spectralLayoutVersion is '2.0'");
}

/* A header that claims a 30000 x 30000 image in a file of a few hundred
 * bytes is refused before 18 GB are asked of malloc. */
static void lying_header_is_refused_before_allocating(void **state) {
  (void)state;
  static const double wl[5] = {400, 450, 500, 550, 600};
  vr_spectral_image img, back;
  vr_error err = {0};
  assert_int_equal(vr_spectral_image_alloc(&img, 2, 2, 5, wl, VR_SPECTRAL_EMISSIVE, &err), VR_OK);
  const char *path = in_dir("liar.exr");
  assert_int_equal(vr_spectral_exr_write(path, &img, NULL, NULL, &err), VR_OK);
  size_t n;
  unsigned char *buf = slurp(path, &n);
  /* "dataWindow\0box2i\0" + int32 size 16 + xmin, ymin, xmax, ymax. */
  static const char key[] = "dataWindow\0box2i";
  unsigned char *at = NULL;
  for (size_t i = 0; i + sizeof key < n; i++)
    if (memcmp(buf + i, key, sizeof key) == 0) at = buf + i + sizeof key + 4;
  assert_non_null(at);
  const int32_t big = 29999;
  memcpy(at + 8, &big, 4); /* little-endian hosts, as OpenEXR files */
  memcpy(at + 12, &big, 4);
  assert_int_equal(vr_spectral_exr_read_memory(buf, n, "liar", &back, NULL, &err),
                   VR_E_PARSE);
  assert_contains(err.message, "liar");
  assert_null(back.data);
  free(buf);
  vr_spectral_image_free(&img);
}

/* Several threads writing and reading their own files at once: no shared
 * state, same bytes back.  cmocka's assertions stay on the main thread. */
typedef struct job {
  int id;
  int ok;
} job;

static void *write_read_job(void *arg) {
  job *j = arg;
  double wl[8];
  for (int b = 0; b < 8; b++) wl[b] = 400.0 + 40.0 * b + j->id;
  vr_spectral_image img, back;
  vr_error err = {0};
  if (vr_spectral_image_alloc(&img, 33, 21, 8, wl, VR_SPECTRAL_EMISSIVE, &err) != VR_OK)
    return NULL;
  for (size_t i = 0; i < 33 * 21 * 8; i++) img.data[i] = (float)(i + (size_t)j->id * 7);
  char path[256];
  snprintf(path, sizeof path, "%s/thread%d.exr", test_dir, j->id);
  for (int round = 0; round < 5; round++) {
    if (vr_spectral_exr_write(path, &img, NULL, "W.m^-2.sr^-1.nm^-1", &err) != VR_OK) break;
    if (vr_spectral_exr_read(path, &back, NULL, &err) != VR_OK) break;
    int same = back.nbands == 8 && memcmp(back.data, img.data, 33 * 21 * 8 * sizeof(float)) == 0 &&
               memcmp(back.wavelengths_nm, wl, sizeof wl) == 0;
    vr_spectral_image_free(&back);
    if (!same) break;
    if (round == 4) j->ok = 1;
  }
  vr_spectral_image_free(&img);
  return NULL;
}

static void threads_do_not_interfere(void **state) {
  (void)state;
  enum { n = 4 };
  pthread_t t[n];
  job jobs[n];
  for (int i = 0; i < n; i++) {
    jobs[i] = (job){.id = i, .ok = 0};
    assert_int_equal(pthread_create(&t[i], NULL, write_read_job, &jobs[i]), 0);
  }
  for (int i = 0; i < n; i++) assert_int_equal(pthread_join(t[i], NULL), 0);
  for (int i = 0; i < n; i++)
    if (!jobs[i].ok) fail_msg("thread %d did not get its image back", i);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(round_trip_is_exact),
      cmocka_unit_test(read_from_memory),
      cmocka_unit_test(channel_names_follow_reference),
      cmocka_unit_test(reads_hand_written_layout),
      cmocka_unit_test(reads_frequencies_and_prefixes),
      cmocka_unit_test(nan_pixel_writes_nothing),
      cmocka_unit_test(write_refuses_bad_arguments),
      cmocka_unit_test(truncated_file_fails),
      cmocka_unit_test(rgb_exr_has_no_spectral_channels),
      cmocka_unit_test(malformed_layouts_are_refused),
      cmocka_unit_test(lying_header_is_refused_before_allocating),
      cmocka_unit_test(threads_do_not_interfere),
  };
  return cmocka_run_group_tests(tests, make_test_dir, remove_test_dir);
}
