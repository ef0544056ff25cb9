/* Running passes: logging, records, the ray flow with its statistics, and
 * the photon pass.  See render_run.h. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "render_run.h"
#include "vr/comm.h"

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

/* What the render holds besides cells and queues: photon maps (growing
 * while a photon pass fills them) and the state maps. */
static size_t held(void *u) {
  const pass_ctx *c = u;
  size_t b = vr_rscene_map_bytes(c->rs);
  b += vr_photon_set_bytes(c->direct) + vr_photon_set_bytes(c->caustic) +
       vr_photon_set_bytes(c->global);
  return b;
}

static void add_stats(vr_render_result *res, const vr_flow_stats *st) {
  res->rays_camera += st->by_purpose[PURPOSE_CAMERA] + st->by_purpose[PURPOSE_GATHER];
  res->rays_shadow += st->by_purpose[PURPOSE_SHADOW];
  res->rays_photon += st->by_purpose[PURPOSE_PHOTON];
  res->rays_other += st->by_purpose[PURPOSE_SENSOR] + st->by_purpose[PURPOSE_UV];
  res->crossings += st->crossings;
  res->rays_created += st->created;
  res->rays_finished += st->finished;
  res->rays_spilled += st->spilled;
  if (st->peak_queue_bytes > res->peak_queue_bytes) res->peak_queue_bytes = st->peak_queue_bytes;
  if (st->peak_spill_bytes > res->peak_spill_bytes) res->peak_spill_bytes = st->peak_spill_bytes;
}

/* The camera pass's units are the image's tiles (vr_camera_generate reads
 * them with vr_flow_tile), whatever count the caller gives.  Image space
 * (--image-space) runs the same callbacks through the tile scheduler over
 * the scene's one cell; see vr/flow.h. */
vr_status vr_run_flow(run *r, rscene *rs, const vr_flow_ops *ops, pass_ctx *c, long units,
                      const char *name, vr_error *err) {
  return vr_run_flow_units(r, rs, ops, c, NULL, units, name, err);
}

vr_status vr_run_flow_units(run *r, rscene *rs, const vr_flow_ops *ops, pass_ctx *c,
                            const long *unit_list, long units, const char *name, vr_error *err) {
  vr_flow_stats st = {0};
  r->pass = name;
  /* Several ranks: all ready, and cells owned by the time the last run
   * spent in them. */
  vr_status s = vr_ranks_sync(r, VR_OK, err);
  if (!s && !r->opt->image_space) s = vr_ranks_assign(r, rs, err);
  if (s) return s;
  size_t maps = held(c);
  if (maps > r->res->peak_map_bytes) r->res->peak_map_bytes = maps;
  int S = vr_domains_count(rs->d);
  memset(rs->cell_ns, 0, (size_t)S * sizeof *rs->cell_ns);
  vr_flow_options o;
  vr_flow_options_default(&o);
  o.threads = r->opt->threads;
  o.image_space = r->opt->image_space;
  o.memory_budget = r->opt->memory_budget;
  o.held = held;
  o.hctx = c;
  o.spill_dir = r->opt->cache_dir;
  o.progress = progress_cb;
  o.pctx = r;
  o.comm = r->comm;
  o.owner = r->nranks > 1 && !r->opt->image_space ? rs->owner : NULL;
  o.send_batch = r->opt->send_batch;
  o.unit_list = unit_list;
  o.cell_ns = rs->cell_ns;
  s = vr_flow_run_with(rs->d, ops, c, units, &o, &st, err);
  if (r->nranks > 1) {
    if (r->opt->image_space) {
      /* Ranks finish image-space runs on their own: agree now. */
      s = vr_ranks_sync(r, s, err);
    } else if (s && !st.failure_shared) {
      /* The waves stopped every rank at once; the rank that failed tells
       * why (the others only know that it did). */
      vr_status a = vr_comm_agree(r->comm, st.other_rank_failed ? VR_OK : s, err);
      r->failure_agreed = true;
      if (a) s = a;
    } else if (s) {
      r->failure_agreed = true;
    }
  }
  maps = held(c);
  if (maps > r->res->peak_map_bytes) r->res->peak_map_bytes = maps;
  add_stats(r->res, &st);
  r->mine.rays_sent += st.sent, r->mine.rays_received += st.received;
  r->mine.messages += st.messages, r->mine.bytes_sent += st.bytes_sent;
  r->mine.waves += st.waves, r->mine.idle_seconds += st.idle_seconds;
  r->mine.rays_traced += st.traversals;
  for (int k = 0; k < S; k++) rs->cell_total_ns[k] += rs->cell_ns[k];
  return s;
}

/* Maps keep only the bins a photon's wavelengths fall in (at most nwl of
 * them), not all 10 nm bins of the range. */
vr_status vr_run_photon_pass(run *r, rscene *rs, pass_ctx *c, long photons, bool caustic,
                             bool global, bool direct, vr_error *err) {
  int nb = (int)ceil((rs->lmax - rs->lmin) / 10.0);
  if (nb < 1) nb = 1;
  /* One map per cell, positions about the scene's centre (vr/photon_set.h). */
  int S = vr_domains_count(rs->d);
  vr_photon_set **sets[3] = {&c->global, &c->direct, &c->caustic};
  bool want[3] = {global, direct, caustic};
  for (int i = 0; i < 3; i++) {
    if (!want[i]) continue;
    *sets[i] = vr_photon_set_create(S, nb, rs->lmin, rs->lmax, rs->nwl, rs->scene_centre, err);
    if (!*sets[i]) return err ? err->status : VR_E_NOMEM;
  }
  c->photons_per_unit = 1024;
  long units = (photons + c->photons_per_unit - 1) / c->photons_per_unit;
  c->photon_scale = 1.0 / (double)(units * c->photons_per_unit);
  vr_status st = vr_run_flow(r, rs, &vr_photon_ops, c, units, "photons", err);
  /* Each rank stored the photons that landed in its cells: every rank gets
   * them all, and builds the same maps as one process would. */
  if (!st) st = vr_ranks_share_photons(r, c, err);
  /* Building needs the staged photons and the built ones at once. */
  size_t staged = held(c);
  if (staged > r->res->peak_map_bytes) r->res->peak_map_bytes = staged;
  for (int i = 0; !st && i < 3; i++)
    if (*sets[i]) st = vr_photon_set_build(*sets[i], err);
  if (!st) {
    r->res->photons_global += c->global ? vr_photon_set_count(c->global) : 0;
    r->res->photons_direct += c->direct ? vr_photon_set_count(c->direct) : 0;
    r->res->photons_caustic += c->caustic ? vr_photon_set_count(c->caustic) : 0;
  }
  return st;
}

void vr_run_free_maps(pass_ctx *c) {
  vr_photon_set_destroy(c->global);
  vr_photon_set_destroy(c->direct);
  vr_photon_set_destroy(c->caustic);
  c->global = c->direct = c->caustic = NULL;
}
