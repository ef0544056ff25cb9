/* The sky statement (CIE general skies, the traditional overcast sky and
 * the Perez all-weather sky, its irradiances given or read from a weather
 * file) and the sky's last pass once the whole scene is read. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/scene_parse.h"
#include "vr/sky.h"
#include "vr/sun.h"
#include "vr/weather.h"

/* The sky's sun=ALTITUDE,AZIMUTH, for a sky without a sun line. */
static vr_status sky_sun(vr_scn_stmt *t, vr_scene_sky *k) {
  vr_scn_parser *p = t->p;
  const vr_scn_opt *o = scn_get(t, "sun");
  if (!o) return VR_OK;
  double aa[2];
  vr_status st = scn_numbers(p, o->word, o->val, false, 2, aa);
  if (st) return st;
  if (!(aa[0] > 0 && aa[0] <= 90))
    return scn_fail(p, o->word, "sun=%s: the altitude must be in (0, 90] degrees", o->val);
  vr_sun_direction_of(aa[0], aa[1], k->sun_direction);
  k->sun_given = true;
  return VR_OK;
}

static vr_status cie_sky(vr_scn_stmt *t, bool cie) {
  vr_scn_parser *p = t->p;
  vr_scene_sky *k = &p->s->sky;
  vr_status st;
  const vr_scn_opt *o, *lx = scn_get(t, "illuminance"), *zen = scn_get(t, "zenith");
  if (cie) {
    long long type;
    if ((st = scn_need(t, "type", &o)) || (st = scn_ints(p, o->word, o->val, ',', 1, 1, 15, &type))) return st;
    k->cie_type = (int)type;
  }
  static const vr_light_unit LX[] = {VR_UNIT_LX, VR_UNIT_NONE}, ZEN[] = {VR_UNIT_CD_M2, VR_UNIT_NONE};
  if (lx && zen) return scn_fail(p, scn_later(lx, zen), "give illuminance= or zenith=, not both");
  if (lx) st = scn_quantity(p, lx->word, lx->val, LX, VR_UNIT_LX, "a diffuse horizontal illuminance", &k->level);
  else if (zen) st = scn_quantity(p, zen->word, zen->val, ZEN, VR_UNIT_CD_M2, "a zenith luminance", &k->level);
  else st = scn_fail(p, t->w[0], "a sky needs illuminance=LX (diffuse horizontal) or zenith=CD/M2");
  if (st || (st = scn_spectrum_opt(t, "spectrum", &k->spectrum))) return st;
  return sky_sun(t, k);
}


/* A weather sky: weather=FILE date=MM-DD time=HH:MM picks the record whose
 * interval holds that local standard time; the sun is placed from the
 * file's site at that instant (in the record's year, or 2021 for a .wea,
 * which has none). */
