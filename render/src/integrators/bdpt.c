/* Bidirectional path tracing (Veach 1997, ch. 10; Lafortune & Willems
 * 1993), `render integrator=bdpt`: an unbiased reference for what the path
 * tracer cannot see, above all caustics from point lights (a diffuse
 * surface seen by the camera, lit by a point light through a mirror or a
 * refraction: no next-event estimate and no BSDF sample can reach a point
 * light through a delta lobe, but a light subpath can, and its last vertex
 * projects onto the image).
 *
 * Each camera sample makes one camera subpath and one light subpath (same
 * wavelengths: hero sampling, vr_wavelengths) and joins every prefix pair
 * (s light vertices, t camera vertices) with s + t - 2 <= depth scattering
 * vertices:
 *   s = 0      the camera subpath hits an emitter;
 *   s = 1      next-event estimation: a light point chosen as light
 *              subpaths choose theirs;
 *   t = 1      light tracing: a light vertex is joined to the lens and
 *              added to the pixel it projects to (pinhole and thin lens);
 *   s, t >= 2  a connection between two non-delta vertices;
 * each weighted by the power heuristic over all strategies that could
 * have made the same path (pbrt-v4's MISWeight: the ratios of reverse to
 * forward area densities along the path, delta vertices skipped).
 *
 * What BDPT does not cover, and why:
 *   - the sun, the sky and the ground glow are far sources with no
 *     position to start a light subpath from inside a room; they are
 *     estimated on the camera subpath as the path tracer does (one sample
 *     of the sun and of the sky at each non-delta vertex, the sky on escape
 *     after a delta vertex, the ground glow on every escape), with weight
 *     1.  So sunlight through a mirror onto a wall stays as invisible here
 *     as to the path tracer; lamps and emitters have every strategy;
 *   - the sub-domains: connections need their answer at once, so each
 *     worker traces whole tiles in the scene's one cell
 *     (vr_domains_intersect), as the image-space mode does: no
 *     --subdomains above 1, no memory budget, one process (vr_bdpt_check);
 *   - fisheye cameras (their importance is not written here).
 * Russian roulette ends subpaths after four scatterings; it is not in the
 * weights (any termination with nonzero probability, compensated in the
 * throughput, keeps every strategy unbiased; pbrt leaves it out the same
 * way). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "integrators/bdpt_internal.h"
#include "vr/filter.h"

/* It needs the whole scene in one cell (no --subdomains above 1 outside
 * image space, no memory budget, one process) and a camera model that
 * light tracing can project onto. */
static vr_status check(const vr_scene *s, const vr_render_options *opt, int nranks,
                       vr_error *err) {
  if (!s->camera.given || opt->no_camera) return VR_OK;
  const char *why = "integrator bdpt traces whole paths in one sub-domain holding the scene";
  if (opt->subdomains > 1 && !opt->image_space)
    return vr_error_set(err, VR_E_ARG, "%s: --subdomains %d is not supported (use 1)", why,
                        opt->subdomains);
  if (opt->memory_budget)
    return vr_error_set(err, VR_E_ARG, "%s: a memory budget is not supported", why);
  if (nranks > 1)
    return vr_error_set(err, VR_E_ARG, "%s: it runs in one process, not on %d MPI ranks", why,
                        nranks);
  /* A translucent diffuser transmits through a lobe that BDPT's
   * connections would take for a refracting interface (a medium behind it):
   * its images came out 40 % dark against the path tracer's, so it is
   * refused rather than rendered wrong. */
  for (size_t i = 0; i < s->nmaterials; i++)
    if (s->materials[i].source == VR_MATSRC_TRANSLUCENT)
      return vr_error_set(err, VR_E_ARG,
                          "%s:%ld: material '%s' is a translucent diffuser (a Radiance trans), "
                          "which integrator bdpt does not render; use integrator=path",
                          s->path, s->materials[i].loc.line, s->materials[i].name);
  if (!vr_camera_model_ops(s->camera.model)->raster)
    return vr_error_set(err, VR_E_ARG,
                        "%s:%ld:%ld: integrator bdpt needs a pinhole or thin-lens camera, not a "
                        "fisheye (light tracing projects onto the image)",
                        s->path, s->camera.loc.line, s->camera.loc.col);
  return VR_OK;
}

