/* vr_render_scene: resolve, analyse, run the passes the scene calls for,
 * collect the film, the sensors and the statistics.
 *
 * Scene analysis (DESIGN §6.2) decides each pass from what the scene holds
 * and says why, so a user can see that a room without mirrors or glass
 * spheres pays nothing for caustics, and a room without photochromic glass
 * runs no UV pass. */
#include <malloc.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "render_run.h"
#include "bdpt.h"
#include "sppm.h"
#include "vr/chromogenic.h"
#include "vr/comm.h"
#include "vr/fisheye.h"

void vr_render_options_default(vr_render_options *o) {
  memset(o, 0, sizeof *o);
  o->subdomains = 1;
  o->threads = 1;
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
  size_t nt = rs->ntexels;
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
    for (int t = 0; t < rs->obj[i].nu * rs->obj[i].nv; t++) {
      c->texel_object[k] = (uint32_t)i;
      c->texel_index[k++] = (uint32_t)t;
    }
  c->acc = &acc;
  c->uv_sky_samples = 64;
  st = vr_run_flow(r, rs, &vr_uv_ops, c, (long)nt, "uv", err);
  if (!st) st = vr_ranks_sum_accum(r, &acc, RANKS_TEXELS, err);
  vr_render_result *res = r->res;
  res->photochromic_texels = nt;
  res->photochromic_state = calloc(nt + 1, sizeof *res->photochromic_state);
  if (!st && !res->photochromic_state) st = vr_error_set(err, VR_E_NOMEM, "out of memory");
  res->photochromic_uv = calloc(nt + 1, sizeof *res->photochromic_uv);
  res->photochromic_object = calloc(nt + 1, sizeof *res->photochromic_object);
  res->photochromic_uv_patch = calloc(nt * VR_SENSOR_PATCHES + 1, sizeof *res->photochromic_uv_patch);
  if (!st && (!res->photochromic_uv || !res->photochromic_uv_patch || !res->photochromic_object))
    st = vr_error_set(err, VR_E_NOMEM, "out of memory");
  res->photochromic_state_min = INFINITY;
  res->photochromic_state_max = -INFINITY;
  for (size_t t = 0; !st && t < nt; t++) {
    robject *o = &rs->obj[c->texel_object[t]];
    const rmaterial *m = &rs->mat[o->material];
    double E = vr_atomic_get(&acc.texel_uv[t]), s;
    res->photochromic_uv[t] = E;
    res->photochromic_object[t] = c->texel_object[t];
    for (size_t q = 0; q < VR_SENSOR_PATCHES; q++)
      res->photochromic_uv_patch[t * VR_SENSOR_PATCHES + q] =
          vr_atomic_get(&acc.texel_patches[t * VR_SENSOR_PATCHES + q]);
    st = vr_chromo_steady_state(m->db, E, m->temperature_K, &s, err);
    if (st) break;
    res->photochromic_state[t] = s;
    if (s < res->photochromic_state_min) res->photochromic_state_min = s;
    if (s > res->photochromic_state_max) res->photochromic_state_max = s;
  }
  vr_accum_destroy(&acc);
  c->acc = NULL;
  /* Each cell's copy of each map it holds takes the states. */
  for (int cell = 0; !st && cell < vr_domains_count(rs->d); cell++) {
    const rcell *rc = &rs->cells[cell];
    for (size_t k = 0; k < rc->nmaps; k++) {
      const robject *o = &rs->obj[rc->map_object[k]];
      memcpy(rc->map[k], res->photochromic_state + o->texel0,
             (size_t)o->nu * (size_t)o->nv * sizeof *rc->map[k]);
    }
  }
  return st;
}

/* The camera pass's units: each tile in waves of at most CAMERA_WAVE_RAYS
 * camera rays (unit = wave x tiles + tile), so the rays in flight, and the
 * memory, do not grow with the samples per pixel. */
enum { CAMERA_WAVE_RAYS = 16384 };

/* The camera pass.  With several ranks owning cells, it runs in two parts:
 * every eighth tile first, whose measured cost per cell then decides who
 * owns which cell for the rest (the film does not care in which part a
 * tile was rendered). */
