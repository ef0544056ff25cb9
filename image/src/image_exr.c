/* OpenEXR through the OpenEXR 3 core C API (openexr.h), not OpenCV: Debian
 * builds OpenCV with its EXR codec switched off, and the C API keeps C++ out
 * of this file.  Reading goes through a memory stream (image.c has the whole
 * file already) whose user data also catches OpenEXR's first error message,
 * so the message can name the file instead of being printed to stderr.
 * Writing goes through a stream onto a vr_atomic_file, so the EXR appears
 * whole or not at all like every other output. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <openexr.h>

#include "exr_stream.h"

#include "image_internal.h"
#include "vr/atomic_file.h"



/* Decodes the colour channels into out and, when alpha is not NULL, the
 * channel A into alpha (width x height floats). */
static vr_status decode_pixels(exr_context_t ctxt, const char *path, const exr_stream *s,
                               exr_attr_box2i_t dw, int grey, vr_image *out, float *alpha,
                               vr_error *err) {
  int32_t lines = 0;
  exr_result_t rv = exr_get_scanlines_per_chunk(ctxt, 0, &lines);
  if (rv != EXR_ERR_SUCCESS || lines < 1) return vr_exr_read_failed(err, path, s, rv, "chunk layout");
  exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
  int started = 0;
  vr_status st = VR_OK;
  const int w = out->width;
  for (int64_t y = dw.min.y; y <= dw.max.y && st == VR_OK; y += lines) {
    exr_chunk_info_t cinfo;
    rv = exr_read_scanline_chunk_info(ctxt, 0, (int)y, &cinfo);
    if (rv == EXR_ERR_SUCCESS)
      rv = started ? exr_decoding_update(ctxt, 0, &cinfo, &dec)
                   : exr_decoding_initialize(ctxt, 0, &cinfo, &dec);
    if (rv != EXR_ERR_SUCCESS) {
      st = vr_exr_read_failed(err, path, s, rv, "reading the scanlines");
      break;
    }
    const size_t first = (size_t)(cinfo.start_y - dw.min.y) * (size_t)w;
    float *row = out->data + first * 3;
    for (int c = 0; c < dec.channel_count; c++) {
      exr_coding_channel_info_t *ci = &dec.channels[c];
      const char *n = ci->channel_name;
      int k = grey ? (strcmp(n, "Y") == 0 ? 0 : -1)
                   : strcmp(n, "R") == 0 ? 0 : strcmp(n, "G") == 0 ? 1 : strcmp(n, "B") == 0 ? 2 : -1;
      if (alpha && strcmp(n, "A") == 0) {
        ci->decode_to_ptr = (uint8_t *)(alpha + first);
        ci->user_pixel_stride = (int32_t)sizeof(float);
        ci->user_line_stride = (int32_t)sizeof(float) * w;
      } else {
        ci->decode_to_ptr = k < 0 ? NULL : (uint8_t *)(row + k);
        ci->user_pixel_stride = 3 * (int32_t)sizeof(float);
        ci->user_line_stride = 3 * (int32_t)sizeof(float) * w;
      }
      ci->user_bytes_per_element = (int16_t)sizeof(float);
      ci->user_data_type = EXR_PIXEL_FLOAT;
    }
    if (!started) {
      started = 1;
      rv = exr_decoding_choose_default_routines(ctxt, 0, &dec);
    }
    if (rv == EXR_ERR_SUCCESS) rv = exr_decoding_run(ctxt, 0, &dec);
    if (rv != EXR_ERR_SUCCESS) st = vr_exr_read_failed(err, path, s, rv, "decoding the scanlines");
  }
  if (started) exr_decoding_destroy(ctxt, &dec);
  if (st == VR_OK && grey) {
    size_t n = (size_t)w * (size_t)out->height;
    for (size_t i = 0; i < n; i++) out->data[3 * i + 1] = out->data[3 * i + 2] = out->data[3 * i];
  }
  return st;
}

