/* Annual glare at view points (annual glare_views=, render/src/annual/
 * annual_glare.c) on the real Chicago weather file of tests/data/weather:
 *  - the sun in view, in the open: every occupied hour whose sun lies in
 *    front of a south-facing eye has the DGP of Wienold & Christoffersen
 *    (2006) with the solar disc as its glare source, computed here from
 *    the published formula: E_n the Perez (1990) direct normal
 *    illuminance of the record, the disc's solid angle of 0.2665 degrees
 *    radius, Guth's position index from its published form;
 *  - a room looking at its window under an overcast sky: the hour's DGP
 *    from the image coefficients against a direct fisheye render of the
 *    same record (sky perez weather= date= time=) and its DGP;
 *  - the hourly table and the views' table as written;
 *  - the glare_views= errors. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "render_test_util.h"
#include "vr_test.h"
#include "daylit_room.h"
#include "vr/annual.h"
#include "vr/fisheye.h"
#include "vr/perez.h"
#include "vr/sun.h"
#include "vr/weather.h"
#include "annual_test_util.h"

#define DEG (M_PI / 180)
#define WEA VR_TEST_DATA "/weather/chicago.wea"

/* Guth's position index as the IES Lighting Handbook gives it (Luckiesh &
 * Guth 1949; the form evalglare uses), for a source above the line of
 * sight at sigma degrees from it, tau degrees from the vertical plane
 * through it. */
static double guth(double sigma, double tau) {
  return exp((35.2 - 0.31889 * tau - 1.22 * exp(-2 * tau / 9)) * 1e-3 * sigma +
             (21 + 0.26667 * tau - 0.002963 * tau * tau) * 1e-5 * sigma * sigma);
}

/* DGP, Wienold & Christoffersen (2006), with Wienold's (2009) low-light
 * correction below 1000 lx. */
static double dgp_of(double ev, double sum) {
  double d = 5.87e-5 * ev + 9.18e-2 * log10(1 + sum / pow(ev, 1.87)) + 0.16;
  if (ev < 1000) d *= exp(0.024 * ev - 4) / (1 + exp(0.024 * ev - 4));
  return fmin(d, 1);
}

static void sun_in_view(void **state) {
  (void)state;
  /* An eye 1.2 m above a dark ground, looking south (-y) and level. */
  vr_annual_result *r = annual_run_text("material ground lambert reflectance=0.05\n"
                                   "rect center=0,0,0 normal=0,0,1 size=20,20 material=ground\n"
                                   "light sun spectrum=D65\n"
                                   "sky perez weather=" WEA " ground=0.05\n"
                                   "sensor eye point position=0,0,1.2 normal=0,-1,0\n"
                                   "annual hours=8,17 glare_views=eye\n"
                                   "render sensor_samples=4096 seed=7\n",
                                        NULL);
  assert_int_equal(r->nviews, 1);
  assert_string_equal(r->views[0].sensor, "eye");
  vr_weather *w = NULL;
  assert_int_equal(vr_weather_read(WEA, &w, NULL), VR_OK);
  vr_sun_site site;
  vr_sun_site_default(&site, w->latitude_deg, w->longitude_deg);
  /* The disc's solid angle: 2 pi (1 - cos 0.2665 deg). */
  double omega = 2 * M_PI * (1 - cos(0.2665 * DEG));
  size_t h = 0, checked = 0, uncapped = 0;
  double worst = 0;
  for (size_t i = 0; i < w->nrecords; i++) {
    const vr_weather_record *rec = &w->records[i];
    double c = 0.5 * (rec->start_h + rec->end_h);
    if (c < 8 || c >= 17) continue;
    size_t row = h++;
    vr_sun_position pos;
    assert_int_equal(vr_sun_position_local(&site, 2021, rec->month, rec->day, 60 * c, w->timezone_h,
                                           &pos, NULL, NULL),
                     VR_OK);
    double alt = pos.altitude_deg, az = pos.azimuth_deg;
    /* In front of the eye, above its line of sight, away from the horizon
     * (the sun's patch is then seen unobstructed) and far from the edge of
     * the view. */
    if (alt < 3 || alt > 60 || fabs(az - 180) > 60 || !(rec->diffuse_horizontal_w_m2 > 0)) continue;
    vr_perez_sky m = record_perez(rec, alt);
    double En = m.direct_normal_lx, ev = r->hourly_lx[row * r->npoints];
    /* A sun bright enough that the sky's own sources are negligible beside
     * it (the sky's sum of L^2 w / P^2 is under 1e-4 of the disc's for
     * E_n above 2000 lx).  Most such hours reach DGP's cap of 1. */
    if (En < 2000) continue;
    /* The sun in the eye's frame: sigma from the line of sight, tau from
     * the vertical plane through it. */
    double d[3] = {cos(alt * DEG) * sin(az * DEG), cos(alt * DEG) * cos(az * DEG), sin(alt * DEG)};
    double fwd = -d[1], right = -d[0], up = d[2];
    double sigma = acos(fwd) / DEG, tau = atan2(fabs(right), up) / DEG;
    double P = fmin(guth(sigma, tau), 16);
    double want = dgp_of(ev, En * En / (omega * P * P));
    double got = r->hourly_dgp[row];
    uncapped += want < 0.99;
    double e = fabs(got - want);
    if (e > worst) worst = e;
    if (e > 2e-3)
      fail_msg("line %ld: DGP %.4f, expected %.4f (E_v %.0f lx, E_n %.0f lx, P %.3f)", rec->line,
               got, want, ev, En, P);
    checked++;
  }
  printf("sun in view: %zu hours (%zu below the cap of 1), worst |DGP - formula| %.2g\n", checked,
         uncapped, worst);
  assert_true(checked > 100);
  assert_true(uncapped >= 5);
  /* The table of the views: hours at each bound and the level they meet. */
  double n35 = 0;
  for (size_t k = 0; k < r->occupied_hours; k++) n35 += r->hourly_dgp[k] >= 0.35;
  assert_true(fabs(r->views[0].hours[0] - n35) < 0.5);
  vr_weather_free(w);
  vr_annual_result_destroy(r);
}

