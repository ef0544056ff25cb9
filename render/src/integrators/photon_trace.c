/* Photon tracing (Jensen 2001) as callbacks of the ray flow.  Each photon
 * carries a few wavelengths (hero sampling, like camera paths) with their
 * power, starts from a source chosen by power (lights/sources.c) and, where
 * it meets a surface with a diffuse lobe, lands through the pass's land():
 * into Jensen's maps (photon.c) or onto SPPM's visible points (sppm.c).  A
 * pane crossed straight does not make a caustic: its transmitted sunlight
 * is direct light, found by shadow rays through the pane.  With sky
 * portals, the far sources also emit through them, their usual photons
 * stop where they would enter by a portal (lights/portals.c), and what an
 * outdoor surface scatters is split into lighter copies
 * (outside_split_count) aimed at the portals (outside_portal_scatter). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "integrators/photon_maps.h"
#include "vr/vec3.h"

static void photon_generate(void *ctx, vr_flow_worker *w, long unit) {
  vr_pass *c = ctx;
  const vr_rscene *rs = c->rs;
  const vr_lights *L = &rs->L;
  if (!L->nsources || !(L->total_power > 0)) return;
  for (long j = 0; j < c->photons_per_unit; j++) {
    vr_payload p = {0};
    p.stream = VR_STREAM_PHOTON + (uint64_t)(unit * c->photons_per_unit + j);
    p.sample = (uint32_t)c->sample_offset;
    p.target = VR_TARGET_PHOTON;
    p.nwl = (uint8_t)rs->nwl;
    p.medium = -1;
    p.weight = 1.0;
    vr_rng_key key = {rs->seed, p.stream, p.sample, 0};
    if (c->fixed_wl)
      memcpy(p.wl, c->fixed_wl, sizeof p.wl); /* the iteration's, shared with the camera */
    else
      vr_wavelengths(rs, &key, 1, p.wl);
    double u = vr_rng(&key, VR_DIM_LIGHT_PICK);
    size_t s = 0;
    while (s + 1 < L->nsources && L->source_cdf[s] <= u) s++;
    double ps = L->source_cdf[s] - (s ? L->source_cdf[s - 1] : 0.0);
    if (!(ps > 0)) continue;
    vr_photon_emit e;
    size_t base = L->nsources - L->nportal_sources;
    bool ground = vr_lights_source_is_ground(L, s);
    if (s >= base) {
      int kind = L->portal_source[s - base];
      if (!vr_lights_emit_portal_photon(L, kind, p.nwl, p.wl, &key, &e, &p.portal_t)) continue;
      p.flags |= VR_PF_PORTAL_PATH;
      ground = kind == VR_PORTAL_SRC_GROUND;
    } else {
      if (!vr_lights_emit_photon(L, s, p.nwl, p.wl, &key, &e)) continue;
      if (L->nportal_sources && vr_lights_source_is_far(L, s)) p.flags |= VR_PF_FAR_DIRECT;
    }
    /* The ground glow is light the ground reflected (a Lambertian ground
     * under the sky): its photons belong with those that bounced off a
     * diffuse surface, as the ground plane's own reflected photons would,
     * since no next-event estimate samples it (vr_lights_environment meets
     * it only on escape). */
    if (ground) p.flags |= VR_PF_HAS_DIFFUSE;
    /* Power per wavelength sample: the spectral power times the
     * wavelength weight, over the source's probability; the 1/N of the
     * photon count is applied at estimate time (photon_scale). */
    double wlw = (rs->lmax - rs->lmin) / p.nwl;
    bool any = false;
    for (int k = 0; k < p.nwl; k++) any |= (p.beta[k] = e.power[k] * wlw / ps) > 0;
    if (!any) continue;
    vr_ray r = {0};
    memcpy(r.org, e.org, sizeof r.org);
    memcpy(r.dir, e.dir, sizeof r.dir);
    r.tmax = INFINITY;
    r.kind = VR_RAY_CLOSEST;
    r.purpose = VR_PURPOSE_PHOTON;
    memcpy(r.payload, &p, sizeof p);
    vr_flow_push(w, &r);
  }
}

