/* vr_render_scene: resolve the scene (world/), analyse what it calls for,
 * run the passes it needs (the photochromic UV pass, the sensors, the
 * camera image by the scene's integrator, integrators/), and collect the
 * film, the sensors and the statistics.
 *
 * Scene analysis (DESIGN §6.2) decides each pass from what the scene holds
 * and says why, so a user can see that a room without mirrors or glass
 * spheres pays nothing for caustics, and a room without photochromic glass
 * runs no UV pass.  This is the top of the renderer: it calls the
 * integrators, nothing below calls back into it. */
#include <malloc.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>

#include "integrators/integrator.h"
#include "integrators/sensors.h"
#include "integrators/uv.h"
#include "film/film_features.h"
#include "vr/comm.h"
#include "vr/models.h"
#include "vr/fisheye.h"

void vr_render_options_default(vr_render_options *o) {
  memset(o, 0, sizeof *o);
  o->subdomains = 1;
  o->threads = 1;
}

/* An adaptive film's sums (summed over the ranks) into means, each pixel
 * divided by its own samples, and each pixel's variance of its mean
 * luminance from its halves (adaptive.c). */
static vr_status adaptive_film(vr_render_result *res, vr_accum *acc, vr_camera_job *job,
                               size_t fb, vr_error *err) {
  size_t px = (size_t)job->W * (size_t)job->H;
  res->pixel_variance = malloc((px ? px : 1) * sizeof *res->pixel_variance);
  if (!res->pixel_variance) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  for (size_t p = 0; p < px; p++) {
    double n = job->pixel_samples[p], inv = n > 0 ? 1.0 / n : 0.0;
    double S = res->xyz[3 * p + 1], B = vr_atomic_get(&acc->half_xyz[3 * p + 1]);
    double d = n > 0 ? 2 * B / n - 2 * (S - B) / n : 0.0;
    res->pixel_variance[p] = d * d / 4;
    for (int k = 0; k < 3; k++) res->xyz[3 * p + (size_t)k] *= inv;
    for (size_t b = 0; b < fb; b++) res->spectral[p * fb + b] *= inv;
  }
  res->pixel_samples = job->pixel_samples;
  job->pixel_samples = NULL;
  res->adaptive = job->adaptive_summary;
  return VR_OK;
}

/* The camera image by the scene's integrator, read out into the result
 * (summed over the ranks, divided by its passes, with what it kept apart). */
