/* Stochastic progressive photon mapping (render integrator=progressive,
 * alias sppm; sppm.h): spp iterations, each of one camera path a pixel to
 * its visible point (paths.c, with this integrator's say at the first
 * diffuse vertex) and `photons` photons landing on the visible points
 * (photon_trace.c); each step's sums are added over the ranks.
 *
 * Denoised (--denoise), it runs two independent chains of spp / 2
 * iterations, each from the first radius with its own block of the
 * sampler's samples and photons: the image is their mean, and the second
 * chain's estimate is the denoiser's second half (film_features.c), as a
 * path tracer's second half of samples.  Each chain's radius shrinks over
 * spp / 2 iterations only, so the mean keeps the bias of spp / 2
 * iterations while its variance is that of spp. */
#include <math.h>
#include <stdlib.h>

#include "integrators/integrator.h"
#include "integrators/photon_maps.h"
#include "integrators/sppm.h"
#include "vr/comm.h"

/* The first radius of a pixel's visible point, in pixel footprints at the
 * point, unless the scene gives radius= (metres). */
#define SPPM_RADIUS_PX 4.0

/* ... or, where one iteration's photons are sparser, the radius that holds
 * SPPM_PILOT_PHOTONS / I of them (at least one), I the chain's iterations:
 * the first disc then meets about SPPM_PILOT_PHOTONS photons over the
 * render (1/16 of relative noise in the photon light before the radius
 * shrinks), and the more iterations, the smaller it starts (the less
 * smoothing bias is left at the end).  The density is read in pilot maps
 * of one iteration's photons traced apart, before the first iteration.
 * Without it the first disc of a few pixels at 640 x 480 in the sample
 * room held about half a photon an iteration, and 16 iterations left
 * blotches of a few photons each (docs/benchmarks.md, "SPPM at the main
 * job's 640 x 480"). */
#define SPPM_PILOT_PHOTONS 256

/* Progressive photon mapping renders spp iterations of one camera path a
 * pixel each; passes= is the older name of that count.  Each iteration's
 * wavelengths serve every pixel, so one iteration's spectral quadrature
 * must be good: 4 wavelengths 75 nm apart left Z (the narrowest
 * colour-matching function) 1.2 x noisier than Y in the white furnace
 * (tests/render/test_sppm.c), 8 do not. */
static vr_status settings(const vr_scn_stmt *t, vr_scene_settings *g, long long *spp,
                          long long *wavelengths) {
  (void)g;
  const vr_scn_opt *o = scn_get(t, "passes");
  if (o) {
    if (scn_get(t, "spp"))
      return scn_fail(t->p, o->word,
                      "spp= and passes= both given: integrator=progressive renders spp iterations "
                      "of one camera path a pixel and `photons` photons each (passes= is the "
                      "older name of spp=)");
    vr_status st = scn_int_opt(t, "passes", 1, 1 << 20, spp);
    if (st) return st;
  }
  if (!scn_get(t, "wavelengths")) *wavelengths = VR_SCENE_MAX_WAVELENGTHS;
  return VR_OK;
}

/* SPPM: the next-event estimate took the direct light; the vertex is the
 * pixel's visible point, where the photons of this iteration add the rest. */
static bool at_diffuse(vr_pass *c, vr_flow_worker *w, vr_payload *p, const vr_hit *hit,
                       const vr_surface *se, const double wo[3]) {
  (void)w;
  /* One visible point a pixel: where a pbr surface's path went on by its
   * specular part after leaving its point, the next diffuse vertices are
   * path traced (next-event estimation and sampling), not a second point
   * over the first. */
  if (p->target != VR_TARGET_PIXEL || (p->flags & VR_PF_VISIBLE_SET)) return false;
  p->flags |= VR_PF_VISIBLE_SET;
  double bw[VR_MAX_WL]; /* the sample's weight too: a pixel filter's negative lobes */
  /* ... and a texture's factor: what the point reflects of the photons. */
  for (int k = 0; k < p->nwl; k++) bw[k] = p->beta[k] * p->weight * (se->tinted ? se->tint[k] : 1.0);
  double ns[3] = {se->ns.x, se->ns.y, se->ns.z}; /* a normal map's, if any */
  vr_sppm_set_point(c->state, c->rs, p->index, hit->p, ns, hit->ng, (int)hit->object, wo,
                    c->rs->obj[hit->object].material, se->state, &se->pt, p->nwl, bw,
                    (p->flags & VR_PF_TERMINATED) != 0);
  return true;
}

