/* Scene statements for what is seen: the camera, material aliases and the
 * shapes (sphere, rect, box, mesh) with their emission and transforms. */
#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scene/scene_parse.h"

/* ---- camera ---- */

/* filter=box|tent|gaussian|mitchell [filter_radius=R] [filter_sigma=S]
 * (vr/filter.h); the radius in pixels, sigma for a gaussian only. */
static vr_status camera_filter(vr_scn_stmt *t, vr_scene_camera *c) {
  vr_scn_parser *p = t->p;
  const vr_scn_opt *o = scn_get(t, "filter"), *r = scn_get(t, "filter_radius"),
                *sg = scn_get(t, "filter_sigma");
  vr_filter_kind kind = VR_FILTER_BOX;
  if (o && !vr_filter_kind_of(o->val, &kind))
    return scn_fail(p, o->word, "\"%s\": expected box, tent, gaussian or mitchell", o->word);
  if ((r || sg) && !o)
    return scn_fail(p, (r ? r : sg)->word, "%s needs filter= (box, tent, gaussian or mitchell)",
                    (r ? r : sg)->word);
  if (sg && kind != VR_FILTER_GAUSSIAN)
    return scn_fail(p, sg->word, "\"%s\": only a gaussian filter has a sigma", sg->word);
  double radius = 0, sigma = 0;
  vr_status st;
  if ((st = scn_range(t, "filter_radius", 0, VR_FILTER_MAX_RADIUS, true, false, &radius)) ||
      (st = scn_range(t, "filter_sigma", 0, VR_FILTER_MAX_RADIUS, true, false, &sigma)))
    return st;
  if (!vr_filter_init(&c->filter, kind, radius, sigma))
    return scn_fail(p, o->word, "\"%s\": not a usable filter", o->word);
  return VR_OK;
}

vr_status scn_camera(vr_scn_stmt *t) {
  vr_scn_parser *p = t->p;
  vr_scene_camera *c = &p->s->camera;
  if (c->given)
    return scn_fail(p, t->w[0], "a second camera (the first is on line %ld)", c->loc.line);
  vr_status st = scn_positional(t, 1, "a model: pinhole, thinlens or fisheye");
  if (st) return st;
  static const char *const PINHOLE[] = {"from",   "to",            "up",           "fov",
                                        "resolution", "exposure", "filter", "filter_radius",
                                        "filter_sigma", NULL};
  static const char *const THINLENS[] = {"from",     "to",       "up",    "fov", "resolution",
                                         "exposure", "aperture", "focus", "filter",
                                         "filter_radius", "filter_sigma", NULL};
  static const char *const FISHEYE[] = {"from",     "to",         "up",     "fov", "resolution",
                                        "exposure", "projection", "filter", "filter_radius",
                                        "filter_sigma", NULL};
  if (!strcmp(t->w[1], "pinhole")) c->model = VR_CAM_PINHOLE, t->what = "a pinhole camera";
  else if (!strcmp(t->w[1], "thinlens")) c->model = VR_CAM_THINLENS, t->what = "a thinlens camera";
  else if (!strcmp(t->w[1], "fisheye")) c->model = VR_CAM_FISHEYE, t->what = "a fisheye camera";
  else return scn_fail(p, t->w[1], "unknown camera model \"%s\" (pinhole, thinlens, fisheye)", t->w[1]);
  if ((st = scn_options(t, 2, c->model == VR_CAM_THINLENS ? THINLENS
                              : c->model == VR_CAM_FISHEYE ? FISHEYE
                                                           : PINHOLE)))
    return st;
  c->given = true;
  c->loc = scn_loc(p, t->w[0]);
  const vr_scn_opt *from, *to, *o;
  if ((st = scn_need(t, "from", &from)) || (st = scn_need(t, "to", &to)) || (st = scn_point(t, from, c->from)) ||
      (st = scn_point(t, to, c->to)))
    return st;
  double view[3] = {c->to[0] - c->from[0], c->to[1] - c->from[1], c->to[2] - c->from[2]};
  double dist = sqrt(vr_dot3(view, view));
  if (!(dist > 0) || !isfinite(dist))
    return scn_fail(p, to->word, "\"%s\": the camera looks from and to the same point", to->word);
  if ((o = scn_get(t, "up")) && (st = scn_direction(p, o->word, o->val, c->up))) return st;
  double side[3];
  vr_cross3(c->up, view, side);
  if (!(sqrt(vr_dot3(side, side)) > 1e-9 * dist))
    return scn_fail(p, o ? o->word : to->word, "up (%g,%g,%g) is parallel to the view direction%s",
                    c->up[0], c->up[1], c->up[2], o ? "" : ": give up=");
  if (c->model == VR_CAM_FISHEYE) {
    static const char *const PROJ[] = {"equisolid", "angular", NULL};
    int proj = 0;
    if ((st = scn_choice(t, "projection", PROJ, &proj))) return st;
    c->projection = (vr_fisheye_projection)proj;
    c->fov_deg = 180;
    if ((st = scn_range(t, "fov", 0, 360, true, false, &c->fov_deg))) return st;
  } else if ((st = scn_range(t, "fov", 0, 180, true, true, &c->fov_deg))) {
    return st;
  }
  if ((st = scn_range(t, "exposure", -HUGE_VAL, HUGE_VAL, false, false, &c->exposure_ev)))
    return st;
  if ((o = scn_get(t, "resolution"))) {
    long long wh[2];
    if ((st = scn_ints(p, o->word, o->val, 'x', 2, 1, 16384, wh))) return st;
    c->width = (int)wh[0], c->height = (int)wh[1];
  }
  if ((o = scn_get(t, "aperture"))) {
    if ((st = scn_length(p, o->word, o->val, &c->aperture_m))) return st;
    if (c->aperture_m < 0) return scn_fail(p, o->word, "\"%s\": must not be negative", o->word);
  }
  c->focus_m = dist;
  if ((o = scn_get(t, "focus")) && (st = scn_positive_length(t, o, &c->focus_m))) return st;
  return camera_filter(t, c);
}

