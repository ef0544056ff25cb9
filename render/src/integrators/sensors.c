/* Illuminance sensors: their points, and the pass that reads them.
 *
 * Two estimators, chosen by the scene's `render sensors=`:
 *   path    paths from the sensor point (next-event estimation plus
 *           cosine-weighted continuation), the reference; valid anywhere;
 *   photon  the same paths ended at their first diffuse hit by the
 *           photon maps' radiance there (final gathering; see
 *           photon_sensors below): valid anywhere, with the maps' bias
 *           estimated and added to the stated error.
 * Both give spectral irradiance in the film's bins (W/(m² nm)) and the
 * illuminance E_v = K_m ∫ V(λ) E(λ) dλ (K_m = 683.002 lm/W, V = ȳ of
 * CIE 1931). */
#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "integrators/photon_maps.h"
#include "integrators/sensors.h"
#include "vr/comm.h"
#include "vr/vec3.h"

#define SENSOR_GATHER_RADIUS_M 1.0

/* The sensor pass's state: the points, and for photon sensors the maps. */
typedef struct vr_sensor_state {
  size_t npoints;
  double (*points)[6];         /* position, normal */
  int samples, groups;
  /* Adaptive rounds (adaptive_rounds): each batch's samples in this pass
   * and the first one's number (in batches: sample g + (first + s) groups);
   * sums: a sample weighs 1, not 1/per.  0, 0, false: one pass of
   * ceil(samples / groups). */
  int per, first;
  bool sums;
  vr_photon_maps maps;
  _Atomic uint64_t fg_photon, fg_path; /* diffuse vertices ended by the maps / continued */
} vr_sensor_state;

/* Sensor unit: one point, one batch of its samples: next-event estimation
 * at the point, then one cosine-weighted direction on (weight cos/pdf = pi). */
static void generate(void *ctx, vr_flow_worker *w, long unit) {
  vr_pass *c = ctx;
  const vr_rscene *rs = c->rs;
  const vr_sensor_state *ss = c->state;
  int groups = ss->groups;
  size_t point = (size_t)unit / (size_t)groups;
  int g = (int)(unit % groups);
  const double *x = ss->points[point], *n = ss->points[point] + 3;
  int per = ss->per > 0 ? ss->per : (ss->samples + groups - 1) / groups;
  for (int s = 0; s < per; s++) {
    vr_payload p = {0};
    p.stream = VR_STREAM_SENSOR + point;
    p.sample = (uint32_t)(g + (ss->first + s) * groups);
    p.index = (uint32_t)point;
    p.target = VR_TARGET_SENSOR;
    p.nwl = (uint8_t)rs->nwl;
    p.medium = -1;
    vr_rng_key key = {rs->seed, p.stream, p.sample, 0};
    vr_wavelengths(rs, &key, (uint32_t)(per * groups), p.wl);
    /* Each batch's illuminance is a mean over its own samples (adaptive:
     * their sum, divided at the end). */
    p.weight = ss->sums ? 1.0 : 1.0 / per;
    for (int k = 0; k < p.nwl; k++) p.beta[k] = 1.0;
    vr_path_next_event(c, w, &p, x, n, n, vr_receiver_f, n, 0, false);
    double u1 = vr_rng(&key, VR_DIM_DIR_U), u2 = vr_rng(&key, VR_DIM_DIR_V);
    vr_ray r = {0};
    vr_sample_cosine(n, u1, u2, r.dir);
    vr_spawn_origin(x, n, r.dir, r.org);
    r.tmax = INFINITY;
    r.kind = VR_RAY_CLOSEST;
    r.purpose = VR_PURPOSE_SENSOR;
    vr_payload q = p;
    for (int k = 0; k < q.nwl; k++) q.beta[k] = M_PI;
    q.depth = 1;
    memcpy(r.payload, &q, sizeof q);
    vr_flow_push(w, &r);
  }
}

static const vr_flow_ops sensor_ops = {vr_path_closest, vr_path_shadow_hit, vr_path_shadow_done,
                                       generate, VR_PAYLOAD_WIRE};