/* Light that has scattered off something other than a straight pane
 * (next-event estimation took the rest) reaches the visible points about
 * the hit. */
static void land(vr_pass *c, const vr_payload *p, const vr_hit *hit, const double dir[3]) {
  if (!(p->flags & (VR_PF_HAS_DIFFUSE | VR_PF_HAS_SPECULAR))) return;
  double wi[3] = {-dir[0], -dir[1], -dir[2]};
  vr_sppm_deposit(c->state, c->rs, hit->p, hit->ng, (int)hit->object, wi, p->beta,
                  (p->flags & VR_PF_TERMINATED) != 0);
}

/* One iteration of a chain of `iterations`: the visible points, their
 * grid, the photons, the update; each step's sums added over the ranks.
 * `sample` is the camera paths' and photons' sample index (the chain's
 * first plus the iteration), whose remainder by `iterations` strata the
 * hero wavelength. */
static vr_status iteration(vr_camera_job *job, vr_pass *c, int sample, int iterations,
                           bool trace_photons, double *t_photons, vr_error *err) {
  vr_run *r = job->run;
  vr_sppm *s = c->state;
  vr_sppm_begin(s, job->rs, sample, iterations);
  c->sample_offset = sample;
  vr_status st = vr_integrator_camera(job, c, &vr_camera_path_ops, err);
  double t0 = vr_run_now();
  if (!st && r->nranks > 1) st = vr_sppm_sum_points(s, r->comm, err);
  if (!st) st = vr_sppm_build(s, job->rs, err);
  job->seconds += vr_run_now() - t0;
  if (st || !trace_photons) return st;
  t0 = vr_run_now();
  vr_pass pc = *c;
  pc.land = land;
  pc.photons_per_unit = 1024;
  long units = (job->photons + pc.photons_per_unit - 1) / pc.photons_per_unit;
  if (units < 1) units = 1;
  st = vr_run_flow(r, &vr_photon_ops, &pc, units, "photons", err);
  if (!st && r->nranks > 1) st = vr_sppm_sum_photons(s, r->comm, err);
  if (!st) vr_sppm_update(s, (uint64_t)units * (uint64_t)pc.photons_per_unit);
  *t_photons += vr_run_now() - t0;
  return st;
}

/* One chain, or two (denoising); the image is their mean. */
typedef struct chains {
  int n;
  vr_sppm s[2];
} chains;

static void add_film(const void *state, double *xyz, double *spectral) {
  const chains *ch = state;
  for (int i = 0; i < ch->n; i++) vr_sppm_film(&ch->s[i], 1.0 / ch->n, xyz, spectral);
}

/* The second chain's photon radiance, to the second half's mean. */
static void add_half_film(const void *state, double *xyz) {
  const chains *ch = state;
  vr_sppm_film(&ch->s[1], 1.0, xyz, NULL);
}

static void free_state(void *state) {
  chains *ch = state;
  for (int i = 0; i < ch->n; i++) vr_sppm_destroy(&ch->s[i]);
  free(ch);
}

