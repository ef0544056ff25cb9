/* Writing spectral OpenEXR files (vr/spectral_exr.h): the layout checks,
 * the header, and vr_spectral_exr_write as one use of the streaming writer.
 * The pixels themselves are filled, checked, compressed and written in
 * order by the workers of spectral_exr_rows.c.
 *
 * Channel names and attributes are those of the reader (spectral_exr.c,
 * which cites the reference code): S0.<λ>nm or T.<λ>nm with 6 decimals and
 * a decimal comma, spectralLayoutVersion "1.0", emissiveUnits; beside
 * them the colour attributes of the R, G, B preview (exr_colour.c). */
#include "vr/spectral_exr.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "image_internal.h"
#include "spectral_exr_internal.h"

#include "vr/atomic_file.h"

/* ---------------------------------------------------------- compression */

static const char *const compression_names[] = {"none", "rle", "zips", "zip", "piz"};
#define NCOMPRESSIONS (sizeof compression_names / sizeof compression_names[0])

const char *vr_exr_compression_name(vr_exr_compression c) {
  return (unsigned)c < NCOMPRESSIONS ? compression_names[c] : "invalid";
}

/* ASCII only: a locale must not decide what "ZIP" means. */
static int same_ignoring_case(const char *a, const char *b) {
  for (; *a && *b; a++, b++) {
    char x = *a >= 'A' && *a <= 'Z' ? (char)(*a - 'A' + 'a') : *a;
    char y = *b >= 'A' && *b <= 'Z' ? (char)(*b - 'A' + 'a') : *b;
    if (x != y) return 0;
  }
  return *a == *b;
}

vr_status vr_exr_compression_parse(const char *s, vr_exr_compression *out, vr_error *err) {
  if (!s || !out)
    return vr_error_set(err, VR_E_ARG, "vr_exr_compression_parse: %s is NULL",
                        s ? "output" : "compression name");
  for (size_t i = 0; i < NCOMPRESSIONS; i++)
    if (same_ignoring_case(s, compression_names[i])) {
      *out = (vr_exr_compression)i;
      return VR_OK;
    }
  return vr_error_set(err, VR_E_ARG,
                      "OpenEXR compression '%s' is unknown: none, rle, zips, zip or piz", s);
}

static exr_compression_t exr_compression(vr_exr_compression c) {
  switch (c) {
  case VR_EXR_COMPRESSION_RLE: return EXR_COMPRESSION_RLE;
  case VR_EXR_COMPRESSION_ZIPS: return EXR_COMPRESSION_ZIPS;
  case VR_EXR_COMPRESSION_ZIP: return EXR_COMPRESSION_ZIP;
  case VR_EXR_COMPRESSION_PIZ: return EXR_COMPRESSION_PIZ;
  default: return EXR_COMPRESSION_NONE;
  }
}

/* ---------------------------------------------------------- the layout */

/* Attributes this writer sets itself, or that OpenEXR keeps for its own
 * header (the required ones, and those of tiled, multi-part and deep
 * files): a caller's string of that name would clash or be refused. */
static const char *const reserved_attrs[] = {
    "spectralLayoutVersion", "emissiveUnits", "channels",   "compression",
    "dataWindow",            "displayWindow", "lineOrder",  "pixelAspectRatio",
    "screenWindowCenter",    "screenWindowWidth", "tiles",  "name",
    "type",                  "version",       "chunkCount", "maxSamplesPerPixel"};

/* OpenEXR's limit on channel and attribute names (with long names on). */
#define EXR_NAME_MAX 255

