/* The Perez all-weather sky: from measured (or weather-file) irradiances to
 * the sky's luminance distribution, its diffuse illuminance and the sun's
 * direct normal illuminance.
 *
 * Two published models, both by Perez and co-authors:
 *
 *  - Perez, Ineichen, Seals, Michalsky & Stewart, "Modeling daylight
 *    availability and irradiance components from direct and global
 *    irradiance", Solar Energy 44(5):271-289, 1990: the sky clearness
 *    epsilon (eq. 1), the sky brightness Delta (eq. 2), the precipitable
 *    water from the dew point (eq. 3), and the luminous efficacies of the
 *    diffuse (eq. 7) and direct (eq. 8) light and the zenith luminance
 *    (eq. 9) with the coefficients of Table 4, per clearness bin.
 *  - Perez, Seals & Michalsky, "All-weather model for sky luminance
 *    distribution - preliminary configuration and validation", Solar
 *    Energy 50(3):235-245, 1993, with its erratum (Solar Energy 51(5):423):
 *    the relative luminance
 *        lv(zeta, gamma) = [1 + a exp(b / cos zeta)] [1 + c exp(d gamma) + e cos^2 gamma]
 *    (zeta the element's zenith angle, gamma its angle from the sun) with
 *    a..e from Table 1: x = x1 + x2 Z + Delta (x3 + x4 Z) per bin, Z the
 *    solar zenith angle in radians, and special forms of c and d in the
 *    first (overcast) bin.
 *
 * The coefficient tables are carried over from the papers as tabulated in
 * Radiance's gendaylit.c (NREL/Radiance, src/gen; coeff_perez and the
 * efficacy functions), which is the implementation lighting designers
 * compare against.  The same program fixes the conventions the papers
 * leave open, which are followed here: the relative optical air mass of
 * Kasten (1966), m = 1 / (cos Z + 0.15 (93.885 - Z_deg)^-1.253); the
 * extraterrestrial irradiance 1367 W/m2 times Spencer's (1971) eccentricity
 * factor; epsilon limited to [1, 12.01] and Delta to [0.01, 0.6] (the range
 * of the data the models were fitted on); and, for 1.065 < epsilon < 2.8,
 * Delta raised to at least 0.2 before the luminance coefficients are
 * formed (below it those bins give skies darker at the zenith than at the
 * horizon by orders of magnitude).  Every such limit that acts is reported
 * in vr_perez_sky.limited, never applied silently.
 *
 * Domain: a sun above the horizon (zenith angle < 90 degrees), diffuse
 * horizontal irradiance > 0, direct normal irradiance >= 0, all finite.
 * Thread-safe, no state. */
#ifndef VR_PEREZ_H
#define VR_PEREZ_H

#include "vr/error.h"
#include <stddef.h>

#include "vr/sky_params.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Clearness bin bounds of Perez (1990) Table 1: bin i (1..8) holds
 * epsilon in [VR_PEREZ_BOUNDS[i-1], VR_PEREZ_BOUNDS[i]). */
extern const double VR_PEREZ_BOUNDS[9];

/* The inputs, as a weather file gives them. */
typedef struct vr_perez_input {
  double sun_zenith_deg;     /* true solar zenith angle, [0, 90) */
  double direct_normal_w_m2; /* direct normal irradiance, >= 0 */
  double diffuse_horizontal_w_m2; /* diffuse horizontal irradiance, > 0 */
  double dew_point_c;        /* surface dew point, for the precipitable water; NAN: W = 2 cm */
  int day_of_year;           /* 1..366, for the Earth-Sun distance; 0: the mean
                                distance (1367 W/m2) */
} vr_perez_input;

