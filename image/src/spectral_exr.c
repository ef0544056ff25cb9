/* Reading spectral OpenEXR files in the layout of Fichet, Pacanowski and
 * Wilkie (JCGT 10(3), 2021), through the OpenEXR 3 core C API like
 * image_exr.c, and the spectral image itself.  Channel names are made and
 * parsed in spectral_exr_names.c, which cites the reference code the names
 * and attributes (spectralLayoutVersion, emissiveUnits) follow; the
 * writers are in spectral_exr_write.c and spectral_exr_rows.c. */
#include "vr/spectral_exr.h"

#include <inttypes.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <openexr.h>

#include "exr_stream.h"
#include "spectral_exr_internal.h"

#include "vr/file.h"

/* ---------------------------------------------------------------- image */

vr_status vr_spectral_image_alloc(vr_spectral_image *img, int w, int h, size_t nbands,
                                  const double *wavelengths_nm, vr_spectral_kind kind,
                                  vr_error *err) {
  if (!img) return vr_error_set(err, VR_E_ARG, "vr_spectral_image_alloc: image is NULL");
  memset(img, 0, sizeof *img);
  if (w < 1 || h < 1)
    return vr_error_set(err, VR_E_ARG, "spectral image size %d x %d: both sides must be at least 1",
                        w, h);
  if (nbands < 1) return vr_error_set(err, VR_E_ARG, "spectral image: nbands is 0");
  if (kind != VR_SPECTRAL_EMISSIVE && kind != VR_SPECTRAL_REFLECTIVE)
    return vr_error_set(err, VR_E_ARG, "spectral image: kind %d is neither emissive nor reflective",
                        (int)kind);
  vr_status st = vr_spectral_check_wavelengths(wavelengths_nm, nbands, err);
  if (st != VR_OK) return st;
  size_t pixels = (size_t)w * (size_t)h;
  if (nbands > SIZE_MAX / sizeof(double) || pixels > SIZE_MAX / sizeof(float) / nbands)
    return vr_error_set(err, VR_E_NOMEM, "spectral image %d x %d x %zu bands is too large", w, h,
                        nbands);
  img->wavelengths_nm = malloc(nbands * sizeof(double));
  img->data = calloc(pixels * nbands, sizeof(float));
  if (!img->wavelengths_nm || !img->data) {
    vr_spectral_image_free(img);
    return vr_error_set(err, VR_E_NOMEM, "out of memory for a %d x %d x %zu-band spectral image",
                        w, h, nbands);
  }
  memcpy(img->wavelengths_nm, wavelengths_nm, nbands * sizeof(double));
  img->width = w;
  img->height = h;
  img->nbands = nbands;
  img->kind = kind;
  return VR_OK;
}

void vr_spectral_image_free(vr_spectral_image *img) {
  if (!img) return;
  free(img->wavelengths_nm);
  free(img->data);
  memset(img, 0, sizeof *img);
}

/* ------------------------------------------------------------- reading */

/* Where each channel read goes: band index >= 0, -1 - c for R, G, B
 * (c = 0, 1, 2), or SKIP. */
#define SKIP INT32_MIN

typedef struct band {
  double nm;
  int channel; /* index in the channel list */
} band;

static int band_cmp(const void *a, const void *b) {
  double x = ((const band *)a)->nm, y = ((const band *)b)->nm;
  return (x > y) - (x < y);
}

/* Only half and full-resolution float can hold what the layout stores. */
static vr_status check_channel(const exr_attr_chlist_entry_t *e, const char *name, vr_error *err) {
  if (e->pixel_type != EXR_PIXEL_HALF && e->pixel_type != EXR_PIXEL_FLOAT)
    return vr_error_at(err, VR_E_PARSE, name, 0, 0,
                       "channel %s holds unsigned integers; half or float needed", e->name.str);
  if (e->x_sampling != 1 || e->y_sampling != 1)
    return vr_error_at(err, VR_E_PARSE, name, 0, 0,
                       "channel %s is subsampled (%d x %d); full resolution needed", e->name.str,
                       e->x_sampling, e->y_sampling);
  return VR_OK;
}

