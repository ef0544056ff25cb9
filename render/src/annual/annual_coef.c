/* The annual study's renders (vr/annual.h): the scene with its sky and
 * lights replaced by a uniform unit sky binned by Tregenza patch, or by one
 * sun at a patch centre, sensors only, path sensors; once per tint state of
 * the switchable glass, and once more with a photochromic glass left to its
 * UV exposure for its UV coefficients. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "annual/annual_internal.h"
#include "vr/filter.h"

/* The scene with its sky and lights taken out and the glass in `state`
 * (NAN: left to its UV exposure); the materials are a copy. */
typedef struct vr_annual_variant {
  vr_scene s;
  vr_scene_light sun;
  vr_scene_material *mats;
} vr_annual_variant;

static vr_status make_variant(const vr_annual_job *j, double state, vr_annual_variant *v, vr_error *err) {
  const vr_scene *s = j->s;
  v->s = *s;
  v->s.camera.given = false;
  v->s.settings.sensors = VR_SENSORS_PATH;
  v->s.nlights = 0;
  v->s.lights = NULL;
  v->s.nportals = 0; /* portals need the scene's sky; the unit sky samples itself */
  v->s.portals = NULL;
  memset(&v->s.sky, 0, sizeof v->s.sky);
  v->mats = malloc((s->nmaterials + 1) * sizeof *v->mats);
  if (!v->mats) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  /* A scene without a material line has none (and a NULL array). */
  if (s->nmaterials) memcpy(v->mats, s->materials, s->nmaterials * sizeof *v->mats);
  if (s->annual.glass >= 0) {
    v->mats[s->annual.glass].state = state;
    v->mats[s->annual.glass].charge_mC_cm2 = NAN;
  }
  /* An operable shade drawn: the window's objects take the shade's
   * material. */
  if (s->annual.shade >= 0 && state == 1) v->mats[s->annual.shade_window] = s->materials[s->annual.shade];
  v->s.materials = v->mats;
  return VR_OK;
}

static void sky_of(const vr_scene *s, vr_scene_sky *k) {
  /* A uniform sky of 1 cd/m2 (CIE type 5) over a ground of luminance
   * 1 cd/m2 (reflectance 1 under E_h = pi lx), the scene's sky spectrum. */
  k->present = true;
  k->cie_type = 5;
  k->level.value = 1.0;
  k->level.unit = VR_UNIT_CD_M2;
  k->spectrum = s->sky.spectrum;
  k->ground_reflectance = 1.0;
  k->sun_direction[2] = 1;
  k->loc = s->sky.loc;
}

static void sun_of(const vr_annual_job *j, int k, vr_annual_variant *v) {
  v->sun = *j->sun;
  vr_sky_patch_centre(k, v->sun.direction);
  v->sun.amount.value = SUN_LX;
  v->sun.amount.unit = VR_UNIT_LX;
  v->sun.from_sky = false;
  v->s.lights = &v->sun;
  v->s.nlights = 1;
}

/* One render of the variant: its sensors (their readings checked), or
 * with `view` its camera only, the image's sky-patch coefficients kept. */
static vr_status render_as(vr_annual_job *j, const vr_annual_variant *v, bool view,
                           vr_render_result **res, vr_error *err) {
  vr_render_options ro = *j->o;
  ro.no_camera = !view;
  if (view) {
    ro.pixel_patches = true;
    ro.film_without_bins = true;
    ro.target_error = 0, ro.time_limit_s = 0, ro.max_spp = 0, ro.denoise = false;
  }
  /* The first render says what the passes decide; the others decide the
   * same, and annual.c reports them a state at a time. */
  if (j->res->renders++ > 0) ro.log = NULL, ro.progress = NULL;
  vr_status st = vr_render_scene(&v->s, j->db, &ro, res, err);
  if (!st && !view && (*res)->nreadings != j->npoints) {
    st = vr_error_set(err, VR_E_NUMERIC, "annual: a render gave %zu readings, not %zu",
                      (*res)->nreadings, j->npoints);
    vr_render_result_destroy(*res);
    *res = NULL;
  }
  return st;
}

static vr_status render(vr_annual_job *j, const vr_annual_variant *v, vr_render_result **res, vr_error *err) {
  return render_as(j, v, false, res, err);
}