static vr_status camera_image(vr_run *r, const vr_integrator_ops *ig, const vr_scene_needs *nd,
                              vr_error *err) {
  vr_rscene *rs = r->rs;
  const vr_scene *s = rs->s;
  const vr_render_options *opt = r->opt;
  const vr_scene_settings *set = &s->settings;
  vr_render_result *res = r->res;
  int W = s->camera.width, H = s->camera.height;
  vr_accum acc = {0};
  vr_camera_job job = {.run = r, .rs = rs, .acc = &acc, .W = W, .H = H,
                       .spp = opt->spp > 0 ? opt->spp : set->spp,
                       .photons = opt->photons > 0 ? opt->photons : set->photons,
                       .caustic_photons = opt->photons > 0 ? opt->photons : set->caustic_photons,
                       .needs = *nd,
                       .lights_exist = rs->L.nsources > 0 && rs->L.total_power > 0};
  job.adaptive = opt->target_error > 0 || opt->time_limit_s > 0;
  /* The film's spectral bins only when an output needs them. */
  size_t fb = opt->film_without_bins ? 0 : rs->nbins;
  vr_status st = vr_accum_create(&acc, W, H, fb, rs->film_lo, rs->film_step, 0, 1, 0, err);
  if (!st && rs->bins_mode) st = vr_accum_set_bins(&acc, rs->lmin, rs->lmax, rs->nwl, err);
  /* The film counts in the budget (its pages fill as the pass writes). */
  r->film_bytes = (size_t)W * (size_t)H * (3 + fb) * sizeof(double);
  /* Adaptive sampling adds a pixel's half-B XYZ and the rounds' arrays
   * (adaptive.c: count, active, sums, num, den, err). */
  if (job.adaptive) r->film_bytes += vr_adaptive_bytes_per_pixel() * (size_t)W * (size_t)H;
  if (opt->denoise) {
    /* The second half's XYZ and the features' sums. */
    job.halves = !job.adaptive;
    if (!st) st = vr_accum_keep_halves(&acc, err);
    if (!st) st = vr_accum_keep_features(&acc, err);
    r->film_bytes += (size_t)W * (size_t)H * (VR_FEATURES + (job.adaptive ? 0 : 3)) * sizeof(double);
  }
  if (!st && opt->pixel_patches) {
    if (!ig->source_tallies || job.adaptive || opt->denoise)
      st = vr_error_set(err, VR_E_ARG,
                        "an image's sky-patch coefficients need the path integrator with a fixed "
                        "number of samples per pixel");
    if (!st) st = vr_accum_keep_patches(&acc, err);
    r->film_bytes += (size_t)W * (size_t)H * VR_PIXEL_SOURCES * sizeof(double);
  }
  res->film_bytes = r->film_bytes;
  if (!st) st = ig->render(&job, err);
  if (st) goto done;
  if (opt->memory_budget) {
    /* The cells are done with: their memory goes to the outputs (the
     * writers' images) rather than on top of them. */
    for (int c = 0; c < vr_domains_count(rs->d); c++) vr_domains_unload(rs->d, c);
    malloc_trim(0);
  }
  vr_pass_record *pc;
  const struct vr_adaptive_summary *as = &job.adaptive_summary;
  if (job.adaptive)
    pc = vr_run_record(r, "camera", true,
                       "%d x %d pixels, %u to %u samples per pixel (mean %.1f, %d rounds), %s", W,
                       H, as->spp_min, as->spp_max, as->spp_mean, as->rounds, ig->what);
  else
    pc = vr_run_record(r, "camera", true, "%d x %d pixels, %d samples per pixel, %s", W, H,
                       job.spp, ig->what);
  if (pc) pc->seconds = job.seconds;
  res->width = W;
  res->height = H;
  res->exposure_ev = s->camera.exposure_ev;
  size_t px = (size_t)W * H;
  /* Each rank's film holds what its rays delivered: the sum is the image. */
  st = vr_ranks_sum_accum(r, &acc, RANKS_FILM, err);
  if (st) goto done;
  /* The sums become the result where they lie: no copy of the film. */
  res->xyz = vr_accum_take_mean(&acc.xyz, px * 3, job.passes);
  res->spectral = fb ? vr_accum_take_mean(&acc.bins, px * fb, job.passes) : NULL;
  if (acc.pixel_patches)
    res->pixel_patch_Y = vr_accum_take_mean(&acc.pixel_patches, px * VR_PIXEL_SOURCES, job.passes);
  if (job.adaptive && (st = adaptive_film(res, &acc, &job, fb, err))) goto done;
  /* What the integrator kept apart, before the denoiser reads the image. */
  if (job.add_film) job.add_film(job.state, res->xyz, res->spectral);
  if (opt->denoise) {
    /* The features on every rank; the denoised image where the files are
     * written. */
    double t0 = vr_run_now();
    st = vr_film_features(res, &acc, job.spp, job.passes, r->rank == 0, job.add_half_film,
                          job.state, opt->threads, err);
    if (st) goto done;
    res->denoise_seconds = vr_run_now() - t0;
    vr_pass_record *pd = r->rank == 0
        ? vr_run_record(r, "denoise", true, "feature-guided non-local means for the PNG (%d x %d)",
                        W, H)
        : vr_run_record(r, "denoise", false, "done by rank 0, which writes the files");
    if (pd) pd->seconds = res->denoise_seconds;
  }
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
  if (job.free_state) job.free_state(job.state);
  free(job.pixel_samples);
  vr_accum_destroy(&acc);
  r->film_bytes = 0;
  return st;
}

/* Each mesh line's triangles and bounds (the objects it became: one per
 * file material), to check a model's units and place the camera; the
 * first MESH_LINES_SAID lines, then how many more.  A line without units=
 * whose model spans more than MESH_UNITS_SUSPECT_M is warned about
 * whatever its rank: a room modelled in millimetres read as metres. */