static vr_status weather_sky(vr_scn_stmt *t, vr_scene_sky *k) {
  vr_scn_parser *p = t->p;
  const vr_scn_opt *wo = scn_get(t, "weather"), *d, *tm;
  vr_status st;
  if (!scn_get(t, "date") && !scn_get(t, "time")) {
    /* The whole file: an annual study (vr/annual.h).  Read it now so a bad
     * file fails here, naming its line. */
    if (!(k->weather_path = scn_resolve(p->s, wo->val))) return scn_nomem(p);
    vr_weather *w = NULL;
    vr_error e = {0};
    if (vr_weather_read(k->weather_path, &w, &e) != VR_OK) return scn_fail(p, wo->word, "%s", e.message);
    vr_weather_free(w);
    k->annual = true;
    return VR_OK;
  }
  if ((st = scn_need(t, "date", &d)) || (st = scn_need(t, "time", &tm))) return st;
  long long md[2];
  if ((st = scn_ints(p, d->word, d->val, '-', 2, 1, 31, md))) return st;
  if (md[0] > 12 || md[1] > scn_month_days(2020, (int)md[0]))
    return scn_fail(p, d->word, "date=%s is not a month and day MM-DD", d->val);
  double minutes;
  if ((st = scn_clock_time(p, tm, &minutes))) return st;
  if (!(k->weather_path = scn_resolve(p->s, wo->val))) return scn_nomem(p);
  vr_weather *w = NULL;
  vr_error e = {0};
  if (vr_weather_read(k->weather_path, &w, &e) != VR_OK)
    return scn_fail(p, wo->word, "%s", e.message);
  const vr_weather_record *r = NULL;
  if (vr_weather_find(w, (int)md[0], (int)md[1], minutes / 60.0, &r, &e) != VR_OK) {
    st = scn_fail(p, d->word, "%s", e.message);
    vr_weather_free(w);
    return st;
  }
  k->weather_line = r->line;
  k->direct_normal_w_m2 = r->direct_normal_w_m2;
  k->diffuse_horizontal_w_m2 = r->diffuse_horizontal_w_m2;
  k->dew_point_c = r->dew_point_c;
  int year = r->year >= 1800 && r->year <= 2200 ? r->year : 2021;
  if (md[0] == 2 && md[1] == 29 && scn_month_days(year, 2) == 28) year = 2020;
  k->day_of_year = scn_day_of_year(year, (int)md[0], (int)md[1]);
  if (isnan(k->direct_normal_w_m2) || isnan(k->diffuse_horizontal_w_m2))
    st = scn_fail(p, d->word, "%s:%ld: the record for %s %s has no %s radiation (9999: missing)",
                  w->path, r->line, d->val, tm->val,
                  isnan(k->direct_normal_w_m2) ? "direct normal" : "diffuse horizontal");
  char when[160];
  snprintf(when, sizeof when, "%s %s (local standard time of %s)", d->val, tm->val, w->place);
  if (!st)
    st = scn_sun_at(p, tm->word, when, w->latitude_deg, w->longitude_deg, w->timezone_h, year,
                    (int)md[0], (int)md[1], minutes, k->sun_direction);
  if (!st && !(k->diffuse_horizontal_w_m2 > 0))
    st = scn_fail(p, tm->word,
                  "%s:%ld: no diffuse light in the record for %s %s (diffuse horizontal %g W/m2): "
                  "the Perez sky is defined by it",
                  w->path, r->line, d->val, tm->val, k->diffuse_horizontal_w_m2);
  vr_weather_free(w);
  k->sun_from_weather = st == VR_OK;
  return st;
}

/* sky perez direct_normal=W/M2 diffuse_horizontal=W/M2 [dew_point=C] [sun=ALT,AZ]
 * sky perez weather=FILE date=MM-DD time=HH:MM */
static vr_status perez_sky(vr_scn_stmt *t) {
  vr_scn_parser *p = t->p;
  vr_scene_sky *k = &p->s->sky;
  k->cie_type = VR_SKY_PEREZ;
  const vr_scn_opt *wo = scn_get(t, "weather");
  static const char *const GIVEN[] = {"direct_normal", "diffuse_horizontal", "dew_point", "sun", NULL};
  static const char *const FROM_FILE[] = {"date", "time", NULL};
  for (int i = 0; GIVEN[i] && wo; i++)
    if (scn_get(t, GIVEN[i]))
      return scn_fail(p, scn_get(t, GIVEN[i])->word,
                      "%s= with weather=: the weather record gives the irradiances, the dew point "
                      "and (from the file's site) the sun",
                      GIVEN[i]);
  for (int i = 0; FROM_FILE[i] && !wo; i++)
    if (scn_get(t, FROM_FILE[i]))
      return scn_fail(p, scn_get(t, FROM_FILE[i])->word,
                      "%s= picks a record of a weather file: it needs weather=FILE", FROM_FILE[i]);
  vr_status st;
  if (wo) {
    st = weather_sky(t, k);
  } else {
    const vr_scn_opt *o;
    if ((st = scn_need(t, "direct_normal", &o)) || (st = scn_need(t, "diffuse_horizontal", &o)) ||
        (st = scn_range(t, "direct_normal", 0, 1500, false, false, &k->direct_normal_w_m2)) ||
        (st = scn_range(t, "diffuse_horizontal", 0, 1000, true, false, &k->diffuse_horizontal_w_m2)) ||
        (st = scn_range(t, "dew_point", -90, 60, false, false, &k->dew_point_c)))
      return st;
    st = sky_sun(t, k);
  }
  return st ? st : scn_spectrum_opt(t, "spectrum", &k->spectrum);
}