/* A photon sensor's diffuse vertex: direct light came from the next-event
 * estimate; what arrives after a diffuse or specular bounce comes from the
 * global and caustic maps (this object's photons), and the path ends
 * there, if the global map is dense here: k photons within the radius
 * (final gathering, Jensen 2001 ch. 9).  Where it is not (a surface few
 * photons reached), a disc of the maximum radius would spread them over
 * area the surface may not have, so the path goes on as in the path
 * estimator instead.  Beside the estimate, the same with a quarter of the
 * photons (or half the radius): a density estimate's bias grows as r^2
 * (the curvature term), so the difference is 3/4 of the bias of the full
 * estimate; it goes to the point's probe slots. */
static bool photon_at_diffuse(vr_pass *c, vr_flow_worker *w, vr_payload *p, const vr_hit *hit,
                              const vr_surface *se, const double wo[3]) {
  (void)w;
  vr_sensor_state *ss = c->state;
  const vr_photon_maps *m = &ss->maps;
  double L[VR_MAX_WL];
  int got = 0;
  vr_photon_maps_radiance(m, c->rs, hit, wo, se, p, VR_MAP_GLOBAL | VR_MAP_CAUSTIC, m->knn,
                          m->radius, L, &got);
  bool dense = m->fixed_radius ? got >= 16 : got >= m->knn;
  atomic_fetch_add_explicit(dense ? &ss->fg_photon : &ss->fg_path, 1, memory_order_relaxed);
  if (dense) {
    vr_path_deliver(c, p, L);
    double Ls[VR_MAX_WL], D[VR_MAX_WL];
    int ks = m->knn / 4 > 1 ? m->knn / 4 : 1;
    vr_photon_maps_radiance(m, c->rs, hit, wo, se, p, VR_MAP_GLOBAL | VR_MAP_CAUSTIC, ks,
                            0.5 * m->radius, Ls, NULL);
    for (int k = 0; k < p->nwl; k++) D[k] = (L[k] - Ls[k]) * p->weight;
    int G = ss->groups;
    vr_accum_sensor_lx(c->acc, p->index, (uint32_t)G + p->sample % (uint32_t)G, p->nwl, p->wl, D,
                       vr_wl_weight(c->rs, p->nwl));
    return true;
  }
  /* Sparse: the caustic map still adds what no path finds (the sun or a
   * lamp through a specular bounce); the path takes the rest. */
  vr_photon_maps_radiance(m, c->rs, hit, wo, se, p, VR_MAP_CAUSTIC, m->knn, m->radius, L, NULL);
  vr_path_deliver(c, p, L);
  p->flags |= VR_PF_CAUSTIC_TAKEN;
  return false;
}

static vr_status sensor_points(const vr_scene *s, vr_sensor_state *c, vr_render_result *res, vr_error *err) {
  size_t n = 0;
  for (size_t i = 0; i < s->nsensors; i++)
    n += s->sensors[i].grid ? (size_t)s->sensors[i].nu * (size_t)s->sensors[i].nv : 1;
  c->npoints = n;
  c->points = calloc(n + 1, sizeof *c->points);
  res->readings = calloc(n + 1, sizeof *res->readings);
  if (!c->points || !res->readings) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  res->nreadings = n;
  /* The readings keep their names past the scene. */
  size_t bytes = 1;
  for (size_t i = 0; i < s->nsensors; i++) bytes += strlen(s->sensors[i].name) + 1;
  char *names = res->sensor_names = malloc(bytes);
  if (!names) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  size_t k = 0;
  for (size_t i = 0; i < s->nsensors; i++) {
    const vr_scene_sensor *se = &s->sensors[i];
    int nu = se->grid ? se->nu : 1, nv = se->grid ? se->nv : 1;
    size_t len = strlen(se->name) + 1;
    memcpy(names, se->name, len);
    const char *name = names;
    names += len;
    for (int j = 0; j < nv; j++)
      for (int u = 0; u < nu; u++, k++) {
        /* Grid points at the centres of the nu x nv cells of the parallelogram. */
        double fu = se->grid ? (u + 0.5) / nu : 0, fv = se->grid ? (j + 0.5) / nv : 0;
        if (se->pts) /* a points file: its u-th line, x y z dx dy dz */
          memcpy(c->points[k], se->pts + 6 * (size_t)u, 6 * sizeof *se->pts);
        else
          for (int a = 0; a < 3; a++) {
            c->points[k][a] = se->position[a] + fu * se->u[a] + fv * se->v[a];
            c->points[k][3 + a] = se->normal[a];
          }
        vr_sensor_reading *rd = &res->readings[k];
        rd->sensor = name;
        rd->i = u;
        rd->j = j;
        memcpy(rd->position, c->points[k], sizeof rd->position);
      }
  }
  return VR_OK;
}

