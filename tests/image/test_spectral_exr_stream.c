/* The streaming spectral OpenEXR writer (vr_spectral_exr_write_rows).
 *
 * Where the expected values come from:
 * - the pixels are those the row callback below computes; every
 *   compression offered is lossless (OpenEXR's documentation of NONE, RLE,
 *   ZIPS, ZIP and PIZ), so float channels must come back bit for bit;
 * - half channels hold IEEE 754-2008 binary16, 11 significant bits: a
 *   float in the normal range of half, rounded to nearest, is off by at
 *   most 2^-11 of its magnitude (half an ulp of 2^-10 relative spacing);
 *   the largest finite half is 65504 (IEEE 754-2008, table 3.5);
 * - the flags are 32-bit unsigned integers (OpenEXR's UINT) and come back
 *   exactly, read with the OpenEXR core API rather than our reader;
 * - the channel names and attributes are those of test_spectral_exr.c
 *   (the reference code of Fichet et al., cited there). */
#include "../acquire/image_test_util.h"

#include <openexr.h>
#include <pthread.h>
#include <signal.h>
#include <stdatomic.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <time.h>

#include "vr/spectral_exr.h"

#include <Imath/half.h> /* imath_float_to_half: the conversion OpenEXR uses */

#include "../../image/src/half_convert.h"

enum { NB = 5 };
static const double wl[NB] = {400, 420, 550, 700.5, 1000};

/* What the callback draws.  Values are a smooth spectrum plus a hashed
 * wobble, between 0.01 and 250: inside half's normal range, so the 2^-11
 * bound holds for every one. */
typedef struct scene {
  int w, h, threads;
  int nan_x, nan_y, nan_band; /* a NaN there when nan_band >= 0 */
  int neg_inf_rgb_y;          /* -infinity in B of (0, y) when >= 0 */
  float big;                  /* when > 0: pixel (1, 1), band 0 gets it */
  int fail_y;                 /* the callback fails on the rows holding it */
  int slow;                   /* sleep on some chunks to shuffle the finishing order */
  atomic_int bad_thread;      /* a thread argument outside 0 .. threads - 1 */
  atomic_int calls;
} scene;

static uint32_t hash(uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  return x ^ (x >> 16);
}

static float spectral_value(int x, int y, int b) {
  double smooth = 0.5 + 0.4 * sin(0.05 * x + 0.07 * y + 0.9 * b);
  double noise = (double)(hash((uint32_t)(x * 7919 + y * 104729 + b * 13)) % 1000) / 1e5;
  double scale = b == NB - 1 ? 250.0 : 1.0; /* one band far above 1 */
  return (float)((smooth + noise + 0.01) * scale);
}

static float rgb_value(int x, int y, int c) { return (float)(0.25 * c + 0.001 * (x + y) + 0.02); }

/* All 32 bits used: 0, the top value, and hashed patterns. */
static uint32_t flags_value(int x, int y) {
  if (x == 0 && y == 0) return 0;
  if (x == 1 && y == 0) return UINT32_MAX;
  return hash((uint32_t)(x + 65536 * y));
}

static vr_status fill(void *user, int thread, int y0, int y1, float *spectra, float *rgb,
                      uint32_t *flags, vr_error *err) {
  scene *s = user;
  atomic_fetch_add(&s->calls, 1);
  if (thread < 0 || thread >= s->threads) atomic_store(&s->bad_thread, 1);
  if (s->slow && y0 % 16 == 0 && (y0 / 16) % 3 == 0) {
    struct timespec ts = {0, 2000000}; /* 2 ms: later chunks overtake this one */
    nanosleep(&ts, NULL);
  }
  if (s->fail_y >= y0 && s->fail_y < y1)
    return vr_error_set(err, VR_E_NUMERIC, "solver diverged at line %d", s->fail_y);
  for (int y = y0; y < y1; y++)
    for (int x = 0; x < s->w; x++) {
      const size_t p = (size_t)(y - y0) * (size_t)s->w + (size_t)x;
      for (int b = 0; b < NB; b++) spectra[p * NB + (size_t)b] = spectral_value(x, y, b);
      if (rgb)
        for (int c = 0; c < 3; c++) rgb[p * 3 + (size_t)c] = rgb_value(x, y, c);
      if (flags) flags[p] = flags_value(x, y);
      if (x == s->nan_x && y == s->nan_y && s->nan_band >= 0)
        spectra[p * NB + (size_t)s->nan_band] = NAN;
      if (x == 0 && y == s->neg_inf_rgb_y && rgb) rgb[p * 3 + 2] = -INFINITY;
      if (x == 1 && y == 1 && s->big > 0) spectra[p * NB] = s->big;
    }
  return VR_OK;
}