static vr_status render(vr_camera_job *job, vr_error *err) {
  vr_run *r = job->run;
  const vr_scene_settings *set = &job->rs->s->settings;
  const vr_scene_needs *nd = &job->needs;
  bool need_global, need_caustic;
  vr_integrator_photon_needs(job, &need_global, &need_caustic);
  bool any = need_global || need_caustic;
  vr_pass_record *rp =
      vr_run_record(r, "photons", any, "%s",
                    any && isnan(set->radius_m)
                        ? "progressive photon mapping: each iteration's photons reach the visible "
                          "points where they land (first radii from a pilot map of one "
                          "iteration's photons)"
                    : any ? "progressive photon mapping: each iteration's photons reach the visible "
                            "points where they land (no map kept; first radius from radius=)"
                    : !nd->diffuse ? "no diffuse surface for photons to reach"
                    : !job->lights_exist ? "no light with power"
                                         : "depth 1: no indirect light asked for");
  chains *ch = calloc(1, sizeof *ch);
  if (!ch) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  /* The denoiser's halves are the chains: the camera passes are not split
   * (vr_integrator_camera), each is one sample a pixel of its chain. */
  ch->n = job->halves ? 2 : 1;
  job->halves = false;
  vr_status st = VR_OK;
  for (int i = 0; i < ch->n && !st; i++) {
    st = vr_sppm_create(&ch->s[i], job->rs, job->W, job->H, job->acc->nbins,
                        isnan(set->radius_m) ? 0 : set->radius_m, SPPM_RADIUS_PX, set->alpha, err);
    if (st) ch->n = i;
  }
  job->state = ch, job->add_film = add_film, job->free_state = free_state;
  if (ch->n == 2) job->add_half_film = add_half_film;
  if (st) return st;
  vr_pass c = vr_integrator_pass(job);
  c.spp = 1;
  c.at_diffuse = at_diffuse;
  job->passes = job->spp;
  double t_photons = 0;
  /* The pilot maps: one iteration's photons, with the sample block after
   * the iterations' (independent of them), read only for first radii. */
  vr_photon_maps pilot = {0};
  bool piloted = any && isnan(set->radius_m);
  int per = job->spp / ch->n; /* check_denoise: spp is even when denoised */
  int pilot_k = (SPPM_PILOT_PHOTONS + per - 1) / per;
  if (piloted) {
    double t0 = vr_run_now();
    vr_pass pc = c;
    pc.sample_offset = job->spp;
    st = vr_photon_maps_trace(r, &pc, &pilot, job->photons, need_caustic, need_global, false, err);
    t_photons += vr_run_now() - t0;
    for (int i = 0; i < ch->n && !st; i++)
      vr_sppm_set_pilot(&ch->s[i], &pilot, pilot_k, 0.1 * job->rs->scene_radius);
  }
  for (int i = 0; i < ch->n && !st; i++) {
    c.state = &ch->s[i];
    c.fixed_wl = ch->s[i].wl;
    c.second_half = i == 1;
    for (int it = 0; !st && it < per; it++)
      st = iteration(job, &c, i * per + it, per, any, &t_photons, err);
  }
  if (piloted) {
    for (int i = 0; i < ch->n; i++) vr_sppm_set_pilot(&ch->s[i], NULL, 0, 0);
    vr_photon_maps_free(r, &pilot);
  }
  if (st) return st;
  double rlo, rmed, rhi;
  vr_sppm_radii(&ch->s[0], &rlo, &rmed, &rhi);
  if (ch->n == 2)
    vr_run_say(r, "progressive: 2 independent chains (the denoiser's halves) of %d iterations of "
                  "%ld photons; the first's pixel radii now %.3g to %.3g mm (median %.3g mm)",
               per, job->photons, 1e3 * rlo, 1e3 * rhi, 1e3 * rmed);
  else
    vr_run_say(r, "progressive: %d iterations of %ld photons; pixel radii now %.3g to %.3g mm "
                  "(median %.3g mm)", job->spp, job->photons, 1e3 * rlo, 1e3 * rhi, 1e3 * rmed);
  if (rp && any) rp->seconds = t_photons;
  return VR_OK;
}

const vr_integrator_ops vr_integrator_progressive = {
    .name = "progressive", .what = "progressive photon mapping", .settings = settings,
    .render = render, .chains = true};
