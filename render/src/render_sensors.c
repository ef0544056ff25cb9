/* Illuminance sensors: their points, and the pass that reads them.
 *
 * Two estimators, chosen by the scene's `render sensors=`:
 *   path    paths from the sensor point (next-event estimation plus
 *           cosine-weighted continuation), the reference; valid anywhere;
 *   photon  density estimation in the direct, caustic and global photon
 *           maps at the sensor point: the irradiance of photons arriving on
 *           the sensor's side, within the k-nearest (or fixed-radius) disc.
 *           Valid on diffuse surfaces, where photons are stored; biased by
 *           the disc's extent where irradiance varies within it (edges,
 *           contact shadows), consistent as the photon count grows.
 * Both give spectral irradiance in the film's bins (W/(m² nm)) and the
 * illuminance E_v = K_m ∫ V(λ) E(λ) dλ (K_m = 683.002 lm/W, V = ȳ of
 * CIE 1931). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "render_run.h"
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
    for (size_t b = 0; b < rs->nbins; b++)
      res->sensor_spectral[k * rs->nbins + b] =
          vr_atomic_get(&acc.sensor_bins[k * rs->nbins + b]) / groups;
  }
  vr_accum_destroy(&acc);
  return st;
}

/* K_m ∫ V over [lo, hi] nm by the trapezoid rule on a 1 nm grid (the
 * weight of one W/(m² nm) held constant over the interval). */
static double luminous_weight(double lo, double hi) {
  double sum = 0;
  int n = (int)ceil(hi - lo);
  if (n < 1) n = 1;
  double h = (hi - lo) / n;
  for (int i = 0; i <= n; i++) {
    double xyz[3];
    vr_cmf_eval(VR_CIE1931_2DEG, lo + i * h, xyz);
    sum += xyz[1] * h * ((i == 0 || i == n) ? 0.5 : 1.0);
  }
  return VR_KM * sum;
}

/* The photon estimator.  Each map answers with its own neighbourhood (k
 * nearest of its photons, or the fixed radius); the standard error is the
 * Poisson estimate E / sqrt(m) per map for m photons found, combined in
 * quadrature: it assumes photons of similar power and leaves out the bias. */
static vr_status photon_sensors(run *r, rscene *rs, pass_ctx *c, long photons, double radius,
                                bool fixed, vr_error *err) {
  vr_render_result *res = r->res;
  vr_status st = vr_run_photon_pass(r, rs, c, photons, true, true, true, err);
  if (st) return st;
  vr_photon_set *maps[3] = {c->direct, c->caustic, c->global};
  const vr_photon_map *bins_of = vr_photon_set_map(c->global, 0); /* every map has these bins */
  int nb = vr_photon_map_nbins(bins_of);
  double *bins = calloc((size_t)nb, sizeof *bins), *E = calloc((size_t)nb, sizeof *E);
  double *V = calloc((size_t)nb, sizeof *V), *lo = calloc((size_t)nb, sizeof *lo),
         *hi = calloc((size_t)nb, sizeof *hi);
  if (!bins || !E || !V || !lo || !hi) st = vr_error_set(err, VR_E_NOMEM, "out of memory");
  for (int b = 0; !st && b < nb; b++) {
    vr_photon_map_bin_range(bins_of, b, &lo[b], &hi[b]);
    V[b] = luminous_weight(lo[b], hi[b]);
  }
  for (size_t k = 0; !st && k < c->npoints; k++) {
    const double *x = c->points[k], *n = c->points[k] + 3;
    memset(E, 0, (size_t)nb * sizeof *E);
    double lx = 0, var = 0;
    for (int m = 0; m < 3; m++) {
      if (!vr_photon_set_count(maps[m])) continue;
      int got = vr_photon_set_irradiance(maps[m], x, n, fixed ? 0 : c->knn, radius, 0.0, bins, NULL);
      if (got <= 0) continue; /* no photon near, or all at x: nothing to add */
      double lm = 0;
      for (int b = 0; b < nb; b++) {
        double e = bins[b] * c->photon_scale / (hi[b] - lo[b]); /* W/(m² nm) */
        E[b] += e;
        lm += V[b] * e;
      }
      lx += lm;
      var += lm * lm / got;
    }
    res->readings[k].illuminance_lx = lx;
    res->readings[k].stderr_lx = sqrt(var);
    /* Film bins: the mean of the piecewise-constant map spectrum over each. */
    for (size_t fb = 0; fb < rs->nbins; fb++) {
      double a = rs->film_lo + fb * rs->film_step, sum = 0;
      int cnt = 0;
      for (double nm = a + 0.5; nm < a + rs->film_step; nm += 1.0, cnt++) {
        int b = vr_photon_map_bin(bins_of, nm);
        if (b >= 0) sum += E[b];
      }
      res->sensor_spectral[k * rs->nbins + fb] = cnt ? sum / cnt : 0.0;
    }
  }
  free(bins);
  free(E);
  free(V);
  free(lo);
  free(hi);
  vr_run_free_maps(c);
  return st;
}

vr_status vr_sensor_pass(run *r, rscene *rs, pass_ctx *c, vr_error *err) {
  vr_render_result *res = r->res;
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
    bool fixed = !isnan(set->radius_m);
    double radius = fixed ? set->radius_m : 0.1 * rs->scene_radius;
    if (fixed)
      p = vr_run_record(r, "sensors", true,
                        "%zu illuminance points from %ld photons, fixed radius %.4g m", c->npoints,
                        photons, radius);
    else
      p = vr_run_record(r, "sensors", true,
                        "%zu illuminance points from %ld photons, %d nearest per map", c->npoints,
                        photons, c->knn);
    st = photon_sensors(r, rs, c, photons, radius, fixed, err);
  } else {
    p = vr_run_record(r, "sensors", true, "%zu illuminance points, %d paths each", c->npoints,
                      c->sensor_samples);
    st = path_sensors(r, rs, c, err);
  }
  if (p) p->seconds = vr_run_now() - t0;
  return st;
}