/* Outside, light reaches the room by the portals.  A photon scattered by
 * a diffuse outdoor surface (outside=yes: a ground, a facade) finds a
 * portal only in the small solid angle it subtends, so the light the
 * outside reflects in would ride on a few photons of large power.  With
 * photon portals, such a scattering draws its direction from a mixture:
 * with probability OUTSIDE_PORTAL_SHARE a point uniform on a portal
 * (vr_portal_sample, as the sky's next-event estimation does), otherwise
 * the BSDF, and the photon is weighted by f |cos| over the mixture's
 * density (the one-sample balance heuristic, Veach 1997, 9.2.4), unbiased
 * for any portal.  The mixture holds for purely diffuse surfaces (no delta
 * or glossy lobe to miss).  A photon sent at a portal skips Russian
 * roulette: its small weight is the point (many light photons in the room
 * in place of a few heavy ones). */
#define OUTSIDE_PORTAL_SHARE 0.5

static bool outside_portal_scatter(const vr_rscene *rs, const vr_rmaterial *m,
                                   const vr_bsdf_point *pt, double state, const vr_hit *hit,
                                   const double ns[3], const double wo[3], const vr_payload *p,
                                   vr_rng_key *key, vr_bsdf_sample *bs, bool *to_portal) {
  const vr_lights *L = &rs->L;
  double wi[3];
  vr_portal_weights pw;
  vr_portal_weights_at(L, hit->p, false, &pw);
  *to_portal = vr_rng(key, VR_DIM_SKY_PICK) < OUTSIDE_PORTAL_SHARE;
  if (*to_portal) {
    if (!vr_portal_sample(L, hit->p, &pw, vr_rng(key, VR_DIM_SKY_W), vr_rng(key, VR_DIM_DIR_U),
                          vr_rng(key, VR_DIM_DIR_V), wi))
      return false;
  } else {
    vr_bsdf_sample b;
    if (!vr_bsdf_sample_at(m->bsdf, pt, state, (vr_vec3){ns[0], ns[1], ns[2]},
                           (vr_vec3){wo[0], wo[1], wo[2]}, p->nwl, p->wl, VR_TRANSPORT_IMPORTANCE,
                           vr_rng(key, VR_DIM_LOBE), vr_rng(key, VR_DIM_DIR_U),
                           vr_rng(key, VR_DIM_DIR_V), &b))
      return false;
    wi[0] = b.wi.x, wi[1] = b.wi.y, wi[2] = b.wi.z;
  }
  /* A reflection only: the other side of the surface is not outside. */
  if (vr_dot3(hit->ng, wi) * vr_dot3(hit->ng, wo) <= 0) return false;
  double f[VR_MAX_WL], pb = 0;
  vr_bsdf_eval_at(m->bsdf, pt, state, (vr_vec3){ns[0], ns[1], ns[2]},
                  (vr_vec3){wo[0], wo[1], wo[2]}, (vr_vec3){wi[0], wi[1], wi[2]}, p->nwl, p->wl,
                  VR_TRANSPORT_IMPORTANCE, f, &pb);
  double pmix = OUTSIDE_PORTAL_SHARE * vr_portal_pdf(L, hit->p, &pw, wi) + (1 - OUTSIDE_PORTAL_SHARE) * pb;
  if (!(pmix > 0)) return false;
  double cosi = fabs(vr_dot3(ns, wi));
  memset(bs, 0, sizeof *bs);
  bs->wi = (vr_vec3){wi[0], wi[1], wi[2]};
  for (int k = 0; k < p->nwl; k++) bs->weight[k] = f[k] * cosi / pmix;
  bs->pdf = pmix;
  bs->lobe = VR_LOBE_DIFFUSE;
  bs->eta = 1;
  return true;
}

/* Splitting by weight: a photon of large power (a usual photon of the
 * far sources, which start on a disc round the whole scene) scattered by
 * an outdoor surface near a window would carry its power into the room
 * on one heavy photon.  It is split into m copies of power 1/m each, each
 * drawing its own direction from the mixture above, with m chosen so that
 * the power aimed at the portals per copy is about a portal photon's:
 * m = 2 rho beta F / P, where rho is the surface's albedo, beta the
 * photon's power, F the form factor towards the portals
 * (vr_portal_form_factor: the share of the reflected light that goes
 * there), 2 the mixture's share and P the portal photons' power.  m is
 * fixed before any direction is drawn, so the copies' mean is the one
 * photon's estimate (unbiased for any m); copies do not split again.  At
 * most OUTSIDE_SPLIT_MAX copies: the cost stays bounded (a ground point
 * 1 m from a 2.4 m2 window, F about 0.16, would otherwise ask for
 * hundreds); in the daylit room of docs/benchmarks.md at most 16, 64 or
 * 256 copies gave the same errors. */