static scene make_scene(int w, int h, int threads) {
  scene s = {.w = w, .h = h, .threads = threads, .nan_band = -1, .neg_inf_rgb_y = -1,
             .fail_y = -1};
  atomic_init(&s.bad_thread, 0);
  atomic_init(&s.calls, 0);
  return s;
}

static const char *const attr_names[2] = {"software", "capture"};
static const char *const attr_values[2] = {"vr tests", "chart 24, D65"};

static vr_spectral_exr_layout make_layout(const scene *s, vr_exr_compression c, int half) {
  vr_spectral_exr_layout L = {.width = s->w,
                              .height = s->h,
                              .nbands = NB,
                              .wavelengths_nm = wl,
                              .kind = VR_SPECTRAL_REFLECTIVE,
                              .half = half,
                              .rgb = 1,
                              .flags_channel = "flags",
                              .nattrs = 2,
                              .attr_names = attr_names,
                              .attr_values = attr_values,
                              .compression = c,
                              .threads = s->threads};
  return L;
}

/* The UINT channel called name, decoded by the OpenEXR core API, with the
 * header facts that go with it. */
static void read_flags(const char *path, const char *name, int w, int h, uint32_t *out,
                       exr_compression_t want_comp, exr_pixel_type_t want_type) {
  exr_context_t ctxt;
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  assert_int_equal(exr_start_read(&ctxt, path, &init), 0);
  exr_compression_t comp;
  assert_int_equal(exr_get_compression(ctxt, 0, &comp), 0);
  assert_int_equal(comp, want_comp);
  const exr_attr_chlist_t *ch = NULL;
  assert_int_equal(exr_get_channels(ctxt, 0, &ch), 0);
  assert_int_equal(ch->num_channels, NB + 3 + 1);
  for (int i = 0; i < ch->num_channels; i++)
    assert_int_equal(ch->entries[i].pixel_type,
                     strcmp(ch->entries[i].name.str, name) == 0 ? EXR_PIXEL_UINT : want_type);
  for (int k = 0; k < 2; k++) {
    int32_t len = 0;
    const char *v = NULL;
    assert_int_equal(exr_attr_get_string(ctxt, 0, attr_names[k], &len, &v), 0);
    assert_string_equal(v, attr_values[k]);
  }
  int32_t lines = 0;
  assert_int_equal(exr_get_scanlines_per_chunk(ctxt, 0, &lines), 0);
  exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
  for (int y = 0; y < h; y += lines) {
    exr_chunk_info_t cinfo;
    assert_int_equal(exr_read_scanline_chunk_info(ctxt, 0, y, &cinfo), 0);
    if (y == 0)
      assert_int_equal(exr_decoding_initialize(ctxt, 0, &cinfo, &dec), 0);
    else
      assert_int_equal(exr_decoding_update(ctxt, 0, &cinfo, &dec), 0);
    for (int c = 0; c < dec.channel_count; c++) {
      exr_coding_channel_info_t *ci = &dec.channels[c];
      ci->decode_to_ptr =
          strcmp(ci->channel_name, name) == 0 ? (uint8_t *)(out + (size_t)y * (size_t)w) : NULL;
      ci->user_pixel_stride = 4;
      ci->user_line_stride = 4 * w;
      ci->user_bytes_per_element = 4;
      ci->user_data_type = EXR_PIXEL_UINT;
    }
    if (y == 0) assert_int_equal(exr_decoding_choose_default_routines(ctxt, 0, &dec), 0);
    assert_int_equal(exr_decoding_run(ctxt, 0, &dec), 0);
  }
  exr_decoding_destroy(ctxt, &dec);
  assert_int_equal(exr_finish(&ctxt), 0);
}

