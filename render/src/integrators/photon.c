/* Photon mapping with Jensen's two maps (render integrator=photon; Jensen
 * 2001): a photon pass fills the global and caustic maps (photon_trace.c),
 * then camera paths follow specular vertices to their first vertex with a
 * diffuse lobe, take the direct light there by next-event estimation
 * (paths.c) and the rest from the maps: the caustic map's estimate and
 * either the global map's or, with final_gather=on, gather rays that read
 * every map where they land.  Each pass is decided from what the scene's
 * materials call for, and said. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "integrators/integrator.h"
#include "integrators/photon_maps.h"
#include "vr/vec3.h"

typedef struct vr_photon_state {
  vr_photon_maps maps;
  bool final_gather;
  int gather_rays;
} vr_photon_state;

/* A camera path's diffuse vertex: rho/pi times the caustic map's
 * irradiance and the global map's, or gather rays for the latter. */
static bool at_diffuse(vr_pass *c, vr_flow_worker *w, vr_payload *p, const vr_hit *hit,
                       const vr_surface *se, const double wo[3]) {
  if (p->target != VR_TARGET_PIXEL) return false;
  const vr_photon_state *ps = c->state;
  const vr_photon_maps *m = &ps->maps;
  const vr_scene_tables *t = c->rs->t;
  double n[3];
  memcpy(n, hit->ng, sizeof n);
  if (vr_dot3(n, wo) < 0)
    for (int a = 0; a < 3; a++) n[a] = -n[a];
  /* rho/pi from the BSDF at wo's mirror about the shading normal (a normal
   * map's, if any), turned towards wo. */
  double refl[3], fc[VR_MAX_WL], L[VR_MAX_WL], sn[3] = {se->ns.x, se->ns.y, se->ns.z};
  if (vr_dot3(sn, wo) < 0)
    for (int a = 0; a < 3; a++) sn[a] = -sn[a];
  for (int a = 0; a < 3; a++) refl[a] = 2 * vr_dot3(sn, wo) * sn[a] - wo[a];
  vr_surface sd = *se; /* the diffuse part (a pbr surface's specular part goes on) */
  sd.pt.only = VR_LOBE_DIFFUSE;
  vr_surface_f(&sd, refl, fc);
  double cs = fabs(vr_dot3(sn, refl)), fd[VR_MAX_WL];
  for (int k = 0; k < p->nwl; k++) fd[k] = cs > 0 ? fc[k] / cs : 0; /* rho / pi */
  double E[VR_MAX_WL], Et[VR_MAX_WL] = {0};
  uint32_t surface = (uint32_t)hit->object;
  vr_photon_maps_irradiance(m, t, m->caustic, hit->p, n, surface, m->knn, m->radius, p->nwl,
                            p->wl, E);
  for (int k = 0; k < p->nwl; k++) Et[k] += E[k];
  if (!ps->final_gather) {
    vr_photon_maps_irradiance(m, t, m->global, hit->p, n, surface, m->knn, m->radius, p->nwl,
                              p->wl, E);
    for (int k = 0; k < p->nwl; k++) Et[k] += E[k];
  }
  for (int k = 0; k < p->nwl; k++) L[k] = p->beta[k] * fd[k] * Et[k];
  vr_path_deliver(c, p, L);
  if (ps->final_gather && p->depth + 1 < c->max_depth) {
    /* Gather rays: cosine-weighted, each carrying beta rho / N; they see
     * no emitter and no sky (the maps hold that light). */
    vr_rng_key key = {c->rs->seed, p->stream, p->sample, 500u + p->depth};
    for (int g = 0; g < ps->gather_rays; g++) {
      double u1 = vr_rng(&key, VR_DIM_GATHER + 2 * (uint32_t)g);
      double u2 = vr_rng(&key, VR_DIM_GATHER + 2 * (uint32_t)g + 1);
      vr_ray gr = {0};
      vr_sample_cosine(n, u1, u2, gr.dir);
      vr_spawn_origin(hit->p, hit->ng, gr.dir, gr.org);
      gr.tmax = INFINITY;
      gr.kind = VR_RAY_CLOSEST;
      gr.purpose = VR_PURPOSE_GATHER;
      vr_payload q = *p;
      q.target = VR_TARGET_GATHER;
      q.flags &= (uint16_t)~VR_PF_SPECULAR_LAST;
      q.holes = 0;
      q.depth++;
      for (int k = 0; k < p->nwl; k++) q.beta[k] = p->beta[k] * fd[k] * M_PI / ps->gather_rays;
      memcpy(gr.payload, &q, sizeof q);
      vr_flow_push(w, &gr);
    }
  }
  return true;
}

