/* The sun: 'light sun' placed by direction=, by altitude= and azimuth=,
 * by a site and a local time (latitude= longitude= date= time=
 * [timezone=]) or by a weather sky, with illuminance= in lx or W/m² normal
 * to the beam (a Perez sky may set it) and an apparent radius= (default
 * 0.2665 degrees; 0 is a parallel beam).  A far light: its next-event
 * samples are directions within the solar disc, each with the whole
 * normal irradiance (soft shadows), and its photons cross a disc of the
 * scene's bounding radius. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "lights/kinds.h"
#include "lights/lights.h"
#include "vr/vec3.h"

#define COS_SUN(l) ((l)->k[0])

/* The sun's direction at a site and a local civil time:
 *   latitude=DEG (north +) longitude=DEG (east +) date=YYYY-MM-DD
 *   time=HH:MM[:SS] [timezone=HOURS east of Greenwich, default 0 = UTC] */
static vr_status from_site(vr_scn_stmt *t, vr_scene_light *l) {
  vr_scn_parser *p = t->p;
  static const char *const SITE[] = {"latitude", "longitude", "date", "time", NULL};
  const vr_scn_opt *o;
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

static vr_status parse(vr_scn_stmt *t, vr_scene_light *l) {
  vr_scn_parser *p = t->p;
  static const char *const SUN[] = {"direction", "altitude", "azimuth", "illuminance", "radius",
                                    "spectrum", "latitude", "longitude", "date", "time",
                                    "timezone", NULL};
  static const vr_light_unit SUN_UNITS[] = {VR_UNIT_LX, VR_UNIT_W_M2, VR_UNIT_NONE};
  t->what = "a sun";
  vr_status st = scn_options(t, 2, SUN);
  if (st) return st;
  const vr_scn_opt *dir = scn_get(t, "direction"), *alt = scn_get(t, "altitude"), *az = scn_get(t, "azimuth"), *o;
  const vr_scn_opt *site = scn_get(t, "latitude") ? scn_get(t, "latitude")
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
    if ((st = from_site(t, l))) return st;
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

static vr_status resolve(vr_light *l, const vr_scene_light *sl, const vr_light_setup *u,
                         vr_error *err) {
  memcpy(l->axis, sl->direction, sizeof l->axis);
  vr_normalize3(l->axis);
  COS_SUN(l) = cos(sl->sun_radius_deg * M_PI / 180.0);
  vr_status st = vr_spd_normalise(&u->spd, &l->spd, sl->amount,
                                  vr_unit_is_photometric(sl->amount.unit), &sl->loc, "sun", err);
  if (st) return st;
  /* Power through a disc of the scene's radius, for photon shares. */
  l->power = vr_rspd_integral(&l->spd, u->spd.lmin, u->spd.lmax) * M_PI * u->radius * u->radius;
  return VR_OK;
}

static bool sample_li(const vr_light *l, const double x[3], const vr_rng_key *key,
                      vr_light_dims dims, int nwl, const double *wl, vr_light_sample *out) {
  (void)x;
  out->delta = true;
  vr_sample_cone(l->axis, COS_SUN(l), vr_rng(key, dims.u), vr_rng(key, dims.v), out->dir);
  out->dist = INFINITY;
  memcpy(out->n, l->axis, sizeof out->n);
  for (int a = 0; a < 3; a++) out->p[a] = INFINITY;
  out->pdf_pos = 1;
  for (int k = 0; k < nwl; k++) out->L[k] = vr_rspd_at(&l->spd, wl[k]);
  return true;
}

static double pdf_li(const vr_light *l, const double x[3], const double dir[3]) {
  (void)l, (void)x, (void)dir;
  return 0;
}

static bool sample_le(const vr_light *l, const vr_light_setup *u, const vr_rng_key *key,
                      vr_light_emission *out) {
  double toward[3];
  vr_sample_cone(l->axis, COS_SUN(l), vr_rng(key, VR_DIM_EMIT_W), vr_rng(key, VR_DIM_EMIT_X),
                 toward);
  for (int a = 0; a < 3; a++) out->dir[a] = -toward[a];
  vr_light_disc_origin(u, out->dir, vr_rng(key, VR_DIM_EMIT_U), vr_rng(key, VR_DIM_EMIT_V),
                       out->org);
  memcpy(out->n, out->dir, sizeof out->n);
  out->pdf_dir = out->pdf_pos = 1;
  out->f = out->weight = M_PI * u->radius * u->radius;
  return true;
}

static double pdf_le_dir(const vr_light *l, const double p[3], const double n[3],
                         const double dir[3]) {
  (void)l, (void)p, (void)n, (void)dir;
  return 0;
}

bool vr_lights_sun_disc(const vr_lights *Ls, const double dir[3], int nwl, const double *wl,
                        double *L) {
  if (Ls->sun >= Ls->n) return false;
  const vr_light *l = &Ls->light[Ls->sun];
  double c = COS_SUN(l);
  if (!(c < 1) || vr_dot3(dir, l->axis) < c) return false;
  /* The disc's radiance: its normal irradiance over its solid angle. */
  double omega = 2 * M_PI * (1 - c);
  for (int k = 0; k < nwl; k++) L[k] = vr_rspd_at(&l->spd, wl[k]) / omega;
  return true;
}

const vr_light_ops vr_light_sun = {
    .name = "sun", .flags = VR_LF_FAR | VR_LF_UNIQUE | VR_LF_SUN, .source = VR_SRC_SUN,
    .spectrum = "db:ASTM-G173-AM1.5D", .parse = parse, .resolve = resolve,
    .sample_li = sample_li, .pdf_li = pdf_li, .sample_le = sample_le, .pdf_le_dir = pdf_le_dir};