/* The reference reader only warns about another version; a later major
 * version may name things differently, so here it stops. */
static vr_status check_version(exr_context_t ctxt, const char *name, vr_error *err) {
  const exr_attribute_t *a = NULL;
  if (exr_get_attribute_by_name(ctxt, 0, "spectralLayoutVersion", &a) != EXR_ERR_SUCCESS || !a)
    return VR_OK; /* absent: files of other writers may leave it out */
  if (a->type != EXR_ATTR_STRING || !a->string || !a->string->str)
    return vr_error_at(err, VR_E_PARSE, name, 0, 0,
                       "attribute spectralLayoutVersion is not a string");
  const char *v = a->string->str;
  int n = a->string->length;
  if (n >= 1 && v[0] == '1' && (n == 1 || v[1] == '.')) return VR_OK;
  return vr_error_at(err, VR_E_PARSE, name, 0, 0,
                     "spectralLayoutVersion is '%.*s'; only version 1 of the layout is read",
                     n > 64 ? 64 : (n < 0 ? 0 : n), v);
}

typedef struct layout {
  band *bands;
  size_t nbands;
  vr_spectral_kind kind;
  int rgb[3]; /* channel indices of R, G, B, or -1 when not read */
} layout;

static vr_status find_layout(const exr_attr_chlist_t *ch, const char *name, int want_rgb,
                             layout *lay, vr_error *err) {
  lay->bands = malloc((size_t)(ch->num_channels > 0 ? ch->num_channels : 1) * sizeof(band));
  if (!lay->bands) return vr_error_at(err, VR_E_NOMEM, name, 0, 0, "out of memory");
  lay->nbands = 0;
  int first_s0 = -1, first_t = -1;
  for (int i = 0; i < ch->num_channels; i++) {
    const exr_attr_chlist_entry_t *e = &ch->entries[i];
    double nm = 0;
    channel_class k = vr_spectral_classify(e->name.str, &nm);
    if (k == CH_MALFORMED)
      return vr_error_at(err, VR_E_PARSE, name, 0, 0,
                         "channel '%s' is not a spectral channel name of the layout (S0..S3 or "
                         "T, a dot, a number with a decimal comma, a unit: S0.550,000000nm, "
                         "T.550,000000nm)", e->name.str);
    if (k != CH_EMISSIVE && k != CH_REFLECTIVE) continue;
    int *first = k == CH_EMISSIVE ? &first_s0 : &first_t;
    if (*first < 0) *first = i;
    vr_status st = check_channel(e, name, err);
    if (st != VR_OK) return st;
    lay->bands[lay->nbands].nm = nm;
    lay->bands[lay->nbands].channel = i;
    lay->nbands++;
  }
  if (first_s0 >= 0 && first_t >= 0)
    return vr_error_at(err, VR_E_PARSE, name, 0, 0,
                       "both emissive (%s) and reflective (%s) spectral channels; one image holds "
                       "one kind", ch->entries[first_s0].name.str, ch->entries[first_t].name.str);
  if (lay->nbands == 0)
    return vr_error_at(err, VR_E_PARSE, name, 0, 0,
                       "no spectral channels (named like S0.550,000000nm or T.550,000000nm) among "
                       "its %d channels", ch->num_channels);
  lay->kind = first_s0 >= 0 ? VR_SPECTRAL_EMISSIVE : VR_SPECTRAL_REFLECTIVE;
  qsort(lay->bands, lay->nbands, sizeof(band), band_cmp);
  for (size_t b = 1; b < lay->nbands; b++)
    if (lay->bands[b].nm == lay->bands[b - 1].nm)
      return vr_error_at(err, VR_E_PARSE, name, 0, 0,
                         "channels '%s' and '%s' have the same wavelength (%.9g nm)",
                         ch->entries[lay->bands[b - 1].channel].name.str,
                         ch->entries[lay->bands[b].channel].name.str, lay->bands[b].nm);
  lay->rgb[0] = lay->rgb[1] = lay->rgb[2] = -1;
  if (want_rgb) {
    int idx[3] = {vr_exr_find_channel(ch, "R"), vr_exr_find_channel(ch, "G"), vr_exr_find_channel(ch, "B")};
    if (idx[0] >= 0 && idx[1] >= 0 && idx[2] >= 0)
      for (int c = 0; c < 3; c++) {
        vr_status st = check_channel(&ch->entries[idx[c]], name, err);
        if (st != VR_OK) return st;
        lay->rgb[c] = idx[c];
      }
  }
  return VR_OK;
}

