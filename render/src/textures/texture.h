/* Textures on surfaces: a factor per wavelength that multiplies a
 * material's reflectance at each point (its base colour map), and an
 * optional alpha that cuts the surface out.
 *
 * Two kinds:
 *   - RGB images (PNG, JPEG, TIFF of 8 or 16 bits, OpenEXR, or the bytes of
 *     such a file embedded in a model).  Integer files are sRGB-encoded
 *     unless told linear (IEC 61966-2-1 decoding), EXR is linear; values
 *     are clamped to [0, 1] (a reflectance factor).  Filtering happens in
 *     linear RGB, then the filtered colour becomes a spectrum through the
 *     sigmoid table (vr/rgb_table.h: within Delta E00 0.45 of the colour),
 *     evaluated at the path's wavelengths.  Stored as 16-bit linear codes,
 *     RGB and alpha: 8 bytes a texel, plus a third for the mips.
 *   - Spectral images (the spectral OpenEXR of vr-rgb2spec --texture,
 *     reflective T.<nm> channels): filtered per band, interpolated
 *     linearly between bands, the end bands held outside their range.
 *     Stored as 16-bit codes, 2 bytes a band a texel (plus a third for the
 *     mips).
 *
 * Coordinates: (u, v) with v up, as the mesh reader's (Assimp's) and the
 * rects' are: (0, 0) is the bottom-left corner of the image, (1, 1) the
 * top-right; the texture repeats outside [0, 1).  Mip level k is the image
 * halved k times by 2 x 2 box averages (odd sizes: the last texel counted
 * once); a lookup of footprint w (in uv units) reads level
 * log2(w * max(width, height)), trilinearly.  Alpha is read bilinearly
 * from the full-size level only (averaged alpha would eat thin cut-outs). */
#ifndef VR_TEXTURES_TEXTURE_H
#define VR_TEXTURES_TEXTURE_H

#include <stdbool.h>
#include <stddef.h>

#include "vr/error.h"

typedef struct vr_texture vr_texture;

/* An RGB texture from a file or from a file's bytes in memory (name is
 * used in messages).  srgb: integer samples are sRGB-encoded (ignored for
 * EXR, which is linear).  Errors name the file. */
vr_status vr_texture_load_rgb(const char *path, bool srgb, vr_texture **out, vr_error *err);
vr_status vr_texture_load_rgb_memory(const void *bytes, size_t len, const char *name, bool srgb,
                                     vr_texture **out, vr_error *err);
/* A spectral texture from a reflective spectral OpenEXR whose SHA-256 must
 * be sha256_hex (64 hex digits; NULL: not checked).  Errors name the file:
 * unreadable, not spectral or not reflective, a different hash (the file
 * changed since the database recorded it), values outside [0, 1.5] or
 * not finite. */
vr_status vr_texture_load_spectral(const char *path, const char *sha256_hex, vr_texture **out,
                                   vr_error *err);
void vr_texture_destroy(vr_texture *t);

/* Bytes held (every level), full-size width and height, mip levels. */
size_t vr_texture_bytes(const vr_texture *t);
void vr_texture_size(const vr_texture *t, int *w, int *h, int *levels);
bool vr_texture_is_spectral(const vr_texture *t);
/* Whether the image has an alpha channel with some texel below opaque. */
bool vr_texture_has_alpha(const vr_texture *t);

/* The factor at (u, v) for a footprint of width uv units (0: the
 * full-size level, bilinear), at nwl wavelengths (nm) into out. */
void vr_texture_eval(const vr_texture *t, double u, double v, double width, int nwl,
                     const double *nm, double *out);
/* The filtered linear RGB of an RGB texture at (u, v), each in [0, 1]
 * (normal maps); 0 for a spectral one. */
void vr_texture_rgb(const vr_texture *t, double u, double v, double width, double rgb[3]);
/* The alpha at (u, v) (1 where the image has none). */
double vr_texture_alpha(const vr_texture *t, double u, double v);
/* The mean linear RGB of the full-size level (for descriptions). */
void vr_texture_mean_rgb(const vr_texture *t, double rgb[3]);

#endif
