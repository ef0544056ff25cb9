/* Scene statements for how the scene is lit and measured: point, spot and
 * sun lights, the sky, illuminance sensors and the render settings. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene_parse.h"
#include "vr/sun.h"

/* ---- lights ---- */

static const vr_light_unit LAMP_UNITS[] = {VR_UNIT_CD, VR_UNIT_LM, VR_UNIT_W, VR_UNIT_W_SR, VR_UNIT_NONE};

static vr_status lamp_amount(const scn_stmt *t, vr_scene_light *l, bool required) {
  const scn_opt *o = scn_get(t, "intensity");
  if (!o) return required ? scn_fail(t->p, t->w[0], "%s needs intensity=", t->what) : VR_OK;
  return scn_quantity(t->p, o->word, o->val, LAMP_UNITS, VR_UNIT_NONE, "an intensity", &l->amount);
}

static vr_status point_light(scn_stmt *t, vr_scene_light *l) {
  scn_parser *p = t->p;
  static const char *const POINT[] = {"position", "intensity", "distribution", "normal", "ies", "spectrum", NULL};
  static const char *const DISTS[] = {"isotropic", "lambertian", "goniometric", NULL};
  t->what = "a point light";
  const scn_opt *o, *ies, *dist;
  vr_status st;
  if ((st = scn_options(t, 2, POINT)) || (st = scn_need(t, "position", &o)) || (st = scn_point(t, o, l->position)))
    return st;
  int d = -1;
  if ((st = scn_choice(t, "distribution", DISTS, &d))) return st;
  ies = scn_get(t, "ies"), dist = scn_get(t, "distribution");
  if (ies && d >= 0 && d != VR_DIST_GONIOMETRIC)
    return scn_fail(p, ies->word, "ies= needs distribution=goniometric (or no distribution=)");
  if (ies) d = VR_DIST_GONIOMETRIC;
  if (d == VR_DIST_GONIOMETRIC && !ies)
    return scn_fail(p, dist->word, "distribution=goniometric needs ies=FILE");
  l->distribution = d < 0 ? VR_DIST_ISOTROPIC : (vr_distribution)d;
  if (ies && !(l->ies_path = scn_resolve(p->s, ies->val))) return scn_nomem(p);
  if ((o = scn_get(t, "normal")) && (st = scn_direction(p, o->word, o->val, l->normal))) return st;
  return lamp_amount(t, l, l->distribution != VR_DIST_GONIOMETRIC);
}

