/* Accumulators that many workers add into at once (accum.c): the film (XYZ
 * and spectral bins per pixel), the sensors (illuminance per batch of
 * samples, by daylight component and sky patch, spectral irradiance) and
 * the photochromic texels (UV irradiance). */
#ifndef VR_FILM_ACCUM_H
#define VR_FILM_ACCUM_H

#include <stdatomic.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "vr/error.h"
#include "vr/render.h"
#include "vr/skypatch.h"

/* The sky's patches and the ground glow: a sensor's tallies by patch. */
#define VR_SENSOR_PATCHES (VR_SKY_PATCHES + 1)
/* A pixel's tallies by source (vr_accum_keep_patches): the sky's patches,
 * the ground glow, then the sun (VR_PIXEL_SUN). */
#define VR_PIXEL_SUN VR_SENSOR_PATCHES
#define VR_PIXEL_SOURCES (VR_SENSOR_PATCHES + 1)

typedef struct vr_accum {
  int width, height, spp;
  size_t nbins;
  double bin_lo, bin_step;
  _Atomic uint64_t *xyz;      /* doubles stored as bits, width*height*3 */
  _Atomic uint64_t *bins;     /* width*height*nbins */
  /* Adaptive sampling (vr_accum_keep_halves): the XYZ of each pixel's
   * second-half samples alone, width*height*3; NULL otherwise.  With the
   * whole sums it gives two independent half estimates, whose difference
   * measures the pixel's error. */
  _Atomic uint64_t *half_xyz;
  /* The denoiser's features (vr_accum_keep_features): per pixel
   * VR_FEATURES sums over the camera samples' first non-delta vertex
   * (VR_FEAT_*), weighted by the samples' filter weights; NULL otherwise. */
  _Atomic uint64_t *feat;
  /* Image daylight coefficients (vr_accum_keep_patches): per pixel
   * VR_PIXEL_SOURCES sums of the luminance (cd/m2) that came from each sky
   * patch, from the ground glow and from the sun; NULL otherwise. */
  _Atomic uint64_t *pixel_patches;
  size_t npoints;             /* sensor points */
  int groups;                 /* batches for the standard error */
  _Atomic uint64_t *sensor_lx;  /* npoints*groups */
  _Atomic uint64_t *sensor_bins;/* npoints*nbins */
  _Atomic uint64_t *sensor_parts;/* npoints*VR_SENSOR_PARTS: illuminance by component (lx, summed
                                    over the groups' samples) */
  _Atomic uint64_t *sensor_patches;/* npoints*VR_SENSOR_PATCHES: the sky's and the ground glow's
                                    illuminance by the patch it came from (lx, summed) */
  size_t ntexels;
  _Atomic uint64_t *texel_uv;   /* W/m2 in the UV band, summed */
  _Atomic uint64_t *texel_patches;/* ntexels*VR_SENSOR_PATCHES: the sky's and the ground glow's
                                    share of texel_uv by the patch it came from */
  /* Fixed-bins mode: the CMFs averaged over each of the cmf_n bins of
   * [cmf_lo, cmf_lo + cmf_n cmf_step], used for a wavelength in that bin
   * instead of their value at it (NULL in hero mode). */
  double (*cmf_avg)[3];
  double cmf_lo, cmf_step;
  int cmf_n;
} vr_accum;

/* A pixel's feature sums: the albedo's XYZ (relative to the equal-energy
 * white: a white Lambertian surface is (1, 1, 1)), the shading normal,
 * the distance from the camera, the weight they were summed with, and the
 * sums of the squared albedo, normal and distance (for their variance). */
enum {
  VR_FEAT_ALBEDO = 0, VR_FEAT_NORMAL = 3, VR_FEAT_DEPTH = 6, VR_FEAT_WEIGHT = 7,
  VR_FEAT_ALBEDO2 = 8, VR_FEAT_NORMAL2 = 9, VR_FEAT_DEPTH2 = 10, VR_FEATURES = 11
};

vr_status vr_accum_create(vr_accum *a, int width, int height, size_t nbins, double bin_lo,
                          double bin_step, size_t npoints, int groups, size_t ntexels,
                          vr_error *err);
void vr_accum_destroy(vr_accum *a);
/* Fixed-bins mode: weight each of the n bins of [lo, hi] by the CMFs'
 * mean over the bin, so a spectrum flat within each bin integrates
 * exactly (the midpoint rule with 4 bins of 117 nm is 17 % off for D65). */
vr_status vr_accum_set_bins(vr_accum *a, double lo, double hi, int n, vr_error *err);
void vr_atomic_add(_Atomic uint64_t *cell, double v);
/* The n sums at *cells, each divided by `by`, as plain doubles in the same
 * memory, which the caller now owns (*cells becomes NULL): a film's sums
 * become its image without a second copy.  No worker may still add. */
double *vr_accum_take_mean(_Atomic uint64_t **cells, size_t n, double by);
double vr_atomic_get(_Atomic uint64_t *cell);
/* Adds radiance samples (already divided by their wavelength pdf) of a pixel. */
/* Keep the film's luminance by source (pixel_patches). */
vr_status vr_accum_keep_patches(vr_accum *a, vr_error *err);
/* Adds a pixel's radiance samples (as vr_accum_pixel) to its tally for the
 * source they came from (a sky patch, VR_SKY_GROUND_PATCH or VR_PIXEL_SUN),
 * as luminance; nothing without pixel_patches. */
void vr_accum_pixel_patch(vr_accum *a, uint32_t pixel, int patch, int nwl, const double *wl,
                          const double *L, double wl_weight);
void vr_accum_pixel(vr_accum *a, uint32_t pixel, int nwl, const double *wl, const double *L,
                    double wl_weight);
/* The same, from a sample of the second half when second_half: with
 * halves kept, its XYZ also goes to half_xyz. */
void vr_accum_pixel_half(vr_accum *a, uint32_t pixel, bool second_half, int nwl,
                         const double *wl, const double *L, double wl_weight);
/* Keeps the second half's XYZ apart from now on (adaptive sampling). */
vr_status vr_accum_keep_halves(vr_accum *a, vr_error *err);
/* Keeps the features of the camera samples from now on (the denoiser). */
vr_status vr_accum_keep_features(vr_accum *a, vr_error *err);
/* Adds one camera sample's features with weight w: the albedo at the nwl
 * wavelengths (its XYZ is the CMF-weighted mean of those values, so a flat
 * albedo gives exactly its value whatever the wavelengths), the unit
 * normal n (zero where the sample saw no surface) and the distance. */
void vr_accum_features(vr_accum *a, uint32_t pixel, double w, int nwl, const double *wl,
                       const double *albedo, const double n[3], double depth);
/* Adds lx to the illuminance point received from sky patch (or the ground). */
void vr_accum_sensor_patch_lx(vr_accum *a, uint32_t point, int patch, double lx);
double vr_accum_sensor(vr_accum *a, uint32_t point, uint32_t sample, int nwl, const double *wl,
                       const double *E, double wl_weight);
/* Adds lx, or the illuminance of E, to part `part` (VR_PART_*) of point. */
void vr_accum_sensor_part_lx(vr_accum *a, uint32_t point, int part, double lx);
void vr_accum_sensor_part(vr_accum *a, uint32_t point, int part, int nwl, const double *wl,
                          const double *E, double wl_weight);
/* Adds the illuminance of E to slot `slot` (< groups) of point only, not
 * to its spectrum: for side sums such as a photon sensor's bias probe. */
void vr_accum_sensor_lx(vr_accum *a, uint32_t point, uint32_t slot, int nwl, const double *wl,
                        const double *E, double wl_weight);

#endif
