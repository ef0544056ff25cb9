/* The 'light' statement, whose kinds are units registered above the
 * grammar (lights/light.c), and the calendar and sun-position helpers the
 * sun and the weather sky share. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/scene_parse.h"
#include "vr/sun.h"

vr_status scn_light(vr_scn_stmt *t) {
  vr_scn_parser *p = t->p;
  vr_scene *s = p->s;
  /* The kinds are units registered above the grammar (vr_scn_light_kind). */
  char list[256] = "", kinds[256] = "";
  vr_scn_light_syntax k;
  size_t nk = 0;
  while (vr_scn_light_kind(nk, &k)) nk++;
  for (size_t i = 0; i < nk && vr_scn_light_kind(i, &k); i++) {
    strncat(list, i ? ", " : "", sizeof list - strlen(list) - 1);
    strncat(list, k.name, sizeof list - strlen(list) - 1);
    strncat(kinds, i ? (i + 1 == nk ? " or " : ", ") : "", sizeof kinds - strlen(kinds) - 1);
    strncat(kinds, k.name, sizeof kinds - strlen(kinds) - 1);
  }
  char what[300];
  snprintf(what, sizeof what, "a kind: %s", kinds);
  vr_status st = scn_positional(t, 1, what);
  if (st) return st;
  const char *name = t->w[1];
  size_t kind = 0;
  while (vr_scn_light_kind(kind, &k) && strcmp(k.name, name)) kind++;
  if (kind == nk) return scn_fail(p, name, "unknown light \"%s\" (%s)", name, list);
  for (size_t i = 0; k.unique && i < s->nlights; i++)
    if (s->lights[i].kind == (vr_light_kind)kind)
      return scn_fail(p, t->w[0], "a second %s (the first is on line %ld)", k.name,
                      s->lights[i].loc.line);
  vr_scene_light *l = scn_grow((void **)&s->lights, &s->nlights, sizeof *l);
  if (!l) return scn_nomem(p);
  l->loc = scn_loc(p, t->w[0]);
  l->normal[2] = -1; /* a ceiling luminaire looks down */
  l->sun_radius_deg = 0.2665;
  l->kind = (vr_light_kind)kind;
  if (k.sun) p->sun = s->nlights;
  st = k.parse(t, l);
  return st ? st : scn_spectrum_opt(t, "spectrum", &l->spectrum);
}

/* Days in a Gregorian month. */
int scn_month_days(int y, int m) {
  static const int D[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  bool leap = (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
  return m == 2 && leap ? 29 : D[m - 1];
}

/* Day of the year (1..366) of a Gregorian date. */
int scn_day_of_year(int y, int m, int d) {
  int n = d;
  for (int i = 1; i < m; i++) n += scn_month_days(y, i);
  return n;
}

/* The sun's direction at a site (latitude north +, longitude east +) and a
 * local civil time (minutes of the day in a zone tz hours east of UTC),
 * through vr_sun_position_at (Meeus; NOAA's series) with standard air for
 * refraction.  A sun on or below the horizon is refused, naming the word at
 * fault: there is no daylight to render at that time. */
vr_status scn_sun_at(vr_scn_parser *p, const char *word, const char *when, double lat, double lon,
                        double tz, int y, int m, int d, double minutes, double dir[3]) {
  vr_sun_site site;
  vr_sun_site_default(&site, lat, lon > 180 ? lon - 360 : lon);
  vr_sun_position pos;
  vr_datetime utc;
  vr_error e = {0};
  if (vr_sun_position_local(&site, y, m, d, minutes, tz, &pos, &utc, &e) != VR_OK)
    return scn_fail(p, word, "sun position: %s", e.message);
  if (pos.altitude_deg <= 0)
    return scn_fail(p, word,
                    "the sun is below the horizon at %s (altitude %.2f deg, UTC %04d-%02d-%02d "
                    "%02d:%02d): no daylight to render",
                    when, pos.altitude_deg, utc.year, utc.month, utc.day, utc.hour, utc.minute);
  memcpy(dir, pos.direction, 3 * sizeof *dir);
  return VR_OK;
}

/* time=HH:MM[:SS] as minutes of the day. */
vr_status scn_clock_time(vr_scn_parser *p, const vr_scn_opt *o, double *minutes) {
  long long hms[3] = {0, 0, 0};
  int colons = 0;
  vr_status st = VR_OK;
  for (const char *c = o->val; *c; c++) colons += *c == ':';
  if ((colons != 1 && colons != 2) ||
      (st = scn_ints(p, o->word, o->val, ':', colons + 1, 0, 59, hms)) || hms[0] > 23)
    return st ? st : scn_fail(p, o->word, "time=%s is not HH:MM or HH:MM:SS (local, 00:00 to 23:59:59)",
                              o->val);
  *minutes = (double)(hms[0] * 60 + hms[1]) + hms[2] / 60.0;
  return VR_OK;
}