/* ---- materials ---- */

vr_status scn_material(vr_scn_stmt *t) {
  vr_scn_parser *p = t->p;
  vr_scene *s = p->s;
  vr_status st = scn_positional(t, 2, "a name and a source: db:NAME, lambert, pbr, bsdf or black");
  if (st) return st;
  for (size_t i = 0; i < s->nmaterials; i++)
    if (!strcmp(s->materials[i].name, t->w[1]))
      return scn_fail(p, t->w[1], "material \"%s\" is defined twice (first on line %ld)", t->w[1],
                      s->materials[i].loc.line);
  vr_scene_material *m = scn_grow((void **)&s->materials, &s->nmaterials, sizeof *m);
  if (!m || !(m->name = strdup(t->w[1]))) return scn_nomem(p);
  m->loc = scn_loc(p, t->w[0]);
  m->roughness = m->thickness_m = m->state = m->charge_mC_cm2 = m->temperature_K = NAN;
  m->alpha_cutoff = 0.5, m->tile[0] = m->tile[1] = 1, m->normal_scale = 1;
  m->bsdf_up[0] = m->bsdf_up[1] = m->bsdf_up[2] = NAN;
  const char *src = t->w[2];
  t->what = "a material";
  bool pbr = !strcmp(src, "pbr");
  if (pbr) t->what = "a pbr material (glTF's factors)";
  if (!strcmp(src, "lambert") || pbr) {
    static const char *const LAMBERT[] = {"reflectance", "color",        "rgb",  "space",
                                          "texture",     "colorspace",   "alpha", "alpha_cutoff",
                                          "tile",        "normal_map",   "normal_scale", NULL};
    static const char *const PBR[] = {"reflectance", "color",      "rgb",          "space",
                                      "texture",     "colorspace", "alpha",        "alpha_cutoff",
                                      "tile",        "normal_map", "normal_scale", "metallic",
                                      "roughness",   "metallic_roughness",         NULL};
    m->source = VR_MATSRC_LAMBERT_CONST;
    const vr_scn_opt *o;
    if ((st = scn_options(t, 3, pbr ? PBR : LAMBERT)) || (pbr && (st = scn_pbr(t, m))) ||
        (st = scn_texture(t, m)))
      return st;
    const vr_scn_opt *colour = scn_get(t, "color") ? scn_get(t, "color") : scn_get(t, "rgb");
    if (colour && (o = scn_get(t, "reflectance")))
      return scn_fail(p, scn_later(o, colour), "give reflectance= or a colour, not both");
    if (colour) return scn_colour(t, &m->reflectance_spectrum);
    if ((o = scn_get(t, "space"))) return scn_fail(p, o->word, "\"%s\": space= goes with rgb=", o->word);
    /* A texture alone: its colours are the reflectance (a factor of 1). */
    if (m->texture && !scn_get(t, "reflectance")) return m->reflectance = 1, VR_OK;
    if ((st = scn_need(t, "reflectance", &o))) return st;
    if (o->val[0] != '[') return scn_range(t, "reflectance", 0, 1, false, false, &m->reflectance);
    /* An inline reflectance spectrum, each value in [0, 1]. */
    if ((st = scn_inline_check(p, o->word, o->val, 1.0))) return st;
    return (m->reflectance_spectrum = strdup(o->val)) ? VR_OK : scn_nomem(p);
  }
  if (!strcmp(src, "black")) {
    static const char *const NONE[] = {NULL};
    m->source = VR_MATSRC_BLACK;
    return scn_options(t, 3, NONE);
  }
  if (!strcmp(src, "bsdf")) {
    /* A measured or simulated layer as WINDOW, the IGSDB or genBSDF write it. */
    static const char *const BSDF[] = {"file", "up", NULL};
    const vr_scn_opt *f, *up;
    t->what = "a BSDF XML material";
    m->source = VR_MATSRC_BSDF_XML;
    if ((st = scn_options(t, 3, BSDF)) || (st = scn_need(t, "file", &f))) return st;
    if (!(m->bsdf_file = scn_resolve(s, f->val))) return scn_nomem(p);
    if ((up = scn_get(t, "up")) && (st = scn_direction(p, up->word, up->val, m->bsdf_up))) return st;
    return VR_OK;
  }
  if (strncmp(src, "db:", 3))
    return scn_fail(p, src, "unknown material source \"%s\" (db:NAME, lambert, pbr, bsdf, black)",
                    src);
  if (!src[3]) return scn_fail(p, src, "db: needs a material name");
  static const char *const DB[] = {"roughness", "thickness",   "model",   "state",
                                   "charge",    "temperature", "coating", "texture",
                                   "extrapolate", NULL};
  m->source = VR_MATSRC_DB;
  if (!(m->db_name = strdup(src + 3))) return scn_nomem(p);
  if ((st = scn_options(t, 3, DB)) || (st = scn_range(t, "roughness", 0, 1, false, false, &m->roughness)) ||
      (st = scn_range(t, "state", 0, 1, false, false, &m->state)))
    return st;
  const vr_scn_opt *o, *state = scn_get(t, "state");
  if ((o = scn_get(t, "thickness"))) {
    /* A pane's thickness: its unit is required (a bare 3 would be 3 m of
     * glass), and it must be a pane's: 0.01-200 mm. */
    size_t n = strlen(o->val);
    if (n && (isdigit((unsigned char)o->val[n - 1]) || o->val[n - 1] == '.'))
      return scn_fail(p, o->word,
                      "\"%s\": a pane's thickness needs its unit (thickness=%smm or "
                      "thickness=%sm; a bare number would be metres)",
                      o->word, o->val, o->val);
    if ((st = scn_positive_length(t, o, &m->thickness_m))) return st;
    if (m->thickness_m < 1e-5 || m->thickness_m > 0.2)
      return scn_fail(p, o->word,
                      "\"%s\": a pane of %g mm is outside 0.01-200 mm (a unit slip?)", o->word,
                      m->thickness_m * 1e3);
  }
  static const char *const MODELS[] = {"thin", "interfaces", NULL};
  int model = -1;
  if ((st = scn_choice(t, "model", MODELS, &model))) return st;
  if (model >= 0) m->pane = model == 0 ? VR_PANE_THIN : VR_PANE_INTERFACES;
  if ((o = scn_get(t, "charge"))) {
    if (state) return scn_fail(p, scn_later(o, state), "give state= or charge=, not both");
    double q;
    size_t n = strlen(o->val), unit = strlen("mC/cm2");
    char num[64];
    /* The unit is optional: "charge=12" or "charge=12mC/cm2". */
    if (n > unit && !strcmp(o->val + n - unit, "mC/cm2") && n - unit < sizeof num) {
      memcpy(num, o->val, n - unit);
      num[n - unit] = '\0';
      st = scn_number(p, o->word, num, &q);
    } else {
      st = scn_number(p, o->word, o->val, &q);
    }
    if (st) return st;
    if (q < 0) return scn_fail(p, o->word, "\"%s\": a charge must not be negative", o->word);
    m->charge_mC_cm2 = q;
  }
  if ((o = scn_get(t, "temperature"))) {
    size_t n = strlen(o->val);
    char num[64];
    if (n > 1 && o->val[n - 1] == 'K' && n - 1 < sizeof num) { /* "temperature=300K" */
      memcpy(num, o->val, n - 1);
      num[n - 1] = '\0';
      st = scn_number(p, o->word, num, &m->temperature_K);
    } else {
      st = scn_number(p, o->word, o->val, &m->temperature_K);
    }
    if (st) return st;
    if (!(m->temperature_K > 0))
      return scn_fail(p, o->word, "\"%s\": a temperature in kelvin must be positive", o->word);
  }
  static const char *const YESNO[] = {"no", "yes", NULL};
  int ex = -1;
  if ((st = scn_choice(t, "extrapolate", YESNO, &ex))) return st;
  m->extrapolate = ex == 1;
  if ((o = scn_get(t, "texture"))) {
    if (strcmp(o->val, "none"))
      return scn_fail(p, o->word,
                      "\"%s\": on a database material, texture= can only be none (render the "
                      "material's mean spectrum instead of the spectral texture it records)",
                      o->word);
    m->texture_off = true;
  }
  if ((o = scn_get(t, "coating"))) {
    if (strncmp(o->val, "db:", 3) || !o->val[3])
      return scn_fail(p, o->word, "\"%s\": a coating is db:NAME", o->word);
    if (!(m->coating_db = strdup(o->val + 3))) return scn_nomem(p);
  }
  return VR_OK;
}

