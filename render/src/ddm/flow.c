/* The ray flow: per-cell queues, the workers that drain them, the counting
 * that tells when all work is done, and the image-space scheduler that
 * runs the same callbacks without queues (see vr/flow.h).
 *
 * Nothing shared is written once per ray.  Statistics are counted by each
 * worker in its own cache line and summed when the run ends; the count of
 * rays in flight is kept by reservation (see reserve below), so a worker
 * touches the shared counter once per CREDIT rays; queues are filled and
 * drained in batches of BATCH rays under their lock.  The queues themselves
 * (and their spill files) are in flow_queue.c, the choice of a cell (and
 * loading cells under a budget) in flow_sched.c. */
#include "ddm/flow_internal.h"
#include "ddm/ray_wire.h"
#include "vr/comm.h"
#include "vr/wire.h"

#include <math.h>
#include <sched.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define BATCH VR_FLOW_BATCH
#define LOW_WATER VR_FLOW_LOW_WATER
#define CREDIT VR_FLOW_CREDIT
#define LINE VR_FLOW_LINE

typedef vr_flow flow;
typedef vr_flow_queue queue;

int vr_flow_worker_index(const vr_flow_worker *w) { return w->index; }

long vr_flow_tiles(int width, int height) {
  if (width <= 0 || height <= 0) return 0;
  long tx = (width + VR_FLOW_TILE - 1) / VR_FLOW_TILE, ty = (height + VR_FLOW_TILE - 1) / VR_FLOW_TILE;
  return tx * ty;
}

void vr_flow_tile(int width, int height, long unit, int *x0, int *y0, int *x1, int *y1) {
  long tx = (width + VR_FLOW_TILE - 1) / VR_FLOW_TILE;
  if (tx < 1 || height < 1 || unit < 0) {
    *x0 = *y0 = *x1 = *y1 = 0; /* no pixels */
    return;
  }
  *x0 = (int)(unit % tx) * VR_FLOW_TILE;
  *y0 = (int)(unit / tx) * VR_FLOW_TILE;
  *x1 = *x0 + VR_FLOW_TILE < width ? *x0 + VR_FLOW_TILE : width;
  *y1 = *y0 + VR_FLOW_TILE < height ? *y0 + VR_FLOW_TILE : height;
}

/* Counting rays in flight without a shared update per ray.
 *
 * Each worker holds a credit c >= 0 that it has already added to
 * f->in_flight: a push spends one unit of it (reserving CREDIT more first
 * when it has none), a finish gives one back.  Summing over the workers,
 * f->in_flight = (rays in flight) + sum of credits, so f->in_flight is never
 * below the number of rays in flight, whoever pushed or finished them and
 * whenever the others last touched the counter.  Reading 0 therefore
 * proves that no ray exists anywhere (in a queue, in a push buffer, in a
 * worker's hands): the count a ray took at its push can only have been
 * handed back by the worker that finished it, after the finish, and the
 * counter's operations are sequentially consistent, so whoever reads 0
 * also sees those finishes (and the rays they pushed, which took their
 * count before).  A worker gives its credit back when it runs out of work,
 * so the count reaches 0 once every worker is out of work.  A worker that
 * finishes far more rays than it pushes (one that only traces what others
 * generate) returns its surplus above 2 CREDIT so the count does not drift
 * far above the truth. */
static void reserve(vr_flow_worker *w) {
  atomic_fetch_add(&w->f->in_flight, CREDIT);
  w->credit += CREDIT;
}

static void give_back(vr_flow_worker *w) {
  if (w->credit) atomic_fetch_sub(&w->f->in_flight, w->credit);
  w->credit = 0;
}

static void finish(vr_flow_worker *w, long n) {
  w->st.finished += (uint64_t)n;
  w->credit += n;
  if (w->credit > 2 * CREDIT) {
    atomic_fetch_sub(&w->f->in_flight, w->credit - CREDIT);
    w->credit = CREDIT;
  }
}

/* Hands n rays to cell c's queue; if neither memory nor disk can take
 * them they are lost, so they are counted finished and the run fails. */
