/* The camera-side integrators as callbacks of the ray flow: camera and
 * sensor paths, shadow rays, final-gather rays, and the UV pass of
 * photochromic glass.
 *
 * One vertex, whatever the integrator:
 *   - emission is counted where no next-event estimate could have found it:
 *     at the first vertex and after a delta lobe (mirror, refraction, pane);
 *   - at a vertex with a non-delta lobe, next-event estimation sends one
 *     shadow ray to each delta light (point, spot, sun), one to an emissive
 *     surface and one to the sky; shadow rays cross thin elements (panes,
 *     chromogenic glass, measured glazing) with their straight
 *     transmittance, so sunlight through a window is direct light;
 *   - the sky is reached only by next-event estimation after a non-delta
 *     lobe (no double counting); the ground glow below the horizon only by
 *     escaping rays;
 *   - then by integrator: the path tracer samples the BSDF and goes on; the
 *     Whitted integrator stops at the first diffuse vertex (the paper's
 *     local illumination: direct light plus specular chains); the photon
 *     integrators add the caustic map and either the global map or final
 *     gathering there and stop.
 * Glossy (GGX) vertices always continue by sampling, with next-event
 * estimation at each. */
#include <math.h>
#include <stdatomic.h>
#include <string.h>

#include "render_internal.h"
#include "sppm.h"
#include "vr/fisheye.h"

