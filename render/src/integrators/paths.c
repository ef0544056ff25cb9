/* The path tracing every camera-side pass shares (pass.h): the flow's
 * callbacks for camera, sensor and UV paths and their shadow rays, delivery
 * to pixels, sensors and texels, next-event estimation, the continuation by
 * BSDF sampling, camera rays and the camera pass. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "integrators/features.h"
#include "integrators/pass.h"
#include "vr/filter.h"
#include "vr/vec3.h"

static double offset_scale(const double p[3]) {
  double m = fmax(fabs(p[0]), fmax(fabs(p[1]), fabs(p[2])));
  return 1e-5 * (1.0 + m);
}

void vr_spawn_origin(const double p[3], const double ng[3], const double dir[3], double o[3]) {
  double e = offset_scale(p), s = vr_dot3(ng, dir) >= 0 ? e : -e;
  for (int a = 0; a < 3; a++) o[a] = p[a] + s * ng[a];
}

double vr_wl_weight(const vr_rscene *rs, int nwl) { return (rs->lmax - rs->lmin) / nwl; }

/* A sensor path's contribution v into its daylight component: the source
 * (p->source) and whether a non-delta vertex reflected it on the way
 * (VR_PF_REFLECTED), the last one exterior or not (VR_PF_OUTSIDE_LAST).  The
 * ground glow is an exterior reflection by definition; its radiance is
 * split between the sun and the sky wavelength by wavelength. */
static void sensor_parts(vr_pass *c, const vr_payload *p, const double *v, double lx) {
  const vr_rscene *rs = c->rs;
  bool reflected = p->flags & VR_PF_REFLECTED, outside = p->flags & VR_PF_OUTSIDE_LAST;
  int erc_or_irc = !reflected || outside ? VR_PART_ERC_SKY : VR_PART_IRC_SKY;
  switch (p->source) {
  case VR_SRC_LAMP: vr_accum_sensor_part_lx(c->acc, p->index, VR_PART_ELECTRIC, lx); break;
  case VR_SRC_SKY:
    vr_accum_sensor_part_lx(c->acc, p->index, reflected ? erc_or_irc : VR_PART_SKY, lx);
    if (p->patch != VR_NO_PATCH) vr_accum_sensor_patch_lx(c->acc, p->index, p->patch, lx);
    break;
  case VR_SRC_SUN:
    vr_accum_sensor_part_lx(c->acc, p->index, reflected ? erc_or_irc + 1 : VR_PART_SUN, lx);
    break;
  case VR_SRC_GROUND: {
    double sun[VR_MAX_WL], sky[VR_MAX_WL], w = vr_wl_weight(rs, p->nwl);
    for (int k = 0; k < p->nwl; k++) {
      double f = vr_lights_ground_sun_share(&rs->L, p->wl[k]);
      sun[k] = v[k] * f;
      sky[k] = v[k] - sun[k];
    }
    vr_accum_sensor_part(c->acc, p->index, erc_or_irc, p->nwl, p->wl, sky, w);
    vr_accum_sensor_part(c->acc, p->index, erc_or_irc + 1, p->nwl, p->wl, sun, w);
    vr_accum_sensor_patch_lx(c->acc, p->index, VR_SKY_GROUND_PATCH, lx);
    break;
  }
  default: break; /* photon-map radiance: no single source */
  }
}