/* The daylit room's shell, an eye at (2, 3, 1.2) looking at the window
 * (-y), a weather sky line and the extra lines. */
static void room(char *buf, size_t n, const char *sky, const char *extra) {
  snprintf(buf, n,
           DAYLIT_ROOM_SHELL
           "light sun spectrum=D65\n"
           "sky perez weather=" WEA "%s\n"
           "sensor eye point position=2,3,1.2 normal=0,-1,0\n"
           "%s",
           sky, extra);
}

static void room_against_direct_renders(void **state) {
  (void)state;
  char text[4096];
  room(text, sizeof text, "", "annual hours=10,14 glare_views=eye glare_resolution=64\n"
                              "render sensor_samples=32768 spp=16 seed=5\n");
  vr_annual_result *r = annual_run_text(text, NULL);
  vr_weather *w = NULL;
  assert_int_equal(vr_weather_read(WEA, &w, NULL), VR_OK);
  /* Overcast records (no direct sun): the sky's coefficients alone.  11
   * March 13:30 (281 W/m2 diffuse), 25 March 10:30 (333 W/m2) and
   * 31 March 11:30 (370 W/m2). */
  struct { int m, d; const char *time; double hour; } cases[] = {
      {3, 11, "13:30", 13.5}, {3, 25, "10:30", 10.5}, {3, 31, "11:30", 11.5}};
  for (size_t c = 0; c < 3; c++) {
    const vr_weather_record *rec = NULL;
    assert_int_equal(vr_weather_find(w, cases[c].m, cases[c].d, cases[c].hour, &rec, NULL), VR_OK);
    assert_true(rec->direct_normal_w_m2 == 0);
    size_t row = r->occupied_hours;
    for (size_t h = 0; h < r->occupied_hours; h++)
      if (r->hourly_line[h] == rec->line) row = h;
    assert_true(row < r->occupied_hours);
    char sky[64];
    snprintf(sky, sizeof sky, " date=%02d-%02d time=%s", cases[c].m, cases[c].d, cases[c].time);
    room(text, sizeof text, sky,
         "camera fisheye from=2,3,1.2 to=2,2,1.2 resolution=128x128\n"
         "render integrator=path spp=64 sensor_samples=32768 seed=9\n");
    vr_scene *s = parse_text(text, VR_TEST_DATA "/hour.scn");
    vr_render_result *d = render_scene_with(s, NULL, 1, 2, false, false);
    vr_scene_destroy(s);
    double got = r->hourly_dgp[row], want = d->glare.dgp;
    double ev = r->hourly_lx[row * r->npoints];
    printf("%02d-%02d %s: coefficients DGP %.4f (E_v %.0f lx), direct render DGP %.4f (E_v %.0f "
           "lx, its sensor %.0f lx, contrast %.3g, sources %.3f sr)\n",
           cases[c].m, cases[c].d, cases[c].time, got, ev, want, d->glare.vertical_lx,
           d->readings[0].illuminance_lx, d->glare.contrast, d->glare.source_omega_sr);
    /* The window is a glare source: without the contrast term the DGP
     * would be lower by 0.0918 log10(1 + contrast), several times the
     * tolerance. */
    assert_true(9.18e-2 * log10(1 + d->glare.contrast) > 0.03);
    /* The two differ by noise and by the sky averaged over each Tregenza
     * patch in the coefficients.  Noise: E_v (the coefficients' view
     * sensor against the render's image) within 4 combined standard
     * errors, taken as the direct render's sensor's, moves DGP by its
     * slope dDGP/dE_v = 5.87e-5 - 0.0918 / ln 10 c / (1 + c) 1.87 / E_v
     * (the contrast c falls as E_v^-1.87).  Patch averaging: 0.003, above
     * the 0.001-0.002 left in these three hours with 16 times the samples
     * on both sides (131072 sensor paths, 256 paths a pixel). */
    double cc = d->glare.contrast, E = d->glare.vertical_lx;
    double slope = fabs(5.87e-5 - 9.18e-2 / log(10) * cc / (1 + cc) * 1.87 / E);
    double tol = 0.003 + 4 * sqrt(2.0) * d->readings[0].stderr_lx * slope;
    printf("  |difference| %.4f, bound %.4f (sensor standard error %.0f lx)\n", fabs(got - want), tol,
           d->readings[0].stderr_lx);
    assert_true(fabs(got - want) <= tol);
    vr_render_result_destroy(d);
  }
  vr_weather_free(w);
  vr_annual_result_destroy(r);
}