static double dot3(const double a[3], const double b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static vr_vec3 v3(const double a[3]) { return (vr_vec3){a[0], a[1], a[2]}; }

static double offset_scale(const double p[3]) {
  double m = fmax(fabs(p[0]), fmax(fabs(p[1]), fabs(p[2])));
  return 1e-5 * (1.0 + m);
}

/* Origin just off the surface on the side of dir. */
static void spawn_origin(const double p[3], const double ng[3], const double dir[3],
                         double o[3]) {
  double e = offset_scale(p), s = dot3(ng, dir) >= 0 ? e : -e;
  for (int a = 0; a < 3; a++) o[a] = p[a] + s * ng[a];
}

double vr_hit_state(const rscene *rs, const vr_hit *hit) {
  const robject *o = &rs->obj[hit->object];
  const double *map = o->nu ? vr_cell_state_map(rs, hit->cell, hit->object) : NULL;
  if (map) {
    int i = (int)(hit->uv[0] * o->nu), j = (int)(hit->uv[1] * o->nv);
    i = i < 0 ? 0 : i >= o->nu ? o->nu - 1 : i;
    j = j < 0 ? 0 : j >= o->nv ? o->nv - 1 : j;
    return map[j * o->nu + i];
  }
  return rs->mat[o->material].state;
}

static double wl_weight(const rscene *rs, int nwl) { return (rs->lmax - rs->lmin) / nwl; }

/* A sensor path's contribution v into its daylight component: the source
 * (p->source) and whether a non-delta vertex reflected it on the way
 * (FLAG_REFLECTED), the last one exterior or not (FLAG_OUTSIDE_LAST).  The
 * ground glow is an exterior reflection by definition; its radiance is
 * split between the sun and the sky wavelength by wavelength. */
static void sensor_parts(pass_ctx *c, const payload *p, const double *v, double lx) {
  const rscene *rs = c->rs;
  bool reflected = p->flags & FLAG_REFLECTED, outside = p->flags & FLAG_OUTSIDE_LAST;
  int erc_or_irc = !reflected || outside ? VR_PART_ERC_SKY : VR_PART_IRC_SKY;
  switch (p->source) {
  case SRC_LAMP: vr_accum_sensor_part_lx(c->acc, p->index, VR_PART_ELECTRIC, lx); break;
  case SRC_SKY:
    vr_accum_sensor_part_lx(c->acc, p->index, reflected ? erc_or_irc : VR_PART_SKY, lx);
    if (p->patch != NO_PATCH) vr_accum_sensor_patch_lx(c->acc, p->index, p->patch, lx);
    break;
  case SRC_SUN:
    vr_accum_sensor_part_lx(c->acc, p->index, reflected ? erc_or_irc + 1 : VR_PART_SUN, lx);
    break;
  case SRC_GROUND: {
    double sun[VR_MAX_WL], sky[VR_MAX_WL], w = wl_weight(rs, p->nwl);
    for (int k = 0; k < p->nwl; k++) {
      double f = vr_light_ground_sun_share(rs, p->wl[k]);
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

/* Delivers a finished contribution to what the path serves. */
static void deliver(pass_ctx *c, const payload *p, const double *v0) {
  double v[VR_MAX_WL];
  for (int k = 0; k < p->nwl; k++) v[k] = v0[k] * p->weight;
  switch (p->target) {
  case TARGET_PIXEL:
  case TARGET_GATHER:
    vr_accum_pixel(c->acc, p->index, p->nwl, p->wl, v, wl_weight(c->rs, p->nwl));
    break;
  case TARGET_SENSOR: {
    /* Photon sensors keep their second half of slots for the bias probe. */
    uint32_t slot = c->sensor_photons ? p->sample % (uint32_t)c->sensor_groups : p->sample;
    double lx = vr_accum_sensor(c->acc, p->index, slot, p->nwl, p->wl, v, wl_weight(c->rs, p->nwl));
    sensor_parts(c, p, v, lx);
    break;
  }
  case TARGET_TEXEL: {
    /* UV band integral: wavelengths uniform over 300-400 nm. */
    double s = 0;
    for (int k = 0; k < p->nwl; k++) s += v[k];
    vr_atomic_add(&c->acc->texel_uv[p->index], s * 100.0 / p->nwl);
    if ((p->source == SRC_SKY || p->source == SRC_GROUND) && p->patch != NO_PATCH)
      vr_atomic_add(&c->acc->texel_patches[(size_t)p->index * VR_SENSOR_PATCHES + p->patch],
                    s * 100.0 / p->nwl);
    break;
  }
  default: break;
  }
}

/* A shadow ray from x (offset to o) towards the light dist away along dir. */
static void push_shadow(vr_flow_worker *w, const payload *p, const double x[3], const double o[3],
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
  r.purpose = PURPOSE_SHADOW;
  payload *q = (payload *)r.payload;
  *q = *p;
  q->source = source;
  q->patch = source == SRC_SKY ? (uint8_t)vr_sky_patch_of(r.dir) : NO_PATCH;
  memcpy(q->beta, contrib, sizeof q->beta);
  vr_flow_push(w, &r);
}

/* Next-event estimation at x: f(wi) supplies BSDF times |cos| per wl. */
typedef void (*bsdf_cos_fn)(const void *u, const double wi[3], double *fc);

static void next_event(pass_ctx *c, vr_flow_worker *w, const payload *p, const double x[3],
                       const double ng[3], const double *n_for_sky, bsdf_cos_fn f,
                       const void *fu, uint32_t depth_key) {
  const rscene *rs = c->rs;
  vr_rng_key key = {rs->seed, p->stream, p->sample, depth_key};
  light_sample ls;
  double fc[VR_MAX_WL], contrib[VR_MAX_WL], o[3];
  for (size_t i = 0; i < rs->nlights; i++) {
    vr_rng_key k2 = key;
    k2.depth = depth_key * 64 + (uint32_t)i + 1;
    if (!vr_light_sample_delta(rs, i, x, p->nwl, p->wl, &k2, &ls)) continue;
    f(fu, ls.dir, fc);
    bool any = false;
    for (int k = 0; k < p->nwl; k++) any |= (contrib[k] = p->beta[k] * fc[k] * ls.L[k]) > 0;
    if (!any) continue;
    spawn_origin(x, ng, ls.dir, o);
    push_shadow(w, p, x, o, ls.dir, ls.dist, contrib,
                rs->lights[i].kind == VR_LIGHT_SUN ? SRC_SUN : SRC_LAMP);
  }
  if (vr_light_sample_emitter(rs, x, p->nwl, p->wl, &key, &ls)) {
    f(fu, ls.dir, fc);
    bool any = false;
    for (int k = 0; k < p->nwl; k++) any |= (contrib[k] = p->beta[k] * fc[k] * ls.L[k]) > 0;
    if (any) {
      spawn_origin(x, ng, ls.dir, o);
      push_shadow(w, p, x, o, ls.dir, ls.dist, contrib, SRC_LAMP);
    }
  }
  if (vr_light_sample_sky(rs, x, n_for_sky, p->nwl, p->wl, &key, &ls)) {
    f(fu, ls.dir, fc);
    bool any = false;
    for (int k = 0; k < p->nwl; k++) any |= (contrib[k] = p->beta[k] * fc[k] * ls.L[k]) > 0;
    if (any) {
      spawn_origin(x, ng, ls.dir, o);
      push_shadow(w, p, x, o, ls.dir, INFINITY, contrib, SRC_SKY);
    }
  }
}

typedef struct surf_eval {
  const vr_bsdf *b;
  double state;
  vr_vec3 n, wo;
  int nwl;
  const double *wl;
  vr_vec3 ns;
} surf_eval;

static void surf_f(const void *u, const double wi[3], double *fc) {
  const surf_eval *s = u;
  double f[VR_BSDF_MAX_WAVELENGTHS], pdf;
  vr_vec3 w = v3(wi);
  vr_bsdf_eval(s->b, s->state, s->n, s->wo, w, s->nwl, s->wl, VR_TRANSPORT_RADIANCE, f, &pdf);
  double c = fabs(s->ns.x * w.x + s->ns.y * w.y + s->ns.z * w.z);
  for (int k = 0; k < s->nwl; k++) fc[k] = f[k] * c;
}

/* A sensor is a cosine receiver: "BSDF times cos" is cos on its front side. */
static void sensor_f(const void *u, const double wi[3], double *fc) {
  const double *n = u;
  double c = dot3(n, wi);
  for (int k = 0; k < VR_MAX_WL; k++) fc[k] = c > 0 ? c : 0.0;
}

/* The share of a density estimate's disc (radius r about x, weighted by the
 * cone filter of constant kc, or uniformly for kc <= 0) that lies on the
 * rectangle of frame f (p = corner + u eu + v ev, u and v in [0, 1]).  A
 * disc reaching past the rectangle's edge holds that surface's photons
 * over only this share of its area, so the estimate, which divides by the
 * whole disc, reads low by this factor near walls' and floors' edges and
 * corners.  In polar coordinates about x: along each of 128 directions the
 * rectangle ends at distance t, and the filter's integral out to s =
 * min(t, r) is s^2/2 - s^3/(3 kc r) (s^2/2 for the box).  Returns 1 for a
 * parallelogram that is not a rectangle. */
static double rect_disc_share(const double f[9], const double x[3], double r, double kc) {
  double Lu = sqrt(dot3(f + 3, f + 3)), Lv = sqrt(dot3(f + 6, f + 6));
  if (!(Lu > 0) || !(Lv > 0) || !(r > 0) || fabs(dot3(f + 3, f + 6)) > 1e-9 * Lu * Lv) return 1.0;
  double d[3] = {x[0] - f[0], x[1] - f[1], x[2] - f[2]};
  double cx = dot3(d, f + 3) / Lu, cy = dot3(d, f + 6) / Lv;
  cx = cx < 0 ? 0 : cx > Lu ? Lu : cx;
  cy = cy < 0 ? 0 : cy > Lv ? Lv : cy;
  enum { DIRS = 128 };
  double full = kc > 0 ? r * r / 2 - r * r / (3 * kc) : r * r / 2, sum = 0;
  for (int i = 0; i < DIRS; i++) {
    double ph = (i + 0.5) * (2 * M_PI / DIRS), cu = cos(ph), sv = sin(ph), t = r;
    if (cu > 0 && (Lu - cx) / cu < t) t = (Lu - cx) / cu;
    if (cu < 0 && -cx / cu < t) t = -cx / cu;
    if (sv > 0 && (Lv - cy) / sv < t) t = (Lv - cy) / sv;
    if (sv < 0 && -cy / sv < t) t = -cy / sv;
    sum += kc > 0 ? t * t / 2 - t * t * t / (3 * kc * r) : t * t / 2;
  }
  double share = sum / DIRS / full;
  return share < 0.05 ? 0.05 : share > 1 ? 1 : share;
}

/* Irradiance at x on object `surface` from the photons of that object only:
 * a floor's estimate never takes the ground's photons from beyond the
 * wall, which share its plane and side (vr_photon_map_store_on). */
static int photon_estimate_k(const pass_ctx *c, const vr_photon_set *ps, const double x[3],
                             const double n[3], uint32_t surface, int k, double radius, int nwl,
                             const double *wl, double *E) {
  /* Edge shares only for photon sensors' gathers: there they remove a 2 %
   * low bias (tests/render/test_photon_sensors.c), but in the camera
   * pass's direct reading of the maps they made the walls by the sample
   * room's east window read far brighter than the path tracer shows, for a
   * reason not yet found (see docs/vr-render.md, "Photon sensors"). */
  const bool edge_share = c->sensor_photons;
  for (int j = 0; j < nwl; j++) E[j] = 0;
  if (!ps || !vr_photon_set_count(ps)) return 0;
  const vr_photon_map *m = vr_photon_set_map(ps, 0); /* for its bins: all maps share them */
  int nb = vr_photon_map_nbins(m);
  double bins[512], r;
  if (nb > 512) return 0;
  int got = vr_photon_set_irradiance_on(ps, x, n, surface, c->fixed_radius ? 0 : k, radius, 1.1,
                                        bins, &r);
  if (got <= 0) return 0;
  /* On a rect, the disc's part beyond its edges held none of its photons. */
  const vr_scene_tables *t = c->rs->t;
  double share = edge_share && surface != VR_PHOTON_ANY_SURFACE && t->is_rect[surface]
                     ? rect_disc_share(t->rect_frame[surface], x, r, 1.1)
                     : 1.0;
  for (int j = 0; j < nwl; j++) {
    int b = vr_photon_map_bin(m, wl[j]);
    double lo, hi;
    if (b < 0 || !vr_photon_map_bin_range(m, b, &lo, &hi)) continue;
    E[j] = bins[b] * c->photon_scale / (hi - lo) / share;
  }
  return got;
}

static void photon_estimate(const pass_ctx *c, const vr_photon_set *ps, const double x[3],
                            const double n[3], uint32_t surface, int nwl, const double *wl,
                            double *E) {
  (void)photon_estimate_k(c, ps, x, n, surface, c->knn, c->radius, nwl, wl, E);
}

/* Radiance towards wo of a diffuse hit from the three photon maps
 * (restricted to the hit's object), times beta: rho/pi E for the
 * neighbourhood of k photons (or the fixed radius). */
enum { MAP_DIRECT = 1, MAP_CAUSTIC = 2, MAP_GLOBAL = 4 };
static void photon_radiance(const pass_ctx *c, const vr_hit *hit, const double wo[3],
                            const void *se_, const payload *p, int maps, int k, double radius,
                            double *L, int *got_global);

/* Continues a path by sampling the BSDF; returns false when it ends. */
static bool continue_path(pass_ctx *c, vr_flow_worker *w, payload *p, const vr_hit *hit,
                          const surf_eval *se, const double dir_in[3]) {
  const rscene *rs = c->rs;
  if (p->depth + 1 >= c->max_depth) return false;
  vr_rng_key key = {rs->seed, p->stream, p->sample, p->depth};
  vr_bsdf_sample bs;
  if (!vr_bsdf_sample_dir(se->b, se->state, se->n, se->wo, p->nwl, p->wl, VR_TRANSPORT_RADIANCE,
                          vr_rng(&key, VR_DIM_LOBE), vr_rng(&key, VR_DIM_DIR_U),
                          vr_rng(&key, VR_DIM_DIR_V), &bs))
    return false;
  /* The factor nwl of a dispersive refraction stands for the secondary
   * wavelengths it ends: once only. */
  if (bs.terminate_secondary && (p->flags & FLAG_TERMINATED)) bs.weight[0] /= p->nwl;
  double mx = 0;
  for (int k = 0; k < p->nwl; k++) {
    p->beta[k] *= bs.weight[k];
    if (p->beta[k] > mx) mx = p->beta[k];
  }
  if (!(mx > 0)) return false;
  if (bs.terminate_secondary) p->flags |= FLAG_TERMINATED;
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
    if (bs.lobe & VR_LOBE_DELTA)
      p->flags |= FLAG_SPECULAR_LAST;
    else
      p->flags &= (uint8_t)~FLAG_SPECULAR_LAST;
  }
  if (bs.lobe & (VR_LOBE_SPECULAR_T | VR_LOBE_GLOSSY_T))
    p->medium = dot3(wi, hit->ng) < 0 ? (int32_t)hit->object : -1;
  (void)dir_in;
  p->depth++;
  vr_ray r = {0};
  spawn_origin(hit->p, hit->ng, wi, r.org);
  memcpy(r.dir, wi, sizeof r.dir);
  r.tmax = INFINITY;
  r.kind = VR_RAY_CLOSEST;
  r.purpose = p->target == TARGET_SENSOR ? PURPOSE_SENSOR : PURPOSE_CAMERA;
  memcpy(r.payload, p, sizeof *p);
  vr_flow_push(w, &r);
  return true;
}

/* maps: MAP_* bits; *got_global (may be NULL) gets the photons the global
 * map's estimate used. */
static void photon_radiance(const pass_ctx *c, const vr_hit *hit, const double wo[3],
                            const void *se_, const payload *p, int maps, int k, double radius,
                            double *L, int *got_global) {
  const surf_eval *se = se_;
  double n[3];
  memcpy(n, hit->ng, sizeof n);
  if (dot3(n, wo) < 0)
    for (int a = 0; a < 3; a++) n[a] = -n[a];
  double E[VR_MAX_WL], Et[VR_MAX_WL] = {0}, fc[VR_MAX_WL];
  const vr_photon_set *set[3] = {c->direct, c->caustic, c->global};
  for (int i = 0; i < 3; i++) {
    if (!(maps >> i & 1)) continue;
    int got = photon_estimate_k(c, set[i], hit->p, n, (uint32_t)hit->object, k, radius, p->nwl,
                                p->wl, E);
    if (i == 2 && got_global) *got_global = got;
    for (int j = 0; j < p->nwl; j++) Et[j] += E[j];
  }
  double refl[3] = {2 * dot3(n, wo) * n[0] - wo[0], 2 * dot3(n, wo) * n[1] - wo[1],
                    2 * dot3(n, wo) * n[2] - wo[2]};
  surf_f(se, refl, fc);
  double cs = fabs(dot3(hit->ns, refl));
  for (int j = 0; j < p->nwl; j++) L[j] = p->beta[j] * (cs > 0 ? fc[j] / cs : 0) * Et[j];
}

static void on_closest(void *ctx, vr_flow_worker *w, const vr_ray *r, const vr_hit *hit) {
  pass_ctx *c = ctx;
  const rscene *rs = c->rs;
  payload p;
  memcpy(&p, r->payload, sizeof p);
  double L[VR_MAX_WL] = {0};
  bool first = (p.flags & FLAG_SPECULAR_LAST) != 0;
  if (!hit) {
    vr_light_environment(rs, r->dir, first && p.target != TARGET_GATHER, p.nwl, p.wl, L);
    for (int k = 0; k < p.nwl; k++) L[k] *= p.beta[k];
    p.source = r->dir[2] >= 0 ? SRC_SKY : SRC_GROUND;
    p.patch = (uint8_t)vr_sky_patch_of(r->dir);
    deliver(c, &p, L);
    return;
  }
  const robject *o = &rs->obj[hit->object];
  const rmaterial *m = &rs->mat[o->material];
  if (p.medium >= 0) {
    const vr_bsdf *mb = rs->mat[rs->obj[p.medium].material].bsdf;
    for (int k = 0; k < p.nwl; k++)
      p.beta[k] *= exp(-vr_bsdf_medium_sigma_a(mb, p.wl[k]) * hit->t);
  }
  double wo[3] = {-r->dir[0], -r->dir[1], -r->dir[2]};
  if (o->emission.n && first && p.target != TARGET_GATHER && dot3(hit->ng, wo) > 0) {
    for (int k = 0; k < p.nwl; k++) L[k] = p.beta[k] * rspd_at(&o->emission, p.wl[k]);
    payload pe = p;
    pe.source = SRC_LAMP;
    deliver(c, &pe, L);
  }
  unsigned lobes = vr_bsdf_lobes(m->bsdf);
  surf_eval se = {m->bsdf, vr_hit_state(rs, hit), v3(hit->ns), v3(wo), p.nwl, p.wl, v3(hit->ns)};
  bool diffuse = lobes & VR_LOBE_DIFFUSE;
  bool nondelta = lobes & (VR_LOBE_DIFFUSE | VR_LOBE_GLOSSY_R | VR_LOBE_GLOSSY_T);

  if (p.target == TARGET_GATHER) {
    /* A final-gather ray: the photon maps' radiance at its first hit. */
    if (!diffuse) return;
    photon_radiance(c, hit, wo, &se, &p, MAP_DIRECT | MAP_CAUSTIC | MAP_GLOBAL, c->knn, c->radius,
                    L, NULL);
    deliver(c, &p, L);
    return;
  }
  if (nondelta && p.target == TARGET_SENSOR) {
    /* This vertex reflects what reaches the sensor from here on. */
    p.flags |= FLAG_REFLECTED;
    if (o->outside)
      p.flags |= FLAG_OUTSIDE_LAST;
    else
      p.flags &= (uint8_t)~FLAG_OUTSIDE_LAST;
  }
  if (nondelta) {
    double nsky[3];
    memcpy(nsky, hit->ng, sizeof nsky);
    if (!(lobes & VR_LOBE_GLOSSY_T) && dot3(nsky, wo) < 0)
      for (int a = 0; a < 3; a++) nsky[a] = -nsky[a];
    next_event(c, w, &p, hit->p, hit->ng, (lobes & VR_LOBE_GLOSSY_T) ? NULL : nsky, surf_f, &se,
               1000u + p.depth);
  }
  if (p.target == TARGET_SENSOR && (p.flags & FLAG_PHOTON_GATHER) && diffuse) {
    /* A photon sensor's diffuse vertex: direct light came from the
     * next-event estimate above; what arrives after a diffuse or specular
     * bounce comes from the global and caustic maps (this object's
     * photons), and the path ends there, if the global map is dense here:
     * k photons within the radius (final gathering, Jensen 2001 ch. 9).
     * Where it is not (a surface few photons reached), a disc of the
     * maximum radius would spread them over area the surface may not
     * have, so the path goes on as in the path estimator instead.
     * Beside the estimate, the same with a quarter of the photons (or half
     * the radius): a density estimate's bias grows as r^2 (the curvature
     * term), so the difference is 3/4 of the bias of the full estimate;
     * it goes to the point's probe slots (render_sensors.c). */
    int got = 0;
    photon_radiance(c, hit, wo, &se, &p, MAP_GLOBAL | MAP_CAUSTIC, c->knn, c->radius, L, &got);
    bool dense = c->fixed_radius ? got >= 16 : got >= c->knn;
    atomic_fetch_add_explicit(dense ? &c->fg_photon : &c->fg_path, 1, memory_order_relaxed);
    if (dense) {
      deliver(c, &p, L);
      double Ls[VR_MAX_WL], D[VR_MAX_WL];
      int ks = c->knn / 4 > 1 ? c->knn / 4 : 1;
      photon_radiance(c, hit, wo, &se, &p, MAP_GLOBAL | MAP_CAUSTIC, ks, 0.5 * c->radius, Ls, NULL);
      for (int k = 0; k < p.nwl; k++) D[k] = (L[k] - Ls[k]) * p.weight;
      int G = c->sensor_groups;
      vr_accum_sensor_lx(c->acc, p.index, (uint32_t)G + p.sample % (uint32_t)G, p.nwl, p.wl, D,
                         wl_weight(c->rs, p.nwl));
      return;
    }
    /* Sparse: the caustic map still adds what no path finds (the sun or a
     * lamp through a specular bounce); the path takes the rest. */
    photon_radiance(c, hit, wo, &se, &p, MAP_CAUSTIC, c->knn, c->radius, L, NULL);
    deliver(c, &p, L);
  }
  if (diffuse && p.target == TARGET_PIXEL && c->sppm) {
    /* SPPM: the next-event estimate above took the direct light; the
     * vertex is the pixel's visible point, where the photons of this
     * iteration add the rest (sppm.c). */
    double bw[VR_MAX_WL]; /* the sample's weight too: a pixel filter's negative lobes */
    for (int k = 0; k < p.nwl; k++) bw[k] = p.beta[k] * p.weight;
    vr_sppm_set_point(c->sppm, rs, p.index, hit->p, hit->ns, wo, o->material, se.state, p.nwl,
                      bw, (p.flags & FLAG_TERMINATED) != 0);
    return;
  }
  bool photon_mode = c->integrator == VR_INT_PHOTON || c->integrator == VR_INT_PROGRESSIVE;
  if (diffuse && p.target == TARGET_PIXEL &&
      (c->integrator == VR_INT_WHITTED || photon_mode)) {
    if (!photon_mode) return;
    double n[3];
    memcpy(n, hit->ng, sizeof n);
    if (dot3(n, wo) < 0)
      for (int a = 0; a < 3; a++) n[a] = -n[a];
    double refl[3], fc[VR_MAX_WL];
    for (int a = 0; a < 3; a++) refl[a] = 2 * dot3(n, wo) * n[a] - wo[a];
    surf_f(&se, refl, fc);
    double cs = fabs(dot3(hit->ns, refl)), fd[VR_MAX_WL];
    for (int k = 0; k < p.nwl; k++) fd[k] = cs > 0 ? fc[k] / cs : 0; /* rho / pi */
    double E[VR_MAX_WL], Et[VR_MAX_WL] = {0};
    photon_estimate(c, c->caustic, hit->p, n, (uint32_t)hit->object, p.nwl, p.wl, E);
    for (int k = 0; k < p.nwl; k++) Et[k] += E[k];
    if (!c->final_gather) {
      photon_estimate(c, c->global, hit->p, n, (uint32_t)hit->object, p.nwl, p.wl, E);
      for (int k = 0; k < p.nwl; k++) Et[k] += E[k];
    }
    for (int k = 0; k < p.nwl; k++) L[k] = p.beta[k] * fd[k] * Et[k];
    deliver(c, &p, L);
    if (c->final_gather && p.depth + 1 < c->max_depth) {
      /* Gather rays: cosine-weighted, each carrying beta rho / N. */
      double t[3], b[3];
      double s = copysign(1.0, n[2]), aa = -1.0 / (s + n[2]), cc = n[0] * n[1] * aa;
      t[0] = 1 + s * n[0] * n[0] * aa, t[1] = s * cc, t[2] = -s * n[0];
      b[0] = cc, b[1] = s + n[1] * n[1] * aa, b[2] = -n[1];
      vr_rng_key key = {c->rs->seed, p.stream, p.sample, 500u + p.depth};
      for (int g = 0; g < c->gather_rays; g++) {
        double u1 = vr_rng(&key, VR_DIM_GATHER + 2 * (uint32_t)g);
        double u2 = vr_rng(&key, VR_DIM_GATHER + 2 * (uint32_t)g + 1);
        double rr = sqrt(u1), ph = 2 * M_PI * u2, z = sqrt(fmax(0, 1 - u1));
        vr_ray gr = {0};
        for (int a = 0; a < 3; a++) gr.dir[a] = z * n[a] + rr * (cos(ph) * t[a] + sin(ph) * b[a]);
        spawn_origin(hit->p, hit->ng, gr.dir, gr.org);
        gr.tmax = INFINITY;
        gr.kind = VR_RAY_CLOSEST;
        gr.purpose = PURPOSE_GATHER;
        payload q = p;
        q.target = TARGET_GATHER;
        q.depth++;
        for (int k = 0; k < p.nwl; k++) q.beta[k] = p.beta[k] * fd[k] * M_PI / c->gather_rays;
        memcpy(gr.payload, &q, sizeof q);
        vr_flow_push(w, &gr);
      }
    }
    return;
  }
  continue_path(c, w, &p, hit, &se, r->dir);
}

static bool on_shadow_hit(void *ctx, vr_flow_worker *w, vr_ray *r, const vr_hit *hit) {
  (void)w;
  pass_ctx *c = ctx;
  const rscene *rs = c->rs;
  const rmaterial *m = &rs->mat[rs->obj[hit->object].material];
  payload *p = (payload *)r->payload;
  double T[VR_BSDF_MAX_WAVELENGTHS];
  double cs = dot3(r->dir, hit->ng);
  if (!vr_bsdf_straight_transmittance(m->bsdf, vr_hit_state(rs, hit), cs, p->nwl, p->wl, T))
    return false;
  bool any = false;
  for (int k = 0; k < p->nwl; k++) any |= (p->beta[k] *= T[k]) > 0;
  return any;
}

static void on_shadow_done(void *ctx, vr_flow_worker *w, const vr_ray *r, bool reached) {
  (void)w;
  if (!reached) return;
  payload p;
  memcpy(&p, r->payload, sizeof p);
  deliver(ctx, &p, p.beta);
}

/* Camera unit: one tile of the image (vr_flow_tile), one wave of its
 * samples.  A sample's random numbers are keyed by its pixel and sample index only, so
 * the cut into units changes nothing in the image. */
void vr_camera_generate(void *ctx, vr_flow_worker *w, long unit) {
  pass_ctx *c = ctx;
  const rscene *rs = c->rs;
  const vr_scene_camera *cam = &rs->s->camera;
  int W = cam->width, H = cam->height, x0, y0, x1, y1;
  double aspect = (double)H / W;
  /* A unit is one tile and one wave of its samples (camera_pass in
   * render.c): wave w makes samples w wave_spp .. (w + 1) wave_spp - 1, so
   * the rays a unit puts in flight are bounded whatever the spp. */
  long tiles = vr_flow_tiles(W, H);
  int wave_spp = c->wave_spp > 0 ? c->wave_spp : c->spp;
  int s0 = (int)(unit / tiles) * wave_spp, s1 = s0 + wave_spp < c->spp ? s0 + wave_spp : c->spp;
  vr_flow_tile(W, H, unit % tiles, &x0, &y0, &x1, &y1);
  int tw = x1 - x0, npix = tw * (y1 - y0);
  for (int i = 0; i < npix; i++) {
    int x = x0 + i % tw, y = y0 + i / tw;
    uint32_t pixel = (uint32_t)(y * W + x);
    for (int s = s0; s < s1; s++) {
      payload p = {0};
      p.stream = pixel;
      p.sample = (uint32_t)(s + c->sample_offset);
      p.index = pixel;
      p.target = TARGET_PIXEL;
      p.flags = FLAG_SPECULAR_LAST; /* the camera sees emitters and the sky directly */
      p.nwl = (uint8_t)rs->nwl;
      p.medium = -1;
      vr_rng_key key = {rs->seed, p.stream, p.sample, 0};
      if (c->sppm)
        memcpy(p.wl, c->sppm->wl, sizeof p.wl); /* the iteration's, shared with the photons */
      else
        vr_wavelengths(rs, &key, (uint32_t)c->spp, p.wl);
      p.weight = 1.0 / c->spp;
      for (int k = 0; k < p.nwl; k++) p.beta[k] = 1.0;
      /* The pixel filter places the sample and weighs it (vr/filter.h). */
      double fdx, fdy;
      p.weight *= vr_filter_sample(&cam->filter, &key, (uint32_t)s, (uint32_t)c->spp, &fdx, &fdy);
      double px = x + 0.5 + fdx, py = y + 0.5 + fdy;
      vr_ray r = {0};
      if (cam->model == VR_CAM_FISHEYE) {
        double d[3];
        if (!vr_fisheye_direction(cam, px, py, d)) continue; /* outside the image circle */
        for (int a = 0; a < 3; a++)
          r.dir[a] = d[2] * rs->cam_w[a] + d[0] * rs->cam_u[a] + d[1] * rs->cam_v[a];
      } else {
        double sx = (2 * px / W - 1) * rs->tan_half;
        double sy = (1 - 2 * py / H) * rs->tan_half * aspect;
        for (int a = 0; a < 3; a++) r.dir[a] = rs->cam_w[a] + sx * rs->cam_u[a] + sy * rs->cam_v[a];
      }
      memcpy(r.org, rs->cam_o, sizeof r.org);
      if (cam->model == VR_CAM_THINLENS && cam->aperture_m > 0) {
        /* Thin lens: the point on the plane of focus stays, the origin
         * moves over the lens disc (uniform by area). */
        double f = cam->focus_m, focus[3];
        for (int a = 0; a < 3; a++) focus[a] = r.org[a] + f * r.dir[a];
        double lr = cam->aperture_m * sqrt(vr_rng(&key, VR_DIM_LENS_U));
        double ph = 2 * M_PI * vr_rng(&key, VR_DIM_LENS_V);
        for (int a = 0; a < 3; a++) {
          r.org[a] += lr * (cos(ph) * rs->cam_u[a] + sin(ph) * rs->cam_v[a]);
          r.dir[a] = focus[a] - r.org[a];
        }
      }
      double l = sqrt(dot3(r.dir, r.dir));
      for (int a = 0; a < 3; a++) r.dir[a] /= l;
      r.tmax = INFINITY;
      r.kind = VR_RAY_CLOSEST;
      r.purpose = PURPOSE_CAMERA;
      memcpy(r.payload, &p, sizeof p);
      vr_flow_push(w, &r);
    }
  }
}

/* Sensor unit: one point, one batch of its samples. */
void vr_sensor_generate(void *ctx, vr_flow_worker *w, long unit) {
  pass_ctx *c = ctx;
  const rscene *rs = c->rs;
  int groups = c->sensor_photons ? c->sensor_groups : c->acc->groups;
  size_t point = (size_t)unit / (size_t)groups;
  int g = (int)(unit % groups);
  const double *x = c->points[point], *n = c->points[point] + 3;
  int per = (c->sensor_samples + groups - 1) / groups;
  for (int s = 0; s < per; s++) {
    payload p = {0};
    p.stream = 0x5E450000000ull + point;
    p.sample = (uint32_t)(g + s * groups);
    p.index = (uint32_t)point;
    p.target = TARGET_SENSOR;
    p.nwl = (uint8_t)rs->nwl;
    p.medium = -1;
    vr_rng_key key = {rs->seed, p.stream, p.sample, 0};
    vr_wavelengths(rs, &key, (uint32_t)(per * groups), p.wl);
    /* Each batch's illuminance is a mean over its own samples. */
    p.weight = 1.0 / per;
    for (int k = 0; k < p.nwl; k++) p.beta[k] = 1.0;
    next_event(c, w, &p, x, n, n, sensor_f, n, 0);
    /* Indirect: a cosine-weighted direction, weight cos/pdf = pi. */
    double t[3], b[3];
    double sg = copysign(1.0, n[2]), aa = -1.0 / (sg + n[2]), cc = n[0] * n[1] * aa;
    t[0] = 1 + sg * n[0] * n[0] * aa, t[1] = sg * cc, t[2] = -sg * n[0];
    b[0] = cc, b[1] = sg + n[1] * n[1] * aa, b[2] = -n[1];
    double u1 = vr_rng(&key, VR_DIM_DIR_U), u2 = vr_rng(&key, VR_DIM_DIR_V);
    double rr = sqrt(u1), ph = 2 * M_PI * u2, z = sqrt(fmax(0, 1 - u1));
    vr_ray r = {0};
    for (int a = 0; a < 3; a++) r.dir[a] = z * n[a] + rr * (cos(ph) * t[a] + sin(ph) * b[a]);
    spawn_origin(x, n, r.dir, r.org);
    r.tmax = INFINITY;
    r.kind = VR_RAY_CLOSEST;
    r.purpose = PURPOSE_SENSOR;
    payload q = p;
    for (int k = 0; k < q.nwl; k++) q.beta[k] = M_PI;
    q.depth = 1;
    if (c->sensor_photons) q.flags |= FLAG_PHOTON_GATHER;
    memcpy(r.payload, &q, sizeof q);
    vr_flow_push(w, &r);
  }
}

/* UV pass: one texel of a photochromic pane, both faces. */
static void uv_generate(void *ctx, vr_flow_worker *w, long unit) {
  pass_ctx *c = ctx;
  const rscene *rs = c->rs;
  uint32_t obj = c->texel_object[unit], ti = c->texel_index[unit];
  const robject *o = &rs->obj[obj];
  int i = (int)(ti % (uint32_t)o->nu), j = (int)(ti / (uint32_t)o->nu);
  double u = (i + 0.5) / o->nu, v = (j + 0.5) / o->nv, x[3];
  for (int a = 0; a < 3; a++) x[a] = o->corner[a] + u * o->eu[a] + v * o->ev[a];
  for (int side = 0; side < 2; side++) {
    double n[3];
    for (int a = 0; a < 3; a++) n[a] = side ? -o->normal[a] : o->normal[a];
    for (int s = 0; s < c->uv_sky_samples; s++) {
      payload p = {0};
      p.stream = 0x0F000000000ull + (uint64_t)unit;
      p.sample = (uint32_t)(side * c->uv_sky_samples + s);
      p.index = (uint32_t)unit;
      p.target = TARGET_TEXEL;
      p.nwl = (uint8_t)rs->nwl;
      p.medium = -1;
      vr_rng_key key = {rs->seed, p.stream, p.sample, 0};
      double h = vr_rng(&key, VR_DIM_WAVELENGTH) * 100.0;
      for (int k = 0; k < p.nwl; k++) p.wl[k] = 300.0 + fmod(h + k * 100.0 / p.nwl, 100.0);
      p.weight = 1.0 / c->uv_sky_samples;
      for (int k = 0; k < p.nwl; k++) p.beta[k] = 1.0;
      /* Every sample draws the lights and the sky; each carries 1/M. */
      next_event(c, w, &p, x, n, n, sensor_f, n, 0);
    }
  }
}

const vr_flow_ops vr_camera_ops = {on_closest, on_shadow_hit, on_shadow_done, vr_camera_generate};
const vr_flow_ops vr_sensor_ops = {on_closest, on_shadow_hit, on_shadow_done, vr_sensor_generate};
const vr_flow_ops vr_uv_ops = {on_closest, on_shadow_hit, on_shadow_done, uv_generate};