/* ---- objects ---- */

#define OBJECT_OPTIONS "material", "name", "emission", "emission_spectrum", "translate", "rotate", "scale", "texels", "outside"

/* A stable in-plane direction for a rectangle without up=: world up (+z)
 * for walls and anything tilted, north (+y) when the normal is within
 * about 2.6 degrees of vertical. */
static void default_up(const double n[3], double up[3]) {
  static const double Z[3] = {0, 0, 1}, Y[3] = {0, 1, 0};
  memcpy(up, fabs(n[2]) < 0.999 ? Z : Y, 3 * sizeof *up);
}

static vr_status rect(vr_scn_stmt *t, vr_scene_object *ob) {
  vr_scn_parser *p = t->p;
  const vr_scn_opt *c, *n, *size, *up;
  vr_status st;
  if ((st = scn_need(t, "center", &c)) || (st = scn_need(t, "normal", &n)) || (st = scn_need(t, "size", &size)) ||
      (st = scn_point(t, c, ob->center)) || (st = scn_direction(p, n->word, n->val, ob->normal)) ||
      (st = scn_numbers(p, size->word, size->val, true, 2, ob->size)))
    return st;
  if (!(ob->size[0] > 0 && ob->size[1] > 0))
    return scn_fail(p, size->word, "\"%s\": a rectangle's width and height must be positive", size->word);
  if ((up = scn_get(t, "up"))) {
    if ((st = scn_direction(p, up->word, up->val, ob->up))) return st;
  } else {
    default_up(ob->normal, ob->up);
  }
  /* Keep only the in-plane part of the hint, so up is the rectangle's v axis. */
  double d = vr_dot3(ob->up, ob->normal), len = 0;
  for (int i = 0; i < 3; i++) ob->up[i] -= d * ob->normal[i], len += ob->up[i] * ob->up[i];
  len = sqrt(len);
  if (!(len > 1e-9))
    return scn_fail(p, up ? up->word : t->w[0], "\"%s\": up is parallel to the normal", up ? up->word : "up");
  for (int i = 0; i < 3; i++) ob->up[i] /= len;
  return VR_OK;
}