static const exr_compression_t exr_of[5] = {EXR_COMPRESSION_NONE, EXR_COMPRESSION_RLE,
                                            EXR_COMPRESSION_ZIPS, EXR_COMPRESSION_ZIP,
                                            EXR_COMPRESSION_PIZ};

/* Every compression, float and half, read back through vr_spectral_exr_read
 * (which must skip the UINT flags channel) and the core API. */
static void round_trip_every_compression(void **state) {
  (void)state;
  enum { w = 37, h = 45 }; /* 45 lines: two PIZ chunks of 32, three ZIP chunks of 16 */
  static uint32_t flags[w * h];
  int before = test_dir_entries();
  for (int c = 0; c <= VR_EXR_COMPRESSION_PIZ; c++)
    for (int half = 0; half <= 1; half++) {
      scene s = make_scene(w, h, 2);
      vr_spectral_exr_layout L = make_layout(&s, (vr_exr_compression)c, half);
      char file[64];
      snprintf(file, sizeof file, "rt_%s_%s.exr", vr_exr_compression_name(c),
               half ? "half" : "float");
      const char *path = in_dir(file);
      vr_error err = {0};
      assert_int_equal(vr_spectral_exr_write_rows(path, &L, fill, &s, &err), VR_OK);
      assert_int_equal(atomic_load(&s.bad_thread), 0);

      vr_spectral_image img;
      vr_image rgb;
      assert_int_equal(vr_spectral_exr_read(path, &img, &rgb, &err), VR_OK);
      assert_int_equal(img.width, w);
      assert_int_equal(img.height, h);
      assert_int_equal(img.nbands, NB);
      assert_int_equal(img.kind, VR_SPECTRAL_REFLECTIVE);
      for (int b = 0; b < NB; b++) assert_true(img.wavelengths_nm[b] == wl[b]);
      assert_non_null(rgb.data);
      for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
          const size_t p = (size_t)y * w + (size_t)x;
          for (int b = 0; b < NB; b++) {
            const float want = spectral_value(x, y, b), got = img.data[p * NB + (size_t)b];
            if (half)
              assert_rel(got, want, 0x1p-11);
            else
              assert_memory_equal(&got, &want, sizeof got);
          }
          for (int k = 0; k < 3; k++) {
            const float want = rgb_value(x, y, k);
            if (half)
              assert_rel(rgb.data[p * 3 + (size_t)k], want, 0x1p-11);
            else
              assert_true(rgb.data[p * 3 + (size_t)k] == want);
          }
        }
      vr_spectral_image_free(&img);
      vr_image_free(&rgb);

      memset(flags, 0xA5, sizeof flags);
      read_flags(path, "flags", w, h, flags, exr_of[c], half ? EXR_PIXEL_HALF : EXR_PIXEL_FLOAT);
      for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) assert_int_equal(flags[y * w + x], flags_value(x, y));
    }
  /* The ten files and nothing else: no temporary file left. */
  assert_int_equal(test_dir_entries(), before + 10);
}

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

/* Chunks are written in increasing y whatever the workers' timing (some
 * chunks sleep so that later ones finish first): 1, 2 and 7 threads give
 * the same bytes. */
static void same_bytes_for_any_thread_count(void **state) {
  (void)state;
  static const int counts[3] = {1, 2, 7};
  for (int c = 0; c <= VR_EXR_COMPRESSION_PIZ; c++)
    for (int half = 0; half <= 1; half++) {
      unsigned char *first = NULL;
      size_t first_len = 0;
      for (int t = 0; t < 3; t++) {
        scene s = make_scene(29, 300, counts[t]); /* 10 PIZ chunks, 19 ZIP, 300 of one line */
        s.slow = 1;
        vr_spectral_exr_layout L = make_layout(&s, (vr_exr_compression)c, half);
        const char *path = in_dir("threads.exr");
        vr_error err = {0};
        assert_int_equal(vr_spectral_exr_write_rows(path, &L, fill, &s, &err), VR_OK);
        assert_int_equal(atomic_load(&s.bad_thread), 0);
        size_t n;
        unsigned char *bytes = slurp(path, &n);
        if (!first) {
          first = bytes;
          first_len = n;
          continue;
        }
        if (n != first_len || memcmp(bytes, first, n) != 0)
          fail_msg("%s %s: %d threads give other bytes than 1",
                   vr_exr_compression_name((vr_exr_compression)c), half ? "half" : "float",
                   counts[t]);
        free(bytes);
      }
      free(first);
    }
}

