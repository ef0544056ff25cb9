/* vr_render_scene: resolve, analyse, run the passes the scene calls for,
 * collect the film, the sensors and the statistics.
 *
 * Scene analysis (DESIGN §6.2) decides each pass from what the scene holds
 * and says why, so a user can see that a room without mirrors or glass
 * spheres pays nothing for caustics, and a room without photochromic glass
 * runs no UV pass. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "render_internal.h"
#include "vr/chromogenic.h"

void vr_render_options_default(vr_render_options *o) {
  memset(o, 0, sizeof *o);
  o->subdomains = 1;
  o->threads = 1;
}

static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

typedef struct run {
  const vr_render_options *opt;
  vr_render_result *res;
  const char *pass;
} run;

static void say(const run *r, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void say(const run *r, const char *fmt, ...) {
  if (!r->opt->log) return;
  char line[512];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(line, sizeof line, fmt, ap);
  va_end(ap);
  r->opt->log(r->opt->user, line);
}

static vr_pass_record *record(run *r, const char *name, bool ran, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
static vr_pass_record *record(run *r, const char *name, bool ran, const char *fmt, ...) {
  vr_render_result *res = r->res;
  if (res->npasses >= VR_MAX_PASSES) return NULL;
  vr_pass_record *p = &res->passes[res->npasses++];
  snprintf(p->name, sizeof p->name, "%s", name);
  p->ran = ran;
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(p->reason, sizeof p->reason, fmt, ap);
  va_end(ap);
  say(r, "%-16s %-4s %s", name, ran ? "run" : "skip", p->reason);
  return p;
}

static void progress_cb(void *u, long done, long total) {
  run *r = u;
  if (r->opt->progress) r->opt->progress(r->opt->user, r->pass, done, total);
}

static void add_stats(vr_render_result *res, const vr_flow_stats *st) {
  res->rays_camera += st->by_purpose[PURPOSE_CAMERA] + st->by_purpose[PURPOSE_GATHER];
  res->rays_shadow += st->by_purpose[PURPOSE_SHADOW];
  res->rays_photon += st->by_purpose[PURPOSE_PHOTON];
  res->rays_other += st->by_purpose[PURPOSE_SENSOR] + st->by_purpose[PURPOSE_UV];
  res->crossings += st->crossings;
  res->rays_created += st->created;
  res->rays_finished += st->finished;
}

static vr_status flow(run *r, rscene *rs, const vr_flow_ops *ops, pass_ctx *c, long units,
                      const char *name, vr_error *err) {
  vr_flow_stats st = {0};
  r->pass = name;
  vr_status s = vr_flow_run(rs->d, ops, c, units, r->opt->threads, progress_cb, r, &st, err);
  add_stats(r->res, &st);
  return s;
}

/* What the scene's materials call for. */
typedef struct needs {
  bool diffuse, specular, photochromic, dispersive, chromogenic;
  const char *specular_example, *dispersive_example;
} needs;

static needs analyse(const rscene *rs) {
  needs n = {0};
  const vr_scene *s = rs->s;
  for (size_t i = 0; i < s->nobjects; i++) {
    const rmaterial *m = &rs->mat[s->objects[i].material];
    unsigned l = vr_bsdf_lobes(m->bsdf);
    const char *name = s->materials[s->objects[i].material].name;
    if (l & VR_LOBE_DIFFUSE) n.diffuse = true;
    if (l & (VR_LOBE_SPECULAR_R | VR_LOBE_SPECULAR_T | VR_LOBE_GLOSSY_R | VR_LOBE_GLOSSY_T)) {
      if (!n.specular) n.specular_example = name;
      n.specular = true;
    }
    if (m->photochromic) n.photochromic = true;
    if (vr_bsdf_is_chromogenic(m->bsdf)) n.chromogenic = true;
    if (vr_bsdf_dispersive(m->bsdf) && (l & (VR_LOBE_SPECULAR_T | VR_LOBE_GLOSSY_T))) {
      if (!n.dispersive) n.dispersive_example = name;
      n.dispersive = true;
    }
  }
  return n;
}

