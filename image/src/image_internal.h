/* What the files of image/src share and nobody else sees: the codec entry
 * points (OpenCV in the module of image_cv.cpp, reached through
 * image_codecs.c; OpenEXR in image_exr.c). */
#ifndef VR_IMAGE_INTERNAL_H
#define VR_IMAGE_INTERNAL_H

#include <stddef.h>

#include "vr/image.h"

#ifdef __cplusplus
extern "C" {
#endif

/* What a decoder keeps besides RGB floats (the keep argument, bits). */
enum {
  VR_IMAGE_KEEP_CODES = 1, /* 8- and 16-bit files as codes (vr_image.codes) */
  VR_IMAGE_KEEP_ALPHA = 2  /* the alpha values (vr_image.alpha_data); with floats only */
};

/* Decodes a PNG, TIFF or JPEG held in memory (format names it in messages);
 * keep: VR_IMAGE_KEEP_* bits.
 * This and vr_image_encode_cv load the OpenCV module on first use; VR_E_IO
 * naming path and the module's paths when it cannot be loaded. */
vr_status vr_image_decode_cv(const unsigned char *buf, size_t len, const char *path,
                             const char *format, int keep, vr_image *out, vr_error *err);

/* malloc for pixel buffers, offering large ones to transparent huge pages
 * (image.c); freed with free(). */
void *vr_image_pixels_alloc(size_t bytes);

/* Encodes img for ext (".png", ".tif", ".jpg") at 8 or 16 bits, values
 * clamped to [0,1] and rounded; *bytes is malloc'ed and owned by the caller. */
vr_status vr_image_encode_cv(const vr_image *img, const char *path, const char *ext, int bits,
                             unsigned char **bytes, size_t *len, vr_error *err);

/* Decodes an OpenEXR file held in memory with the OpenEXR core C API. */
vr_status vr_image_decode_exr(const unsigned char *buf, size_t len, const char *path,
                              int keep, vr_image *out, vr_error *err);

/* The check of a vr_exr_colour (exr_colour.c): VR_E_ARG naming path and
 * the value at fault; NULL is fine. */
vr_status vr_exr_colour_check(const char *path, const vr_exr_colour *c, vr_error *err);

/* Writes an RGB OpenEXR of float (half = 0) or half (half = 1) channels,
 * with the attributes of colour (NULL: none; checked by the caller). */
vr_status vr_image_write_exr_as(const char *path, const vr_image *img, int half,
                                const vr_exr_colour *colour, const vr_exr_channel *extra,
                                size_t nextra, vr_error *err);

#ifdef __cplusplus
}
#endif
#endif