void vr_path_deliver(vr_pass *c, const vr_payload *p, const double *v0) {
  double v[VR_MAX_WL];
  for (int k = 0; k < p->nwl; k++) v[k] = v0[k] * p->weight;
  switch (p->target) {
  case VR_TARGET_PIXEL:
  case VR_TARGET_GATHER:
    vr_accum_pixel_half(c->acc, p->index, c->second_half, p->nwl, p->wl, v,
                        vr_wl_weight(c->rs, p->nwl));
    /* Image daylight coefficients: the sky's light by its patch, the
     * ground glow's and the sun's apart (an emitter's in none). */
    if (p->source == VR_SRC_SKY && p->patch != VR_NO_PATCH)
      vr_accum_pixel_patch(c->acc, p->index, p->patch, p->nwl, p->wl, v, vr_wl_weight(c->rs, p->nwl));
    else if (p->source == VR_SRC_GROUND || p->source == VR_SRC_SUN)
      vr_accum_pixel_patch(c->acc, p->index,
                           p->source == VR_SRC_SUN ? VR_PIXEL_SUN : VR_SKY_GROUND_PATCH, p->nwl,
                           p->wl, v, vr_wl_weight(c->rs, p->nwl));
    break;
  case VR_TARGET_SENSOR: {
    uint32_t slot = c->sensor_slots ? p->sample % c->sensor_slots : p->sample;
    double lx = vr_accum_sensor(c->acc, p->index, slot, p->nwl, p->wl, v, vr_wl_weight(c->rs, p->nwl));
    sensor_parts(c, p, v, lx);
    break;
  }
  case VR_TARGET_TEXEL: {
    /* UV band integral: wavelengths uniform over 300-400 nm. */
    double s = 0;
    for (int k = 0; k < p->nwl; k++) s += v[k];
    vr_atomic_add(&c->acc->texel_uv[p->index], s * 100.0 / p->nwl);
    if ((p->source == VR_SRC_SKY || p->source == VR_SRC_GROUND) && p->patch != VR_NO_PATCH)
      vr_atomic_add(&c->acc->texel_patches[(size_t)p->index * VR_SENSOR_PATCHES + p->patch],
                    s * 100.0 / p->nwl);
    break;
  }
  default: break;
  }
}

/* A shadow ray from x (offset to o) towards the light dist away along dir. */
static void push_shadow(vr_flow_worker *w, const vr_payload *p, const double x[3], const double o[3],
                        const double dir[3], double dist, const double *contrib, uint8_t source) {
  vr_ray r = {0};
  memcpy(r.org, o, sizeof r.org);
  r.tnear = 0;
  if (isinf(dist)) {
    memcpy(r.dir, dir, sizeof r.dir);
    r.tmax = INFINITY;
  } else {
    /* Aim from the offset origin at the light's point itself, and stop
     * short of it so the emitter's own surface does not block. */
    double d2 = 0;
    for (int a = 0; a < 3; a++) {
      r.dir[a] = x[a] + dist * dir[a] - o[a];
      d2 += r.dir[a] * r.dir[a];
    }
    double d = sqrt(d2);
    for (int a = 0; a < 3; a++) r.dir[a] /= d;
    r.tmax = d * (1 - 1e-5);
  }
  r.kind = VR_RAY_SHADOW;
  r.purpose = VR_PURPOSE_SHADOW;
  vr_payload *q = (vr_payload *)r.payload;
  *q = *p;
  q->source = source;
  q->patch = source == VR_SRC_SKY ? (uint8_t)vr_sky_patch_of(r.dir) : VR_NO_PATCH;
  memcpy(q->beta, contrib, sizeof q->beta);
  vr_flow_push(w, &r);
}

/* One light sample's shadow ray, if it carries anything. */
static void shadow_for(vr_flow_worker *w, const vr_payload *p, const double x[3],
                       const double ng[3], vr_bsdf_cos_fn f, const void *fu,
                       const vr_light_sample *ls, double dist, uint8_t source) {
  double fc[VR_MAX_WL], contrib[VR_MAX_WL], o[3];
  f(fu, ls->dir, fc);
  bool any = false;
  for (int k = 0; k < p->nwl; k++) any |= (contrib[k] = p->beta[k] * fc[k] * ls->L[k]) > 0;
  if (!any) return;
  vr_spawn_origin(x, ng, ls->dir, o);
  push_shadow(w, p, x, o, ls->dir, dist, contrib, source);
}

void vr_path_next_event(vr_pass *c, vr_flow_worker *w, const vr_payload *p, const double x[3],
                        const double ng[3], const double *n_for_sky, vr_bsdf_cos_fn f,
                        const void *fu, uint32_t depth_key, bool lines_only) {
  const vr_rscene *rs = c->rs;
  const vr_lights *L = &rs->L;
  vr_rng_key key = {rs->seed, p->stream, p->sample, depth_key};
  vr_light_sample ls;
  for (size_t i = 0; i < L->n; i++) {
    vr_rng_key k2 = key;
    k2.depth = depth_key * 64 + (uint32_t)i + 1;
    if (vr_lights_sample_light(L, i, x, &k2, p->nwl, p->wl, &ls))
      shadow_for(w, p, x, ng, f, fu, &ls, ls.dist, (uint8_t)L->light[i].ops->source);
  }
  if (lines_only) return;
  if (vr_lights_sample_emitter(L, x, p->nwl, p->wl, &key, &ls))
    shadow_for(w, p, x, ng, f, fu, &ls, ls.dist, VR_SRC_LAMP);
  if (vr_lights_sample_sky(L, x, n_for_sky, p->nwl, p->wl, &key, &ls))
    shadow_for(w, p, x, ng, f, fu, &ls, INFINITY, VR_SRC_SKY);
}