/* Every chunk is located before any pixel memory is taken: a cut file
 * fails here, with OpenEXR's own words, whatever its header claims. */
static vr_status check_chunks(exr_context_t ctxt, const char *name, const exr_stream *s,
                              exr_attr_box2i_t dw, int32_t lines, vr_error *err) {
  for (int64_t y = dw.min.y; y <= dw.max.y; y += lines) {
    exr_chunk_info_t cinfo;
    exr_result_t rv = exr_read_scanline_chunk_info(ctxt, 0, (int)y, &cinfo);
    if (rv != EXR_ERR_SUCCESS) {
      char doing[64];
      snprintf(doing, sizeof doing, "truncated or corrupt at the chunk of line %" PRId64, y);
      return vr_exr_read_failed(err, name, s, rv, doing);
    }
  }
  return VR_OK;
}

static vr_status decode_pixels(exr_context_t ctxt, const char *name, const exr_stream *s,
                               exr_attr_box2i_t dw, int32_t lines, const layout *lay,
                               const exr_attr_chlist_t *ch, vr_spectral_image *out, vr_image *rgb,
                               vr_error *err) {
  /* Channel list index -> destination, built once; the decoder's channels
   * follow the channel list. */
  int32_t *dest = malloc((size_t)ch->num_channels * sizeof *dest);
  if (!dest) return vr_error_at(err, VR_E_NOMEM, name, 0, 0, "out of memory");
  for (int i = 0; i < ch->num_channels; i++) dest[i] = SKIP;
  for (size_t b = 0; b < lay->nbands; b++) dest[lay->bands[b].channel] = (int32_t)b;
  for (int c = 0; c < 3; c++)
    if (lay->rgb[c] >= 0) dest[lay->rgb[c]] = -1 - c;

  exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
  int started = 0;
  vr_status st = VR_OK;
  const size_t nb = out->nbands, w = (size_t)out->width;
  for (int64_t y = dw.min.y; y <= dw.max.y && st == VR_OK; y += lines) {
    exr_chunk_info_t cinfo;
    exr_result_t rv = exr_read_scanline_chunk_info(ctxt, 0, (int)y, &cinfo);
    if (rv == EXR_ERR_SUCCESS)
      rv = started ? exr_decoding_update(ctxt, 0, &cinfo, &dec)
                   : exr_decoding_initialize(ctxt, 0, &cinfo, &dec);
    if (rv != EXR_ERR_SUCCESS) {
      st = vr_exr_read_failed(err, name, s, rv, "reading the scanlines");
      break;
    }
    const size_t row = (size_t)(cinfo.start_y - dw.min.y);
    for (int c = 0; c < dec.channel_count; c++) {
      exr_coding_channel_info_t *ci = &dec.channels[c];
      int i = c < ch->num_channels && strcmp(ch->entries[c].name.str, ci->channel_name) == 0
                  ? c
                  : vr_exr_find_channel(ch, ci->channel_name);
      int32_t d = i < 0 ? SKIP : dest[i];
      if (d == SKIP) {
        ci->decode_to_ptr = NULL;
      } else if (d >= 0) {
        ci->decode_to_ptr = (uint8_t *)(out->data + row * w * nb + (size_t)d);
        ci->user_pixel_stride = (int32_t)(nb * sizeof(float));
        ci->user_line_stride = (int32_t)(w * nb * sizeof(float));
      } else {
        ci->decode_to_ptr = (uint8_t *)(rgb->data + row * w * 3 + (size_t)(-1 - d));
        ci->user_pixel_stride = 3 * (int32_t)sizeof(float);
        ci->user_line_stride = (int32_t)(w * 3 * sizeof(float));
      }
      ci->user_bytes_per_element = (int16_t)sizeof(float);
      ci->user_data_type = EXR_PIXEL_FLOAT;
    }
    if (!started) {
      started = 1;
      rv = exr_decoding_choose_default_routines(ctxt, 0, &dec);
    }
    if (rv == EXR_ERR_SUCCESS) rv = exr_decoding_run(ctxt, 0, &dec);
    if (rv != EXR_ERR_SUCCESS) st = vr_exr_read_failed(err, name, s, rv, "decoding the scanlines");
  }
  if (started) exr_decoding_destroy(ctxt, &dec);
  free(dest);
  return st;
}