static vr_status camera_pass(run *r, rscene *rs, pass_ctx *c, int W, int H, vr_error *err) {
  if (rs->s->settings.integrator == VR_INT_BDPT) return vr_bdpt_camera_pass(r, rs, c, W, H, err);
  long tiles = vr_flow_tiles(W, H);
  c->wave_spp = CAMERA_WAVE_RAYS / (VR_FLOW_TILE * VR_FLOW_TILE);
  if (c->wave_spp < 1) c->wave_spp = 1;
  if (c->wave_spp > c->spp) c->wave_spp = c->spp;
  long waves = (c->spp + c->wave_spp - 1) / c->wave_spp, units = tiles * waves;
  if (r->nranks == 1 || r->opt->image_space || tiles < 16)
    return vr_run_flow(r, rs, &vr_camera_ops, c, units, "camera", err);
  long *list = malloc((size_t)units * sizeof *list), n = 0;
  vr_status st = list ? VR_OK : vr_error_set(err, VR_E_NOMEM, "out of memory");
  st = vr_ranks_sync(r, st, err);
  if (st) {
    free(list);
    return st;
  }
  /* The first wave's every eighth tile probes the cells' costs first. */
  for (long t = 0; t < tiles; t += 8) list[n++] = t;
  long probe = n;
  for (long u = 0; u < units; u++)
    if (u >= tiles || u % 8) list[n++] = u;
  st = vr_run_flow_units(r, rs, &vr_camera_ops, c, list, probe, "camera", err);
  if (!st) st = vr_run_flow_units(r, rs, &vr_camera_ops, c, list + probe, n - probe, "camera", err);
  free(list);
  return st;
}

/* The first radius of a pixel's visible point in SPPM, in pixel
 * footprints at the point, unless the scene gives radius= (metres). */
#define SPPM_RADIUS_PX 4.0

/* One SPPM iteration (sppm.h): the visible points, their grid, the
 * photons, the update; each step's sums added over the ranks. */
static vr_status sppm_iteration(run *r, rscene *rs, pass_ctx *c, int W, int H, int it,
                                int iterations, long photons, bool trace_photons,
                                double *t_camera, double *t_photons, vr_error *err) {
  vr_sppm *s = c->sppm;
  vr_sppm_begin(s, rs, it, iterations);
  double t0 = vr_run_now();
  c->spp = 1;
  vr_status st = camera_pass(r, rs, c, W, H, err);
  if (!st && r->nranks > 1) st = vr_sppm_sum_points(s, r->comm, err);
  if (!st) st = vr_sppm_build(s, err);
  *t_camera += vr_run_now() - t0;
  if (st || !trace_photons) return st;
  t0 = vr_run_now();
  c->photons_per_unit = 1024;
  long units = (photons + c->photons_per_unit - 1) / c->photons_per_unit;
  if (units < 1) units = 1;
  st = vr_run_flow(r, rs, &vr_photon_ops, c, units, "photons", err);
  if (!st && r->nranks > 1) st = vr_sppm_sum_photons(s, r->comm, err);
  if (!st) vr_sppm_update(s, (uint64_t)units * (uint64_t)c->photons_per_unit);
  *t_photons += vr_run_now() - t0;
  return st;
}

