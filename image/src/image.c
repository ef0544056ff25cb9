/* The file side of vr/image.h: an image's memory, reading a whole file and
 * telling its format by its first bytes (never by its name, so that a text
 * file called .png gets a clear message instead of a codec's), choosing the
 * writer by extension, and writing every output atomically. */
#include "vr/file.h"
#include "vr/image.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>

#include "image_internal.h"
#include "vr/atomic_file.h"

/* A photo's pixels are tens of megabytes that are written once: in 4 KiB
 * pages that is one page fault per 4 KiB, and on a virtual machine a fault
 * costs microseconds (150 000 of them were a tenth of the CPU time of
 * vr-rgb2spec on four 12-megapixel photos).  Large buffers are aligned to
 * 2 MiB and offered to transparent huge pages, which the kernel uses when
 * it is set to "madvise" or "always" (nothing changes when it is off).
 * Freed with free(). */
void *vr_image_pixels_alloc(size_t bytes) {
  const size_t huge = (size_t)2 << 20;
  if (bytes < 4 * huge) return malloc(bytes ? bytes : 1);
  void *p = NULL;
  if (posix_memalign(&p, huge, bytes)) return NULL;
#ifdef MADV_HUGEPAGE
  (void)madvise(p, bytes, MADV_HUGEPAGE); /* advice only: a refusal changes nothing */
#endif
  return p;
}

vr_status vr_image_alloc(vr_image *img, int w, int h, vr_error *err) {
  if (!img) return vr_error_set(err, VR_E_ARG, "vr_image_alloc: image is NULL");
  memset(img, 0, sizeof *img);
  if (w < 1 || h < 1)
    return vr_error_set(err, VR_E_ARG, "image size %d x %d: both sides must be at least 1", w, h);
  if ((size_t)w > SIZE_MAX / 3 / sizeof(float) / (size_t)h)
    return vr_error_set(err, VR_E_NOMEM, "image size %d x %d is too large", w, h);
  img->data = calloc((size_t)w * (size_t)h * 3, sizeof(float));
  if (!img->data)
    return vr_error_set(err, VR_E_NOMEM, "out of memory for a %d x %d image", w, h);
  img->width = w;
  img->height = h;
  img->channels = 3;
  img->bit_depth = 32;
  return VR_OK;
}

void vr_image_free(vr_image *img) {
  if (!img) return;
  free(img->data);
  free(img->codes);
  free(img->alpha_data);
  memset(img, 0, sizeof *img);
}

vr_status vr_image_check_any(const vr_image *img, const char *what, vr_error *err) {
  if (!img || (!img->data && !img->codes))
    return vr_error_set(err, VR_E_ARG, "%s: no image (NULL or without pixels)", what);
  if (img->width < 1 || img->height < 1 || img->channels != 3)
    return vr_error_set(err, VR_E_ARG, "%s: bad image shape %d x %d x %d (need RGB, 3 channels)",
                        what, img->width, img->height, img->channels);
  if (!img->data && img->bit_depth != 8 && img->bit_depth != 16)
    return vr_error_set(err, VR_E_ARG, "%s: integer codes of bit depth %d (need 8 or 16)", what,
                        img->bit_depth);
  return VR_OK;
}

vr_status vr_image_check(const vr_image *img, const char *what, vr_error *err) {
  vr_status st = vr_image_check_any(img, what, err);
  if (st == VR_OK && !img->data)
    return vr_error_set(err, VR_E_ARG, "%s: the image holds %d-bit codes (vr_image_read_codes), "
                        "not the floats needed here: convert it with vr_image_to_float", what,
                        img->bit_depth);
  return st;
}

vr_status vr_image_to_float(vr_image *img, vr_error *err) {
  vr_status st = vr_image_check_any(img, "vr_image_to_float", err);
  if (st != VR_OK || img->data) return st;
  const size_t n = (size_t)img->width * (size_t)img->height * 3;
  if (n > SIZE_MAX / sizeof(float))
    return vr_error_set(err, VR_E_NOMEM, "image %d x %d is too large for floats", img->width,
                        img->height);
  float *f = vr_image_pixels_alloc(n * sizeof *f);
  if (!f)
    return vr_error_set(err, VR_E_NOMEM, "out of memory for a %d x %d image", img->width,
                        img->height);
  /* The same true division as the decoder's (image_cv.cpp). */
  if (img->bit_depth == 8) {
    const uint8_t *c = img->codes;
    for (size_t i = 0; i < n; i++) f[i] = (float)c[i] / 255.0f;
  } else {
    const uint16_t *c = img->codes;
    for (size_t i = 0; i < n; i++) f[i] = (float)c[i] / 65535.0f;
  }
  free(img->codes);
  img->codes = NULL;
  img->data = f;
  return VR_OK;
}

