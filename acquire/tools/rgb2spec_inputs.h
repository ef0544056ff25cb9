/* vr-rgb2spec's checks of each photo once read: what the file format and
 * the manifest line say about how far its pixel values can be trusted. */
#ifndef VR_RGB2SPEC_INPUTS_H
#define VR_RGB2SPEC_INPUTS_H

#include <stdbool.h>
#include <stdio.h>
#include "vr/args.h"
#include "vr/error.h"
#include "vr/image.h"
#include "vr/manifest.h"
#include "vr/out_guard.h"

/* Checks photo p of capture cap, read into img (vr_image_read):
 *  - refuses (VR_E_ARG) a photo with pixels that are not fully opaque,
 *    naming the file, the count and what to do (flatten it onto the scene,
 *    or remove the alpha channel; for OpenEXR, that its colour is
 *    premultiplied by alpha);
 *  - notes on notes ("vr-rgb2spec: note: PATH: ...") an alpha channel
 *    whose every pixel is opaque: it is ignored;
 *  - warns ("vr-rgb2spec: warning: PATH: ...") for a JPEG (lossy: blocks
 *    and chroma subsampling bleed colour across patch edges) and for a
 *    16-bit photo decoded as sRGB by default (rg_encoding_hint).
 * notes may be NULL (nothing is written).  Each note or warning is one
 * line. */
vr_status rg_check_photo(const vr_capture *cap, const vr_capture_photo *p, const vr_image *img,
                         FILE *notes, vr_error *err);

/* The hint for a 16-bit integer photo that is decoded as sRGB only by
 * default (no encoding= on its photo line, no stored tone curves for the
 * camera): raw converters usually write 16-bit files linear.  A constant
 * sentence for a failure message (no file name, no line), or NULL when the
 * photo is not such a case. */
const char *rg_encoding_hint(const vr_capture *cap, const vr_capture_photo *p, const vr_image *img);

/* Records in g every file the capture reads, for vr_out_guard_check: the
 * manifest (unless it came from a stream), every photo it lists (unless
 * photos is false: simulate writes them), its labels image, and the file:
 * camera, lights and references (relative to the manifest's folder, as the
 * manifest reader resolves them). */
void rg_guard_capture(vr_out_guard *g, const vr_capture *cap, bool photos);

#endif
