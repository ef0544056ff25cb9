/* The 'annual' statement: what the annual study of a scene whose sky is a
 * whole weather file computes (vr/annual.h): the occupied hours, the
 * metrics' thresholds, and the switchable glass with its tint states and
 * the rule that picks one each hour. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scene/scene_parse.h"

/* Two numbers "A,B" into lo, hi, each in [min, max], lo < hi when strict. */
static vr_status pair(const vr_scn_stmt *t, const char *key, double min, double max, bool strict,
                      double *lo, double *hi) {
  const vr_scn_opt *o = scn_get(t, key);
  if (!o) return VR_OK;
  double v[2];
  vr_status st = scn_numbers(t->p, o->word, o->val, false, 2, v);
  if (st) return st;
  if (!(v[0] >= min && v[0] <= max && v[1] >= min && v[1] <= max))
    return scn_fail(t->p, o->word, "\"%s\": each value must be in [%g, %g]", o->word, min, max);
  if (strict ? !(v[0] < v[1]) : !(v[0] <= v[1]))
    return scn_fail(t->p, o->word, "\"%s\": the first value must be %s the second", o->word,
                    strict ? "below" : "at most");
  *lo = v[0], *hi = v[1];
  return VR_OK;
}

/* ase=LX,HOURS: an illuminance above 0 and a number of hours in a year. */
static vr_status ase(const vr_scn_stmt *t, vr_scene_annual *a) {
  const vr_scn_opt *o = scn_get(t, "ase");
  if (!o) return VR_OK;
  double v[2];
  vr_status st = scn_numbers(t->p, o->word, o->val, false, 2, v);
  if (st) return st;
  if (!(v[0] > 0)) return scn_fail(t->p, o->word, "\"%s\": the illuminance must be above 0", o->word);
  if (!(v[1] >= 0 && v[1] <= 8784))
    return scn_fail(t->p, o->word, "\"%s\": the hours must be in [0, 8784]", o->word);
  a->ase_lx = v[0], a->ase_hours = v[1];
  return VR_OK;
}

/* states=S1,S2,... ascending in [0, 1], at most VR_ANNUAL_MAX_STATES. */
static vr_status states(const vr_scn_stmt *t, vr_scene_annual *a) {
  const vr_scn_opt *o = scn_get(t, "states");
  if (!o) return VR_OK;
  char buf[512];
  if (strlen(o->val) >= sizeof buf) return scn_fail(t->p, o->word, "\"%s\": too long", o->word);
  strcpy(buf, o->val);
  int n = 0;
  for (char *save = NULL, *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
    if (n == VR_ANNUAL_MAX_STATES)
      return scn_fail(t->p, o->word, "\"%s\": at most %d states", o->word, VR_ANNUAL_MAX_STATES);
    double v;
    vr_status st = scn_number(t->p, o->word, tok, &v);
    if (st) return st;
    if (!(v >= 0 && v <= 1))
      return scn_fail(t->p, o->word, "\"%s\": tint state %g outside [0, 1]", o->word, v);
    if (n && !(v > a->states[n - 1]))
      return scn_fail(t->p, o->word, "\"%s\": states must increase", o->word);
    a->states[n++] = v;
  }
  if (!n) return scn_fail(t->p, o->word, "\"%s\": no state", o->word);
  a->nstates = n;
  return VR_OK;
}

