/* The subpaths of the bidirectional path tracer and what joins them: the
 * random walk that extends a camera or light subpath (pbrt-v4's
 * RandomWalk, with this renderer's thin panes, absorbing media and
 * dispersion), the visibility of a connection through panes, and, on the
 * camera subpath, the light of the far sources (sun, sky, ground glow),
 * which BDPT leaves to the path tracer's strategies.
 *
 * Rays are traced here, in the scene's one cell (vr_domains_intersect on
 * cell 0), not through the ray flow: a connection needs its answer before
 * the sample goes on. */
#include <math.h>
#include <string.h>

#include "integrators/bdpt_internal.h"

static double offset_scale(const double p[3]) {
  double m = fmax(fabs(p[0]), fmax(fabs(p[1]), fabs(p[2])));
  return 1e-5 * (1.0 + m);
}

/* The point a ray from v towards dir starts at: just off a surface on the
 * side of dir, the point itself for a point light or the camera. */
static void spawn(const vr_bdpt_vertex *v, const double dir[3], double o[3]) {
  if (!v->on_surface) {
    memcpy(o, v->p, 3 * sizeof *o);
    return;
  }
  double e = offset_scale(v->p), s = vr_dot3(v->ng, dir) >= 0 ? e : -e;
  for (int a = 0; a < 3; a++) o[a] = v->p[a] + s * v->ng[a];
}

/* The medium a segment leaving v along dir lies in. */
static int32_t medium_towards(const vr_bdpt_vertex *v, const double dir[3]) {
  if (v->type == BV_SURFACE && (v->lobes & (VR_LOBE_SPECULAR_T | VR_LOBE_GLOSSY_T)))
    return vr_dot3(dir, v->ng) < 0 ? (int32_t)v->object : -1;
  return v->medium;
}

static void absorb(const vr_rscene *rs, int32_t medium, double dist, int nwl, const double *wl,
                   double *v) {
  if (medium < 0) return;
  const vr_bsdf *mb = rs->mat[rs->obj[medium].material].bsdf;
  for (int k = 0; k < nwl; k++) v[k] *= exp(-vr_bsdf_medium_sigma_a(mb, wl[k]) * dist);
}

/* A pane met travelling along dir: T per wavelength and the probabilities
 * that vr_bsdf_sample_dir goes straight through it travelling that way
 * (*p_fwd) and the other way (*p_rev): the sum of T over the sum of R + T
 * of the side the light comes from (bsdf_pane.c). */
static void pane_choice(const vr_bsdf *pb, double state, const double ns[3], const double dir[3],
                        int nwl, const double *wl, double *T, double *p_fwd, double *p_rev) {
  double c = vr_dot3(dir, ns), rf = 0, rb = 0, st = 0;
  for (int k = 0; k < nwl; k++) {
    double R, Tk, A;
    vr_bsdf_rta(pb, state, -c, wl[k], &R, &Tk, &A);
    rf += R;
    st += Tk;
    if (T) T[k] = Tk;
    vr_bsdf_rta(pb, state, c, wl[k], &R, &Tk, &A);
    rb += R;
  }
  *p_fwd = st + rf > 0 ? st / (st + rf) : 0;
  *p_rev = st + rb > 0 ? st / (st + rb) : 0;
}

void bdpt_f(const vr_bdpt_vertex *v, const double wi[3], int nwl, const double *wl, bool importance,
            double *f, double *pdf) {
  double fb[VR_BSDF_MAX_WAVELENGTHS];
  vr_vec3 n = {v->ns[0], v->ns[1], v->ns[2]}, wo = {v->wo[0], v->wo[1], v->wo[2]};
  vr_vec3 w = {wi[0], wi[1], wi[2]};
  vr_bsdf_eval_at(v->bsdf, &v->pt, v->state, n, wo, w, nwl, wl,
               importance ? VR_TRANSPORT_IMPORTANCE : VR_TRANSPORT_RADIANCE, fb, pdf);
  double corr = 1;
  if (importance) {
    /* Shading normals make the adjoint BSDF f(wi, wo) |wo.ns| |wi.ng| /
     * (|wo.ng| |wi.ns|) (Veach 1997, eq. 5.20). */
    double on = fabs(vr_dot3(v->wo, v->ns)), og = fabs(vr_dot3(v->wo, v->ng));
    double in = fabs(vr_dot3(wi, v->ns)), ig = fabs(vr_dot3(wi, v->ng));
    corr = og > 0 && in > 0 ? on * ig / (og * in) : 0;
  }
  if (v->bent && vr_dot3(v->ng, wi) * vr_dot3(v->ng, v->wo) <= 0) corr = 0;
  for (int k = 0; k < nwl; k++) f[k] = fb[k] * corr * (v->tinted ? v->tint[k] : 1.0);
}

