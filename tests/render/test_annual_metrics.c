/* The annual study's schedules and EN 17037 (vr/annual.h), on the real
 * Chicago weather file of tests/data/weather and real occupancy files of
 * tests/data/occupancy (SOURCES.md there):
 *  - EN 17037:2018 Table A.1's levels from the points' shares, on a plane
 *    built to sit on each criterion's boundary;
 *  - the daylight factor from a render under the CIE standard overcast
 *    sky: 100 % on an unobstructed horizontal point and
 *    (pi/6 + 4/9) / (7 pi/9) = 39.62 % on an unobstructed vertical one with
 *    a black ground (the CIE overcast sky's vertical-to-horizontal ratio,
 *    the 39.6 % of BRE 209's maximum vertical sky component);
 *  - the daylight hours: half the year's records (4380 of 8760), the
 *    median diffuse illuminance over them and the points' hours above each
 *    threshold, against a ranking of the records' global horizontal
 *    illuminance done here from the Perez (1990) efficacy model;
 *  - the operable-shade rule of IES LM-83-12 (drawn when more than 2 % of
 *    the work plane sees 1000 lx of direct sun) against the direct
 *    horizontal illuminance of the Perez model in the open, and the shade's
 *    material taking the window's place in a room;
 *  - occupancy files: a Daysim file (3650 hours: "365 days a year from 8AM
 *    to 6PM" with daylight saving time, its header says) and Honeybee's
 *    one-value-per-line schedule (4380 ones), and their errors. */
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
#include "temp_db.h"
#include "vr/annual.h"
#include "vr/perez.h"
#include "vr/sun.h"
#include "vr/weather.h"
#include "annual_test_util.h"

#define DEG (M_PI / 180)
#define WEA VR_TEST_DATA "/weather/chicago.wea"
#define DAYSIM VR_TEST_DATA "/occupancy/8to6withDST.60min.occ.csv"
#define HONEYBEE VR_TEST_DATA "/occupancy/daylight_hours.csv"

static vr_status try_annual_db(const char *text, vr_matdb *db, vr_annual_result **r, vr_error *err) {
  vr_scene *s = parse_text(text, VR_TEST_DATA "/annual.scn");
  vr_render_options o;
  vr_render_options_default(&o);
  o.threads = 2;
  o.no_camera = true;
  *r = NULL;
  vr_status st = vr_annual_run(s, db, &o, r, err);
  vr_scene_destroy(s);
  return st;
}

static vr_status try_annual(const char *text, vr_annual_result **r, vr_error *err) {
  return try_annual_db(text, NULL, r, err);
}

static vr_annual_result *run_annual_db(const char *text, vr_matdb *db) {
  vr_annual_result *r = NULL;
  vr_error err = {0};
  vr_status st = try_annual_db(text, db, &r, &err);
  if (st) fprintf(stderr, "annual: %s\n", err.message);
  assert_int_equal(st, VR_OK);
  return r;
}

static vr_annual_result *run_annual(const char *text) { return run_annual_db(text, NULL); }

/* EN 17037:2018 Table A.1: at each level a target illuminance over 50 % of
 * the reference plane and a minimum target over 95 % of it, each for 50 %
 * of the daylight hours (300/100, 500/300, 750/500 lx); method 1 the same
 * with daylight factors D = 100 E / E_v,d,med.  Twenty work-plane points:
 * 19 (95 %) reach 100 and 300 lx in exactly half the hours, 10 (50 %)
 * reach 500 lx, 9 (45 %) reach 750 lx: the medium level, not the high one;
 * with a point fewer at 300 lx (90 %) only the minimum level.  A point off
 * the work plane that never reaches anything is not counted. */