vr_status scn_sky(vr_scn_stmt *t) {
  vr_scn_parser *p = t->p;
  vr_scene_sky *k = &p->s->sky;
  if (k->present) return scn_fail(p, t->w[0], "a second sky (the first is on line %ld)", k->loc.line);
  vr_status st = scn_positional(t, 1, "a kind: cie, overcast or perez");
  if (st) return st;
  static const char *const CIE[] = {"type", "illuminance", "zenith", "spectrum", "ground", "sun", NULL};
  static const char *const OVERCAST[] = {"illuminance", "zenith", "spectrum", "ground", NULL};
  static const char *const PEREZ[] = {"direct_normal", "diffuse_horizontal", "dew_point", "sun",
                                      "weather", "date", "time", "spectrum", "ground", NULL};
  bool cie = !strcmp(t->w[1], "cie"), perez = !strcmp(t->w[1], "perez");
  if (!cie && !perez && strcmp(t->w[1], "overcast"))
    return scn_fail(p, t->w[1], "unknown sky \"%s\" (cie, overcast, perez)", t->w[1]);
  t->what = cie ? "a CIE sky" : perez ? "a Perez sky" : "an overcast sky";
  if ((st = scn_options(t, 2, cie ? CIE : perez ? PEREZ : OVERCAST))) return st;
  k->present = true;
  k->loc = scn_loc(p, t->w[0]);
  st = perez ? perez_sky(t) : cie_sky(t, cie);
  return st ? st : scn_range(t, "ground", 0, 1, false, false, &k->ground_reflectance);
}

/* ---- the last pass ---- */

static vr_status at_sky(vr_scn_parser *p, const char *fmt, const char *a, double x) {
  const vr_scene_sky *k = &p->s->sky;
  return vr_error_at(p->err, VR_E_PARSE, p->file, k->loc.line, k->loc.col, fmt, a, x);
}

static vr_status perez_finish(vr_scn_parser *p) {
  vr_scene *s = p->s;
  vr_scene_sky *k = &s->sky;
  vr_scene_light *sun = p->sun ? &s->lights[p->sun - 1] : NULL;
  if (sun && !isnan(sun->amount.value))
    return vr_error_at(p->err, VR_E_PARSE, p->file, sun->loc.line, sun->loc.col,
                       "the sun's illuminance comes from the Perez sky on line %ld (its direct "
                       "normal irradiance times the Perez 1990 efficacy): drop illuminance=",
                       k->loc.line);
  if (!sun && k->direct_normal_w_m2 > 0)
    return at_sky(p,
                  "the Perez sky has %s%g W/m2 of direct sun but the scene has no 'light sun' "
                  "line to carry it: add 'light sun' (its illuminance comes from the sky)",
                  "direct normal irradiance ", k->direct_normal_w_m2);
  if (sun && !k->sun_from_weather && sun->day_of_year) k->day_of_year = sun->day_of_year;
  vr_perez_input in = {0};
  double alt, az;
  vr_sun_angles_of(k->sun_direction, &alt, &az);
  in.sun_zenith_deg = 90.0 - alt;
  in.direct_normal_w_m2 = k->direct_normal_w_m2;
  in.diffuse_horizontal_w_m2 = k->diffuse_horizontal_w_m2;
  in.dew_point_c = k->dew_point_c;
  in.day_of_year = k->day_of_year;
  vr_error e = {0};
  if (vr_perez_sky_from(&in, &k->perez, &e) != VR_OK)
    return vr_error_at(p->err, VR_E_PARSE, p->file, k->loc.line, k->loc.col, "%s", e.message);
  k->level.value = k->perez.diffuse_horizontal_lx;
  k->level.unit = VR_UNIT_LX;
  if (sun) {
    sun->amount.value = k->perez.direct_normal_lx;
    sun->amount.unit = VR_UNIT_LX;
  }
  return VR_OK;
}