/* A cut-out (alpha) point of a textured surface, which rays go through.
 * BDPT's walks trace outside the ray flow and its sample keys: a see-
 * through (blend) point lets a ray through with probability 1 - alpha
 * drawn from a hash of the hit and the direction. */
static bool cut_out(const vr_rscene *rs, const vr_hit *h, const double dir[3]) {
  if (!vr_rmaterial_cuts(&rs->mat[rs->obj[h->object].material])) return false;
  uint64_t a, b, c;
  memcpy(&a, &h->t, 8), memcpy(&b, &dir[0], 8), memcpy(&c, &dir[1], 8);
  uint64_t z = vr_mix64(a ^ vr_mix64(b ^ vr_mix64(c ^ h->prim)));
  return vr_hit_cut_out(rs, h, (double)(z >> 11) * 0x1.0p-53);
}

double bdpt_to_area(const vr_bdpt_vertex *v, const vr_bdpt_vertex *to, double pdf) {
  double d[3], d2 = 0;
  for (int a = 0; a < 3; a++) {
    d[a] = to->p[a] - v->p[a];
    d2 += d[a] * d[a];
  }
  if (!(d2 > 0)) return 0;
  if (to->on_surface) pdf *= fabs(vr_dot3(to->ng, d)) / sqrt(d2);
  return pdf / d2;
}

bool bdpt_visible(const vr_bdpt *b, vr_bdpt_tls *tl, const vr_bdpt_vertex *a, const vr_bdpt_vertex *c, int nwl,
                  const double *wl, double *T, double *p_ab, double *p_ba) {
  const vr_rscene *rs = b->rs;
  double d[3], d2 = 0;
  for (int k = 0; k < 3; k++) {
    d[k] = c->p[k] - a->p[k];
    d2 += d[k] * d[k];
  }
  if (!(d2 > 0)) return false;
  double dist = sqrt(d2), back[3];
  for (int k = 0; k < 3; k++) d[k] /= dist, back[k] = -d[k];
  double o[3], e[3], dir[3], len2 = 0;
  spawn(a, d, o);
  spawn(c, back, e);
  for (int k = 0; k < 3; k++) {
    dir[k] = e[k] - o[k];
    len2 += dir[k] * dir[k];
  }
  double len = sqrt(len2);
  if (!(len > 0) || vr_dot3(dir, d) <= 0) return false;
  for (int k = 0; k < 3; k++) dir[k] /= len;
  double tmax = len * (1 - 1e-6), tnear = 0;
  for (int k = 0; k < nwl; k++) T[k] = 1;
  *p_ab = *p_ba = 1;
  for (;;) {
    vr_hit hit;
    tl->rays_shadow++;
    if (!vr_domains_intersect(rs->d, 0, o, dir, tnear, tmax, &hit)) break;
    if (cut_out(rs, &hit, dir)) {
      tnear = hit.t + fmax(1e-6 * fabs(hit.t), 1e-7);
      if (tnear >= tmax) break;
      continue;
    }
    const vr_bsdf *pb = rs->mat[rs->obj[hit.object].material].bsdf;
    if (!vr_bsdf_is_thin(pb)) return false;
    double Tp[VR_MAX_WL], pf, pr;
    pane_choice(pb, vr_hit_state(rs, &hit), hit.ns, dir, nwl, wl, Tp, &pf, &pr);
    bool any = false;
    for (int k = 0; k < nwl; k++) any |= (T[k] *= Tp[k]) > 0;
    if (!any) return false;
    *p_ab *= pf;
    *p_ba *= pr;
    tnear = hit.t + fmax(1e-6 * fabs(hit.t), 1e-7);
    if (tnear >= tmax) break;
  }
  absorb(rs, medium_towards(a, d), dist, nwl, wl, T);
  return true;
}

