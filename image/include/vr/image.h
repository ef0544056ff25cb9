/* Photographs as plain arrays of floats: reading and writing PNG, TIFF, JPEG
 * (through OpenCV, behind a C shim) and OpenEXR (through the OpenEXR 3 core C
 * API), and the means over rectangles and labelled regions that turn a photo
 * into numbers.  No OpenCV or OpenEXR type appears here.
 *
 * Pixel values: integer files are scaled to [0,1] (v/255 or v/65535, nothing
 * else: no gamma is removed, no white balance applied); float files (EXR,
 * 32-bit float TIFF) are kept as stored.  Images are always RGB: grey files are
 * expanded, OpenCV's BGR order is turned into RGB.  Alpha is not applied to the
 * colour, nor kept: the reader only records whether the file had it and how
 * many pixels it makes less than opaque (vr_image.alpha, .transparent), so a
 * caller can refuse what it cannot use.  EXIF orientation is not applied:
 * pixels are used as stored in the file.
 *
 * Integer codes: vr_image_read_codes keeps an 8- or 16-bit file as the codes
 * it holds (vr_image.codes; data is NULL), a quarter or a half of the memory
 * of floats and no conversion, for callers that look every code up in a
 * table anyway.  Code k stands for the value (float)k / 255 or / 65535,
 * exactly the float vr_image_read gives, so the region functions below
 * (vr_image_rect_mean, vr_image_label_means, vr_region_quad_stats, and the
 * chart functions of vr/chart.h) return the same numbers for either form.
 * Every other function, and any code reading .data, needs floats:
 * vr_image_check refuses an image of codes, vr_image_to_float converts one.
 *
 * Coordinates: x to the right, y down, (0,0) the top-left corner of the image.
 * Pixel (i, j) covers [i, i+1) x [j, j+1), so its centre is (i+0.5, j+0.5).
 *
 * Every function is thread-safe on distinct images. */
#ifndef VR_IMAGE_H
#define VR_IMAGE_H

#include "vr/error.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The kind of file an image was read from (vr_image.format). */
typedef enum vr_image_format {
  VR_IMAGE_FORMAT_NONE = 0, /* not read from a file (vr_image_alloc) */
  VR_IMAGE_FORMAT_PNG,
  VR_IMAGE_FORMAT_TIFF,
  VR_IMAGE_FORMAT_JPEG,
  VR_IMAGE_FORMAT_EXR
} vr_image_format;

typedef struct vr_image {
  int width, height;
  int channels;  /* always 3 */
  float *data;   /* row-major RGB: pixel (x,y) channel c at data[(y*width + x)*3 + c] */
  int bit_depth; /* of the file read: 8, 16, or 32 (float); vr_image_alloc sets 32 */
  int format;    /* a vr_image_format */
  /* 1 when the file carries transparency: an alpha channel (PNG grey+alpha
   * or RGBA, TIFF RGBA, an OpenEXR channel "A") or a PNG tRNS chunk (which
   * makes one colour, or palette entries, transparent); else 0. */
  int alpha;
  /* Pixels whose alpha is below fully opaque (255, 65535, or 1.0 for float
   * samples; a NaN alpha counts too); 0 when alpha is 0.  Their colour is
   * left as decoded: not premultiplied in PNG (PNG 1.2 spec, section 2.6),
   * premultiplied in OpenEXR by convention (Technical Introduction to
   * OpenEXR, "Premultiplied vs. Un-Premultiplied Color Channels"), and for
   * an 8-bit RGBA TIFF premultiplied by OpenCV's decoder (libtiff's RGBA
   * interface) whatever the file says. */
  long transparent;
  /* Only from vr_image_read_codes of an 8- or 16-bit file, else NULL: the
   * codes, row-major RGB like data, uint8_t (bit_depth 8) or uint16_t (16);
   * data is NULL then. */
  void *codes;
  /* Only from vr_image_read_alpha of a file with transparency, else NULL:
   * width x height alpha values, row-major (1 opaque; integer codes over
   * 255 or 65535; a PNG tRNS grey level gives 0 at that level, 1 elsewhere). */
  float *alpha_data;
} vr_image;

/* Allocates a w x h RGB image set to zero (bit_depth 32, format NONE,
 * alpha 0, transparent 0).  w, h >= 1. */
vr_status vr_image_alloc(vr_image *img, int w, int h, vr_error *err);
/* Frees the pixels and zeroes the struct; safe on a zeroed or freed image. */
void vr_image_free(vr_image *img);