void vr_surface_f(const void *u, const double wi[3], double *fc) {
  const vr_surface *s = u;
  double f[VR_BSDF_MAX_WAVELENGTHS], pdf;
  vr_vec3 w = vr_vec3_of(wi);
  vr_bsdf_eval_at(s->b, &s->pt, s->state, s->n, s->wo, w, s->nwl, s->wl, VR_TRANSPORT_RADIANCE,
                  f, &pdf);
  double c = fabs(vr_vec3_dot(s->ns, w));
  if (s->bent && vr_vec3_dot(s->ng, w) * vr_vec3_dot(s->ng, s->wo) <= 0) c = 0;
  for (int k = 0; k < s->nwl; k++) fc[k] = f[k] * c * (s->tinted ? s->tint[k] : 1.0);
}

/* A sensor is a cosine receiver: "BSDF times cos" is cos on its front side. */
void vr_receiver_f(const void *u, const double wi[3], double *fc) {
  const double *n = u;
  double c = vr_dot3(n, wi);
  for (int k = 0; k < VR_MAX_WL; k++) fc[k] = c > 0 ? c : 0.0;
}

/* Continues a path by sampling the BSDF; returns false when it ends. */
static bool continue_path(vr_pass *c, vr_flow_worker *w, vr_payload *p, const vr_hit *hit,
                          const vr_surface *se) {
  const vr_rscene *rs = c->rs;
  if (p->depth + 1 >= c->max_depth) return false;
  vr_rng_key key = {rs->seed, p->stream, p->sample, p->depth};
  vr_bsdf_sample bs;
  if (!vr_bsdf_sample_at(se->b, &se->pt, se->state, se->n, se->wo, p->nwl, p->wl,
                         VR_TRANSPORT_RADIANCE, vr_rng(&key, VR_DIM_LOBE),
                         vr_rng(&key, VR_DIM_DIR_U), vr_rng(&key, VR_DIM_DIR_V), &bs))
    return false;
  /* Around a normal map's normal, a reflection may point into the surface. */
  if (se->bent && vr_vec3_dot(se->ng, bs.wi) * vr_vec3_dot(se->ng, se->wo) <= 0) return false;
  /* The factor nwl of a dispersive refraction stands for the secondary
   * wavelengths it ends: once only. */
  if (bs.terminate_secondary && (p->flags & VR_PF_TERMINATED)) bs.weight[0] /= p->nwl;
  double mx = 0;
  for (int k = 0; k < p->nwl; k++) {
    p->beta[k] *= bs.weight[k] * (se->tinted ? se->tint[k] : 1.0);
    if (p->beta[k] > mx) mx = p->beta[k];
  }
  if (!(mx > 0)) return false;
  if (bs.terminate_secondary) p->flags |= VR_PF_TERMINATED;
  /* Russian roulette from the fourth vertex on. */
  if (p->depth >= 3) {
    double q = fmin(1.0, mx);
    if (vr_rng(&key, VR_DIM_ROULETTE) >= q) return false;
    for (int k = 0; k < p->nwl; k++) p->beta[k] /= q;
  }
  double wi[3] = {bs.wi.x, bs.wi.y, bs.wi.z};
  /* Whether the next hit's emission (and the sky on escape) counts: only
   * if no next-event estimate covered it, i.e. after the camera or a
   * deflecting delta lobe.  Straight transmission through a pane changes
   * nothing: next-event shadow rays cross panes too, so a path going on
   * straight after a diffuse vertex must not count the sky again. */
  if (bs.lobe != VR_LOBE_STRAIGHT) {
    /* A BSDF XML window's patches are as narrow as 0.02 sr around the
     * straight-through direction, which a sky sample seldom finds: its
     * vertex has no next-event estimate for the sky and the emitters, and
     * what its sampled direction hits counts instead. */
    if ((bs.lobe & VR_LOBE_DELTA) ||
        (vr_bsdf_is_klems(se->b) && !(p->flags & VR_PF_CAUSTIC_TAKEN)))
      p->flags |= VR_PF_SPECULAR_LAST;
    else
      p->flags &= (uint16_t)~VR_PF_SPECULAR_LAST;
    /* The sun's disc has no next-event estimate from the eye's side of a
     * non-delta vertex only where it is a delta light: past any such
     * vertex its light arrives by the sun's own samples. */
    if (!(bs.lobe & VR_LOBE_DELTA)) p->flags &= (uint16_t)~VR_PF_SEES_SUN;
  }
  /* What a BSDF XML layer reflects towards a sensor is reflected light
   * (what it transmits keeps its component, vr_path_closest). */
  if (vr_bsdf_is_klems(se->b) && (bs.lobe & VR_LOBE_GLOSSY_R) && p->target == VR_TARGET_SENSOR) {
    p->flags |= VR_PF_REFLECTED;
    if (rs->obj[hit->object].outside)
      p->flags |= VR_PF_OUTSIDE_LAST;
    else
      p->flags &= (uint16_t)~VR_PF_OUTSIDE_LAST;
  }
  if (bs.lobe & (VR_LOBE_SPECULAR_T | VR_LOBE_GLOSSY_T))
    p->medium = vr_dot3(wi, hit->ng) < 0 ? (int32_t)hit->object : -1;
  if (c->rs->ntex) vr_cone_advance(p, hit->t, bs.lobe);
  p->holes = 0;
  p->depth++;
  vr_ray r = {0};
  vr_spawn_origin(hit->p, hit->ng, wi, r.org);
  memcpy(r.dir, wi, sizeof r.dir);
  r.tmax = INFINITY;
  r.kind = VR_RAY_CLOSEST;
  r.purpose = p->target == VR_TARGET_SENSOR ? VR_PURPOSE_SENSOR : VR_PURPOSE_CAMERA;
  memcpy(r.payload, p, sizeof *p);
  vr_flow_push(w, &r);
  return true;
}