/* A reading's parts (the sums over all samples, over the groups) and its
 * daylight factor, eh the unobstructed sky's horizontal illuminance (lx). */
static void set_parts(double eh, vr_accum *acc, size_t k, double by, vr_sensor_reading *rd) {
  for (int q = 0; q < VR_SENSOR_PARTS; q++)
    rd->part_lx[q] = vr_atomic_get(&acc->sensor_parts[k * VR_SENSOR_PARTS + (size_t)q]) / by;
  if (eh > 0) {
    rd->df_sc_pct = 100 * rd->part_lx[VR_PART_SKY] / eh;
    rd->df_erc_pct = 100 * rd->part_lx[VR_PART_ERC_SKY] / eh;
    rd->df_irc_pct = 100 * rd->part_lx[VR_PART_IRC_SKY] / eh;
    rd->df_pct = rd->df_sc_pct + rd->df_erc_pct + rd->df_irc_pct;
  } else {
    rd->df_pct = rd->df_sc_pct = rd->df_erc_pct = rd->df_irc_pct = NAN;
  }
}

/* Adaptive path sensors (--target-error): rounds of the 16 batches, each
 * doubling a point's samples, until the point's relative standard error
 * (the batches' spread over their mean) is at most the target, or it has
 * SENSOR_ADAPTIVE_CAP times sensor_samples.  A sample weighs 1, so the
 * sums are divided by each point's own samples at the end; a round's
 * sample numbers follow the last round's, and its wavelength strata are
 * its own (whole sets of groups x per consecutive numbers).  Decisions
 * are taken on the batches summed over the ranks, so every rank takes the
 * same ones.  Returns each point's samples per batch in *per_out. */
enum { SENSOR_ADAPTIVE_CAP = 64 };

static vr_status adaptive_rounds(vr_run *r, vr_pass *c, vr_sensor_state *ss, uint32_t **per_out,
                                 vr_error *err) {
  const int G = ss->groups;
  const size_t n = ss->npoints;
  double target = r->opt->target_error;
  uint32_t *done = calloc(n + 1, sizeof *done);
  long *units = malloc((n * (size_t)G + 1) * sizeof *units);
  uint8_t *active = malloc(n + 1);
  double *e = malloc((n * (size_t)G + 1) * sizeof *e);
  vr_status st = VR_OK;
  if (!done || !units || !active || !e) {
    st = vr_error_set(err, VR_E_NOMEM, "adaptive sensors: out of memory");
    goto out;
  }
  memset(active, 1, n);
  int per0 = (ss->samples + G - 1) / G;
  long cap = (long)per0 * SENSOR_ADAPTIVE_CAP;
  ss->sums = true;
  ss->first = 0;
  ss->per = per0;
  size_t nactive = n, reached = 0;
  int rounds = 0;
  while (nactive) {
    size_t nu = 0;
    for (size_t k = 0; k < n; k++)
      for (int g = 0; active[k] && g < G; g++) units[nu++] = (long)(k * (size_t)G + (size_t)g);
    if ((st = vr_run_flow_units(r, &sensor_ops, c, units, (long)nu, "sensors", err))) goto out;
    for (size_t k = 0; k < n; k++) done[k] += active[k] ? (uint32_t)ss->per : 0u;
    rounds++;
    for (size_t i = 0; i < n * (size_t)G; i++) e[i] = vr_atomic_get(&c->acc->sensor_lx[i]);
    if (r->nranks > 1 && (st = vr_comm_sum_doubles(r->comm, e, n * (size_t)G, err))) goto out;
    nactive = 0;
    for (size_t k = 0; k < n; k++) {
      if (!active[k]) continue;
      double sum = 0, sum2 = 0;
      for (int g = 0; g < G; g++) {
        double v = e[k * (size_t)G + (size_t)g] / done[k];
        sum += v;
        sum2 += v * v;
      }
      double mean = sum / G, var = fmax(0, (sum2 - G * mean * mean) / (G - 1));
      double se = sqrt(var / G);
      bool ok = se <= target * fabs(mean) || (se == 0 && mean == 0);
      reached += ok;
      if (ok || (long)done[k] * 2 > cap) active[k] = 0;
      nactive += active[k];
    }
    vr_run_say(r, "sensors round %d: %u paths a point so far, %zu of %zu points at %.3g", rounds,
               (unsigned)(ss->first + ss->per) * (unsigned)G, reached, n, target);
    ss->first += ss->per;
    ss->per = ss->first; /* the next round doubles an active point's samples */
  }
  *per_out = done;
  done = NULL;
out:
  ss->sums = false;
  ss->first = 0;
  ss->per = 0;
  free(done);
  free(units);
  free(active);
  free(e);
  return st;
}