static void put(vr_flow_worker *w, int c, const vr_ray *rays, int n) {
  vr_flow *f = w->f;
  if (f->net) atomic_fetch_add_explicit(&f->put_rays, n, memory_order_relaxed);
  int dest = vr_flow_route(f, c, n);
  if (dest == f->rank ? vr_flow_queue_put(f, c, rays, n, w) : vr_flow_net_put(f, dest, rays, n))
    return;
  w->oom = true;
  atomic_store(&w->f->failed, 1);
  finish(w, n);
}

static void flush(vr_flow_worker *w) {
  if (!w->nout) return;
  for (int c = 0; c < w->f->ncells; c++) {
    if (w->nout[c]) put(w, c, w->out + (size_t)c * w->f->batch, w->nout[c]);
    w->nout[c] = 0;
  }
}

/* Profile: a ray from the worker's cell (or its unit) into cell c. */
static void note_move(vr_flow_worker *w, int c) {
  vr_flow_profile *p = w->f->profile;
  int from = w->cur >= 0 ? w->cur : p->ncells;
  atomic_fetch_add_explicit(&p->moves[(size_t)from * (size_t)p->ncells + (size_t)c], 1,
                            memory_order_relaxed);
}

/* Queues r for cell c (the ray's tnear and cell already set). */
static void enqueue(vr_flow_worker *w, const vr_ray *r) {
  int c = r->cell, b = w->f->batch;
  if (w->f->profile) note_move(w, c);
  w->out[(size_t)c * b + (size_t)w->nout[c]++] = *r;
  if (w->nout[c] == b) {
    put(w, c, w->out + (size_t)c * b, b);
    w->nout[c] = 0;
  }
}

/* Image space: the free slot on top of the worker's own stack, or NULL
 * when it cannot grow. */
static vr_ray *stack_slot(vr_flow_worker *w) {
  if (w->top == w->cap) {
    size_t cap = w->cap ? 2 * w->cap : 1024;
    vr_ray *s = realloc(w->stack, cap * sizeof *s);
    if (!s) return NULL;
    w->stack = s;
    w->cap = cap;
  }
  return &w->stack[w->top];
}

void vr_flow_push(vr_flow_worker *w, const vr_ray *r0) {
  flow *f = w->f;
  /* The cell is the rounded ray's (vr_ray_round). */
  double org[3], dir[3], te;
  for (int a = 0; a < 3; a++) {
    org[a] = vr_wire_round(r0->org[a]);
    dir[a] = vr_wire_round(r0->dir[a]);
  }
  int c = vr_domains_locate(f->d, org, dir, vr_wire_round(r0->tnear), &te);
  if (w->credit == 0) reserve(w);
  w->credit--;
  w->st.created++;
  if (r0->kind == VR_RAY_SHADOW)
    w->st.shadow++;
  else
    w->st.closest++;
  w->st.by_purpose[r0->purpose & 7]++;
  if (f->profile && !f->image_space) note_move(w, c);
  /* Copied once, straight to where it waits, and rounded there. */
  vr_ray *r = f->image_space ? stack_slot(w) : &w->out[(size_t)c * f->batch + (size_t)w->nout[c]];
  if (!r) {
    /* The stack cannot grow: the ray is lost, the run fails. */
    w->oom = true;
    atomic_store(&f->failed, 1);
    finish(w, 1);
    return;
  }
  *r = *r0;
  vr_ray_round(r);
  if (f->ops->round) f->ops->round(f->ctx, r->payload);
  r->cell = c;
  r->crossings = 0;
  if (f->image_space) {
    w->top++;
  } else if (++w->nout[c] == f->batch) {
    put(w, c, w->out + (size_t)c * f->batch, f->batch);
    w->nout[c] = 0;
  }
}

/* Traces r from its cell on.  In the queued flow a ray that leaves the
 * cell is queued for the next one and the call returns; in image space
 * (walk) the worker follows it into the next cell itself. */