static vr_status check_flags_channel(const char *path, const vr_spectral_exr_layout *L,
                                     vr_error *err) {
  const char *f = L->flags_channel;
  if (!f) return VR_OK;
  if (!f[0] || strlen(f) > EXR_NAME_MAX)
    return vr_error_at(err, VR_E_ARG, path, 0, 0,
                       "layout.flags_channel is %s; a channel name has 1 to %d bytes",
                       f[0] ? "too long" : "empty", EXR_NAME_MAX);
  /* R, G, B are refused even without the preview: a reader finding all
   * three would take an integer channel for a colour. */
  if ((f[0] == 'R' || f[0] == 'G' || f[0] == 'B') && !f[1])
    return vr_error_at(err, VR_E_ARG, path, 0, 0,
                       "layout.flags_channel '%s' is the name of an R, G, B preview channel", f);
  /* Band names (and any other name of the layout's grammar) would make the
   * reader take the integers for a spectral channel and refuse the file. */
  if (vr_spectral_name_is_spectral(f))
    return vr_error_at(err, VR_E_ARG, path, 0, 0,
                       "layout.flags_channel '%s' is named like a spectral channel (S0..S3 or "
                       "T, a dot and a number)", f);
  return VR_OK;
}

static vr_status check_attrs(const char *path, const vr_spectral_exr_layout *L, vr_error *err) {
  if (L->nattrs == 0) return VR_OK;
  if (!L->attr_names || !L->attr_values)
    return vr_error_at(err, VR_E_ARG, path, 0, 0, "layout.%s is NULL with nattrs = %zu",
                       L->attr_names ? "attr_values" : "attr_names", L->nattrs);
  for (size_t i = 0; i < L->nattrs; i++) {
    const char *n = L->attr_names[i];
    if (!n || !n[0] || strlen(n) > EXR_NAME_MAX)
      return vr_error_at(err, VR_E_ARG, path, 0, 0,
                         "layout.attr_names[%zu] is %s; an attribute name has 1 to %d bytes", i,
                         !n ? "NULL" : !n[0] ? "empty" : "too long", EXR_NAME_MAX);
    if (!L->attr_values[i])
      return vr_error_at(err, VR_E_ARG, path, 0, 0,
                         "layout.attr_values[%zu] (attribute %s) is NULL", i, n);
    for (size_t r = 0; r < sizeof reserved_attrs / sizeof reserved_attrs[0]; r++)
      if (strcmp(n, reserved_attrs[r]) == 0)
        return vr_error_at(err, VR_E_ARG, path, 0, 0,
                           "layout.attr_names[%zu] = '%s' is an attribute the writer or "
                           "OpenEXR sets itself", i, n);
    /* Typed attributes of layout.colour: a string of that name would be
     * read as the wrong type, or clash. */
    if (vr_exr_colour_attr(n))
      return vr_error_at(err, VR_E_ARG, path, 0, 0,
                         "layout.attr_names[%zu] = '%s' is a colour attribute: give it in "
                         "layout.colour", i, n);
    for (size_t j = 0; j < i; j++)
      if (strcmp(n, L->attr_names[j]) == 0)
        return vr_error_at(err, VR_E_ARG, path, 0, 0,
                           "layout.attr_names[%zu] = '%s' repeats attr_names[%zu]", i, n, j);
  }
  return VR_OK;
}