/* Whole file in memory: images are read once and decoded from the buffer,
 * so the format is known before any codec sees the bytes. */
static vr_status read_whole_file(const char *path, unsigned char **buf, size_t *len,
                                 vr_error *err) {
  *buf = NULL;
  *len = 0;
  /* Before opening: a named pipe would block the open until a writer came. */
  vr_status rs = vr_file_check_regular(path, err);
  if (rs) return rs;
  FILE *fp = fopen(path, "rb");
  if (!fp) return vr_error_at(err, VR_E_IO, path, 0, 0, "cannot open: %s", strerror(errno));
  struct stat st;
  if (fstat(fileno(fp), &st) != 0 || !S_ISREG(st.st_mode)) {
    fclose(fp);
    return vr_error_at(err, VR_E_IO, path, 0, 0, "not a regular file");
  }
  if (st.st_size == 0) {
    fclose(fp);
    return vr_error_at(err, VR_E_PARSE, path, 0, 0, "empty file, not an image");
  }
  size_t size = (size_t)st.st_size;
  unsigned char *b = vr_image_pixels_alloc(size);
  if (!b) {
    fclose(fp);
    return vr_error_at(err, VR_E_NOMEM, path, 0, 0, "out of memory for %zu bytes", size);
  }
  size_t got = fread(b, 1, size, fp);
  int failed = ferror(fp);
  fclose(fp);
  if (got != size || failed) {
    free(b);
    return vr_error_at(err, VR_E_IO, path, 0, 0, "read %zu of %zu bytes", got, size);
  }
  *buf = b;
  *len = size;
  return VR_OK;
}

/* Searched from the end: what is looked for closes the file, so a whole
 * photo of tens of megabytes is not scanned byte by byte to find it. */
static int contains(const unsigned char *b, size_t len, const unsigned char *what, size_t n) {
  for (size_t i = len >= n ? len - n + 1 : 0; i-- > 0;)
    if (b[i] == what[0] && memcmp(b + i, what, n) == 0) return 1;
  return 0;
}

/* In a JPEG's entropy-coded data 0xFF is always followed by 0x00 or a
 * restart marker, so an end-of-image marker (FF D9) after the last
 * start-of-scan (FF DA) tells a complete last scan from a cut one.  Data
 * that some cameras append after the image does not disturb this. */
static int jpeg_is_complete(const unsigned char *b, size_t len) {
  size_t last_sos = 0;
  int have_sos = 0;
  for (size_t i = 0; i + 1 < len; i++)
    if (b[i] == 0xFF && b[i + 1] == 0xDA) {
      last_sos = i;
      have_sos = 1;
    }
  if (!have_sos) return 0;
  for (size_t i = last_sos + 2; i + 1 < len; i++)
    if (b[i] == 0xFF && b[i + 1] == 0xD9) return 1;
  return 0;
}

static uint32_t be32(const unsigned char *b) {
  return (uint32_t)b[0] << 24 | (uint32_t)b[1] << 16 | (uint32_t)b[2] << 8 | b[3];
}

/* The transparent grey level of a greyscale PNG (colour type 0) with a tRNS
 * chunk, as the 8- or 16-bit code OpenCV decodes it to; -1 when there is
 * none.  OpenCV drops such a chunk (it only turns tRNS into alpha for RGB
 * and palette images), so it is looked up here.  PNG 1.2 spec, section
 * 4.2.1.1: for a grey image tRNS holds one 2-byte level in the image's bit
 * depth; levels of 1, 2 and 4 bits come out of libpng scaled to 8 bits
 * (level * 255 / (2^depth - 1)). */