static void en17037_levels(void **state) {
  (void)state;
  vr_annual_point pts[21];
  memset(pts, 0, sizeof pts);
  const double edmed = 15000; /* lx: D_T = 2, 3.33, 5 %; D_TM = 0.67, 2, 3.33 % */
  for (int p = 0; p < 20; p++) {
    pts[p].workplane = true;
    double v = p < 19 ? 0.5 : 0.49;
    pts[p].en17037_share[0] = pts[p].en17037_share[1] = v;
    pts[p].en17037_share[2] = p < 10 ? 0.5 : 0.2;
    pts[p].en17037_share[3] = p < 9 ? 0.5 : 0.1;
    /* The same plane by daylight factor. */
    pts[p].df_pct = p < 9 ? 5.0 : p < 10 ? 3.34 : p < 19 ? 2.0 : 0.5;
  }
  pts[20].df_pct = 0;
  vr_en17037 e = {0};
  vr_en17037_assess(pts, 21, edmed, &e);
  assert_int_equal(e.m2_level, 1);
  assert_near(e.m2_target[0], 0.95, 1e-12);
  assert_near(e.m2_minimum[0], 0.95, 1e-12);
  assert_near(e.m2_target[1], 0.50, 1e-12);
  assert_near(e.m2_minimum[1], 0.95, 1e-12);
  assert_near(e.m2_target[2], 0.45, 1e-12);
  assert_near(e.m2_minimum[2], 0.50, 1e-12);
  assert_int_equal(e.m1_level, 1);
  assert_near(e.m1_target[1], 0.50, 1e-12);
  assert_near(e.m1_minimum[1], 0.95, 1e-12);
  assert_near(e.m1_target[2], 0.45, 1e-12);
  /* One point fewer at 300 lx and 100 lx: the minimum target of 100 lx is
   * met on 90 % (< 95 %) and no level is; the method 1 plane keeps its
   * medium level. */
  pts[18].en17037_share[0] = pts[18].en17037_share[1] = 0.4;
  vr_en17037_assess(pts, 21, edmed, &e);
  assert_int_equal(e.m2_level, -1);
  assert_int_equal(e.m1_level, 1);
  /* E_v,d,med halved doubles every D target's reach: D >= 2 x 750/15000 % =
   * 10 % nowhere, the points at 5 % now meet only the targets of 300 lx
   * (D_T 4 %) on 9 points (45 %) and the minimum of 100 lx (1.33 %) on 19. */
  vr_en17037_assess(pts, 21, edmed / 2, &e);
  assert_int_equal(e.m1_level, -1);
  assert_near(e.m1_target[0], 0.45, 1e-12);
}

/* A record's diffuse and direct horizontal illuminance (lx) by the Perez
 * (1990) efficacy model; 0 with the sun down or no diffuse light. */
static void perez_of(const vr_weather *w, const vr_weather_record *rec, double *diffuse,
                     double *direct) {
  *diffuse = *direct = 0;
  double alt = altitude_of(w, rec);
  if (alt <= 0 || !(rec->diffuse_horizontal_w_m2 > 0)) return;
  vr_perez_sky m = record_perez(rec, alt);
  *diffuse = m.diffuse_horizontal_lx;
  *direct = m.direct_normal_lx * sin(alt * DEG);
}

typedef struct lit {
  double egh, edh;
  size_t i;
} lit;

static int most_light(const void *a, const void *b) {
  const lit *x = a, *y = b;
  if (x->egh != y->egh) return x->egh > y->egh ? -1 : 1;
  return x->i < y->i ? -1 : 1;
}

static int ascending(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return x < y ? -1 : x > y;
}

/* An unobstructed horizontal point and two vertical ones (south, north) in
 * the open with a black ground, en17037=yes under the Chicago year, the
 * occupied hours being the daylight hours as ranked here: the study's own
 * daylight hours must be the same, so each point's share of them at each
 * threshold equals its share of the occupied hours in the hourly table. */
