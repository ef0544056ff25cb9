/* The Perez sky in a scene: `sky perez` from given irradiances or from a
 * weather file's record, the sun it lights, the messages for what does not
 * fit together, and a rendered reading against an analytic value.
 *
 * Analytic check: a horizontal sensor open to the whole sky reads the
 * diffuse horizontal illuminance the sky was scaled to plus the sun's
 * direct normal illuminance times sin(altitude) (energy conservation of
 * the sky's normalisation and of its importance sampling; the efficacies
 * themselves are checked in test_perez.c against ladybug's vector).
 *
 * Weather files are real published files (tests/data/weather/SOURCES.md):
 * ladybug's chicago.wea (written by ladybug from the Chicago O'Hare TMY3
 * EPW). */
#include <unistd.h>

#include "vr_test.h"

#include "render_test_util.h"
#include "vr/sky.h"
#include "vr/sun.h"
#include "vr/weather.h"

#ifndef VR_TEST_DATA
#error "VR_TEST_DATA must name tests/data"
#endif

static vr_status parse(const char *text, vr_scene **s, vr_error *err) {
  return vr_scene_parse(text, strlen(text), "room.scn", s, err);
}

static void refused(const char *text, const char *needle) {
  vr_scene *s = NULL;
  vr_error err = {0};
  char buf[5000];
  snprintf(buf, sizeof buf, "%ssensor s point position=0,0,0 normal=0,0,1\n", text);
  assert_int_equal(parse(buf, &s, &err), VR_E_PARSE);
  if (!strstr(err.message, needle)) fail_msg("'%s' does not say '%s'", err.message, needle);
  assert_null(s);
}

static void open_sky_reads_its_illuminance(void **state) {
  (void)state;
  const char *scn = "material black lambert reflectance=0\n"
                    "rect center=0,0,-0.01 normal=0,0,1 size=2,2 material=black\n"
                    "light sun altitude=60 azimuth=180 spectrum=D65\n"
                    "sky perez direct_normal=800 diffuse_horizontal=200 dew_point=15\n"
                    "sensor p point position=0,0,0 normal=0,0,1\n"
                    "render sensors=path sensor_samples=65536\n";
  vr_scene *s = parse_text(scn, "open.scn");
  const vr_perez_sky *m = &s->sky.perez;
  assert_int_equal(s->sky.cie_type, VR_SKY_PEREZ);
  assert_int_equal(m->bin, 6);
  /* The scene carries the model's levels: the sky's in lx, the sun's. */
  assert_near(s->sky.level.value, m->diffuse_horizontal_lx, 0);
  assert_near(s->lights[0].amount.value, m->direct_normal_lx, 0);
  double want = m->diffuse_horizontal_lx + m->direct_normal_lx * sin(60 * M_PI / 180);
  vr_render_result *r = render_scene_with(s, NULL, 1, 2, true, false);
  const vr_sensor_reading *p = &r->readings[0];
  print_message("  open sky: %.1f lx +- %.1f (E_dh + E_dn sin h = %.1f lx)\n", p->illuminance_lx,
                p->stderr_lx, want);
  assert_near(p->illuminance_lx, want, fmax(4 * p->stderr_lx, 1e-4 * want));
  assert_near(r->sky_horizontal_lx, m->diffuse_horizontal_lx, 1e-6 * want);
  vr_render_result_destroy(r);
  vr_scene_destroy(s);
}

