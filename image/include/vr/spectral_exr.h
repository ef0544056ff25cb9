/* Spectral images as OpenEXR files in the layout of Fichet, Pacanowski and
 * Wilkie, "An OpenEXR Layout for Spectral Images", JCGT 10(3), 2021, as their
 * reference code (github.com/afichet/spectral-exr) writes and reads it: one
 * float channel per wavelength, named S0.<λ>nm for emitted radiance (the
 * Stokes S0 component) or T.<λ>nm for reflectance / transmittance, the
 * wavelength with a decimal comma ("S0.550,000000nm"), optional R, G, B
 * channels beside them for ordinary viewers, and the string attributes
 * spectralLayoutVersion ("1.0") and emissiveUnits.  The film of vr-render
 * and any measured spectral picture go through here.
 *
 * Polarisation (S1..S3) and bi-spectral re-radiation (T.<λ>nm.<λ'>nm)
 * channels of the layout are not represented: the reader checks their names
 * and skips them, the writer never makes them.
 *
 * Every function is thread-safe on distinct images; there is no global
 * state. */
#ifndef VR_SPECTRAL_EXR_H
#define VR_SPECTRAL_EXR_H

#include <stddef.h>
#include <stdint.h>

#include "vr/error.h"
#include "vr/image.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The emissiveUnits of spectral radiance as the layout's reference code
 * spells it: the writer of the layout's authors (ART's OpenEXR wrapper)
 * and pbrt-v4's spectral film both write "W.m^-2.sr^-1" beside S0 channels
 * that hold radiance per nanometre of wavelength, so a reader comparing
 * the string finds the unit it knows. */
#define VR_SPECTRAL_EMISSIVE_UNITS "W.m^-2.sr^-1"

typedef enum {
  VR_SPECTRAL_EMISSIVE,  /* channels S0.<λ>nm: radiance-like quantities */
  VR_SPECTRAL_REFLECTIVE /* channels T.<λ>nm: reflectance or transmittance */
} vr_spectral_kind;

typedef struct vr_spectral_image {
  int width, height;
  size_t nbands;
  double *wavelengths_nm; /* nbands, strictly increasing */
  float *data;            /* pixel (x,y) band b at data[(y*width + x)*nbands + b] */
  vr_spectral_kind kind;
} vr_spectral_image;

/* Allocates a w x h image of nbands bands set to zero, copying the
 * wavelengths (finite, > 0, strictly increasing).  VR_E_ARG naming the
 * parameter at fault; VR_E_NOMEM when it does not fit in memory. */
vr_status vr_spectral_image_alloc(vr_spectral_image *img, int w, int h, size_t nbands,
                                  const double *wavelengths_nm, vr_spectral_kind kind,
                                  vr_error *err);
/* Frees the arrays and zeroes the struct; safe on a zeroed or freed image. */
void vr_spectral_image_free(vr_spectral_image *img);

/* Writes img as a scanline OpenEXR of 32-bit float channels, ZIP compressed
 * (lossless), data window (0,0)-(w-1,h-1).  Channel names carry the
 * wavelength in nanometres with 6 decimals: a wavelength is stored to
 * 1e-6 nm, and two wavelengths that would share a name are VR_E_ARG.
 * Wavelengths must lie in (0, 1e9] nm.
 *
 * rgb, when not NULL, must have img's size and adds R, G, B channels (a
 * preview for viewers that know no spectra; the caller computes it).
 * emissive_units (for example VR_SPECTRAL_EMISSIVE_UNITS) goes into the
 * emissiveUnits attribute; NULL writes none.  It is VR_E_ARG on a
 * reflective image, where the layout gives it no meaning.
 *
 * A NaN or -infinity in img or rgb is VR_E_RANGE naming the pixel and band
 * (or channel) and nothing is written; +infinity is kept.  The file appears
 * whole or not at all (temporary file beside it, then rename). */
vr_status vr_spectral_exr_write(const char *path, const vr_spectral_image *img,
                                const vr_image *rgb, const char *emissive_units, vr_error *err);

/* vr_spectral_exr_write with the colour attributes of the R, G, B channels
 * (vr/image.h, vr_exr_colour: chromaticities, whiteLuminance, exposure),
 * checked as vr_image_write_exr_with does.  colour needs rgb (VR_E_ARG
 * otherwise: the attributes describe those channels); NULL writes none. */
vr_status vr_spectral_exr_write_with(const char *path, const vr_spectral_image *img,
                                     const vr_image *rgb, const char *emissive_units,
                                     const vr_exr_colour *colour, vr_error *err);

/* Streaming, multi-threaded writing, for images too large to hold twice
 * (a 12-megapixel, 31-band texture is 1.5 GB as floats).  The caller fills
 * the pixels chunk by chunk through a callback; `threads` workers each fill
 * a chunk, compress it, and the chunks are written in order, so the file is
 * the same whatever the number of threads.
 *
 * Compression: every one lossless.  NONE writes fastest and largest; RLE
 * (one line per chunk) is cheap and gains a third on half data; ZIPS (one
 * line) and ZIP (16 lines, zlib at zip_level) are slow; PIZ (wavelet +
 * Huffman, 32 lines) gave the smallest files of noisy reflectance textures
 * at a fifth of ZIP's time (docs/benchmarks.md). */
