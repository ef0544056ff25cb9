/* Shared by the annual-study tests (test_annual.c, test_annual_metrics.c). */
#ifndef VR_ANNUAL_TEST_UTIL_H
#define VR_ANNUAL_TEST_UTIL_H

#include "vr/sun.h"
#include "vr/weather.h"

/* The sun's altitude at the centre of a .wea record's hour (local
 * standard time, the year 2021 as the renderer takes it). */
static inline double altitude_of(const vr_weather *w, const vr_weather_record *r) {
  vr_sun_site site;
  vr_sun_site_default(&site, w->latitude_deg, w->longitude_deg);
  vr_sun_position p;
  assert_int_equal(vr_sun_position_local(&site, 2021, r->month, r->day,
                                         30.0 * (r->start_h + r->end_h), w->timezone_h, &p, NULL,
                                         NULL),
                   VR_OK);
  return p.altitude_deg;
}

#endif