vr_status vr_render_scene(const vr_scene *s, vr_matdb *db, const vr_render_options *opt,
                          vr_render_result **out, vr_error *err) {
  *out = NULL;
  double t_start = vr_run_now();
  /* Each pass's ray flow allocates its queue blocks (a few hundred KiB
   * each, above glibc's default mmap threshold) and frees them at its end:
   * with many passes (an SPPM iteration is two) every block came back as
   * fresh pages, a third of the run in page faults.  Freed memory now stays
   * in the heap for the next pass (bounded by the largest pass's queues). */
  mallopt(M_MMAP_THRESHOLD, 64 << 20);
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
  vr_render_result *res = calloc(1, sizeof *res);
  if (res) res->eye_illuminance_lx = res->glare.dgp = NAN; /* set by a fisheye camera pass */
  if (!res) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  run r = {.opt = opt, .res = res, .comm = opt->comm, .rank = vr_comm_rank(opt->comm),
           .nranks = vr_comm_size(opt->comm)};
  int S = opt->image_space ? 1 : (opt->subdomains > 0 ? opt->subdomains : 1);
  rscene *rs = NULL;
  pass_ctx c = {0};
  accum acc = {0};
  vr_sppm vp = {0};
  double t0 = vr_run_now();
  if (opt->memory_budget && opt->image_space) {
    free(res);
    return vr_error_set(err, VR_E_ARG,
                        "image space keeps the whole scene in every thread; it cannot run under "
                        "a memory budget");
  }
  res->subdomains = S;
  res->memory_budget = opt->memory_budget;
  /* BDPT needs the whole scene in one cell: refused before any work otherwise. */
  vr_status st = vr_bdpt_check(s, opt, r.nranks, err);
  if (!st) st = vr_rscene_create(s, db, opt, S, &rs, err);
  /* Several ranks: every one must have its scene before they compare. */
  st = vr_ranks_sync(&r, st, err);
  if (!st) st = vr_ranks_check_scene(&r, rs, err);
  /* Without a budget every cell is loaded now, as the passes start (with
   * several ranks each loads the cells it owns when a pass starts). */
  if (!st && !opt->memory_budget && r.nranks == 1) st = vr_domains_load_all(rs->d, err);
  if (st) goto done;
  /* The film's bins, for the camera's spectral film and the sensors' spectra. */
  res->nbins = rs->nbins;
  res->bin_width_nm = rs->film_step;
  res->bin_nm = malloc((rs->nbins + 1) * sizeof *res->bin_nm);
  if (!res->bin_nm) {
    st = vr_error_set(err, VR_E_NOMEM, "out of memory");
    goto done;
  }
  for (size_t b = 0; b < rs->nbins; b++) res->bin_nm[b] = rs->film_lo + (b + 0.5) * rs->film_step;
  res->degenerate_triangles = (size_t)rs->t->degenerate_dropped;
  if (rs->t->degenerate_dropped)
    vr_run_say(&r, "warning: %zu degenerate triangles dropped from meshes",
               (size_t)rs->t->degenerate_dropped);
  vr_run_say(&r, "scene: %zu objects, %llu triangles, %llu spheres, %zu lights%s, %d sub-domain%s",
      s->nobjects, (unsigned long long)rs->t->ntris, (unsigned long long)rs->t->nspheres,
      rs->nlights, rs->has_sky ? " + sky" : "", S,
      S == 1 ? "" : "s");
  vr_pass_record *prep = vr_run_record(&r, "prepare", true, "materials from the database, geometry, %d sub-domain%s",
                                S, S == 1 ? "" : "s");
  if (prep) prep->seconds = vr_run_now() - t0;

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

  vr_run_record(&r, "sky", rs->has_sky, rs->has_sky ? "the scene has a sky: next-event estimation samples it"
                                             : "no sky in the scene");
  vr_run_record(&r, "dispersion", nd.dispersive,
         nd.dispersive ? "material '%s' refracts with n varying over the range: refraction keeps the hero wavelength"
                       : "%s",
         nd.dispersive ? nd.dispersive_example
                       : "no dispersive refraction: every path keeps all its wavelengths");
  /* UV pass for photochromic glass. */
  if (nd.photochromic) {
    t0 = vr_run_now();
    vr_pass_record *p = vr_run_record(&r, "uv", true, "photochromic glass: its state follows the UV irradiance per texel");
    st = uv_pass(&r, rs, &c, err);
    if (p) p->seconds = vr_run_now() - t0;
    if (st) goto done;
    vr_run_say(&r, "photochromic state: %.4f to %.4f over %zu texels", res->photochromic_state_min,
        res->photochromic_state_max, res->photochromic_texels);
  } else {
    vr_run_record(&r, "uv", false, "no photochromic glass in the scene");
  }
  /* Sensors. */
  st = vr_sensor_points(s, &c, res, err);
  if (!st) st = vr_sensor_pass(&r, rs, &c, err);
  if (st) goto done;

  if (!camera) {
    vr_run_record(&r, "camera", false, s->camera.given ? "camera pass not asked for" : "the scene has no camera");
    goto done;
  }
  int W = s->camera.width, H = s->camera.height;
  st = vr_accum_create(&acc, W, H, rs->nbins, rs->film_lo, rs->film_step, 0, 1, 0, err);
  if (!st && rs->bins_mode) st = vr_accum_set_bins(&acc, rs->lmin, rs->lmax, rs->nwl, err);
  if (st) goto done;
  c.acc = &acc;
  int spp = opt->spp > 0 ? opt->spp : set->spp;
  long photons = opt->photons > 0 ? opt->photons : set->photons;
  long cphotons = opt->photons > 0 ? opt->photons : set->caustic_photons;
  bool need_global = photon_mode && nd.diffuse && set->max_depth > 1 && lights_exist;
  bool need_caustic = photon_mode && nd.specular && nd.diffuse && lights_exist;
  if (set->integrator == VR_INT_PROGRESSIVE) {
    bool any = need_global || need_caustic;
    vr_run_record(&r, "photons", any, "%s",
                  any ? "progressive photon mapping: each iteration's photons reach the visible "
                        "points where they land (no map kept)"
                  : !nd.diffuse ? "no diffuse surface for photons to reach"
                  : !lights_exist ? "no light with power"
                                  : "depth 1: no indirect light asked for");
  } else if (photon_mode) {
    vr_run_record(&r, "global photons", need_global, "%s",
           need_global ? "diffuse surfaces interreflect: global photon map for indirect light"
           : !nd.diffuse ? "no diffuse surface to store photons on"
           : !lights_exist ? "no light with power"
                           : "depth 1: no indirect light asked for");
    if (need_caustic)
      vr_run_record(&r, "caustic photons", true,
             "material '%s' reflects or refracts specularly onto diffuse surfaces",
             nd.specular_example);
    else
      vr_run_record(&r, "caustic photons", false, "%s",
             !nd.specular ? "no specular or glossy surface: no caustics possible"
                          : "no diffuse surface or no light: caustics cannot form");
  } else {
    vr_run_record(&r, "global photons", false, "integrator %s uses no photon map",
           set->integrator == VR_INT_PATH   ? "path"
           : set->integrator == VR_INT_BDPT ? "bdpt"
                                            : "whitted");
    vr_run_record(&r, "caustic photons", false, "integrator %s uses no photon map",
           set->integrator == VR_INT_PATH   ? "path"
           : set->integrator == VR_INT_BDPT ? "bdpt"
                                            : "whitted");
  }
  /* Progressive photon mapping (sppm.c): spp iterations of one camera
   * path a pixel and `photons` photons each. */
  bool sppm = set->integrator == VR_INT_PROGRESSIVE;
  int passes = sppm ? spp : 1;
  double t_photons = 0, t_camera = 0;
  int spp_pass = sppm ? 1 : spp;
  if (sppm) {
    st = vr_sppm_create(&vp, rs, W, H, isnan(set->radius_m) ? 0 : set->radius_m, SPPM_RADIUS_PX,
                        set->alpha, err);
    if (st) goto done;
    c.sppm = &vp;
  }
  for (int pass = 0; pass < passes; pass++) {
    c.fixed_radius = !isnan(set->radius_m);
    c.radius = isnan(set->radius_m) ? 0.1 * rs->scene_radius : set->radius_m;
    c.sample_offset = pass * spp_pass;
    if (sppm) {
      st = sppm_iteration(&r, rs, &c, W, H, pass, passes, photons, need_global || need_caustic,
                          &t_camera, &t_photons, err);
      if (st) goto done;
      continue;
    }
    if (need_global || need_caustic) {
      t0 = vr_run_now();
      long np = need_global ? photons : cphotons;
      st = vr_run_photon_pass(&r, rs, &c, np, need_caustic, need_global, need_global && c.final_gather, err);
      t_photons += vr_run_now() - t0;
      if (st) goto done;
    }
    t0 = vr_run_now();
    /* Each pass makes spp_pass samples of weight 1/spp_pass; the passes
     * are averaged when the film is read out. */
    c.spp = spp_pass;
    st = camera_pass(&r, rs, &c, W, H, err);
    t_camera += vr_run_now() - t0;
    vr_run_free_maps(&c);
    if (st) goto done;
  }
  if (sppm) {
    double rlo, rmed, rhi;
    vr_sppm_radii(&vp, &rlo, &rmed, &rhi);
    vr_run_say(&r, "progressive: %d iterations of %ld photons; pixel radii now %.3g to %.3g mm "
                   "(median %.3g mm)", passes, photons, 1e3 * rlo, 1e3 * rhi, 1e3 * rmed);
  }
  if (need_global || need_caustic) {
    for (size_t i = 0; i < res->npasses; i++)
      if (strstr(res->passes[i].name, "photons") && res->passes[i].ran)
        res->passes[i].seconds = t_photons;
  }
  vr_pass_record *pc = vr_run_record(&r, "camera", true, "%d x %d pixels, %d samples per pixel, %s", W, H,
                              spp_pass * passes,
                              set->integrator == VR_INT_PATH          ? "path tracing"
                              : set->integrator == VR_INT_WHITTED     ? "ray tracing with shadow rays"
                              : set->integrator == VR_INT_PROGRESSIVE ? "progressive photon mapping"
                              : set->integrator == VR_INT_BDPT        ? "bidirectional path tracing"
                                                                      : "photon mapping");
  if (pc) pc->seconds = t_camera;
  res->width = W;
  res->height = H;
  res->exposure_ev = s->camera.exposure_ev;
  size_t px = (size_t)W * H;
  res->xyz = malloc(px * 3 * sizeof *res->xyz);
  res->spectral = malloc(px * rs->nbins * sizeof *res->spectral);
  if (!res->xyz || !res->spectral) {
    st = vr_error_set(err, VR_E_NOMEM, "out of memory");
    goto done;
  }
  /* Each rank's film holds what its rays delivered: the sum is the image. */
  st = vr_ranks_sum_accum(&r, &acc, RANKS_FILM, err);
  if (st) goto done;
  for (size_t i = 0; i < px * 3; i++) res->xyz[i] = vr_atomic_get(&acc.xyz[i]) / passes;
  for (size_t i = 0; i < px * rs->nbins; i++) res->spectral[i] = vr_atomic_get(&acc.bins[i]) / passes;
  /* SPPM: the photons' radiance, the same on every rank. */
  if (sppm) vr_sppm_film(&vp, res->xyz, res->spectral);
  if (s->camera.model == VR_CAM_FISHEYE) {
    /* The vertical illuminance at the lens and the glare probability from
     * the image's luminance. */
    double *Y = malloc(px * sizeof *Y);
    if (!Y) {
      st = vr_error_set(err, VR_E_NOMEM, "out of memory");
      goto done;
    }
    for (size_t i = 0; i < px; i++) Y[i] = res->xyz[3 * i + 1];
    vr_fisheye_dgp(&s->camera, Y, 0.0, &res->glare);
    res->eye_illuminance_lx = res->glare.vertical_lx;
    free(Y);
  }

done:
  /* A failure the other ranks do not know of yet meets their next sync. */
  if (st && !r.failure_agreed) vr_ranks_sync(&r, st, err);
  if (rs && rs->d) {
    vr_domains_stats ds;
    vr_domains_get_stats(rs->d, &ds);
    res->cell_loads = ds.loads;
    res->cell_unloads = ds.unloads;
    res->cell_bytes_read = ds.bytes_read;
    res->cell_load_seconds = ds.load_seconds;
    res->peak_cells_bytes = ds.peak_cells;
    res->peak_geometry_bytes = ds.peak_geometry;
    res->peak_embree_bytes = ds.peak_embree;
    res->cache_built = ds.cache_built;
    snprintf(res->cache_reason, sizeof res->cache_reason, "%s", ds.cache_reason);
    res->cache_seconds = ds.cache_seconds;
    res->cache_bytes = ds.cache_bytes;
  }
  if (!st) st = vr_ranks_finish(&r, rs, res, err);
  vr_accum_destroy(&acc);
  vr_sppm_destroy(&vp);
  vr_run_free_maps(&c);
  free(c.points);
  free(c.texel_object);
  free(c.texel_index);
  vr_rscene_destroy(rs);
  res->seconds_total = vr_run_now() - t_start;
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
  free(r->sky_patch_lx);
  free(r->sensor_names);
  free(r->photochromic_state);
  free(r->photochromic_uv);
  free(r->photochromic_object);
  free(r->photochromic_uv_patch);
  free(r->rank_stats);
  free(r->cell_seconds);
  free(r->cell_owner);
  free(r);
}