static vr_status read_context(exr_context_t ctxt, const char *name, const exr_stream *s,
                              vr_spectral_image *out, vr_image *rgb, vr_error *err) {
  exr_storage_t storage;
  exr_result_t rv = exr_get_storage(ctxt, 0, &storage);
  if (rv != EXR_ERR_SUCCESS) return vr_exr_read_failed(err, name, s, rv, "storage type");
  if (storage != EXR_STORAGE_SCANLINE)
    return vr_error_at(err, VR_E_PARSE, name, 0, 0,
                       "OpenEXR: only scanline images are read, this one is %s",
                       storage == EXR_STORAGE_TILED ? "tiled" : "deep");
  exr_attr_box2i_t dw;
  const exr_attr_chlist_t *ch = NULL;
  int32_t lines = 0;
  if ((rv = exr_get_data_window(ctxt, 0, &dw)) != EXR_ERR_SUCCESS)
    return vr_exr_read_failed(err, name, s, rv, "data window");
  if ((rv = exr_get_channels(ctxt, 0, &ch)) != EXR_ERR_SUCCESS || !ch)
    return vr_exr_read_failed(err, name, s, rv, "channel list");
  if ((rv = exr_get_scanlines_per_chunk(ctxt, 0, &lines)) != EXR_ERR_SUCCESS || lines < 1)
    return vr_exr_read_failed(err, name, s, rv, "chunk layout");
  vr_status st = check_version(ctxt, name, err);
  if (st != VR_OK) return st;
  layout lay = {0};
  st = find_layout(ch, name, rgb != NULL, &lay, err);
  if (st != VR_OK) {
    free(lay.bands);
    return st;
  }
  /* As image_exr.c: no more than 2^30 pixels, whatever the header says.
   * And no more pixel memory than the file could decompress to: zlib's
   * ratio tops out near 1032:1, the other codecs' below, so 4096 times the
   * file's size (with 64 MiB always allowed) is only ever passed by a
   * header that lies, which must not cost gigabytes of memory to find. */
  int64_t w = (int64_t)dw.max.x - dw.min.x + 1, h = (int64_t)dw.max.y - dw.min.y + 1;
  uint64_t floats = 0;
  if (w >= 1 && h >= 1 && w <= INT32_MAX && h <= INT32_MAX && w * h <= ((int64_t)1 << 30))
    floats = (uint64_t)(w * h) * (lay.nbands + (lay.rgb[0] >= 0 ? 3 : 0));
  if (floats == 0)
    st = vr_error_at(err, VR_E_PARSE, name, 0, 0,
                     "OpenEXR: data window (%d,%d)-(%d,%d) is empty or larger than 2^30 pixels",
                     dw.min.x, dw.min.y, dw.max.x, dw.max.y);
  else if (floats * sizeof(float) > ((uint64_t)64 << 20) &&
           floats * sizeof(float) / 4096 > (uint64_t)s->len)
    st = vr_error_at(err, VR_E_PARSE, name, 0, 0,
                     "OpenEXR: a %" PRId64 " x %" PRId64 " x %zu-band image cannot come from "
                     "%zu bytes; the header is corrupt", w, h, lay.nbands, s->len);
  else if ((uint64_t)w * lay.nbands > INT32_MAX / sizeof(float))
    st = vr_error_at(err, VR_E_PARSE, name, 0, 0,
                     "%" PRId64 " pixels x %zu bands per line is more than OpenEXR's strides hold",
                     w, lay.nbands);
  if (st == VR_OK) st = check_chunks(ctxt, name, s, dw, lines, err);
  if (st == VR_OK) {
    double *wl = malloc(lay.nbands * sizeof *wl);
    if (!wl) {
      st = vr_error_at(err, VR_E_NOMEM, name, 0, 0, "out of memory");
    } else {
      for (size_t b = 0; b < lay.nbands; b++) wl[b] = lay.bands[b].nm;
      st = vr_spectral_image_alloc(out, (int)w, (int)h, lay.nbands, wl, lay.kind, err);
      free(wl);
      if (st == VR_OK && lay.rgb[0] >= 0) st = vr_image_alloc(rgb, (int)w, (int)h, err);
      if (st != VR_OK) vr_error_prefix(err, "%s: ", name);
    }
  }
  if (st == VR_OK) st = decode_pixels(ctxt, name, s, dw, lines, &lay, ch, out, rgb, err);
  free(lay.bands);
  return st;
}

