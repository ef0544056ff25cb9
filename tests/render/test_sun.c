/* Solar position against published test cases: Reda & Andreas' SPA
 * example (NREL/TP-560-34302, 2008 revision, Table A5.2) and Meeus,
 * Astronomical Algorithms 2nd ed., Examples 7.a and 25.a. */
#include "vr_test.h"
#include "vr/sun.h"

static void julian_day(void **state) {
  (void)state;
  /* Meeus Example 7.a: 1957 October 4.81 (19:26:24) -> JD 2436116.31;
   * J2000.0 = 2000 January 1.5 -> 2451545.0. */
  vr_datetime t = {1957, 10, 4, 19, 26, 24.0};
  assert_near(vr_sun_julian_day(&t), 2436116.31, 1e-8);
  vr_datetime j2000 = {2000, 1, 1, 12, 0, 0.0};
  assert_near(vr_sun_julian_day(&j2000), 2451545.0, 0);
  /* Reda & Andreas Table A5.2: 2003-10-17 12:30:30 at UTC-7 -> 2452930.312847. */
  vr_datetime spa = {2003, 10, 17, 19, 30, 30.0};
  assert_near(vr_sun_julian_day(&spa), 2452930.312847, 5e-7);
}

static void meeus_example_25a(void **state) {
  (void)state;
  /* 1992 October 13.0 TD: apparent alpha = 13h13m31.4s = 198.38083 deg,
   * delta = -7 deg 47' 06" = -7.78507 deg, R = 0.99766 AU.  delta T = 0 so
   * that UT = TD as in the example. */
  vr_sun_site site;
  vr_sun_site_default(&site, 0.0, 0.0);
  site.delta_t_s = 0.0;
  vr_datetime t = {1992, 10, 13, 0, 0, 0.0};
  vr_sun_position p;
  vr_error err = {0};
  if (vr_sun_position_at(&site, &t, &p, &err) != VR_OK) fail_msg("%s", err.message);
  assert_near(p.right_ascension_deg, 198.38083, 1e-5);
  assert_near(p.declination_deg, -7.78507, 1e-5);
  assert_near(p.distance_au, 0.99766, 1e-5);
}

static void spa_test_case(void **state) {
  (void)state;
  /* Reda & Andreas (2008), Table A5.2: 2003-10-17 12:30:30 local, UTC-7,
   * latitude 39.742476, longitude -105.1786, 820 mbar, 11 C, delta T 67 s:
   * topocentric zenith 50.11162 deg, azimuth 194.34024 deg; geocentric
   * alpha 202.22741, delta -9.31434, hour angle 11.105900, R 0.9965422974.
   * The Meeus series lands within 0.001 deg in zenith and 0.006 deg in
   * azimuth (its solar longitude is good to about 0.01 deg). */
  vr_sun_site site;
  vr_sun_site_default(&site, 39.742476, -105.1786);
  site.pressure_hpa = 820.0;
  site.temperature_c = 11.0;
  site.delta_t_s = 67.0;
  vr_datetime t = {2003, 10, 17, 19, 30, 30.0};
  vr_sun_position p;
  vr_error err = {0};
  if (vr_sun_position_at(&site, &t, &p, &err) != VR_OK) fail_msg("%s", err.message);
  print_message("SPA case: zenith %.5f (SPA 50.11162, off %.5f), azimuth %.5f (SPA 194.34024, "
                "off %.5f)\n",
                p.zenith_deg, p.zenith_deg - 50.11162, p.azimuth_deg, p.azimuth_deg - 194.34024);
  assert_near(p.zenith_deg, 50.11162, 0.002);
  assert_near(p.azimuth_deg, 194.34024, 0.01);
  assert_near(p.right_ascension_deg, 202.22741, 0.01);
  assert_near(p.declination_deg, -9.31434, 0.005);
  assert_near(p.hour_angle_deg, 11.105900, 0.01);
  assert_near(p.distance_au, 0.9965422974, 1e-5);
  assert_near(p.altitude_deg + p.zenith_deg, 90.0, 1e-12);
  /* The direction vector agrees with the angles (z up, azimuth from +y
   * towards +x): south-south-west and up. */
  double alt, az;
  assert_true(vr_sun_angles_of(p.direction, &alt, &az));
  assert_near(alt, p.altitude_deg, 1e-9);
  assert_near(az, p.azimuth_deg, 1e-9);
  assert_true(p.direction[0] < 0 && p.direction[1] < 0 && p.direction[2] > 0);
  assert_near(p.direction[0] * p.direction[0] + p.direction[1] * p.direction[1] +
                  p.direction[2] * p.direction[2],
              1.0, 1e-12);

  /* Refraction: turning it off leaves the geometric altitude, lower by
   * about 1' at this altitude (SPA's e - e0 = 0.016332 deg). */
  site.pressure_hpa = 0.0;
  vr_sun_position q;
  assert_int_equal(vr_sun_position_at(&site, &t, &q, &err), VR_OK);
  assert_near(q.altitude_deg, q.true_altitude_deg, 0);
  assert_near(p.altitude_deg - q.altitude_deg, 39.888378 - 39.872046, 0.001);
}