static double remap0(double x) { return x != 0 ? x : 1; }

/* Area density at next of sampling it from v, v reached from prev. */
static double vpdf(const vr_bdpt *b, const vr_bdpt_sample *sm, const vr_bdpt_vertex *v, const vr_bdpt_vertex *prev,
                   const vr_bdpt_vertex *next) {
  double wn[3], l2 = 0, pdf = 0;
  for (int a = 0; a < 3; a++) {
    wn[a] = next->p[a] - v->p[a];
    l2 += wn[a] * wn[a];
  }
  if (!(l2 > 0)) return 0;
  double l = sqrt(l2);
  for (int a = 0; a < 3; a++) wn[a] /= l;
  switch (v->type) {
  case BV_CAMERA: pdf = b->cam->ops->pdf_dir(b->cam, v->p, next->p); break;
  case BV_LIGHT: pdf = bdpt_light_pdf_dir(b, v, wn); break;
  default: {
    if (!prev) return 0;
    double wp[3], m2 = 0, f[VR_BSDF_MAX_WAVELENGTHS];
    for (int a = 0; a < 3; a++) {
      wp[a] = prev->p[a] - v->p[a];
      m2 += wp[a] * wp[a];
    }
    if (!(m2 > 0)) return 0;
    double m = sqrt(m2);
    vr_bsdf_eval_at(v->bsdf, &v->pt, v->state, (vr_vec3){v->ns[0], v->ns[1], v->ns[2]},
                    (vr_vec3){wp[0] / m, wp[1] / m, wp[2] / m}, (vr_vec3){wn[0], wn[1], wn[2]},
                    1, sm->wl, VR_TRANSPORT_RADIANCE, f, &pdf);
  }
  }
  return bdpt_to_area(v, next, pdf);
}

/* The power-heuristic weight of strategy (s, t) for the path it made:
 * 1 / (1 + sum over the other strategies of (p_i / p_s)^2), the ratios
 * walked outwards from the connection (pbrt-v4's MISWeight).  sampled
 * replaces light[0] (s = 1) or cam[0] (t = 1); p_cl and p_lc are the
 * panes' choice probabilities on the connection, travelling from the
 * camera side to the light side and back.  sa_pq and sa_qp, when not
 * negative, are the direction densities the connection's BSDF
 * evaluations already gave: at the camera side's end towards the light
 * side's and back. */
