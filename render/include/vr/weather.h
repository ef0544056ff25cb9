/* Weather files: the irradiances a Perez sky is made from, hour by hour.
 *
 * Two formats, told apart by their first line:
 *
 *  - EnergyPlus weather (.epw; "Auxiliary Programs", EnergyPlus
 *    documentation, "Weather Converter Program" chapter): a LOCATION line
 *    (city, state, country, source, WMO, latitude north +, longitude
 *    east +, time zone in hours from UTC, elevation), seven more header
 *    lines, then one comma-separated record per interval: year, month, day,
 *    hour 1..24 (the interval ENDING at that hour, local standard time),
 *    minute, flags, dry bulb, dew point (field 8) ... direct normal (field
 *    15) and diffuse horizontal (field 16) irradiance in W/m2 (averages over
 *    the interval).  9999 marks missing radiation, 99.9 a missing dew point.
 *  - Radiance/Daysim .wea (as epw2wea and ladybug write it): place,
 *    latitude (north +), longitude (WEST +), time_zone (the standard
 *    meridian in degrees WEST: 90 is UTC-6), site_elevation and
 *    weather_data_file_units (1: direct normal and diffuse horizontal
 *    irradiance in W/m2, the only kind read here), then
 *    "month day hour dni dhi" lines, hour the CENTRE of the interval in
 *    decimal hours of local standard time.
 *
 * Both are converted to one form: records with the interval they average
 * over, [start, end) in decimal hours of the local standard day. */
#ifndef VR_WEATHER_H
#define VR_WEATHER_H

#include <stdbool.h>
#include <stddef.h>

#include "vr/error.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vr_weather_record {
  int year;                  /* EPW's year field; 0 in a .wea */
  int month, day;
  double start_h, end_h;     /* the interval, local standard time, hours of the day */
  double direct_normal_w_m2, diffuse_horizontal_w_m2;
  double dew_point_c;        /* NAN where the file has none */
  long line;                 /* 1-based line in the file */
} vr_weather_record;

typedef struct vr_weather {
  char *path;
  char place[128];
  double latitude_deg;       /* north + */
  double longitude_deg;      /* EAST + (a .wea's west-positive value is negated) */
  double timezone_h;         /* hours east of UTC of the local standard time */
  double elevation_m;
  bool epw;
  vr_weather_record *records;
  size_t nrecords;
} vr_weather;

/* Reads a weather file.  A malformed line, a missing field, a value that is
 * not a number or is out of range is VR_E_PARSE naming the file, the line
 * and the field.  A missing irradiance (EPW 9999) is kept as NAN and only
 * refused when that record is used. */
vr_status vr_weather_read(const char *path, vr_weather **out, vr_error *err);
void vr_weather_free(vr_weather *w);

/* Day of the year (1..366) of a record (its year's, or a 365-day year's). */
int vr_weather_day_of_year(const vr_weather_record *r);

/* The record whose interval holds a local standard time (hours, [0, 24))
 * on a month and day.  VR_E_RANGE when the file has no such record (a
 * 29 February in a 365-day year, a partial file). */
vr_status vr_weather_find(const vr_weather *w, int month, int day, double hour,
                          const vr_weather_record **rec, vr_error *err);

#ifdef __cplusplus
}
#endif
#endif
