/* The ray flow: per-cell queues, the workers that drain them, and the
 * counting that tells when all work is done (see vr/flow.h). */
#include "vr/flow.h"

#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

/* A worker pushes into a private buffer per cell and hands it to the cell's
 * queue in one locked step when it is full or when the worker moves on, so
 * the locks are taken once per batch, not once per ray. */
#define BATCH 256
/* Generate more work only while fewer rays than this wait in the queues:
 * it bounds memory whatever the image size. */
#define LOW_WATER 65536

typedef struct queue {
  pthread_mutex_t lock;
  vr_ray *rays;
  size_t n, cap;
  _Atomic long pending; /* = n, readable without the lock to choose a cell */
} queue;

typedef struct flow {
  const vr_domains *d;
  const vr_flow_ops *ops;
  void *ctx;
  int ncells;
  queue *q;
  long units;
  _Atomic long next_unit, done_units;
  _Atomic long in_flight, queued;
  _Atomic uint64_t created, finished, crossings, closest, shadow, traversals;
  _Atomic uint64_t by_purpose[8];
  _Atomic int failed;
  pthread_mutex_t progress_lock;
  void (*progress)(void *, long, long);
  void *pctx;
} flow;

struct vr_flow_worker {
  flow *f;
  int index;
  vr_ray *out;      /* BATCH rays per cell */
  int *nout;        /* per cell */
  bool oom;
};

int vr_flow_worker_index(const vr_flow_worker *w) { return w->index; }

static void queue_put(flow *f, int c, const vr_ray *rays, int n, vr_flow_worker *w) {
  queue *q = &f->q[c];
  pthread_mutex_lock(&q->lock);
  if (q->n + (size_t)n > q->cap) {
    size_t cap = q->cap ? q->cap : 1024;
    while (cap < q->n + (size_t)n) cap *= 2;
    vr_ray *r = realloc(q->rays, cap * sizeof *r);
    if (!r) {
      pthread_mutex_unlock(&q->lock);
      w->oom = true;
      atomic_store(&f->failed, 1);
      /* The rays are lost: count them finished so the run still ends. */
      atomic_fetch_sub(&f->in_flight, n);
      atomic_fetch_add(&f->finished, (uint64_t)n);
      return;
    }
    q->rays = r;
    q->cap = cap;
  }
  memcpy(q->rays + q->n, rays, (size_t)n * sizeof *rays);
  q->n += (size_t)n;
  atomic_fetch_add(&q->pending, n);
  atomic_fetch_add(&f->queued, n);
  pthread_mutex_unlock(&q->lock);
}

static void flush(vr_flow_worker *w) {
  for (int c = 0; c < w->f->ncells; c++) {
    if (w->nout[c]) queue_put(w->f, c, w->out + (size_t)c * BATCH, w->nout[c], w);
    w->nout[c] = 0;
  }
}

/* Queues r for cell c (the ray's tnear and cell already set). */
static void enqueue(vr_flow_worker *w, const vr_ray *r) {
  int c = r->cell;
  w->out[(size_t)c * BATCH + (size_t)w->nout[c]++] = *r;
  if (w->nout[c] == BATCH) {
    queue_put(w->f, c, w->out + (size_t)c * BATCH, BATCH, w);
    w->nout[c] = 0;
  }
}

void vr_flow_push(vr_flow_worker *w, const vr_ray *r0) {
  flow *f = w->f;
  vr_ray r = *r0;
  double te;
  r.cell = vr_domains_locate(f->d, r.org, r.dir, r.tnear, &te);
  r.crossings = 0;
  atomic_fetch_add(&f->in_flight, 1);
  atomic_fetch_add(&f->created, 1);
  atomic_fetch_add(r.kind == VR_RAY_SHADOW ? &f->shadow : &f->closest, 1);
  atomic_fetch_add(&f->by_purpose[r.purpose & 7], 1);
  enqueue(w, &r);
}

static void finish(flow *f) {
  atomic_fetch_add(&f->finished, 1);
  atomic_fetch_sub(&f->in_flight, 1);
}

/* Traces r inside its cell; returns true if it moved on to another cell
 * (and was queued there). */
static void trace_in_cell(vr_flow_worker *w, vr_ray *r) {
  flow *f = w->f;
  for (;;) {
    double t_exit;
    int c = vr_domains_locate(f->d, r->org, r->dir, r->tnear, &t_exit);
    if (c != r->cell) {
      /* Hand-over: the ray entered another cell at tnear (the interface). */
      r->cell = c;
      r->crossings++;
      atomic_fetch_add(&f->crossings, 1);
      enqueue(w, r);
      return;
    }
    double tfar = t_exit < r->tmax ? t_exit : r->tmax;
    vr_hit hit;
    atomic_fetch_add(&f->traversals, 1);
    bool got = vr_domains_intersect(f->d, c, r->org, r->dir, r->tnear, tfar, &hit);
    if (got) {
      if (r->kind == VR_RAY_CLOSEST) {
        f->ops->closest(f->ctx, w, r, &hit);
        finish(f);
        return;
      }
      if (!f->ops->shadow_hit(f->ctx, w, r, &hit)) {
        f->ops->shadow_done(f->ctx, w, r, false);
        finish(f);
        return;
      }
      /* Past a thin element: go on just beyond it, in float steps, so the
       * same surface is not met again. */
      double t = hit.t;
      double step = fmax(1e-6 * fabs(t), 1e-7);
      r->tnear = t + step;
      if (r->tnear >= r->tmax) {
        f->ops->shadow_done(f->ctx, w, r, true);
        finish(f);
        return;
      }
      continue;
    }
    if (t_exit >= r->tmax || isinf(t_exit)) {
      if (r->kind == VR_RAY_CLOSEST)
        f->ops->closest(f->ctx, w, r, NULL);
      else
        f->ops->shadow_done(f->ctx, w, r, true);
      finish(f);
      return;
    }
    r->tnear = t_exit;
  }
}