/* Which of the model's domain limits acted (bits). */
enum {
  VR_PEREZ_LIMIT_EPSILON_LOW = 1,  /* epsilon < 1 raised to 1 */
  VR_PEREZ_LIMIT_EPSILON_HIGH = 2, /* epsilon > 12.01 lowered to 12.01 */
  VR_PEREZ_LIMIT_DELTA_LOW = 4,    /* Delta < 0.01 raised to 0.01 */
  VR_PEREZ_LIMIT_DELTA_HIGH = 8,   /* Delta > 0.6 lowered to 0.6 */
  VR_PEREZ_LIMIT_DELTA_BIN = 16,   /* 1.065 < epsilon < 2.8, Delta < 0.2: 0.2 for a..e */
};

typedef struct vr_perez_sky {
  double epsilon_raw, delta_raw; /* as computed from the inputs */
  double epsilon, delta;         /* after the domain limits */
  int bin;                       /* clearness bin 1..8 */
  int limited;                   /* VR_PEREZ_LIMIT_* bits that acted */
  double air_mass;               /* relative optical air mass (Kasten 1966) */
  double extraterrestrial_w_m2;  /* normal incidence, at this day's distance */
  double water_cm;               /* precipitable water W */
  vr_sky_params lum;             /* a..e of the 1993 luminance distribution */
  double diffuse_efficacy;       /* lm/W, eq. 7 */
  double direct_efficacy;        /* lm/W, eq. 8 (0 where the fit goes negative) */
  double diffuse_horizontal_lx;  /* E_dh = diffuse irradiance x diffuse efficacy */
  double direct_normal_lx;       /* E_dn = direct irradiance x direct efficacy */
  double zenith_cd_m2;           /* eq. 9: the 1990 zenith luminance estimate */
} vr_perez_sky;

/* Precipitable water (cm) from the surface dew point (deg C), Perez 1990
 * eq. 3: W = exp(0.07 Td - 0.075). */
double vr_perez_water_cm(double dew_point_c);
/* Relative optical air mass of Kasten (1966), zenith angle in degrees. */
double vr_perez_air_mass(double sun_zenith_deg);
/* Extraterrestrial normal irradiance on a day of the year: 1367 W/m2 times
 * Spencer's eccentricity factor. */
double vr_perez_extraterrestrial(int day_of_year);
/* The clearness bin (1..8) of an epsilon already in [1, 12.01]. */
int vr_perez_bin(double epsilon);

/* The 1993 distribution's factors, each held at 0 or more: the gradation
 * 1 + a exp(b / max(cos zeta, 0.01)) (the floor keeps a positive b from
 * exploding at the horizon, as Radiance's perezlum.cal does), the
 * indicatrix 1 + c exp(d gamma) + e cos^2 gamma, and their product for a
 * unit direction and a unit sun direction (0 below the horizon); not
 * normalised. */
double vr_perez_gradation(const vr_sky_params *p, double cos_zeta);
double vr_perez_indicatrix(const vr_sky_params *p, double gamma);
double vr_perez_relative(const vr_sky_params *p, const double sun[3], const double dir[3]);

/* The 1993 luminance coefficients a..e for a solar zenith angle (radians),
 * a clearness and a brightness already inside the model's domain. */
void vr_perez_luminance_params(double sun_zenith_rad, double epsilon, double delta,
                               vr_sky_params *out);

/* The 1990 efficacies (lm/W) and zenith luminance coefficient (cd/m2 per
 * W/m2 of diffuse irradiance) of one bin, for a zenith angle in radians, a
 * brightness and a precipitable water in cm. */
double vr_perez_diffuse_efficacy(int bin, double sun_zenith_rad, double delta, double water_cm);
double vr_perez_direct_efficacy(int bin, double sun_zenith_rad, double delta, double water_cm);
double vr_perez_zenith_ratio(int bin, double sun_zenith_rad, double delta);

/* Everything from the inputs.  VR_E_RANGE names the input out of the
 * domain (a sun on or below the horizon, no diffuse light, a negative or
 * non-finite irradiance, a day outside 0..366). */
vr_status vr_perez_sky_from(const vr_perez_input *in, vr_perez_sky *out, vr_error *err);

/* A short human-readable list of the limits that acted ("" if none). */
const char *vr_perez_limits_text(int limited, char *buf, size_t size);

#ifdef __cplusplus
}
#endif
#endif