enum { MESH_LINES_SAID = 12 };
#define MESH_UNITS_SUSPECT_M 1000.0
static void say_meshes(vr_run *r) {
  const vr_rscene *rs = r->rs;
  const vr_scene *s = rs->s;
  const vr_scene_tables *t = rs->t;
  size_t said = 0, more = 0;
  for (size_t i = 0; i < s->nobjects; i++) {
    const vr_scene_object *o = &s->objects[i];
    if (o->shape != VR_SHAPE_MESH) continue;
    /* The first object of its line only (the line's others follow it). */
    if (i > 0 && s->objects[i - 1].shape == VR_SHAPE_MESH && s->objects[i - 1].loc.line == o->loc.line)
      continue;
    uint64_t prims = 0;
    size_t nobj = 0;
    double box[6] = {0};
    bool any = false;
    for (size_t j = i; j < s->nobjects && s->objects[j].shape == VR_SHAPE_MESH &&
                       s->objects[j].loc.line == o->loc.line;
         j++, nobj++) {
      if (!t->object_prims || !t->object_prims[j]) continue;
      prims += t->object_prims[j];
      for (int a = 0; a < 3; a++) {
        if (!any || t->object_box[j][a] < box[a]) box[a] = t->object_box[j][a];
        if (!any || t->object_box[j][3 + a] > box[3 + a]) box[3 + a] = t->object_box[j][3 + a];
      }
      any = true;
    }
    const char *b = strrchr(o->mesh_path, '/');
    b = b ? b + 1 : o->mesh_path;
    double span = fmax(box[3] - box[0], fmax(box[4] - box[1], box[5] - box[2]));
    if (any && !o->units_given && span > MESH_UNITS_SUSPECT_M)
      vr_run_say(r, "warning: mesh '%s' (line %ld) spans %.4g m read as metres, as a line without "
                 "units= is: if the model is in millimetres or centimetres, add units=mm or "
                 "units=cm to that line (units=m if it really is in metres)", b, o->loc.line, span);
    if (said == MESH_LINES_SAID) {
      more++;
      continue;
    }
    vr_run_say(r, "scene: mesh '%s' (line %ld): %llu triangles in %zu object%s, bounds x %.4g to %.4g, "
               "y %.4g to %.4g, z %.4g to %.4g (m)",
               b, o->loc.line, (unsigned long long)prims, nobj,
               nobj == 1 ? "" : "s", box[0], box[3], box[1], box[4], box[2], box[5]);
    said++;
  }
  if (more) vr_run_say(r, "scene: ... and %zu more mesh lines", more);
}

/* The film's bins (for the camera's spectral film and the sensors'
 * spectra) and what the scene is, said once it is resolved. */
static vr_status describe(vr_run *r, int S, double t0, vr_error *err) {
  vr_rscene *rs = r->rs;
  vr_render_result *res = r->res;
  res->nbins = rs->nbins;
  res->bin_width_nm = rs->film_step;
  res->bin_nm = malloc((rs->nbins + 1) * sizeof *res->bin_nm);
  if (!res->bin_nm) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  for (size_t b = 0; b < rs->nbins; b++) res->bin_nm[b] = rs->film_lo + (b + 0.5) * rs->film_step;
  res->degenerate_triangles = (size_t)rs->t->degenerate_dropped;
  if (rs->t->degenerate_dropped)
    vr_run_say(r, "warning: %zu degenerate triangles dropped from meshes",
               (size_t)rs->t->degenerate_dropped);
  vr_run_say(r, "scene: %zu objects, %llu triangles, %llu spheres, %zu lights%s, %d sub-domain%s",
             rs->s->nobjects, (unsigned long long)rs->t->ntris,
             (unsigned long long)rs->t->nspheres, rs->L.n, rs->L.has_sky ? " + sky" : "", S,
             S == 1 ? "" : "s");
  if (rs->L.n == 0 && rs->L.nemitters == 0 && !rs->L.has_sky)
    vr_run_say(r, "warning: the scene has no light (no light line, no object with emission=, "
               "no sky): every pixel and reading will be 0");
  /* Where the geometry is, to place a camera in a model of unknown units. */
  vr_run_say(r, "scene: bounds x %.4g to %.4g, y %.4g to %.4g, z %.4g to %.4g (m, %.4g x %.4g x %.4g)",
             rs->t->bmin[0], rs->t->bmax[0], rs->t->bmin[1], rs->t->bmax[1], rs->t->bmin[2],
             rs->t->bmax[2], rs->t->bmax[0] - rs->t->bmin[0], rs->t->bmax[1] - rs->t->bmin[1],
             rs->t->bmax[2] - rs->t->bmin[2]);
  res->textures = rs->ntex;
  res->texture_bytes = rs->tex_bytes;
  res->texture_seconds = rs->tex_seconds;
  if (rs->ntex)
    vr_run_say(r, "textures: %zu loaded, %.1f MiB with their mip-maps, in %.2f s", rs->ntex,
               (double)rs->tex_bytes / 1048576.0, rs->tex_seconds);
  say_meshes(r);
  vr_pass_record *prep = vr_run_record(r, "prepare", true,
                                       "materials from the database, geometry, %d sub-domain%s", S,
                                       S == 1 ? "" : "s");
  if (prep) prep->seconds = vr_run_now() - t0;
  return VR_OK;
}