/* A failing callback: its status and message come back, naming the file;
 * nothing at the path, no temporary file, and an older file there stays. */
static void callback_error_leaves_nothing(void **state) {
  (void)state;
  int before = test_dir_entries();
  const char *path = in_dir("fails.exr");
  for (int threads = 1; threads <= 3; threads += 2) {
    scene s = make_scene(31, 200, threads);
    s.fail_y = 100;
    vr_spectral_exr_layout L = make_layout(&s, VR_EXR_COMPRESSION_ZIP, 1);
    vr_error err = {0};
    assert_int_equal(vr_spectral_exr_write_rows(path, &L, fill, &s, &err), VR_E_NUMERIC);
    assert_contains(err.message, path);
    assert_contains(err.message, "rows 96 to 111"); /* the ZIP chunk of line 100 */
    assert_contains(err.message, "solver diverged at line 100");
    struct stat sb;
    assert_int_not_equal(stat(path, &sb), 0);
    assert_int_equal(test_dir_entries(), before);
  }
  /* Over an existing file: it is left as it was. */
  scene s = make_scene(31, 20, 2);
  vr_spectral_exr_layout L = make_layout(&s, VR_EXR_COMPRESSION_ZIP, 0);
  vr_error err = {0};
  assert_int_equal(vr_spectral_exr_write_rows(path, &L, fill, &s, &err), VR_OK);
  size_t n0, n1;
  unsigned char *old = slurp(path, &n0);
  s = make_scene(31, 200, 2);
  s.fail_y = 5;
  L = make_layout(&s, VR_EXR_COMPRESSION_PIZ, 1);
  assert_int_equal(vr_spectral_exr_write_rows(path, &L, fill, &s, &err), VR_E_NUMERIC);
  unsigned char *now = slurp(path, &n1);
  assert_int_equal(n1, n0);
  assert_memory_equal(now, old, n0);
  assert_int_equal(test_dir_entries(), before + 1);
  free(old);
  free(now);
  unlink(path);
}

/* A write that fails half way (the file size limit of the process, as on
 * a full disk): VR_E_IO, and nothing left.  SIGXFSZ is ignored so that the
 * write returns EFBIG instead of ending the process. */
static void write_error_leaves_nothing(void **state) {
  (void)state;
  int before = test_dir_entries();
  const char *path = in_dir("too_big.exr");
  struct rlimit old;
  assert_int_equal(getrlimit(RLIMIT_FSIZE, &old), 0);
  struct rlimit small = old;
  small.rlim_cur = 100000; /* the header fits, the pixels (about 1.3 MB) do not */
  void (*was)(int) = signal(SIGXFSZ, SIG_IGN);
  assert_int_equal(setrlimit(RLIMIT_FSIZE, &small), 0);
  scene s = make_scene(64, 600, 2);
  vr_spectral_exr_layout L = make_layout(&s, VR_EXR_COMPRESSION_NONE, 0);
  vr_error err = {0};
  vr_status st = vr_spectral_exr_write_rows(path, &L, fill, &s, &err);
  assert_int_equal(setrlimit(RLIMIT_FSIZE, &old), 0);
  signal(SIGXFSZ, was);
  assert_int_equal(st, VR_E_IO);
  assert_contains(err.message, path);
  assert_contains(err.message, "write failed");
  struct stat sb;
  assert_int_not_equal(stat(path, &sb), 0);
  assert_int_equal(test_dir_entries(), before);
}

/* A texture of 88 MiB (more than the 64 MiB from which the writer stages
 * its bytes and writes them with O_DIRECT, exr_stream.h) comes back value
 * for value, flags included, with the chunk offset table (written below
 * the staged part at the end) good enough for the reader; and a write that
 * fails in that mode (the size limit of write_error_leaves_nothing, now in
 * the middle of the pixels) leaves nothing.  Where the file system refuses
 * O_DIRECT (tmpfs), the same is checked through the page cache. */