static void trace(vr_flow_worker *w, vr_ray *r, bool walk) {
  flow *f = w->f;
  for (;;) {
    double t_exit;
    int c = vr_domains_locate(f->d, r->org, r->dir, r->tnear, &t_exit);
    double tfar = t_exit < r->tmax ? t_exit : r->tmax;
    if (c != r->cell) {
      /* Hand-over: the ray entered another cell at tnear (the interface). */
      r->cell = c;
      r->crossings++;
      w->st.crossings++;
      /* A cell whose primitives the segment cannot meet is crossed here
       * and now: its queue (and loading it) would gain nothing. */
      if (!vr_domains_may_hit(f->d, c, r->org, r->dir, r->tnear, tfar)) {
        w->st.skipped++;
        if (t_exit >= r->tmax || isinf(t_exit)) goto escaped;
        r->tnear = t_exit;
        continue;
      }
      /* The ray goes on here when the worker walks (image space) or the
       * cell is loaded for the whole run; else it waits in the cell's
       * queue (or goes to a rank that holds the cell). */
      if (!walk && !(f->walk_loaded && vr_domains_loaded(f->d, c))) {
        enqueue(w, r);
        return;
      }
    }
    vr_hit hit;
    w->st.traversals++;
    bool got = vr_domains_intersect(f->d, c, r->org, r->dir, r->tnear, tfar, &hit);
    if (got) {
      if (r->kind == VR_RAY_CLOSEST) {
        f->ops->closest(f->ctx, w, r, &hit);
        finish(w, 1);
        return;
      }
      if (!f->ops->shadow_hit(f->ctx, w, r, &hit)) {
        f->ops->shadow_done(f->ctx, w, r, false);
        finish(w, 1);
        return;
      }
      if (f->ops->round) f->ops->round(f->ctx, r->payload);
      /* Past a thin element: go on just beyond it, in float steps, so the
       * same surface is not met again. */
      double t = hit.t;
      double step = fmax(1e-6 * fabs(t), 1e-7);
      r->tnear = t + step;
      if (r->tnear >= r->tmax) {
        f->ops->shadow_done(f->ctx, w, r, true);
        finish(w, 1);
        return;
      }
      continue;
    }
    if (t_exit >= r->tmax || isinf(t_exit)) goto escaped;
    r->tnear = t_exit;
  }
escaped:
  if (r->kind == VR_RAY_CLOSEST)
    f->ops->closest(f->ctx, w, r, NULL);
  else
    f->ops->shadow_done(f->ctx, w, r, true);
  finish(w, 1);
}

/* This rank's k-th unit: every nranks-th index of the run from its rank,
 * through the run's unit list if it has one. */
static long unit_of(const flow *f, long k) {
  long i = f->rank + k * f->nranks;
  return f->unit_list ? f->unit_list[i] : i;
}

static double clock_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void report_progress(flow *f) {
  if (!f->progress) return;
  if (pthread_mutex_trylock(&f->progress_lock) != 0) return;
  f->progress(f->pctx, atomic_load(&f->done_units), f->units);
  pthread_mutex_unlock(&f->progress_lock);
}

/* A worker with nothing to trace since idle_since found work: the time
 * counts as idle, but for the loads it did meanwhile (ahead of rays). */
static void end_idle(vr_flow_worker *w, double *idle_since) {
  if (*idle_since <= 0) return;
  double t = clock_s() - *idle_since - w->loads_since_idle;
  if (t > 0) w->st.idle_seconds += t;
  *idle_since = 0;
}

