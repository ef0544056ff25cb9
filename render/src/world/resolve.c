/* Resolving a parsed scene for rendering: materials loaded from the
 * database and turned into vr_bsdf, the lights, emitters and sky in
 * radiometric units (lights/), the camera (camera/), the photochromic state
 * maps, and the geometry cut into sub-domains. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vr/chromogenic.h"
#include "vr/matdb.h"
#include "textures/texture.h"
#include "world/resolve.h"

static vr_status resolve_materials(vr_rscene *rs, vr_matdb *db, vr_error *err) {
  const vr_scene *s = rs->s;
  rs->nmat = s->nmaterials;
  rs->mat = calloc(s->nmaterials + 1, sizeof *rs->mat);
  if (!rs->mat) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  for (size_t i = 0; i < s->nmaterials; i++) {
    const vr_scene_material *sm = &s->materials[i];
    vr_rmaterial *rm = &rs->mat[i];
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
    /* A database material that records a spectral texture (vr-rgb2spec
     * --texture) reflects its texture's spectra: the BSDF is a white
     * Lambertian that the texture multiplies (world/textures.c). */
    const vr_property *tp = sm->source == VR_MATSRC_DB && !sm->texture_off && rm->db
                                ? vr_material_property(rm->db, "texture")
                                : NULL;
    vr_scene_material white;
    if (tp) {
      white = *sm;
      white.source = VR_MATSRC_LAMBERT_CONST;
      white.reflectance = 1;
      white.reflectance_spectrum = NULL;
    }
    st = vr_bsdf_create(tp ? &white : sm, tp ? NULL : rm->db, coating, rs->lmin, rs->lmax,
                        &rm->bsdf, err);
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
    rm->chromo_flags = sm->extrapolate ? VR_CHROMO_EXTRAPOLATE : 0;
    /* An option that would change nothing is refused, not ignored. */
    if (sm->extrapolate && !vr_bsdf_is_photochromic(rm->bsdf))
      return vr_error_at(err, VR_E_ARG, s->path, sm->loc.line, sm->loc.col,
                         "material '%s': extrapolate=yes applies to photochromic glass, whose "
                         "state follows its UV; '%s' is not", sm->name,
                         sm->db_name ? sm->db_name : sm->name);
  }
  return VR_OK;
}

static vr_status resolve_objects(vr_rscene *rs, vr_error *err) {
  const vr_scene *s = rs->s;
  rs->obj = calloc(s->nobjects + 1, sizeof *rs->obj);
  if (!rs->obj) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  for (size_t i = 0; i < s->nobjects; i++) {
    const vr_scene_object *so = &s->objects[i];
    vr_robject *o = &rs->obj[i];
    o->material = so->material;
    o->outside = so->outside;
    o->emitter = -1;
    if (so->emission.value > 0) {
      vr_status st = vr_lights_add_emitter(&rs->L, so, (uint32_t)i, rs->t->object_area[i],
                                           &o->emitter, err);
      if (st) return st;
      if (o->emitter < 0) continue; /* a zero-area emitter */
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
  vr_lights_emitters_done(&rs->L);
  return VR_OK;
}

vr_status vr_rscene_create(const vr_scene *s, vr_matdb *db, const vr_render_options *opt,
                           int subdomains, vr_rscene **out, vr_error *err) {
  *out = NULL;
  vr_rscene *rs = calloc(1, sizeof *rs);
  if (!rs) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  rs->s = s;
  const vr_scene_settings *set = &s->settings;
  rs->lmin = set->lambda_min;
  rs->lmax = set->lambda_max;
  rs->bins_mode = set->spectral == VR_SPECTRAL_BINS;
  rs->nwl = set->wavelengths;
  /* The sampler spreads its points over a pixel's samples (vr/rng.h). */
  int spp = opt && opt->spp > 0 ? opt->spp : set->spp;
  /* A denoised render of fixed spp takes its samples in two halves, each
   * a whole block of the sampler (vr_integrator_camera). */
  if (opt && opt->denoise && !(opt->target_error > 0 || opt->time_limit_s > 0) && spp % 2 == 0)
    spp /= 2;
  rs->seed = vr_rng_seed_make(set->seed, set->sampler, spp > 0 ? (uint32_t)spp : 1u);
  rs->film_lo = set->film_min_nm;
  rs->film_step = set->film_step_nm;
  rs->nbins = (size_t)floor((set->film_max_nm - set->film_min_nm) / set->film_step_nm + 1e-9);
  vr_status st = VR_OK;
  if (rs->nwl < 1 || rs->nwl > VR_MAX_WL) {
    st = vr_error_at(err, VR_E_ARG, set->source ? set->source : s->path, set->loc.line, set->loc.col,
                     "wavelengths=%d: the renderer carries 1 to %d per path", rs->nwl, VR_MAX_WL);
    goto fail;
  }
  if (rs->nbins < 1) rs->nbins = 1;
  /* What the parser decided for the user (a model's own materials). */
  for (size_t i = 0; opt->log && i < s->nnotes; i++) opt->log(opt->user, s->notes[i]);
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
  vr_light_setup lu = {{s->path, db, rs->lmin, rs->lmax},
                       {rs->scene_centre[0], rs->scene_centre[1], rs->scene_centre[2]},
                       rs->scene_radius};
  if (!st) st = resolve_materials(rs, db, err);
  if (!st) st = vr_lights_create(&rs->L, s, &lu, rs->t, err);
  rs->sun_disc = !(opt && opt->pixel_patches);
  if (!st) st = vr_rscene_textures(rs, opt && opt->threads > 0 ? opt->threads : 1, err);
  if (!st) st = resolve_objects(rs, err);
  if (!st) st = vr_rscene_cell_maps(rs, err);
  if (!st) {
    int S = vr_domains_count(rs->d);
    rs->cell_ns = calloc((size_t)S, sizeof *rs->cell_ns);
    rs->cell_total_ns = calloc((size_t)S, sizeof *rs->cell_total_ns);
    if (!rs->cell_ns || !rs->cell_total_ns) st = vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  if (!st) st = vr_lights_sky_create(&rs->L, s, err);
  if (!st) st = vr_lights_portals_create(&rs->L, s, err);
  if (!st) st = vr_lights_sources_create(&rs->L, vr_scene_photon_portals(s), err);
  if (st) goto fail;
  vr_camera_init(&rs->cam, &s->camera);
  *out = rs;
  return VR_OK;
fail:
  vr_rscene_destroy(rs);
  return st;
}

void vr_rscene_destroy(vr_rscene *rs) {
  if (!rs) return;
  for (size_t i = 0; rs->mat && i < rs->nmat; i++) {
    vr_bsdf_destroy(rs->mat[i].bsdf);
    vr_material_destroy(rs->mat[i].db);
  }
  for (size_t i = 0; i < rs->ntex; i++) vr_texture_destroy(rs->tex[i]);
  free(rs->tex);
  for (int c = 0; rs->cells && c < vr_domains_count(rs->d); c++) {
    for (size_t k = 0; k < rs->cells[c].nmaps; k++) free(rs->cells[c].map[k]);
    free(rs->cells[c].map);
    free(rs->cells[c].map_object);
  }
  free(rs->cells);
  free(rs->cell_ns);
  free(rs->cell_total_ns);
  vr_lights_destroy(&rs->L);
  free(rs->mat);
  free(rs->obj);
  vr_domains_destroy(rs->d);
  free(rs);
}
