/* CIE colorimetry: standard observers, illuminants, tristimulus integration,
 * colour spaces (xyY, CIELAB, sRGB), chromatic adaptation and colour
 * differences.
 *
 * Scale: tristimulus values of reflecting or transmitting samples are
 * normalised so that the perfect reflecting diffuser has Y = 1 (not 100);
 * white points passed to CIELAB use the same scale.  Emitters are absolute:
 * a spectral radiance in W sr^-1 m^-2 nm^-1 gives luminance in cd/m^2. */
#ifndef VR_COLOUR_H
#define VR_COLOUR_H

#include <stdbool.h>
#include <stddef.h>
#include "vr/error.h"
#include "vr/spectrum.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum vr_observer { VR_CIE1931_2DEG = 0, VR_CIE1964_10DEG = 1 } vr_observer;

/* Maximum luminous efficacy for photopic vision, lm/W (CIE 015:2018, 683.002). */
#define VR_KM 683.002

/* The colour-matching functions at 1 nm from 360 to 830 nm (471 rows of
 * nm, xbar, ybar, zbar); rows receives 471. */
const double *vr_cmf_table(vr_observer obs, size_t *rows);
/* x̄, ȳ, z̄ at any wavelength (linear between the 1 nm samples, 0 outside). */
void vr_cmf_eval(vr_observer obs, double nm, double xyz[3]);
/* "2", "1931", "10", "1964" (optionally with "deg" or "°"). */
vr_status vr_observer_parse(const char *text, vr_observer *obs, vr_error *err);

/* Tristimulus values of a reflectance (or transmittance) under an illuminant,
 * k = 1 / sum(S ȳ), summed at the CMFs' 1 nm steps over 360-830 nm with
 * both spectra interpolated linearly (end values held outside their grids,
 * CIE 015:2018 section 7.2.2). */
void vr_xyz_reflectance(const vr_spectrum *refl, const vr_spectrum *illum, vr_observer obs,
                        double xyz[3]);
/* White point of an illuminant (the perfect diffuser), Y = 1. */
void vr_xyz_white(const vr_spectrum *illum, vr_observer obs, double xyz[3]);
/* Absolute tristimulus values of an emitter: Km * sum(L x̄) * 1 nm. */
void vr_xyz_emitter(const vr_spectrum *radiance, vr_observer obs, double xyz[3]);

/* Colour spaces.  Degenerate inputs (X+Y+Z = 0, Y = 0) give the white
 * point's chromaticity or zeros instead of NaN. */
void vr_xyz_to_xyy(const double xyz[3], const double white_xyz[3], double xyy[3]);
void vr_xyy_to_xyz(const double xyy[3], double xyz[3]);
void vr_xyz_to_lab(const double xyz[3], const double white_xyz[3], double lab[3]);
void vr_lab_to_xyz(const double lab[3], const double white_xyz[3], double xyz[3]);
void vr_lab_to_lch(const double lab[3], double lch[3]); /* h in degrees [0, 360) */

/* sRGB, IEC 61966-2-1:1999: linear RGB from XYZ (D65, Y = 1) with the
 * standard's 4-digit matrices, and the piecewise transfer curve. */
void vr_xyz_to_srgb_linear(const double xyz[3], double rgb[3]);
void vr_srgb_linear_to_xyz(const double rgb[3], double xyz[3]);
double vr_srgb_encode(double linear);  /* linear [0,1] -> non-linear; sign-symmetric outside */
double vr_srgb_decode(double encoded);

/* inv = m^-1 (row-major 3 x 3, by cofactors): for colour matrices, which
 * are far from singular (no check). */
void vr_mat3_inverse(const double m[9], double inv[9]);
/* 8-bit sRGB from XYZ (D65): clips to [0, 1] and rounds; returns true if
 * any linear channel lay outside [-0.001, 1.001] (out of gamut beyond the
 * precision of the standard's matrices). */
bool vr_xyz_to_srgb8(const double xyz[3], int rgb8[3]);

/* The sRGB white point (x, y = 0.3127, 0.3290 per IEC 61966-2-1) as XYZ, Y = 1. */
void vr_srgb_white(double xyz[3]);

/* Bradford chromatic adaptation (Lam 1985; CIE 159 simplified, linear). */
void vr_bradford(const double xyz[3], const double src_white[3], const double dst_white[3],
                 double out[3]);

/* Colour differences. */
double vr_delta_e76(const double lab1[3], const double lab2[3]);
/* CIEDE2000 (CIE 142-2001) with kL = kC = kH = 1, following the
 * implementation notes of Sharma, Wu and Dalal (2005). */
double vr_delta_e2000(const double lab1[3], const double lab2[3]);

/* Illuminants, relative spectral power, normalised as the CIE tables are. */
/* CIE illuminant A from its defining formula (CIE 015:2018 eq. 2.1),
 * 300-830 nm at 1 nm, 100 at 560 nm. */
vr_spectrum *vr_illuminant_a(vr_error *err);
/* CIE daylight at a correlated colour temperature 4000-25000 K from S0, S1,
 * S2 (CIE 015:2018 section 4.1), 300-830 nm at 5 nm, with M1, M2 rounded to
 * three decimals as the CIE prescribes. */
vr_spectrum *vr_illuminant_d(double cct, vr_error *err);
/* Blackbody of temperature T, 300-830 nm at 1 nm, normalised to 100 at 560 nm. */
vr_spectrum *vr_illuminant_blackbody(double kelvin, vr_error *err);
/* By name: "A", "D65" and "D50" (the CIE 1 nm tables), "D55", "D75", "E", "F1".."F12",
 * "LED-B1".."LED-B5", "LED-BH1", "LED-RGB1", "LED-V1", "LED-V2",
 * "D<CCT>" such as "D6000" for any daylight, "BB<T>" such as "BB2700" for a
 * blackbody.  Unknown names give VR_E_NOT_FOUND. */
vr_spectrum *vr_illuminant(const char *name, vr_error *err);
/* The fixed names above, for listings; count receives how many. */
const char *const *vr_illuminant_names(size_t *count);

/* Planck's law: spectral radiance in W sr^-1 m^-2 nm^-1 at wavelength nm and
 * temperature kelvin (CODATA 2018 constants). */
double vr_planck(double nm, double kelvin);

#ifdef __cplusplus
}
#endif
#endif