static double mis_weight(const vr_bdpt *b, const vr_bdpt_sample *sm, vr_bdpt_vertex *light, vr_bdpt_vertex *cam, int s,
                         int t, const vr_bdpt_vertex *sampled, double p_cl, double p_lc, double sa_pq,
                         double sa_qp) {
  if (s + t == 2) return 1;
  vr_bdpt_vertex keep0 = {0};
  if (s == 1) keep0 = light[0], light[0] = *sampled;
  if (t == 1) keep0 = cam[0], cam[0] = *sampled;
  vr_bdpt_vertex *qs = s > 0 ? &light[s - 1] : NULL, *pt = &cam[t - 1];
  vr_bdpt_vertex *qsm = s > 1 ? &light[s - 2] : NULL, *ptm = t > 1 ? &cam[t - 2] : NULL;
  double pt_rev = pt->pdf_rev, ptm_rev = ptm ? ptm->pdf_rev : 0;
  double qs_rev = qs ? qs->pdf_rev : 0, qsm_rev = qsm ? qsm->pdf_rev : 0;
  bool pt_delta = pt->delta, qs_delta = qs ? qs->delta : false;
  pt->delta = false;
  if (qs) qs->delta = false;
  if (s > 0) {
    pt->pdf_rev = (sa_qp >= 0 ? bdpt_to_area(qs, pt, sa_qp) : vpdf(b, sm, qs, qsm, pt)) * p_lc;
    if (ptm) ptm->pdf_rev = vpdf(b, sm, pt, qs, ptm) * pt->seg_rev;
    qs->pdf_rev = (sa_pq >= 0 ? bdpt_to_area(pt, qs, sa_pq) : vpdf(b, sm, pt, ptm, qs)) * p_cl;
    if (qsm) qsm->pdf_rev = vpdf(b, sm, qs, pt, qsm) * qs->seg_rev;
  } else {
    /* The camera subpath hit an emitter: its point as a light subpath's
     * origin, and the emission towards the vertex before. */
    pt->pdf_rev = bdpt_light_pdf_origin(b, pt);
    if (ptm) {
      double w[3], l = 0;
      for (int a = 0; a < 3; a++) w[a] = ptm->p[a] - pt->p[a], l += w[a] * w[a];
      l = sqrt(l);
      for (int a = 0; a < 3; a++) w[a] /= l;
      ptm->pdf_rev = bdpt_to_area(pt, ptm, bdpt_light_pdf_dir(b, pt, w)) * pt->seg_rev;
    }
  }
  double sum = 0, ri = 1;
  for (int i = t - 1; i > 0; i--) {
    double r = remap0(cam[i].pdf_rev) / remap0(cam[i].pdf_fwd);
    ri *= r * r;
    if (!cam[i].delta && !cam[i - 1].delta) sum += ri;
  }
  ri = 1;
  for (int i = s - 1; i >= 0; i--) {
    double r = remap0(light[i].pdf_rev) / remap0(light[i].pdf_fwd);
    ri *= r * r;
    bool delta_before = i > 0 ? light[i - 1].delta : light[0].delta_light;
    if (!light[i].delta && !delta_before) sum += ri;
  }
  if (qsm) qsm->pdf_rev = qsm_rev;
  if (qs) qs->pdf_rev = qs_rev, qs->delta = qs_delta;
  if (ptm) ptm->pdf_rev = ptm_rev;
  pt->pdf_rev = pt_rev, pt->delta = pt_delta;
  if (s == 1) light[0] = keep0;
  if (t == 1) cam[0] = keep0;
  return 1.0 / (1.0 + sum);
}

static bool finite_all(const double *v, int n) {
  for (int k = 0; k < n; k++)
    if (!isfinite(v[k])) return false;
  return true;
}

static void unit_to(const double from[3], const double to[3], double d[3], double *d2) {
  *d2 = 0;
  for (int a = 0; a < 3; a++) {
    d[a] = to[a] - from[a];
    *d2 += d[a] * d[a];
  }
  double l = sqrt(*d2);
  for (int a = 0; a < 3; a++) d[a] /= l;
}

/* Light tracing (t = 1): light vertex s-1 joined to the lens, added to the
 * pixel it projects to. */