/* portal center=X,Y,Z normal=X,Y,Z size=W,H [up=X,Y,Z]: a rectangle the
 * sky's light enters through (a window, an opening), used only to aim the
 * sky's next-event estimation; it is not geometry. */
vr_status scn_portal(vr_scn_stmt *t) {
  vr_scn_parser *p = t->p;
  vr_scene *s = p->s;
  static const char *const PORTAL[] = {"center", "normal", "size", "up", NULL};
  t->what = "a portal";
  vr_status st = scn_options(t, 1, PORTAL);
  if (st) return st;
  if (s->nportals >= VR_SCENE_MAX_PORTALS)
    return scn_fail(p, t->w[0], "more than %d portals (merge neighbouring windows into one)",
                    VR_SCENE_MAX_PORTALS);
  vr_scene_object ob;
  memset(&ob, 0, sizeof ob);
  if ((st = rect(t, &ob))) return st;
  vr_scene_portal *q = scn_grow((void **)&s->portals, &s->nportals, sizeof *q);
  if (!q) return scn_nomem(p);
  q->loc = scn_loc(p, t->w[0]);
  double u[3];
  vr_cross3(ob.up, ob.normal, u); /* unit: up is in-plane and unit */
  for (int i = 0; i < 3; i++) {
    q->u[i] = ob.size[0] * u[i];
    q->v[i] = ob.size[1] * ob.up[i];
    q->corner[i] = ob.center[i] - 0.5 * (q->u[i] + q->v[i]);
  }
  return VR_OK;
}