static vr_status uv_pass(run *r, rscene *rs, pass_ctx *c, vr_error *err) {
  size_t nt = 0;
  for (size_t i = 0; i < rs->s->nobjects; i++)
    if (rs->obj[i].state) nt += (size_t)rs->obj[i].nu * (size_t)rs->obj[i].nv;
  c->ntexels = nt;
  c->texel_object = calloc(nt + 1, sizeof *c->texel_object);
  c->texel_index = calloc(nt + 1, sizeof *c->texel_index);
  accum acc;
  vr_status st = vr_accum_create(&acc, 1, 1, 1, 0, 1, 0, 1, nt, err);
  if (st) return st;
  if (!c->texel_object || !c->texel_index) {
    vr_accum_destroy(&acc);
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  size_t k = 0;
  for (size_t i = 0; i < rs->s->nobjects; i++)
    for (int t = 0; rs->obj[i].state && t < rs->obj[i].nu * rs->obj[i].nv; t++) {
      c->texel_object[k] = (uint32_t)i;
      c->texel_index[k++] = (uint32_t)t;
    }
  c->acc = &acc;
  c->uv_sky_samples = 64;
  st = flow(r, rs, &vr_uv_ops, c, (long)nt, "uv", err);
  vr_render_result *res = r->res;
  res->photochromic_texels = nt;
  res->photochromic_state = calloc(nt + 1, sizeof *res->photochromic_state);
  if (!st && !res->photochromic_state) st = vr_error_set(err, VR_E_NOMEM, "out of memory");
  res->photochromic_state_min = INFINITY;
  res->photochromic_state_max = -INFINITY;
  for (size_t t = 0; !st && t < nt; t++) {
    robject *o = &rs->obj[c->texel_object[t]];
    const rmaterial *m = &rs->mat[o->material];
    double E = vr_atomic_get(&acc.texel_uv[t]), s;
    st = vr_chromo_steady_state(m->db, E, m->temperature_K, &s, err);
    if (st) break;
    o->state[c->texel_index[t]] = s;
    res->photochromic_state[t] = s;
    if (s < res->photochromic_state_min) res->photochromic_state_min = s;
    if (s > res->photochromic_state_max) res->photochromic_state_max = s;
  }
  vr_accum_destroy(&acc);
  c->acc = NULL;
  return st;
}

static vr_status photon_pass(run *r, rscene *rs, pass_ctx *c, long photons, bool caustic,
                             bool global, vr_error *err) {
  int nb = (int)ceil((rs->lmax - rs->lmin) / 10.0);
  if (nb < 1) nb = 1;
  if (global) {
    c->global = vr_photon_map_create(nb, rs->lmin, rs->lmax, err);
    c->direct = c->final_gather ? vr_photon_map_create(nb, rs->lmin, rs->lmax, err) : NULL;
    if (!c->global || (c->final_gather && !c->direct)) return err ? err->status : VR_E_NOMEM;
  }
  if (caustic) {
    c->caustic = vr_photon_map_create(nb, rs->lmin, rs->lmax, err);
    if (!c->caustic) return err ? err->status : VR_E_NOMEM;
  }
  c->photons_per_unit = 1024;
  long units = (photons + c->photons_per_unit - 1) / c->photons_per_unit;
  c->photon_scale = 1.0 / (double)(units * c->photons_per_unit);
  vr_status st = flow(r, rs, &vr_photon_ops, c, units, "photons", err);
  vr_photon_map *maps[3] = {c->global, c->direct, c->caustic};
  for (int i = 0; !st && i < 3; i++)
    if (maps[i]) st = vr_photon_map_build(maps[i], err);
  if (!st) {
    r->res->photons_global += c->global ? vr_photon_map_count(c->global) : 0;
    r->res->photons_direct += c->direct ? vr_photon_map_count(c->direct) : 0;
    r->res->photons_caustic += c->caustic ? vr_photon_map_count(c->caustic) : 0;
  }
  return st;
}

static void free_maps(pass_ctx *c) {
  vr_photon_map_destroy(c->global);
  vr_photon_map_destroy(c->direct);
  vr_photon_map_destroy(c->caustic);
  c->global = c->direct = c->caustic = NULL;
}

static vr_status sensor_points(const vr_scene *s, pass_ctx *c, vr_render_result *res,
                               vr_error *err) {
  size_t n = 0;
  for (size_t i = 0; i < s->nsensors; i++)
    n += s->sensors[i].grid ? (size_t)s->sensors[i].nu * (size_t)s->sensors[i].nv : 1;
  c->npoints = n;
  c->points = calloc(n + 1, sizeof *c->points);
  res->readings = calloc(n + 1, sizeof *res->readings);
  if (!c->points || !res->readings) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  res->nreadings = n;
  size_t k = 0;
  for (size_t i = 0; i < s->nsensors; i++) {
    const vr_scene_sensor *se = &s->sensors[i];
    int nu = se->grid ? se->nu : 1, nv = se->grid ? se->nv : 1;
    for (int j = 0; j < nv; j++)
      for (int u = 0; u < nu; u++, k++) {
        /* Grid points at the centres of the nu x nv cells of the parallelogram. */
        double fu = se->grid ? (u + 0.5) / nu : 0, fv = se->grid ? (j + 0.5) / nv : 0;
        for (int a = 0; a < 3; a++) {
          c->points[k][a] = se->position[a] + fu * se->u[a] + fv * se->v[a];
          c->points[k][3 + a] = se->normal[a];
        }
        vr_sensor_reading *rd = &res->readings[k];
        rd->sensor = se->name;
        rd->i = u;
        rd->j = j;
        memcpy(rd->position, c->points[k], sizeof rd->position);
      }
  }
  return VR_OK;
}

vr_status vr_render_scene(const vr_scene *s, vr_matdb *db, const vr_render_options *opt,
                          vr_render_result **out, vr_error *err) {
  *out = NULL;
  double t_start = now();
  vr_render_result *res = calloc(1, sizeof *res);
  if (!res) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  run r = {.opt = opt, .res = res};
  int S = opt->image_space ? 1 : (opt->subdomains > 0 ? opt->subdomains : 1);
  rscene *rs = NULL;
  pass_ctx c = {0};
  accum acc = {0};
  double t0 = now();
  vr_status st = vr_rscene_create(s, db, S, &rs, err);
  if (st) goto done;
  res->degenerate_triangles = rs->g->degenerate_dropped;
  if (rs->g->degenerate_dropped)
    say(&r, "warning: %zu degenerate triangles dropped from meshes", rs->g->degenerate_dropped);
  say(&r, "scene: %zu objects, %zu triangles, %zu spheres, %zu lights%s, %d sub-domain%s",
      s->nobjects, rs->g->ntris, rs->g->nspheres, rs->nlights, rs->has_sky ? " + sky" : "", S,
      S == 1 ? "" : "s");
  vr_pass_record *prep = record(&r, "prepare", true, "materials from the database, geometry, %d sub-domain%s",
                                S, S == 1 ? "" : "s");
  if (prep) prep->seconds = now() - t0;

  const vr_scene_settings *set = &s->settings;
  needs nd = analyse(rs);
  bool camera = s->camera.given && !opt->no_camera;
  bool photon_mode = set->integrator == VR_INT_PHOTON || set->integrator == VR_INT_PROGRESSIVE;
  bool lights_exist = rs->nsources > 0 && rs->total_power > 0;
  c.rs = rs;
  c.integrator = set->integrator;
  c.max_depth = set->max_depth;
  c.seed = set->seed;
  c.knn = set->knn;
  c.final_gather = set->final_gather;
  c.gather_rays = set->gather_rays;
  c.sensor_samples = set->sensor_samples;

  record(&r, "sky", rs->has_sky, rs->has_sky ? "the scene has a sky: next-event estimation samples it"
                                             : "no sky in the scene");
  record(&r, "dispersion", nd.dispersive,
         nd.dispersive ? "material '%s' refracts with n varying over the range: refraction keeps the hero wavelength"
                       : "%s",
         nd.dispersive ? nd.dispersive_example
                       : "no dispersive refraction: every path keeps all its wavelengths");
  /* UV pass for photochromic glass. */
  if (nd.photochromic) {
    t0 = now();
    vr_pass_record *p = record(&r, "uv", true, "photochromic glass: its state follows the UV irradiance per texel");
    st = uv_pass(&r, rs, &c, err);
    if (p) p->seconds = now() - t0;
    if (st) goto done;
    say(&r, "photochromic state: %.4f to %.4f over %zu texels", res->photochromic_state_min,
        res->photochromic_state_max, res->photochromic_texels);
  } else {
    record(&r, "uv", false, "no photochromic glass in the scene");
  }
  /* Sensors. */
  st = sensor_points(s, &c, res, err);
  if (st) goto done;
  if (c.npoints) {
    t0 = now();
    vr_pass_record *p = record(&r, "sensors", true, "%zu illuminance points, %d paths each",
                               c.npoints, c.sensor_samples);
    int groups = 16;
    st = vr_accum_create(&acc, 1, 1, rs->nbins, rs->film_lo, rs->film_step, c.npoints, groups, 0, err);
    if (st) goto done;
    c.acc = &acc;
    vr_integrator keep = c.integrator;
    c.integrator = VR_INT_PATH; /* sensors read the reference estimator */
    st = flow(&r, rs, &vr_sensor_ops, &c, (long)(c.npoints * (size_t)groups), "sensors", err);
    c.integrator = keep;
    if (p) p->seconds = now() - t0;
    if (st) goto done;
    res->sensor_spectral = calloc(c.npoints * rs->nbins + 1, sizeof *res->sensor_spectral);
    if (!res->sensor_spectral) {
      st = vr_error_set(err, VR_E_NOMEM, "out of memory");
      goto done;
    }
    for (size_t k = 0; k < c.npoints; k++) {
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
    c.acc = NULL;
  } else {
    record(&r, "sensors", false, "no sensors in the scene");
  }

  if (!camera) {
    record(&r, "camera", false, s->camera.given ? "camera pass not asked for" : "the scene has no camera");
    goto done;
  }
  int W = s->camera.width, H = s->camera.height;
  st = vr_accum_create(&acc, W, H, rs->nbins, rs->film_lo, rs->film_step, 0, 1, 0, err);
  if (st) goto done;
  c.acc = &acc;
  int spp = opt->spp > 0 ? opt->spp : set->spp;
  long photons = opt->photons > 0 ? opt->photons : set->photons;
  long cphotons = opt->photons > 0 ? opt->photons : set->caustic_photons;
  bool need_global = photon_mode && nd.diffuse && set->max_depth > 1 && lights_exist;
  bool need_caustic = photon_mode && nd.specular && nd.diffuse && lights_exist;
  if (photon_mode) {
    record(&r, "global photons", need_global, "%s",
           need_global ? "diffuse surfaces interreflect: global photon map for indirect light"
           : !nd.diffuse ? "no diffuse surface to store photons on"
           : !lights_exist ? "no light with power"
                           : "depth 1: no indirect light asked for");
    if (need_caustic)
      record(&r, "caustic photons", true,
             "material '%s' reflects or refracts specularly onto diffuse surfaces",
             nd.specular_example);
    else
      record(&r, "caustic photons", false, "%s",
             !nd.specular ? "no specular or glossy surface: no caustics possible"
                          : "no diffuse surface or no light: caustics cannot form");
  } else {
    record(&r, "global photons", false, "integrator %s uses no photon map",
           set->integrator == VR_INT_PATH ? "path" : "whitted");
    record(&r, "caustic photons", false, "integrator %s uses no photon map",
           set->integrator == VR_INT_PATH ? "path" : "whitted");
  }
  int passes = set->integrator == VR_INT_PROGRESSIVE ? (set->passes > 0 ? set->passes : 1) : 1;
  double radius0 = isnan(set->radius_m) ? 0.05 * rs->scene_radius : set->radius_m;
  double r2 = radius0 * radius0;
  double t_photons = 0, t_camera = 0;
  int spp_pass = passes > 1 ? (spp + passes - 1) / passes : spp;
  if (spp_pass < 1) spp_pass = 1;
  for (int pass = 0; pass < passes; pass++) {
    c.fixed_radius = set->integrator == VR_INT_PROGRESSIVE || !isnan(set->radius_m);
    c.radius = set->integrator == VR_INT_PROGRESSIVE ? sqrt(r2)
               : isnan(set->radius_m)                ? 0.1 * rs->scene_radius
                                                     : set->radius_m;
    c.sample_offset = pass * spp_pass;
    if (need_global || need_caustic) {
      t0 = now();
      long np = need_global ? photons : cphotons;
      st = photon_pass(&r, rs, &c, np, need_caustic, need_global, err);
      t_photons += now() - t0;
      if (st) goto done;
    }
    t0 = now();
    /* Each pass makes spp_pass samples of weight 1/spp_pass; the passes
     * are averaged when the film is read out. */
    c.spp = spp_pass;
    st = flow(&r, rs, &vr_camera_ops, &c, H, "camera", err);
    t_camera += now() - t0;
    free_maps(&c);
    if (st) goto done;
    /* Progressive radius reduction (Knaus & Zwicker 2011): r_{i+1}^2 = r_i^2 (i + alpha) / (i + 1). */
    r2 = r2 * (pass + set->alpha) / (pass + 1);
  }
  if (need_global || need_caustic) {
    for (size_t i = 0; i < res->npasses; i++)
      if (strstr(res->passes[i].name, "photons") && res->passes[i].ran)
        res->passes[i].seconds = t_photons;
  }
  vr_pass_record *pc = record(&r, "camera", true, "%d x %d pixels, %d samples per pixel, %s", W, H,
                              spp_pass * passes,
                              set->integrator == VR_INT_PATH          ? "path tracing"
                              : set->integrator == VR_INT_WHITTED     ? "ray tracing with shadow rays"
                              : set->integrator == VR_INT_PROGRESSIVE ? "progressive photon mapping"
                                                                      : "photon mapping");
  if (pc) pc->seconds = t_camera;
  res->width = W;
  res->height = H;
  res->nbins = rs->nbins;
  res->bin_width_nm = rs->film_step;
  res->exposure_ev = s->camera.exposure_ev;
  size_t px = (size_t)W * H;
  res->xyz = malloc(px * 3 * sizeof *res->xyz);
  res->spectral = malloc(px * rs->nbins * sizeof *res->spectral);
  res->bin_nm = malloc(rs->nbins * sizeof *res->bin_nm);
  if (!res->xyz || !res->spectral || !res->bin_nm) {
    st = vr_error_set(err, VR_E_NOMEM, "out of memory");
    goto done;
  }
  for (size_t i = 0; i < px * 3; i++) res->xyz[i] = vr_atomic_get(&acc.xyz[i]) / passes;
  for (size_t i = 0; i < px * rs->nbins; i++) res->spectral[i] = vr_atomic_get(&acc.bins[i]) / passes;
  for (size_t b = 0; b < rs->nbins; b++) res->bin_nm[b] = rs->film_lo + (b + 0.5) * rs->film_step;

done:
  vr_accum_destroy(&acc);
  free_maps(&c);
  free(c.points);
  free(c.texel_object);
  free(c.texel_index);
  vr_rscene_destroy(rs);
  res->seconds_total = now() - t_start;
  if (st) {
    vr_render_result_destroy(res);
    return st;
  }
  *out = res;
  return VR_OK;
}

void vr_render_result_destroy(vr_render_result *r) {
  if (!r) return;
  free(r->xyz);
  free(r->bin_nm);
  free(r->spectral);
  free(r->readings);
  free(r->sensor_spectral);
  free(r->photochromic_state);
  free(r);
}