/* The path estimator: `groups` independent batches per point, whose spread
 * gives the standard error; with a target error, in adaptive rounds. */
static vr_status path_sensors(vr_run *r, vr_rscene *rs, vr_sensor_state *ss, vr_error *err) {
  vr_pass c = {.rs = rs, .max_depth = rs->s->settings.max_depth, .state = ss};
  vr_render_result *res = r->res;
  int groups = 16;
  vr_accum acc;
  vr_status st =
      vr_accum_create(&acc, 1, 1, rs->nbins, rs->film_lo, rs->film_step, ss->npoints, groups, 0, err);
  if (!st && rs->bins_mode) st = vr_accum_set_bins(&acc, rs->lmin, rs->lmax, rs->nwl, err);
  if (st) {
    vr_accum_destroy(&acc);
    return st;
  }
  res->sky_patch_lx = calloc(ss->npoints * VR_SENSOR_PATCHES + 1, sizeof *res->sky_patch_lx);
  if (!res->sky_patch_lx) {
    vr_accum_destroy(&acc);
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  c.acc = &acc;
  ss->groups = groups;
  uint32_t *per = NULL; /* adaptive: each point's samples per batch */
  if (r->opt->target_error > 0)
    st = adaptive_rounds(r, &c, ss, &per, err);
  else
    st = vr_run_flow(r, &sensor_ops, &c, (long)(ss->npoints * (size_t)groups), "sensors", err);
  if (!st) st = vr_ranks_sum_accum(r, &acc, RANKS_SENSORS, err);
  for (size_t k = 0; !st && k < ss->npoints; k++) {
    /* Adaptive sums are over the point's own samples; else each batch is a mean. */
    double pk = per ? (double)per[k] : 1.0, by = groups * pk;
    double sum = 0, sum2 = 0;
    for (int g = 0; g < groups; g++) {
      double e = vr_atomic_get(&acc.sensor_lx[k * (size_t)groups + (size_t)g]) / pk;
      sum += e;
      sum2 += e * e;
    }
    double mean = sum / groups, var = fmax(0, (sum2 - groups * mean * mean) / (groups - 1));
    res->readings[k].illuminance_lx = mean;
    res->readings[k].stderr_lx = sqrt(var / groups);
    set_parts(res->sky_horizontal_lx, &acc, k, by, &res->readings[k]);
    res->readings[k].paths = (uint64_t)(groups * pk * (per ? 1 : (ss->samples + groups - 1) / groups));
    for (int q = 0; q < VR_SENSOR_PATCHES; q++)
      res->sky_patch_lx[k * VR_SENSOR_PATCHES + (size_t)q] =
          vr_atomic_get(&acc.sensor_patches[k * VR_SENSOR_PATCHES + (size_t)q]) / by;
    for (size_t b = 0; b < rs->nbins; b++)
      res->sensor_spectral[k * rs->nbins + b] =
          vr_atomic_get(&acc.sensor_bins[k * rs->nbins + b]) / by;
  }
  free(per);
  vr_accum_destroy(&acc);
  return st;
}

/* The photon estimator: the paths of the path estimator (next-event
 * estimation at the point, one cosine-weighted direction on), each ended at
 * its first diffuse hit by the photon maps' radiance there, from that
 * object's photons only (final gathering, Jensen 2001 ch. 9).  Direct light
 * at the point is as exact as in the path estimator; the photon maps only
 * stand in for the light reflected by the surfaces the point sees, where
 * their density errors (the disc across an edge, or across a wall) are
 * averaged over the hemisphere instead of read at the point itself.  So a
 * point need not lie on a surface (a work plane in mid-air reads the same as
 * with paths), and photons from beyond a wall never reach it: a floor's
 * estimate takes the floor's photons, not the ground's.
 *
 * The stated standard error is the spread of the `groups` batches (the
 * gathering's noise) and the estimated bias of the density estimates in
 * quadrature: each gather hit is read twice, with k and k/4 photons (or r
 * and r/2); the bias of a density estimate grows as r^2 and r^2 is about
 * proportional to k, so bias(k) ~ 4/3 (E(k) - E(k/4)). */
static vr_status photon_sensors(vr_run *r, vr_rscene *rs, vr_sensor_state *ss, long photons,
                                double *ended, double *went_on, vr_error *err) {
  vr_render_result *res = r->res;
  vr_pass c = {.rs = rs, .max_depth = rs->s->settings.max_depth, .state = ss,
               .at_diffuse = photon_at_diffuse};
  vr_status st = vr_photon_maps_trace(r, &c, &ss->maps, photons, true, true, true, err);
  if (st) {
    vr_photon_maps_free(r, &ss->maps);
    return st;
  }
  const int groups = 16;
  vr_accum acc;
  st = vr_accum_create(&acc, 1, 1, rs->nbins, rs->film_lo, rs->film_step, ss->npoints, 2 * groups,
                       0, err);
  if (!st && rs->bins_mode) st = vr_accum_set_bins(&acc, rs->lmin, rs->lmax, rs->nwl, err);
  if (st) {
    vr_accum_destroy(&acc);
    vr_photon_maps_free(r, &ss->maps);
    return st;
  }
  c.acc = &acc;
  /* Photon sensors keep their second half of slots for the bias probe. */
  c.sensor_slots = (uint32_t)groups;
  ss->groups = groups;
  atomic_store(&ss->fg_photon, 0);
  atomic_store(&ss->fg_path, 0);
  st = vr_run_flow(r, &sensor_ops, &c, (long)(ss->npoints * (size_t)groups), "sensors", err);
  *ended = (double)atomic_load(&ss->fg_photon);
  *went_on = (double)atomic_load(&ss->fg_path);
  if (!st) st = vr_ranks_sum_accum(r, &acc, RANKS_SENSORS, err);
  for (size_t k = 0; !st && k < ss->npoints; k++) {
    double sum = 0, sum2 = 0, diff = 0;
    for (int g = 0; g < groups; g++) {
      double e = vr_atomic_get(&acc.sensor_lx[k * (size_t)(2 * groups) + (size_t)g]);
      sum += e;
      sum2 += e * e;
      diff += vr_atomic_get(&acc.sensor_lx[k * (size_t)(2 * groups) + (size_t)(groups + g)]);
    }
    double mean = sum / groups, var = fmax(0, (sum2 - groups * mean * mean) / (groups - 1));
    double bias = 4.0 / 3.0 * diff / groups;
    res->readings[k].illuminance_lx = mean;
    res->readings[k].stderr_lx = sqrt(var / groups + bias * bias);
    /* Map radiance has no single source: no parts, no daylight factor. */
    for (int q = 0; q < VR_SENSOR_PARTS; q++) res->readings[k].part_lx[q] = NAN;
    res->readings[k].df_pct = res->readings[k].df_sc_pct = res->readings[k].df_erc_pct =
        res->readings[k].df_irc_pct = NAN;
    for (size_t b = 0; b < rs->nbins; b++)
      res->sensor_spectral[k * rs->nbins + b] =
          vr_atomic_get(&acc.sensor_bins[k * rs->nbins + b]) / groups;
  }
  vr_accum_destroy(&acc);
  vr_photon_maps_free(r, &ss->maps);
  return st;
}

static vr_status sensor_pass(vr_run *r, vr_rscene *rs, vr_sensor_state *c, vr_error *err) {
  vr_render_result *res = r->res;
  res->sky_horizontal_lx = vr_lights_sky_horizontal_lx(&rs->L);
  const vr_scene_settings *set = &rs->s->settings;
  if (!c->npoints) {
    vr_run_record(r, "sensors", false, "no sensors in the scene");
    return VR_OK;
  }
  res->sensor_spectral = calloc(c->npoints * rs->nbins + 1, sizeof *res->sensor_spectral);
  if (!res->sensor_spectral) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  double t0 = vr_run_now();
  vr_pass_record *p;
  vr_status st;
  if (set->sensors == VR_SENSORS_PHOTON) {
    long photons = r->opt->photons > 0 ? r->opt->photons : set->photons;
    if (photons < 1)
      return vr_error_at(err, VR_E_ARG, set->source ? set->source : rs->s->path, set->loc.line, set->loc.col,
                         "sensors=photon needs photons > 0");
    c->maps.fixed_radius = !isnan(set->radius_m);
    c->maps.edge_share = true;
    /* The k nearest are looked for within a metre at most: a surface with
     * fewer photons than that (under k / (pi 1 m^2), 32 per m^2 for
     * k = 100) goes on as paths.  A disc sized by the scene alone (a tenth
     * of its radius: 4 m with a 60 m outdoor ground) spans a room's sun
     * patch and its shade, and floor points read 5-10 % high. */
    c->maps.radius = c->maps.fixed_radius ? set->radius_m
                                          : fmin(0.1 * rs->scene_radius, SENSOR_GATHER_RADIUS_M);
    if (!isnan(set->radius_m))
      p = vr_run_record(r, "sensors", true,
                        "%zu illuminance points, %d paths each ending in the maps of %ld photons "
                        "(fixed radius %.4g m)",
                        c->npoints, c->samples, photons, set->radius_m);
    else
      p = vr_run_record(r, "sensors", true,
                        "%zu illuminance points, %d paths each ending in the maps of %ld photons "
                        "(%d nearest per map)",
                        c->npoints, c->samples, photons, set->sensor_knn);
    double ended = 0, went_on = 0;
    c->maps.knn = set->sensor_knn;
    st = photon_sensors(r, rs, c, photons, &ended, &went_on, err);
    res->sensor_map_share = ended / fmax(1.0, ended + went_on);
    if (!st)
      vr_run_record(r, "sensor gathers", true,
                    "%.1f %% of the diffuse vertices of sensor paths read the photon maps, %.1f %% "
                    "went on as paths (fewer than the %s photons of this surface within reach)",
                    100.0 * ended / fmax(1.0, ended + went_on),
                    100.0 * went_on / fmax(1.0, ended + went_on),
                    c->maps.fixed_radius ? "16" : "k nearest");
  } else {
    p = vr_run_record(r, "sensors", true, "%zu illuminance points, %d paths each", c->npoints,
                      c->samples);
    st = path_sensors(r, rs, c, err);
  }
  if (p) p->seconds = vr_run_now() - t0;
  return st;
}

vr_status vr_sensors_run(vr_run *r, vr_error *err) {
  vr_sensor_state ss = {.samples = r->rs->s->settings.sensor_samples};
  vr_status st = sensor_points(r->rs->s, &ss, r->res, err);
  if (!st) st = sensor_pass(r, r->rs, &ss, err);
  free(ss.points);
  return st;
}
