/* Running passes: logging, records, the ray flow with its statistics, and
 * the photon pass.  See render_run.h. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "render_run.h"

double vr_run_now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

void vr_run_say(const run *r, const char *fmt, ...) {
  if (!r->opt->log) return;
  char line[512];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(line, sizeof line, fmt, ap);
  va_end(ap);
  r->opt->log(r->opt->user, line);
}

vr_pass_record *vr_run_record(run *r, const char *name, bool ran, const char *fmt, ...) {
  vr_render_result *res = r->res;
  if (res->npasses >= VR_MAX_PASSES) return NULL;
  vr_pass_record *p = &res->passes[res->npasses++];
  snprintf(p->name, sizeof p->name, "%s", name);
  p->ran = ran;
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(p->reason, sizeof p->reason, fmt, ap);
  va_end(ap);
  vr_run_say(r, "%-16s %-4s %s", name, ran ? "run" : "skip", p->reason);
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

/* The camera pass's units are the image's tiles (vr_camera_generate reads
 * them with vr_flow_tile), whatever count the caller gives.  Image space
 * (--image-space) runs the same callbacks through the tile scheduler over
 * the scene's one cell; see vr/flow.h. */
vr_status vr_run_flow(run *r, rscene *rs, const vr_flow_ops *ops, pass_ctx *c, long units,
                      const char *name, vr_error *err) {
  vr_flow_stats st = {0};
  r->pass = name;
  vr_status s = (r->opt->image_space ? vr_flow_run_image_space : vr_flow_run)(
      rs->d, ops, c, units, r->opt->threads, progress_cb, r, &st, err);
  add_stats(r->res, &st);
  return s;
}

/* Maps keep only the bins a photon's wavelengths fall in (at most nwl of
 * them), not all 10 nm bins of the range. */
vr_status vr_run_photon_pass(run *r, rscene *rs, pass_ctx *c, long photons, bool caustic,
                             bool global, bool direct, vr_error *err) {
  int nb = (int)ceil((rs->lmax - rs->lmin) / 10.0);
  if (nb < 1) nb = 1;
  if (global) {
    c->global = vr_photon_map_create_sparse(nb, rs->lmin, rs->lmax, rs->nwl, err);
    if (!c->global) return err ? err->status : VR_E_NOMEM;
  }
  if (direct) {
    c->direct = vr_photon_map_create_sparse(nb, rs->lmin, rs->lmax, rs->nwl, err);
    if (!c->direct) return err ? err->status : VR_E_NOMEM;
  }
  if (caustic) {
    c->caustic = vr_photon_map_create_sparse(nb, rs->lmin, rs->lmax, rs->nwl, err);
    if (!c->caustic) return err ? err->status : VR_E_NOMEM;
  }
  c->photons_per_unit = 1024;
  long units = (photons + c->photons_per_unit - 1) / c->photons_per_unit;
  c->photon_scale = 1.0 / (double)(units * c->photons_per_unit);
  vr_status st = vr_run_flow(r, rs, &vr_photon_ops, c, units, "photons", err);
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

void vr_run_free_maps(pass_ctx *c) {
  vr_photon_map_destroy(c->global);
  vr_photon_map_destroy(c->direct);
  vr_photon_map_destroy(c->caustic);
  c->global = c->direct = c->caustic = NULL;
}