static void daylight_hours_and_factor(void **state) {
  (void)state;
  vr_weather *w = NULL;
  assert_int_equal(vr_weather_read(WEA, &w, NULL), VR_OK);
  lit *l = calloc(w->nrecords, sizeof *l);
  for (size_t i = 0; i < w->nrecords; i++) {
    const vr_weather_record *rec = &w->records[i];
    l[i].i = i;
    double direct;
    perez_of(w, rec, &l[i].edh, &direct);
    l[i].egh = l[i].edh + direct;
  }
  qsort(l, w->nrecords, sizeof *l, most_light);
  bool *top = calloc(w->nrecords, sizeof *top);
  double d[4380];
  for (int k = 0; k < 4380; k++) d[k] = l[k].edh, top[l[k].i] = true;
  qsort(d, 4380, sizeof *d, ascending);
  double median = 0.5 * (d[2189] + d[2190]);
  char path[] = "/tmp/vr_dlh_XXXXXX";
  int fd = mkstemp(path);
  assert_true(fd >= 0);
  FILE *f = fdopen(fd, "w");
  for (size_t i = 0; i < w->nrecords; i++) fprintf(f, "%d\n", top[i] ? 1 : 0);
  fclose(f);
  char text[1024];
  snprintf(text, sizeof text,
           "light sun spectrum=D65\n"
           "sky perez weather=" WEA " ground=0\n"
           "sensor top point position=0,0,1 normal=0,0,1\n"
           "sensor south point position=0,0,1 normal=0,-1,0\n"
           "sensor north point position=0,0,1 normal=0,1,0\n"
           "annual en17037=yes occupancy=%s\n"
           "render sensor_samples=16384 seed=7\n",
           path);
  vr_annual_result *r = run_annual(text);
  unlink(path);
  const vr_en17037 *e = &r->en17037;
  assert_true(e->run);
  assert_false(e->edmed_given);
  /* Half the year's 8760 records (EN 17037's daylight hours). */
  assert_int_equal(e->daylight_hours, 4380);
  assert_int_equal(r->occupied_hours, 4380);
  printf("E_v,d,med %.1f lx (here %.1f lx)\n", e->edmed_lx, median);
  assert_near(e->edmed_lx, median, 1e-9 * median);
  for (size_t p = 0; p < 3; p++)
    for (int k = 0; k < 4; k++) {
      size_t n = 0;
      for (size_t h = 0; h < 4380; h++) n += r->hourly_lx[h * 3 + p] >= VR_EN17037_LX[k];
      printf("%s, %g lx: %.0f daylight hours, %zu in the hourly table\n", r->points[p].sensor,
             VR_EN17037_LX[k], r->points[p].en17037_share[k] * 4380, n);
      assert_near(r->points[p].en17037_share[k] * 4380, (double)n, 1e-6);
    }

  /* The daylight factors, analytic for the CIE overcast sky L(a) = L_z
   * (1 + 2 sin a) / 3 with a black ground: horizontal 100 %, vertical
   * (pi/6 + 4/9) / (7 pi / 9) = 39.62 %.  Allowed: four standard deviations
   * of a reading over seeds, measured on this scene over six seeds: 0.018
   * (horizontal) and 0.063 (vertical) percentage points. */
  double vertical = 100 * (M_PI / 6 + 4.0 / 9) / (7 * M_PI / 9);
  printf("DF: horizontal %.3f %%, vertical %.3f %% and %.3f %% (analytic 100, %.3f)\n",
         r->points[0].df_pct, r->points[1].df_pct, r->points[2].df_pct, vertical);
  assert_true(fabs(r->points[0].df_pct - 100) <= 4 * 0.018);
  assert_true(fabs(r->points[1].df_pct - vertical) <= 4 * 0.063);
  assert_true(fabs(r->points[2].df_pct - vertical) <= 4 * 0.063);
  free(top);
  free(l);
  vr_weather_free(w);
  vr_annual_result_destroy(r);
}

/* The Daysim file: 3650 occupied hours; 8-9 h the first on 1 January,
 * 7-8 h (standard time) the first on 1 July under daylight saving time. */