#define OUTSIDE_SPLIT_MAX 64

static int outside_split_count(const vr_rscene *rs, const vr_rmaterial *m, const vr_bsdf_point *pt,
                               double state, const vr_hit *hit, const double ns[3],
                               const vr_payload *p) {
  const vr_lights *L = &rs->L;
  if ((p->flags & VR_PF_SPLIT) || !(L->portal_photon_power > 0)) return 1;
  double F = vr_portal_form_factor(L, hit->p, ns);
  if (!(F > 0)) return 1;
  /* The albedo of a diffuse surface: pi f at normal incidence. */
  double f[VR_MAX_WL], pdf = 0, rho = 0, beta = 0;
  vr_bsdf_eval_at(m->bsdf, pt, state, (vr_vec3){ns[0], ns[1], ns[2]},
                  (vr_vec3){ns[0], ns[1], ns[2]}, (vr_vec3){ns[0], ns[1], ns[2]}, p->nwl, p->wl,
                  VR_TRANSPORT_IMPORTANCE, f, &pdf);
  for (int k = 0; k < p->nwl; k++) {
    rho = fmax(rho, M_PI * f[k]);
    beta += p->beta[k];
  }
  double want = 2.0 * fmin(rho, 1.0) * beta * F / L->portal_photon_power;
  if (!(want > 1)) return 1;
  return want >= OUTSIDE_SPLIT_MAX ? OUTSIDE_SPLIT_MAX : (int)ceil(want);
}

/* A copy's random numbers: its own stream, derived from the photon's
 * (photon streams are VR_STREAM_PHOTON + the photon's number, far below
 * 2^40, so copy j's stream + (j + 1) 2^40 meets no other photon's). */
#define SPLIT_STREAM_SHIFT 40

/* The photon leaves the vertex along bs: Russian roulette (none on a
 * portal branch), its flags, and the next ray. */
static void photon_continue(vr_flow_worker *w, const vr_hit *hit,
                            vr_payload p, vr_rng_key *key, const vr_bsdf_sample *bs,
                            bool to_portal, bool before_portal, const double *tint) {
  if (before_portal) {
    if (!(bs->lobe & VR_LOBE_STRAIGHT)) return; /* shaded before the portal */
    p.portal_t -= hit->t;
  }
  double weight0 = bs->weight[0];
  if (!(bs->lobe & VR_LOBE_STRAIGHT)) p.flags &= (uint16_t)~VR_PF_FAR_DIRECT;
  if (bs->terminate_secondary) {
    if (p.flags & VR_PF_TERMINATED) weight0 /= p.nwl;
    p.flags |= VR_PF_TERMINATED;
  }
  double old = 0, mx = 0;
  for (int k = 0; k < p.nwl; k++) {
    if (p.beta[k] > old) old = p.beta[k];
    p.beta[k] *= (k ? bs->weight[k] : weight0) * (tint ? tint[k] : 1.0);
    if (p.beta[k] > mx) mx = p.beta[k];
  }
  if (!(mx > 0) || !(old > 0)) return;
  /* Russian roulette keeping the power per photon roughly constant. */
  double q = to_portal ? 1.0 : fmin(1.0, mx / old);
  if (vr_rng(key, VR_DIM_ROULETTE) >= q) return;
  for (int k = 0; k < p.nwl; k++) p.beta[k] /= q;
  if (bs->lobe & (VR_LOBE_DIFFUSE))
    p.flags |= VR_PF_HAS_DIFFUSE;
  else if (bs->lobe & (VR_LOBE_SPECULAR_R | VR_LOBE_SPECULAR_T | VR_LOBE_GLOSSY_R | VR_LOBE_GLOSSY_T))
    p.flags |= VR_PF_HAS_SPECULAR;
  double wi[3] = {bs->wi.x, bs->wi.y, bs->wi.z};
  if (bs->lobe & (VR_LOBE_SPECULAR_T | VR_LOBE_GLOSSY_T))
    p.medium = vr_dot3(wi, hit->ng) < 0 ? (int32_t)hit->object : -1;
  p.holes = 0;
  p.depth++;
  vr_ray nr = {0};
  vr_spawn_origin(hit->p, hit->ng, wi, nr.org);
  memcpy(nr.dir, wi, sizeof nr.dir);
  nr.tmax = INFINITY;
  nr.kind = VR_RAY_CLOSEST;
  nr.purpose = VR_PURPOSE_PHOTON;
  memcpy(nr.payload, &p, sizeof p);
  vr_flow_push(w, &nr);
}