static vr_status check_layout(const char *path, const vr_spectral_exr_layout *L,
                              vr_spectral_rows_fn fill, vr_error *err) {
  if (!path) return vr_error_set(err, VR_E_ARG, "vr_spectral_exr_write_rows: path is NULL");
  if (!L) return vr_error_at(err, VR_E_ARG, path, 0, 0, "layout is NULL");
  if (!fill) return vr_error_at(err, VR_E_ARG, path, 0, 0, "no row callback (fill is NULL)");
  if (L->width < 1 || L->height < 1)
    return vr_error_at(err, VR_E_ARG, path, 0, 0,
                       "layout.%s = %d: the image needs at least one pixel each way",
                       L->width < 1 ? "width" : "height", L->width < 1 ? L->width : L->height);
  if (L->nbands < 1) return vr_error_at(err, VR_E_ARG, path, 0, 0, "layout.nbands is 0");
  if (L->kind != VR_SPECTRAL_EMISSIVE && L->kind != VR_SPECTRAL_REFLECTIVE)
    return vr_error_at(err, VR_E_ARG, path, 0, 0,
                       "layout.kind %d is neither emissive nor reflective", (int)L->kind);
  vr_status st = vr_spectral_check_wavelengths(L->wavelengths_nm, L->nbands, err);
  if (st != VR_OK) {
    vr_error_prefix(err, "%s: layout: ", path);
    return st;
  }
  st = vr_spectral_check_names(path, L->wavelengths_nm, L->nbands, L->kind, err);
  if (st != VR_OK) return st;
  /* The core API takes strides as int32: a line of all bands must fit. */
  if ((size_t)L->width * L->nbands > INT32_MAX / sizeof(float))
    return vr_error_at(err, VR_E_ARG, path, 0, 0,
                       "%d pixels x %zu bands per line is more than OpenEXR's strides hold",
                       L->width, L->nbands);
  if ((unsigned)L->compression >= NCOMPRESSIONS)
    return vr_error_at(err, VR_E_ARG, path, 0, 0,
                       "layout.compression = %d is none of none, rle, zips, zip, piz",
                       (int)L->compression);
  if (L->zip_level < 0 || L->zip_level > 9)
    return vr_error_at(err, VR_E_ARG, path, 0, 0,
                       "layout.zip_level = %d: 1 (fast) to 9 (small), or 0 for OpenEXR's "
                       "default", L->zip_level);
  if (L->threads < 1 || L->threads > VR_SPECTRAL_MAX_THREADS)
    return vr_error_at(err, VR_E_ARG, path, 0, 0, "layout.threads = %d: 1 to %d workers",
                       L->threads, VR_SPECTRAL_MAX_THREADS);
  if (L->emissive_units && L->kind != VR_SPECTRAL_EMISSIVE)
    return vr_error_at(err, VR_E_ARG, path, 0, 0,
                       "layout.emissive_units '%s' given for a reflective image (T channels "
                       "hold ratios without units)", L->emissive_units);
  if (L->emissive_units && !L->emissive_units[0])
    return vr_error_at(err, VR_E_ARG, path, 0, 0,
                       "layout.emissive_units is an empty string; pass NULL to write none");
  if (L->colour && !L->rgb)
    return vr_error_at(err, VR_E_ARG, path, 0, 0,
                       "layout.colour given without R, G, B channels (layout.rgb = 0): the "
                       "attributes describe those channels");
  st = vr_exr_colour_check(path, L->colour, err);
  if (st == VR_OK) st = check_flags_channel(path, L, err);
  if (st == VR_OK) st = check_attrs(path, L, err);
  return st;
}

/* ---------------------------------------------------------- the header */

/* Channels sorted as OpenEXR keeps them, attributes, then the header
 * itself: after this only pixels are left to write. */
static exr_result_t write_header(exr_context_t ctxt, int part, const vr_spectral_exr_layout *L,
                                 char (*names)[NAME_LEN]) {
  exr_result_t rv = exr_initialize_required_attr_simple(ctxt, part, L->width, L->height,
                                                         exr_compression(L->compression));
  if (rv == EXR_ERR_SUCCESS && L->zip_level > 0)
    rv = exr_set_zip_compression_level(ctxt, part, L->zip_level);
  const exr_pixel_type_t type = L->half ? EXR_PIXEL_HALF : EXR_PIXEL_FLOAT;
  /* The reference writer adds R, G, B first and always; here they are the
   * caller's choice, since only the caller knows the observer and white. */
  static const char *const rgb_names[3] = {"R", "G", "B"};
  for (int k = 0; L->rgb && k < 3 && rv == EXR_ERR_SUCCESS; k++)
    rv = exr_add_channel(ctxt, part, rgb_names[k], type, EXR_PERCEPTUALLY_LINEAR, 1, 1);
  /* Spectral values are radiometric, not perceptual: linear for lossy codecs. */
  for (size_t b = 0; b < L->nbands && rv == EXR_ERR_SUCCESS; b++)
    rv = exr_add_channel(ctxt, part, names[b], type, EXR_PERCEPTUALLY_LINEAR, 1, 1);
  /* The hint means nothing for integers; OpenEXR's default (0) it is. */
  if (rv == EXR_ERR_SUCCESS && L->flags_channel)
    rv = exr_add_channel(ctxt, part, L->flags_channel, EXR_PIXEL_UINT,
                         EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1);
  if (rv == EXR_ERR_SUCCESS)
    rv = exr_attr_set_string(ctxt, part, "spectralLayoutVersion", LAYOUT_VERSION);
  if (rv == EXR_ERR_SUCCESS && L->emissive_units)
    rv = exr_attr_set_string(ctxt, part, "emissiveUnits", L->emissive_units);
  for (size_t i = 0; i < L->nattrs && rv == EXR_ERR_SUCCESS; i++)
    rv = exr_attr_set_string(ctxt, part, L->attr_names[i], L->attr_values[i]);
  if (rv == EXR_ERR_SUCCESS) rv = vr_exr_colour_set(ctxt, part, L->colour);
  if (rv == EXR_ERR_SUCCESS) rv = exr_write_header(ctxt);
  return rv;
}