/* The points' names, places and normals, as the renderer lays them out. */
static vr_status fill_points(vr_annual_job *j, const vr_render_result *r, vr_error *err) {
  const vr_scene *s = j->s;
  vr_annual_result *res = j->res;
  size_t nchars = 1;
  for (size_t i = 0; i < s->nsensors; i++) nchars += strlen(s->sensors[i].name) + 1;
  if (!(res->names = malloc(nchars))) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  size_t *at = calloc(s->nsensors + 1, sizeof *at), off = 0;
  if (!at) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  for (size_t i = 0; i < s->nsensors; i++) {
    strcpy(res->names + off, s->sensors[i].name);
    at[i] = off;
    off += strlen(s->sensors[i].name) + 1;
  }
  bool grids = vr_scene_has_grid(s);
  for (size_t p = 0; p < j->npoints; p++) {
    const vr_sensor_reading *rd = &r->readings[p];
    vr_annual_point *pt = &res->points[p];
    for (size_t i = 0; i < s->nsensors; i++)
      if (rd->sensor && !strcmp(rd->sensor, s->sensors[i].name)) {
        pt->sensor = res->names + at[i];
        memcpy(pt->normal, s->sensors[i].pts ? s->sensors[i].pts + 6 * (size_t)rd->i + 3
                                              : s->sensors[i].normal,
               sizeof pt->normal);
        /* The work plane (IES LM-83): the grid named, else every grid. */
        pt->workplane = s->annual.workplane >= 0 ? (int)i == s->annual.workplane
                                                 : !grids || s->sensors[i].grid;
      }
    pt->i = rd->i, pt->j = rd->j;
    memcpy(pt->position, rd->position, sizeof pt->position);
  }
  free(at);
  return VR_OK;
}

/* One render per sun patch the year visits (the variant's sky taken
 * out), each result handed to take with its patch. */
typedef void (*vr_sun_take)(void *ctx, int k, const vr_render_result *r);

static vr_status each_sun(vr_annual_job *j, vr_annual_variant *v, bool view, vr_sun_take take,
                          void *ctx, vr_error *err) {
  memset(&v->s.sky, 0, sizeof v->s.sky);
  for (int k = 0; k < VR_SKY_PATCHES; k++) {
    if (!j->need[k]) continue;
    sun_of(j, k, v);
    vr_render_result *r = NULL;
    vr_status st = render_as(j, v, view, &r, err);
    if (st) return st;
    take(ctx, k, r);
    vr_render_result_destroy(r);
  }
  return VR_OK;
}

typedef struct vr_dc_take_ctx {
  vr_dc_set *d;
  size_t np;
} vr_dc_take_ctx;

/* The sun's light at every point: the reading without what the scene's
 * emitters gave (a daylight study counts daylight only; the sky's
 * coefficients, by patch, leave them out too). */
static void dc_take(void *ctx, int k, const vr_render_result *r) {
  const vr_dc_take_ctx *c = ctx;
  for (size_t p = 0; p < c->np; p++) {
    const vr_sensor_reading *rd = &r->readings[p];
    c->d->sun_total[p * VR_SKY_PATCHES + (size_t)k] =
        (rd->illuminance_lx - rd->part_lx[VR_PART_ELECTRIC]) / SUN_LX;
    c->d->sun_direct[p * VR_SKY_PATCHES + (size_t)k] = r->readings[p].part_lx[VR_PART_SUN] / SUN_LX;
  }
}

vr_status annual_dc(vr_annual_job *j, double state, vr_dc_set *d, vr_error *err) {
  size_t np = j->npoints;
  memset(d, 0, sizeof *d);
  d->sky = calloc(np * NPATCH + 1, sizeof *d->sky);
  d->sun_total = calloc(np * VR_SKY_PATCHES + 1, sizeof *d->sun_total);
  d->sun_direct = calloc(np * VR_SKY_PATCHES + 1, sizeof *d->sun_direct);
  if (!d->sky || !d->sun_total || !d->sun_direct)
    return vr_error_set(err, VR_E_NOMEM, "out of memory for daylight coefficients");
  vr_annual_variant v;
  vr_status st = make_variant(j, state, &v, err);
  if (st) return st;
  sky_of(j->s, &v.s.sky);
  vr_render_result *r = NULL;
  if (!(st = render(j, &v, &r, err))) {
    memcpy(d->sky, r->sky_patch_lx, np * NPATCH * sizeof *d->sky);
    if (!j->res->names) st = fill_points(j, r, err);
    vr_render_result_destroy(r);
  }
  vr_dc_take_ctx c = {d, np};
  if (!st) st = each_sun(j, &v, false, dc_take, &c, err);
  free(v.mats);
  return st;
}