static void photon_closest(void *ctx, vr_flow_worker *w, const vr_ray *r, const vr_hit *hit) {
  vr_pass *c = ctx;
  const vr_rscene *rs = c->rs;
  if (!hit || vr_path_pass_through(c, w, r, hit)) return;
  vr_payload p;
  memcpy(&p, r->payload, sizeof p);
  vr_path_absorb(rs, &p, hit);
  /* Portals: a portal photon met something before its portal (only a
   * straight pane may let it on); a far source's unscattered photon that
   * enters by a portal is the portal photons' light: it stops there. */
  bool before_portal = false;
  if (p.flags & VR_PF_PORTAL_PATH) {
    if (hit->t < p.portal_t * (1 - 1e-9)) before_portal = true;
    else p.flags &= (uint16_t)~VR_PF_PORTAL_PATH;
  }
  if ((p.flags & VR_PF_FAR_DIRECT) && vr_portal_crossed_inward(&rs->L, r->org, r->dir, hit->t))
    return;
  const vr_rmaterial *m = &rs->mat[rs->obj[hit->object].material];
  unsigned lobes = vr_bsdf_lobes(m->bsdf);
  if ((lobes & VR_LOBE_DIFFUSE) && !before_portal) c->land(c, &p, hit, r->dir);
  if (p.depth + 1 >= c->max_depth) return;
  vr_rng_key key = {rs->seed, p.stream, p.sample, p.depth + 1};
  double wo[3] = {-r->dir[0], -r->dir[1], -r->dir[2]};
  vr_bsdf_sample bs;
  double ns[3] = {hit->ns[0], hit->ns[1], hit->ns[2]};
  bool bent = m->nmap && vr_hit_normal_map(rs, hit, 0, ns);
  /* A texture multiplies what the surface reflects (finest level: a
   * photon has no footprint); a pbr material's textures are its BRDF's. */
  vr_bsdf_point pt = vr_bsdf_point_plain();
  double tint[VR_MAX_WL];
  bool tinted = !vr_hit_pbr(rs, hit, 0, p.nwl, p.wl, &pt) &&
                vr_hit_texture(rs, hit, 0, p.nwl, p.wl, tint);
  double state = vr_hit_state(rs, hit);
  if (rs->obj[hit->object].outside && rs->L.nportal_sources && lobes == VR_LOBE_DIFFUSE &&
      !before_portal && !bent) {
    int copies = outside_split_count(rs, m, &pt, state, hit, ns, &p);
    for (int j = 0; j < copies; j++) {
      vr_payload q = p;
      vr_rng_key kq = key;
      if (copies > 1) {
        q.stream = p.stream + ((uint64_t)(j + 1) << SPLIT_STREAM_SHIFT);
        q.flags |= VR_PF_SPLIT;
        for (int k = 0; k < q.nwl; k++) q.beta[k] /= copies;
        kq = (vr_rng_key){rs->seed, q.stream, q.sample, q.depth + 1};
      }
      bool to_portal = false;
      if (outside_portal_scatter(rs, m, &pt, state, hit, ns, wo, &q, &kq, &bs, &to_portal))
        photon_continue(w, hit, q, &kq, &bs, to_portal, false, tinted ? tint : NULL);
    }
    return;
  }
  if (!vr_bsdf_sample_at(m->bsdf, &pt, state, (vr_vec3){ns[0], ns[1], ns[2]},
                         (vr_vec3){wo[0], wo[1], wo[2]}, p.nwl, p.wl, VR_TRANSPORT_IMPORTANCE,
                         vr_rng(&key, VR_DIM_LOBE), vr_rng(&key, VR_DIM_DIR_U),
                         vr_rng(&key, VR_DIM_DIR_V), &bs))
    return;
  /* Around a normal map's normal, a reflection may point into the surface. */
  if (bent && vr_dot3(hit->ng, (double[3]){bs.wi.x, bs.wi.y, bs.wi.z}) * vr_dot3(hit->ng, wo) <= 0)
    return;
  photon_continue(w, hit, p, &key, &bs, false, before_portal, tinted ? tint : NULL);
}

static bool photon_shadow_hit(void *ctx, vr_flow_worker *w, vr_ray *r, const vr_hit *hit) {
  (void)ctx, (void)w, (void)r, (void)hit;
  return false;
}

