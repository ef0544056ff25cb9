/* Scene statements for how the scene is measured and rendered: the
 * illuminance sensors and the render settings, whose integrator names are
 * the units registered in integrators/registry.c. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/scene_parse.h"
#include "vr/vec3.h"

vr_status scn_sensor(vr_scn_stmt *t) {
  vr_scn_parser *p = t->p;
  vr_scene *s = p->s;
  vr_status st = scn_positional(t, 2, "a name and a kind: point, grid or points");
  if (st) return st;
  for (size_t i = 0; i < s->nsensors; i++)
    if (!strcmp(s->sensors[i].name, t->w[1]))
      return scn_fail(p, t->w[1], "sensor \"%s\" is defined twice (first on line %ld)", t->w[1],
                      s->sensors[i].loc.line);
  static const char *const POINT[] = {"position", "normal", NULL};
  static const char *const GRID[] = {"origin", "u", "v", "n", "normal", NULL};
  static const char *const POINTS[] = {"file", NULL};
  bool grid = !strcmp(t->w[2], "grid"), points = !strcmp(t->w[2], "points");
  if (!grid && !points && strcmp(t->w[2], "point"))
    return scn_fail(p, t->w[2], "unknown sensor kind \"%s\" (point, grid, points)", t->w[2]);
  t->what = grid ? "a grid sensor" : points ? "a points-file sensor" : "a point sensor";
  if ((st = scn_options(t, 3, grid ? GRID : points ? POINTS : POINT))) return st;
  vr_scene_sensor *se = scn_grow((void **)&s->sensors, &s->nsensors, sizeof *se);
  if (!se || !(se->name = strdup(t->w[1]))) return scn_nomem(p);
  se->grid = grid || points;
  se->loc = scn_loc(p, t->w[0]);
  se->nu = se->nv = 1;
  if (points) {
    /* Radiance's .pts: a point a line, x y z dx dy dz; an analysis grid. */
    const vr_scn_opt *f;
    if ((st = scn_need(t, "file", &f))) return st;
    if (!(se->pts_path = scn_resolve(s, f->val))) return scn_nomem(p);
    vr_error e = {0};
    if (scn_read_pts(se->pts_path, &se->pts, &se->nu, &e)) return scn_fail(p, f->word, "%s", e.message);
    se->position[2] = 0, se->normal[2] = 1; /* unused: each point has its own */
    return VR_OK;
  }
  const vr_scn_opt *pos, *n, *u, *v, *cnt;
  if ((st = scn_need(t, grid ? "origin" : "position", &pos)) || (st = scn_need(t, "normal", &n)) ||
      (st = scn_point(t, pos, se->position)) || (st = scn_direction(p, n->word, n->val, se->normal)))
    return st;
  if (!grid) return VR_OK;
  if ((st = scn_need(t, "u", &u)) || (st = scn_need(t, "v", &v)) || (st = scn_need(t, "n", &cnt)) ||
      (st = scn_point(t, u, se->u)) || (st = scn_point(t, v, se->v)))
    return st;
  double c[3];
  vr_cross3(se->u, se->v, c);
  if (!(vr_dot3(se->u, se->u) > 0)) return scn_fail(p, u->word, "\"%s\": a zero-length edge", u->word);
  if (!(vr_dot3(se->v, se->v) > 0)) return scn_fail(p, v->word, "\"%s\": a zero-length edge", v->word);
  if (!(sqrt(vr_dot3(c, c)) > 1e-9 * sqrt(vr_dot3(se->u, se->u)) * sqrt(vr_dot3(se->v, se->v))))
    return scn_fail(p, v->word, "\"%s\": the grid's edges u and v are parallel", v->word);
  long long nn[2];
  if ((st = scn_ints(p, cnt->word, cnt->val, ',', 2, 1, 10000, nn))) return st;
  se->nu = (int)nn[0], se->nv = (int)nn[1];
  return VR_OK;
}

/* MIN,MAX[,STEP] in nm. */
static vr_status band(const vr_scn_stmt *t, const char *key, bool step, double *lo, double *hi, double *dl) {
  const vr_scn_opt *o = scn_get(t, key);
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

vr_status scn_render(vr_scn_stmt *t) {
  vr_scn_parser *p = t->p;
  vr_scene_settings *g = &p->s->settings;
  if (p->have_render)
    return scn_fail(p, t->w[0], "a second render line (the first is on line %ld)", g->loc.line);
  static const char *const RENDER[] = {
      "integrator", "spp",          "depth",      "spectral",       "wavelengths", "range",
      "photons",    "caustic_photons", "knn",     "radius",         "final_gather", "gather_rays",
      "passes",     "alpha",        "sensor_samples", "seed",       "film",        "sensors",
      "sensor_knn", "photon_portals", "sampler", NULL};
  static const char *const SPECTRAL[] = {"hero", "bins", NULL};
  static const char *const ONOFF[] = {"off", "on", NULL};
  static const char *const SENSORS[] = {"path", "photon", NULL};
  /* The integrators are units registered above the grammar. */
  enum { MAX_INTEGRATORS = 32 };
  const char *integrators[MAX_INTEGRATORS + 1];
  vr_scn_settings_rule rules[MAX_INTEGRATORS];
  size_t ni = 0;
  while (ni < MAX_INTEGRATORS && (integrators[ni] = vr_scn_integrator(ni, &rules[ni]))) ni++;
  integrators[ni] = NULL;
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
  const vr_scn_opt *o;
  if ((st = scn_choice(t, "integrator", integrators, &integ)) || (st = scn_choice(t, "spectral", SPECTRAL, &spectral)) ||
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
  /* The integrator's own rules (spp and wavelengths defaults, aliases). */
  if (rules[integ] && (st = rules[integ](t, g, &spp, &wl))) return st;
  if ((o = scn_get(t, "seed")) && (st = scn_u64(p, o->word, o->val, &g->seed))) return st;
  static const char *const SAMPLERS[] = {"independent", "stratified", "sobol", NULL};
  int sampler = (int)g->sampler;
  if ((st = scn_choice(t, "sampler", SAMPLERS, &sampler))) return st;
  g->sampler = (vr_sampler_kind)sampler;
  /* Fixed bins default to the most wavelengths a path carries: 4 bins of
   * 117 nm cannot follow a lamp's spectrum. */
  if (spectral == VR_SPECTRAL_BINS && !scn_get(t, "wavelengths")) wl = VR_SCENE_MAX_WAVELENGTHS;
  g->photon_portals = pport;
  g->photon_portals_given = scn_get(t, "photon_portals") != NULL;
  g->integrator = (vr_integrator)integ, g->spectral = (vr_spectral_mode)spectral, g->final_gather = fg;
  g->sensors = (vr_sensor_estimator)sensors;
  g->spp = (int)spp, g->max_depth = (int)depth, g->wavelengths = (int)wl, g->photons = (long)photons;
  g->caustic_photons = (long)caustic, g->knn = (int)knn, g->gather_rays = (int)gather;
  g->passes = (int)passes, g->sensor_samples = (int)samples;
  /* Photon sensors read the maps with knn photons unless told otherwise. */
  g->sensor_knn = scn_get(t, "sensor_knn") ? (int)sensor_knn : (int)knn;
  return VR_OK;
}