/* The passes the scene calls for, each decided and said: the sky and
 * dispersion (no pass of their own), the UV pass of photochromic glass,
 * the sensors, the camera image. */
static vr_status passes(vr_run *r, const vr_integrator_ops *ig, vr_error *err) {
  vr_rscene *rs = r->rs;
  const vr_scene *s = rs->s;
  vr_render_result *res = r->res;
  vr_scene_needs nd = vr_rscene_needs(rs);
  vr_run_record(r, "sky", rs->L.has_sky,
                rs->L.has_sky ? "the scene has a sky: next-event estimation samples it"
                              : "no sky in the scene");
  vr_run_record(r, "dispersion", nd.dispersive,
                nd.dispersive ? "material '%s' refracts with n varying over the range: refraction "
                                "keeps the hero wavelength"
                              : "%s",
                nd.dispersive ? nd.dispersive_example
                              : "no dispersive refraction: every path keeps all its wavelengths");
  vr_status st = VR_OK;
  if (nd.photochromic) {
    double t0 = vr_run_now();
    vr_pass_record *p = vr_run_record(
        r, "uv", true, "photochromic glass: its state follows the UV irradiance per texel");
    st = vr_uv_run(r, err);
    if (p) p->seconds = vr_run_now() - t0;
    if (st) return st;
    vr_run_say(r, "photochromic state: %.4f to %.4f over %zu texels", res->photochromic_state_min,
               res->photochromic_state_max, res->photochromic_texels);
    if (res->photochromic_extrapolated)
      vr_run_say(r, "warning: %zu texels outside the UV or temperature range the glass was "
                 "fitted on, extrapolated as extrapolate=yes asked", res->photochromic_extrapolated);
  } else {
    vr_run_record(r, "uv", false, "no photochromic glass in the scene");
  }
  st = vr_sensors_run(r, err);
  if (st) return st;
  if (!s->camera.given || r->opt->no_camera) {
    vr_run_record(r, "camera", false,
                  s->camera.given ? "camera pass not asked for" : "the scene has no camera");
    return VR_OK;
  }
  return camera_image(r, ig, &nd, err);
}

/* The sub-domains' counters into the result. */
static void domain_stats(const vr_rscene *rs, vr_render_result *res) {
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
  if (res->nprofiles) {
    int S = vr_domains_count(rs->d);
    res->profile_load_seconds = calloc((size_t)S, sizeof *res->profile_load_seconds);
    res->profile_cell_bytes = calloc((size_t)S, sizeof *res->profile_cell_bytes);
    for (int c = 0; res->profile_load_seconds && res->profile_cell_bytes && c < S; c++) {
      res->profile_load_seconds[c] = vr_domains_cell_load_seconds(rs->d, c);
      res->profile_cell_bytes[c] = (double)vr_domains_cell_bytes(rs->d, c);
    }
  }
}

