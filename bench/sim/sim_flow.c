/* The discrete-event model of the ray flow (sim_flow.h). */
#include "sim_flow.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define BATCH 256           /* rays a worker takes from a queue (VR_FLOW_BATCH) */
#define SEND_BATCH 256      /* rays a message carries (vr-render's default) */
#define MAX_PENDING 65536   /* waiting rays before no unit is generated (LOW_WATER) */
#define ADOPT_RAYS 1024     /* VR_FLOW_ADOPT_RAYS */
#define OUTBOX_WAIT 200e-6  /* an outbox leaves after this, full or not */

void sim_config_default(sim_config *c) {
  memset(c, 0, sizeof *c);
  c->nodes = c->cores = c->ranks = c->threads = 1;
  c->latency = 50e-6, c->bandwidth = 1.25e9;          /* 10 Gbit/s Ethernet */
  c->node_latency = 2e-6, c->node_bandwidth = 5e9;     /* shared memory */
  c->wire_bytes = 180;
  c->seed = 1;
}

enum { EV_DONE, EV_MSG, EV_NEWS, EV_TIMER };
enum { ACT_NONE, ACT_GEN, ACT_TRACE, ACT_LOAD };

typedef struct ev {
  double t;
  int type, rank, a, b; /* DONE: worker a (version n); MSG: from a; NEWS: from a, cell b (loaded: n); TIMER: dest a */
  long n;
  double *counts;       /* MSG: rays per cell */
} ev;

/* A worker's action runs at the speed its node gives it now (processor
 * sharing): when the node's load changes, what is left is re-timed. */
typedef struct worker {
  int act, cell;
  double n;
  double rem;      /* work left, in seconds at full speed */
  double weight;   /* cores it would use (a load: Embree's threads) */
  double speed, t_upd;
  long version;    /* its DONE event's; older ones are stale */
} worker;

typedef struct rank_st {
  int node;
  long units, next;
  double *q, queued, outbox, put, reserved, debt;
  double generating; /* rays of the units being generated (vr_flow's reservation) */
  double *routed;
  unsigned char *loaded, *loading, *known; /* known: S x R, what this rank knows others hold */
  int *pins;
  double *out, *out_n, *out_since; /* R x S, per dest rays, per dest oldest */
  unsigned char *timer;
  worker *w;
  int idle;
} rank_st;

typedef struct sim {
  const sim_profile *p;
  const sim_config *c;
  const sim_pass *ps;
  int S, R, T;
  rank_st *r;
  double *busy;  /* per node: the weights of the running actions */
  double load_weight; /* cores a load uses: Embree builds with the rank's threads */
  ev **heap;
  size_t nheap, capheap;
  unsigned long long rng;
  double now, last;
  double in_transit;
  sim_result *res;
  bool oom;
} sim;

/* ---- events ---- */

static void push(sim *m, ev *e) {
  if (m->nheap == m->capheap) {
    size_t cap = m->capheap ? 2 * m->capheap : 1024;
    ev **h = realloc(m->heap, cap * sizeof *h);
    if (!h) {
      m->oom = true;
      free(e->counts), free(e);
      return;
    }
    m->heap = h, m->capheap = cap;
  }
  size_t i = m->nheap++;
  while (i && m->heap[(i - 1) / 2]->t > e->t) m->heap[i] = m->heap[(i - 1) / 2], i = (i - 1) / 2;
  m->heap[i] = e;
}

static ev *pop(sim *m) {
  ev *top = m->heap[0], *last = m->heap[--m->nheap];
  size_t i = 0;
  for (;;) {
    size_t l = 2 * i + 1, s = i;
    const ev *small = last;
    if (l < m->nheap && m->heap[l]->t < small->t) s = l, small = m->heap[l];
    if (l + 1 < m->nheap && m->heap[l + 1]->t < small->t) s = l + 1;
    if (s == i) break;
    m->heap[i] = m->heap[s], i = s;
  }
  if (m->nheap) m->heap[i] = last;
  return top;
}

