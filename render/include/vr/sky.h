/* The sky dome: the 15 CIE standard general skies and the traditional CIE
 * overcast sky, as relative luminance distributions, their absolute level,
 * and an importance sampler over the upper hemisphere.
 *
 * CIE standard general sky (ISO 15469:2004 / CIE S 011/E:2003), for a sky
 * element at zenith angle Z and angular distance chi from the sun, the sun
 * at zenith angle Zs:
 *
 *   L(Z, chi) / Lz = f(chi) phi(Z) / (f(Zs) phi(0))
 *   gradation  phi(Z) = 1 + a exp(b / cos Z),   phi(90 deg) = 1
 *   indicatrix f(chi) = 1 + c (exp(d chi) - exp(d pi/2)) + e cos^2 chi
 *
 * with a..e from the standard's Table 1 for types 1..15 (vr_sky_params_of).
 * Type 0 here is the traditional CIE overcast sky (Moon & Spencer 1942,
 * adopted by the CIE in 1955), L(Z) = Lz (1 + 2 cos Z) / 3, which the
 * standard keeps as a separate formula.
 *
 * The sky gives nothing below the horizon (cos Z < 0): the relative
 * luminance and the sampling pdf are 0 there and the sampler never returns
 * such a direction.  The ground below the horizon is a separate element of
 * the scene (vr_scene_sky.ground_reflectance), lit by sun and sky.
 *
 * Directions are unit vectors, z up, azimuth from north (+y) towards east
 * (+x).  A vr_sky is immutable after creation: every function taking a
 * const vr_sky * may be called from many threads at once. */
#ifndef VR_SKY_H
#define VR_SKY_H

#include "vr/error.h"
#include "vr/scene.h"
#include "vr/sky_params.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Resolution of the sampler's table: cells equal in solid angle, uniform in
 * cos Z (0 at the horizon, 1 at the zenith) and in azimuth. */
#define VR_SKY_SAMPLER_NU 64
#define VR_SKY_SAMPLER_NPHI 256


/* ISO 15469:2004 Table 1 parameters of types 1..15; VR_E_ARG for any other
 * number (type 0, the traditional overcast sky, has no such parameters). */
vr_status vr_sky_params_of(int cie_type, vr_sky_params *out, vr_error *err);
/* phi(Z) for cos Z in [0, 1] (1 at the horizon, cos Z <= 0). */
double vr_sky_gradation(const vr_sky_params *p, double cos_z);
/* f(chi), chi in radians in [0, pi]. */
double vr_sky_indicatrix(const vr_sky_params *p, double chi);

typedef struct vr_sky vr_sky;

/* vr_sky_type of a Perez all-weather sky (vr/perez.h). */
#define VR_SKY_PEREZ 16

/* Builds a sky of type 0..15 for a sun direction (towards the sun; need not
 * be unit length).  Type 0 ignores the sun (sun_dir may be NULL).  The CIE
 * general skies are defined for a sun on or above the horizon: a sun below
 * it is VR_E_RANGE naming its altitude.  Computes E_h/Lz and the sampling
 * table once (about ten milliseconds). */
vr_status vr_sky_create(int cie_type, const double sun_dir[3], vr_sky **out, vr_error *err);
/* A Perez (1993) all-weather sky with coefficients a..e (from
 * vr_perez_luminance_params), relative luminance
 *   [1 + a exp(b / max(cos zeta, 0.01))] [1 + c exp(d gamma) + e cos^2 gamma]
 * with each factor held at 0 or more, normalised to 1 at the zenith.
 * Coefficients that make the zenith dark (the fitted model far outside
 * its data, e.g. a clear high-sun sky of almost no brightness) are
 * VR_E_NUMERIC. */
vr_status vr_sky_create_perez(const vr_sky_params *p, const double sun_dir[3], vr_sky **out,
                              vr_error *err);
void vr_sky_destroy(vr_sky *sky);

int vr_sky_type(const vr_sky *sky); /* 0..15 or VR_SKY_PEREZ */

/* L(dir) / Lz; 0 below the horizon. */
double vr_sky_relative_luminance(const vr_sky *sky, const double dir[3]);

/* Diffuse horizontal illuminance over zenith luminance, E_h / Lz in sr:
 * the integral of L/Lz cos Z over the upper hemisphere, computed in
 * sun-centred coordinates with composite Gauss-Legendre rules.  Doubling
 * every panel count moves it by less than 1e-8 (relative) for all types and
 * sun altitudes, by 1e-11 for the overcast and azimuth-uniform skies
 * (exactly 7 pi / 9 for the traditional overcast sky). */
double vr_sky_horizontal_ratio(const vr_sky *sky);

/* The zenith level from the scene's sky level: lx (diffuse horizontal
 * illuminance) or cd/m2 (zenith luminance) give a zenith luminance in cd/m2;
 * the radiometric W/m2 and W/(m2 sr) give a zenith radiance in W/(m2 sr).
 * Any other unit, a negative or non-finite value: VR_E_ARG naming it. */
vr_status vr_sky_zenith_level(const vr_sky *sky, vr_quantity level, vr_quantity *zenith,
                              vr_error *err);

/* Importance sampling of the upper hemisphere with a density proportional
 * to the sky's luminance, piecewise constant over VR_SKY_SAMPLER_NU x
 * VR_SKY_SAMPLER_NPHI cells (cell means by 3 x 3 Gauss-Legendre points).
 * u1, u2 in [0, 1) (values outside are clamped); the same (u1, u2) always
 * give the same direction.  pdf is per steradian and equals
 * vr_sky_pdf(sky, dir). */
void vr_sky_sample(const vr_sky *sky, double u1, double u2, double dir[3], double *pdf);
double vr_sky_pdf(const vr_sky *sky, const double dir[3]);

#ifdef __cplusplus
}
#endif
#endif