static void *queued_worker(vr_flow_worker *w) {
  flow *f = w->f;
  vr_ray batch[BATCH];
  int idle = 0;
  double idle_since = 0;
  for (;;) {
    if (atomic_load_explicit(&f->failed, memory_order_relaxed)) break;
    long waiting = atomic_load_explicit(&f->queued, memory_order_relaxed) +
                   atomic_load_explicit(&f->outbox_rays, memory_order_relaxed) +
                   atomic_load_explicit(&f->generating, memory_order_relaxed);
    /* Room for a whole unit's rays below the cap (a unit's size, the most
     * one has made so far, grows with the spp up to the camera's wave),
     * counting the units other workers are generating: the queues' peak is
     * the cap whatever the spp (for units up to half the cap; two workers
     * that both find the queues empty may still start together).  Before
     * any unit is done its size is unknown and half the cap is reserved.
     * A unit larger than half the cap (a sensor point's batch of many
     * paths) reserves half, so that the next one overlaps the last one's
     * tail instead of waiting for empty queues: such units may pass the
     * cap by what they hold beyond half of it. */
    long unit_rays = atomic_load_explicit(&f->unit_rays, memory_order_relaxed);
    if (unit_rays == 0 || unit_rays > f->max_pending / 2) unit_rays = f->max_pending / 2;
    bool low = (waiting == 0 || waiting + unit_rays < f->max_pending) &&
               (!f->budget || vr_flow_loaded_pending(f) < f->low_water);
    long u = -1;
    if (low && atomic_load_explicit(&f->next_unit, memory_order_relaxed) < f->units) {
      u = atomic_fetch_add(&f->next_unit, 1);
      if (u >= f->units) u = -1;
    }
    if (u >= 0) {
      atomic_fetch_add_explicit(&f->generating, unit_rays, memory_order_relaxed);
      end_idle(w, &idle_since);
      double tg = f->profile ? clock_s() : 0;
      w->cur = -1;
      long made = w->st.created;
      f->ops->generate(f->ctx, w, unit_of(f, u));
      made = w->st.created - made;
      for (long m = atomic_load_explicit(&f->unit_rays, memory_order_relaxed);
           made > m && !atomic_compare_exchange_weak(&f->unit_rays, &m, made);)
        ;
      flush(w);
      atomic_fetch_sub_explicit(&f->generating, unit_rays, memory_order_relaxed);
      if (f->profile) {
        atomic_fetch_add(&f->profile->gen_ns, (uint64_t)((clock_s() - tg) * 1e9));
        atomic_fetch_add(&f->profile->units, 1);
      }
      atomic_fetch_add(&f->done_units, 1);
      report_progress(f);
      if (f->net) vr_flow_net_progress(f);
      continue;
    }
    int c = vr_flow_sched_pick(f, w);
    if (c >= 0) {
      double t0 = clock_s();
      end_idle(w, &idle_since);
      int n = vr_flow_queue_take(f, c, batch, w);
      atomic_fetch_add_explicit(&f->traced[c], (unsigned long long)n, memory_order_relaxed);
      if (f->profile) {
        /* Each ray timed: its cell's cost by kind, for the model. */
        w->cur = c;
        vr_flow_profile *p = f->profile;
        for (int i = 0; i < n; i++) {
          int k = batch[i].kind == VR_RAY_SHADOW;
          double tr = clock_s();
          trace(w, &batch[i], false);
          atomic_fetch_add_explicit(&p->ns[k][c], (uint64_t)((clock_s() - tr) * 1e9),
                                    memory_order_relaxed);
          atomic_fetch_add_explicit(&p->rays[k][c], 1, memory_order_relaxed);
        }
        w->cur = -1;
      } else {
        for (int i = 0; i < n; i++) trace(w, &batch[i], false);
      }
      vr_flow_sched_release(f, c);
      flush(w);
      atomic_fetch_add_explicit(&f->cell_ns[c], (unsigned long long)((clock_s() - t0) * 1e9),
                                memory_order_relaxed);
      if (f->net) vr_flow_net_progress(f);
      idle = 0;
      continue;
    }
    if (idle_since == 0) {
      idle_since = clock_s();
      w->loads_since_idle = 0;
    }
    /* Out of work, with every ray of ours flushed: give the credit back,
     * then the run is over when every unit has been generated (a unit
     * being generated is not yet done) and the count, which is never below
     * the rays in flight, is 0.  Otherwise another worker still holds rays
     * that will reach the queues. */
    give_back(w);
    if (f->net) {
      /* Rays may still come from other ranks: the waves decide. */
      if (atomic_load(&f->terminated)) break;
      if (vr_flow_net_progress(f)) {
        idle = 0;
        continue;
      }
    } else if (atomic_load(&f->done_units) >= f->units && atomic_load(&f->in_flight) == 0) {
      break;
    }
    /* Others hold the work (or load a cell, or the rays are on another
     * rank): yield a few times, then sleep until rays are queued here, so
     * that a waiting worker costs no core (on a machine shared by ranks,
     * a spinning worker would slow the busy one). */
    if (++idle < 8) {
      sched_yield();
    } else {
      pthread_mutex_lock(&f->idle_lock);
      atomic_fetch_add(&f->sleepers, 1);
      struct timespec until;
      clock_gettime(CLOCK_REALTIME, &until);
      until.tv_nsec += 1000000;
      if (until.tv_nsec >= 1000000000) until.tv_sec++, until.tv_nsec -= 1000000000;
      pthread_cond_timedwait(&f->idle_cv, &f->idle_lock, &until);
      atomic_fetch_sub(&f->sleepers, 1);
      pthread_mutex_unlock(&f->idle_lock);
    }
  }
  end_idle(w, &idle_since);
  flush(w);
  give_back(w);
  return NULL;
}