vr_status vr_spectral_exr_write_rows(const char *path, const vr_spectral_exr_layout *layout,
                                     vr_spectral_rows_fn fill, void *user, vr_error *err) {
  vr_status st = check_layout(path, layout, fill, err);
  if (st != VR_OK) return st;
  char (*names)[NAME_LEN] = malloc(layout->nbands * sizeof *names);
  if (!names) return vr_error_at(err, VR_E_NOMEM, path, 0, 0, "out of memory for channel names");
  for (size_t b = 0; b < layout->nbands; b++)
    vr_spectral_channel_name(names[b], layout->kind, layout->wavelengths_nm[b]);

  vr_atomic_file af;
  st = vr_atomic_file_open(&af, path, err);
  if (st != VR_OK) {
    free(names);
    return st;
  }
  exr_stream s = {.fp = af.fp, .af = &af};
  /* The pixels uncompressed: a large texture goes past the page cache. */
  const uint64_t channels = layout->nbands + (layout->rgb ? 3u : 0u);
  vr_exr_stream_direct_begin(&s, af.tmp,
                             (uint64_t)layout->width * (uint64_t)layout->height *
                                 (channels * (layout->half ? 2u : 4u) +
                                  (layout->flags_channel ? 4u : 0u)));
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.user_data = &s;
  init.write_fn = vr_exr_stream_write;
  init.error_handler_fn = vr_exr_on_write_error;
  exr_context_t ctxt = NULL;
  int part = 0;
  exr_result_t rv = exr_start_write(&ctxt, path, EXR_WRITE_FILE_DIRECTLY, &init);
  if (rv == EXR_ERR_SUCCESS) rv = exr_add_part(ctxt, NULL, EXR_STORAGE_SCANLINE, &part);
  if (rv == EXR_ERR_SUCCESS) rv = write_header(ctxt, part, layout, names);
  if (rv == EXR_ERR_SUCCESS) {
    vr_spectral_rows_job job = {.ctxt = ctxt, .part = part, .path = path, .layout = layout,
                                .fill = fill, .user = user, .stream = &s, .names = names};
    st = vr_spectral_exr_write_chunks(&job, err);
  }
  if (ctxt) {
    /* exr_finish writes the chunk offset table: its result counts too. */
    exr_result_t fin = exr_finish(&ctxt);
    if (rv == EXR_ERR_SUCCESS) rv = fin;
  }
  vr_exr_stream_direct_end(&s);
  free(names);
  if (st != VR_OK) {
    vr_atomic_file_abort(&af);
    return st;
  }
  if (rv != EXR_ERR_SUCCESS || s.write_errno) {
    vr_atomic_file_abort(&af);
    if (s.write_errno)
      return vr_error_at(err, VR_E_IO, path, 0, 0, "write failed: %s", strerror(s.write_errno));
    return vr_error_at(err, VR_E_IO, path, 0, 0, "OpenEXR could not write the spectral image: %s",
                       exr_get_default_error_message(rv));
  }
  return vr_atomic_file_commit(&af, err);
}

/* ------------------------------------------------- a whole image at once */