/* Reads PNG, TIFF or JPEG (8 or 16 bit, grey, RGB or with alpha; TIFF may
 * also be 32-bit float) and OpenEXR (scanline, R,G,B or else Y channels,
 * half or float, and an alpha channel A; the first part of a multi-part
 * file; the image is its data window).  The format is told by the file's
 * first bytes, not its name; format, alpha and transparent are filled in.
 * A grey + alpha TIFF is refused (VR_E_PARSE): OpenCV would drop its alpha
 * and cut 16-bit samples to 8 bits.  An EXR alpha channel must be half or
 * float at full resolution, like the colour channels.
 * Errors name the path: VR_E_IO when it cannot be opened or read, VR_E_PARSE
 * when it is not an image of a supported kind, or is truncated or corrupt.
 * Truncation is checked before decoding where the format allows: a PNG must
 * hold its closing IEND chunk, a JPEG an end-of-image marker after its last
 * scan (libjpeg would otherwise fill the missing rows with grey and
 * succeed).  A 2 GiB file limit applies to PNG, TIFF and JPEG. */
vr_status vr_image_read(const char *path, vr_image *out, vr_error *err);

/* vr_image_read, except that an 8- or 16-bit file (PNG, TIFF, JPEG) is kept
 * as its codes (out->codes set, out->data NULL; see "Integer codes" above).
 * Float files come back as floats, as from vr_image_read. */
vr_status vr_image_read_codes(const char *path, vr_image *out, vr_error *err);

/* vr_image_read, keeping the alpha values too (out->alpha_data) when the
 * file carries transparency: textures with cut-outs. */
vr_status vr_image_read_alpha(const char *path, vr_image *out, vr_error *err);
/* The same from the bytes of such a file held in memory (a model's
 * embedded texture); name stands for the path in messages. */
vr_status vr_image_decode_alpha(const void *bytes, size_t len, const char *name, vr_image *out,
                                vr_error *err);

/* PNG, TIFF and JPEG go through OpenCV, in a module (vr-image-cv.so) loaded
 * the first time such a file is read or written, so that a program that
 * only reads and writes OpenEXR never loads OpenCV.  This loads it now, for
 * a tool that would rather fail before its work than after it: VR_E_IO
 * naming every path tried when it cannot be found or loaded.  The module is
 * looked for at $VR_IMAGE_CV_MODULE if set, else beside the program
 * (DIR/vr-image-cv.so, DIR/../lib/virtuelium-c/vr-image-cv.so), else where
 * the build put it. */
vr_status vr_image_codecs_load(vr_error *err);

/* Turns an image of codes into floats in place (the values vr_image_read
 * would have given); nothing to do for an image of floats. */
vr_status vr_image_to_float(vr_image *img, vr_error *err);

/* Writes an RGB PNG of 8 or 16 bits per channel: values clamped to [0,1],
 * then v*255 (or v*65535) rounded to nearest.  A NaN is refused (VR_E_RANGE)
 * rather than written as some colour.  The file appears whole or not at all
 * (temporary file in the same directory, then rename). */
vr_status vr_image_write_png(const char *path, const vr_image *img, int bits, vr_error *err);

/* Writes a 32-bit float RGB OpenEXR (ZIP compression, lossless), values as
 * they are; atomically like vr_image_write_png. */
vr_status vr_image_write_exr(const char *path, const vr_image *img, vr_error *err);

/* What a viewer needs to show the R, G, B of an OpenEXR as they were meant:
 *   chromaticities  (OpenEXR standard optional attribute) the CIE 1931 x, y
 *                   of the red, green and blue primaries and of the white;
 *                   without it a reader assumes Rec. 709 / sRGB primaries
 *                   and D65, so it says what was meant instead of leaving
 *                   it to a default;
 *   whiteLuminance  (standard) the luminance in cd/m² of RGB (1, 1, 1):
 *                   with the chromaticities, a reader turns pixels into
 *                   absolute CIE XYZ.  1 for pixels that are cd/m² already;
 *   exposure        (float, in stops; not an OpenEXR standard attribute,
 *                   which has none for this) the exposure to apply for
 *                   display, as the exposure control of EXR viewers does:
 *                   pixel x 2^exposure, then 1.0 is display white.
 * Each is written only when set; a zeroed struct writes none. */
typedef struct vr_exr_colour {
  int has_chromaticities;
  float chromaticities[8]; /* red x, y, green x, y, blue x, y, white x, y */
  double white_luminance;  /* cd/m²; > 0 writes whiteLuminance, 0 none */
  int has_exposure;
  double exposure;         /* stops */
} vr_exr_colour;

/* Linear sRGB: the primaries of ITU-R BT.709-6 (those of IEC 61966-2-1:
 * red 0.640, 0.330, green 0.300, 0.600, blue 0.150, 0.060) and the D65
 * white 0.3127, 0.3290, with whiteLuminance and exposure as given. */
