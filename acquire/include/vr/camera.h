/* Camera models for spectral recovery: what a three-channel camera records of
 * a reflectance, sampled on a wavelength grid, under a known light.
 *
 * A reflectance is represented by its values r_j on the camera's grid and is
 * taken to be linear between the samples and constant beyond the ends (the
 * end-value rule of CIE 015:2018 section 7.2.2, which vr_xyz_reflectance()
 * also uses).  The response of channel c under light S is then the 1 nm sum
 * over 360-830 nm
 *
 *     c = k * sum_l S(l) s_c(l) r(l),      k = 1 / sum_l S(l) s_n(l),
 *
 * which is linear in the samples: c = sum_j a_cj r_j, each a_cj the sum of
 * S s_c against the "hat" function of sample j.  The normaliser k makes a
 * perfect white (r = 1) give a response of 1 in the normalising channel.
 *
 * Two kinds of camera:
 *   - the CIE 1931 2° observer seen through the sRGB primaries (IEC
 *     61966-2-1): s = (x̄, ȳ, z̄), s_n = ȳ, then linear RGB = M_XYZ->sRGB XYZ,
 *     so the responses are exactly M * vr_xyz_reflectance();
 *   - measured sensitivities (three spectra r, g, b): s_n = g, taken as zero
 *     outside each curve's tabulated range (data are assumed to cover where
 *     the sensor responds), linear between samples.
 * Exposure (a per-light scale) is applied by the recovery system, not here. */
#ifndef VR_CAMERA_H
#define VR_CAMERA_H

#include <stddef.h>
#include "vr/error.h"
#include "vr/spectrum.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vr_camera vr_camera;

typedef enum vr_camera_kind {
  VR_CAMERA_CIE1931_SRGB = 0, /* CIE 1931 2° observer with sRGB primaries */
  VR_CAMERA_MEASURED = 1      /* three measured sensitivity curves */
} vr_camera_kind;

/* The default grid: 400-700 nm every 10 nm, 31 samples. */
#define VR_CAMERA_DEFAULT_START_NM 400.0
#define VR_CAMERA_DEFAULT_STEP_NM 10.0
#define VR_CAMERA_DEFAULT_SAMPLES 31

/* The CIE 1931 observer with sRGB primaries on the grid grid_nm[0..n-1]
 * (strictly increasing, n >= 3), or on the default grid when grid_nm is
 * NULL (n is then ignored). */
vr_camera *vr_camera_create_srgb(size_t n, const double *grid_nm, vr_error *err);
/* A camera from measured sensitivities sens[0..2] = red, green, blue (any
 * grids); grid as above. */
vr_camera *vr_camera_create_measured(const vr_spectrum *const sens[3], size_t n,
                                     const double *grid_nm, vr_error *err);
void vr_camera_destroy(vr_camera *cam);

vr_camera_kind vr_camera_get_kind(const vr_camera *cam);
size_t vr_camera_samples(const vr_camera *cam);
const double *vr_camera_grid(const vr_camera *cam);

/* Fills grid with start, start+step, ... up to stop (inclusive within 1e-9
 * of a step), e.g. 380, 730, 10 -> 36 samples; n receives the count.
 * VR_E_ARG if step <= 0, stop < start, or more than cap samples. */
vr_status vr_camera_grid_uniform(double start_nm, double stop_nm, double step_nm, double *grid,
                                 size_t cap, size_t *n, vr_error *err);

/* The 3 x n response matrix (row-major, rows R, G, B) under light at unit
 * exposure: row c, column j is the response of channel c to the hat function
 * of sample j, so the responses to r are a * r.  VR_E_ARG if the light gives
 * no response in the normalising channel (k undefined). */
vr_status vr_camera_response(const vr_camera *cam, const vr_spectrum *light, double *a,
                             vr_error *err);

#ifdef __cplusplus
}
#endif
#endif
