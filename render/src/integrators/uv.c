/* The UV pass of photochromic glass: the UV irradiance (300-400 nm) on
 * both faces of every texel of every photochromic pane, from every light,
 * emitter and the sky by next-event estimation, then each texel's steady
 * state (vr_chromo_steady_state) written into every cell's copy of its
 * object's state map. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "integrators/uv.h"
#include "vr/chromogenic.h"

/* Next-event samples per texel face: each carries 1/UV_SAMPLES. */
#define UV_SAMPLES 64

typedef struct vr_uv_state {
  uint32_t *texel_object;
  uint32_t *texel_index;
} vr_uv_state;

/* UV pass: one texel of a photochromic pane, both faces. */
static void generate(void *ctx, vr_flow_worker *w, long unit) {
  vr_pass *c = ctx;
  const vr_rscene *rs = c->rs;
  const vr_uv_state *us = c->state;
  uint32_t obj = us->texel_object[unit], ti = us->texel_index[unit];
  const vr_robject *o = &rs->obj[obj];
  int i = (int)(ti % (uint32_t)o->nu), j = (int)(ti / (uint32_t)o->nu);
  double u = (i + 0.5) / o->nu, v = (j + 0.5) / o->nv, x[3];
  for (int a = 0; a < 3; a++) x[a] = o->corner[a] + u * o->eu[a] + v * o->ev[a];
  for (int side = 0; side < 2; side++) {
    double n[3];
    for (int a = 0; a < 3; a++) n[a] = side ? -o->normal[a] : o->normal[a];
    for (int s = 0; s < UV_SAMPLES; s++) {
      vr_payload p = {0};
      p.stream = VR_STREAM_UV + (uint64_t)unit;
      p.sample = (uint32_t)(side * UV_SAMPLES + s);
      p.index = (uint32_t)unit;
      p.target = VR_TARGET_TEXEL;
      p.nwl = (uint8_t)rs->nwl;
      p.medium = -1;
      vr_rng_key key = {rs->seed, p.stream, p.sample, 0};
      double h = vr_rng(&key, VR_DIM_WAVELENGTH) * 100.0;
      for (int k = 0; k < p.nwl; k++) p.wl[k] = 300.0 + fmod(h + k * 100.0 / p.nwl, 100.0);
      p.weight = 1.0 / UV_SAMPLES;
      for (int k = 0; k < p.nwl; k++) p.beta[k] = 1.0;
      /* Every sample draws the lights and the sky; each carries 1/M. */
      vr_path_next_event(c, w, &p, x, n, n, vr_receiver_f, n, 0, false);
    }
  }
}

static const vr_flow_ops uv_ops = {vr_path_closest, vr_path_shadow_hit, vr_path_shadow_done,
                                   generate, VR_PAYLOAD_WIRE};

vr_status vr_uv_run(vr_run *r, vr_error *err) {
  vr_rscene *rs = r->rs;
  size_t nt = rs->ntexels;
  vr_uv_state us = {0};
  vr_uv_state *c = &us;
  c->texel_object = calloc(nt + 1, sizeof *c->texel_object);
  c->texel_index = calloc(nt + 1, sizeof *c->texel_index);
  vr_accum acc;
  vr_status st = vr_accum_create(&acc, 1, 1, 1, 0, 1, 0, 1, nt, err);
  if (st) {
    free(c->texel_object), free(c->texel_index);
    return st;
  }
  if (!c->texel_object || !c->texel_index) {
    vr_accum_destroy(&acc);
    free(c->texel_object), free(c->texel_index);
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  size_t k = 0;
  for (size_t i = 0; i < rs->s->nobjects; i++)
    for (int t = 0; t < rs->obj[i].nu * rs->obj[i].nv; t++) {
      c->texel_object[k] = (uint32_t)i;
      c->texel_index[k++] = (uint32_t)t;
    }
  vr_pass pass = {.rs = rs, .acc = &acc, .max_depth = rs->s->settings.max_depth, .state = c};
  st = vr_run_flow(r, &uv_ops, &pass, (long)nt, "uv", err);
  if (!st) st = vr_ranks_sum_accum(r, &acc, RANKS_TEXELS, err);
  vr_render_result *res = r->res;
  res->photochromic_texels = nt;
  res->photochromic_state = calloc(nt + 1, sizeof *res->photochromic_state);
  if (!st && !res->photochromic_state) st = vr_error_set(err, VR_E_NOMEM, "out of memory");
  res->photochromic_uv = calloc(nt + 1, sizeof *res->photochromic_uv);
  res->photochromic_object = calloc(nt + 1, sizeof *res->photochromic_object);
  res->photochromic_uv_patch = calloc(nt * VR_SENSOR_PATCHES + 1, sizeof *res->photochromic_uv_patch);
  if (!st && (!res->photochromic_uv || !res->photochromic_uv_patch || !res->photochromic_object))
    st = vr_error_set(err, VR_E_NOMEM, "out of memory");
  res->photochromic_state_min = INFINITY;
  res->photochromic_state_max = -INFINITY;
  for (size_t t = 0; !st && t < nt; t++) {
    vr_robject *o = &rs->obj[c->texel_object[t]];
    const vr_rmaterial *m = &rs->mat[o->material];
    double E = vr_atomic_get(&acc.texel_uv[t]), s;
    res->photochromic_uv[t] = E;
    res->photochromic_object[t] = c->texel_object[t];
    for (size_t q = 0; q < VR_SENSOR_PATCHES; q++)
      res->photochromic_uv_patch[t * VR_SENSOR_PATCHES + q] =
          vr_atomic_get(&acc.texel_patches[t * VR_SENSOR_PATCHES + q]);
    /* E is the UV pass's estimate: VR_CHROMO_ESTIMATE allows its noise. */
    unsigned flags = m->chromo_flags | VR_CHROMO_ESTIMATE;
    st = vr_chromo_steady_state(m->db, E, m->temperature_K, flags, &s, err);
    if (st) {
      vr_error_prefix(err, "UV pass, the object of scene line %ld: ",
                      rs->s->objects[c->texel_object[t]].loc.line);
      break;
    }
    if ((flags & VR_CHROMO_EXTRAPOLATE) && vr_chromo_check_domain(m->db, E, m->temperature_K, flags, NULL))
      res->photochromic_extrapolated++;
    res->photochromic_state[t] = s;
    if (s < res->photochromic_state_min) res->photochromic_state_min = s;
    if (s > res->photochromic_state_max) res->photochromic_state_max = s;
  }
  vr_accum_destroy(&acc);
  free(c->texel_object), free(c->texel_index);
  /* Each cell's copy of each map it holds takes the states. */
  for (int cell = 0; !st && cell < vr_domains_count(rs->d); cell++) {
    const vr_rcell *rc = &rs->cells[cell];
    for (size_t k = 0; k < rc->nmaps; k++) {
      const vr_robject *o = &rs->obj[rc->map_object[k]];
      memcpy(rc->map[k], res->photochromic_state + o->texel0,
             (size_t)o->nu * (size_t)o->nv * sizeof *rc->map[k]);
    }
  }
  return st;
}