static void mismatches_refused(void **state) {
  (void)state;
  refused("light sun altitude=60 azimuth=180 illuminance=1000\n"
          "sky perez direct_normal=800 diffuse_horizontal=200\n",
          "room.scn:1:1: the sun's illuminance comes from the Perez sky on line 2");
  refused("sky perez direct_normal=800 diffuse_horizontal=200 sun=60,180\n",
          "no 'light sun' line to carry it");
  refused("sky perez direct_normal=0 diffuse_horizontal=200\n", "does not say where the sun is");
  refused("light sun altitude=60 azimuth=180\nsky cie type=12 illuminance=10000\n",
          "room.scn:1:1: a sun needs illuminance=");
  refused("light sun illuminance=1000\nsky cie type=12 illuminance=10000\n",
          "only a weather sky");
  refused("sky perez diffuse_horizontal=200 sun=60,180\n", "direct_normal");
  refused("sky perez direct_normal=100 diffuse_horizontal=0 sun=60,180\n", "diffuse_horizontal");
  refused("sky perez direct_normal=100 diffuse_horizontal=50 date=01-05\n",
          "date= picks a record of a weather file");
  refused("sky perez weather=x.wea direct_normal=100 date=01-05 time=11:00\n",
          "direct_normal= with weather=");
  refused("light sun\nsky perez weather=missing.wea date=01-05 time=11:00\n", "missing.wea");
  /* A direct-only sky with no diffuse light has no Perez distribution. */
  refused("light sun altitude=60 azimuth=180\n"
          "sky perez direct_normal=800 diffuse_horizontal=0.0\n",
          "diffuse_horizontal");
}

/* chicago.wea, 5 January: "1 5 11.500 859 69" is the record for
 * 11:00-12:00 local standard time (UTC-6, time_zone 90 deg west). */
static void weather_record_and_sun(void **state) {
  (void)state;
  char text[1024];
  snprintf(text, sizeof text,
           "material black lambert reflectance=0\n"
           "rect center=0,0,-0.01 normal=0,0,1 size=2,2 material=black\n"
           "light sun spectrum=D65\n"
           "sky perez weather=%s/weather/chicago.wea date=01-05 time=11:10\n"
           "sensor p point position=0,0,0 normal=0,0,1\n"
           "render sensors=path sensor_samples=16384\n",
           VR_TEST_DATA);
  vr_scene *s = parse_text(text, "chicago.scn");
  assert_near(s->sky.direct_normal_w_m2, 859, 0);
  assert_near(s->sky.diffuse_horizontal_w_m2, 69, 0);
  assert_true(isnan(s->sky.dew_point_c)); /* a .wea has none: W = 2 cm */
  assert_int_equal(s->sky.day_of_year, 5);
  /* The sun: Chicago O'Hare (41.98 N, 87.92 W), 2021-01-05 11:10 CST =
   * 17:10 UTC, through the library's solar position (tested against
   * Reda & Andreas' SPA case in test_sun.c). */
  vr_sun_site site;
  vr_sun_site_default(&site, 41.98, -87.92);
  vr_datetime utc = {2021, 1, 5, 17, 10, 0};
  vr_sun_position pos;
  vr_error err = {0};
  assert_int_equal(vr_sun_position_at(&site, &utc, &pos, &err), VR_OK);
  for (int k = 0; k < 3; k++) {
    assert_near(s->sky.sun_direction[k], pos.direction[k], 1e-12);
    assert_near(s->lights[0].direction[k], pos.direction[k], 1e-12);
  }
  /* A winter noon sun in Chicago: about 25 degrees high, to the south. */
  assert_true(pos.altitude_deg > 20 && pos.altitude_deg < 28);
  assert_true(pos.azimuth_deg > 160 && pos.azimuth_deg < 200);
  vr_render_result *r = render_scene_with(s, NULL, 1, 2, true, false);
  double want = s->sky.perez.diffuse_horizontal_lx +
                s->sky.perez.direct_normal_lx * sin(pos.altitude_deg * M_PI / 180);
  assert_near(r->readings[0].illuminance_lx, want, fmax(4 * r->readings[0].stderr_lx, 1e-4 * want));
  vr_render_result_destroy(r);
  vr_scene_destroy(s);
  /* Night, and a date the file lacks. */
  snprintf(text, sizeof text, "light sun\nsky perez weather=%s/weather/chicago.wea date=01-05 time=03:00\n",
           VR_TEST_DATA);
  refused(text, "below the horizon");
  snprintf(text, sizeof text, "light sun\nsky perez weather=%s/weather/chicago.wea date=02-29 time=12:00\n",
           VR_TEST_DATA);
  refused(text, "no record for 02-29");
  /* The weather sky places the sun: a sun line that places it too is
   * refused. */
  snprintf(text, sizeof text,
           "light sun altitude=30 azimuth=180\nsky perez weather=%s/weather/chicago.wea "
           "date=01-05 time=11:10\n",
           VR_TEST_DATA);
  refused(text, "places the sun from its file's site");
}