void vr_path_absorb(const vr_rscene *rs, vr_payload *p, const vr_hit *hit) {
  if (p->medium < 0) return;
  const vr_bsdf *mb = rs->mat[rs->obj[p->medium].material].bsdf;
  for (int k = 0; k < p->nwl; k++) p->beta[k] *= exp(-vr_bsdf_medium_sigma_a(mb, p->wl[k]) * hit->t);
}

vr_surface vr_path_surface(const vr_rscene *rs, const vr_payload *p, const vr_hit *hit,
                           const double wo[3]) {
  const vr_rmaterial *m = &rs->mat[rs->obj[hit->object].material];
  vr_surface se = {m->bsdf, vr_hit_state(rs, hit), vr_vec3_of(hit->ns), vr_vec3_of(wo),
                   p->nwl, p->wl, vr_vec3_of(hit->ns), false, {0}, vr_bsdf_point_plain(), false,
                   vr_vec3_of(hit->ng)};
  if (!m->tex && !m->nmap && !m->mrmap && !m->vcol) return se;
  /* The footprint on the surface: the cone's width, stretched by the
   * incidence (at most 20 times, near grazing). */
  double width = (double)p->cone_w + hit->t * (double)p->cone_a, nsn[3];
  width /= fmax(fabs(vr_dot3(wo, hit->ng)), 0.05);
  if (vr_bsdf_is_pbr(m->bsdf))
    vr_hit_pbr(rs, hit, width, p->nwl, p->wl, &se.pt);
  else
    se.tinted = vr_hit_texture(rs, hit, width, p->nwl, p->wl, se.tint);
  if (m->nmap && vr_hit_normal_map(rs, hit, width, nsn)) se.n = se.ns = vr_vec3_of(nsn), se.bent = true;
  return se;
}

/* The key depth of a see-through test: the path's depth and the holes
 * passed since its last vertex (the same whatever the sub-domains), in a
 * range no other use of the depth reaches; shadow rays apart. */
static uint32_t alpha_key(const vr_payload *p, bool shadow) {
  return 0x40000000u | (shadow ? 0x20000000u : 0) | (uint32_t)p->depth << 8 | p->holes;
}