/* Adaptive sampling's options: their ranges, and an integrator that can. */
static vr_status check_adaptive(const vr_scene *s, const vr_render_options *opt,
                                const vr_integrator_ops *ig, vr_error *err) {
  if (!(opt->target_error >= 0 && opt->target_error < 1))
    return vr_error_set(err, VR_E_ARG, "target error %g: must be in [0, 1) (relative; 0: none)",
                        opt->target_error);
  if (!(opt->time_limit_s >= 0) || isinf(opt->time_limit_s))
    return vr_error_set(err, VR_E_ARG, "time limit %g s: must be finite and >= 0 (0: none)",
                        opt->time_limit_s);
  if (opt->max_spp < 0)
    return vr_error_set(err, VR_E_ARG, "max spp %d: must be >= 0 (0: 65536)", opt->max_spp);
  if (opt->target_error == 0 && opt->time_limit_s == 0) return VR_OK;
  if (opt->no_camera || !s->camera.given) {
    /* Path sensors take a target error too (sensors.c); the rest is the
     * camera's. */
    bool path_sensors = s->nsensors > 0 && s->settings.sensors != VR_SENSORS_PHOTON;
    if (opt->time_limit_s > 0 || opt->max_spp > 0 || !path_sensors)
      return vr_error_set(err, VR_E_ARG,
                          "%s: %s applies to the camera image's pixels%s, and this render has no "
                          "camera pass%s",
                          s->path ? s->path : "<scene>",
                          opt->time_limit_s > 0 ? "a time limit"
                          : opt->max_spp > 0    ? "a max spp"
                                                : "a target error",
                          opt->time_limit_s > 0 || opt->max_spp > 0 ? "" : " and path sensors",
                          opt->time_limit_s > 0 || opt->max_spp > 0 ? "" : " and no path sensors");
    return VR_OK;
  }
  if (opt->flow_profile)
    return vr_error_set(err, VR_E_ARG,
                        "%s: a flow profile records each pass of the ray flow, and adaptive "
                        "sampling's rounds are many passes: profile a render of fixed spp",
                        s->path ? s->path : "<scene>");
  int spp = opt->spp > 0 ? opt->spp : s->settings.spp, first = 2 * vr_adaptive_half(spp);
  if (opt->max_spp > 0 && opt->max_spp < first)
    return vr_error_set(err, VR_E_ARG,
                        "max spp %d is below the first round's %d samples a pixel (two halves, each "
                        "the smallest multiple of spp = %d that is at least 4)",
                        opt->max_spp, first, spp);
  if (!ig->adaptive)
    return vr_error_set(err, VR_E_ARG,
                        "%s: integrator=%s cannot sample adaptively (a pixel's estimate is not its "
                        "own samples' mean: %s); use path, photon or whitted",
                        s->path ? s->path : "<scene>", ig->name,
                        strcmp(ig->name, "bdpt") == 0
                            ? "light paths land on any pixel"
                            : "its photon statistics are shared by every pixel over iterations");
  return VR_OK;
}

/* What the denoiser needs: a camera pass by an integrator whose pixels are
 * their own samples' means (as adaptive sampling), or one that renders two
 * independent chains (SPPM), and two equal halves of samples. */