static void splat(const vr_bdpt *b, vr_bdpt_tls *tl, const vr_bdpt_sample *sm, vr_bdpt_vertex *light, vr_bdpt_vertex *cam,
                  int s) {
  const vr_camera *cm = b->cam;
  vr_bdpt_vertex *qs = &light[s - 1];
  if (!qs->connectible) return;
  vr_bdpt_vertex c = cam[0];
  vr_rng_key key = {b->rs->seed, sm->stream, sm->sample, BK_LENS + (uint32_t)s};
  cm->ops->sample_lens(cm, &key, c.p);
  double px, py, ct, wi[3], d2, f[VR_MAX_WL], L[VR_MAX_WL], T[VR_MAX_WL], p_cl, p_lc;
  if (!cm->ops->raster(cm, c.p, qs->p, &px, &py, &ct)) return;
  unit_to(qs->p, c.p, wi, &d2);
  double sa_qp;
  bdpt_f(qs, wi, sm->nwl, sm->wl, true, f, &sa_qp);
  double g = fabs(vr_dot3(qs->ns, wi)) / (d2 * cm->area * ct * ct * ct);
  bool any = false;
  for (int k = 0; k < sm->nwl; k++) any |= (L[k] = qs->beta[k] * f[k] * g) > 0;
  if (!any || !bdpt_visible(b, tl, &c, qs, sm->nwl, sm->wl, T, &p_cl, &p_lc)) return;
  double w = mis_weight(b, sm, light, cam, s, 1, &c, p_cl, p_lc, -1, sa_qp) / b->spp;
  for (int k = 0; k < sm->nwl; k++) L[k] *= T[k] * w;
  if (!finite_all(L, sm->nwl)) {
    tl->dropped++;
    return;
  }
  const vr_filter *fl = &b->rs->s->camera.filter;
  if (fl->kind == VR_FILTER_BOX && !(fl->radius > 0.5)) {
    vr_accum_pixel(b->acc, (uint32_t)((int)py * cm->W + (int)px), sm->nwl, sm->wl, L,
                   b->wl_weight);
    return;
  }
  /* A wider filter: pixel j's measurement weighs the image point by
   * f(p - centre_j) / F, so the point goes to every pixel within reach. */
  double R = fl->radius, F = fl->f_all, Lj[VR_MAX_WL];
  int jx0 = (int)floor(px - R - 0.5), jx1 = (int)ceil(px + R - 0.5);
  int jy0 = (int)floor(py - R - 0.5), jy1 = (int)ceil(py + R - 0.5);
  for (int jy = jy0 < 0 ? 0 : jy0; jy <= jy1 && jy < cm->H; jy++)
    for (int jx = jx0 < 0 ? 0 : jx0; jx <= jx1 && jx < cm->W; jx++) {
      double fw = vr_filter_eval(fl, px - (jx + 0.5), py - (jy + 0.5)) / F;
      if (fw == 0) continue;
      for (int k = 0; k < sm->nwl; k++) Lj[k] = L[k] * fw;
      vr_accum_pixel(b->acc, (uint32_t)(jy * cm->W + jx), sm->nwl, sm->wl, Lj, b->wl_weight);
    }
}

/* Strategy (s, t) with t >= 2, added to sum. */
static void connect(const vr_bdpt *b, vr_bdpt_tls *tl, const vr_bdpt_sample *sm, vr_bdpt_vertex *light, vr_bdpt_vertex *cam,
                    int s, int t, double *sum) {
  const int nwl = sm->nwl;
  vr_bdpt_vertex *pt = &cam[t - 1], sampled = {0};
  double L[VR_MAX_WL], T[VR_MAX_WL], f[VR_MAX_WL], wi[3], d2, p_cl = 1, p_lc = 1;
  double sa_pq = -1, sa_qp = -1;
  bool any = false;
  if (s == 0) {
    if (pt->source < 0) return;
    double Le[VR_MAX_WL];
    bdpt_emitted(b, pt, pt->wo, nwl, sm->wl, Le);
    for (int k = 0; k < nwl; k++) any |= (L[k] = pt->beta[k] * Le[k]) > 0;
    if (!any) return;
  } else if (s == 1) {
    double c[VR_MAX_WL];
    if (!pt->connectible ||
        !bdpt_light_sample(b, sm, BK_NEE + (uint32_t)(t - 1), pt->p, &sampled, c))
      return;
    unit_to(pt->p, sampled.p, wi, &d2);
    bdpt_f(pt, wi, nwl, sm->wl, false, f, &sa_pq);
    double cs = fabs(vr_dot3(pt->ns, wi));
    for (int k = 0; k < nwl; k++) any |= (L[k] = pt->beta[k] * f[k] * cs * c[k]) > 0;
    if (!any || !bdpt_visible(b, tl, pt, &sampled, nwl, sm->wl, T, &p_cl, &p_lc)) return;
    for (int k = 0; k < nwl; k++) L[k] *= T[k];
  } else {
    vr_bdpt_vertex *qs = &light[s - 1];
    if (!pt->connectible || !qs->connectible) return;
    double fl[VR_MAX_WL], back[3];
    unit_to(pt->p, qs->p, wi, &d2);
    for (int a = 0; a < 3; a++) back[a] = -wi[a];
    bdpt_f(pt, wi, nwl, sm->wl, false, f, &sa_pq);
    bdpt_f(qs, back, nwl, sm->wl, true, fl, &sa_qp);
    double g = fabs(vr_dot3(pt->ns, wi)) * fabs(vr_dot3(qs->ns, wi)) / d2;
    /* Two dispersive refractions, one on each side: the factor nwl once. */
    if (pt->term && qs->term) g /= nwl;
    for (int k = 0; k < nwl; k++) any |= (L[k] = pt->beta[k] * f[k] * g * fl[k] * qs->beta[k]) > 0;
    if (!any || !bdpt_visible(b, tl, pt, qs, nwl, sm->wl, T, &p_cl, &p_lc)) return;
    for (int k = 0; k < nwl; k++) L[k] *= T[k];
  }
  double w = mis_weight(b, sm, light, cam, s, t, &sampled, p_cl, p_lc, sa_pq, sa_qp);
  for (int k = 0; k < nwl; k++) L[k] *= w;
  if (!finite_all(L, nwl)) {
    tl->dropped++;
    return;
  }
  for (int k = 0; k < nwl; k++) sum[k] += L[k];
}