static vr_status check_writable(const char *path, const vr_spectral_image *img,
                                const vr_image *rgb, const char *units, vr_error *err) {
  if (!path) return vr_error_set(err, VR_E_ARG, "vr_spectral_exr_write: path is NULL");
  if (!img || !img->data)
    return vr_error_at(err, VR_E_ARG, path, 0, 0, "no spectral image (NULL or without pixels)");
  if (img->width < 1 || img->height < 1 || img->nbands < 1)
    return vr_error_at(err, VR_E_ARG, path, 0, 0, "bad spectral image shape %d x %d x %zu bands",
                       img->width, img->height, img->nbands);
  if (img->kind != VR_SPECTRAL_EMISSIVE && img->kind != VR_SPECTRAL_REFLECTIVE)
    return vr_error_at(err, VR_E_ARG, path, 0, 0, "spectral kind %d is neither emissive nor "
                       "reflective", (int)img->kind);
  vr_status st = vr_spectral_check_wavelengths(img->wavelengths_nm, img->nbands, err);
  if (st != VR_OK) {
    vr_error_prefix(err, "%s: ", path);
    return st;
  }
  st = vr_spectral_check_names(path, img->wavelengths_nm, img->nbands, img->kind, err);
  if (st != VR_OK) return st;
  /* The core API takes strides as int32: a line of all bands must fit. */
  if ((size_t)img->width * img->nbands > INT32_MAX / sizeof(float))
    return vr_error_at(err, VR_E_ARG, path, 0, 0,
                       "%d pixels x %zu bands per line is more than OpenEXR's strides hold",
                       img->width, img->nbands);
  if (rgb) {
    st = vr_image_check(rgb, "RGB preview", err);
    if (st != VR_OK) {
      vr_error_prefix(err, "%s: ", path);
      return st;
    }
    if (rgb->width != img->width || rgb->height != img->height)
      return vr_error_at(err, VR_E_ARG, path, 0, 0,
                         "RGB preview is %d x %d, the spectral image %d x %d", rgb->width,
                         rgb->height, img->width, img->height);
  }
  if (units && img->kind != VR_SPECTRAL_EMISSIVE)
    return vr_error_at(err, VR_E_ARG, path, 0, 0,
                       "emissive units '%s' given for a reflective image (T channels hold "
                       "ratios without units)", units);
  if (units && !units[0])
    return vr_error_at(err, VR_E_ARG, path, 0, 0,
                       "emissive units are an empty string; pass NULL to write none");
  return VR_OK;
}

typedef struct image_rows {
  const vr_spectral_image *img;
  const vr_image *rgb;
} image_rows;

/* The rows asked for, copied from the image in memory. */
static vr_status copy_image_rows(void *user, int thread, int y0, int y1, float *spectra,
                                 float *rgb, uint32_t *flags, vr_error *err) {
  (void)thread;
  (void)flags;
  (void)err;
  const image_rows *r = user;
  const size_t w = (size_t)r->img->width, nb = r->img->nbands, n = (size_t)(y1 - y0) * w;
  memcpy(spectra, r->img->data + (size_t)y0 * w * nb, n * nb * sizeof(float));
  if (rgb) memcpy(rgb, r->rgb->data + (size_t)y0 * w * 3, n * 3 * sizeof(float));
  return VR_OK;
}

vr_status vr_spectral_exr_write(const char *path, const vr_spectral_image *img,
                                const vr_image *rgb, const char *emissive_units, vr_error *err) {
  return vr_spectral_exr_write_with(path, img, rgb, emissive_units, NULL, err);
}

vr_status vr_spectral_exr_write_with(const char *path, const vr_spectral_image *img,
                                     const vr_image *rgb, const char *emissive_units,
                                     const vr_exr_colour *colour, vr_error *err) {
  vr_status st = check_writable(path, img, rgb, emissive_units, err);
  if (st != VR_OK) return st;
  vr_spectral_exr_layout layout = {.width = img->width,
                                   .height = img->height,
                                   .nbands = img->nbands,
                                   .wavelengths_nm = img->wavelengths_nm,
                                   .kind = img->kind,
                                   .half = 0,
                                   .rgb = rgb != NULL,
                                   .emissive_units = emissive_units,
                                   .compression = VR_EXR_COMPRESSION_ZIP,
                                   .threads = 1,
                                   .colour = colour};
  image_rows rows = {img, rgb};
  return vr_spectral_exr_write_rows(path, &layout, copy_image_rows, &rows, err);
}