vr_status scn_annual(vr_scn_stmt *t) {
  static const char *const KEYS[] = {"hours", "da",      "sda",   "udi",            "ase",
                                     "glass", "states",  "control", "max",          "control_sensor",
                                     "workplane", "occupancy", "en17037", "edmed", "shade", "window",
                                     "glare_views", "glare_resolution", NULL};
  static const char *const CONTROLS[] = {"fixed", "illuminance", "sun", "glare", NULL};
  static const char *const YESNO[] = {"no", "yes", NULL};
  vr_scn_parser *p = t->p;
  vr_scene_annual *a = &p->s->annual;
  if (a->given)
    return scn_fail(p, t->w[0], "a second 'annual' line (the first is on line %ld)", a->loc.line);
  t->what = "the annual line";
  vr_status st = scn_options(t, 1, KEYS);
  if (st) return st;
  a->given = true;
  a->loc = scn_loc(p, t->w[0]);
  int control = -1, en = -1;
  double sda_pct = 100 * a->sda_share;
  if ((st = pair(t, "hours", 0, 24, true, &a->from_h, &a->to_h)) ||
      (st = scn_range(t, "da", 0, INFINITY, true, true, &a->da_lx)) ||
      (st = scn_range(t, "sda", 0, 100, true, false, &sda_pct)) ||
      (st = pair(t, "udi", 0, INFINITY, true, &a->udi_lo, &a->udi_hi)) ||
      (st = ase(t, a)) || (st = states(t, a)) ||
      (st = scn_choice(t, "control", CONTROLS, &control)) ||
      (st = scn_range(t, "max", 0, INFINITY, true, true, &a->max)) ||
      (st = scn_choice(t, "en17037", YESNO, &en)) ||
      (st = scn_range(t, "edmed", 0, INFINITY, true, true, &a->edmed_lx)))
    return st;
  a->en17037 = en == 1;
  double res = a->view_resolution;
  if ((st = scn_range(t, "glare_resolution", 8, 512, false, false, &res))) return st;
  if (res != floor(res))
    return scn_fail(p, scn_get(t, "glare_resolution")->word, "\"%s\": a whole number of pixels",
                    scn_get(t, "glare_resolution")->word);
  a->view_resolution = (int)res;
  const vr_scn_opt *gv = scn_get(t, "glare_views");
  if (gv) {
    if (!(p->annual_views = strdup(gv->val))) return scn_nomem(p);
    p->annual_views_loc = scn_loc(p, gv->word);
  } else if (scn_get(t, "glare_resolution"))
    return scn_fail(p, scn_get(t, "glare_resolution")->word,
                    "\"%s\": the images are the glare views': give glare_views=SENSOR,...",
                    scn_get(t, "glare_resolution")->word);
  if (scn_get(t, "edmed") && !a->en17037)
    return scn_fail(p, scn_get(t, "edmed")->word,
                    "\"%s\": the median diffuse illuminance is EN 17037's: give en17037=yes",
                    scn_get(t, "edmed")->word);
  const vr_scn_opt *occ = scn_get(t, "occupancy");
  if (occ) {
    if (scn_get(t, "hours"))
      return scn_fail(p, scn_get(t, "hours")->word,
                      "\"%s\": the occupied hours come from occupancy= on this line; give one "
                      "or the other",
                      scn_get(t, "hours")->word);
    if (!(a->occupancy_path = scn_resolve(p->s, occ->val))) return scn_nomem(p);
  }
  if (control == VR_CONTROL_GLARE && scn_get(t, "max") && !(a->max > 0.184 && a->max <= 1))
    return scn_fail(p, scn_get(t, "max")->word,
                    "\"%s\": a DGPs threshold lies in (0.184, 1] (0.184 is DGPs in the dark)",
                    scn_get(t, "max")->word);
  a->sda_share = sda_pct / 100;
  if (control >= 0) a->control = (vr_annual_control)control;
  const vr_scn_opt *g = scn_get(t, "glass"), *cs = scn_get(t, "control_sensor");
  const vr_scn_opt *wp = scn_get(t, "workplane");
  if (wp) {
    if (!(p->annual_workplane = strdup(wp->val))) return scn_nomem(p);
    p->annual_workplane_loc = scn_loc(p, wp->word);
  }
  if (g) {
    if (!(p->annual_glass = strdup(g->val))) return scn_nomem(p);
    p->annual_glass_loc = scn_loc(p, g->word);
  }
  if (cs) {
    if (!(p->annual_sensor = strdup(cs->val))) return scn_nomem(p);
    p->annual_sensor_loc = scn_loc(p, cs->word);
  }
  const vr_scn_opt *sh = scn_get(t, "shade"), *wi = scn_get(t, "window");
  if (!sh != !wi)
    return scn_fail(p, (sh ? sh : wi)->word,
                    "\"%s\": an operable shade needs both shade=MATERIAL (the shaded system) "
                    "and window=MATERIAL (the glazing it replaces)",
                    (sh ? sh : wi)->word);
  if (sh && g)
    return scn_fail(p, sh->word,
                    "\"%s\": a study has either a switchable glass (glass=) or an operable "
                    "shade (shade=), not both",
                    sh->word);
  if (sh) {
    if (!(p->annual_shade = strdup(sh->val)) || !(p->annual_window = strdup(wi->val)))
      return scn_nomem(p);
    p->annual_shade_loc = scn_loc(p, sh->word);
    p->annual_window_loc = scn_loc(p, wi->word);
  }
  /* Options that need a glass to mean anything are refused without one,
   * rather than ignored. */
  const char *needs_glass[] = {"states", "control", "max", "control_sensor"};
  for (size_t i = 0; !g && i < sizeof needs_glass / sizeof *needs_glass; i++) {
    const vr_scn_opt *o = scn_get(t, needs_glass[i]);
    if (o)
      return scn_fail(p, o->word, "\"%s\" applies to a switchable glass: give glass=MATERIAL",
                      o->word);
  }
  if (cs && a->control == VR_CONTROL_FIXED)
    return scn_fail(p, cs->word, "\"%s\": a fixed glass has no control sensor", cs->word);
  if (scn_get(t, "max") && a->control == VR_CONTROL_FIXED)
    return scn_fail(p, scn_get(t, "max")->word, "\"%s\": a fixed glass has no threshold",
                    scn_get(t, "max")->word);
  return VR_OK;
}