void vr_cone_advance(vr_payload *p, double t, unsigned lobe) {
  p->cone_w = (float)((double)p->cone_w + t * (double)p->cone_a);
  if (!(lobe & VR_LOBE_DELTA)) p->cone_a = (float)((double)p->cone_a + VR_CONE_SPREAD_SCATTER);
}

bool vr_path_pass_through(vr_pass *c, vr_flow_worker *w, const vr_ray *r, const vr_hit *hit) {
  const vr_rscene *rs = c->rs;
  if (!vr_rmaterial_cuts(&rs->mat[rs->obj[hit->object].material])) return false;
  vr_payload p;
  memcpy(&p, r->payload, sizeof p);
  vr_rng_key key = {rs->seed, p.stream, p.sample, alpha_key(&p, false)};
  if (!vr_hit_cut_out(rs, hit, vr_rng(&key, VR_DIM_ALPHA))) return false;
  if (p.holes < 255) p.holes++;
  /* On through the hole, as if nothing were there. */
  vr_path_absorb(rs, &p, hit);
  vr_cone_advance(&p, hit->t, VR_LOBE_STRAIGHT);
  if (p.flags & VR_PF_PORTAL_PATH) p.portal_t -= hit->t;
  /* A new ray from the hole: the flow's own fields (the cell, tnear moved
   * to a hand-over, the crossings) belong to the old one. */
  vr_ray n = {0};
  vr_spawn_origin(hit->p, hit->ng, r->dir, n.org);
  memcpy(n.dir, r->dir, sizeof n.dir);
  n.tmax = isinf(r->tmax) ? r->tmax : r->tmax - hit->t;
  n.kind = r->kind;
  n.purpose = r->purpose;
  memcpy(n.payload, &p, sizeof p);
  vr_flow_push(w, &n);
  return true;
}

void vr_path_closest(void *ctx, vr_flow_worker *w, const vr_ray *r, const vr_hit *hit) {
  vr_pass *c = ctx;
  const vr_rscene *rs = c->rs;
  vr_payload p;
  memcpy(&p, r->payload, sizeof p);
  double L[VR_MAX_WL] = {0};
  bool first = (p.flags & VR_PF_SPECULAR_LAST) != 0;
  if (!hit) {
    vr_lights_environment(&rs->L, r->dir, first, p.nwl, p.wl, L);
    for (int k = 0; k < p.nwl; k++) L[k] *= p.beta[k];
    p.source = r->dir[2] >= 0 ? VR_SRC_SKY : VR_SRC_GROUND;
    p.patch = (uint8_t)vr_sky_patch_of(r->dir);
    if (vr_features_wanted(c, &p)) vr_features_escape(c, &p);
    vr_path_deliver(c, &p, L);
    /* The sun's disc, seen by the eye straight or through delta lobes. */
    if ((p.flags & VR_PF_SEES_SUN) && p.target == VR_TARGET_PIXEL && rs->sun_disc &&
        vr_lights_sun_disc(&rs->L, r->dir, p.nwl, p.wl, L)) {
      for (int k = 0; k < p.nwl; k++) L[k] *= p.beta[k];
      p.source = VR_SRC_SUN;
      p.patch = VR_NO_PATCH;
      vr_path_deliver(c, &p, L);
    }
    return;
  }
  if (vr_path_pass_through(c, w, r, hit)) return;
  const vr_robject *o = &rs->obj[hit->object];
  vr_path_absorb(rs, &p, hit);
  double wo[3] = {-r->dir[0], -r->dir[1], -r->dir[2]};
  const vr_rspd *emission = vr_rscene_emission(rs, (uint32_t)hit->object);
  if (emission && first && vr_dot3(hit->ng, wo) > 0) {
    for (int k = 0; k < p.nwl; k++) L[k] = p.beta[k] * vr_rspd_at(emission, p.wl[k]);
    vr_payload pe = p;
    pe.source = VR_SRC_LAMP;
    vr_path_deliver(c, &pe, L);
  }
  vr_surface se = vr_path_surface(rs, &p, hit, wo);
  unsigned lobes = vr_bsdf_lobes(se.b);
  bool diffuse = lobes & VR_LOBE_DIFFUSE;
  bool nondelta = lobes & (VR_LOBE_DIFFUSE | VR_LOBE_GLOSSY_R | VR_LOBE_GLOSSY_T);
  if (nondelta && vr_features_wanted(c, &p)) vr_features_hit(c, &p, hit, &se);
  if (nondelta && p.target == VR_TARGET_SENSOR && !vr_bsdf_is_klems(se.b)) {
    /* This vertex reflects what reaches the sensor from here on.  A BSDF
     * XML window does not: light it transmits keeps its component (the sky
     * seen through a window is the sky component), as through a pane; its
     * reflections are marked when sampled (continue_path).  The sun it
     * passes to the sensor by its next-event estimate counts as sun, even
     * through a diffusing shade. */
    p.flags |= VR_PF_REFLECTED;
    if (o->outside)
      p.flags |= VR_PF_OUTSIDE_LAST;
    else
      p.flags &= (uint16_t)~VR_PF_OUTSIDE_LAST;
  }
  /* After a photon sensor's sparse vertex took the caustic map, light
   * through a BSDF XML layer is the map's: none estimated here. */
  bool klems = vr_bsdf_is_klems(se.b);
  if (nondelta && !(klems && (p.flags & VR_PF_CAUSTIC_TAKEN))) {
    double nsky[3];
    memcpy(nsky, hit->ng, sizeof nsky);
    if (!(lobes & VR_LOBE_GLOSSY_T) && vr_dot3(nsky, wo) < 0)
      for (int a = 0; a < 3; a++) nsky[a] = -nsky[a];
    vr_path_next_event(c, w, &p, hit->p, hit->ng, (lobes & VR_LOBE_GLOSSY_T) ? NULL : nsky,
                       vr_surface_f, &se, 1000u + p.depth, klems);
  }
  if (diffuse && c->at_diffuse && c->at_diffuse(c, w, &p, hit, &se, wo)) {
    /* The integrator took the diffuse part; a pbr surface's specular part
     * goes on by sampling. */
    if (!(lobes & ~(unsigned)VR_LOBE_DIFFUSE)) return;
    se.pt.only = lobes & ~(unsigned)VR_LOBE_DIFFUSE;
  }
  continue_path(c, w, &p, hit, &se);
}