static long png_grey_transparent_level(const unsigned char *b, size_t len) {
  if (len < 33 || memcmp(b + 12, "IHDR", 4) != 0) return -1;
  const int depth = b[24], colour = b[25];
  if (colour != 0 || depth < 1 || depth > 16) return -1;
  for (size_t at = 8; at + 12 <= len;) {
    const uint32_t n = be32(b + at);
    const unsigned char *type = b + at + 4;
    if (n > len - at - 12) return -1;
    if (memcmp(type, "IDAT", 4) == 0 || memcmp(type, "IEND", 4) == 0) return -1;
    if (memcmp(type, "tRNS", 4) == 0) {
      if (n < 2) return -1;
      const long top = (1L << depth) - 1;
      const long level = ((long)b[at + 8] << 8 | b[at + 9]) & top;
      return depth >= 8 ? level : level * 255 / top;
    }
    at += 12 + (size_t)n;
  }
  return -1;
}

/* Pixels of a grey image (R = G = B) whose code equals level. */
static long count_grey_level(const vr_image *img, long level) {
  const double top = img->bit_depth == 16 ? 65535.0 : 255.0;
  const size_t n = (size_t)img->width * (size_t)img->height;
  long hits = 0;
  if (img->codes && img->bit_depth == 8)
    for (size_t i = 0; i < n; i++) hits += ((const uint8_t *)img->codes)[3 * i] == level;
  else if (img->codes)
    for (size_t i = 0; i < n; i++) hits += ((const uint16_t *)img->codes)[3 * i] == level;
  else
    for (size_t i = 0; i < n; i++)
      if (lround((double)img->data[3 * i] * top) == level) hits++;
  return hits;
}

/* The alpha of a grey PNG whose tRNS makes one grey level transparent. */
static vr_status grey_level_alpha(vr_image *img, long level, const char *path, vr_error *err) {
  const double top = img->bit_depth == 16 ? 65535.0 : 255.0;
  const size_t n = (size_t)img->width * (size_t)img->height;
  if (!(img->alpha_data = vr_image_pixels_alloc(n * sizeof *img->alpha_data)))
    return vr_error_at(err, VR_E_NOMEM, path, 0, 0, "out of memory for the alpha channel");
  for (size_t i = 0; i < n; i++)
    img->alpha_data[i] = lround((double)img->data[3 * i] * top) == level ? 0.0f : 1.0f;
  return VR_OK;
}

/* Unsigned integer of n bytes (2, 4 or 8) at b + at, in the TIFF's byte
 * order (little-endian when le). */
static uint64_t tiff_uint(const unsigned char *b, size_t at, int n, int le) {
  uint64_t v = 0;
  for (int i = 0; i < n; i++) v = v << 8 | b[at + (size_t)(le ? n - 1 - i : i)];
  return v;
}

/* Reads the first image directory of a TIFF (classic or BigTIFF, either
 * byte order) for the tags that tell an alpha sample: SamplesPerPixel (277)
 * and ExtraSamples (338), whose first value 1 or 2 means associated or
 * unassociated alpha (TIFF 6.0 spec, section 8, ExtraSamples, and section
 * 18; 0 is unspecified data, not alpha).
 * *samples gets SamplesPerPixel (1 when absent), *extra_alpha 1 when the
 * file declares an alpha sample.  A directory that cannot be walked leaves
 * the defaults: the decoder then reports on that file. */
static void tiff_alpha_tags(const unsigned char *b, size_t len, int *samples, int *extra_alpha) {
  *samples = 1;
  *extra_alpha = 0;
  const int le = b[0] == 'I';
  const int big = (le ? b[2] : b[3]) == 43;
  if (len < (big ? 16u : 8u)) return;
  const uint64_t ifd = big ? tiff_uint(b, 8, 8, le) : tiff_uint(b, 4, 4, le);
  const size_t count_size = big ? 8 : 2, entry_size = big ? 20 : 12, field = big ? 8 : 4;
  if (ifd > len || len - ifd < count_size) return;
  const uint64_t count = tiff_uint(b, (size_t)ifd, (int)count_size, le);
  size_t at = (size_t)ifd + count_size;
  for (uint64_t i = 0; i < count && entry_size <= len - at; i++, at += entry_size) {
    const unsigned tag = (unsigned)tiff_uint(b, at, 2, le);
    const unsigned type = (unsigned)tiff_uint(b, at + 2, 2, le);
    const uint64_t n = tiff_uint(b, at + 4, (int)field, le);
    if ((tag != 277 && tag != 338) || n < 1 || (type != 3 && type != 4)) continue;
    const int size = type == 3 ? 2 : 4; /* SHORT or LONG */
    size_t where = at + 4 + field;      /* the value itself, when it fits */
    if (n * (uint64_t)size > field) {   /* else an offset to the values */
      const uint64_t off = tiff_uint(b, where, (int)field, le);
      if (off > len || len - off < (uint64_t)size) continue;
      where = (size_t)off;
    }
    const uint64_t first = tiff_uint(b, where, size, le);
    if (tag == 277) *samples = first > 64 ? 64 : (int)first;
    else *extra_alpha = first == 1 || first == 2;
  }
}

