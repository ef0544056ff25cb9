/* Running passes: logging, records, and the ray flow with its statistics
 * (run.h). */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "run/run.h"
#include "vr/comm.h"

double vr_run_now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

void vr_run_say(const vr_run *r, const char *fmt, ...) {
  if (!r->opt->log) return;
  char line[512];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(line, sizeof line, fmt, ap);
  va_end(ap);
  r->opt->log(r->opt->user, line);
}

vr_pass_record *vr_run_record(vr_run *r, const char *name, bool ran, const char *fmt, ...) {
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
  vr_run *r = u;
  if (r->opt->progress) r->opt->progress(r->opt->user, r->pass, done, total);
}

/* What the render holds besides cells and queues: the state maps, the
 * film, the textures (loaded whole on every rank), and what the
 * integrator in charge holds (photon maps, growing while a photon pass
 * fills them). */
static size_t held(void *u) {
  const vr_run *r = u;
  return vr_rscene_map_bytes(r->rs) + r->film_bytes + r->rs->tex_bytes +
         (r->held ? r->held(r->held_ctx) : 0);
}

void vr_run_note_held(vr_run *r) {
  size_t b = held(r);
  if (b > r->res->peak_map_bytes) r->res->peak_map_bytes = b;
}

static void add_stats(vr_render_result *res, const vr_flow_stats *st) {
  res->rays_camera += st->by_purpose[VR_PURPOSE_CAMERA] + st->by_purpose[VR_PURPOSE_GATHER];
  res->rays_shadow += st->by_purpose[VR_PURPOSE_SHADOW];
  res->rays_photon += st->by_purpose[VR_PURPOSE_PHOTON];
  res->rays_other += st->by_purpose[VR_PURPOSE_SENSOR] + st->by_purpose[VR_PURPOSE_UV];
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
vr_status vr_run_flow(vr_run *r, const vr_flow_ops *ops, void *ctx, long units, const char *name,
                      vr_error *err) {
  return vr_run_flow_units(r, ops, ctx, NULL, units, name, err);
}

vr_status vr_run_flow_units(vr_run *r, const vr_flow_ops *ops, void *ctx, const long *unit_list,
                            long units, const char *name, vr_error *err) {
  vr_rscene *rs = r->rs;
  vr_flow_stats st = {0};
  r->pass = name;
  /* Several ranks: all ready. */
  vr_status s = vr_ranks_sync(r, VR_OK, err);
  if (s) return s;
  vr_run_note_held(r);
  int S = vr_domains_count(rs->d);
  memset(rs->cell_ns, 0, (size_t)S * sizeof *rs->cell_ns);
  vr_flow_options o;
  vr_flow_options_default(&o);
  o.threads = r->opt->threads;
  o.image_space = r->opt->image_space;
  o.memory_budget = r->opt->memory_budget;
  o.held = held;
  o.hctx = r;
  o.rss_base = r->rss_base;
  o.spill_dir = r->opt->cache_dir;
  o.progress = progress_cb;
  o.pctx = r;
  o.comm = r->comm;
  o.send_batch = r->opt->send_batch;
  o.send_credit = r->opt->send_credit;
  o.unit_list = unit_list;
  o.cell_ns = rs->cell_ns;
  vr_render_result *res = r->res;
  if (r->opt->flow_profile && !r->opt->image_space && res->nprofiles < VR_MAX_PASSES) {
    o.profile = vr_flow_profile_create(S);
    if (!o.profile) return vr_error_set(err, VR_E_NOMEM, "out of memory");
    snprintf(res->profiles[res->nprofiles].name, sizeof res->profiles[0].name, "%s", name);
    res->profiles[res->nprofiles++].p = o.profile;
  }
  s = vr_flow_run_with(rs->d, ops, ctx, units, &o, &st, err);
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
  vr_run_note_held(r);
  add_stats(r->res, &st);
  r->mine.rays_sent += st.sent, r->mine.rays_received += st.received;
  r->mine.messages += st.messages, r->mine.bytes_sent += st.bytes_sent;
  r->mine.waves += st.waves, r->mine.idle_seconds += st.idle_seconds;
  r->mine.credit_waits += st.credit_waits;
  r->mine.ray_messages += st.ray_messages, r->mine.ray_bytes_sent += st.ray_bytes;
  if (st.peak_uncounted_bytes > r->res->peak_uncounted_bytes)
    r->res->peak_uncounted_bytes = st.peak_uncounted_bytes;
  if (st.peak_uncredited > r->mine.peak_uncredited) r->mine.peak_uncredited = st.peak_uncredited;
  if (st.peak_queue_bytes > r->mine.peak_queue_bytes) r->mine.peak_queue_bytes = st.peak_queue_bytes;
  r->mine.rays_traced += st.traversals;
  for (int k = 0; k < S; k++) rs->cell_total_ns[k] += rs->cell_ns[k];
  return s;
}