/* One camera sample of pixel (x, y): both subpaths and every strategy. */
static void one_sample(const vr_bdpt *b, vr_bdpt_tls *tl, int x, int y, int s_index) {
  const vr_rscene *rs = b->rs;
  const vr_camera *cm = b->cam;
  vr_bdpt_sample sm = {.stream = (uint64_t)y * cm->W + x, .sample = (uint32_t)(s_index + b->sample_offset),
                .nwl = b->nwl};
  vr_rng_key key = {rs->seed, sm.stream, sm.sample, 0};
  vr_wavelengths(rs, &key, (uint32_t)b->spp, sm.wl);
  /* The pixel filter's sample (vr/filter.h): its offset from the pixel's
   * centre and its weight (1 but for the negative lobes of mitchell). */
  double dx, dy;
  double fw = vr_filter_sample(&rs->s->camera.filter, &key, (uint32_t)s_index, (uint32_t)b->spp,
                               &dx, &dy);
  double dir[3], org[3];
  cm->ops->generate(cm, x + 0.5 + dx, y + 0.5 + dy, &key, org, dir);
  double ct = vr_dot3(dir, cm->w);
  vr_bdpt_vertex *cam = tl->cam, *light = tl->light;
  memset(&cam[0], 0, sizeof cam[0]);
  cam[0].type = BV_CAMERA;
  memcpy(cam[0].p, org, sizeof org);
  memcpy(cam[0].ng, cm->w, sizeof cam[0].ng);
  memcpy(cam[0].ns, cm->w, sizeof cam[0].ns);
  cam[0].medium = -1;
  cam[0].source = -1;
  cam[0].connectible = true;
  cam[0].seg_rev = 1;
  cam[0].pdf_fwd = 1;
  for (int k = 0; k < sm.nwl; k++) cam[0].beta[k] = 1;
  double sum[VR_MAX_WL] = {0};
  int nc = bdpt_walk(b, tl, &sm, cam, 1, b->max_depth + 2, dir, 1.0 / (cm->area * ct * ct * ct),
                     cam[0].beta, false, BK_CAMERA_WALK, sum);
  int nl = 0;
  if (b->L.n) {
    double ldir[3], lpdf, lbeta[VR_MAX_WL];
    if (bdpt_light_start(b, &sm, &light[0], ldir, &lpdf, lbeta))
      nl = bdpt_walk(b, tl, &sm, light, 1, b->max_depth + 1, ldir, lpdf, lbeta, true,
                     BK_LIGHT_WALK, NULL);
  }
  int smax = nl > 1 ? nl : (b->L.n ? 1 : 0);
  for (int t = 1; t <= nc; t++)
    for (int s = 0; s <= smax; s++) {
      int depth = s + t - 2;
      if ((s == 1 && t == 1) || depth < 0 || depth > b->max_depth) continue;
      if (t == 1) splat(b, tl, &sm, light, cam, s);
      else connect(b, tl, &sm, light, cam, s, t, sum);
    }
  if (!finite_all(sum, sm.nwl)) {
    tl->dropped++;
    return;
  }
  for (int k = 0; k < sm.nwl; k++) sum[k] *= fw / b->spp;
  vr_accum_pixel(b->acc, (uint32_t)sm.stream, sm.nwl, sm.wl, sum, b->wl_weight);
}