typedef enum {
  VR_EXR_COMPRESSION_NONE = 0,
  VR_EXR_COMPRESSION_RLE = 1,
  VR_EXR_COMPRESSION_ZIPS = 2,
  VR_EXR_COMPRESSION_ZIP = 3,
  VR_EXR_COMPRESSION_PIZ = 4
} vr_exr_compression;

/* Parses "none", "rle", "zips", "zip", "piz" (case-insensitive); VR_E_ARG
 * naming the accepted values otherwise. */
vr_status vr_exr_compression_parse(const char *s, vr_exr_compression *out, vr_error *err);
/* "none", "rle", "zips", "zip", "piz"; "invalid" for any other value. */
const char *vr_exr_compression_name(vr_exr_compression c);

typedef struct vr_spectral_exr_layout {
  int width, height;              /* >= 1 */
  size_t nbands;                  /* >= 1 */
  const double *wavelengths_nm;   /* nbands, as for vr_spectral_image */
  vr_spectral_kind kind;
  int half;                       /* spectral and R, G, B channels as 16-bit half (else float) */
  int rgb;                        /* add R, G, B channels */
  const char *flags_channel;      /* NULL, or the name of a 32-bit unsigned integer
                                     channel written beside the bands (e.g. "flags") */
  size_t nattrs;                  /* extra string attributes (name, value) */
  const char *const *attr_names;
  const char *const *attr_values;
  const char *emissive_units;     /* as for vr_spectral_exr_write */
  vr_exr_compression compression;
  int zip_level;                  /* ZIP/ZIPS: 1 (fast) .. 9 (small); 0: OpenEXR's default */
  int threads;                    /* workers, 1 .. 256 */
  const vr_exr_colour *colour;    /* NULL, or the colour attributes of the R, G, B
                                     channels (needs rgb; see vr_spectral_exr_write_with) */
} vr_spectral_exr_layout;

/* Fills rows y0 <= y < y1 of the image: spectra receives (y1 - y0) * width *
 * nbands floats (pixel x of row y at ((y - y0) * width + x) * nbands), rgb
 * 3 floats per pixel (NULL when the layout has no R, G, B), flags one
 * uint32_t per pixel (NULL without a flags channel).  thread (0 ..
 * threads - 1) tells which worker calls, so that the caller can keep
 * per-thread sums without locks; calls for different rows run at the same
 * time.  A status other than VR_OK stops the write: nothing is left at the
 * path and that error is returned. */
typedef vr_status (*vr_spectral_rows_fn)(void *user, int thread, int y0, int y1, float *spectra,
                                         float *rgb, uint32_t *flags, vr_error *err);

/* Writes the image the callback fills to path (scanline OpenEXR, data
 * window (0,0)-(w-1,h-1), the channel names, spectralLayoutVersion and
 * emissiveUnits of vr_spectral_exr_write).  A NaN or -infinity produced by
 * the callback is VR_E_RANGE naming the pixel and band; so is, with half
 * channels, a finite value that half would round to infinity (magnitude
 * 65520 or more; +infinity itself is kept).  The file appears whole or not
 * at all. */
vr_status vr_spectral_exr_write_rows(const char *path, const vr_spectral_exr_layout *layout,
                                     vr_spectral_rows_fn fill, void *user, vr_error *err);

/* Reads a file in that layout: the first part, scanline storage, half or
 * float channels in any order; the image is the data window; bands come out
 * sorted by wavelength.  Channel names are parsed as the reference code's
 * regular expression allows: S0..S3 or T, a dot, a number with an optional
 * decimal comma and exponent, an optional SI prefix, and m or Hz (a
 * frequency is turned into a wavelength in vacuum).  A name that starts
 * like a spectral channel (S0. to S3. or T. and a digit or comma) but does
 * not parse is an error; other channels (A, Y, layer.R, ...) are skipped.
 *
 * rgb_or_null, when not NULL, receives the R, G, B channels if the file
 * has all three, and is left zeroed (data NULL) if it has not.
 *
 * Errors name the path (and the channel when one is at fault), all
 * VR_E_PARSE except VR_E_IO (cannot read) and VR_E_NOMEM: not an OpenEXR
 * file, truncated or corrupt, tiled or deep, no spectral channel, both S0
 * and T channels (the struct holds one kind), a malformed spectral name,
 * two channels of the same wavelength, integer or subsampled spectral
 * channels, a spectralLayoutVersion other than 1.x.  On error *out (and
 * *rgb_or_null) are zeroed. */
vr_status vr_spectral_exr_read(const char *path, vr_spectral_image *out, vr_image *rgb_or_null,
                               vr_error *err);

/* The same from a file already in memory; name stands for the file in
 * messages (NULL reads "memory").  A header that claims far more pixels
 * than len bytes can hold (over 4096 times len, beyond any OpenEXR
 * compression's ratio, and over 64 MiB) is refused before allocating. */
vr_status vr_spectral_exr_read_memory(const void *buf, size_t len, const char *name,
                                      vr_spectral_image *out, vr_image *rgb_or_null,
                                      vr_error *err);

#ifdef __cplusplus
}
#endif
#endif