/* units=mm|cm|m|in|ft (to metres) and up=y|z (y up turned to the
 * renderer's z up: +90 degrees about x, so +y goes to +z and +z to -y). */
static vr_status mesh_frame(vr_scn_stmt *t, vr_xform *x, bool *units_given) {
  static const char *const UNITS[] = {"m", "mm", "cm", "in", "ft", NULL};
  static const char *const SCALE[] = {"1", "0.001", "0.01", "0.0254", "0.3048"};
  static const char *const UP[] = {"z", "y", NULL};
  int unit = -1, up = -1;
  vr_status st;
  if ((st = scn_choice(t, "units", UNITS, &unit)) || (st = scn_choice(t, "up", UP, &up))) return st;
  *units_given = unit >= 0;
  if (up == 1 && (st = scn_transform(t->p, scn_get(t, "up")->word, "rotate", "1,0,0,90", x))) return st;
  if (unit > 0 && (st = scn_transform(t->p, scn_get(t, "units")->word, "scale", SCALE[unit], x)))
    return st;
  return VR_OK;
}

vr_status scn_object(vr_scn_stmt *t, vr_shape_kind kind) {
  vr_scn_parser *p = t->p;
  vr_scene *s = p->s;
  static const char *const SPHERE[] = {"center", "radius", OBJECT_OPTIONS, NULL};
  static const char *const RECT[] = {"center", "normal", "size", "up", OBJECT_OPTIONS, NULL};
  static const char *const BOX[] = {"min", "max", OBJECT_OPTIONS, NULL};
  static const char *const MESH[] = {OBJECT_OPTIONS, "material.*", "materials", "units", "up", NULL};
  static const char *const *const ALLOWED[] = {SPHERE, RECT, BOX, MESH};
  static const char *const WHAT[] = {"a sphere", "a rectangle", "a box", "a mesh"};
  t->what = WHAT[kind];
  size_t npos = kind == VR_SHAPE_MESH ? 1 : 0;
  vr_status st = npos ? scn_positional(t, 1, "a file (OBJ, PLY or glTF)") : VR_OK;
  if (st || (st = scn_options(t, 1 + npos, ALLOWED[kind]))) return st;
  /* The alias slot first, so that both arrays always cover every object. */
  char **alias = realloc(p->alias, (s->nobjects + 1) * sizeof *alias);
  if (!alias) return scn_nomem(p);
  p->alias = alias;
  alias[s->nobjects] = NULL;
  p->nalias = s->nobjects + 1;
  vr_scene_loc *aloc = realloc(p->alias_loc, (s->nobjects + 1) * sizeof *aloc);
  if (!aloc) return scn_nomem(p);
  p->alias_loc = aloc;
  vr_scene_object *ob = scn_grow((void **)&s->objects, &s->nobjects, sizeof *ob);
  if (!ob) return scn_nomem(p);
  ob->shape = kind;
  ob->loc = scn_loc(p, t->w[0]);
  ob->material = -1;
  ob->mesh_material = -1;
  ob->texels[0] = ob->texels[1] = 16;
  vr_xform_identity(&ob->xform);
  const vr_scn_opt *o, *o2;
  switch (kind) {
  case VR_SHAPE_SPHERE:
    if ((st = scn_need(t, "center", &o)) || (st = scn_need(t, "radius", &o2)) || (st = scn_point(t, o, ob->center)) ||
        (st = scn_positive_length(t, o2, &ob->radius)))
      return st;
    break;
  case VR_SHAPE_RECT:
    if ((st = rect(t, ob))) return st;
    break;
  case VR_SHAPE_BOX:
    if ((st = scn_need(t, "min", &o)) || (st = scn_need(t, "max", &o2)) || (st = scn_point(t, o, ob->bmin)) ||
        (st = scn_point(t, o2, ob->bmax)))
      return st;
    for (int i = 0; i < 3; i++)
      if (!(ob->bmax[i] > ob->bmin[i]))
        return scn_fail(p, o2->word, "\"%s\": a box's max must exceed its min on every axis", o2->word);
    break;
  case VR_SHAPE_MESH:
    if (!(ob->mesh_path = scn_resolve(s, t->w[1]))) return scn_nomem(p);
    break;
  }
  /* A mesh may leave material= out: its file's materials are used. */
  o = scn_get(t, "material");
  if (!o && kind != VR_SHAPE_MESH && (st = scn_need(t, "material", &o))) return st;
  if (o && !(alias[s->nobjects - 1] = strdup(o->val))) return scn_nomem(p);
  aloc[s->nobjects - 1] = scn_loc(p, o ? o->word : t->w[0]);
  for (size_t i = 0; i < t->no; i++) {
    const vr_scn_opt *m = &t->o[i];
    if (m->klen <= 9 || strncmp(m->word, "material.", 9)) continue;
    vr_scn_mesh_map *map = scn_grow((void **)&p->maps, &p->nmaps, sizeof *map);
    if (!map) return scn_nomem(p);
    map->object = s->nobjects - 1;
    map->loc = scn_loc(p, m->word);
    if (!(map->pattern = strndup(m->word + 9, m->klen - 9)) || !(map->alias = strdup(m->val)))
      return scn_nomem(p);
  }
  if (kind == VR_SHAPE_MESH && (o = scn_get(t, "materials")) && (st = scn_map_file(t, o, s->nobjects - 1)))
    return st;
  if ((o = scn_get(t, "name")) && !(ob->name = strdup(o->val))) return scn_nomem(p);
  static const vr_light_unit EMISSION[] = {VR_UNIT_CD_M2, VR_UNIT_W_M2_SR, VR_UNIT_NONE};
  if ((o = scn_get(t, "emission")) &&
      (st = scn_quantity(p, o->word, o->val, EMISSION, VR_UNIT_NONE, "an emission", &ob->emission)))
    return st;
  if ((st = scn_spectrum_opt(t, "emission_spectrum", &ob->emission_spectrum))) return st;
  static const char *const YESNO[] = {"no", "yes", NULL};
  int outside = 0;
  if ((st = scn_choice(t, "outside", YESNO, &outside))) return st;
  ob->outside = outside == 1;
  if ((o = scn_get(t, "texels"))) {
    long long n[2];
    if ((st = scn_ints(p, o->word, o->val, ',', 2, 1, 4096, n))) return st;
    ob->texels[0] = (int)n[0], ob->texels[1] = (int)n[1];
  }
  /* A mesh file's units and up axis come before the transforms written. */
  if (kind == VR_SHAPE_MESH && (st = mesh_frame(t, &ob->xform, &ob->units_given))) return st;
  for (size_t i = 0; i < t->no; i++) {
    char key[16];
    if (!scn_is_transform(t->o[i].word, t->o[i].klen)) continue;
    memcpy(key, t->o[i].word, t->o[i].klen);
    key[t->o[i].klen] = '\0';
    if ((st = scn_transform(p, t->o[i].word, key, t->o[i].val, &ob->xform))) return st;
  }
  return VR_OK;
}

