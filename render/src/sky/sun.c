/* Solar position: Meeus' low-accuracy solar coordinates (Astronomical
 * Algorithms, 2nd ed., ch. 25), Greenwich sidereal time (eq. 12.4), the
 * equatorial-to-horizontal transform (eq. 13.5-13.6), the solar parallax and
 * the refraction of Reda & Andreas' SPA (NREL/TP-560-34302, eq. 42).  Every
 * number below comes from those pages; Meeus' chapter 25 series is kept
 * exactly so that his Example 25.a reproduces digit for digit. */
#include "vr/sun.h"

#include <math.h>
#include <stdbool.h>
#include <stddef.h>

#define PI 3.14159265358979323846
#define DEG (PI / 180.0)

static double wrap360(double deg) {
  double r = fmod(deg, 360.0);
  return r < 0.0 ? r + 360.0 : r;
}

static bool leap_year(int y) { return (y % 4 == 0 && y % 100 != 0) || y % 400 == 0; }

static int days_in_month(int y, int m) {
  static const int days[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  return m == 2 && leap_year(y) ? 29 : days[m - 1];
}

void vr_sun_site_default(vr_sun_site *site, double latitude_deg, double longitude_deg) {
  site->latitude_deg = latitude_deg;
  site->longitude_deg = longitude_deg;
  /* ISO 2533 standard atmosphere at sea level. */
  site->pressure_hpa = 1013.25;
  site->temperature_c = 15.0;
  /* IERS Bulletin A: TT - UT1 = 32.184 s + (TAI - UTC = 37 s) - (UT1 - UTC,
   * under 1 s) ~ 69 s from 2017 on.  One minute of error moves the sun by
   * 0.0007 degree in longitude, so the exact value matters little. */
  site->delta_t_s = 69.0;
}

double vr_sun_julian_day(const vr_datetime *t) {
  /* Meeus eq. 7.1, Gregorian calendar. */
  int y = t->year, m = t->month;
  if (m <= 2) {
    y -= 1;
    m += 12;
  }
  double a = floor(y / 100.0);
  double b = 2.0 - a + floor(a / 4.0);
  double day = t->day + (t->hour + (t->minute + t->second / 60.0) / 60.0) / 24.0;
  return floor(365.25 * (y + 4716)) + floor(30.6001 * (m + 1)) + day + b - 1524.5;
}

static vr_status check(const vr_sun_site *s, const vr_datetime *t, vr_error *err) {
  if (!s || !t) return vr_error_set(err, VR_E_ARG, "solar position: missing site or time");
  if (t->year < 1800 || t->year > 2200)
    return vr_error_set(err, VR_E_ARG,
                        "solar position: year %d outside 1800..2200 (the range where the "
                        "series and delta T are trusted)",
                        t->year);
  if (t->month < 1 || t->month > 12)
    return vr_error_set(err, VR_E_ARG, "solar position: month %d outside 1..12", t->month);
  if (t->day < 1 || t->day > days_in_month(t->year, t->month))
    return vr_error_set(err, VR_E_ARG, "solar position: day %d does not exist in %04d-%02d",
                        t->day, t->year, t->month);
  if (t->hour < 0 || t->hour > 23)
    return vr_error_set(err, VR_E_ARG, "solar position: hour %d outside 0..23", t->hour);
  if (t->minute < 0 || t->minute > 59)
    return vr_error_set(err, VR_E_ARG, "solar position: minute %d outside 0..59", t->minute);
  if (!(t->second >= 0.0 && t->second < 61.0))
    return vr_error_set(err, VR_E_ARG, "solar position: second %g outside [0, 61)", t->second);
  if (!(s->latitude_deg >= -90.0 && s->latitude_deg <= 90.0))
    return vr_error_set(err, VR_E_ARG, "solar position: latitude %g outside [-90, 90]",
                        s->latitude_deg);
  if (!(s->longitude_deg >= -180.0 && s->longitude_deg < 360.0))
    return vr_error_set(err, VR_E_ARG, "solar position: longitude %g outside [-180, 360)",
                        s->longitude_deg);
  if (!(s->pressure_hpa >= 0.0 && s->pressure_hpa < 2000.0))
    return vr_error_set(err, VR_E_ARG, "solar position: pressure %g hPa outside [0, 2000)",
                        s->pressure_hpa);
  if (!(s->temperature_c > -100.0 && s->temperature_c < 100.0))
    return vr_error_set(err, VR_E_ARG, "solar position: temperature %g C outside (-100, 100)",
                        s->temperature_c);
  if (!(fabs(s->delta_t_s) < 3600.0))
    return vr_error_set(err, VR_E_ARG, "solar position: delta T %g s is not plausible",
                        s->delta_t_s);
  return VR_OK;
}

vr_status vr_sun_position_at(const vr_sun_site *site, const vr_datetime *utc,
                             vr_sun_position *out, vr_error *err) {
  vr_status st = check(site, utc, err);
  if (st != VR_OK) return st;

  double jd = vr_sun_julian_day(utc);
  double jde = jd + site->delta_t_s / 86400.0;
  /* Julian centuries from J2000.0: dynamical time for the orbit, universal
   * time for the Earth's rotation. */
  double T = (jde - 2451545.0) / 36525.0;
  double Tu = (jd - 2451545.0) / 36525.0;

  /* Meeus eq. 25.2-25.4: geometric mean longitude, mean anomaly, eccentricity. */
  double L0 = wrap360(280.46646 + T * (36000.76983 + T * 0.0003032));
  double M = wrap360(357.52911 + T * (35999.05029 - T * 0.0001537));
  double e = 0.016708634 - T * (0.000042037 + T * 0.0000001267);
  /* Equation of the centre (Meeus ch. 25). */
  double C = (1.914602 - T * (0.004817 + T * 0.000014)) * sin(M * DEG) +
             (0.019993 - T * 0.000101) * sin(2.0 * M * DEG) + 0.000289 * sin(3.0 * M * DEG);
  double true_lon = L0 + C, nu = M + C;
  /* Meeus eq. 25.5: radius vector in AU. */
  double R = 1.000001018 * (1.0 - e * e) / (1.0 + e * cos(nu * DEG));
  /* Apparent longitude: nutation (-0.00478 sin Omega) and aberration
   * (-0.00569), Meeus ch. 25. */
  double Omega = 125.04 - 1934.136 * T;
  double lambda = true_lon - 0.00569 - 0.00478 * sin(Omega * DEG);
  /* Mean obliquity, Meeus eq. 22.2 (23 deg 26' 21.448"), plus the
   * correction for the apparent position (Meeus eq. 25.8). */
  double eps0 = 23.0 + 26.0 / 60.0 +
                (21.448 - T * (46.8150 + T * (0.00059 - T * 0.001813))) / 3600.0;
  double eps = eps0 + 0.00256 * cos(Omega * DEG);
  /* Meeus eq. 25.6-25.7. */
  double alpha = wrap360(atan2(cos(eps * DEG) * sin(lambda * DEG), cos(lambda * DEG)) / DEG);
  double delta = asin(sin(eps * DEG) * sin(lambda * DEG)) / DEG;

  /* Greenwich mean sidereal time, Meeus eq. 12.4, then apparent sidereal
   * time with the nutation in right ascension (Meeus ch. 12). */
  double theta0 = 280.46061837 + 360.98564736629 * (jd - 2451545.0) +
                  Tu * Tu * (0.000387933 - Tu / 38710000.0);
  double theta = theta0 + (-0.00478 * sin(Omega * DEG)) * cos(eps * DEG);
  /* Local hour angle, west positive (Meeus ch. 13 with east-positive
   * longitude). */
  double H = wrap360(theta + site->longitude_deg - alpha);
  if (H > 180.0) H -= 360.0;

  double phi = site->latitude_deg * DEG;
  double sin_h = sin(phi) * sin(delta * DEG) + cos(phi) * cos(delta * DEG) * cos(H * DEG);
  if (sin_h > 1.0) sin_h = 1.0;
  if (sin_h < -1.0) sin_h = -1.0;
  double h = asin(sin_h) / DEG;
  /* Meeus eq. 13.5, multiplied through by cos(delta) so the pole needs no
   * tangent; azimuth from the south, turned to count from the north. */
  double az = atan2(sin(H * DEG) * cos(delta * DEG),
                    cos(H * DEG) * sin(phi) * cos(delta * DEG) - sin(delta * DEG) * cos(phi)) /
                  DEG +
              180.0;
  az = wrap360(az);

  /* Parallax in altitude: the equatorial horizontal parallax of the sun is
   * 8.794"/R (Meeus ch. 40; SPA eq. 33); for an observer near sea level
   * the altitude drops by that much times cos h.  At most 0.0025 deg. */
  double xi = 8.794 / 3600.0 / R;
  double h_topo = h - xi * cos(h * DEG);

  /* Refraction, SPA eq. 42 (Bennett's formula as tuned by Saemundsson,
   * scaled by P/1010 hPa and 283 K/T); SPA applies it while the sun's
   * upper limb can still be refracted above the horizon: e0 >= -(0.26667
   * sun radius + 0.5667 horizon refraction) degrees. */
  double refr = 0.0;
  if (site->pressure_hpa > 0.0 && h_topo >= -(0.26667 + 0.5667)) {
    refr = (site->pressure_hpa / 1010.0) * (283.0 / (273.0 + site->temperature_c)) * 1.02 /
           (60.0 * tan((h_topo + 10.3 / (h_topo + 5.11)) * DEG));
  }
  double h_app = h_topo + refr;

  out->altitude_deg = h_app;
  out->zenith_deg = 90.0 - h_app;
  out->azimuth_deg = az;
  vr_sun_direction_of(h_app, az, out->direction);
  out->true_altitude_deg = h_topo;
  out->declination_deg = delta;
  out->right_ascension_deg = alpha;
  out->hour_angle_deg = H;
  out->distance_au = R;
  out->julian_day = jd;
  return VR_OK;
}

void vr_sun_direction_of(double altitude_deg, double azimuth_deg, double dir[3]) {
  double h = altitude_deg * DEG, a = azimuth_deg * DEG;
  dir[0] = cos(h) * sin(a);
  dir[1] = cos(h) * cos(a);
  dir[2] = sin(h);
}

bool vr_sun_angles_of(const double dir[3], double *altitude_deg, double *azimuth_deg) {
  double horiz = hypot(dir[0], dir[1]);
  double len = hypot(horiz, dir[2]);
  if (!(len > 0.0)) return false;
  if (altitude_deg) *altitude_deg = atan2(dir[2], horiz) / DEG;
  if (azimuth_deg) *azimuth_deg = horiz > 0.0 ? wrap360(atan2(dir[0], dir[1]) / DEG) : 0.0;
  return true;
}

static int month_days(int y, int m) {
  static const int D[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  bool leap = (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
  return m == 2 && leap ? 29 : D[m - 1];
}

vr_status vr_sun_position_local(const vr_sun_site *site, int y, int m, int d, double minutes,
                                double tz_h, vr_sun_position *out, vr_datetime *utc,
                                vr_error *err) {
  if (m < 1 || m > 12 || d < 1 || d > month_days(y, m) || !isfinite(minutes) || !isfinite(tz_h))
    return vr_error_set(err, VR_E_ARG, "local time %04d-%02d-%02d %g min (zone %+g h) is not a date",
                        y, m, d, minutes, tz_h);
  minutes -= tz_h * 60.0;
  while (minutes < 0) {
    minutes += 1440;
    if (--d < 1) {
      if (--m < 1) m = 12, y--;
      d = month_days(y, m);
    }
  }
  while (minutes >= 1440) {
    minutes -= 1440;
    if (++d > month_days(y, m)) {
      d = 1;
      if (++m > 12) m = 1, y++;
    }
  }
  vr_datetime t = {y, m, d, (int)(minutes / 60), (int)fmod(minutes, 60.0), 0.0};
  t.second = (minutes - floor(minutes)) * 60.0;
  if (utc) *utc = t;
  return vr_sun_position_at(site, &t, out, err);
}