static void large_file_past_the_page_cache(void **state) {
  (void)state;
  enum { w = 2048, h = 1200 }; /* 2048 x 1200 x (8 float + flags) x 4 bytes */
  int before = test_dir_entries();
  const char *path = in_dir("large.exr");
  scene s = make_scene(w, h, 2);
  vr_spectral_exr_layout L = make_layout(&s, VR_EXR_COMPRESSION_NONE, 0);
  vr_error err = {0};
  assert_int_equal(vr_spectral_exr_write_rows(path, &L, fill, &s, &err), VR_OK);
  assert_true(file_size(path) > (64L << 20));
  vr_spectral_image img;
  vr_image rgb;
  assert_int_equal(vr_spectral_exr_read(path, &img, &rgb, &err), VR_OK);
  assert_int_equal(img.width, w);
  assert_int_equal(img.height, h);
  size_t wrong = 0;
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++) {
      const size_t p = (size_t)y * w + (size_t)x;
      for (int b = 0; b < NB; b++) wrong += img.data[p * NB + (size_t)b] != spectral_value(x, y, b);
      for (int k = 0; k < 3; k++) wrong += rgb.data[p * 3 + (size_t)k] != rgb_value(x, y, k);
    }
  assert_int_equal(wrong, 0);
  vr_spectral_image_free(&img);
  vr_image_free(&rgb);
  uint32_t *flags = malloc((size_t)w * h * sizeof *flags);
  assert_non_null(flags);
  read_flags(path, "flags", w, h, flags, EXR_COMPRESSION_NONE, EXR_PIXEL_FLOAT);
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++) wrong += flags[(size_t)y * w + (size_t)x] != flags_value(x, y);
  assert_int_equal(wrong, 0);
  free(flags);
  unlink(path);

  const char *big = in_dir("large_too_big.exr");
  struct rlimit old;
  assert_int_equal(getrlimit(RLIMIT_FSIZE, &old), 0);
  struct rlimit small = old;
  small.rlim_cur = 20L << 20; /* two staged buffers and a half */
  void (*was)(int) = signal(SIGXFSZ, SIG_IGN);
  assert_int_equal(setrlimit(RLIMIT_FSIZE, &small), 0);
  s = make_scene(w, h, 2);
  vr_status st = vr_spectral_exr_write_rows(big, &L, fill, &s, &err);
  assert_int_equal(setrlimit(RLIMIT_FSIZE, &old), 0);
  signal(SIGXFSZ, was);
  assert_int_equal(st, VR_E_IO);
  assert_contains(err.message, big);
  assert_contains(err.message, "write failed");
  assert_int_equal(test_dir_entries(), before);
}

/* NaN, -infinity, and values beyond half: VR_E_RANGE naming the pixel and
 * the band or channel, the lowest chunk's whatever the threads. */
static void bad_values_name_the_pixel(void **state) {
  (void)state;
  int before = test_dir_entries();
  const char *path = in_dir("nan.exr");
  vr_error err = {0};
  for (int threads = 1; threads <= 7; threads += 3) {
    scene s = make_scene(23, 90, threads);
    s.nan_x = 5;
    s.nan_y = 70;
    s.nan_band = 1;
    s.neg_inf_rgb_y = 80; /* in a later chunk: the NaN is reported */
    vr_spectral_exr_layout L = make_layout(&s, VR_EXR_COMPRESSION_ZIP, 0);
    assert_int_equal(vr_spectral_exr_write_rows(path, &L, fill, &s, &err), VR_E_RANGE);
    assert_contains(err.message, path);
    assert_contains(err.message, "pixel (5, 70), band 1 (420 nm, channel T.420,000000nm) is NaN");
    s.nan_band = -1;
    assert_int_equal(vr_spectral_exr_write_rows(path, &L, fill, &s, &err), VR_E_RANGE);
    assert_contains(err.message, "RGB preview pixel (0, 80), channel B is -infinity");
  }
  /* 7e4 is beyond half's largest finite value: refused in half, kept in
   * float; +infinity is kept in both. */
  scene s = make_scene(4, 3, 1);
  s.big = 7e4f;
  vr_spectral_exr_layout L = make_layout(&s, VR_EXR_COMPRESSION_NONE, 1);
  assert_int_equal(vr_spectral_exr_write_rows(path, &L, fill, &s, &err), VR_E_RANGE);
  assert_contains(err.message, "pixel (1, 1), band 0 (400 nm, channel T.400,000000nm) is 70000");
  struct stat sb;
  assert_int_not_equal(stat(path, &sb), 0);
  assert_int_equal(test_dir_entries(), before);
  for (int half = 0; half <= 1; half++) {
    s.big = half ? INFINITY : 7e4f;
    L = make_layout(&s, VR_EXR_COMPRESSION_NONE, half);
    assert_int_equal(vr_spectral_exr_write_rows(path, &L, fill, &s, &err), VR_OK);
    vr_spectral_image img;
    assert_int_equal(vr_spectral_exr_read(path, &img, NULL, &err), VR_OK);
    assert_true(img.data[(1 * 4 + 1) * NB] == s.big);
    vr_spectral_image_free(&img);
  }
  unlink(path);
}

