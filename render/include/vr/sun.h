/* Where the sun is: solar position from latitude, longitude and a UTC date
 * and time, for the sun light and the sun-dependent CIE skies.
 *
 * Algorithm: the "low accuracy" solar coordinates of Meeus, Astronomical
 * Algorithms (2nd ed., 1998), chapter 25 (the same series NOAA's solar
 * calculator uses), sidereal time from Meeus eq. 12.4, the horizontal
 * coordinates of Meeus eq. 13.5-13.6, the solar parallax in altitude, and
 * atmospheric refraction from Reda & Andreas, "Solar position algorithm for
 * solar radiation applications", NREL/TP-560-34302 (2008 revision), eq. 42
 * (Saemundsson / Bennett, scaled for pressure and temperature).
 *
 * Accuracy: Meeus states 0.01 degree for the solar coordinates of this
 * series; on Reda & Andreas' own SPA test case (tests/render/test_sun.c)
 * the zenith angle is off by 0.001 degree and the azimuth by 0.006 degree,
 * nearly all of it from the truncated solar longitude (the full SPA, with
 * the VSOP87 series, reaches 0.0003 degree).  Dates are accepted from 1800 to 2200, where the series and
 * the supplied delta T are meaningful.
 *
 * Conventions: z up; azimuth measured from north (+y) towards east (+x),
 * in [0, 360); altitude above the horizon.  Thread-safe, no state. */
#ifndef VR_SUN_H
#define VR_SUN_H

#include <stdbool.h>
#include "vr/error.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A civil date and time in UTC (not local time: subtract the zone offset). */
typedef struct vr_datetime {
  int year, month, day;  /* Gregorian calendar, 1800..2200 */
  int hour, minute;      /* 0..23, 0..59 */
  double second;         /* [0, 61) to allow a leap second */
} vr_datetime;

/* Where and in what air the sun is observed. */
typedef struct vr_sun_site {
  double latitude_deg;   /* north positive, [-90, 90] */
  double longitude_deg;  /* EAST positive, [-180, 360) */
  double pressure_hpa;   /* for refraction; 0 turns refraction off */
  double temperature_c;  /* for refraction */
  double delta_t_s;      /* TT - UT1, seconds (about 69 s around 2020) */
} vr_sun_site;

/* Fills a site with sea-level standard air (1013.25 hPa, 15 C) and
 * delta T = 69 s (IERS, about 2020), refraction on. */
void vr_sun_site_default(vr_sun_site *site, double latitude_deg, double longitude_deg);

typedef struct vr_sun_position {
  double altitude_deg;       /* apparent (topocentric, refracted) altitude */
  double zenith_deg;         /* 90 - altitude_deg */
  double azimuth_deg;        /* from north towards east, [0, 360) */
  double direction[3];       /* unit vector from the observer towards the sun */
  double true_altitude_deg;  /* geometric altitude before refraction (with parallax) */
  double declination_deg;    /* apparent geocentric declination */
  double right_ascension_deg;/* apparent geocentric right ascension, [0, 360) */
  double hour_angle_deg;     /* local hour angle, (-180, 180], west positive */
  double distance_au;        /* Earth-Sun distance, astronomical units */
  double julian_day;         /* Julian day (UT) of the instant */
} vr_sun_position;

/* Julian day (UT) of a Gregorian date and time, Meeus eq. 7.1. */
double vr_sun_julian_day(const vr_datetime *utc);

/* Solar position for a site and a UTC instant.  VR_E_ARG names the field
 * out of range (month, day, latitude, ...). */
vr_status vr_sun_position_at(const vr_sun_site *site, const vr_datetime *utc,
                             vr_sun_position *out, vr_error *err);

/* The same for a local civil time: `minutes` after midnight of y-m-d in
 * a zone tz_h hours east of UTC (any value; the date rolls over as
 * needed).  *utc (may be NULL) receives the UTC instant. */
vr_status vr_sun_position_local(const vr_sun_site *site, int y, int m, int d, double minutes,
                                double tz_h, vr_sun_position *out, vr_datetime *utc,
                                vr_error *err);

/* Unit vector of a direction given as altitude and azimuth (degrees, azimuth
 * from +y towards +x): (cos h sin A, cos h cos A, sin h). */
void vr_sun_direction_of(double altitude_deg, double azimuth_deg, double dir[3]);
/* The inverse: altitude and azimuth ([0, 360)) of a direction; dir need not
 * be unit length; false for the zero vector. */
bool vr_sun_angles_of(const double dir[3], double *altitude_deg, double *azimuth_deg);

#ifdef __cplusplus
}
#endif
#endif