static vr_status decode_image(const unsigned char *buf, size_t len, const char *path, int keep,
                              vr_image *out, vr_error *err);

static vr_status read_image(const char *path, int keep, vr_image *out, vr_error *err) {
  if (!out) return vr_error_set(err, VR_E_ARG, "vr_image_read: output image is NULL");
  memset(out, 0, sizeof *out);
  if (!path) return vr_error_set(err, VR_E_ARG, "vr_image_read: path is NULL");
  unsigned char *buf;
  size_t len;
  vr_status st = read_whole_file(path, &buf, &len, err);
  if (st != VR_OK) return st;
  st = decode_image(buf, len, path, keep, out, err);
  free(buf);
  return st;
}

/* Decodes the bytes of an image file (named path in messages). */
static vr_status decode_image(const unsigned char *buf, size_t len, const char *path, int keep,
                              vr_image *out, vr_error *err) {
  vr_status st = VR_OK;
  static const unsigned char png[8] = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
  /* The IEND chunk that closes every PNG: its type and its fixed CRC. */
  static const unsigned char png_end[8] = {'I', 'E', 'N', 'D', 0xAE, 0x42, 0x60, 0x82};
  static const unsigned char exr[4] = {0x76, 0x2F, 0x31, 0x01};
  int format = VR_IMAGE_FORMAT_NONE;
  if (len >= 8 && memcmp(buf, png, 8) == 0) {
    format = VR_IMAGE_FORMAT_PNG;
    if (!contains(buf, len, png_end, sizeof png_end))
      st = vr_error_at(err, VR_E_PARSE, path, 0, 0, "truncated PNG: no IEND chunk at its end");
    else
      st = vr_image_decode_cv(buf, len, path, "PNG", keep, out, err);
    long level = st == VR_OK && !out->alpha ? png_grey_transparent_level(buf, len) : -1;
    if (level >= 0) {
      out->alpha = 1;
      out->transparent = count_grey_level(out, level);
      if (keep & VR_IMAGE_KEEP_ALPHA) st = grey_level_alpha(out, level, path, err);
    }
  } else if (len >= 3 && buf[0] == 0xFF && buf[1] == 0xD8 && buf[2] == 0xFF) {
    format = VR_IMAGE_FORMAT_JPEG;
    if (!jpeg_is_complete(buf, len))
      st = vr_error_at(err, VR_E_PARSE, path, 0, 0,
                       "truncated JPEG: no end-of-image marker after its last scan");
    else
      st = vr_image_decode_cv(buf, len, path, "JPEG", keep, out, err);
  } else if (len >= 4 && ((buf[0] == 'I' && buf[1] == 'I' && (buf[2] == 42 || buf[2] == 43) &&
                           buf[3] == 0) ||
                          (buf[0] == 'M' && buf[1] == 'M' && buf[2] == 0 &&
                           (buf[3] == 42 || buf[3] == 43)))) {
    format = VR_IMAGE_FORMAT_TIFF;
    st = vr_image_decode_cv(buf, len, path, "TIFF", keep, out, err);
    int samples, extra_alpha;
    tiff_alpha_tags(buf, len, &samples, &extra_alpha);
    /* A fourth channel from OpenCV is alpha only when the file says so (it
     * may be CMYK turned into RGBA, or unspecified extra data)... */
    if (st == VR_OK && out->alpha && !extra_alpha) {
      out->alpha = 0, out->transparent = 0;
      free(out->alpha_data);
      out->alpha_data = NULL;
    }
    /* ... and OpenCV reads a grey TIFF as one channel whatever else it holds. */
    if (st == VR_OK && extra_alpha && !out->alpha)
      st = vr_error_at(err, VR_E_PARSE, path, 0, 0,
                       "TIFF with an alpha sample (%d samples per pixel) that OpenCV's "
                       "decoder drops, as it does for grey + alpha images (cutting 16-bit "
                       "samples to 8 bits too): save it as grey without alpha, or as RGB or "
                       "RGBA", samples);
  } else if (len >= 4 && memcmp(buf, exr, 4) == 0) {
    format = VR_IMAGE_FORMAT_EXR;
    st = vr_image_decode_exr(buf, len, path, keep, out, err);
  } else {
    char shown[48] = "";
    for (size_t i = 0; i < len && i < 8; i++)
      snprintf(shown + strlen(shown), sizeof shown - strlen(shown), "%s%02x", i ? " " : "",
               buf[i]);
    st = vr_error_at(err, VR_E_PARSE, path, 0, 0,
                     "not a PNG, TIFF, JPEG or OpenEXR file (it starts with bytes %s)", shown);
  }
  if (st != VR_OK) vr_image_free(out);
  else out->format = format;
  return st;
}