static void occupancy_daysim(void **state) {
  (void)state;
  vr_annual_result *r = run_annual("light sun spectrum=D65\n"
                                   "sky perez weather=" WEA "\n"
                                   "sensor top point position=0,0,1 normal=0,0,1\n"
                                   "annual occupancy=" DAYSIM "\n"
                                   "render sensor_samples=256\n");
  assert_int_equal(r->occupied_hours, 3650);
  vr_weather *w = NULL;
  assert_int_equal(vr_weather_read(WEA, &w, NULL), VR_OK);
  const vr_weather_record *first = NULL, *july = NULL;
  for (size_t h = 0; h < r->occupied_hours; h++)
    for (size_t i = 0; i < w->nrecords; i++)
      if (w->records[i].line == r->hourly_line[h]) {
        if (!first) first = &w->records[i];
        if (!july && w->records[i].month == 7 && w->records[i].day == 1) july = &w->records[i];
      }
  assert_non_null(first);
  assert_non_null(july);
  assert_int_equal(first->month, 1);
  assert_near(first->start_h, 8, 1e-9);
  assert_near(july->start_h, 7, 1e-9);

  /* The same schedule as one value per record gives the same hours. */
  char path[] = "/tmp/vr_occ_XXXXXX";
  int fd = mkstemp(path);
  assert_true(fd >= 0);
  FILE *f = fdopen(fd, "w");
  for (size_t i = 0, h = 0; i < w->nrecords; i++) {
    bool on = h < r->occupied_hours && r->hourly_line[h] == w->records[i].line;
    h += on;
    fprintf(f, "%d\n", on ? 1 : 0);
  }
  fclose(f);
  char text[1024];
  snprintf(text, sizeof text,
           "light sun spectrum=D65\nsky perez weather=" WEA "\n"
           "sensor top point position=0,0,1 normal=0,0,1\nannual occupancy=%s\n"
           "render sensor_samples=256\n",
           path);
  vr_annual_result *r2 = run_annual(text);
  assert_int_equal(r2->occupied_hours, 3650);
  assert_memory_equal(r2->hourly_line, r->hourly_line, 3650 * sizeof *r->hourly_line);
  unlink(path);
  vr_annual_result_destroy(r2);
  vr_weather_free(w);
  vr_annual_result_destroy(r);

  /* Honeybee's daylight-hours schedule as an occupancy: its 4380 ones. */
  r = run_annual("light sun spectrum=D65\nsky perez weather=" WEA "\n"
                 "sensor top point position=0,0,1 normal=0,0,1\n"
                 "annual occupancy=" HONEYBEE "\nrender sensor_samples=256\n");
  assert_int_equal(r->occupied_hours, 4380);
  vr_annual_result_destroy(r);
}

/* A schedule file with the given text is refused with a message holding
 * `needle` (the file's name is in every message). */
static void refused_schedule(const char *content, const char *needle) {
  char path[] = "/tmp/vr_occ_XXXXXX";
  int fd = mkstemp(path);
  assert_true(fd >= 0);
  FILE *f = fdopen(fd, "w");
  fputs(content, f);
  fclose(f);
  char text[1024];
  snprintf(text, sizeof text,
           "light sun\nsky perez weather=" WEA "\nsensor top point position=0,0,1 normal=0,0,1\n"
           "annual occupancy=%s\n",
           path);
  vr_annual_result *r = NULL;
  vr_error err = {0};
  assert_int_not_equal(try_annual(text, &r, &err), VR_OK);
  assert_null(r);
  if (!strstr(err.message, needle) || !strstr(err.message, path))
    fail_msg("'%s' lacks '%s' or the file's name", err.message, needle);
  unlink(path);
}