/* A unit: one tile of the image, all its samples. */
static void generate(void *ctx, vr_flow_worker *w, long unit) {
  const vr_bdpt *b = ctx;
  vr_bdpt_tls *tl = &b->tls[vr_flow_worker_index(w)];
  int x0, y0, x1, y1;
  vr_flow_tile(b->cam->W, b->cam->H, unit, &x0, &y0, &x1, &y1);
  for (int y = y0; y < y1; y++)
    for (int x = x0; x < x1; x++)
      for (int s = 0; s < b->spp; s++) one_sample(b, tl, x, y, s);
}

/* BDPT pushes no ray into the flow: these are never called. */
static void no_closest(void *ctx, vr_flow_worker *w, const vr_ray *r, const vr_hit *hit) {
  (void)ctx, (void)w, (void)r, (void)hit;
}
static bool no_shadow_hit(void *ctx, vr_flow_worker *w, vr_ray *r, const vr_hit *hit) {
  (void)ctx, (void)w, (void)r, (void)hit;
  return false;
}
static void no_shadow_done(void *ctx, vr_flow_worker *w, const vr_ray *r, bool reached) {
  (void)ctx, (void)w, (void)r, (void)reached;
}
static const vr_flow_ops bdpt_ops = {no_closest, no_shadow_hit, no_shadow_done, generate,
                                      NULL, NULL, NULL};

static void progress(void *u, long done, long total) {
  const vr_run *r = u;
  if (r->opt->progress) r->opt->progress(r->opt->user, r->pass, done, total);
}

static vr_status render(vr_camera_job *job, vr_error *err) {
  vr_run *r = job->run;
  vr_rscene *rs = job->rs;
  vr_integrator_no_photons(r, "bdpt");
  job->passes = 1;
  double t0 = vr_run_now();
  vr_bdpt b = {.rs = rs, .acc = job->acc, .cam = &rs->cam, .spp = job->spp, .sample_offset = 0,
               .max_depth = rs->s->settings.max_depth, .nwl = rs->nwl};
  b.wl_weight = (rs->lmax - rs->lmin) / rs->nwl;
  b.threads = r->opt->threads > 0 ? r->opt->threads : 1;
  vr_status st = bdpt_lights_init(&b.L, rs, err);
  if (st) return st;
  b.tls = calloc((size_t)b.threads, sizeof *b.tls);
  for (int i = 0; b.tls && i < b.threads; i++) {
    b.tls[i].cam = malloc((size_t)(b.max_depth + 2) * sizeof *b.tls[i].cam);
    b.tls[i].light = malloc((size_t)(b.max_depth + 2) * sizeof *b.tls[i].light);
    if (!b.tls[i].cam || !b.tls[i].light) st = VR_E_NOMEM;
  }
  if (!b.tls || st) st = vr_error_set(err, VR_E_NOMEM, "bdpt: out of memory");
  vr_flow_stats fs = {0};
  r->pass = "camera";
  if (!st)
    st = vr_flow_run_image_space(rs->d, &bdpt_ops, &b, vr_flow_tiles(job->W, job->H), b.threads,
                                 progress, r, &fs, err);
  uint64_t cam_rays = 0, light_rays = 0, shadow = 0, dropped = 0;
  for (int i = 0; b.tls && i < b.threads; i++) {
    cam_rays += b.tls[i].rays_camera, light_rays += b.tls[i].rays_light;
    shadow += b.tls[i].rays_shadow, dropped += b.tls[i].dropped;
    free(b.tls[i].cam);
    free(b.tls[i].light);
  }
  free(b.tls);
  bdpt_lights_free(&b.L);
  vr_render_result *res = r->res;
  res->rays_camera += cam_rays;
  res->rays_photon += light_rays;
  res->rays_shadow += shadow;
  res->rays_created += cam_rays + light_rays + shadow;
  res->rays_finished += cam_rays + light_rays + shadow;
  if (!st && dropped)
    vr_run_say(r, "bdpt: %llu contributions that were not finite left out",
               (unsigned long long)dropped);
  job->seconds += vr_run_now() - t0;
  return st;
}

const vr_integrator_ops vr_integrator_bdpt = {.name = "bdpt", .what = "bidirectional path tracing",
                                              .check = check, .render = render};