/* *index = the sensor called name, given by the option key at loc. */
static vr_status sensor_named(vr_scn_parser *p, const char *key, const char *name,
                              vr_scene_loc loc, int *index) {
  const vr_scene *s = p->s;
  for (size_t i = 0; i < s->nsensors; i++)
    if (!strcmp(s->sensors[i].name, name)) *index = (int)i;
  if (*index < 0)
    return vr_error_at(p->err, VR_E_PARSE, p->file, loc.line, loc.col,
                       "%s=%s: no sensor of that name", key, name);
  return VR_OK;
}

/* glare_views=NAME,...: point sensors whose normal (the line of sight)
 * is not vertical, since the view's up is +z; each named once. */
static vr_status views_named(vr_scn_parser *p) {
  vr_scene_annual *a = &p->s->annual;
  vr_scene_loc at = p->annual_views_loc;
  char *save = NULL;
  a->nviews = 0;
  for (char *tok = strtok_r(p->annual_views, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
    if (a->nviews == VR_ANNUAL_MAX_VIEWS)
      return vr_error_at(p->err, VR_E_PARSE, p->file, at.line, at.col,
                         "glare_views=: at most %d views", VR_ANNUAL_MAX_VIEWS);
    int k = -1;
    vr_status st = sensor_named(p, "glare_views", tok, at, &k);
    if (st) return st;
    const vr_scene_sensor *sn = &p->s->sensors[k];
    if (sn->grid)
      return vr_error_at(p->err, VR_E_PARSE, p->file, at.line, at.col,
                         "glare_views=%s: a grid; a glare view is a point sensor at the eye, "
                         "its normal the line of sight",
                         tok);
    if (fabs(sn->normal[2]) > 0.99)
      return vr_error_at(p->err, VR_E_PARSE, p->file, at.line, at.col,
                         "glare_views=%s: the sensor looks straight %s; a glare view's up is "
                         "+z, so its line of sight must not be vertical",
                         tok, sn->normal[2] > 0 ? "up" : "down");
    for (int i = 0; i < a->nviews; i++)
      if (a->views[i] == k)
        return vr_error_at(p->err, VR_E_PARSE, p->file, at.line, at.col,
                           "glare_views=: %s named twice", tok);
    a->views[a->nviews++] = k;
  }
  if (!a->nviews)
    return vr_error_at(p->err, VR_E_PARSE, p->file, at.line, at.col, "glare_views=: no sensor named");
  return VR_OK;
}

vr_status scn_annual_finish(vr_scn_parser *p) {
  vr_scene *s = p->s;
  vr_scene_annual *a = &s->annual;
  if (a->given && !s->sky.annual)
    return vr_error_at(p->err, VR_E_PARSE, p->file, a->loc.line, a->loc.col,
                       "an annual study needs a year of skies: 'sky perez weather=FILE' with no "
                       "date= and time=");
  if (s->sky.annual && !s->nsensors)
    return vr_error_at(p->err, VR_E_PARSE, p->file, s->sky.loc.line, s->sky.loc.col,
                       "a year of weather is an annual study of sensors: the scene has none");
  if (p->annual_glass) {
    for (size_t i = 0; i < s->nmaterials; i++)
      if (!strcmp(s->materials[i].name, p->annual_glass)) a->glass = (int)i;
    if (a->glass < 0)
      return vr_error_at(p->err, VR_E_PARSE, p->file, p->annual_glass_loc.line,
                         p->annual_glass_loc.col, "glass=%s: no material of that name",
                         p->annual_glass);
    const vr_scene_material *m = &s->materials[a->glass];
    if (m->source != VR_MATSRC_DB)
      return vr_error_at(p->err, VR_E_PARSE, p->file, p->annual_glass_loc.line,
                         p->annual_glass_loc.col,
                         "glass=%s: a switchable glass is a chromogenic material of the database",
                         p->annual_glass);
  }
  if (p->annual_shade) {
    const char *names[2] = {p->annual_shade, p->annual_window};
    const vr_scene_loc locs[2] = {p->annual_shade_loc, p->annual_window_loc};
    int *idx[2] = {&a->shade, &a->shade_window};
    for (int k = 0; k < 2; k++) {
      for (size_t i = 0; i < s->nmaterials; i++)
        if (!strcmp(s->materials[i].name, names[k])) *idx[k] = (int)i;
      if (*idx[k] < 0)
        return vr_error_at(p->err, VR_E_PARSE, p->file, locs[k].line, locs[k].col,
                           "%s=%s: no material of that name", k ? "window" : "shade", names[k]);
    }
    bool used = false;
    for (size_t i = 0; i < s->nobjects && !used; i++) used = s->objects[i].material == a->shade_window;
    for (size_t i = 0; i < s->nmesh_maps && !used; i++) used = s->mesh_maps[i].material == a->shade_window;
    if (!used)
      return vr_error_at(p->err, VR_E_PARSE, p->file, p->annual_window_loc.line,
                         p->annual_window_loc.col,
                         "window=%s: no object has this material, so the shade would change "
                         "nothing",
                         p->annual_window);
    if (a->shade == a->shade_window)
      return vr_error_at(p->err, VR_E_PARSE, p->file, p->annual_shade_loc.line,
                         p->annual_shade_loc.col, "shade=%s is the window's own material",
                         p->annual_shade);
  }
  vr_status st;
  if (p->annual_workplane) {
    if ((st = sensor_named(p, "workplane", p->annual_workplane, p->annual_workplane_loc,
                           &a->workplane)))
      return st;
    if (!s->sensors[a->workplane].grid)
      return vr_error_at(p->err, VR_E_PARSE, p->file, p->annual_workplane_loc.line,
                         p->annual_workplane_loc.col,
                         "workplane=%s: a point sensor; sDA and ASE are over a work-plane grid "
                         "(IES LM-83): name a 'sensor NAME grid' or 'sensor NAME points' line",
                         p->annual_workplane);
  }
  if (p->annual_views && (st = views_named(p))) return st;
  if (p->annual_sensor &&
      (st = sensor_named(p, "control_sensor", p->annual_sensor, p->annual_sensor_loc,
                         &a->control_sensor)))
    return st;
  if (a->control == VR_CONTROL_GLARE && a->nviews && a->control_sensor >= 0) {
    bool view = false;
    for (int i = 0; i < a->nviews; i++) view |= a->views[i] == a->control_sensor;
    if (!view)
      return vr_error_at(p->err, VR_E_PARSE, p->file, p->annual_sensor_loc.line,
                         p->annual_sensor_loc.col,
                         "control_sensor=%s: with glare views, control=glare keeps their DGP "
                         "within max; name one of glare_views=",
                         p->annual_sensor);
  }
  return VR_OK;
}