/* Image space: each unit is traced to the end by the worker that claimed
 * it, depth first on its private stack: pop the newest ray, trace it
 * through the whole scene, and what its callbacks push lands on top.  The
 * stack therefore holds at most the rays the unit itself made plus, for
 * the one path being followed, the rays each of its vertices spawned
 * beside the one followed (shadow rays to the lights, final-gather rays):
 * path depth times branching, whatever the image size or the number of
 * threads.  No ray is shared, so the run ends when the units run out and
 * every worker has emptied its stack. */
static void *image_space_worker(vr_flow_worker *w) {
  flow *f = w->f;
  for (;;) {
    if (atomic_load_explicit(&f->failed, memory_order_relaxed)) break;
    long u = atomic_fetch_add(&f->next_unit, 1);
    if (u >= f->units) break;
    f->ops->generate(f->ctx, w, unit_of(f, u));
    while (w->top > 0) {
      vr_ray r = w->stack[--w->top];
      trace(w, &r, true);
    }
    atomic_fetch_add(&f->done_units, 1);
    report_progress(f);
  }
  give_back(w);
  return NULL;
}

static void *worker_main(void *arg) {
  vr_flow_worker *w = arg;
  return w->f->image_space ? image_space_worker(w) : queued_worker(w);
}

static void *alloc_lines(size_t n, size_t size) {
  size_t bytes = (n * size + LINE - 1) / LINE * LINE;
  void *p = aligned_alloc(LINE, bytes ? bytes : LINE);
  if (p) memset(p, 0, bytes ? bytes : LINE);
  return p;
}

static void add_stats(vr_flow_stats *to, const vr_flow_stats *s) {
  to->created += s->created;
  to->finished += s->finished;
  to->crossings += s->crossings;
  to->closest += s->closest;
  to->shadow += s->shadow;
  to->traversals += s->traversals;
  to->spilled += s->spilled;
  to->skipped += s->skipped;
  to->idle_seconds += s->idle_seconds;
  for (int i = 0; i < 8; i++) to->by_purpose[i] += s->by_purpose[i];
}

vr_flow_profile *vr_flow_profile_create(int ncells) {
  vr_flow_profile *p = calloc(1, sizeof *p);
  if (!p) return NULL;
  p->ncells = ncells;
  p->moves = calloc((size_t)(ncells + 1) * (size_t)ncells, sizeof *p->moves);
  for (int k = 0; k < 2; k++) {
    p->rays[k] = calloc((size_t)ncells, sizeof *p->rays[k]);
    p->ns[k] = calloc((size_t)ncells, sizeof *p->ns[k]);
  }
  if (!p->moves || !p->rays[0] || !p->rays[1] || !p->ns[0] || !p->ns[1]) {
    vr_flow_profile_destroy(p);
    return NULL;
  }
  return p;
}

void vr_flow_profile_destroy(vr_flow_profile *p) {
  if (!p) return;
  free(p->moves);
  for (int k = 0; k < 2; k++) free(p->rays[k]), free(p->ns[k]);
  free(p);
}

void vr_flow_options_default(vr_flow_options *o) {
  memset(o, 0, sizeof *o);
  o->threads = 1;
}

