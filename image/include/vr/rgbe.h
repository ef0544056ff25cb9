/* Radiance pictures (.hdr, .pic): Greg Ward's RGBE format as Radiance's
 * tools write and read it (Ward, "Real Pixels", Graphics Gems II, 1991;
 * Radiance's src/common/color.c and header.c):
 *
 *   #?RADIANCE
 *   FORMAT=32-bit_rle_rgbe
 *   EXPOSURE=e           (pixels = radiance x e; several lines multiply)
 *   PRIMARIES=rx ry gx gy bx by wx wy
 *   VIEW= -vtv -vp ... (the view's options, as rpict takes them)
 *   <empty line>
 *   -Y H +X W            (rows from the top, pixels left to right)
 *
 * then H scanlines, each 4 bytes a pixel (a shared exponent e - 128 and
 * three 8-bit mantissas: value = (m + 0.5) 2^(e-136)), written with the
 * "new" run-length encoding (2, 2, W/256, W%256, then each of the four
 * components in runs) when 8 <= W < 32768, else flat.  The reader takes
 * both, and refuses what it cannot read with the file, the line or
 * scanline, and why: another FORMAT (XYZE), another orientation, the old
 * run-length encoding, a file cut short. */
#ifndef VR_RGBE_H
#define VR_RGBE_H

#include <stdbool.h>

#include "vr/error.h"
#include "vr/image.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vr_rgbe_header {
  double exposure;       /* EXPOSURE= written when > 0 */
  const char *view;      /* VIEW= options, or NULL for none */
  const char *software;  /* SOFTWARE=, or NULL */
  /* PRIMARIES= rx ry gx gy bx by wx wy; all zero: none written (Radiance's
   * standard primaries are then assumed by its tools). */
  double primaries[8];
} vr_rgbe_header;

/* Writes img (RGB floats; negative values as 0) to path.  A NaN or an
 * infinity is VR_E_RANGE naming the pixel, and nothing is written. */
vr_status vr_rgbe_write(const char *path, const vr_image *img, const vr_rgbe_header *h,
                        vr_error *err);

/* What a picture's header said (vr_rgbe_read). */
typedef struct vr_rgbe_info {
  double exposure;    /* the product of its EXPOSURE lines, 1 without */
  char view[512];     /* its last VIEW= line's options, "" without */
  bool has_primaries;
  double primaries[8];
} vr_rgbe_info;

/* Reads a Radiance picture into out (pixel values as stored: divide by
 * info->exposure for radiance).  info may be NULL. */
vr_status vr_rgbe_read(const char *path, vr_image *out, vr_rgbe_info *info, vr_error *err);

#ifdef __cplusplus
}
#endif

#endif