static vr_status read_context(exr_context_t ctxt, const char *path, const exr_stream *s,
                              int keep, vr_image *out, vr_error *err) {
  exr_storage_t storage;
  exr_result_t rv = exr_get_storage(ctxt, 0, &storage);
  if (rv != EXR_ERR_SUCCESS) return vr_exr_read_failed(err, path, s, rv, "storage type");
  if (storage != EXR_STORAGE_SCANLINE)
    return vr_error_at(err, VR_E_PARSE, path, 0, 0,
                       "OpenEXR: only scanline images are read, this one is %s",
                       storage == EXR_STORAGE_TILED ? "tiled" : "deep");
  exr_attr_box2i_t dw;
  const exr_attr_chlist_t *ch = NULL;
  if ((rv = exr_get_data_window(ctxt, 0, &dw)) != EXR_ERR_SUCCESS)
    return vr_exr_read_failed(err, path, s, rv, "data window");
  if ((rv = exr_get_channels(ctxt, 0, &ch)) != EXR_ERR_SUCCESS || !ch)
    return vr_exr_read_failed(err, path, s, rv, "channel list");
  int idx[3] = {vr_exr_find_channel(ch, "R"), vr_exr_find_channel(ch, "G"), vr_exr_find_channel(ch, "B")};
  int grey = 0;
  if (idx[0] < 0 || idx[1] < 0 || idx[2] < 0) {
    int y = vr_exr_find_channel(ch, "Y");
    if (y < 0)
      return vr_error_at(err, VR_E_PARSE, path, 0, 0,
                         "OpenEXR: no R, G and B channels (nor a Y channel) among its %d "
                         "channels", ch->num_channels);
    grey = 1;
    idx[0] = idx[1] = idx[2] = y;
  }
  /* A is the alpha channel of an EXR (Technical Introduction to OpenEXR:
   * "A", with the colour premultiplied by it); checked like the colour so
   * that it can be decoded beside them. */
  const int a_index = vr_exr_find_channel(ch, "A");
  for (int k = 0; k < 4; k++) {
    if (k == 3 && a_index < 0) break;
    const exr_attr_chlist_entry_t *e = &ch->entries[k == 3 ? a_index : idx[k]];
    if (e->pixel_type != EXR_PIXEL_HALF && e->pixel_type != EXR_PIXEL_FLOAT)
      return vr_error_at(err, VR_E_PARSE, path, 0, 0,
                         "OpenEXR: channel %s holds unsigned integers; half or float needed",
                         e->name.str);
    if (e->x_sampling != 1 || e->y_sampling != 1)
      return vr_error_at(err, VR_E_PARSE, path, 0, 0,
                         "OpenEXR: channel %s is subsampled (%d x %d); full resolution needed",
                         e->name.str, e->x_sampling, e->y_sampling);
  }
  /* A header is a few bytes and can claim any size: refuse more pixels than
   * OpenCV's own reader accepts (CV_IO_MAX_IMAGE_PIXELS, 2^30) rather than
   * try to allocate them. */
  int64_t w = (int64_t)dw.max.x - dw.min.x + 1, h = (int64_t)dw.max.y - dw.min.y + 1;
  if (w < 1 || h < 1 || w > INT32_MAX || h > INT32_MAX || w * h > ((int64_t)1 << 30))
    return vr_error_at(err, VR_E_PARSE, path, 0, 0,
                       "OpenEXR: data window (%d,%d)-(%d,%d) is empty or larger than 2^30 "
                       "pixels", dw.min.x, dw.min.y, dw.max.x, dw.max.y);
  vr_status st = vr_image_alloc(out, (int)w, (int)h, err);
  if (st != VR_OK) {
    vr_error_prefix(err, "%s: ", path);
    return st;
  }
  float *alpha = NULL;
  if (a_index >= 0 && !(alpha = malloc((size_t)w * (size_t)h * sizeof *alpha)))
    return vr_error_at(err, VR_E_NOMEM, path, 0, 0, "out of memory for the alpha channel");
  st = decode_pixels(ctxt, path, s, dw, grey, out, alpha, err);
  if (st == VR_OK && alpha) {
    long below = 0;
    for (size_t i = 0; i < (size_t)w * (size_t)h; i++)
      if (!(alpha[i] >= 1.0f)) below++;
    out->alpha = 1;
    out->transparent = below;
    if (keep & VR_IMAGE_KEEP_ALPHA) out->alpha_data = alpha, alpha = NULL;
  }
  free(alpha);
  return st;
}

vr_status vr_image_decode_exr(const unsigned char *buf, size_t len, const char *path,
                              int keep, vr_image *out, vr_error *err) {
  memset(out, 0, sizeof *out);
  exr_stream s = {.buf = buf, .len = len};
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.user_data = &s;
  init.read_fn = vr_exr_stream_read;
  init.size_fn = vr_exr_stream_size;
  init.error_handler_fn = vr_exr_on_read_error;
  /* A cut file should fail, not be half-rebuilt from whatever chunks remain. */
  init.flags = EXR_CONTEXT_FLAG_DISABLE_CHUNK_RECONSTRUCTION;
  exr_context_t ctxt = NULL;
  exr_result_t rv = exr_start_read(&ctxt, path, &init);
  vr_status st = rv == EXR_ERR_SUCCESS ? read_context(ctxt, path, &s, keep, out, err)
                                       : vr_exr_read_failed(err, path, &s, rv, "header");
  if (ctxt) exr_finish(&ctxt);
  if (st != VR_OK) {
    vr_image_free(out);
    return st;
  }
  out->bit_depth = 32;
  return VR_OK;
}