vr_status vr_image_read(const char *path, vr_image *out, vr_error *err) {
  return read_image(path, 0, out, err);
}

vr_status vr_image_read_codes(const char *path, vr_image *out, vr_error *err) {
  return read_image(path, VR_IMAGE_KEEP_CODES, out, err);
}

vr_status vr_image_read_alpha(const char *path, vr_image *out, vr_error *err) {
  return read_image(path, VR_IMAGE_KEEP_ALPHA, out, err);
}

vr_status vr_image_decode_alpha(const void *bytes, size_t len, const char *name, vr_image *out,
                                vr_error *err) {
  if (!out) return vr_error_set(err, VR_E_ARG, "vr_image_decode_alpha: output image is NULL");
  memset(out, 0, sizeof *out);
  if (!bytes || !name) return vr_error_set(err, VR_E_ARG, "vr_image_decode_alpha: no bytes or name");
  return decode_image(bytes, len, name, VR_IMAGE_KEEP_ALPHA, out, err);
}

static vr_status write_bytes_atomic(const char *path, const unsigned char *bytes, size_t len,
                                    vr_error *err) {
  vr_atomic_file f;
  vr_status st = vr_atomic_file_open(&f, path, err);
  if (st != VR_OK) return st;
  if (fwrite(bytes, 1, len, f.fp) != len) {
    int saved = errno;
    vr_atomic_file_abort(&f);
    return vr_error_at(err, VR_E_IO, path, 0, 0, "write failed: %s", strerror(saved));
  }
  return vr_atomic_file_commit(&f, err);
}

/* Quantised formats have no code for NaN; refusing it names the pixel
 * instead of writing a colour nobody measured. */
static vr_status check_no_nan(const vr_image *img, const char *path, vr_error *err) {
  size_t n = (size_t)img->width * (size_t)img->height * 3;
  for (size_t i = 0; i < n; i++)
    if (isnan(img->data[i])) {
      size_t p = i / 3;
      return vr_error_at(err, VR_E_RANGE, path, 0, 0,
                         "pixel (%zu, %zu) channel %zu is NaN; PNG, TIFF and JPEG cannot "
                         "store it",
                         p % (size_t)img->width, p / (size_t)img->width, i % 3);
    }
  return VR_OK;
}

static vr_status write_cv(const char *path, const vr_image *img, const char *ext, int bits,
                          vr_error *err) {
  vr_status st = vr_image_check(img, path, err);
  if (st != VR_OK) return st;
  if ((st = check_no_nan(img, path, err)) != VR_OK) return st;
  unsigned char *bytes = NULL;
  size_t len = 0;
  st = vr_image_encode_cv(img, path, ext, bits, &bytes, &len, err);
  if (st == VR_OK) st = write_bytes_atomic(path, bytes, len, err);
  free(bytes);
  return st;
}