/* Unblocked towards the sky from o along dir, through panes (their
 * straight transmittance, as the path tracer's shadow rays). */
static bool visible_far(const vr_bdpt *b, vr_bdpt_tls *tl, const double o[3], const double dir[3],
                        int nwl, const double *wl, double *T) {
  const vr_rscene *rs = b->rs;
  double tnear = 0;
  for (;;) {
    vr_hit hit;
    tl->rays_shadow++;
    if (!vr_domains_intersect(rs->d, 0, o, dir, tnear, INFINITY, &hit)) return true;
    if (cut_out(rs, &hit, dir)) {
      tnear = hit.t + fmax(1e-6 * fabs(hit.t), 1e-7);
      continue;
    }
    const vr_bsdf *pb = rs->mat[rs->obj[hit.object].material].bsdf;
    double Tp[VR_BSDF_MAX_WAVELENGTHS];
    if (!vr_bsdf_straight_transmittance(pb, vr_hit_state(rs, &hit), vr_dot3(dir, hit.ng), nwl,
                                        wl, Tp))
      return false;
    bool any = false;
    for (int k = 0; k < nwl; k++) any |= (T[k] *= Tp[k]) > 0;
    if (!any) return false;
    tnear = hit.t + fmax(1e-6 * fabs(hit.t), 1e-7);
  }
}

/* The far sources at camera vertex v (index i): one sample of the sun and
 * one of the sky, each through a shadow ray, weight 1 (no other strategy
 * of this integrator finds them there). */
static void far_light(const vr_bdpt *b, vr_bdpt_tls *tl, const vr_bdpt_sample *sm, const vr_bdpt_vertex *v, int i,
                      double *far) {
  const vr_rscene *rs = b->rs;
  vr_rng_key key = {rs->seed, sm->stream, sm->sample, BK_FAR + (uint32_t)i};
  vr_light_sample ls;
  double f[VR_MAX_WL], T[VR_MAX_WL], o[3];
  for (int which = 0; which < 2; which++) {
    bool got;
    if (which == 0) {
      got = rs->L.sun < rs->L.n &&
            vr_lights_sample_light(&rs->L, rs->L.sun, v->p, &key, sm->nwl, sm->wl, &ls);
    } else {
      double nsky[3];
      bool glossy_t = v->lobes & VR_LOBE_GLOSSY_T;
      memcpy(nsky, v->ng, sizeof nsky);
      if (vr_dot3(nsky, v->wo) < 0)
        for (int a = 0; a < 3; a++) nsky[a] = -nsky[a];
      got = vr_lights_sample_sky(&rs->L, v->p, glossy_t ? NULL : nsky, sm->nwl, sm->wl, &key, &ls);
    }
    if (!got) continue;
    bdpt_f(v, ls.dir, sm->nwl, sm->wl, false, f, NULL);
    double c = fabs(vr_dot3(v->ns, ls.dir));
    bool any = false;
    for (int k = 0; k < sm->nwl; k++) any |= (T[k] = v->beta[k] * f[k] * c * ls.L[k]) > 0;
    if (!any) continue;
    spawn(v, ls.dir, o);
    if (!visible_far(b, tl, o, ls.dir, sm->nwl, sm->wl, T)) continue;
    for (int k = 0; k < sm->nwl; k++) far[k] += T[k];
  }
}