vr_status scn_sky_finish(vr_scn_parser *p) {
  vr_scene *s = p->s;
  vr_scene_sky *k = &s->sky;
  bool perez = k->present && k->cie_type == VR_SKY_PEREZ;
  vr_scene_light *sun = p->sun ? &s->lights[p->sun - 1] : NULL;
  if (sun && sun->from_sky && !k->sun_from_weather && !k->annual)
    return vr_error_at(p->err, VR_E_PARSE, p->file, sun->loc.line, sun->loc.col,
                       "a sun needs direction=, altitude= and azimuth=, or latitude=, longitude=, "
                       "date= and time= (only a weather sky, 'sky perez weather=...', places it "
                       "itself)");
  if (sun && !sun->from_sky && (k->sun_from_weather || k->annual))
    return vr_error_at(p->err, VR_E_PARSE, p->file, sun->loc.line, sun->loc.col,
                       "the weather sky on line %ld places the sun from its file's site, date "
                       "and time: drop this sun's direction or site",
                       k->loc.line);
  if (sun && isnan(sun->amount.value) && !perez)
    return vr_error_at(p->err, VR_E_PARSE, p->file, sun->loc.line, sun->loc.col,
                       "a sun needs illuminance= (only a Perez sky sets it itself)");
  if (sun && k->present && k->sun_given)
    return vr_error_at(p->err, VR_E_PARSE, p->file, k->loc.line, k->loc.col,
                       "the sky's sun= and the sun on line %ld both place the sun: give it once "
                       "(the sun line places the sky's too)",
                       sun->loc.line);
  if (sun && k->sun_from_weather) memcpy(sun->direction, k->sun_direction, sizeof sun->direction);
  else if (sun) memcpy(k->sun_direction, sun->direction, sizeof k->sun_direction);
  if (k->annual) {
    if (!sun)
      return vr_error_at(p->err, VR_E_PARSE, p->file, k->loc.line, k->loc.col,
                         "a year of weather needs a 'light sun' line for the hours of direct sun "
                         "(the file places it and gives its illuminance hour by hour)");
    if (!isnan(sun->amount.value))
      return vr_error_at(p->err, VR_E_PARSE, p->file, sun->loc.line, sun->loc.col,
                         "the sun's illuminance comes from the weather file on line %ld, hour by "
                         "hour: drop illuminance=",
                         k->loc.line);
    return VR_OK;
  }
  if (k->present && k->cie_type > 0 && !sun && !k->sun_given && !k->sun_from_weather) {
    /* A sky whose luminance follows the sun (an indicatrix that is not
     * flat) must be told where the sun is, not given the zenith. */
    vr_sky_params sp;
    if (perez || (vr_sky_params_of(k->cie_type, &sp, NULL) == VR_OK && (sp.c != 0.0 || sp.e != 0.0)))
      return vr_error_at(p->err, VR_E_PARSE, p->file, k->loc.line, k->loc.col,
                         "%s%.0d is brighter towards the sun, but the scene does not say where "
                         "the sun is: add a 'light sun' line (its place sets the sky's) or give "
                         "the sky sun=ALTITUDE,AZIMUTH",
                         perez ? "the Perez sky" : "CIE sky type ", perez ? 0 : k->cie_type);
  }
  if (s->nportals && !k->present)
    return vr_error_at(p->err, VR_E_PARSE, p->file, s->portals[0].loc.line, s->portals[0].loc.col,
                       "a portal aims the sky's light, but the scene has no sky line");
  return perez ? perez_finish(p) : VR_OK;
}