/* zip_level reaches zlib: levels 1 and 9 both read back exactly, and the
 * files differ in size. */
static void zip_level_is_used(void **state) {
  (void)state;
  long size[2];
  for (int k = 0; k < 2; k++) {
    scene s = make_scene(64, 64, 2);
    vr_spectral_exr_layout L = make_layout(&s, VR_EXR_COMPRESSION_ZIP, 0);
    L.zip_level = k == 0 ? 1 : 9;
    const char *path = in_dir(k == 0 ? "zip1.exr" : "zip9.exr");
    vr_error err = {0};
    assert_int_equal(vr_spectral_exr_write_rows(path, &L, fill, &s, &err), VR_OK);
    vr_spectral_image img;
    assert_int_equal(vr_spectral_exr_read(path, &img, NULL, &err), VR_OK);
    for (int b = 0; b < NB; b++) assert_true(img.data[(size_t)(63 * 64 + 63) * NB + (size_t)b] ==
                                             spectral_value(63, 63, b));
    vr_spectral_image_free(&img);
    size[k] = file_size(path);
  }
  assert_true(size[0] != size[1]);
}

static void expect_bad_layout(const vr_spectral_exr_layout *L, vr_spectral_rows_fn f,
                              const char *what) {
  const char *path = in_dir("bad_layout.exr");
  scene s = make_scene(4, 4, 1);
  vr_error err = {0};
  int before = test_dir_entries();
  assert_int_equal(vr_spectral_exr_write_rows(path, L, f, &s, &err), VR_E_ARG);
  assert_contains(err.message, what);
  assert_int_equal(atomic_load(&s.calls), 0);
  assert_int_equal(test_dir_entries(), before);
}

