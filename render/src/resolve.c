/* Resolving a parsed scene for rendering: materials loaded from the
 * database and turned into vr_bsdf, lights and emitters converted from the
 * units the user gave (cd, lm, W, lx, cd/m²) to spectral radiometric
 * quantities on a 1 nm grid, the sky normalised to its stated level, the
 * camera frame, and the geometry cut into sub-domains.
 *
 * Photometric to radiometric: an amount in photometric units Q_v with a
 * relative spectrum S(λ) is Q_e(λ) = Q_v S(λ) / (K_m ∫ V(λ) S(λ) dλ), with
 * K_m = 683.002 lm/W (VR_KM, CIE 015:2018) and V = ȳ of the CIE 1931
 * observer, integrated over 360-830 nm.  A radiometric amount (W, W/sr,
 * W/m², W/(m² sr)) is taken over the renderer's sampled range. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render_internal.h"
#include "vr/chromogenic.h"
#include "vr/colour.h"
#include "vr/ies.h"
#include "vr/matdb.h"

#define UV_LO 300.0 /* the photochromic UV band, nm */

double rspd_at(const rspd *s, double nm) {
  if (!s->n) return 0.0;
  double x = nm - s->lo;
  if (x <= 0) return s->v[0];
  int i = (int)x;
  if (i >= s->n - 1) return s->v[s->n - 1];
  double f = x - i;
  return s->v[i] * (1 - f) + s->v[i + 1] * f;
}

static void rspd_free(rspd *s) {
  free(s->v);
  s->v = NULL;
  s->n = 0;
}

static double rspd_integral(const rspd *s, double lo, double hi) {
  double sum = 0;
  for (double nm = lo; nm <= hi + 1e-9; nm += 1.0)
    sum += rspd_at(s, nm) * ((nm == lo || nm > hi - 0.5) ? 0.5 : 1.0);
  return sum;
}

/* K_m ∫ V S dλ over 360-830 nm, 1 nm steps: lumens per unit of S. */
static double luminous(const rspd *s) {
  double sum = 0;
  for (int nm = 360; nm <= 830; nm++) {
    double xyz[3];
    vr_cmf_eval(VR_CIE1931_2DEG, nm, xyz);
    sum += xyz[1] * rspd_at(s, nm) * ((nm == 360 || nm == 830) ? 0.5 : 1.0);
  }
  return VR_KM * sum;
}