vr_status vr_image_write_png(const char *path, const vr_image *img, int bits, vr_error *err) {
  if (!path) return vr_error_set(err, VR_E_ARG, "vr_image_write_png: path is NULL");
  if (bits != 8 && bits != 16)
    return vr_error_at(err, VR_E_ARG, path, 0, 0, "PNG bit depth %d: must be 8 or 16", bits);
  return write_cv(path, img, ".png", bits, err);
}

vr_status vr_image_write_exr(const char *path, const vr_image *img, vr_error *err) {
  return vr_image_write_exr_with(path, img, NULL, err);
}

vr_status vr_image_write_exr_with(const char *path, const vr_image *img,
                                  const vr_exr_colour *colour, vr_error *err) {
  if (!path) return vr_error_set(err, VR_E_ARG, "vr_image_write_exr: path is NULL");
  vr_status st = vr_image_check(img, path, err);
  if (st == VR_OK) st = vr_exr_colour_check(path, colour, err);
  if (st != VR_OK) return st;
  return vr_image_write_exr_as(path, img, 0, colour, NULL, 0, err);
}

vr_status vr_image_write_exr_channels(const char *path, const vr_image *img,
                                      const vr_exr_colour *colour, const vr_exr_channel *extra,
                                      size_t nextra, vr_error *err) {
  if (!path) return vr_error_set(err, VR_E_ARG, "vr_image_write_exr: path is NULL");
  vr_status st = vr_image_check(img, path, err);
  if (st == VR_OK) st = vr_exr_colour_check(path, colour, err);
  if (st != VR_OK) return st;
  for (size_t i = 0; i < nextra; i++) {
    const char *n = extra[i].name;
    if (!n || !*n || !extra[i].data || !strcmp(n, "R") || !strcmp(n, "G") || !strcmp(n, "B"))
      return vr_error_at(err, VR_E_ARG, path, 0, 0,
                         "extra channel %zu: needs a name other than R, G, B and its data", i);
    for (size_t j = 0; j < i; j++)
      if (!strcmp(n, extra[j].name))
        return vr_error_at(err, VR_E_ARG, path, 0, 0, "extra channel '%s' given twice", n);
  }
  return vr_image_write_exr_as(path, img, 0, colour, extra, nextra, err);
}

/* Lower-case extension including the dot ("" when there is none). */
static void extension_of(const char *path, char *ext, size_t size) {
  ext[0] = '\0';
  const char *slash = strrchr(path, '/');
  const char *dot = strrchr(slash ? slash + 1 : path, '.');
  if (!dot || strlen(dot) >= size) return;
  size_t i = 0;
  for (; dot[i]; i++) ext[i] = (char)tolower((unsigned char)dot[i]);
  ext[i] = '\0';
}

vr_status vr_image_write(const char *path, const vr_image *img, int bits, vr_error *err) {
  if (!path) return vr_error_set(err, VR_E_ARG, "vr_image_write: path is NULL");
  char ext[8];
  extension_of(path, ext, sizeof ext);
  if (strcmp(ext, ".png") == 0) return vr_image_write_png(path, img, bits, err);
  if (strcmp(ext, ".tif") == 0 || strcmp(ext, ".tiff") == 0) {
    if (bits != 8 && bits != 16)
      return vr_error_at(err, VR_E_ARG, path, 0, 0, "TIFF bit depth %d: must be 8 or 16", bits);
    return write_cv(path, img, ".tif", bits, err);
  }
  if (strcmp(ext, ".jpg") == 0 || strcmp(ext, ".jpeg") == 0) {
    if (bits != 8)
      return vr_error_at(err, VR_E_ARG, path, 0, 0, "JPEG bit depth %d: must be 8", bits);
    return write_cv(path, img, ".jpg", bits, err);
  }
  if (strcmp(ext, ".exr") == 0) {
    if (bits != 16 && bits != 32)
      return vr_error_at(err, VR_E_ARG, path, 0, 0,
                         "OpenEXR bit depth %d: must be 16 (half) or 32 (float)", bits);
    vr_status st = vr_image_check(img, path, err);
    if (st != VR_OK) return st;
    return vr_image_write_exr_as(path, img, bits == 16, NULL, NULL, 0, err);
  }
  return vr_error_at(err, VR_E_ARG, path, 0, 0,
                     "unknown image extension '%s': use .png, .tif, .tiff, .jpg, .jpeg or .exr",
                     ext);
}
