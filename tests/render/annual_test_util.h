/* Shared by the annual-study tests (test_annual.c, test_annual_metrics.c,
 * test_annual_glare.c). */
#ifndef VR_ANNUAL_TEST_UTIL_H
#define VR_ANNUAL_TEST_UTIL_H

#include "vr/annual.h"
#include "vr/perez.h"
#include "vr/sun.h"
#include "vr/weather.h"

/* The Perez (1990) sky of a record whose sun stands alt degrees high (no
 * dew point: W = 2 cm, as gendaylit). */
static inline vr_perez_sky record_perez(const vr_weather_record *rec, double alt) {
  vr_perez_input in = {90 - alt, rec->direct_normal_w_m2, rec->diffuse_horizontal_w_m2, NAN,
                       vr_weather_day_of_year(rec)};
  vr_perez_sky m;
  assert_int_equal(vr_perez_sky_from(&in, &m, NULL), VR_OK);
  return m;
}

/* Parses text (named as a scene of tests/data, so that its relative paths
 * resolve there; render_test_util.h's parse_text) and runs its annual
 * study on two threads, sensors only; a failure fails the test. */
static inline vr_annual_result *annual_run_text(const char *text, struct vr_matdb *db) {
  vr_scene *s = parse_text(text, VR_TEST_DATA "/annual.scn");
  vr_render_options o;
  vr_render_options_default(&o);
  o.threads = 2;
  o.no_camera = true;
  vr_annual_result *r = NULL;
  vr_error err = {0};
  vr_status st = vr_annual_run(s, db, &o, &r, &err);
  if (st) fprintf(stderr, "annual: %s\n", err.message);
  assert_int_equal(st, VR_OK);
  vr_scene_destroy(s);
  return r;
}

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