static void photon_shadow_done(void *ctx, vr_flow_worker *w, const vr_ray *r, bool reached) {
  (void)ctx, (void)w, (void)r, (void)reached;
}

const vr_flow_ops vr_photon_ops = {photon_closest, photon_shadow_hit, photon_shadow_done,
                                   photon_generate, VR_PAYLOAD_WIRE};
/* Jensen's maps: into the map of its path's kind, of the cell where the
 * photon landed. */
static void store(vr_pass *c, const vr_payload *p, const vr_hit *hit, const double dir[3]) {
  const vr_photon_maps *maps = c->state;
  vr_photon_set *ps = (p->flags & VR_PF_HAS_DIFFUSE)    ? maps->global
                      : (p->flags & VR_PF_HAS_SPECULAR) ? maps->caustic
                                                        : maps->direct;
  if (!ps) return;
  const vr_photon_map *m = vr_photon_set_map(ps, hit->cell);
  int nb = vr_photon_map_nbins(m);
  float power[512];
  if (nb > 512) return;
  memset(power, 0, (size_t)nb * sizeof *power);
  bool any = false;
  for (int k = 0; k < p->nwl; k++) {
    int b = vr_photon_map_bin(m, p->wl[k]);
    if (b < 0 || !(p->beta[k] > 0)) continue;
    power[b] += (float)p->beta[k];
    any = true;
  }
  if (!any) return;
  uint64_t key = p->stream * 64u + p->depth;
  vr_photon_set_store_on(ps, hit->cell, key, hit->p, dir, hit->ng, (uint32_t)hit->object, power,
                         NULL);
}

static size_t maps_bytes(const void *u) {
  const vr_photon_maps *m = u;
  return vr_photon_set_bytes(m->direct) + vr_photon_set_bytes(m->caustic) +
         vr_photon_set_bytes(m->global);
}


/* Maps keep only the bins a photon's wavelengths fall in (at most nwl of
 * them), not all 10 nm bins of the range. */
vr_status vr_photon_maps_trace(vr_run *r, const vr_pass *base, vr_photon_maps *m, long photons,
                               bool caustic, bool global, bool direct, vr_error *err) {
  vr_rscene *rs = base->rs;
  int nb = (int)ceil((rs->lmax - rs->lmin) / 10.0);
  if (nb < 1) nb = 1;
  /* One map per cell, positions about the scene's centre (vr/photon_set.h). */
  int S = vr_domains_count(rs->d);
  vr_photon_set **sets[3] = {&m->global, &m->direct, &m->caustic};
  bool want[3] = {global, direct, caustic};
  r->held = maps_bytes, r->held_ctx = m;
  for (int i = 0; i < 3; i++) {
    if (!want[i]) continue;
    *sets[i] = vr_photon_set_create(S, nb, rs->lmin, rs->lmax, rs->nwl, rs->scene_centre, err);
    if (!*sets[i]) return err ? err->status : VR_E_NOMEM;
  }
  vr_pass c = *base;
  c.land = store;
  c.state = m;
  c.photons_per_unit = 1024;
  long units = (photons + c.photons_per_unit - 1) / c.photons_per_unit;
  m->scale = 1.0 / (double)(units * c.photons_per_unit);
  vr_status st = vr_run_flow(r, &vr_photon_ops, &c, units, "photons", err);
  /* Each rank stored the photons that landed in its cells: every rank gets
   * them all, and builds the same maps as one process would. */
  vr_photon_set *all[3] = {m->global, m->direct, m->caustic};
  if (!st) st = vr_ranks_share_photons(r, all, 3, err);
  /* Building needs the staged photons and the built ones at once. */
  vr_run_note_held(r);
  for (int i = 0; !st && i < 3; i++)
    if (*sets[i]) st = vr_photon_set_build(*sets[i], err);
  if (!st) {
    r->res->photons_global += m->global ? vr_photon_set_count(m->global) : 0;
    r->res->photons_direct += m->direct ? vr_photon_set_count(m->direct) : 0;
    r->res->photons_caustic += m->caustic ? vr_photon_set_count(m->caustic) : 0;
  }
  return st;
}

void vr_photon_maps_free(vr_run *r, vr_photon_maps *m) {
  vr_photon_set_destroy(m->global);
  vr_photon_set_destroy(m->direct);
  vr_photon_set_destroy(m->caustic);
  m->global = m->direct = m->caustic = NULL;
  if (r && r->held_ctx == m) r->held = NULL, r->held_ctx = NULL;
}