static void weather_file_reading(void **state) {
  (void)state;
  char path[4096];
  snprintf(path, sizeof path, "%s/weather/chicago.wea", VR_TEST_DATA);
  vr_weather *w = NULL;
  vr_error err = {0};
  assert_int_equal(vr_weather_read(path, &w, &err), VR_OK);
  assert_false(w->epw);
  assert_string_equal(w->place, "Chicago Ohare Intl Ap_USA");
  assert_near(w->latitude_deg, 41.98, 0);
  assert_near(w->longitude_deg, -87.92, 0); /* .wea: 87.92 west */
  assert_near(w->timezone_h, -6, 0);        /* time_zone 90 deg west */
  assert_int_equal(w->nrecords, 8760);
  const vr_weather_record *r = NULL;
  assert_int_equal(vr_weather_find(w, 1, 5, 11.0, &r, &err), VR_OK);
  assert_near(r->start_h, 11.0, 1e-12);
  assert_near(r->end_h, 12.0, 1e-12);
  assert_near(r->direct_normal_w_m2, 859, 0);
  assert_near(r->diffuse_horizontal_w_m2, 69, 0);
  assert_int_equal(r->line, 6 + 4 * 24 + 12);
  assert_int_equal(vr_weather_find(w, 12, 31, 23.99, &r, &err), VR_OK);
  assert_near(r->end_h, 24.0, 1e-12);
  vr_weather_free(w);
}

/* A real EnergyPlus file (tests/data/weather/SOURCES.md): Aachen-Orsbach,
 * 1-9 January 2022, time zone 0.  Line 117, "2022,1,5,13,0,...": the hour
 * ending 13:00 has dew point 1.1 C, direct normal 16.2 W/m2 and diffuse
 * horizontal 19.5 W/m2. */
static void epw_record(void **state) {
  (void)state;
  char path[4096];
  snprintf(path, sizeof path, "%s/weather/15000_20220101_20220110_Aachen-Orsbach.epw", VR_TEST_DATA);
  vr_weather *w = NULL;
  vr_error err = {0};
  assert_int_equal(vr_weather_read(path, &w, &err), VR_OK);
  assert_true(w->epw);
  assert_string_equal(w->place, "Aachen-Orsbach");
  assert_near(w->latitude_deg, 50.798, 0);
  assert_near(w->longitude_deg, 6.024, 0);
  assert_near(w->timezone_h, 0, 0);
  assert_int_equal(w->nrecords, 216); /* 9 days x 24 hours */
  const vr_weather_record *r = NULL;
  assert_int_equal(vr_weather_find(w, 1, 5, 12.5, &r, &err), VR_OK);
  assert_int_equal(r->line, 117);
  assert_int_equal(r->year, 2022);
  assert_near(r->start_h, 12, 0);
  assert_near(r->end_h, 13, 0);
  assert_near(r->dew_point_c, 1.1, 0);
  assert_near(r->direct_normal_w_m2, 16.2, 0);
  assert_near(r->diffuse_horizontal_w_m2, 19.5, 0);
  /* 10 January is not in the file. */
  assert_int_equal(vr_weather_find(w, 1, 10, 12, &r, &err), VR_E_RANGE);
  vr_weather_free(w);
  /* In a scene: the record, its dew point, the sun from the site. */
  char text[4600];
  snprintf(text, sizeof text,
           "light sun spectrum=D65\nsky perez weather=%s date=01-05 time=12:30\n"
           "sensor p point position=0,0,0 normal=0,0,1\n",
           path);
  vr_scene *s = parse_text(text, "aachen.scn");
  assert_near(s->sky.dew_point_c, 1.1, 0);
  assert_near(s->sky.perez.water_cm, exp(0.07 * 1.1 - 0.075), 1e-12); /* Perez 1990 eq. 3 */
  assert_int_equal(s->sky.weather_line, 117);
  vr_sun_site site;
  vr_sun_site_default(&site, 50.798, 6.024);
  vr_datetime utc = {2022, 1, 5, 12, 30, 0};
  vr_sun_position pos;
  assert_int_equal(vr_sun_position_at(&site, &utc, &pos, &err), VR_OK);
  for (int k = 0; k < 3; k++) assert_near(s->lights[0].direction[k], pos.direction[k], 1e-12);
  vr_scene_destroy(s);
  /* 16:30 on 5 January in Aachen: the record has no diffuse light (the
   * sun is all but set): refused, naming the file and its line. */
  snprintf(text, sizeof text, "light sun\nsky perez weather=%s date=01-05 time=15:30\n", path);
  refused(text, ":120: no diffuse light");
}

