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
#include <string.h>

#include "render_internal.h"

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

/* Delivers a finished contribution to what the path serves. */
static void deliver(pass_ctx *c, const payload *p, const double *v0) {
  double v[VR_MAX_WL];
  for (int k = 0; k < p->nwl; k++) v[k] = v0[k] * p->weight;
  switch (p->target) {
  case TARGET_PIXEL:
  case TARGET_GATHER:
    vr_accum_pixel(c->acc, p->index, p->nwl, p->wl, v, wl_weight(c->rs, p->nwl));
    break;
  case TARGET_SENSOR:
    vr_accum_sensor(c->acc, p->index, p->sample, p->nwl, p->wl, v, wl_weight(c->rs, p->nwl));
    break;
  case TARGET_TEXEL: {
    /* UV band integral: wavelengths uniform over 300-400 nm. */
    double s = 0;
    for (int k = 0; k < p->nwl; k++) s += v[k];
    vr_atomic_add(&c->acc->texel_uv[p->index], s * 100.0 / p->nwl);
    break;
  }
  default: break;
  }
}

/* A shadow ray from x (offset to o) towards the light dist away along dir. */
static void push_shadow(vr_flow_worker *w, const payload *p, const double x[3], const double o[3],
                        const double dir[3], double dist, const double *contrib) {
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
    push_shadow(w, p, x, o, ls.dir, ls.dist, contrib);
  }
  if (vr_light_sample_emitter(rs, x, p->nwl, p->wl, &key, &ls)) {
    f(fu, ls.dir, fc);
    bool any = false;
    for (int k = 0; k < p->nwl; k++) any |= (contrib[k] = p->beta[k] * fc[k] * ls.L[k]) > 0;
    if (any) {
      spawn_origin(x, ng, ls.dir, o);
      push_shadow(w, p, x, o, ls.dir, ls.dist, contrib);
    }
  }
  if (vr_light_sample_sky(rs, x, n_for_sky, p->nwl, p->wl, &key, &ls)) {
    f(fu, ls.dir, fc);
    bool any = false;
    for (int k = 0; k < p->nwl; k++) any |= (contrib[k] = p->beta[k] * fc[k] * ls.L[k]) > 0;
    if (any) {
      spawn_origin(x, ng, ls.dir, o);
      push_shadow(w, p, x, o, ls.dir, INFINITY, contrib);
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

static void photon_estimate(const pass_ctx *c, const vr_photon_set *ps, const double x[3],
                            const double n[3], int nwl, const double *wl, double *E) {
  for (int k = 0; k < nwl; k++) E[k] = 0;
  if (!ps || !vr_photon_set_count(ps)) return;
  const vr_photon_map *m = vr_photon_set_map(ps, 0); /* for its bins: all maps share them */
  int nb = vr_photon_map_nbins(m);
  double bins[512], r;
  if (nb > 512) return;
  int got = vr_photon_set_irradiance(ps, x, n, c->fixed_radius ? 0 : c->knn, c->radius, 1.1,
                                     bins, &r);
  if (got <= 0) return;
  for (int k = 0; k < nwl; k++) {
    int b = vr_photon_map_bin(m, wl[k]);
    double lo, hi;
    if (b < 0 || !vr_photon_map_bin_range(m, b, &lo, &hi)) continue;
    E[k] = bins[b] * c->photon_scale / (hi - lo);
  }
}

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
    deliver(c, &p, L);
  }
  unsigned lobes = vr_bsdf_lobes(m->bsdf);
  surf_eval se = {m->bsdf, vr_hit_state(rs, hit), v3(hit->ns), v3(wo), p.nwl, p.wl, v3(hit->ns)};
  bool diffuse = lobes & VR_LOBE_DIFFUSE;
  bool nondelta = lobes & (VR_LOBE_DIFFUSE | VR_LOBE_GLOSSY_R | VR_LOBE_GLOSSY_T);

  if (p.target == TARGET_GATHER) {
    /* A final-gather ray: the photon maps' radiance at its first hit. */
    if (!diffuse) return;
    double n[3];
    memcpy(n, hit->ng, sizeof n);
    if (dot3(n, wo) < 0)
      for (int a = 0; a < 3; a++) n[a] = -n[a];
    double E[VR_MAX_WL], Et[VR_MAX_WL] = {0}, fc[VR_MAX_WL];
    const vr_photon_set *maps[3] = {c->direct, c->caustic, c->global};
    for (int i = 0; i < 3; i++) {
      photon_estimate(c, maps[i], hit->p, n, p.nwl, p.wl, E);
      for (int k = 0; k < p.nwl; k++) Et[k] += E[k];
    }
    double refl[3] = {2 * dot3(n, wo) * n[0] - wo[0], 2 * dot3(n, wo) * n[1] - wo[1],
                      2 * dot3(n, wo) * n[2] - wo[2]};
    surf_f(&se, refl, fc);
    double cs = fabs(dot3(hit->ns, refl));
    for (int k = 0; k < p.nwl; k++) L[k] = p.beta[k] * (cs > 0 ? fc[k] / cs : 0) * Et[k];
    deliver(c, &p, L);
    return;
  }

  if (nondelta) {
    double nsky[3];
    memcpy(nsky, hit->ng, sizeof nsky);
    if (!(lobes & VR_LOBE_GLOSSY_T) && dot3(nsky, wo) < 0)
      for (int a = 0; a < 3; a++) nsky[a] = -nsky[a];
    next_event(c, w, &p, hit->p, hit->ng, (lobes & VR_LOBE_GLOSSY_T) ? NULL : nsky, surf_f, &se,
               1000u + p.depth);
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
    photon_estimate(c, c->caustic, hit->p, n, p.nwl, p.wl, E);
    for (int k = 0; k < p.nwl; k++) Et[k] += E[k];
    if (!c->final_gather) {
      photon_estimate(c, c->global, hit->p, n, p.nwl, p.wl, E);
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

/* Camera unit: one tile of the image (vr_flow_tile), all its samples.  A
 * sample's random numbers are keyed by its pixel and sample index only, so
 * the cut into units changes nothing in the image. */
void vr_camera_generate(void *ctx, vr_flow_worker *w, long unit) {
  pass_ctx *c = ctx;
  const rscene *rs = c->rs;
  const vr_scene_camera *cam = &rs->s->camera;
  int W = cam->width, H = cam->height, x0, y0, x1, y1;
  double aspect = (double)H / W;
  vr_flow_tile(W, H, unit, &x0, &y0, &x1, &y1);
  int tw = x1 - x0, npix = tw * (y1 - y0);
  for (int i = 0; i < npix; i++) {
    int x = x0 + i % tw, y = y0 + i / tw;
    uint32_t pixel = (uint32_t)(y * W + x);
    for (int s = 0; s < c->spp; s++) {
      payload p = {0};
      p.stream = pixel;
      p.sample = (uint32_t)(s + c->sample_offset);
      p.index = pixel;
      p.target = TARGET_PIXEL;
      p.flags = FLAG_SPECULAR_LAST; /* the camera sees emitters and the sky directly */
      p.nwl = (uint8_t)rs->nwl;
      p.medium = -1;
      vr_rng_key key = {rs->seed, p.stream, p.sample, 0};
      vr_wavelengths(rs, &key, (uint32_t)c->spp, p.wl);
      p.weight = 1.0 / c->spp;
      for (int k = 0; k < p.nwl; k++) p.beta[k] = 1.0;
      double sx = (2 * (x + vr_rng(&key, VR_DIM_PIXEL_X)) / W - 1) * rs->tan_half;
      double sy = (1 - 2 * (y + vr_rng(&key, VR_DIM_PIXEL_Y)) / H) * rs->tan_half * aspect;
      vr_ray r = {0};
      for (int a = 0; a < 3; a++) r.dir[a] = rs->cam_w[a] + sx * rs->cam_u[a] + sy * rs->cam_v[a];
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
  int groups = c->acc->groups;
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