/* The relative spectrum named by ref (NULL: dflt) on [lo, hi] every nm. */
vr_status vr_rscene_spectrum(const rscene *rs, vr_matdb *db, const char *ref, const char *dflt,
                          const vr_scene_loc *loc, rspd *out, vr_error *err) {
  const char *name = ref ? ref : dflt;
  vr_spectrum *sp = NULL;
  vr_material *m = NULL;
  vr_status st = VR_OK;
  if (!strncmp(name, "db:", 3)) {
    if (!db)
      return vr_error_at(err, VR_E_NOT_FOUND, rs->s->path, loc->line, loc->col,
                         "spectrum '%s' needs a material database", name);
    st = vr_matdb_load(db, name + 3, 0, &m, err);
    if (st) {
      vr_error_prefix(err, "%s:%ld:%ld: spectrum '%s': ", rs->s->path, loc->line, loc->col, name);
      return st;
    }
    const vr_spectrum *v = vr_material_spectrum(m, "value");
    if (!v) {
      vr_material_destroy(m);
      return vr_error_at(err, VR_E_ARG, rs->s->path, loc->line, loc->col,
                         "spectrum '%s' is a %s material without a 'value' spectrum", name,
                         vr_kind_name(m->kind));
    }
    sp = vr_spectrum_copy(v, err);
    vr_material_destroy(m);
  } else if (!strncmp(name, "bb:", 3)) {
    sp = vr_illuminant_blackbody(strtod(name + 3, NULL), err);
  } else if (name[0] == '[') {
    sp = vr_scene_inline_spectrum(name, err); /* checked when the scene was read */
  } else {
    sp = vr_illuminant(name, err);
  }
  if (!sp) {
    vr_error_prefix(err, "%s:%ld:%ld: spectrum '%s': ", rs->s->path, loc->line, loc->col, name);
    return err ? err->status : VR_E_ARG;
  }
  double lo = fmin(UV_LO, rs->lmin), hi = fmax(830.0, rs->lmax);
  out->lo = lo;
  out->n = (int)(hi - lo) + 1;
  out->v = malloc((size_t)out->n * sizeof *out->v);
  if (!out->v) {
    vr_spectrum_destroy(sp);
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  for (int i = 0; i < out->n; i++) {
    double nm = lo + i;
    /* Zero outside the data: a light is not assumed to emit where its
     * spectrum was not measured. */
    out->v[i] = (nm < sp->nm[0] || nm > sp->nm[sp->n - 1])
                    ? 0.0
                    : fmax(0.0, vr_spectrum_eval(sp, nm, VR_INTERP_LINEAR));
  }
  vr_spectrum_destroy(sp);
  return VR_OK;
}

static void scale_spd(rspd *s, double f) {
  for (int i = 0; i < s->n; i++) s->v[i] *= f;
}

/* Scales a relative spd so that it carries the amount q (photometric or
 * radiometric per unit): after this, s is the radiometric spectral amount. */
vr_status vr_rscene_normalise(const rscene *rs, rspd *s, vr_quantity q, bool photometric,
                                  const vr_scene_loc *loc, const char *what, vr_error *err) {
  double denom = photometric ? luminous(s) : rspd_integral(s, rs->lmin, rs->lmax);
  if (!(denom > 0))
    return vr_error_at(err, VR_E_RANGE, rs->s->path, loc->line, loc->col,
                       "%s: its spectrum has no %s power", what,
                       photometric ? "visible" : "in-range");
  scale_spd(s, q.value / denom);
  return VR_OK;
}

static bool is_photometric(vr_light_unit u) {
  return u == VR_UNIT_LM || u == VR_UNIT_CD || u == VR_UNIT_LX || u == VR_UNIT_CD_M2;
}

static void unit(double v[3]) {
  double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (l > 0)
    for (int a = 0; a < 3; a++) v[a] /= l;
}

static vr_status resolve_lights(rscene *rs, vr_matdb *db, vr_error *err) {
  const vr_scene *s = rs->s;
  rs->nlights = s->nlights;
  rs->lights = calloc(s->nlights + 1, sizeof *rs->lights);
  if (!rs->lights) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  for (size_t i = 0; i < s->nlights; i++) {
    const vr_scene_light *sl = &s->lights[i];
    rlight *l = &rs->lights[i];
    l->kind = sl->kind;
    memcpy(l->pos, sl->position, sizeof l->pos);
    l->dist = sl->distribution;
    vr_status st = vr_rscene_spectrum(rs, db, sl->spectrum,
                            sl->kind == VR_LIGHT_SUN ? "db:ASTM-G173-AM1.5D" : "D65", &sl->loc,
                            &l->spd, err);
    if (st) return st;
    vr_quantity q = sl->amount;
    bool photo = is_photometric(q.unit);
    if (sl->kind == VR_LIGHT_SUN) {
      memcpy(l->axis, sl->direction, sizeof l->axis);
      unit(l->axis);
      l->cos_sun = cos(sl->sun_radius_deg * M_PI / 180.0);
      st = vr_rscene_normalise(rs, &l->spd, q, photo, &sl->loc, "sun", err);
      if (st) return st;
      /* Power through a disc of the scene's radius, for photon shares. */
      l->power = rspd_integral(&l->spd, rs->lmin, rs->lmax) * M_PI * rs->scene_radius *
                 rs->scene_radius;
      continue;
    }
    if (sl->kind == VR_LIGHT_SPOT) {
      memcpy(l->axis, sl->direction, sizeof l->axis);
      unit(l->axis);
      l->cos_inner = cos(sl->cone_deg * M_PI / 180.0);
      l->cos_outer = cos((sl->cone_deg + sl->falloff_deg) * M_PI / 180.0);
    } else {
      memcpy(l->axis, sl->normal, sizeof l->axis);
      unit(l->axis);
    }
    if (sl->distribution == VR_DIST_GONIOMETRIC) {
      st = vr_ies_read(sl->ies_path, &l->ies, err);
      if (st) {
        vr_error_prefix(err, "%s:%ld:%ld: ", s->path, sl->loc.line, sl->loc.col);
        return st;
      }
    }
    /* Solid-angle integral of the distribution relative to its on-axis
     * (peak) value: converts flux (lm, W) to intensity. */
    double omega;
    if (sl->kind == VR_LIGHT_SPOT)
      omega = 2 * M_PI * (1 - 0.5 * (l->cos_inner + l->cos_outer));
    else if (sl->distribution == VR_DIST_LAMBERTIAN)
      omega = M_PI;
    else if (sl->distribution == VR_DIST_GONIOMETRIC)
      omega = vr_ies_lumens(l->ies) / fmax(vr_ies_max_candela(l->ies), 1e-300);
    else
      omega = 4 * M_PI;
    if (q.unit == VR_UNIT_LM || q.unit == VR_UNIT_W) q.value /= omega;
    if (sl->distribution == VR_DIST_GONIOMETRIC && (q.unit == VR_UNIT_NONE)) {
      /* The file's own candela values: the peak is the amount. */
      q.value = vr_ies_max_candela(l->ies);
      photo = true;
    }
    st = vr_rscene_normalise(rs, &l->spd, q, photo, &sl->loc, "light", err);
    if (st) return st;
    l->power = rspd_integral(&l->spd, rs->lmin, rs->lmax) * omega;
  }
  return VR_OK;
}

static vr_status resolve_materials(rscene *rs, vr_matdb *db, vr_error *err) {
  const vr_scene *s = rs->s;
  rs->nmat = s->nmaterials;
  rs->mat = calloc(s->nmaterials + 1, sizeof *rs->mat);
  if (!rs->mat) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  for (size_t i = 0; i < s->nmaterials; i++) {
    const vr_scene_material *sm = &s->materials[i];
    rmaterial *rm = &rs->mat[i];
    vr_material *coating = NULL;
    vr_status st = VR_OK;
    if (sm->source == VR_MATSRC_DB || sm->coating_db) {
      if (!db)
        return vr_error_at(err, VR_E_NOT_FOUND, s->path, sm->loc.line, sm->loc.col,
                           "material '%s' needs a material database", sm->name);
    }
    if (sm->source == VR_MATSRC_DB) {
      st = vr_matdb_load(db, sm->db_name, 0, &rm->db, err);
      if (st) {
        vr_error_prefix(err, "%s:%ld:%ld: material '%s': ", s->path, sm->loc.line, sm->loc.col,
                        sm->name);
        return st;
      }
    }
    if (sm->coating_db) {
      st = vr_matdb_load(db, sm->coating_db, 0, &coating, err);
      if (st) {
        vr_error_prefix(err, "%s:%ld:%ld: coating of '%s': ", s->path, sm->loc.line,
                        sm->loc.col, sm->name);
        return st;
      }
    }
    st = vr_bsdf_create(sm, rm->db, coating, rs->lmin, rs->lmax, &rm->bsdf, err);
    vr_material_destroy(coating);
    if (st) {
      vr_error_prefix(err, "%s:", s->path);
      return st;
    }
    rm->state = vr_bsdf_default_state(rm->bsdf);
    /* state= fixes a photochromic pane's state (a tint study, the annual
     * study's tint states): no UV pass moves it. */
    rm->photochromic = vr_bsdf_is_photochromic(rm->bsdf) && isnan(sm->state);
    rm->temperature_K = isnan(sm->temperature_K) ? 298.15 : sm->temperature_K;
  }
  return VR_OK;
}

/* The bounding sphere (centre of the bounding box, half its diagonal) of
 * an emissive object, from the replicated tables. */
static void emitter_bounds(const vr_scene_tables *t, size_t o, double out[4]) {
  if (t->sphere[o][3] > 0) {
    memcpy(out, t->sphere[o], 4 * sizeof *out);
    return;
  }
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (uint64_t e = t->emit_begin[o]; e < t->emit_end[o]; e++)
    for (int k = 0; k < 9; k++) {
      double v = t->emit_verts[9 * e + k];
      if (v < lo[k % 3]) lo[k % 3] = v;
      if (v > hi[k % 3]) hi[k % 3] = v;
    }
  double r2 = 0;
  for (int a = 0; a < 3; a++) {
    out[a] = 0.5 * (lo[a] + hi[a]);
    r2 += 0.25 * (hi[a] - lo[a]) * (hi[a] - lo[a]);
  }
  out[3] = sqrt(r2);
}

static vr_status resolve_objects(rscene *rs, vr_matdb *db, vr_error *err) {
  const vr_scene *s = rs->s;
  rs->obj = calloc(s->nobjects + 1, sizeof *rs->obj);
  rs->emitters = calloc(s->nobjects + 1, sizeof *rs->emitters);
  rs->emitter_cdf = calloc(s->nobjects + 1, sizeof *rs->emitter_cdf);
  rs->emitter_sphere = calloc(s->nobjects + 1, sizeof *rs->emitter_sphere);
  if (!rs->obj || !rs->emitters || !rs->emitter_cdf || !rs->emitter_sphere)
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  double acc = 0;
  for (size_t i = 0; i < s->nobjects; i++) {
    const vr_scene_object *so = &s->objects[i];
    robject *o = &rs->obj[i];
    o->material = so->material;
    o->outside = so->outside;
    if (so->emission.value > 0) {
      vr_status st = vr_rscene_spectrum(rs, db, so->emission_spectrum, "D65", &so->loc, &o->emission, err);
      if (!st)
        st = vr_rscene_normalise(rs, &o->emission, so->emission, is_photometric(so->emission.unit),
                              &so->loc, "emission", err);
      if (st) return st;
      double area = rs->t->object_area[i];
      if (!(area > 0)) {
        /* A zero-area emitter emits nothing; it is not an error. */
        rspd_free(&o->emission);
        continue;
      }
      o->emitted_power = rspd_integral(&o->emission, rs->lmin, rs->lmax) * M_PI * area;
      acc += o->emitted_power;
      emitter_bounds(rs->t, i, rs->emitter_sphere[rs->nemitters]);
      rs->emitters[rs->nemitters] = (uint32_t)i;
      rs->emitter_cdf[rs->nemitters++] = acc;
    }
    if (rs->mat[so->material].photochromic) {
      if (so->shape != VR_SHAPE_RECT)
        return vr_error_at(err, VR_E_ARG, s->path, so->loc.line, so->loc.col,
                           "photochromic glass must be a rect (its state map is laid over "
                           "the rectangle)");
      o->nu = so->texels[0] > 0 ? so->texels[0] : 16;
      o->nv = so->texels[1] > 0 ? so->texels[1] : 16;
      o->texel0 = rs->ntexels;
      rs->ntexels += (size_t)o->nu * (size_t)o->nv;
      /* The rectangle's frame, from the replicated tables. */
      const double *f = rs->t->rect_frame[i];
      memcpy(o->corner, f, sizeof o->corner);
      memcpy(o->eu, f + 3, sizeof o->eu);
      memcpy(o->ev, f + 6, sizeof o->ev);
      memcpy(o->normal, so->normal, sizeof o->normal);
    }
  }
  for (size_t e = 0; e < rs->nemitters; e++) rs->emitter_cdf[e] /= acc > 0 ? acc : 1;
  return VR_OK;
}

/* Each cell holds the state maps of the photochromic objects it has
 * primitives of, starting at the material's own state. */
static vr_status cell_maps(rscene *rs, vr_error *err) {
  int S = vr_domains_count(rs->d);
  rs->cells = calloc((size_t)S, sizeof *rs->cells);
  if (!rs->cells) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  for (int c = 0; c < S; c++) {
    size_t n;
    const uint32_t *objs = vr_domains_cell_objects(rs->d, c, &n);
    rcell *rc = &rs->cells[c];
    for (size_t i = 0; i < n; i++) rc->nmaps += rs->obj[objs[i]].nu > 0;
    if (!rc->nmaps) continue;
    rc->map_object = calloc(rc->nmaps, sizeof *rc->map_object);
    rc->map = calloc(rc->nmaps, sizeof *rc->map);
    if (!rc->map_object || !rc->map) return vr_error_set(err, VR_E_NOMEM, "out of memory");
    size_t k = 0;
    for (size_t i = 0; i < n; i++) {
      const robject *o = &rs->obj[objs[i]];
      if (!o->nu) continue;
      size_t nt = (size_t)o->nu * (size_t)o->nv;
      rc->map_object[k] = objs[i];
      if (!(rc->map[k] = malloc(nt * sizeof **rc->map)))
        return vr_error_set(err, VR_E_NOMEM, "out of memory");
      for (size_t t = 0; t < nt; t++) rc->map[k][t] = rs->mat[o->material].state;
      k++;
    }
  }
  return VR_OK;
}

double *vr_cell_state_map(const rscene *rs, int c, uint32_t o) {
  const rcell *rc = &rs->cells[c];
  size_t lo = 0, hi = rc->nmaps;
  while (lo < hi) {
    size_t mid = lo + (hi - lo) / 2;
    if (rc->map_object[mid] < o)
      lo = mid + 1;
    else
      hi = mid;
  }
  return lo < rc->nmaps && rc->map_object[lo] == o ? rc->map[lo] : NULL;
}

size_t vr_rscene_map_bytes(const rscene *rs) {
  size_t b = 0;
  for (int c = 0; rs->cells && c < vr_domains_count(rs->d); c++) {
    const rcell *rc = &rs->cells[c];
    b += rc->nmaps * (sizeof *rc->map_object + sizeof *rc->map);
    for (size_t k = 0; k < rc->nmaps; k++) {
      const robject *o = &rs->obj[rc->map_object[k]];
      b += (size_t)o->nu * (size_t)o->nv * sizeof **rc->map;
    }
  }
  return b;
}

static void camera_frame(rscene *rs) {
  const vr_scene_camera *c = &rs->s->camera;
  double w[3], u[3], v[3];
  for (int a = 0; a < 3; a++) w[a] = c->to[a] - c->from[a];
  unit(w);
  u[0] = w[1] * c->up[2] - w[2] * c->up[1];
  u[1] = w[2] * c->up[0] - w[0] * c->up[2];
  u[2] = w[0] * c->up[1] - w[1] * c->up[0];
  unit(u);
  v[0] = u[1] * w[2] - u[2] * w[1];
  v[1] = u[2] * w[0] - u[0] * w[2];
  v[2] = u[0] * w[1] - u[1] * w[0];
  memcpy(rs->cam_o, c->from, sizeof rs->cam_o);
  memcpy(rs->cam_u, u, sizeof u);
  memcpy(rs->cam_v, v, sizeof v);
  memcpy(rs->cam_w, w, sizeof w);
  rs->tan_half = tan(0.5 * c->fov_deg * M_PI / 180.0);
}

static vr_status resolve_sources(rscene *rs, vr_error *err) {
  /* The sky is two photon sources: the sky above the horizon and the
   * ground glow below it (the light an escaping path meets there,
   * vr_light_environment), so photon maps hold ground-reflected light too.
   * With portals, the far sources (sun, sky, ground glow) also emit through
   * them (portals.c): those sources get VR_PORTAL_PHOTON_SHARE of the
   * photons, shared by power, the usual ones the rest. */
  rs->sun_light = rs->nlights;
  for (size_t i = 0; i < rs->nlights; i++)
    if (rs->lights[i].kind == VR_LIGHT_SUN) rs->sun_light = i;
  rs->nportal_sources = 0;
  double pp[3], portal_total = 0;
  if (rs->nportals && rs->s->settings.photon_portals) {
    static const int KINDS[3] = {PORTAL_SRC_SUN, PORTAL_SRC_SKY, PORTAL_SRC_GROUND};
    for (int i = 0; i < 3; i++) {
      double w = vr_light_portal_power(rs, KINDS[i]);
      if (!(w > 0)) continue;
      rs->portal_source[rs->nportal_sources] = KINDS[i];
      pp[rs->nportal_sources++] = w;
      portal_total += w;
    }
  }
  size_t base = rs->nlights + rs->nemitters + (rs->has_sky ? 2 : 0);
  size_t n = base + rs->nportal_sources;
  rs->nsources = n;
  rs->source_cdf = calloc(n + 1, sizeof *rs->source_cdf);
  if (!rs->source_cdf) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  double acc = 0;
  size_t k = 0;
  for (size_t i = 0; i < rs->nlights; i++) rs->source_cdf[k++] = (acc += rs->lights[i].power);
  for (size_t i = 0; i < rs->nemitters; i++)
    rs->source_cdf[k++] = (acc += rs->obj[rs->emitters[i]].emitted_power);
  if (rs->has_sky) {
    rs->source_cdf[k++] = (acc += vr_light_sky_power(rs));
    rs->source_cdf[k++] = (acc += vr_light_ground_power(rs));
  }
  rs->total_power = acc;
  double q = rs->nportal_sources && acc > 0 ? VR_PORTAL_PHOTON_SHARE : 0.0;
  if (rs->nportal_sources && !(acc > 0)) q = 1.0;
  for (size_t i = 0; i < base; i++) rs->source_cdf[i] = acc > 0 ? (1 - q) * rs->source_cdf[i] / acc : 0;
  double pacc = 0;
  for (size_t i = 0; i < rs->nportal_sources; i++)
    rs->source_cdf[base + i] = (1 - q) + q * (pacc += pp[i]) / portal_total;
  if (rs->nportal_sources) rs->source_cdf[n - 1] = 1.0;
  if (rs->nportal_sources) rs->total_power += portal_total;
  return VR_OK;
}

vr_status vr_rscene_create(const vr_scene *s, vr_matdb *db, const vr_render_options *opt,
                           int subdomains, rscene **out, vr_error *err) {
  *out = NULL;
  rscene *rs = calloc(1, sizeof *rs);
  if (!rs) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  rs->s = s;
  const vr_scene_settings *set = &s->settings;
  rs->lmin = set->lambda_min;
  rs->lmax = set->lambda_max;
  rs->bins_mode = set->spectral == VR_SPECTRAL_BINS;
  rs->nwl = set->wavelengths;
  /* The sampler spreads its points over a pixel's samples (vr/rng.h). */
  int spp = opt && opt->spp > 0 ? opt->spp : set->spp;
  rs->seed = vr_rng_seed_make(set->seed, set->sampler, spp > 0 ? (uint32_t)spp : 1u);
  rs->film_lo = set->film_min_nm;
  rs->film_step = set->film_step_nm;
  rs->nbins = (size_t)floor((set->film_max_nm - set->film_min_nm) / set->film_step_nm + 1e-9);
  vr_status st = VR_OK;
  if (rs->nwl < 1 || rs->nwl > VR_MAX_WL) {
    st = vr_error_at(err, VR_E_ARG, s->path, set->loc.line, set->loc.col,
                     "wavelengths=%d: the renderer carries 1 to %d per path", rs->nwl, VR_MAX_WL);
    goto fail;
  }
  if (rs->nbins < 1) rs->nbins = 1;
  vr_domains_options dopt;
  vr_domains_options_default(&dopt);
  dopt.subdomains = subdomains;
  dopt.cache_dir = opt->cache_dir;
  dopt.threads = opt->threads > 0 ? opt->threads : 1;
  dopt.log = opt->log;
  dopt.user = opt->user;
  st = vr_domains_open(s, &dopt, &rs->d, err);
  if (st) goto fail;
  rs->t = vr_domains_tables(rs->d);
  for (int a = 0; a < 3; a++) {
    rs->scene_lo[a] = rs->t->bmin[a];
    rs->scene_hi[a] = rs->t->bmax[a];
    rs->scene_centre[a] = 0.5 * (rs->t->bmin[a] + rs->t->bmax[a]);
  }
  {
    double d2 = 0;
    for (int a = 0; a < 3; a++) d2 += pow(rs->t->bmax[a] - rs->t->bmin[a], 2);
    rs->scene_radius = fmax(0.5 * sqrt(d2), 1e-3);
  }
  if (!st) st = resolve_materials(rs, db, err);
  if (!st) st = resolve_lights(rs, db, err);
  if (!st) st = resolve_objects(rs, db, err);
  if (!st) st = cell_maps(rs, err);
  if (!st) {
    int S = vr_domains_count(rs->d);
    rs->owner = calloc((size_t)S, sizeof *rs->owner);
    rs->cell_ns = calloc((size_t)S, sizeof *rs->cell_ns);
    rs->cell_total_ns = calloc((size_t)S, sizeof *rs->cell_total_ns);
    if (!rs->owner || !rs->cell_ns || !rs->cell_total_ns) st = vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  if (!st) st = vr_light_sky_create(rs, db, err);
  if (!st) st = vr_portals_create(rs, err);
  if (!st) st = resolve_sources(rs, err);
  if (st) goto fail;
  camera_frame(rs);
  *out = rs;
  return VR_OK;
fail:
  vr_rscene_destroy(rs);
  return st;
}

void vr_rscene_destroy(rscene *rs) {
  if (!rs) return;
  for (size_t i = 0; rs->mat && i < rs->nmat; i++) {
    vr_bsdf_destroy(rs->mat[i].bsdf);
    vr_material_destroy(rs->mat[i].db);
  }
  for (size_t i = 0; rs->lights && i < rs->nlights; i++) {
    rspd_free(&rs->lights[i].spd);
    vr_ies_destroy(rs->lights[i].ies);
  }
  for (size_t i = 0; rs->obj && i < rs->s->nobjects; i++) rspd_free(&rs->obj[i].emission);
  for (int c = 0; rs->cells && c < vr_domains_count(rs->d); c++) {
    for (size_t k = 0; k < rs->cells[c].nmaps; k++) free(rs->cells[c].map[k]);
    free(rs->cells[c].map);
    free(rs->cells[c].map_object);
  }
  free(rs->cells);
  free(rs->owner);
  free(rs->cell_ns);
  free(rs->cell_total_ns);
  vr_light_sky_destroy(rs);
  free(rs->mat);
  free(rs->lights);
  free(rs->obj);
  free(rs->emitters);
  free(rs->portals);
  free(rs->portal_area_cdf);
  free(rs->emitter_cdf);
  free(rs->emitter_sphere);
  free(rs->source_cdf);
  vr_domains_destroy(rs->d);
  free(rs);
}