bool vr_path_shadow_hit(void *ctx, vr_flow_worker *w, vr_ray *r, const vr_hit *hit) {
  (void)w;
  vr_pass *c = ctx;
  const vr_rscene *rs = c->rs;
  const vr_rmaterial *m = &rs->mat[rs->obj[hit->object].material];
  vr_payload *p = (vr_payload *)r->payload;
  if (vr_rmaterial_cuts(m)) {
    vr_rng_key key = {rs->seed, p->stream, p->sample, alpha_key(p, true)};
    bool through = vr_hit_cut_out(rs, hit, vr_rng(&key, VR_DIM_ALPHA));
    if (p->holes < 255) p->holes++;
    if (through) return true;
  }
  double T[VR_BSDF_MAX_WAVELENGTHS];
  double cs = vr_dot3(r->dir, hit->ng);
  if (!vr_bsdf_straight_transmittance(m->bsdf, vr_hit_state(rs, hit), cs, p->nwl, p->wl, T))
    return false;
  bool any = false;
  for (int k = 0; k < p->nwl; k++) any |= (p->beta[k] *= T[k]) > 0;
  return any;
}

void vr_path_shadow_done(void *ctx, vr_flow_worker *w, const vr_ray *r, bool reached) {
  (void)w;
  if (!reached) return;
  vr_payload p;
  memcpy(&p, r->payload, sizeof p);
  vr_path_deliver(ctx, &p, p.beta);
}

/* Camera unit: one tile of the image (vr_flow_tile), one wave of its
 * samples.  A sample's random numbers are keyed by its pixel and sample
 * index only, so the cut into units changes nothing in the image. */