static vr_status run(vr_domains *d, const vr_flow_ops *ops, void *ctx, long units,
                     const vr_flow_options *o, bool image_space, vr_flow_stats *stats,
                     vr_error *err) {
  int threads = o->threads;
  if (threads < 1 || threads > VR_MAX_THREADS)
    return vr_error_set(err, VR_E_ARG, "threads = %d, expected 1 to %d", threads, VR_MAX_THREADS);
  flow f = {.d = d, .ops = ops, .ctx = ctx, .all_units = units, .image_space = image_space,
            .progress = o->progress, .pctx = o->pctx, .threads = threads, .batch = BATCH,
            .budget = o->memory_budget, .spill_dir = o->spill_dir, .held = o->held,
            .hctx = o->hctx, .unit_list = o->unit_list, .rss_base = o->rss_base,
            .profile = o->profile};
  f.ncells = vr_domains_count(d);
  f.rank = vr_comm_rank(o->comm);
  f.nranks = vr_comm_size(o->comm);
  /* This rank's share of the units: indices rank, rank + R, ... */
  f.units = units > f.rank ? (units - f.rank + f.nranks - 1) / f.nranks : 0;
  f.max_pending = o->max_pending > 0 ? o->max_pending
                  : f.budget         ? VR_FLOW_BUDGET_PENDING
                                     : LOW_WATER;
  pthread_mutex_init(&f.progress_lock, NULL);
  pthread_mutex_init(&f.sched_lock, NULL);
  pthread_mutex_init(&f.pool_lock, NULL);
  pthread_mutex_init(&f.idle_lock, NULL);
  pthread_cond_init(&f.idle_cv, NULL);
  f.q = image_space ? NULL : alloc_lines((size_t)f.ncells, sizeof *f.q);
  f.pins = calloc((size_t)f.ncells, sizeof *f.pins);
  f.traced = calloc((size_t)f.ncells, sizeof *f.traced);
  f.cell_ns = calloc((size_t)f.ncells, sizeof *f.cell_ns);
  f.loading = calloc((size_t)f.ncells, sizeof *f.loading);
  bool ranks = f.nranks > 1 && !image_space;
  f.held_by = ranks ? calloc((size_t)f.ncells * (size_t)f.nranks, sizeof *f.held_by) : NULL;
  f.routed = ranks ? calloc((size_t)f.ncells, sizeof *f.routed) : NULL;
  f.prefetch_left = ranks ? calloc((size_t)f.nranks, sizeof *f.prefetch_left) : NULL;
  f.adopt_rays = VR_FLOW_ADOPT_RAYS;
  f.lazy = ranks && !f.budget;
  f.walk_loaded = !f.budget && !f.profile;
  vr_flow_worker *ws = alloc_lines((size_t)threads, sizeof *ws);
  pthread_t *tids = calloc((size_t)threads, sizeof *tids);
  vr_status st = VR_OK;
  for (int c = 0; f.q && c < f.ncells; c++) vr_flow_queue_init(&f.q[c]);
  if ((!image_space && !f.q) || !ws || !tids || !f.pins || !f.loading || !f.traced ||
      !f.cell_ns || (ranks && (!f.held_by || !f.routed || !f.prefetch_left))) {
    st = vr_error_set(err, VR_E_NOMEM, "ray flow: out of memory");
    goto done;
  }
  if (f.profile && (image_space || f.profile->ncells != f.ncells)) {
    st = vr_error_set(err, VR_E_ARG, "ray flow: a profile is for the queued flow over the same cells");
    goto done;
  }
  if (f.budget && image_space) {
    st = vr_error_set(err, VR_E_ARG,
                      "image space keeps the whole scene in every thread; it cannot run under a "
                      "memory budget");
    goto done;
  }
  if (f.budget) {
    st = vr_flow_budget_plan(&f, err);
  } else if (f.lazy) {
    /* Several ranks, no budget: each loads the cells its rays need, when
     * they need them (ddm/flow_net.c), and keeps them. */
    f.cells_cap = f.queue_cap = (size_t)-1 / 4;
    f.low_water = LOW_WATER;
  } else {
    /* One process, no budget: every cell loaded, all along. */
    for (int c = 0; !st && c < f.ncells; c++) st = vr_domains_load(d, c, err);
  }
  if (ranks) {
    /* Every rank must be ready before any waits for the others' waves. */
    st = vr_comm_agree(o->comm, st, err);
    if (st && stats) stats->failure_shared = true;
    if (!st) st = vr_flow_net_start(&f, o->comm, o->send_batch, o->send_credit, err);
  }
  if (st) goto done;
  f.block_bytes = sizeof(vr_flow_block) + (size_t)f.batch * sizeof(vr_ray);
  if (f.budget) {
    size_t buffers = (size_t)threads * (size_t)f.ncells * (size_t)f.batch * sizeof(vr_ray);
    f.max_blocks = f.queue_cap > buffers ? (f.queue_cap - buffers) / f.block_bytes : 0;
    if (f.max_blocks < 1) f.max_blocks = 1;
  }
  for (int i = 0; i < threads; i++) {
    ws[i].f = &f;
    ws[i].index = i;
    ws[i].cur = -1;
    if (image_space) continue;
    ws[i].out = malloc((size_t)f.ncells * (size_t)f.batch * sizeof(vr_ray));
    ws[i].nout = calloc((size_t)f.ncells, sizeof(int));
    if (!ws[i].out || !ws[i].nout) {
      st = vr_error_set(err, VR_E_NOMEM, "ray flow: out of memory");
      goto done;
    }
    vr_flow_note_bytes(&f.queue_bytes, &f.peak_queue_bytes,
                       (long long)((size_t)f.ncells * (size_t)f.batch * sizeof(vr_ray)));
  }
  int started = 0;
  for (int i = 1; i < threads; i++) {
    if (pthread_create(&tids[i], NULL, worker_main, &ws[i]) != 0) break;
    started = i;
  }
  worker_main(&ws[0]);
  for (int i = 1; i <= started; i++) pthread_join(tids[i], NULL);
  vr_flow_stats net_stats = {0};
  vr_flow_net_stop(&f, &net_stats);
  if (atomic_load(&f.failed)) {
    if (f.fail_err.status)
      st = vr_error_set(err, f.fail_err.status, "%s", f.fail_err.message);
    else
      st = vr_error_set(err, VR_E_NOMEM, "ray flow: out of memory in a %s",
                        image_space ? "worker's ray stack" : "queue (and its spill file)");
  }
  if (f.progress) f.progress(f.pctx, atomic_load(&f.done_units), f.units);
  if (stats) {
    memset(stats, 0, sizeof *stats);
    for (int i = 0; i < threads; i++) add_stats(stats, &ws[i].st);
    stats->sent = net_stats.sent, stats->received = net_stats.received;
    stats->messages = net_stats.messages, stats->bytes_sent = net_stats.bytes_sent;
    stats->waves = net_stats.waves, stats->spilled += net_stats.spilled;
    stats->credit_waits = net_stats.credit_waits;
    stats->ray_messages = net_stats.ray_messages, stats->ray_bytes = net_stats.ray_bytes;
    stats->peak_uncredited = net_stats.peak_uncredited;
    stats->other_rank_failed = net_stats.other_rank_failed;
    stats->peak_queue_bytes = (size_t)atomic_load(&f.peak_queue_bytes);
    stats->peak_spill_bytes = (size_t)atomic_load(&f.peak_spill_bytes);
    stats->peak_uncounted_bytes = f.peak_uncounted;
  }
done:
  for (int i = 0; ws && i < threads; i++) {
    free(ws[i].out);
    free(ws[i].nout);
    free(ws[i].stack);
  }
  for (int c = 0; f.q && c < f.ncells; c++) vr_flow_queue_free(&f, &f.q[c]);
  vr_flow_pool_free(&f);
  free(f.q);
  free(f.pins);
  free(f.traced);
  if (o->cell_ns)
    for (int c = 0; f.cell_ns && c < f.ncells; c++) o->cell_ns[c] += atomic_load(&f.cell_ns[c]);
  free(f.cell_ns);
  free(f.loading);
  free(f.held_by);
  free(f.routed);
  free(f.prefetch_left);
  pthread_mutex_destroy(&f.progress_lock);
  pthread_mutex_destroy(&f.sched_lock);
  pthread_mutex_destroy(&f.pool_lock);
  pthread_mutex_destroy(&f.idle_lock);
  pthread_cond_destroy(&f.idle_cv);
  free(ws);
  free(tids);
  return st;
}

vr_status vr_flow_run_with(vr_domains *d, const vr_flow_ops *ops, void *ctx, long units,
                           const vr_flow_options *o, vr_flow_stats *stats, vr_error *err) {
  return run(d, ops, ctx, units, o, o->image_space, stats, err);
}

vr_status vr_flow_run(vr_domains *d, const vr_flow_ops *ops, void *ctx, long units,
                      int threads, void (*progress)(void *, long, long), void *pctx,
                      vr_flow_stats *stats, vr_error *err) {
  vr_flow_options o;
  vr_flow_options_default(&o);
  o.threads = threads;
  o.progress = progress;
  o.pctx = pctx;
  return run(d, ops, ctx, units, &o, false, stats, err);
}

vr_status vr_flow_run_image_space(vr_domains *d, const vr_flow_ops *ops, void *ctx,
                                  long units, int threads,
                                  void (*progress)(void *, long, long), void *pctx,
                                  vr_flow_stats *stats, vr_error *err) {
  vr_flow_options o;
  vr_flow_options_default(&o);
  o.threads = threads;
  o.progress = progress;
  o.pctx = pctx;
  return run(d, ops, ctx, units, &o, true, stats, err);
}
