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

#include "render_run.h"

#define SENSOR_GATHER_RADIUS_M 1.0
#include "vr/colour.h"

vr_status vr_sensor_points(const vr_scene *s, pass_ctx *c, vr_render_result *res, vr_error *err) {
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
static void set_parts(double eh, accum *acc, size_t k, int groups, vr_sensor_reading *rd) {
  for (int q = 0; q < VR_SENSOR_PARTS; q++)
    rd->part_lx[q] = vr_atomic_get(&acc->sensor_parts[k * VR_SENSOR_PARTS + (size_t)q]) / groups;
  if (eh > 0) {
    rd->df_sc_pct = 100 * rd->part_lx[VR_PART_SKY] / eh;
    rd->df_erc_pct = 100 * rd->part_lx[VR_PART_ERC_SKY] / eh;
    rd->df_irc_pct = 100 * rd->part_lx[VR_PART_IRC_SKY] / eh;
    rd->df_pct = rd->df_sc_pct + rd->df_erc_pct + rd->df_irc_pct;
  } else {
    rd->df_pct = rd->df_sc_pct = rd->df_erc_pct = rd->df_irc_pct = NAN;
  }
}

/* The path estimator: `groups` independent batches per point, whose spread
 * gives the standard error. */
static vr_status path_sensors(run *r, rscene *rs, pass_ctx *c, vr_error *err) {
  vr_render_result *res = r->res;
  int groups = 16;
  accum acc;
  vr_status st =
      vr_accum_create(&acc, 1, 1, rs->nbins, rs->film_lo, rs->film_step, c->npoints, groups, 0, err);
  if (!st && rs->bins_mode) st = vr_accum_set_bins(&acc, rs->lmin, rs->lmax, rs->nwl, err);
  if (st) {
    vr_accum_destroy(&acc);
    return st;
  }
  res->sky_patch_lx = calloc(c->npoints * VR_SENSOR_PATCHES + 1, sizeof *res->sky_patch_lx);
  if (!res->sky_patch_lx) {
    vr_accum_destroy(&acc);
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  c->acc = &acc;
  vr_integrator keep = c->integrator;
  c->integrator = VR_INT_PATH;
  st = vr_run_flow(r, rs, &vr_sensor_ops, c, (long)(c->npoints * (size_t)groups), "sensors", err);
  c->integrator = keep;
  c->acc = NULL;
  if (!st) st = vr_ranks_sum_accum(r, &acc, RANKS_SENSORS, err);
  for (size_t k = 0; !st && k < c->npoints; k++) {
    double sum = 0, sum2 = 0;
    for (int g = 0; g < groups; g++) {
      double e = vr_atomic_get(&acc.sensor_lx[k * (size_t)groups + (size_t)g]);
      sum += e;
      sum2 += e * e;
    }
    double mean = sum / groups, var = fmax(0, (sum2 - groups * mean * mean) / (groups - 1));
    res->readings[k].illuminance_lx = mean;
    res->readings[k].stderr_lx = sqrt(var / groups);
    set_parts(res->sky_horizontal_lx, &acc, k, groups, &res->readings[k]);
    for (int q = 0; q < VR_SENSOR_PATCHES; q++)
      res->sky_patch_lx[k * VR_SENSOR_PATCHES + (size_t)q] =
          vr_atomic_get(&acc.sensor_patches[k * VR_SENSOR_PATCHES + (size_t)q]) / groups;
    for (size_t b = 0; b < rs->nbins; b++)
      res->sensor_spectral[k * rs->nbins + b] =
          vr_atomic_get(&acc.sensor_bins[k * rs->nbins + b]) / groups;
  }
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
static vr_status photon_sensors(run *r, rscene *rs, pass_ctx *c, long photons, double *ended,
                                double *went_on, vr_error *err) {
  vr_render_result *res = r->res;
  vr_status st = vr_run_photon_pass(r, rs, c, photons, true, true, true, err);
  if (st) return st;
  const int groups = 16;
  accum acc;
  st = vr_accum_create(&acc, 1, 1, rs->nbins, rs->film_lo, rs->film_step, c->npoints, 2 * groups,
                       0, err);
  if (!st && rs->bins_mode) st = vr_accum_set_bins(&acc, rs->lmin, rs->lmax, rs->nwl, err);
  if (st) {
    vr_accum_destroy(&acc);
    vr_run_free_maps(c);
    return st;
  }
  c->acc = &acc;
  c->sensor_photons = true;
  c->sensor_groups = groups;
  vr_integrator keep = c->integrator;
  c->integrator = VR_INT_PATH;
  atomic_store(&c->fg_photon, 0);
  atomic_store(&c->fg_path, 0);
  st = vr_run_flow(r, rs, &vr_sensor_ops, c, (long)(c->npoints * (size_t)groups), "sensors", err);
  c->integrator = keep;
  c->sensor_photons = false;
  *ended = (double)atomic_load(&c->fg_photon);
  *went_on = (double)atomic_load(&c->fg_path);
  c->acc = NULL;
  if (!st) st = vr_ranks_sum_accum(r, &acc, RANKS_SENSORS, err);
  for (size_t k = 0; !st && k < c->npoints; k++) {
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
  vr_run_free_maps(c);
  return st;
}

vr_status vr_sensor_pass(run *r, rscene *rs, pass_ctx *c, vr_error *err) {
  vr_render_result *res = r->res;
  res->sky_horizontal_lx = vr_light_sky_horizontal_lx(rs);
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
      return vr_error_at(err, VR_E_ARG, rs->s->path, set->loc.line, set->loc.col,
                         "sensors=photon needs photons > 0");
    c->fixed_radius = !isnan(set->radius_m);
    /* The k nearest are looked for within a metre at most: a surface with
     * fewer photons than that (under k / (pi 1 m^2), 32 per m^2 for
     * k = 100) goes on as paths.  A disc sized by the scene alone (a tenth
     * of its radius: 4 m with a 60 m outdoor ground) spans a room's sun
     * patch and its shade, and floor points read 5-10 % high. */
    c->radius = c->fixed_radius ? set->radius_m : fmin(0.1 * rs->scene_radius, SENSOR_GATHER_RADIUS_M);
    if (!isnan(set->radius_m))
      p = vr_run_record(r, "sensors", true,
                        "%zu illuminance points, %d paths each ending in the maps of %ld photons "
                        "(fixed radius %.4g m)",
                        c->npoints, c->sensor_samples, photons, set->radius_m);
    else
      p = vr_run_record(r, "sensors", true,
                        "%zu illuminance points, %d paths each ending in the maps of %ld photons "
                        "(%d nearest per map)",
                        c->npoints, c->sensor_samples, photons, set->sensor_knn);
    double ended = 0, went_on = 0;
    int keep_knn = c->knn;
    c->knn = set->sensor_knn;
    st = photon_sensors(r, rs, c, photons, &ended, &went_on, err);
    c->knn = keep_knn;
    res->sensor_map_share = ended / fmax(1.0, ended + went_on);
    if (!st)
      vr_run_record(r, "sensor gathers", true,
                    "%.1f %% of the diffuse vertices of sensor paths read the photon maps, %.1f %% "
                    "went on as paths (fewer than the %s photons of this surface within reach)",
                    100.0 * ended / fmax(1.0, ended + went_on),
                    100.0 * went_on / fmax(1.0, ended + went_on),
                    c->fixed_radius ? "16" : "k nearest");
  } else {
    p = vr_run_record(r, "sensors", true, "%zu illuminance points, %d paths each", c->npoints,
                      c->sensor_samples);
    st = path_sensors(r, rs, c, err);
  }
  if (p) p->seconds = vr_run_now() - t0;
  return st;
}