void vr_camera_generate(void *ctx, vr_flow_worker *w, long unit) {
  vr_pass *c = ctx;
  const vr_rscene *rs = c->rs;
  const vr_camera *cam = &rs->cam;
  int W = cam->W, H = cam->H, x0, y0, x1, y1;
  /* Wave w makes samples w wave_spp .. (w + 1) wave_spp - 1, so the rays a
   * unit puts in flight are bounded whatever the spp. */
  long tiles = vr_flow_tiles(W, H);
  int wave_spp = c->wave_spp > 0 ? c->wave_spp : c->spp;
  int s0 = (int)(unit / tiles) * wave_spp, s1 = s0 + wave_spp < c->spp ? s0 + wave_spp : c->spp;
  vr_flow_tile(W, H, unit % tiles, &x0, &y0, &x1, &y1);
  int tw = x1 - x0, npix = tw * (y1 - y0);
  for (int i = 0; i < npix; i++) {
    int x = x0 + i % tw, y = y0 + i / tw;
    uint32_t pixel = (uint32_t)(y * W + x);
    if (c->active && !c->active[pixel]) continue;
    for (int s = s0; s < s1; s++) {
      vr_payload p = {0};
      p.stream = pixel;
      p.sample = (uint32_t)(s + c->sample_offset);
      p.index = pixel;
      p.target = VR_TARGET_PIXEL;
      /* The camera sees emitters, the sky and the sun's disc directly. */
      p.flags = VR_PF_SPECULAR_LAST | VR_PF_SEES_SUN;
      p.nwl = (uint8_t)rs->nwl;
      p.medium = -1;
      vr_rng_key key = {rs->seed, p.stream, p.sample, 0};
      if (c->fixed_wl)
        memcpy(p.wl, c->fixed_wl, sizeof p.wl); /* the iteration's, shared with the photons */
      else
        vr_wavelengths(rs, &key, (uint32_t)c->spp, p.wl);
      p.weight = c->sum_samples ? 1.0 : 1.0 / (c->weight_spp > 0 ? c->weight_spp : c->spp);
      for (int k = 0; k < p.nwl; k++) p.beta[k] = 1.0;
      /* The pixel filter places the sample and weighs it (vr/filter.h). */
      double fdx, fdy;
      p.weight *= vr_filter_sample(&cam->sc->filter, &key, (uint32_t)s, (uint32_t)c->spp, &fdx, &fdy);
      vr_ray r = {0};
      if (!cam->ops->generate(cam, x + 0.5 + fdx, y + 0.5 + fdy, &key, r.org, r.dir)) continue;
      if (rs->ntex) {
        /* The ray cone of a pixel: the angle to the next pixel's ray. */
        double o2[3], d2[3];
        if (cam->ops->generate(cam, x + 1.5 + fdx, y + 0.5 + fdy, &key, o2, d2))
          p.cone_a = (float)acos(fmax(-1.0, fmin(1.0, vr_dot3(r.dir, d2))));
      }
      r.tmax = INFINITY;
      r.kind = VR_RAY_CLOSEST;
      r.purpose = VR_PURPOSE_CAMERA;
      memcpy(r.payload, &p, sizeof p);
      vr_flow_push(w, &r);
    }
  }
}

const vr_flow_ops vr_camera_path_ops = {vr_path_closest, vr_path_shadow_hit, vr_path_shadow_done,
                                   vr_camera_generate, VR_PAYLOAD_WIRE};

/* The camera pass's units: each tile in waves of at most CAMERA_WAVE_RAYS
 * camera rays (unit = wave x tiles + tile), so the rays in flight, and the
 * memory, do not grow with the samples per pixel.  Smaller waves would make
 * the units the same size at any spp, but cost speed (waves of 1024 and
 * 4096 rays: 2 ranks 15 % and 7 % slower on the sample room at 64 spp);
 * the flow instead leaves a unit's room below its cap (docs/ddm.md, "Queue
 * memory"). */
enum { CAMERA_WAVE_RAYS = 16384 };

vr_status vr_camera_pass(vr_run *r, vr_pass *c, const vr_flow_ops *ops, int W, int H,
                         vr_error *err) {
  long tiles = vr_flow_tiles(W, H);
  c->wave_spp = CAMERA_WAVE_RAYS / (VR_FLOW_TILE * VR_FLOW_TILE);
  if (c->wave_spp < 1) c->wave_spp = 1;
  if (c->wave_spp > c->spp) c->wave_spp = c->spp;
  long waves = (c->spp + c->wave_spp - 1) / c->wave_spp;
  return vr_run_flow(r, ops, c, tiles * waves, "camera", err);
}