/* The variant as one glare view's render: a 180-degree equisolid fisheye
 * at the view sensor looking along its normal, up +z, box pixels; no
 * sensors; the path integrator (the only one that knows the patch a
 * pixel's light came from). */
static void as_view(const vr_annual_job *j, const vr_glare_view *gv, vr_annual_variant *v) {
  vr_scene_camera *c = &v->s.camera;
  memset(c, 0, sizeof *c);
  c->model = VR_CAM_FISHEYE;
  c->projection = VR_FISHEYE_EQUISOLID;
  c->fov_deg = 180;
  c->width = c->height = gv->cam.width;
  memcpy(c->from, gv->cam.from, sizeof c->from);
  memcpy(c->to, gv->cam.to, sizeof c->to);
  memcpy(c->up, gv->cam.up, sizeof c->up);
  vr_filter_init(&c->filter, VR_FILTER_BOX, 0.5, 0);
  c->given = true;
  c->loc = j->s->annual.loc;
  v->s.nsensors = 0;
  v->s.sensors = NULL;
  v->s.settings.integrator = VR_INT_PATH;
}

typedef struct vr_view_take_ctx {
  const vr_glare_view *gv;
  double *sun;
} vr_view_take_ctx;

/* The sun's own light in the picture (its slot after the sky's patches
 * and the ground's): not an emitter's, which a daylight study leaves out. */
static void view_take(void *ctx, int k, const vr_render_result *r) {
  const vr_view_take_ctx *c = ctx;
  for (size_t i = 0; i < c->gv->npx; i++)
    c->sun[i * VR_SKY_PATCHES + (size_t)k] =
        r->pixel_patch_Y[c->gv->pixel[i] * (NPATCH + 1) + NPATCH] / SUN_LX;
}

vr_status annual_view_dc(vr_annual_job *j, double state, int si, vr_glare_set *g, vr_error *err) {
  vr_annual_variant v;
  vr_status st = make_variant(j, state, &v, err);
  for (int i = 0; !st && i < g->n; i++) {
    vr_glare_view *gv = &g->v[i];
    gv->sky[si] = calloc(gv->npx * NPATCH + 1, sizeof *gv->sky[si]);
    gv->sun[si] = calloc(gv->npx * VR_SKY_PATCHES + 1, sizeof *gv->sun[si]);
    if (!gv->sky[si] || !gv->sun[si]) {
      st = vr_error_set(err, VR_E_NOMEM, "out of memory for a glare view's coefficients");
      break;
    }
    as_view(j, gv, &v);
    sky_of(j->s, &v.s.sky);
    vr_render_result *r = NULL;
    if ((st = render_as(j, &v, true, &r, err))) break;
    for (size_t p = 0; p < gv->npx; p++)
      memcpy(gv->sky[si] + p * NPATCH, r->pixel_patch_Y + gv->pixel[p] * (NPATCH + 1),
             NPATCH * sizeof *gv->sky[si]);
    vr_render_result_destroy(r);
    vr_view_take_ctx c = {gv, gv->sun[si]};
    st = each_sun(j, &v, true, view_take, &c, err);
  }
  free(v.mats);
  return st;
}

