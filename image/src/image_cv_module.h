/* The interface between vr_image and its OpenCV module (vr-image-cv.so,
 * image_cv.cpp): PNG, TIFF and JPEG are coded by OpenCV, whose libraries
 * are some hundred shared objects and a tenth of a second or more of
 * start-up, so they are loaded with dlopen the first time such a file is
 * read or written (image_codecs.c) instead of being linked into every
 * program that uses vr_image.  A render that writes only OpenEXR never
 * loads them.
 *
 * The module exports one symbol, VR_IMAGE_CV_ENTRY, returning its table.
 * It links nothing of this project: what it needs of vr_image and vr_core
 * (allocation, errors) reaches it through the host table of each call, so
 * no symbol has to be exported from the executables.  VR_IMAGE_CV_ABI
 * changes whenever these structs or vr_image / vr_error change, so that a
 * module of another build is refused by name rather than misread. */
#ifndef VR_IMAGE_CV_MODULE_H
#define VR_IMAGE_CV_MODULE_H

#include <stddef.h>

#include "vr/image.h"

#ifdef __cplusplus
extern "C" {
#endif

#define VR_IMAGE_CV_ABI 2
#define VR_IMAGE_CV_ENTRY "vr_image_cv_module_codecs"

/* What the module may call back into: vr_image_pixels_alloc,
 * vr_image_alloc, vr_image_free, vr_error_at, vr_error_prefix. */
typedef struct vr_image_cv_host {
  void *(*pixels_alloc)(size_t bytes);
  vr_status (*image_alloc)(vr_image *img, int w, int h, vr_error *err);
  void (*image_free)(vr_image *img);
  vr_status (*error_at)(vr_error *err, vr_status status, const char *file, long line, long col,
                        const char *fmt, ...) __attribute__((format(printf, 6, 7)));
  void (*error_prefix)(vr_error *err, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
} vr_image_cv_host;

typedef struct vr_image_cv_codecs {
  int abi;             /* VR_IMAGE_CV_ABI of the module's build */
  size_t vr_image_size; /* sizeof(vr_image) there */
  size_t vr_error_size; /* sizeof(vr_error) there */
  /* What vr_image_decode_cv and vr_image_encode_cv (image_internal.h) do. */
  vr_status (*decode)(const vr_image_cv_host *host, const unsigned char *buf, size_t len,
                      const char *path, const char *format, int keep, vr_image *out,
                      vr_error *err);
  vr_status (*encode)(const vr_image_cv_host *host, const vr_image *img, const char *path,
                      const char *ext, int bits, unsigned char **bytes, size_t *len,
                      vr_error *err);
} vr_image_cv_codecs;

/* VR_IMAGE_CV_ENTRY, as the module defines it and dlsym finds it. */
const vr_image_cv_codecs *vr_image_cv_module_codecs(void);
typedef const vr_image_cv_codecs *(*vr_image_cv_entry)(void);

#ifdef __cplusplus
}
#endif
#endif