vr_status vr_spectral_exr_read_memory(const void *buf, size_t len, const char *name,
                                      vr_spectral_image *out, vr_image *rgb_or_null,
                                      vr_error *err) {
  if (!out) return vr_error_set(err, VR_E_ARG, "vr_spectral_exr_read: output image is NULL");
  memset(out, 0, sizeof *out);
  if (rgb_or_null) memset(rgb_or_null, 0, sizeof *rgb_or_null);
  if (!name) name = "memory";
  if (!buf && len > 0) return vr_error_set(err, VR_E_ARG, "%s: buffer is NULL", name);
  static const unsigned char magic[4] = {0x76, 0x2F, 0x31, 0x01};
  if (len < 4 || memcmp(buf, magic, 4) != 0)
    return vr_error_at(err, VR_E_PARSE, name, 0, 0, "not an OpenEXR file (no magic number)");
  exr_stream s = {.buf = buf, .len = len};
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.user_data = &s;
  init.read_fn = vr_exr_stream_read;
  init.size_fn = vr_exr_stream_size;
  init.error_handler_fn = vr_exr_on_read_error;
  /* A cut file should fail, not be half-rebuilt from whatever chunks remain. */
  init.flags = EXR_CONTEXT_FLAG_DISABLE_CHUNK_RECONSTRUCTION;
  exr_context_t ctxt = NULL;
  exr_result_t rv = exr_start_read(&ctxt, name, &init);
  vr_status st = rv == EXR_ERR_SUCCESS ? read_context(ctxt, name, &s, out, rgb_or_null, err)
                                       : vr_exr_read_failed(err, name, &s, rv, "header");
  if (ctxt) exr_finish(&ctxt);
  if (st != VR_OK) {
    vr_spectral_image_free(out);
    vr_image_free(rgb_or_null);
  }
  return st;
}

vr_status vr_spectral_exr_read(const char *path, vr_spectral_image *out, vr_image *rgb_or_null,
                               vr_error *err) {
  if (!out) return vr_error_set(err, VR_E_ARG, "vr_spectral_exr_read: output image is NULL");
  memset(out, 0, sizeof *out);
  if (rgb_or_null) memset(rgb_or_null, 0, sizeof *rgb_or_null);
  if (!path) return vr_error_set(err, VR_E_ARG, "vr_spectral_exr_read: path is NULL");
  char *buf = NULL;
  size_t len = 0;
  vr_status st = vr_read_file(path, 0, &buf, &len, err);
  if (st != VR_OK) return st;
  st = vr_spectral_exr_read_memory(buf, len, path, out, rgb_or_null, err);
  free(buf);
  return st;
}