static void occupancy_errors(void **state) {
  (void)state;
  refused_schedule("0\n1\n2\n", ":3:1: field 'occupancy': 2 is neither 1 (present) nor 0");
  refused_schedule("0\n1\n", "2 values for the 8760 records");
  refused_schedule("1\nx\n", ":2:1: field 'occupancy': expected a number");
  refused_schedule("# Daysim occupancy file\n1,1,0.5,0\n2,30,8.5,1\n",
                   ":3:1: month 2, day 30, time 8.5: no record of the weather file");
  refused_schedule("1,1,0.5,0\n1,1,0.5,1\n", ":2:1: month 1, day 1, time 0.5: the weather record");
  refused_schedule("1,1,0.5,0\n1,1,1.5\n", ":2:1: 3 fields");
  refused_schedule("1,1,0.5,0\n", "no occupancy row for the weather record at");
  refused_schedule("1,1,0.5,0.5\n", "0.5 is neither 1 (present) nor 0");
  /* The scene line's own errors. */
  const char *base = "light sun\nsky perez weather=" WEA "\nsensor s point position=0,0,1 normal=0,0,1\n";
  struct { const char *line, *needle; } bad[] = {
      {"annual occupancy=" DAYSIM " hours=8,18\n", "give one or the other"},
      {"annual edmed=15000\n", "give en17037=yes"},
      {"annual en17037=maybe\n", "expected no, yes"},
      {"annual en17037=yes edmed=0\n", "edmed"},
      {"annual shade=s\n", "needs both shade=MATERIAL"},
      {"annual window=s\n", "needs both shade=MATERIAL"},
      {"material g db:x\nannual glass=g shade=g window=g\n", "not both"},
      {"annual shade=nope window=nope\n", "shade=nope: no material of that name"},
      {"material a black\nmaterial b black\nannual shade=a window=b\n",
       "window=b: no object has this material"},
      {"material a black\nrect center=0,0,5 normal=0,0,1 size=1,1 material=a\n"
       "annual shade=a window=a\n", "the window's own material"},
  };
  for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
    char t[1024];
    snprintf(t, sizeof t, "%s%s", base, bad[i].line);
    vr_scene *s = NULL;
    vr_error err = {0};
    assert_int_not_equal(vr_scene_parse(t, strlen(t), VR_TEST_DATA "/annual.scn", &s, &err), VR_OK);
    if (!strstr(err.message, bad[i].needle)) fail_msg("'%s' lacks '%s'", err.message, bad[i].needle);
  }
}

/* The LM-83 rule, analytic: four work-plane points in the open, the
 * "window" a small object far away (the shade drawn changes nothing
 * there).  Every point sees the sun unobstructed, so the shade is drawn
 * exactly in the occupied hours whose direct horizontal illuminance E_dn
 * sin h (the Perez efficacy model, computed here) reaches 1000 lx, give or
 * take the hours within 3 % of it (test_annual.c: an unobstructed point's
 * hour within 3 %). */
static void shade_rule_in_the_open(void **state) {
  (void)state;
  vr_annual_result *r = run_annual(
      "material win lambert reflectance=0.5\n"
      "material blind bsdf file=" VR_TEST_DATA "/bsdf/cgdb_14060_urban_loft_river_stone.xml.gz\n"
      "rect center=100,100,5 normal=0,0,1 size=1,1 material=win\n"
      "light sun spectrum=D65\n"
      "sky perez weather=" WEA " ground=0\n"
      "sensor plane grid origin=-1,-1,0.8 u=2,0,0 v=0,2,0 n=2,2 normal=0,0,1\n"
      "annual shade=blind window=win\n"
      "render sensor_samples=256\n");
  assert_true(r->glass == VR_ANNUAL_SHADE);
  assert_string_equal(r->glass_name, "blind");
  assert_string_equal(r->window_name, "win");
  vr_weather *w = NULL;
  assert_int_equal(vr_weather_read(WEA, &w, NULL), VR_OK);
  size_t expected = 0, near = 0, drawn = 0;
  for (size_t i = 0, h = 0; i < w->nrecords; i++) {
    const vr_weather_record *rec = &w->records[i];
    double c = 0.5 * (rec->start_h + rec->end_h);
    if (c < 8 || c >= 18) continue;
    assert_int_equal(r->hourly_line[h], rec->line);
    drawn += r->hourly_state[h++] == 1;
    double diffuse, direct;
    perez_of(w, rec, &diffuse, &direct);
    expected += direct >= 1000;
    near += fabs(direct - 1000) <= 30;
  }
  printf("shade drawn %zu h, %zu expected (%zu within 3 %% of 1000 lx); %.0f counted\n", drawn,
         expected, near, r->state_hours[1]);
  assert_true(labs((long)drawn - (long)expected) <= (long)near);
  assert_near(r->state_hours[1], (double)drawn, 0.5);
  /* ASE is the open window's: here every point's direct-sun hours. */
  assert_near(r->points[0].direct_hours, (double)drawn, 0.5);
  vr_weather_free(w);
  vr_annual_result_destroy(r);
}

