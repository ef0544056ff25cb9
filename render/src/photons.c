/* Photon tracing (Jensen 2001) as callbacks of the ray flow.  Each photon
 * carries a few wavelengths (hero sampling, like camera paths) with their
 * power, and is stored where it meets a diffuse surface, in one of three
 * maps according to the path it took:
 *   direct   light, then thin elements only (panes) -> diffuse: what
 *            next-event estimation already computes; used only by final
 *            gathering, whose gather points need all the light;
 *   caustic  light, then at least one specular or glossy bounce or
 *            refraction, no diffuse one -> diffuse;
 *   global   at least one diffuse bounce before.
 * A pane crossed straight does not make a caustic: its transmitted sunlight
 * is direct light, found by shadow rays through the pane.
 * Photon power is stored per spectral bin; the estimate divides by the bin
 * width, so the maps answer in W/(m² nm) at any wavelength.  Each map is a
 * vr_photon_set: a photon is stored in the map of the cell where it
 * landed, and estimates gather across cells as one map would.
 * With sky portals, the far sources also emit through them and their usual
 * photons stop where they would enter by a portal (portals.c). */
#include <math.h>
#include <string.h>

#include "render_internal.h"
#include "sppm.h"

static double dot3(const double a[3], const double b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void photon_generate(void *ctx, vr_flow_worker *w, long unit) {
  pass_ctx *c = ctx;
  const rscene *rs = c->rs;
  if (!rs->nsources || !(rs->total_power > 0)) return;
  for (long j = 0; j < c->photons_per_unit; j++) {
    payload p = {0};
    p.stream = 0x9000000000000ull + (uint64_t)(unit * c->photons_per_unit + j);
    p.sample = (uint32_t)c->sample_offset;
    p.target = TARGET_PHOTON;
    p.nwl = (uint8_t)rs->nwl;
    p.medium = -1;
    p.weight = 1.0;
    vr_rng_key key = {rs->seed, p.stream, p.sample, 0};
    if (c->sppm)
      memcpy(p.wl, c->sppm->wl, sizeof p.wl); /* the iteration's, shared with the camera */
    else
      vr_wavelengths(rs, &key, 1, p.wl);
    double u = vr_rng(&key, VR_DIM_LIGHT_PICK);
    size_t s = 0;
    while (s + 1 < rs->nsources && rs->source_cdf[s] <= u) s++;
    double ps = rs->source_cdf[s] - (s ? rs->source_cdf[s - 1] : 0.0);
    if (!(ps > 0)) continue;
    photon_emit e;
    size_t base = rs->nsources - rs->nportal_sources;
    bool ground = rs->has_sky && s == rs->nlights + rs->nemitters + 1;
    if (s >= base) {
      int kind = rs->portal_source[s - base];
      if (!vr_light_emit_portal_photon(rs, kind, p.nwl, p.wl, &key, &e, &p.portal_t)) continue;
      p.flags |= FLAG_PORTAL_PATH;
      ground = kind == PORTAL_SRC_GROUND;
    } else {
      if (!vr_light_emit_photon(rs, s, p.nwl, p.wl, &key, &e)) continue;
      bool far = s == rs->sun_light || (rs->has_sky && s >= rs->nlights + rs->nemitters);
      if (rs->nportal_sources && far) p.flags |= FLAG_FAR_DIRECT;
    }
    /* The ground glow is light the ground reflected (a Lambertian ground
     * under the sky): its photons belong in the global map, as the ground
     * plane's own reflected photons would, since no next-event estimate
     * samples it (vr_light_environment meets it only on escape). */
    if (ground) p.flags |= FLAG_HAS_DIFFUSE;
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
    r.purpose = PURPOSE_PHOTON;
    memcpy(r.payload, &p, sizeof p);
    vr_flow_push(w, &r);
  }
}

/* Into the map of the cell where the photon landed. */
static void store(pass_ctx *c, vr_photon_set *ps, const payload *p, const vr_hit *hit,
                  const double dir[3]) {
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
  (void)c;
}

static void photon_closest(void *ctx, vr_flow_worker *w, const vr_ray *r, const vr_hit *hit) {
  pass_ctx *c = ctx;
  const rscene *rs = c->rs;
  if (!hit) return;
  payload p;
  memcpy(&p, r->payload, sizeof p);
  if (p.medium >= 0) {
    const vr_bsdf *mb = rs->mat[rs->obj[p.medium].material].bsdf;
    for (int k = 0; k < p.nwl; k++) p.beta[k] *= exp(-vr_bsdf_medium_sigma_a(mb, p.wl[k]) * hit->t);
  }
  /* Portals: a portal photon met something before its portal (only a
   * straight pane may let it on); a far source's unscattered photon that
   * enters by a portal is the portal photons' light: it stops there. */
  bool before_portal = false;
  if (p.flags & FLAG_PORTAL_PATH) {
    if (hit->t < p.portal_t * (1 - 1e-9)) before_portal = true;
    else p.flags &= (uint8_t)~FLAG_PORTAL_PATH;
  }
  if ((p.flags & FLAG_FAR_DIRECT) && vr_portal_crossed_inward(rs, r->org, r->dir, hit->t)) return;
  const rmaterial *m = &rs->mat[rs->obj[hit->object].material];
  unsigned lobes = vr_bsdf_lobes(m->bsdf);
  if ((lobes & VR_LOBE_DIFFUSE) && !before_portal && c->sppm) {
    /* SPPM: light that has scattered off something other than a straight
     * pane (next-event estimation took the rest) reaches the visible
     * points about the hit. */
    if (p.flags & (FLAG_HAS_DIFFUSE | FLAG_HAS_SPECULAR)) {
      double wi[3] = {-r->dir[0], -r->dir[1], -r->dir[2]};
      vr_sppm_deposit(c->sppm, rs, hit->p, wi, p.beta, (p.flags & FLAG_TERMINATED) != 0);
    }
  } else if ((lobes & VR_LOBE_DIFFUSE) && !before_portal) {
    vr_photon_set *map = (p.flags & FLAG_HAS_DIFFUSE)    ? c->global
                         : (p.flags & FLAG_HAS_SPECULAR) ? c->caustic
                                                         : c->direct;
    store(c, map, &p, hit, r->dir);
  }
  if (p.depth + 1 >= c->max_depth) return;
  vr_rng_key key = {rs->seed, p.stream, p.sample, p.depth + 1};
  double wo[3] = {-r->dir[0], -r->dir[1], -r->dir[2]};
  vr_bsdf_sample bs;
  if (!vr_bsdf_sample_dir(m->bsdf, vr_hit_state(rs, hit), (vr_vec3){hit->ns[0], hit->ns[1], hit->ns[2]},
                          (vr_vec3){wo[0], wo[1], wo[2]}, p.nwl, p.wl, VR_TRANSPORT_IMPORTANCE,
                          vr_rng(&key, VR_DIM_LOBE), vr_rng(&key, VR_DIM_DIR_U),
                          vr_rng(&key, VR_DIM_DIR_V), &bs))
    return;
  if (before_portal) {
    if (!(bs.lobe & VR_LOBE_STRAIGHT)) return; /* shaded before the portal */
    p.portal_t -= hit->t;
  }
  if (!(bs.lobe & VR_LOBE_STRAIGHT)) p.flags &= (uint8_t)~FLAG_FAR_DIRECT;
  if (bs.terminate_secondary) {
    if (p.flags & FLAG_TERMINATED) bs.weight[0] /= p.nwl;
    p.flags |= FLAG_TERMINATED;
  }
  double old = 0, mx = 0;
  for (int k = 0; k < p.nwl; k++) {
    if (p.beta[k] > old) old = p.beta[k];
    p.beta[k] *= bs.weight[k];
    if (p.beta[k] > mx) mx = p.beta[k];
  }
  if (!(mx > 0) || !(old > 0)) return;
  /* Russian roulette keeping the power per photon roughly constant. */
  double q = fmin(1.0, mx / old);
  if (vr_rng(&key, VR_DIM_ROULETTE) >= q) return;
  for (int k = 0; k < p.nwl; k++) p.beta[k] /= q;
  if (bs.lobe & (VR_LOBE_DIFFUSE))
    p.flags |= FLAG_HAS_DIFFUSE;
  else if (bs.lobe & (VR_LOBE_SPECULAR_R | VR_LOBE_SPECULAR_T | VR_LOBE_GLOSSY_R | VR_LOBE_GLOSSY_T))
    p.flags |= FLAG_HAS_SPECULAR;
  double wi[3] = {bs.wi.x, bs.wi.y, bs.wi.z};
  if (bs.lobe & (VR_LOBE_SPECULAR_T | VR_LOBE_GLOSSY_T))
    p.medium = dot3(wi, hit->ng) < 0 ? (int32_t)hit->object : -1;
  p.depth++;
  vr_ray nr = {0};
  double e = 1e-5 * (1 + fmax(fabs(hit->p[0]), fmax(fabs(hit->p[1]), fabs(hit->p[2]))));
  double sg = dot3(hit->ng, wi) >= 0 ? e : -e;
  for (int a = 0; a < 3; a++) nr.org[a] = hit->p[a] + sg * hit->ng[a];
  memcpy(nr.dir, wi, sizeof nr.dir);
  nr.tmax = INFINITY;
  nr.kind = VR_RAY_CLOSEST;
  nr.purpose = PURPOSE_PHOTON;
  memcpy(nr.payload, &p, sizeof p);
  vr_flow_push(w, &nr);
}

static bool photon_shadow_hit(void *ctx, vr_flow_worker *w, vr_ray *r, const vr_hit *hit) {
  (void)ctx, (void)w, (void)r, (void)hit;
  return false;
}

static void photon_shadow_done(void *ctx, vr_flow_worker *w, const vr_ray *r, bool reached) {
  (void)ctx, (void)w, (void)r, (void)reached;
}

const vr_flow_ops vr_photon_ops = {photon_closest, photon_shadow_hit, photon_shadow_done,
                                   photon_generate};