static void bad_layouts_are_refused(void **state) {
  (void)state;
  scene s = make_scene(4, 4, 1);
  const vr_spectral_exr_layout good = make_layout(&s, VR_EXR_COMPRESSION_ZIP, 0);
  vr_spectral_exr_layout L;
  expect_bad_layout(NULL, fill, "layout is NULL");
  expect_bad_layout(&good, NULL, "fill is NULL");
#define BAD(field, value, what) \
  L = good;                     \
  L.field = value;              \
  expect_bad_layout(&L, fill, what)
  BAD(width, 0, "layout.width = 0");
  BAD(height, -3, "layout.height = -3");
  BAD(nbands, 0, "layout.nbands is 0");
  BAD(kind, (vr_spectral_kind)7, "layout.kind 7");
  BAD(wavelengths_nm, NULL, "wavelengths_nm is NULL");
  static const double down[NB] = {400, 500, 450, 600, 700};
  BAD(wavelengths_nm, down, "wavelengths_nm[2] = 450 nm");
  static const double close[NB] = {400, 500, 500.0000001, 600, 700};
  BAD(wavelengths_nm, close, "would both be channel T.500,000000nm");
  BAD(compression, (vr_exr_compression)5, "layout.compression = 5");
  BAD(zip_level, -1, "layout.zip_level = -1");
  BAD(zip_level, 10, "layout.zip_level = 10");
  BAD(threads, 0, "layout.threads = 0");
  BAD(threads, 257, "layout.threads = 257");
  BAD(emissive_units, "W.m^-2.sr^-1.nm^-1", "layout.emissive_units 'W.m^-2.sr^-1.nm^-1' given "
                                            "for a reflective image");
  BAD(flags_channel, "", "layout.flags_channel is empty");
  BAD(flags_channel, "G", "layout.flags_channel 'G' is the name of an R, G, B");
  BAD(flags_channel, "T.550,000000nm", "layout.flags_channel 'T.550,000000nm' is named like");
  BAD(flags_channel, "S0.5nm", "layout.flags_channel 'S0.5nm' is named like");
  BAD(attr_names, NULL, "layout.attr_names is NULL with nattrs = 2");
  static const char *const reserved[2] = {"software", "emissiveUnits"};
  BAD(attr_names, reserved, "layout.attr_names[1] = 'emissiveUnits'");
  static const char *const twice[2] = {"software", "software"};
  BAD(attr_names, twice, "layout.attr_names[1] = 'software' repeats attr_names[0]");
  static const char *const no_value[2] = {"x", NULL};
  BAD(attr_values, no_value, "layout.attr_values[1] (attribute capture) is NULL");
#undef BAD
  L = good;
  L.kind = VR_SPECTRAL_EMISSIVE;
  L.emissive_units = "";
  expect_bad_layout(&L, fill, "layout.emissive_units is an empty string");
  /* And the good one is good: units allowed on emissive images. */
  L.emissive_units = "W.m^-2.sr^-1.nm^-1";
  vr_error err = {0};
  assert_int_equal(vr_spectral_exr_write_rows(in_dir("good.exr"), &L, fill, &s, &err), VR_OK);
  unlink(in_dir("good.exr"));
}

/* The writer converts half channels itself with F16C where the processor
 * has it.  OpenEXR's own float-to-half conversion is the reference: the
 * file must be the same bytes with the conversion left to OpenEXR.  The
 * values probe IEEE 754 binary16's edges: subnormals (2^-24 = 5.96e-8 the
 * smallest), the smallest normal 2^-14, ties to even at 1 + 2^-11 and
 * 2049, the largest finite 65504 and 65519 (rounds to it), and +infinity. */
extern int vr_half_disable_f16c;

static const float edge_values[] = {0.0f,       1.0f,          5.96e-8f,    2.98e-8f,
                                    3.0e-5f,    6.1035156e-5f, 0.33333334f, 1.00048828f,
                                    2049.0f,    65504.0f,      65519.0f,    INFINITY,
                                    0.1f,       1e-7f,         0.999f,      12345.678f};

static vr_status fill_edges(void *user, int thread, int y0, int y1, float *spectra, float *rgb,
                            uint32_t *flags, vr_error *err) {
  (void)thread;
  (void)err;
  const scene *s = user;
  const size_t nv = sizeof edge_values / sizeof edge_values[0];
  for (int y = y0; y < y1; y++)
    for (int x = 0; x < s->w; x++) {
      const size_t p = (size_t)(y - y0) * (size_t)s->w + (size_t)x;
      for (int b = 0; b < NB; b++)
        spectra[p * NB + (size_t)b] = edge_values[(size_t)(x + 3 * y + b) % nv];
      for (int c = 0; c < 3; c++) rgb[p * 3 + (size_t)c] = edge_values[(size_t)(x + y + c) % nv];
      flags[p] = (uint32_t)x;
    }
  return VR_OK;
}

/* The band-major conversion the writer uses for half spectra: 8 x 8
 * blocks transposed in registers, masked loads for the last bands, scalar
 * tails.  Reference: Imath's imath_float_to_half (OpenEXR's conversion),
 * value by value, on 31 bands (3 whole blocks and a tail of 7) and 8 (one
 * whole block) over 19 pixels (2 blocks and a tail of 3), 3 lines. */