int bdpt_walk(const vr_bdpt *b, vr_bdpt_tls *tl, const vr_bdpt_sample *sm, vr_bdpt_vertex *path, int n, int maxv,
              const double dir0[3], double pdf_dir, const double *beta0, bool importance,
              uint32_t key_base, double *far) {
  const vr_rscene *rs = b->rs;
  const int nwl = sm->nwl;
  double beta[VR_MAX_WL], dir[3], ref = 0;
  memcpy(beta, beta0, sizeof beta);
  memcpy(dir, dir0, sizeof dir);
  for (int k = 0; k < nwl; k++) ref = fmax(ref, beta[k]);
  bool term = path[n - 1].term;
  int32_t medium = path[n - 1].medium;
  if (path[n - 1].type == BV_SURFACE) medium = medium_towards(&path[n - 1], dir);
  vr_transport mode = importance ? VR_TRANSPORT_IMPORTANCE : VR_TRANSPORT_RADIANCE;
  while (n < maxv) {
    vr_bdpt_vertex *prev = &path[n - 1];
    vr_rng_key key = {rs->seed, sm->stream, sm->sample, key_base + (uint32_t)n};
    /* Trace to the next vertex, straight through thin panes. */
    double o[3], seg_fwd = 1, seg_rev = 1, tnear = 0;
    spawn(prev, dir, o);
    vr_hit hit;
    bool got = false, pane_reflect = false;
    vr_bsdf_sample bs;
    for (uint32_t crossing = 0;; crossing++) {
      if (importance) tl->rays_light++;
      else tl->rays_camera++;
      got = vr_domains_intersect(rs->d, 0, o, dir, tnear, INFINITY, &hit);
      if (!got) break;
      if (cut_out(rs, &hit, dir)) {
        tnear = hit.t + fmax(1e-6 * fabs(hit.t), 1e-7);
        continue;
      }
      const vr_robject *ob = &rs->obj[hit.object];
      const vr_bsdf *hb = rs->mat[ob->material].bsdf;
      if (!vr_bsdf_is_thin(hb) || ob->emitter >= 0) break;
      double state = vr_hit_state(rs, &hit), wo[3] = {-dir[0], -dir[1], -dir[2]};
      if (!vr_bsdf_sample_dir(hb, state, (vr_vec3){hit.ns[0], hit.ns[1], hit.ns[2]},
                              (vr_vec3){wo[0], wo[1], wo[2]}, nwl, sm->wl, mode,
                              vr_rng(&key, BK_PANE_DIM + 2 * crossing),
                              vr_rng(&key, BK_PANE_DIM + 2 * crossing + 1),
                              vr_rng(&key, BK_PANE_DIM + 2 * crossing), &bs))
        return n;
      if (bs.lobe != VR_LOBE_STRAIGHT) {
        pane_reflect = true; /* the reflection is a (delta) vertex */
        break;
      }
      double pf, pr;
      pane_choice(hb, state, hit.ns, dir, nwl, sm->wl, NULL, &pf, &pr);
      bool any = false;
      for (int k = 0; k < nwl; k++) any |= (beta[k] *= bs.weight[k]) > 0;
      if (!any) return n;
      seg_fwd *= bs.pdf;
      seg_rev *= pr;
      tnear = hit.t + fmax(1e-6 * fabs(hit.t), 1e-7);
    }
    if (!got) {
      /* Escaped: the ground glow always, the sky only where no next-event
       * estimate could have found it (after the camera or a delta lobe). */
      if (far) {
        double L[VR_MAX_WL];
        vr_lights_environment(&rs->L, dir, prev->type == BV_CAMERA || prev->delta, nwl, sm->wl, L);
        /* The sun's disc where every vertex since the eye was delta (its
         * next-event sample covers it everywhere else). */
        bool all_delta = rs->sun_disc;
        for (int i = 1; i < n && all_delta; i++) all_delta = path[i].delta;
        double Ls[VR_MAX_WL];
        if (all_delta && vr_lights_sun_disc(&rs->L, dir, nwl, sm->wl, Ls))
          for (int k = 0; k < nwl; k++) L[k] += Ls[k];
        absorb(rs, medium, INFINITY, nwl, sm->wl, L);
        for (int k = 0; k < nwl; k++) far[k] += beta[k] * L[k];
      }
      return n;
    }
    absorb(rs, medium, hit.t, nwl, sm->wl, beta);
    vr_bdpt_vertex *v = &path[n];
    memset(v, 0, sizeof *v);
    v->type = BV_SURFACE;
    v->on_surface = true;
    memcpy(v->p, hit.p, sizeof v->p);
    memcpy(v->ng, hit.ng, sizeof v->ng);
    memcpy(v->ns, hit.ns, sizeof v->ns);
    for (int a = 0; a < 3; a++) v->wo[a] = -dir[a];
    memcpy(v->beta, beta, sizeof v->beta);
    v->object = hit.object;
    v->medium = medium;
    v->term = term;
    const vr_robject *ob = &rs->obj[hit.object];
    v->bsdf = rs->mat[ob->material].bsdf;
    v->state = vr_hit_state(rs, &hit);
    v->pt = vr_bsdf_point_plain();
    v->tinted = !vr_hit_pbr(rs, &hit, 0, nwl, sm->wl, &v->pt) &&
                vr_hit_texture(rs, &hit, 0, nwl, sm->wl, v->tint);
    v->bent = vr_hit_normal_map(rs, &hit, 0, v->ns);
    v->lobes = vr_bsdf_lobes(v->bsdf);
    v->connectible = v->lobes & (VR_LOBE_DIFFUSE | VR_LOBE_GLOSSY_R | VR_LOBE_GLOSSY_T);
    v->source = b->L.of_object[hit.object];
    v->seg_rev = seg_rev;
    v->pdf_fwd = bdpt_to_area(prev, v, pdf_dir * seg_fwd);
    n++;
    if (far && v->connectible && n - 1 <= b->max_depth) far_light(b, tl, sm, v, n - 1, far);
    if (n >= maxv) break;
    /* Scatter. */
    if (!pane_reflect) {
      key.depth = key_base + (uint32_t)(n - 1) + 0x800u;
      vr_vec3 ns = {v->ns[0], v->ns[1], v->ns[2]}, wo = {v->wo[0], v->wo[1], v->wo[2]};
      if (!vr_bsdf_sample_at(v->bsdf, &v->pt, v->state, ns, wo, nwl, sm->wl, mode,
                             vr_rng(&key, VR_DIM_LOBE), vr_rng(&key, VR_DIM_DIR_U),
                             vr_rng(&key, VR_DIM_DIR_V), &bs))
        break;
    }
    /* The factor nwl of a dispersive refraction stands for the secondary
     * wavelengths it ends: once per subpath (integrate.c's continue_path). */
    if (bs.terminate_secondary && term) bs.weight[0] /= nwl;
    if (bs.terminate_secondary) term = true;
    double wi[3] = {bs.wi.x, bs.wi.y, bs.wi.z};
    if (v->bent && vr_dot3(v->ng, wi) * vr_dot3(v->ng, v->wo) <= 0) break;
    double pdf_fwd = bs.pdf, pdf_rev = 0;
    if (bs.lobe & VR_LOBE_DELTA) {
      v->delta = true;
      pdf_fwd = 0;
    } else {
      double fb[VR_BSDF_MAX_WAVELENGTHS];
      vr_vec3 ns = {v->ns[0], v->ns[1], v->ns[2]};
      vr_bsdf_eval_at(v->bsdf, &v->pt, v->state, ns, (vr_vec3){wi[0], wi[1], wi[2]},
                      (vr_vec3){v->wo[0], v->wo[1], v->wo[2]}, 1, sm->wl, mode, fb, &pdf_rev);
    }
    double corr = 1;
    if (importance) {
      double on = fabs(vr_dot3(v->wo, v->ns)), og = fabs(vr_dot3(v->wo, v->ng));
      double in = fabs(vr_dot3(wi, v->ns)), ig = fabs(vr_dot3(wi, v->ng));
      corr = og > 0 && in > 0 ? on * ig / (og * in) : 0;
    }
    double mx = 0;
    for (int k = 0; k < nwl; k++) {
      beta[k] *= bs.weight[k] * corr * (v->tinted ? v->tint[k] : 1.0);
      if (beta[k] > mx) mx = beta[k];
    }
    prev->pdf_rev = bdpt_to_area(v, prev, pdf_rev * seg_rev);
    if (!(mx > 0)) break;
    /* Russian roulette from the fourth scattering on, keeping the
     * throughput near its start (ignored by the weights: a choice with
     * nonzero probability, compensated in beta, leaves every strategy
     * unbiased). */
    if (n - 1 >= 4) {
      double q = fmin(1.0, mx / ref);
      if (vr_rng(&key, VR_DIM_ROULETTE) >= q) break;
      for (int k = 0; k < nwl; k++) beta[k] /= q;
    }
    memcpy(dir, wi, sizeof dir);
    pdf_dir = pdf_fwd;
    medium = medium_towards(v, dir);
  }
  return n;
}