static ev *event(sim *m, double t, int type, int rank, int a, int b, long n) {
  ev *e = calloc(1, sizeof *e);
  if (!e) {
    m->oom = true;
    return NULL;
  }
  *e = (ev){t, type, rank, a, b, n, NULL};
  return e;
}

static double uniform(sim *m) { /* splitmix64 */
  uint64_t z = (m->rng += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return (double)(z >> 11) * 0x1p-53;
}

/* x rounded at random to a whole number with mean x. */
static double sround(sim *m, double x) {
  double f = floor(x);
  return f + (uniform(m) < x - f ? 1 : 0);
}

/* ---- ranks' decisions ---- */

static bool holds(const rank_st *r, int c) { return r->loaded[c] || r->loading[c]; }

static int holder(const sim *m, int rank, int c) {
  const rank_st *r = &m->r[rank];
  for (int k = 1; k < m->R; k++) {
    int h = (rank + k) % m->R;
    if (r->known[(size_t)c * (size_t)m->R + (size_t)h]) return h;
  }
  return -1;
}

static bool room(const sim *m, const rank_st *r, int c) {
  return !m->c->budget || r->reserved + m->p->bytes[c] <= m->c->budget;
}

static bool hot(const sim *m, const rank_st *r, int c) {
  double n = r->routed[c] + r->q[c];
  /* An eighth of this rank's rays, or 1/R on R > 8 ranks (vr_flow_hot). */
  double share = m->R > 8 ? m->R : 8;
  return n > ADOPT_RAYS && (share * n > r->put || n > m->p->bytes[c] / 64);
}

static double link_time(const sim *m, int a, int b, double rays) {
  bool same = m->r[a].node == m->r[b].node;
  double bytes = 8 + rays * m->c->wire_bytes;
  return same ? m->c->node_latency + bytes / m->c->node_bandwidth
              : m->c->latency + bytes / m->c->bandwidth;
}

/* Sends what rank's outbox for dest holds (all of it, in messages of
 * SEND_BATCH rays). */
static void send_out(sim *m, int rank, int dest) {
  rank_st *r = &m->r[rank];
  double n = r->out_n[dest];
  if (n <= 0) return;
  ev *e = event(m, m->now + link_time(m, rank, dest, fmin(n, SEND_BATCH)) +
                       (ceil(n / SEND_BATCH) - 1) * SEND_BATCH * m->c->wire_bytes /
                           (m->r[rank].node == m->r[dest].node ? m->c->node_bandwidth
                                                                : m->c->bandwidth),
                EV_MSG, dest, rank, 0, 0);
  if (!e) return;
  e->counts = malloc((size_t)m->S * sizeof *e->counts);
  if (!e->counts) {
    free(e);
    m->oom = true;
    return;
  }
  memcpy(e->counts, r->out + (size_t)dest * (size_t)m->S, (size_t)m->S * sizeof *e->counts);
  memset(r->out + (size_t)dest * (size_t)m->S, 0, (size_t)m->S * sizeof *r->out);
  r->outbox -= n;
  r->out_n[dest] = 0;
  r->debt += n * m->c->ray_overhead / 2;
  m->in_transit += n;
  m->res->rays_sent += n;
  push(m, e);
}

static void to_outbox(sim *m, int rank, int dest, int c, double n) {
  rank_st *r = &m->r[rank];
  if (!r->out_n[dest]) {
    r->out_since[dest] = m->now;
    if (!r->timer[dest]) {
      ev *e = event(m, m->now + OUTBOX_WAIT, EV_TIMER, rank, dest, 0, 0);
      if (e) push(m, e), r->timer[dest] = 1;
    }
  }
  r->out[(size_t)dest * (size_t)m->S + (size_t)c] += n;
  r->out_n[dest] += n;
  r->outbox += n;
  if (r->out_n[dest] >= SEND_BATCH) send_out(m, rank, dest);
}

static void enqueue(rank_st *r, int c, double n) {
  r->q[c] += n;
  r->queued += n;
}

/* n rays for cell c, from rank's own work (vr_flow_route). */
static void route(sim *m, int rank, int c, double n) {
  if (n <= 0) return;
  rank_st *r = &m->r[rank];
  r->put += n;
  if (m->R == 1 || holds(r, c)) return enqueue(r, c, n);
  int dest = holder(m, rank, c);
  if (dest < 0) dest = c % m->R;
  if (dest == rank) return enqueue(r, c, n);
  r->routed[c] += n;
  if (hot(m, r, c) && room(m, r, c)) return enqueue(r, c, n);
  to_outbox(m, rank, dest, c, n);
}

static void news(sim *m, int rank, int c, bool loaded) {
  for (int k = 0; k < m->R; k++) {
    if (k == rank) continue;
    ev *e = event(m, m->now + link_time(m, rank, k, 0), EV_NEWS, k, rank, c, loaded);
    if (e) push(m, e);
  }
}

/* The speed of an action of kind act on node now: the node's cores
 * shared among the running actions' weights, and each other busy core
 * slowing it through the memory bus. */
static double speed(const sim *m, int node, int act) {
  double b = m->busy[node], cores = m->c->cores;
  double share = b > cores ? cores / b : 1;
  double others = (b < cores ? b : cores) - 1;
  double k = act == ACT_LOAD ? m->c->load_contention : m->c->trace_contention;
  return share / (1 + k * (others > 0 ? others : 0));
}

/* Re-times the running actions of node after its load changed. */
static void retime(sim *m, int node) {
  for (int k = node; k < m->R; k += m->c->nodes) {
    rank_st *r = &m->r[k];
    for (int wi = 0; wi < m->T; wi++) {
      worker *w = &r->w[wi];
      if (w->act <= ACT_NONE) continue;
      w->rem -= (m->now - w->t_upd) * w->speed;
      if (w->rem < 0) w->rem = 0;
      w->t_upd = m->now;
      w->speed = speed(m, node, w->act);
      ev *e = event(m, m->now + w->rem / w->speed, EV_DONE, k, wi, 0, ++w->version);
      if (e) push(m, e);
    }
  }
}

static void start(sim *m, int rank, int wi, int act, int c, double n, double work) {
  rank_st *r = &m->r[rank];
  worker *w = &r->w[wi];
  w->act = act, w->cell = c, w->n = n;
  w->rem = work + r->debt;
  r->debt = 0;
  w->weight = act == ACT_LOAD ? m->load_weight : 1;
  w->t_upd = m->now;
  w->speed = 1;
  m->busy[r->node] += w->weight;
  retime(m, r->node);
}

static void load(sim *m, int rank, int wi, int c) {
  rank_st *r = &m->r[rank];
  r->loading[c] = 1;
  r->reserved += m->p->bytes[c];
  if (m->R > 1) news(m, rank, c, true);
  m->res->loads++;
  start(m, rank, wi, ACT_LOAD, c, 0, m->p->load_s[c] / m->load_weight);
}

/* Under a budget: unloads cells until c fits; whether it does. */
static bool make_room(sim *m, int rank, int c) {
  rank_st *r = &m->r[rank];
  while (!room(m, r, c)) {
    int victim = -1;
    for (int k = 0; k < m->S; k++)
      if (r->loaded[k] && !r->pins[k] && r->q[k] < r->q[c] && (victim < 0 || r->q[k] < r->q[victim]))
        victim = k;
    if (victim < 0) return false;
    r->loaded[victim] = 0;
    r->reserved -= m->p->bytes[victim];
    if (m->R > 1) news(m, rank, victim, false);
  }
  return true;
}

/* A cell no rank holds, for an idle rank to load ahead: its own home
 * cells first, then another rank's, leaving each its last. */
static int prefetch(sim *m, int rank) {
  rank_st *r = &m->r[rank];
  int own = -1, other = -1;
  int *left = calloc((size_t)m->R, sizeof *left);
  if (!left) return -1;
  for (int c = 0; c < m->S; c++) {
    if (holds(r, c) || holder(m, rank, c) >= 0 || m->p->bytes[c] <= 0) continue;
    if (m->c->budget && !room(m, r, c)) continue;
    left[c % m->R]++;
    if (c % m->R == rank) {
      if (own < 0) own = c;
    } else {
      other = c;
    }
  }
  if (own < 0 && other >= 0 && left[other % m->R] < 2) other = -1;
  free(left);
  return own >= 0 ? own : other;
}

/* The rays a generated unit reserves, as vr_flow does: its rays, at most
 * half the cap. */
static double unit_reserve(const sim *m) {
  double unit = 0;
  for (int b = 0; b < m->S; b++) unit += m->ps->out[(size_t)m->S * (size_t)m->S + (size_t)b];
  return unit > MAX_PENDING / 2 ? MAX_PENDING / 2 : unit;
}

/* A free worker of rank chooses what to do (vr_flow's worker loop). */
static void decide(sim *m, int rank, int wi) {
  rank_st *r = &m->r[rank];
  const sim_pass *ps = m->ps;
  int S = m->S;
  for (;;) {
    /* As vr_flow: a unit starts when its rays (at most half the cap) fit
     * below the cap with those waiting and being generated, or when
     * nothing waits. */
    double unit = unit_reserve(m), waiting = r->queued + r->outbox + r->generating;
    if (r->next < r->units && (waiting <= 0 || waiting + unit < MAX_PENDING)) {
      r->next++;
      r->generating += unit;
      start(m, rank, wi, ACT_GEN, -1, 0, ps->units > 0 ? ps->gen_s / (double)ps->units : 0);
      return;
    }
    int bl = -1, bu = -1;
    for (int c = 0; c < S; c++) {
      if (r->q[c] <= 0 || r->loading[c]) continue;
      if (r->loaded[c]) {
        if (bl < 0 || r->q[c] > r->q[bl]) bl = c;
      } else if (bu < 0 || r->q[c] > r->q[bu]) {
        bu = c;
      }
    }
    if (bl >= 0) {
      double n = fmin(r->q[bl], BATCH);
      r->q[bl] -= n, r->queued -= n;
      r->pins[bl]++;
      start(m, rank, wi, ACT_TRACE, bl, n, n * ps->cost[bl]);
      return;
    }
    if (bu >= 0) {
      int h = m->R > 1 ? holder(m, rank, bu) : -1;
      bool hh = m->R > 1 && hot(m, r, bu) && room(m, r, bu);
      if (m->R > 1 && h < 0 && !hh && bu % m->R != rank) h = bu % m->R;
      if (h >= 0 && !hh) {
        double n = r->q[bu];
        r->q[bu] = 0, r->queued -= n;
        to_outbox(m, rank, h, bu, n);
        send_out(m, rank, h);
        continue;
      }
      if (make_room(m, rank, bu)) {
        load(m, rank, wi, bu);
        return;
      }
    } else if (m->R > 1) {
      int c = prefetch(m, rank);
      if (c >= 0) {
        load(m, rank, wi, c);
        return;
      }
    }
    r->w[wi].act = ACT_NONE;
    r->idle++;
    return;
  }
}

static void wake(sim *m, int rank) {
  rank_st *r = &m->r[rank];
  for (int wi = 0; wi < m->T && r->idle; wi++)
    if (r->w[wi].act == ACT_NONE) {
      r->idle--;
      r->w[wi].act = -1; /* deciding */
      decide(m, rank, wi);
    }
}

static void done(sim *m, ev *e) {
  rank_st *r = &m->r[e->rank];
  worker *w = &r->w[e->a];
  if (w->act <= ACT_NONE || e->n != w->version) return; /* re-timed since */
  m->busy[r->node] -= w->weight;
  if (m->busy[r->node] < 1e-9) m->busy[r->node] = 0;
  const sim_pass *ps = m->ps;
  int S = m->S;
  if (w->act == ACT_GEN) {
    r->generating -= unit_reserve(m);
    for (int b = 0; b < S; b++) route(m, e->rank, b, sround(m, ps->out[(size_t)S * (size_t)S + (size_t)b]));
  } else if (w->act == ACT_TRACE) {
    int c = w->cell;
    r->pins[c]--;
    for (int b = 0; b < S; b++) {
      double per = ps->out[(size_t)c * (size_t)S + (size_t)b];
      if (per > 0) route(m, e->rank, b, sround(m, w->n * per));
    }
  } else if (w->act == ACT_LOAD) {
    r->loading[w->cell] = 0;
    r->loaded[w->cell] = 1;
  }
  m->last = m->now;
  w->act = -1;
  retime(m, r->node);
  decide(m, e->rank, e->a);
  wake(m, e->rank);
}

/* ---- one pass ---- */

static bool run_pass(sim *m) {
  for (int k = 0; k < m->R; k++) {
    rank_st *r = &m->r[k];
    r->units = m->ps->units > k ? (m->ps->units - k + m->R - 1) / m->R : 0;
    r->next = 0;
    r->put = 0;
    memset(r->routed, 0, (size_t)m->S * sizeof *r->routed);
    r->idle = 0;
    for (int wi = 0; wi < m->T; wi++) r->w[wi].act = ACT_NONE, r->idle++;
  }
  for (int k = 0; k < m->R; k++) wake(m, k);
  while (m->nheap && !m->oom) {
    ev *e = pop(m);
    m->now = e->t;
    rank_st *r = &m->r[e->rank];
    if (e->type == EV_DONE) {
      done(m, e);
    } else if (e->type == EV_MSG) {
      double n = 0;
      for (int c = 0; c < m->S; c++)
        if (e->counts[c] > 0) enqueue(r, c, e->counts[c]), n += e->counts[c];
      m->in_transit -= n;
      r->debt += n * m->c->ray_overhead / 2;
      m->last = m->now;
      wake(m, e->rank);
    } else if (e->type == EV_NEWS) {
      r->known[(size_t)e->b * (size_t)m->R + (size_t)e->a] = (unsigned char)e->n;
      wake(m, e->rank);
    } else if (e->type == EV_TIMER) {
      r->timer[e->a] = 0;
      if (r->out_n[e->a] > 0) {
        if (m->now - r->out_since[e->a] >= OUTBOX_WAIT - 1e-12) {
          send_out(m, e->rank, e->a);
        } else {
          ev *t = event(m, r->out_since[e->a] + OUTBOX_WAIT, EV_TIMER, e->rank, e->a, 0, 0);
          if (t) push(m, t), r->timer[e->a] = 1;
        }
      }
    }
    free(e->counts);
    free(e);
  }
  if (m->oom) return false;
  /* Every ray traced: a model that stalls with rays left is a defect. */
  for (int k = 0; k < m->R; k++)
    if (m->r[k].queued > 0.5 || m->r[k].outbox > 0.5) return false;
  m->now = m->last;
  return true;
}

/* The cores a load of a rank uses: its threads, at most the node's cores
 * (more threads than cores build no faster), each adding less than a
 * core: T^load_scaling. */
static double load_weight(const sim_config *c) {
  double t = c->threads < c->cores ? c->threads : c->cores;
  double w = t > 1 ? pow(t, c->load_scaling) : 1;
  return w > c->cores ? c->cores : w;
}

/* ---- image space ---- */

static void image_space(const sim_profile *p, const sim_config *c, sim_result *res) {
  double scene = 0;
  for (int k = 0; k < p->S; k++) scene += p->bytes[k];
  if (c->budget && scene > c->budget) {
    res->refused = true;
    return;
  }
  /* Each rank loads the whole scene (the profile's cells as one: their
   * load times), then its threads trace its share of the units whole. */
  int per_node = (c->ranks + c->nodes - 1) / c->nodes;
  int busy = per_node * c->threads;
  double cpu = busy > c->cores ? (double)busy / c->cores : 1;
  int shared = (busy < c->cores ? busy : c->cores) - 1;
  double lw = load_weight(c);
  double load = 0, lbusy = per_node * lw;
  for (int k = 0; k < p->S; k++) load += p->load_s[k] / lw;
  double lshared = (lbusy < c->cores ? lbusy : c->cores) - 1;
  load *= (lbusy > c->cores ? lbusy / c->cores : 1) * (1 + c->load_contention * lshared);
  double t = c->prepare_s + load;
  for (int i = 0; i < p->npasses; i++) {
    const sim_pass *ps = &p->pass[i];
    double unit = sim_pass_seconds(p, i) / (ps->units > 0 ? (double)ps->units : 1);
    long mine = ps->units > 0 ? (ps->units + c->ranks - 1) / c->ranks : 0;
    double waves = ceil((double)mine / c->threads);
    t += waves * unit * cpu * (1 + c->trace_contention * shared);
  }
  res->seconds = t;
  res->loads = c->ranks;
}

bool sim_run(const sim_profile *p, const sim_config *c, sim_result *res) {
  memset(res, 0, sizeof *res);
  if (c->image_space) {
    image_space(p, c, res);
    return true;
  }
  sim m = {.p = p, .c = c, .S = p->S, .R = c->ranks, .T = c->threads, .rng = c->seed, .res = res};
  int S = p->S, R = c->ranks;
  m.r = calloc((size_t)R, sizeof *m.r);
  m.busy = calloc((size_t)c->nodes, sizeof *m.busy);
  /* A load builds on the rank's threads, as fast as load_speedup says. */
  m.load_weight = load_weight(c);
  bool ok = m.r && m.busy;
  for (int k = 0; ok && k < R; k++) {
    rank_st *r = &m.r[k];
    r->node = k % c->nodes;
    r->q = calloc((size_t)S, sizeof *r->q);
    r->routed = calloc((size_t)S, sizeof *r->routed);
    r->loaded = calloc((size_t)S, 1);
    r->loading = calloc((size_t)S, 1);
    r->known = calloc((size_t)S * (size_t)R, 1);
    r->pins = calloc((size_t)S, sizeof *r->pins);
    r->out = calloc((size_t)R * (size_t)S, sizeof *r->out);
    r->out_n = calloc((size_t)R, sizeof *r->out_n);
    r->out_since = calloc((size_t)R, sizeof *r->out_since);
    r->timer = calloc((size_t)R, 1);
    r->w = calloc((size_t)c->threads, sizeof *r->w);
    ok = r->q && r->routed && r->loaded && r->loading && r->known && r->pins && r->out && r->out_n &&
         r->out_since && r->timer && r->w;
  }
  if (ok) {
    m.now = c->prepare_s;
    /* One process without a budget loads every cell first, one by one. */
    if (R == 1 && !c->budget) {
      for (int k = 0; k < S; k++) {
        m.now += p->load_s[k] / m.load_weight;
        m.r[0].loaded[k] = 1;
        m.r[0].reserved += p->bytes[k];
        res->loads++;
      }
    }
    m.last = m.now;
    for (int i = 0; ok && i < p->npasses; i++) {
      m.ps = &p->pass[i];
      ok = run_pass(&m);
    }
    res->seconds = m.now;
  }
  for (int k = 0; m.r && k < R; k++) {
    rank_st *r = &m.r[k];
    free(r->q), free(r->routed), free(r->loaded), free(r->loading), free(r->known);
    free(r->pins), free(r->out), free(r->out_n), free(r->out_since), free(r->timer), free(r->w);
  }
  while (m.nheap) {
    ev *e = pop(&m);
    free(e->counts), free(e);
  }
  free(m.heap);
  free(m.r);
  free(m.busy);
  return ok;
}