static vr_status spot_light(scn_stmt *t, vr_scene_light *l) {
  scn_parser *p = t->p;
  static const char *const SPOT[] = {"position", "direction", "cone", "falloff", "intensity", "spectrum", NULL};
  t->what = "a spot light";
  const scn_opt *o, *dir, *cone;
  vr_status st;
  if ((st = scn_options(t, 2, SPOT)) || (st = scn_need(t, "position", &o)) || (st = scn_need(t, "direction", &dir)) ||
      (st = scn_need(t, "cone", &cone)) || (st = scn_point(t, o, l->position)) ||
      (st = scn_direction(p, dir->word, dir->val, l->direction)) ||
      (st = scn_range(t, "cone", 0, 180, true, true, &l->cone_deg)) ||
      (st = scn_range(t, "falloff", 0, 180, false, false, &l->falloff_deg)))
    return st;
  if (l->cone_deg + l->falloff_deg > 180)
    return scn_fail(p, scn_get(t, "falloff") ? scn_get(t, "falloff")->word : t->w[0], "cone + falloff exceeds 180 degrees");
  return lamp_amount(t, l, true);
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
vr_status scn_sun_at(scn_parser *p, const char *word, const char *when, double lat, double lon,
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
vr_status scn_clock_time(scn_parser *p, const scn_opt *o, double *minutes) {
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

/* The sun's direction at a site and a local civil time:
 *   latitude=DEG (north +) longitude=DEG (east +) date=YYYY-MM-DD
 *   time=HH:MM[:SS] [timezone=HOURS east of Greenwich, default 0 = UTC] */
static vr_status sun_from_site(scn_stmt *t, vr_scene_light *l) {
  scn_parser *p = t->p;
  static const char *const SITE[] = {"latitude", "longitude", "date", "time", NULL};
  const scn_opt *o;
  for (int i = 0; SITE[i]; i++)
    if (!scn_get(t, SITE[i]))
      return scn_fail(p, t->w[0], "a sun placed by site and time needs latitude=, longitude=, "
                                  "date= and time= (%s= is missing)", SITE[i]);
  double lat, lon, tz = 0;
  vr_status st;
  if ((st = scn_range(t, "latitude", -90, 90, false, false, &lat)) ||
      (st = scn_range(t, "longitude", -180, 360, false, true, &lon)) ||
      (st = scn_range(t, "timezone", -14, 14, false, false, &tz)))
    return st;
  long long ymd[3];
  o = scn_get(t, "date");
  if ((st = scn_ints(p, o->word, o->val, '-', 3, 0, 9999, ymd))) return st;
  if (ymd[0] < 1800 || ymd[0] > 2200 || ymd[1] < 1 || ymd[1] > 12 || ymd[2] < 1 ||
      ymd[2] > scn_month_days((int)ymd[0], (int)ymd[1]))
    return scn_fail(p, o->word, "date=%s is not a calendar date YYYY-MM-DD between 1800 and 2200",
                    o->val);
  double minutes;
  if ((st = scn_clock_time(p, scn_get(t, "time"), &minutes))) return st;
  char when[96];
  snprintf(when, sizeof when, "%s %s", o->val, scn_get(t, "time")->val);
  l->day_of_year = scn_day_of_year((int)ymd[0], (int)ymd[1], (int)ymd[2]);
  return scn_sun_at(p, scn_get(t, "time")->word, when, lat, lon, tz, (int)ymd[0], (int)ymd[1],
                (int)ymd[2], minutes, l->direction);
}

static vr_status sun_light(scn_stmt *t, vr_scene_light *l) {
  scn_parser *p = t->p;
  static const char *const SUN[] = {"direction", "altitude", "azimuth", "illuminance", "radius",
                                    "spectrum", "latitude", "longitude", "date", "time",
                                    "timezone", NULL};
  static const vr_light_unit SUN_UNITS[] = {VR_UNIT_LX, VR_UNIT_W_M2, VR_UNIT_NONE};
  t->what = "a sun";
  vr_status st = scn_options(t, 2, SUN);
  if (st) return st;
  const scn_opt *dir = scn_get(t, "direction"), *alt = scn_get(t, "altitude"), *az = scn_get(t, "azimuth"), *o;
  const scn_opt *site = scn_get(t, "latitude") ? scn_get(t, "latitude")
                        : scn_get(t, "longitude") ? scn_get(t, "longitude")
                        : scn_get(t, "date")      ? scn_get(t, "date")
                        : scn_get(t, "time")      ? scn_get(t, "time")
                                                  : scn_get(t, "timezone");
  if (dir && (alt || az))
    return scn_fail(p, scn_later(dir, alt ? alt : az), "give direction= or altitude= and azimuth=, not both");
  if (site && (dir || alt || az))
    return scn_fail(p, scn_later(site, dir ? dir : alt ? alt : az),
                    "give the sun's place as direction=, altitude= and azimuth=, or latitude=, "
                    "longitude=, date= and time=, not both");
  if (site) {
    if ((st = sun_from_site(t, l))) return st;
  } else if (dir) {
    if ((st = scn_direction(p, dir->word, dir->val, l->direction))) return st;
  } else {
    if (!alt && !az) {
      /* Only a weather sky may place it; the parser's last pass checks. */
      l->from_sky = true;
      goto amount;
    }
    if (!alt || !az) return scn_fail(p, (alt ? alt : az)->word, "a sun needs both altitude= and azimuth=");
    double a = 0, z = 0;
    if ((st = scn_range(t, "altitude", -90, 90, false, false, &a)) ||
        (st = scn_range(t, "azimuth", -HUGE_VAL, HUGE_VAL, false, false, &z)))
      return st;
    /* Azimuth from north (+y) towards east (+x), altitude above z = 0. */
    double ar = a * M_PI / 180, zr = z * M_PI / 180;
    l->direction[0] = cos(ar) * sin(zr);
    l->direction[1] = cos(ar) * cos(zr);
    l->direction[2] = sin(ar);
  }
amount:
  /* Without illuminance=, only a Perez sky may set it (the last pass checks). */
  if (!(o = scn_get(t, "illuminance"))) {
    l->amount.value = NAN;
  } else if ((st = scn_quantity(p, o->word, o->val, SUN_UNITS, VR_UNIT_LX, "a sun's illuminance",
                                &l->amount))) {
    return st;
  }
  return scn_range(t, "radius", 0, 90, false, true, &l->sun_radius_deg);
}

vr_status scn_light(scn_stmt *t) {
  scn_parser *p = t->p;
  vr_scene *s = p->s;
  vr_status st = scn_positional(t, 1, "a kind: point, spot or sun");
  if (st) return st;
  const char *kind = t->w[1];
  bool sun = !strcmp(kind, "sun");
  if (!sun && strcmp(kind, "point") && strcmp(kind, "spot"))
    return scn_fail(p, kind, "unknown light \"%s\" (point, spot, sun)", kind);
  if (sun && p->sun)
    return scn_fail(p, t->w[0], "a second sun (the first is on line %ld)", s->lights[p->sun - 1].loc.line);
  vr_scene_light *l = scn_grow((void **)&s->lights, &s->nlights, sizeof *l);
  if (!l) return scn_nomem(p);
  l->loc = scn_loc(p, t->w[0]);
  l->normal[2] = -1; /* a ceiling luminaire looks down */
  l->sun_radius_deg = 0.2665;
  if (sun) {
    l->kind = VR_LIGHT_SUN;
    p->sun = s->nlights;
    st = sun_light(t, l);
  } else if (!strcmp(kind, "point")) {
    l->kind = VR_LIGHT_POINT;
    st = point_light(t, l);
  } else {
    l->kind = VR_LIGHT_SPOT;
    st = spot_light(t, l);
  }
  return st ? st : scn_spectrum_opt(t, "spectrum", &l->spectrum);
}

/* ---- sensors and settings ---- */

vr_status scn_sensor(scn_stmt *t) {
  scn_parser *p = t->p;
  vr_scene *s = p->s;
  vr_status st = scn_positional(t, 2, "a name and a kind: point or grid");
  if (st) return st;
  for (size_t i = 0; i < s->nsensors; i++)
    if (!strcmp(s->sensors[i].name, t->w[1]))
      return scn_fail(p, t->w[1], "sensor \"%s\" is defined twice (first on line %ld)", t->w[1],
                      s->sensors[i].loc.line);
  static const char *const POINT[] = {"position", "normal", NULL};
  static const char *const GRID[] = {"origin", "u", "v", "n", "normal", NULL};
  bool grid = !strcmp(t->w[2], "grid");
  if (!grid && strcmp(t->w[2], "point"))
    return scn_fail(p, t->w[2], "unknown sensor kind \"%s\" (point, grid)", t->w[2]);
  t->what = grid ? "a grid sensor" : "a point sensor";
  if ((st = scn_options(t, 3, grid ? GRID : POINT))) return st;
  vr_scene_sensor *se = scn_grow((void **)&s->sensors, &s->nsensors, sizeof *se);
  if (!se || !(se->name = strdup(t->w[1]))) return scn_nomem(p);
  se->grid = grid;
  se->loc = scn_loc(p, t->w[0]);
  se->nu = se->nv = 1;
  const scn_opt *pos, *n, *u, *v, *cnt;
  if ((st = scn_need(t, grid ? "origin" : "position", &pos)) || (st = scn_need(t, "normal", &n)) ||
      (st = scn_point(t, pos, se->position)) || (st = scn_direction(p, n->word, n->val, se->normal)))
    return st;
  if (!grid) return VR_OK;
  if ((st = scn_need(t, "u", &u)) || (st = scn_need(t, "v", &v)) || (st = scn_need(t, "n", &cnt)) ||
      (st = scn_point(t, u, se->u)) || (st = scn_point(t, v, se->v)))
    return st;
  double c[3];
  scn_cross3(se->u, se->v, c);
  if (!(scn_dot3(se->u, se->u) > 0)) return scn_fail(p, u->word, "\"%s\": a zero-length edge", u->word);
  if (!(scn_dot3(se->v, se->v) > 0)) return scn_fail(p, v->word, "\"%s\": a zero-length edge", v->word);
  if (!(sqrt(scn_dot3(c, c)) > 1e-9 * sqrt(scn_dot3(se->u, se->u)) * sqrt(scn_dot3(se->v, se->v))))
    return scn_fail(p, v->word, "\"%s\": the grid's edges u and v are parallel", v->word);
  long long nn[2];
  if ((st = scn_ints(p, cnt->word, cnt->val, ',', 2, 1, 10000, nn))) return st;
  se->nu = (int)nn[0], se->nv = (int)nn[1];
  return VR_OK;
}

/* MIN,MAX[,STEP] in nm. */
static vr_status band(const scn_stmt *t, const char *key, bool step, double *lo, double *hi, double *dl) {
  const scn_opt *o = scn_get(t, key);
  if (!o) return VR_OK;
  double v[3];
  vr_status st = scn_numbers(t->p, o->word, o->val, false, step ? 3 : 2, v);
  if (st) return st;
  if (!(v[0] > 0 && v[1] > v[0] && v[1] <= 1e5))
    return scn_fail(t->p, o->word, "\"%s\": need 0 < MIN < MAX <= 100000 nm", o->word);
  if (step && !(v[2] > 0 && v[2] <= v[1] - v[0] && (v[1] - v[0]) / v[2] <= 1e5))
    return scn_fail(t->p, o->word, "\"%s\": need 0 < STEP <= MAX - MIN, at most 100000 bins", o->word);
  *lo = v[0], *hi = v[1];
  if (step) *dl = v[2];
  return VR_OK;
}

vr_status scn_render(scn_stmt *t) {
  scn_parser *p = t->p;
  vr_scene_settings *g = &p->s->settings;
  if (p->have_render)
    return scn_fail(p, t->w[0], "a second render line (the first is on line %ld)", g->loc.line);
  static const char *const RENDER[] = {
      "integrator", "spp",          "depth",      "spectral",       "wavelengths", "range",
      "photons",    "caustic_photons", "knn",     "radius",         "final_gather", "gather_rays",
      "passes",     "alpha",        "sensor_samples", "seed",       "film",        "sensors",
      "sensor_knn", "photon_portals", "sampler", NULL};
  static const char *const INTEGRATORS[] = {"path", "whitted", "photon", "progressive", "bdpt",
                                            NULL};
  static const char *const SPECTRAL[] = {"hero", "bins", NULL};
  static const char *const ONOFF[] = {"off", "on", NULL};
  static const char *const SENSORS[] = {"path", "photon", NULL};
  t->what = "render";
  vr_status st = scn_options(t, 1, RENDER);
  if (st) return st;
  p->have_render = true;
  g->loc = scn_loc(p, t->w[0]);
  int integ = (int)g->integrator, spectral = (int)g->spectral, fg = g->final_gather,
      pport = g->photon_portals,
      sensors = (int)g->sensors;
  long long spp = g->spp, depth = g->max_depth, wl = g->wavelengths, photons = g->photons,
            caustic = g->caustic_photons, knn = g->knn, gather = g->gather_rays, passes = g->passes,
            samples = g->sensor_samples, sensor_knn = g->sensor_knn;
  const scn_opt *o;
  if ((st = scn_choice(t, "integrator", INTEGRATORS, &integ)) || (st = scn_choice(t, "spectral", SPECTRAL, &spectral)) ||
      (st = scn_choice(t, "final_gather", ONOFF, &fg)) ||
      (st = scn_choice(t, "photon_portals", ONOFF, &pport)) || (st = scn_choice(t, "sensors", SENSORS, &sensors)) || (st = scn_int_opt(t, "spp", 1, 1 << 20, &spp)) ||
      (st = scn_int_opt(t, "depth", 0, 1024, &depth)) || (st = scn_int_opt(t, "wavelengths", 1, VR_SCENE_MAX_WAVELENGTHS, &wl)) ||
      (st = scn_int_opt(t, "photons", 0, 1000000000000LL, &photons)) ||
      (st = scn_int_opt(t, "caustic_photons", 0, 1000000000000LL, &caustic)) ||
      (st = scn_int_opt(t, "knn", 1, 100000, &knn)) || (st = scn_int_opt(t, "gather_rays", 1, 1 << 20, &gather)) ||
      (st = scn_int_opt(t, "passes", 1, 1 << 20, &passes)) ||
      (st = scn_int_opt(t, "sensor_samples", 1, 1 << 30, &samples)) ||
      (st = scn_int_opt(t, "sensor_knn", 1, 100000, &sensor_knn)) ||
      (st = scn_range(t, "alpha", 0, 1, true, true, &g->alpha)) ||
      (st = band(t, "range", false, &g->lambda_min, &g->lambda_max, NULL)) ||
      (st = band(t, "film", true, &g->film_min_nm, &g->film_max_nm, &g->film_step_nm)))
    return st;
  if ((o = scn_get(t, "radius")) && (st = scn_positive_length(t, o, &g->radius_m))) return st;
  /* Progressive photon mapping renders spp iterations of one camera path a
   * pixel each; passes= is the older name of that count. */
  if (integ == VR_INT_PROGRESSIVE && (o = scn_get(t, "passes"))) {
    const scn_opt *os = scn_get(t, "spp");
    if (os)
      return scn_fail(p, o->word,
                      "spp= and passes= both given: integrator=progressive renders spp iterations "
                      "of one camera path a pixel and `photons` photons each (passes= is the "
                      "older name of spp=)");
    spp = passes;
  }
  /* Each progressive iteration's wavelengths serve every pixel, so one
   * iteration's spectral quadrature must be good: 4 wavelengths 75 nm
   * apart left Z (the narrowest colour-matching function) 1.2 x noisier
   * than Y in the white furnace (tests/render/test_sppm.c), 8 do not. */
  if (integ == VR_INT_PROGRESSIVE && !scn_get(t, "wavelengths")) wl = VR_SCENE_MAX_WAVELENGTHS;
  if ((o = scn_get(t, "seed")) && (st = scn_u64(p, o->word, o->val, &g->seed))) return st;
  static const char *const SAMPLERS[] = {"independent", "stratified", "sobol", NULL};
  int sampler = (int)g->sampler;
  if ((st = scn_choice(t, "sampler", SAMPLERS, &sampler))) return st;
  g->sampler = (vr_sampler_kind)sampler;
  /* Fixed bins default to the most wavelengths a path carries: 4 bins of
   * 117 nm cannot follow a lamp's spectrum. */
  if (spectral == VR_SPECTRAL_BINS && !scn_get(t, "wavelengths")) wl = VR_SCENE_MAX_WAVELENGTHS;
  g->photon_portals = pport;
  g->integrator = (vr_integrator)integ, g->spectral = (vr_spectral_mode)spectral, g->final_gather = fg;
  g->sensors = (vr_sensor_estimator)sensors;
  g->spp = (int)spp, g->max_depth = (int)depth, g->wavelengths = (int)wl, g->photons = (long)photons;
  g->caustic_photons = (long)caustic, g->knn = (int)knn, g->gather_rays = (int)gather;
  g->passes = (int)passes, g->sensor_samples = (int)samples;
  /* Photon sensors read the maps with knn photons unless told otherwise. */
  g->sensor_knn = scn_get(t, "sensor_knn") ? (int)sensor_knn : (int)knn;
  return VR_OK;
}