static void refused(const char *text, const char *needle) {
  vr_error err = {0};
  vr_scene *s = NULL;
  assert_int_not_equal(vr_scene_parse(text, strlen(text), VR_TEST_DATA "/annual.scn", &s, &err), VR_OK);
  if (!strstr(err.message, needle)) fail_msg("'%s' lacks '%s'", err.message, needle);
}

static void glare_views_errors(void **state) {
  (void)state;
  char text[1024];
  const char *base = "light sun\nsky perez weather=" WEA "\n"
                     "sensor eye point position=0,0,1.2 normal=0,-1,0\n"
                     "sensor up point position=0,0,1.2 normal=0,0,1\n"
                     "sensor g grid origin=0,0,0.8 u=1,0,0 v=0,1,0 n=2,2 normal=0,0,1\n";
  /* Each annual line, and what its refusal says. */
  static const struct { const char *line, *needle; } cases[] = {
      {"glare_views=nobody", "glare_views=nobody: no sensor of that name"},
      {"glare_views=g", "glare_views=g: a grid"},
      {"glare_views=up", "looks straight up"},
      {"glare_views=eye,eye", "eye named twice"},
      {"glare_resolution=32", "give glare_views="},
      {"glare_views=eye glare_resolution=4", "glare_resolution"},
      {"glare_views=eye glare_resolution=32.5", "a whole number of pixels"},
      /* control=glare with glare views watches their DGP: a control
       * sensor that is not a view would watch nothing. */
      {"glass=ec control=glare glare_views=eye control_sensor=up",
       "control_sensor=up: with glare views, control=glare keeps their DGP"},
  };
  for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
    snprintf(text, sizeof text, "material ec db:ec\n%sannual %s\n", base, cases[i].line);
    refused(text, cases[i].needle);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(glare_views_errors),
      cmocka_unit_test(sun_in_view),
      cmocka_unit_test(room_against_direct_renders),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