/* A final-gather ray's first hit: the maps' radiance there; its escapes
 * are the path code's (the ground glow only). */
static void closest(void *ctx, vr_flow_worker *w, const vr_ray *r, const vr_hit *hit) {
  if (r->purpose != VR_PURPOSE_GATHER || !hit) {
    vr_path_closest(ctx, w, r, hit);
    return;
  }
  vr_pass *c = ctx;
  if (vr_path_pass_through(c, w, r, hit)) return;
  const vr_photon_state *ps = c->state;
  vr_payload p;
  memcpy(&p, r->payload, sizeof p);
  vr_path_absorb(c->rs, &p, hit);
  double wo[3] = {-r->dir[0], -r->dir[1], -r->dir[2]}, L[VR_MAX_WL];
  vr_surface se = vr_path_surface(c->rs, &p, hit, wo);
  if (!(vr_bsdf_lobes(se.b) & VR_LOBE_DIFFUSE)) return;
  vr_photon_maps_radiance(&ps->maps, c->rs, hit, wo, &se, &p,
                          VR_MAP_DIRECT | VR_MAP_CAUSTIC | VR_MAP_GLOBAL, ps->maps.knn,
                          ps->maps.radius, L, NULL);
  vr_path_deliver(c, &p, L);
}

static const vr_flow_ops camera_ops = {closest, vr_path_shadow_hit, vr_path_shadow_done,
                                       vr_camera_generate, VR_PAYLOAD_WIRE};

static vr_status render(vr_camera_job *job, vr_error *err) {
  vr_run *r = job->run;
  const vr_scene_settings *set = &job->rs->s->settings;
  const vr_scene_needs *nd = &job->needs;
  bool need_global, need_caustic;
  vr_integrator_photon_needs(job, &need_global, &need_caustic);
  vr_pass_record *rg =
      vr_run_record(r, "global photons", need_global, "%s",
                    need_global ? "diffuse surfaces interreflect: global photon map for indirect light"
                    : !nd->diffuse ? "no diffuse surface to store photons on"
                    : !job->lights_exist ? "no light with power"
                                         : "depth 1: no indirect light asked for");
  vr_pass_record *rc;
  if (need_caustic)
    rc = vr_run_record(r, "caustic photons", true,
                       "material '%s' reflects or refracts specularly onto diffuse surfaces",
                       nd->specular_example);
  else
    rc = vr_run_record(r, "caustic photons", false, "%s",
                       !nd->specular ? "no specular or glossy surface: no caustics possible"
                                     : "no diffuse surface or no light: caustics cannot form");
  vr_photon_state ps = {.final_gather = set->final_gather, .gather_rays = set->gather_rays};
  ps.maps.knn = set->knn;
  ps.maps.fixed_radius = !isnan(set->radius_m);
  ps.maps.radius = isnan(set->radius_m) ? 0.1 * job->rs->scene_radius : set->radius_m;
  /* An estimate on a rect reads its sheet (surface_disc.h): the share of
   * its disc there divides it (docs/vr-render.md, "Photon sensors"). */
  ps.maps.edge_share = true;
  vr_pass c = vr_integrator_pass(job);
  c.at_diffuse = at_diffuse;
  c.state = &ps;
  job->passes = 1;
  vr_status st = VR_OK;
  double t_photons = 0;
  if (need_global || need_caustic) {
    double t0 = vr_run_now();
    st = vr_photon_maps_trace(r, &c, &ps.maps, need_global ? job->photons : job->caustic_photons,
                              need_caustic, need_global, need_global && ps.final_gather, err);
    t_photons = vr_run_now() - t0;
  }
  if (!st && need_caustic && vr_photon_set_count(ps.maps.caustic) == 0) {
    /* Specular surfaces exist but no photon reached a diffuse one through
     * them (they are not lit, or too small for the photons traced):
     * nothing to read, and the pass says so. */
    rc->ran = false;
    snprintf(rc->reason, sizeof rc->reason,
             "none of %ld photons stored: no specular surface (e.g. '%.24s') lit a diffuse one; "
             "map not read (%.2f s)",
             need_global ? job->photons : job->caustic_photons, nd->specular_example, t_photons);
    vr_photon_set_destroy(ps.maps.caustic);
    ps.maps.caustic = NULL;
  }
  if (!st) st = vr_integrator_camera(job, &c, &camera_ops, err);
  vr_photon_maps_free(r, &ps.maps);
  for (vr_pass_record *p = rg; p && p <= rc; p++)
    if (p->ran) p->seconds = t_photons;
  return st;
}

const vr_integrator_ops vr_integrator_photon = {.name = "photon", .what = "photon mapping",
                                                .render = render, .adaptive = true};
