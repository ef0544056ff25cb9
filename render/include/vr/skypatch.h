/* The Tregenza sky subdivision (Tregenza, "Subdivision of the sky hemisphere
 * for luminance measurements", Lighting Research and Technology 19(1),
 * 1987): 145 patches in 8 bands of 12 degrees of altitude (the last a
 * polar cap of 6 degrees radius) holding 30, 30, 24, 24, 18, 12, 6 and 1
 * patches, the patches of a band equal in azimuth, the first of each band
 * centred on north (azimuth 0, from north towards east).  Used for daylight
 * coefficients: the illuminance a point receives per unit luminance of each
 * patch (and of the ground below the horizon, index VR_SKY_PATCHES). */
#ifndef VR_SKYPATCH_H
#define VR_SKYPATCH_H

#ifdef __cplusplus
extern "C" {
#endif

#define VR_SKY_PATCHES 145
#define VR_SKY_GROUND_PATCH VR_SKY_PATCHES /* the ground, below the horizon */

/* The patch of a unit direction (z up, y north, x east), or
 * VR_SKY_GROUND_PATCH below the horizon. */
int vr_sky_patch_of(const double dir[3]);
/* Altitude and azimuth bounds of patch k (degrees; the cap: azimuth 0..360). */
void vr_sky_patch_bounds(int k, double *alt_lo, double *alt_hi, double *az_lo, double *az_hi);
/* The unit direction of patch k's centre (the cap's: the zenith). */
void vr_sky_patch_centre(int k, double dir[3]);
/* Solid angle of patch k, sr (they sum to 2 pi). */
double vr_sky_patch_solid_angle(int k);

#ifdef __cplusplus
}
#endif
#endif