static exr_result_t encode_pixels(exr_context_t ctxt, int part, const vr_image *img,
                                  const vr_exr_channel *extra, size_t nextra) {
  int32_t lines = 0;
  exr_result_t rv = exr_get_scanlines_per_chunk(ctxt, part, &lines);
  if (rv != EXR_ERR_SUCCESS) return rv;
  exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
  int started = 0;
  for (int y = 0; y < img->height && rv == EXR_ERR_SUCCESS; y += lines) {
    exr_chunk_info_t cinfo;
    rv = exr_write_scanline_chunk_info(ctxt, part, y, &cinfo);
    if (rv == EXR_ERR_SUCCESS)
      rv = started ? exr_encoding_update(ctxt, part, &cinfo, &enc)
                   : exr_encoding_initialize(ctxt, part, &cinfo, &enc);
    if (rv != EXR_ERR_SUCCESS) break;
    const float *row = img->data + (size_t)y * (size_t)img->width * 3;
    for (int c = 0; c < enc.channel_count; c++) {
      exr_coding_channel_info_t *ci = &enc.channels[c];
      const char *n = ci->channel_name;
      const vr_exr_channel *x = NULL;
      for (size_t e = 0; e < nextra && !x; e++)
        if (!strcmp(n, extra[e].name)) x = &extra[e];
      if (x) {
        /* 4 bytes a value either way: uint32 or float. */
        const unsigned char *base = x->data;
        ci->encode_from_ptr = base + (size_t)y * (size_t)img->width * 4;
        ci->user_pixel_stride = 4;
        ci->user_line_stride = 4 * img->width;
        ci->user_bytes_per_element = 4;
        ci->user_data_type = x->is_uint ? EXR_PIXEL_UINT : EXR_PIXEL_FLOAT;
        continue;
      }
      int k = strcmp(n, "R") == 0 ? 0 : strcmp(n, "G") == 0 ? 1 : 2;
      ci->encode_from_ptr = (const uint8_t *)(row + k);
      ci->user_pixel_stride = 3 * (int32_t)sizeof(float);
      ci->user_line_stride = 3 * (int32_t)sizeof(float) * img->width;
      ci->user_bytes_per_element = (int16_t)sizeof(float);
      ci->user_data_type = EXR_PIXEL_FLOAT;
    }
    if (!started) {
      started = 1;
      rv = exr_encoding_choose_default_routines(ctxt, part, &enc);
      if (rv == EXR_ERR_SUCCESS) rv = vr_exr_guard_zip(ctxt, part, &enc);
    }
    if (rv == EXR_ERR_SUCCESS) rv = exr_encoding_run(ctxt, part, &enc);
  }
  if (started) exr_encoding_destroy(ctxt, &enc);
  return rv;
}

vr_status vr_image_write_exr_as(const char *path, const vr_image *img, int half,
                                const vr_exr_colour *colour, const vr_exr_channel *extra,
                                size_t nextra, vr_error *err) {
  vr_atomic_file af;
  vr_status st = vr_atomic_file_open(&af, path, err);
  if (st != VR_OK) return st;
  exr_stream s = {.fp = af.fp, .af = &af};
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.user_data = &s;
  init.write_fn = vr_exr_stream_write;
  init.error_handler_fn = vr_exr_on_write_error;
  exr_context_t ctxt = NULL;
  int part = 0;
  const exr_pixel_type_t type = half ? EXR_PIXEL_HALF : EXR_PIXEL_FLOAT;
  exr_result_t rv = exr_start_write(&ctxt, path, EXR_WRITE_FILE_DIRECTLY, &init);
  if (rv == EXR_ERR_SUCCESS) rv = exr_add_part(ctxt, NULL, EXR_STORAGE_SCANLINE, &part);
  if (rv == EXR_ERR_SUCCESS)
    rv = exr_initialize_required_attr_simple(ctxt, part, img->width, img->height,
                                             EXR_COMPRESSION_ZIP);
  static const char *const names[3] = {"R", "G", "B"};
  for (int k = 0; k < 3 && rv == EXR_ERR_SUCCESS; k++)
    rv = exr_add_channel(ctxt, part, names[k], type, EXR_PERCEPTUALLY_LINEAR, 1, 1);
  for (size_t e = 0; e < nextra && rv == EXR_ERR_SUCCESS; e++)
    rv = exr_add_channel(ctxt, part, extra[e].name, extra[e].is_uint ? EXR_PIXEL_UINT : EXR_PIXEL_FLOAT,
                         EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1); /* not colour: no pLinear hint */
  if (rv == EXR_ERR_SUCCESS) rv = vr_exr_colour_set(ctxt, part, colour);
  if (rv == EXR_ERR_SUCCESS) rv = exr_write_header(ctxt);
  if (rv == EXR_ERR_SUCCESS) rv = encode_pixels(ctxt, part, img, extra, nextra);
  if (ctxt) {
    /* exr_finish writes the chunk offset table: its result counts too. */
    exr_result_t fin = exr_finish(&ctxt);
    if (rv == EXR_ERR_SUCCESS) rv = fin;
  }
  if (rv != EXR_ERR_SUCCESS || s.write_errno) {
    vr_atomic_file_abort(&af);
    if (s.write_errno)
      return vr_error_at(err, VR_E_IO, path, 0, 0, "write failed: %s", strerror(s.write_errno));
    return vr_error_at(err, VR_E_IO, path, 0, 0, "OpenEXR could not write the image: %s",
                       exr_get_default_error_message(rv));
  }
  return vr_atomic_file_commit(&af, err);
}