/* Malformed files: each refused with the file, the line and the field. */
static void weather_bad_input(void **state) {
  (void)state;
  const struct {
    const char *text, *needle;
  } CASES[] = {
      {"", ":1: empty weather file"},
      {"hello\n", "not a weather file"},
      {"place X\nlatitude 41\nlongitude 87\ntime_zone 90\nsite_elevation 1\n"
       "weather_data_file_units 2\n1 1 0.5 0 0\n",
       ":6: weather_data_file_units"},
      {"place X\nlatitude north\n", ":2: latitude: \"north\" is not a number"},
      {"place X\nlatitude 41\nlongitude 87\ntime_zone 90\nsite_elevation 1\n"
       "weather_data_file_units 1\n1 1 0.5 0 0\n1 1 1.5 0\n",
       ":8: a .wea record"},
      {"place X\nlatitude 41\nlongitude 87\ntime_zone 90\nsite_elevation 1\n"
       "weather_data_file_units 1\n1 1 0.5 0 nan\n",
       ":7: diffuse horizontal irradiance"},
      {"place X\nlatitude 41\nlongitude 87\ntime_zone 90\nsite_elevation 1\n"
       "weather_data_file_units 1\n13 1 0.5 0 0\n",
       ":7: month"},
      {"place X\nlatitude 41\nlongitude 87\ntime_zone 90\nsite_elevation 1\n"
       "weather_data_file_units 1\n1 1 0.5 -3 0\n",
       ":7: direct normal irradiance: is negative"},
      {"LOCATION,X,,,,,41,-87\n", ":1: LOCATION"},
      {"LOCATION,X,,,,,41,-87,-6,200\nD\nT\nG\nH\nC1\nC2\n", "ends inside the EPW header"},
      {"LOCATION,X,,,,,41,-87,-6,200\nD\nT\nG\nH\nC1\nC2\nDP\n1999,1,1,1,0,?,1,2,3,4,5,6,7,8,9\n",
       ":9: an EPW record needs at least 16 fields"},
      {"LOCATION,X,,,,,41,-87,-6,200\nD\nT\nG\nH\nC1\nC2\nDP\n1999,1,1,25,0,?,1,2,3,4,5,6,7,8,9,10\n",
       ":9: hour"},
  };
  char path[] = "/tmp/vr_weather_XXXXXX";
  int fd = mkstemp(path);
  assert_true(fd >= 0);
  close(fd);
  for (size_t i = 0; i < sizeof CASES / sizeof CASES[0]; i++) {
    FILE *f = fopen(path, "w");
    fputs(CASES[i].text, f);
    fclose(f);
    vr_weather *w = (vr_weather *)&w;
    vr_error err = {0};
    vr_status st = vr_weather_read(path, &w, &err);
    if (st == VR_OK || !strstr(err.message, CASES[i].needle) || !strstr(err.message, path))
      fail_msg("case %zu: status %d, '%s' (expected '%s')", i, (int)st, err.message, CASES[i].needle);
    assert_null(w);
  }
  remove(path);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(open_sky_reads_its_illuminance), cmocka_unit_test(mismatches_refused),
      cmocka_unit_test(weather_record_and_sun),         cmocka_unit_test(weather_file_reading),
      cmocka_unit_test(weather_bad_input),              cmocka_unit_test(epw_record),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