vr_exr_colour vr_exr_colour_srgb(double white_luminance, double exposure);

/* vr_image_write_exr with the attributes of colour (NULL: none).  A
 * chromaticity or exposure that is not finite, a chromaticity outside
 * [0, 1], a white y of 0, or a white luminance that is negative or not
 * finite is VR_E_ARG and nothing is written. */
vr_status vr_image_write_exr_with(const char *path, const vr_image *img,
                                  const vr_exr_colour *colour, vr_error *err);

/* A channel written beside R, G, B: one value a pixel, in the image's
 * row order; uint32 (EXR UINT) or float (EXR FLOAT).  A name with a dot
 * puts it in a layer, as OpenEXR's convention has it ("samples.N"). */
typedef struct vr_exr_channel {
  const char *name;
  int is_uint;
  const void *data;
} vr_exr_channel;

/* vr_image_write_exr_with plus nextra channels (names distinct, none R, G
 * or B, else VR_E_ARG and nothing is written). */
vr_status vr_image_write_exr_channels(const char *path, const vr_image *img,
                                      const vr_exr_colour *colour, const vr_exr_channel *extra,
                                      size_t nextra, vr_error *err);

/* Writes by the file name's extension (case-insensitive):
 *   .png          bits 8 or 16, as vr_image_write_png
 *   .tif / .tiff  bits 8 or 16, same quantisation, LZW (lossless)
 *   .jpg / .jpeg  bits 8 only, baseline JPEG at quality 95 (lossy: 8-bit
 *                 values come back within a few units, see the tests)
 *   .exr          bits 32 (float) or 16 (half: 11 significant bits)
 * Any other extension or bit depth is VR_E_ARG. */
vr_status vr_image_write(const char *path, const vr_image *img, int bits, vr_error *err);

/* Mean and sample standard deviation (divisor n-1; 0 for one pixel) of each
 * channel over the w x h pixels whose top-left pixel is (x, y); *clipped gets
 * the number of those pixels with at least one channel >= clip_level.  sd and
 * clipped may be NULL.  A rectangle that is empty or leaves the image is
 * VR_E_RANGE, naming the rectangle and the image size. */
vr_status vr_image_rect_mean(const vr_image *img, int x, int y, int w, int h, double rgb[3],
                             double sd[3], int *clipped, double clip_level, vr_error *err);

/* One region of a label image: all pixels carrying the same label. */
typedef struct vr_label_region {
  int label;     /* 1 ... 65535 */
  long pixels;   /* number of pixels with this label */
  long clipped;  /* of which with at least one channel >= clip_level */
  double rgb[3]; /* mean of the photo's values over the region */
  double sd[3];  /* sample standard deviation (divisor n-1; 0 for one pixel) */
} vr_label_region;

typedef struct vr_label_means {
  int count;                /* regions found */
  vr_label_region *regions; /* sorted by label; labels absent from the image are left out */
} vr_label_means;

/* Per-region statistics of img for a label image: an 8- or 16-bit image
 * (grey, or RGB with R = G = B) whose integer pixel value is a region id;
 * label 0 is background and ignored.  labels must have img's size.  A float
 * label image, a non-grey pixel or a size mismatch is an error naming
 * labels_name (used in messages only; NULL reads "label image").
 * Free the result with vr_label_means_free. */
vr_status vr_image_label_means(const vr_image *img, const vr_image *labels,
                               const char *labels_name, double clip_level,
                               vr_label_means *out, vr_error *err);
/* The same with the label image read from a file (PNG or TIFF). */
vr_status vr_image_label_means_file(const vr_image *img, const char *labels_path,
                                    double clip_level, vr_label_means *out, vr_error *err);
void vr_label_means_free(vr_label_means *m);

/* Checks that img is a usable RGB image of floats (what names it in
 * messages): VR_E_ARG for a NULL or empty image, an image of codes, or a
 * channel count other than 3. */
vr_status vr_image_check(const vr_image *img, const char *what, vr_error *err);
/* The same, but an image of codes (vr_image_read_codes) is usable too. */
vr_status vr_image_check_any(const vr_image *img, const char *what, vr_error *err);

/* Statistics of the pixels whose centres lie inside a convex quadrilateral
 * (corners in order, either orientation; image coordinates, pixel centres at
 * +0.5).  pixels may come back 0: the caller decides whether that is an error. */
typedef struct vr_region_stats {
  long pixels;
  double mean[3];
  double sd[3];
  double max; /* largest channel value; -inf when pixels == 0 */
} vr_region_stats;

vr_status vr_region_quad_stats(const vr_image *img, const double quad[4][2],
                               vr_region_stats *out, vr_error *err);

#ifdef __cplusplus
}
#endif
#endif