vr_status annual_df(vr_annual_job *j, double state, double *df_pct, vr_error *err) {
  vr_annual_variant v;
  vr_status st = make_variant(j, state, &v, err);
  if (st) return st;
  /* The CIE standard overcast sky of Moon & Spencer (1942), L(a) = L_z (1 +
   * 2 sin a) / 3 (the traditional overcast sky, vr/sky.h), over the
   * scene's ground; the daylight factor is the sensors' own (SC + ERC +
   * IRC over the sky's horizontal illuminance), the scene's portals aiming
   * the sky's samples. */
  v.s.sky.present = true;
  v.s.sky.cie_type = 0;
  v.s.sky.level.value = 10000;
  v.s.sky.level.unit = VR_UNIT_LX;
  v.s.sky.spectrum = j->s->sky.spectrum;
  v.s.sky.ground_reflectance = j->s->sky.ground_reflectance;
  v.s.sky.sun_direction[2] = 1;
  v.s.sky.loc = j->s->sky.loc;
  v.s.nportals = j->s->nportals;
  v.s.portals = j->s->portals;
  vr_render_result *r = NULL;
  if (!(st = render(j, &v, &r, err))) {
    for (size_t p = 0; p < j->npoints; p++) df_pct[p] = r->readings[p].df_pct;
    vr_render_result_destroy(r);
  }
  free(v.mats);
  return st;
}

/* The texels of the glass's objects in a render's photochromic tables. */
static size_t glass_texels(const vr_annual_job *j, const vr_render_result *r, size_t *idx) {
  size_t n = 0;
  for (size_t t = 0; t < r->photochromic_texels; t++)
    if (j->s->objects[r->photochromic_object[t]].material == j->s->annual.glass) {
      if (idx) idx[n] = t;
      n++;
    }
  return n;
}

typedef struct vr_uv_take_ctx {
  vr_uv_set *u;
  const size_t *idx;
} vr_uv_take_ctx;

static void uv_take(void *ctx, int k, const vr_render_result *r) {
  const vr_uv_take_ctx *c = ctx;
  for (size_t t = 0; t < c->u->ntexels; t++)
    c->u->sun[t * VR_SKY_PATCHES + (size_t)k] = r->photochromic_uv[c->idx[t]] / SUN_LX;
}

vr_status annual_uv(vr_annual_job *j, vr_uv_set *u, vr_error *err) {
  memset(u, 0, sizeof *u);
  vr_annual_variant v;
  vr_status st = make_variant(j, NAN, &v, err);
  if (st) return st;
  /* The UV pass has its own samples; the sensors here are not used.  Only
   * the UV irradiances are kept: the states these unit skies and suns
   * would give are never used, so the glass's fitted domain does not
   * apply to them (year() checks each hour's UV). */
  v.s.settings.sensor_samples = 1;
  if (j->s->annual.glass >= 0) v.mats[j->s->annual.glass].extrapolate = true;
  sky_of(j->s, &v.s.sky);
  vr_render_result *r = NULL;
  size_t *idx = NULL;
  if ((st = render(j, &v, &r, err))) goto done;
  u->ntexels = glass_texels(j, r, NULL);
  idx = calloc(u->ntexels + 1, sizeof *idx);
  u->sky = calloc(u->ntexels * NPATCH + 1, sizeof *u->sky);
  u->sun = calloc(u->ntexels * VR_SKY_PATCHES + 1, sizeof *u->sun);
  u->normal = calloc(u->ntexels * 3 + 1, sizeof *u->normal);
  if (!idx || !u->sky || !u->sun || !u->normal) {
    vr_render_result_destroy(r);
    st = vr_error_set(err, VR_E_NOMEM, "out of memory for UV coefficients");
    goto done;
  }
  glass_texels(j, r, idx);
  for (size_t t = 0; t < u->ntexels; t++) {
    memcpy(u->sky + t * NPATCH, r->photochromic_uv_patch + idx[t] * NPATCH, NPATCH * sizeof *u->sky);
    const vr_scene_object *ob = &j->s->objects[r->photochromic_object[idx[t]]];
    if (!vr_xform_normal(&ob->xform, ob->normal, u->normal + 3 * t))
      memcpy(u->normal + 3 * t, ob->normal, sizeof ob->normal);
  }
  vr_render_result_destroy(r);
  vr_uv_take_ctx c = {u, idx};
  st = each_sun(j, &v, false, uv_take, &c, err);
done:
  free(idx);
  free(v.mats);
  return st;
}

void annual_dc_free(vr_dc_set *d) {
  free(d->sky), free(d->sun_total), free(d->sun_direct);
  memset(d, 0, sizeof *d);
}

void annual_uv_free(vr_uv_set *u) {
  free(u->sky), free(u->sun), free(u->normal);
  memset(u, 0, sizeof *u);
}