/* The cell with the most pending rays, or -1. */
static int busiest(flow *f) {
  int best = -1;
  long most = 0;
  for (int c = 0; c < f->ncells; c++) {
    long p = atomic_load(&f->q[c].pending);
    if (p > most) {
      most = p;
      best = c;
    }
  }
  return best;
}

static int take(flow *f, int c, vr_ray *batch) {
  queue *q = &f->q[c];
  pthread_mutex_lock(&q->lock);
  int n = q->n < BATCH ? (int)q->n : BATCH;
  q->n -= (size_t)n;
  memcpy(batch, q->rays + q->n, (size_t)n * sizeof *batch);
  atomic_fetch_sub(&q->pending, n);
  atomic_fetch_sub(&f->queued, n);
  pthread_mutex_unlock(&q->lock);
  return n;
}

static void report_progress(flow *f) {
  if (!f->progress) return;
  if (pthread_mutex_trylock(&f->progress_lock) != 0) return;
  f->progress(f->pctx, atomic_load(&f->done_units), f->units);
  pthread_mutex_unlock(&f->progress_lock);
}

static void *worker_main(void *arg) {
  vr_flow_worker *w = arg;
  flow *f = w->f;
  vr_ray batch[BATCH];
  for (;;) {
    if (atomic_load(&f->failed)) break;
    bool low = atomic_load(&f->queued) < LOW_WATER;
    long u = -1;
    if (low && atomic_load(&f->next_unit) < f->units) {
      u = atomic_fetch_add(&f->next_unit, 1);
      if (u >= f->units) u = -1;
    }
    if (u >= 0) {
      f->ops->generate(f->ctx, w, u);
      flush(w);
      atomic_fetch_add(&f->done_units, 1);
      report_progress(f);
      continue;
    }
    int c = busiest(f);
    if (c >= 0) {
      int n = take(f, c, batch);
      for (int i = 0; i < n; i++) trace_in_cell(w, &batch[i]);
      flush(w);
      continue;
    }
    /* Nothing queued: done when nothing is in flight and no unit is left;
     * otherwise another worker holds rays it has not pushed yet. */
    if (atomic_load(&f->in_flight) == 0 && atomic_load(&f->next_unit) >= f->units) break;
    sched_yield();
  }
  flush(w);
  return NULL;
}

vr_status vr_flow_run(const vr_domains *d, const vr_flow_ops *ops, void *ctx, long units,
                      int threads, void (*progress)(void *, long, long), void *pctx,
                      vr_flow_stats *stats, vr_error *err) {
  if (threads < 1 || threads > 1024)
    return vr_error_set(err, VR_E_ARG, "threads = %d, expected 1 to 1024", threads);
  flow f = {.d = d, .ops = ops, .ctx = ctx, .units = units, .progress = progress, .pctx = pctx};
  f.ncells = vr_domains_count(d);
  f.q = calloc((size_t)f.ncells, sizeof *f.q);
  vr_flow_worker *ws = calloc((size_t)threads, sizeof *ws);
  pthread_t *tids = calloc((size_t)threads, sizeof *tids);
  vr_status st = VR_OK;
  if (!f.q || !ws || !tids) {
    st = vr_error_set(err, VR_E_NOMEM, "ray flow: out of memory");
    goto done;
  }
  pthread_mutex_init(&f.progress_lock, NULL);
  for (int c = 0; c < f.ncells; c++) pthread_mutex_init(&f.q[c].lock, NULL);
  for (int i = 0; i < threads; i++) {
    ws[i].f = &f;
    ws[i].index = i;
    ws[i].out = malloc((size_t)f.ncells * BATCH * sizeof(vr_ray));
    ws[i].nout = calloc((size_t)f.ncells, sizeof(int));
    if (!ws[i].out || !ws[i].nout) {
      st = vr_error_set(err, VR_E_NOMEM, "ray flow: out of memory");
      goto done;
    }
  }
  int started = 0;
  for (int i = 1; i < threads; i++) {
    if (pthread_create(&tids[i], NULL, worker_main, &ws[i]) != 0) break;
    started = i;
  }
  worker_main(&ws[0]);
  for (int i = 1; i <= started; i++) pthread_join(tids[i], NULL);
  if (atomic_load(&f.failed)) st = vr_error_set(err, VR_E_NOMEM, "ray flow: out of memory in a queue");
  if (progress) progress(pctx, atomic_load(&f.done_units), units);
  if (stats) {
    stats->created = atomic_load(&f.created);
    stats->finished = atomic_load(&f.finished);
    stats->crossings = atomic_load(&f.crossings);
    stats->closest = atomic_load(&f.closest);
    stats->shadow = atomic_load(&f.shadow);
    stats->traversals = atomic_load(&f.traversals);
    for (int i = 0; i < 8; i++) stats->by_purpose[i] = atomic_load(&f.by_purpose[i]);
  }
done:
  for (int i = 0; ws && i < threads; i++) {
    free(ws[i].out);
    free(ws[i].nout);
  }
  for (int c = 0; f.q && c < f.ncells; c++) {
    free(f.q[c].rays);
    pthread_mutex_destroy(&f.q[c].lock);
  }
  free(f.q);
  free(ws);
  free(tids);
  return st;
}