static vr_status check_denoise(const vr_scene *s, const vr_render_options *opt,
                               const vr_integrator_ops *ig, vr_error *err) {
  if (!opt->denoise) return VR_OK;
  const char *path = s->path ? s->path : "<scene>";
  if (opt->no_camera || !s->camera.given)
    return vr_error_set(err, VR_E_ARG, "%s: denoising filters the camera image, and this render "
                        "has no camera pass", path);
  if (!ig->adaptive && !ig->chains)
    return vr_error_set(err, VR_E_ARG,
                        "%s: integrator=%s cannot be denoised (its pixels are not their own "
                        "samples' means, so two halves of them are not independent estimates); "
                        "use path, photon, progressive or whitted", path, ig->name);
  if (opt->flow_profile)
    return vr_error_set(err, VR_E_ARG,
                        "%s: a flow profile records each pass of the ray flow, and a denoised "
                        "render's camera pass is two (its halves): profile a render without "
                        "--denoise", path);
  int spp = opt->spp > 0 ? opt->spp : s->settings.spp;
  if (!(opt->target_error > 0 || opt->time_limit_s > 0) && (spp < 2 || spp % 2))
    return vr_error_set(err, VR_E_ARG,
                        "%s: denoising takes a pixel's samples in two independent halves: spp=%d "
                        "must be even and at least 2", path, spp);
  return VR_OK;
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
  if (vr_scene_models_pending(s))
    return vr_error_set(err, VR_E_ARG,
                        "%s: mesh lines take their materials from their files: call "
                        "vr_scene_load_models before rendering",
                        s->path ? s->path : "<scene>");
  if (opt->memory_budget && opt->image_space)
    return vr_error_set(err, VR_E_ARG,
                        "image space keeps the whole scene in every thread; it cannot run under "
                        "a memory budget");
  vr_render_result *res = calloc(1, sizeof *res);
  if (!res) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  res->eye_illuminance_lx = res->glare.dgp = NAN; /* set by a fisheye camera pass */
  vr_run r = {.opt = opt, .res = res, .comm = opt->comm, .rank = vr_comm_rank(opt->comm),
              .nranks = vr_comm_size(opt->comm), .t_start = t_start};
  int S = opt->image_space ? 1 : (opt->subdomains > 0 ? opt->subdomains : 1);
  res->subdomains = S;
  res->memory_budget = opt->memory_budget;
  /* What the integrator cannot do is refused before any work. */
  const vr_integrator_ops *ig = vr_integrator_ops_of((size_t)s->settings.integrator);
  vr_status st = ig->check ? ig->check(s, opt, r.nranks, err) : VR_OK;
  if (!st) st = check_adaptive(s, opt, ig, err);
  if (!st) st = check_denoise(s, opt, ig, err);
  if (!st) st = vr_rscene_create(s, db, opt, S, &r.rs, err);
  if (!st && opt->memory_budget) {
    /* Under a budget the resident memory is watched, from here: the
     * budget is what the render adds to what the process holds now (its
     * libraries' data, the scene's tables).  Transparent huge pages are
     * off for the process: a 2 MiB page that holds a few KiB of an Embree
     * block made the resident memory a fifth larger than what was
     * allocated (docs/ddm.md, "The memory budget"), and freed memory goes
     * back to the system soon. */
    prctl(PR_SET_THP_DISABLE, 1, 0, 0, 0);
    mallopt(M_TRIM_THRESHOLD, 8 << 20);
    /* The textures, read with the scene, are the render's: counted in
     * the budget (run.c's held), so not in the base. */
    r.rss_base = vr_flow_rss_bytes(true);
    if (!st && r.rss_base > (long long)r.rs->tex_bytes) r.rss_base -= (long long)r.rs->tex_bytes;
    res->rss_base_bytes = r.mine.rss_base_bytes = r.rss_base;
    res->rss_start_bytes = r.mine.rss_start_bytes = vr_flow_rss_bytes(false);
  }
  /* Several ranks: every one must have its scene before they compare. */
  st = vr_ranks_sync(&r, st, err);
  if (!st) st = vr_ranks_check_scene(&r, r.rs, err);
  /* Without a budget every cell is loaded now, as the passes start (with
   * several ranks each loads the cells it owns when a pass starts). */
  if (!st && !opt->memory_budget && r.nranks == 1) st = vr_domains_load_all(r.rs->d, err);
  if (!st) st = describe(&r, S, t_start, err);
  if (!st) st = passes(&r, ig, err);
  /* A failure the other ranks do not know of yet meets their next sync. */
  if (st && !r.failure_agreed) vr_ranks_sync(&r, st, err);
  if (r.rs && r.rs->d) domain_stats(r.rs, res);
  if (!st) st = vr_ranks_finish(&r, r.rs, res, err);
  vr_rscene_destroy(r.rs);
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
  free(r->pixel_samples);
  free(r->pixel_variance);
  free(r->features);
  free(r->xyz_display);
  free(r->bin_nm);
  free(r->spectral);
  free(r->readings);
  free(r->sensor_spectral);
  free(r->sky_patch_lx);
  free(r->pixel_patch_Y);
  free(r->sensor_names);
  free(r->photochromic_state);
  free(r->photochromic_uv);
  free(r->photochromic_object);
  free(r->photochromic_uv_patch);
  free(r->rank_stats);
  free(r->cell_seconds);
  free(r->cell_ranks);
  for (int i = 0; i < r->nprofiles; i++) vr_flow_profile_destroy(r->profiles[i].p);
  free(r->profile_load_seconds);
  free(r->profile_cell_bytes);
  free(r);
}