static void planar_conversion_matches_imath(void **state) {
  (void)state;
  vr_half_disable_f16c = 0; /* whatever a failed test before left */
  if (!vr_half_available()) {
#if defined(__x86_64__) || defined(__i386__)
    /* The fast path is built here: a CPU without F16C cannot test it, and
     * that is a failure, not a skip (README: the tests need an x86-64 CPU
     * with F16C, as every one since 2013 has). */
    fail_msg("this x86 CPU has no F16C: the half conversion's fast path cannot be tested");
#else
    skip(); /* not built on this architecture: OpenEXR converts */
#endif
  }
  const size_t lines = 3, width = 19, nbs[2] = {31, 8};
  const size_t nv = sizeof edge_values / sizeof edge_values[0];
  for (int t = 0; t < 2; t++) {
    const size_t nb = nbs[t], n = lines * width * nb;
    /* Exactly n floats, so a read past the last pixel's bands would be
     * caught by ASan. */
    float *in = malloc(n * sizeof *in);
    uint16_t *out = malloc(n * sizeof *out);
    assert_non_null(in);
    assert_non_null(out);
    for (size_t i = 0; i < n; i++) in[i] = edge_values[(i * 7 + i / 5) % nv];
    memset(out, 0xAB, n * sizeof *out);
    vr_half_convert_planar(in, out, lines, width, nb);
    for (size_t y = 0; y < lines; y++)
      for (size_t x = 0; x < width; x++)
        for (size_t b = 0; b < nb; b++) {
          const float v = in[(y * width + x) * nb + b];
          const uint16_t got = out[(y * nb + b) * width + x], want = imath_float_to_half(v);
          if (got != want)
            fail_msg("%zu bands: line %zu pixel %zu band %zu: %g gave 0x%04x, Imath 0x%04x", nb, y,
                     x, b, (double)v, got, want);
        }
    free(in);
    free(out);
  }
}

static void half_conversion_matches_openexr(void **state) {
  (void)state;
  unsigned char *bytes[2];
  size_t len[2];
  for (int k = 0; k < 2; k++) {
    vr_half_disable_f16c = k;
    scene s = make_scene(17, 40, 2);
    vr_spectral_exr_layout L = make_layout(&s, VR_EXR_COMPRESSION_NONE, 1);
    const char *path = in_dir("edges.exr");
    vr_error err = {0};
    assert_int_equal(vr_spectral_exr_write_rows(path, &L, fill_edges, &s, &err), VR_OK);
    bytes[k] = slurp(path, &len[k]);
  }
  vr_half_disable_f16c = 0;
  assert_int_equal(len[0], len[1]);
  assert_memory_equal(bytes[0], bytes[1], len[0]);
  free(bytes[0]);
  free(bytes[1]);
}

static void compression_names(void **state) {
  (void)state;
  static const char *const spellings[5] = {"none", "RLE", "Zips", "zip", "PIZ"};
  vr_error err = {0};
  for (int c = 0; c < 5; c++) {
    vr_exr_compression got = (vr_exr_compression)-1;
    assert_int_equal(vr_exr_compression_parse(spellings[c], &got, &err), VR_OK);
    assert_int_equal(got, c);
    assert_int_equal(vr_exr_compression_parse(vr_exr_compression_name(got), &got, &err), VR_OK);
    assert_int_equal(got, c);
  }
  assert_string_equal(vr_exr_compression_name(VR_EXR_COMPRESSION_ZIPS), "zips");
  vr_exr_compression got;
  assert_int_equal(vr_exr_compression_parse("zip2", &got, &err), VR_E_ARG);
  assert_contains(err.message, "'zip2'");
  assert_contains(err.message, "none, rle, zips, zip or piz");
  assert_int_equal(vr_exr_compression_parse(NULL, &got, &err), VR_E_ARG);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(round_trip_every_compression),
      cmocka_unit_test(same_bytes_for_any_thread_count),
      cmocka_unit_test(callback_error_leaves_nothing),
      cmocka_unit_test(write_error_leaves_nothing),
      cmocka_unit_test(large_file_past_the_page_cache),
      cmocka_unit_test(bad_values_name_the_pixel),
      cmocka_unit_test(zip_level_is_used),
      cmocka_unit_test(bad_layouts_are_refused),
      cmocka_unit_test(compression_names),
      cmocka_unit_test(half_conversion_matches_openexr),
      cmocka_unit_test(planar_conversion_matches_imath),
  };
  return cmocka_run_group_tests(tests, make_test_dir, remove_test_dir);
}