/* The shade's material in place of the window's: the daylit room with a
 * soda-lime pane in its opening and, drawn, a black shade, so that every
 * point reads 0 lx in the drawn hours (the room has no other opening); in
 * the open hours the same illuminance as the room without a shade line
 * (the same seed renders the same open-state coefficients); ASE the same
 * as without the shade (LM-83 defines it without operable shading); the
 * drawn hours at least those of the point with the most direct-sun hours,
 * at most their sum (any lit point draws it). */
static void shade_replaces_window(void **state) {
  (void)state;
  char path[64];
  vr_matdb *db = temp_db(path, sizeof path);
  const char *fmt = DAYLIT_ROOM_SHELL
      "material pane db:soda-lime-glass thickness=6mm\n"
      "material shut black\n"
      "rect center=2,0,1.5 normal=0,1,0 size=2,1.2 material=pane\n"
      "light sun spectrum=D65\n"
      "sky perez weather=" WEA "\n"
      "sensor floor grid origin=0.25,0.25,0.8 u=3.5,0,0 v=0,3.5,0 n=3,3 normal=0,0,1\n"
      "%s"
      "render sensor_samples=1024 seed=4\n";
  char text[4096];
  snprintf(text, sizeof text, fmt, "annual hours=8,18\n");
  vr_annual_result *open = run_annual_db(text, db);
  snprintf(text, sizeof text, fmt, "annual shade=shut window=pane\n");
  vr_annual_result *r = run_annual_db(text, db);
  assert_int_equal(r->occupied_hours, open->occupied_hours);
  size_t np = r->npoints, drawn = 0;
  for (size_t h = 0; h < r->occupied_hours; h++) {
    bool shut = r->hourly_state[h] == 1;
    drawn += shut;
    for (size_t p = 0; p < np; p++) {
      double e = r->hourly_lx[h * np + p], o = open->hourly_lx[h * np + p];
      if (shut) assert_true(e == 0);
      else if (fabs(e - o) > 1e-9 * o) fail_msg("hour %zu point %zu: %.12g lx, open %.12g lx", h, p, e, o);
    }
  }
  double most = 0, sum = 0;
  for (size_t p = 0; p < np; p++) {
    most = fmax(most, r->points[p].direct_hours), sum += r->points[p].direct_hours;
    assert_near(r->points[p].direct_hours, open->points[p].direct_hours, 0.5);
  }
  printf("room: shade drawn %zu of %zu hours; direct-sun hours: most %.0f, sum %.0f; sDA %.2f "
         "(open %.2f), ASE %.2f (open %.2f)\n",
         drawn, r->occupied_hours, most, sum, r->sda, open->sda, r->ase, open->ase);
  assert_true(drawn > 0);
  assert_true((double)drawn >= most && (double)drawn <= sum);
  assert_near(r->ase, open->ase, 1e-12);
  assert_true(r->sda <= open->sda);
  vr_annual_result_destroy(r);
  vr_annual_result_destroy(open);
  temp_db_close(db, path);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(en17037_levels),
      cmocka_unit_test(occupancy_errors),
      cmocka_unit_test(occupancy_daysim),
      cmocka_unit_test(daylight_hours_and_factor),
      cmocka_unit_test(shade_rule_in_the_open),
      cmocka_unit_test(shade_replaces_window),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
