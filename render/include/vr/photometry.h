/* Photometry for light sources: the luminous efficacy of a spectrum, the
 * factors between photometric and radiometric amounts (lm <-> W, cd <-> W/sr,
 * lx <-> W/m2, cd/m2 <-> W/(m2 sr)), and the radiometric amounts of a
 * scene's lights from the quantities the user wrote.
 *
 * Luminous efficacy of radiation over a band [lo, hi] (the ILV entry
 * "luminous efficacy (of radiation)", CIE S 017), with V the CIE 1924
 * photopic luminous efficiency function, which is ybar of the CIE 1931
 * observer (CIE 015:2018 section 3.1):
 *
 *   K = Km int_lo^hi V(l) S(l) dl / int_lo^hi S(l) dl,  Km = 683.002 lm/W
 *
 * Both integrals run over the same band, the band the renderer carries
 * (vr_scene_settings lambda_min..lambda_max): the lumens a rendered sensor
 * measures then reproduce the lumens the user asked for.  For the default
 * 360-830 nm band this is the full photometric integral, V being 0 outside
 * it.  S is interpolated linearly between its samples (end values held
 * outside its grid, as vr_spectrum_eval does) and V between the 1 nm rows
 * of the CIE table; both integrals are exact for those piecewise-linear
 * functions (the product is integrated interval by interval with Simpson's
 * rule, exact for its quadratic pieces).
 *
 * Everything here is a pure function of its arguments: thread-safe. */
#ifndef VR_PHOTOMETRY_H
#define VR_PHOTOMETRY_H

#include <stdbool.h>
#include "vr/error.h"
#include "vr/scene.h"
#include "vr/spectrum.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Short printable name of a unit: "W", "lm", "cd", "W/sr", "lx", "W/m2",
 * "cd/m2", "W/(m2 sr)", "(no unit)". */
const char *vr_photometry_unit_name(vr_light_unit u);
/* True for lm, cd, lx, cd/m2. */
bool vr_photometry_is_photometric(vr_light_unit u);
/* The same kind of amount on the other side: lm <-> W, cd <-> W/sr,
 * lx <-> W/m2, cd/m2 <-> W/(m2 sr); VR_UNIT_NONE for VR_UNIT_NONE. */
vr_light_unit vr_photometry_counterpart(vr_light_unit u);

/* int_lo^hi S dl (units of S times nm), exact for linear interpolation. */
double vr_photometry_band_integral(const vr_spectrum *spd, double lo_nm, double hi_nm);
/* int_lo^hi V S dl, exact for linear interpolation of both. */
double vr_photometry_v_integral(const vr_spectrum *spd, double lo_nm, double hi_nm);

/* K in lm/W over [lo, hi].  VR_E_ARG for an empty or inverted band;
 * VR_E_RANGE when the spectrum carries no power in the band (its integral
 * is not > 0). */
vr_status vr_photometry_efficacy(const vr_spectrum *spd, double lo_nm, double hi_nm,
                                 double *efficacy_lm_per_w, vr_error *err);

/* Converts q to unit `to` for a source of relative spectral power spd over
 * [lo, hi]: photometric = K x radiometric for the same kind of amount,
 * identity when the units agree.  Different kinds (lm to cd, lx to W/sr)
 * or VR_UNIT_NONE: VR_E_ARG naming both units. */
vr_status vr_photometry_convert(vr_quantity q, vr_light_unit to, const vr_spectrum *spd,
                                double lo_nm, double hi_nm, double *out, vr_error *err);

/* Phi = omega I0 for a point light of a given distribution: 4 pi for
 * isotropic (I = Phi / 4 pi), pi for the Lambertian point source
 * I(theta) = I0 cos theta over a hemisphere (int_0^{pi/2} I0 cos(theta)
 * 2 pi sin(theta) dtheta = pi I0); NAN for goniometric lights, whose ratio
 * comes from their file (vr_ies_lumens / the reference candela). */
double vr_photometry_solid_angle(vr_distribution d);

/* Radiometry of a point (or spot) light. */
typedef struct vr_point_radiometry {
  double efficacy_lm_per_w; /* K of the spectrum over the band */
  double power_w;           /* radiant power in the band, W */
  double intensity_w_sr;    /* reference radiant intensity I0 (on axis), W/sr */
  /* Spectral radiant intensity per unit of the relative SPD:
   * I0(l) = intensity_scale * S(l) W/(sr nm), so that int I0(l) dl over the
   * band is intensity_w_sr. */
  double intensity_scale;
} vr_point_radiometry;

/* From the amount as written (W, lm: total power; cd, W/sr: I0) and
 * omega = Phi / I0 (vr_photometry_solid_angle, or the spot's or file's own
 * figure).  Illuminance and luminance units do not describe a point light:
 * VR_E_ARG naming the unit.  omega must be > 0; the value finite and >= 0. */
vr_status vr_photometry_point_light(vr_quantity amount, double omega_sr, const vr_spectrum *spd,
                                    double lo_nm, double hi_nm, vr_point_radiometry *out,
                                    vr_error *err);

/* Radiometric amount of a non-point quantity for a spectrum: the sun's
 * normal illuminance (lx or W/m2 -> W/m2), a surface's or the sky's
 * luminance (cd/m2 or W/(m2 sr) -> W/(m2 sr)).  `expect` is the radiometric
 * unit wanted; a quantity of another kind is VR_E_ARG naming its unit.
 * scale (may be NULL) receives the factor turning the relative SPD into
 * spectral units: amount(l) = scale * S(l) per nm. */
vr_status vr_photometry_radiometric(vr_quantity q, vr_light_unit expect, const vr_spectrum *spd,
                                    double lo_nm, double hi_nm, double *amount, double *scale,
                                    vr_error *err);

#ifdef __cplusplus
}
#endif
#endif