static void local_time(void **state) {
  (void)state;
  /* SPA's test case given as its local time, 2003-10-17 12:30:30 at
   * UTC-7 (Reda & Andreas 2008, Table A5.2: zenith 50.11162 deg), and the
   * same instant written across a day, a month and a year boundary. */
  vr_sun_site site;
  vr_sun_site_default(&site, 39.742476, -105.1786);
  site.pressure_hpa = 820.0, site.temperature_c = 11.0, site.delta_t_s = 67.0;
  vr_sun_position p, q;
  vr_datetime utc;
  assert_int_equal(vr_sun_position_local(&site, 2003, 10, 17, 12 * 60 + 30.5, -7, &p, &utc, NULL),
                   VR_OK);
  assert_near(p.zenith_deg, 50.11162, 0.002);
  assert_int_equal(utc.day, 17);
  assert_int_equal(utc.hour, 19);
  assert_int_equal(utc.minute, 30);
  /* 2003-12-31 20:00 at UTC-7 is 2004-01-01 03:00 UTC; 2004-01-01 01:00
   * at UTC+9 is 2003-12-31 16:00 UTC. */
  assert_int_equal(vr_sun_position_local(&site, 2003, 12, 31, 20 * 60, -7, &p, &utc, NULL), VR_OK);
  assert_true(utc.year == 2004 && utc.month == 1 && utc.day == 1 && utc.hour == 3);
  vr_datetime t = {2004, 1, 1, 3, 0, 0.0};
  assert_int_equal(vr_sun_position_at(&site, &t, &q, NULL), VR_OK);
  assert_near(p.zenith_deg, q.zenith_deg, 1e-12);
  assert_int_equal(vr_sun_position_local(&site, 2004, 1, 1, 60, 9, &p, &utc, NULL), VR_OK);
  assert_true(utc.year == 2003 && utc.month == 12 && utc.day == 31 && utc.hour == 16);
  /* 29 February exists in 2004, not in 2003. */
  assert_int_equal(vr_sun_position_local(&site, 2004, 2, 29, 720, 0, &p, NULL, NULL), VR_OK);
  assert_int_not_equal(vr_sun_position_local(&site, 2003, 2, 29, 720, 0, &p, NULL, NULL), VR_OK);
}

static void directions(void **state) {
  (void)state;
  double d[3];
  vr_sun_direction_of(0.0, 0.0, d); /* north horizon */
  assert_near(d[0], 0, 1e-15); assert_near(d[1], 1, 1e-15); assert_near(d[2], 0, 1e-15);
  vr_sun_direction_of(0.0, 90.0, d); /* east */
  assert_near(d[0], 1, 1e-15); assert_near(d[1], 0, 1e-15);
  vr_sun_direction_of(90.0, 123.0, d); /* zenith */
  assert_near(d[2], 1, 1e-15);
  double v[3] = {-1, -1, 0}, alt, az;
  assert_true(vr_sun_angles_of(v, &alt, &az));
  assert_near(az, 225.0, 1e-12);
  assert_near(alt, 0.0, 1e-12);
  double zero[3] = {0, 0, 0};
  assert_false(vr_sun_angles_of(zero, &alt, &az));
}

static void arguments(void **state) {
  (void)state;
  vr_sun_site site;
  vr_sun_site_default(&site, 45.0, 5.0);
  vr_sun_position p;
  vr_error err = {0};
  vr_datetime t = {2003, 2, 29, 12, 0, 0.0};
  assert_int_equal(vr_sun_position_at(&site, &t, &p, &err), VR_E_ARG);
  assert_contains(err.message, "day 29 does not exist in 2003-02");
  t.day = 28;
  t.month = 13;
  assert_int_equal(vr_sun_position_at(&site, &t, &p, &err), VR_E_ARG);
  assert_contains(err.message, "month 13");
  t.month = 2;
  site.latitude_deg = 91.0;
  assert_int_equal(vr_sun_position_at(&site, &t, &p, &err), VR_E_ARG);
  assert_contains(err.message, "latitude 91");
  site.latitude_deg = 45.0;
  t.year = 1700;
  assert_int_equal(vr_sun_position_at(&site, &t, &p, &err), VR_E_ARG);
  assert_contains(err.message, "year 1700");
  /* A leap day that exists. */
  t.year = 2004;
  t.day = 29;
  assert_int_equal(vr_sun_position_at(&site, &t, &p, &err), VR_OK);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(julian_day),
      cmocka_unit_test(meeus_example_25a),
      cmocka_unit_test(spa_test_case),
      cmocka_unit_test(local_time),
      cmocka_unit_test(directions),
      cmocka_unit_test(arguments),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
