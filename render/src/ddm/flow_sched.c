/* Which cell a worker traces next, and (under a memory budget) which cells
 * are loaded: the paper's scheduler (Gbikpi-Benissan et al. 2014, sec. 3).
 *
 * Without a budget every cell is loaded, and a worker takes the cell with
 * the most pending rays, reading the counts without a lock.
 *
 * With a budget, decisions are made under sched_lock, once per batch:
 *   - the loaded cell with the most pending rays is the candidate;
 *   - if no loaded cell has rays, or the best has fewer than a batch while
 *     a cell that is not loaded has more, the worker loads that cell (the
 *     one with the most pending rays): first it unloads, fewest pending
 *     first, loaded cells that no worker is tracing in and that have fewer
 *     pending rays than it, until the new cell fits; if it cannot make
 *     room it traces the loaded candidate instead, or waits;
 *   - the chosen cell is pinned while the worker traces its batch, so it
 *     is never unloaded under a worker.
 * A cell being loaded is counted at its load peak (its arrays plus the most
 * Embree holds while building), then at what it keeps.  Rays for a cell
 * that is not loaded wait in its queue, which spills to disk when the
 * queues' share of the budget is used up (flow_queue.c).  Every ray is
 * eventually traced: when loaded cells run dry, a cell with rays is loaded
 * after the dry ones are unloaded, and the budget was checked to hold the
 * largest cell alone. */
#include "ddm/flow_internal.h"

#include <malloc.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

void vr_flow_fail(vr_flow *f, const vr_error *e) {
  pthread_mutex_lock(&f->sched_lock);
  if (!f->fail_err.status) f->fail_err = *e;
  pthread_mutex_unlock(&f->sched_lock);
  atomic_store(&f->failed, 1);
}

static void mib(char *out, size_t n, size_t bytes) {
  if (bytes >= ((size_t)1 << 30))
    snprintf(out, n, "%.2f GiB", (double)bytes / (1 << 30));
  else if (bytes >= ((size_t)1 << 20))
    snprintf(out, n, "%.2f MiB", (double)bytes / (1 << 20));
  else
    snprintf(out, n, "%.1f KiB", (double)bytes / 1024);
}

static size_t held(const vr_flow *f) { return f->held ? f->held(f->hctx) : 0; }

long long vr_flow_rss_bytes(bool anon_only) {
  /* statm: size resident shared text lib data dt, in pages; resident
   * minus shared leaves the anonymous pages (file-backed code and
   * libraries, and shared memory, are not the run's to budget). */
  FILE *fp = fopen("/proc/self/statm", "r");
  if (!fp) return 0;
  long long size = 0, resident = 0, shared = 0;
  int n = fscanf(fp, "%lld %lld %lld", &size, &resident, &shared);
  fclose(fp);
  if (n != 3 || resident < shared) return 0;
  long page = sysconf(_SC_PAGESIZE);
  return (anon_only ? resident - shared : resident) * (page > 0 ? page : 4096);
}

/* Budget: resident memory the run does not count (sched_lock held): what
 * the process holds beyond its base, the cells, queues, maps and film, and
 * the allowance. */
static size_t uncounted(vr_flow *f, size_t maps) {
  if (!f->rss_base) return 0;
  /* /proc is read at most every 10 ms: picks come every batch of rays. */
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  double t = (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
  if (t - f->rss_read_at < 0.01) return f->rss_extra;
  f->rss_read_at = t;
  long long now = vr_flow_rss_bytes(true);
  long long counted = (long long)f->reserved + atomic_load(&f->queue_bytes) + (long long)maps;
  long long extra = now > 0 ? now - f->rss_base - counted : 0;
  if (extra > 0 && (size_t)extra > f->peak_uncounted) f->peak_uncounted = (size_t)extra;
  /* The process's own small allocations (thread stacks, MPI's buffers,
   * the allocator's free lists) are allowed for: only what passes the
   * allowance takes room from the cells. */
  extra -= VR_FLOW_RSS_ALLOWANCE;
  f->rss_extra = extra > 0 ? (size_t)extra : 0;
  return f->rss_extra;
}

vr_status vr_flow_budget_plan(vr_flow *f, vr_error *err) {
  size_t fixed = held(f);
  /* Push buffers: as many rays per cell and worker as fit in a sixteenth
   * of the budget (at least 8, at most VR_FLOW_BATCH). */
  size_t per = f->budget / 16 / ((size_t)f->threads * (size_t)f->ncells * sizeof(vr_ray));
  f->batch = per >= VR_FLOW_BATCH ? VR_FLOW_BATCH : per < 8 ? 8 : (int)per;
  size_t buffers = (size_t)f->threads * (size_t)f->ncells * (size_t)f->batch * sizeof(vr_ray);
  /* Queues: an eighth of the budget, and at least the push buffers plus
   * one batch per cell (what overflows goes to disk). */
  size_t qmin = buffers + (size_t)f->ncells * (size_t)f->batch * sizeof(vr_ray);
  f->queue_cap = f->budget / 8 > qmin ? f->budget / 8 : qmin;
  /* New work while the loaded cells' rays would fill at most half the
   * queues' memory. */
  long lw = (long)((f->queue_cap - buffers) / sizeof(vr_ray) / 2);
  f->low_water = lw > VR_FLOW_LOW_WATER ? VR_FLOW_LOW_WATER : lw < f->batch ? f->batch : lw;
  size_t largest = 0;
  int big = 0;
  for (int c = 0; c < f->ncells; c++) {
    size_t p = vr_domains_cell_load_peak(f->d, c);
    if (p > largest) largest = p, big = c;
  }
  f->largest = largest;
  size_t other = f->queue_cap + fixed;
  f->cells_cap = f->budget > other ? f->budget - other : 0;
  if (largest <= f->cells_cap) {
    /* Cells an earlier pass left loaded count from the start; if the maps
     * built since leave them too little room, the emptiest go. */
    f->reserved = 0;
    for (int c = 0; c < f->ncells; c++)
      if (vr_domains_loaded(f->d, c)) f->reserved += vr_domains_cell_bytes(f->d, c);
    for (int c = 0; c < f->ncells && f->reserved > f->cells_cap; c++)
      if (vr_domains_loaded(f->d, c)) {
        f->reserved -= vr_domains_cell_bytes(f->d, c);
        vr_domains_unload(f->d, c);
      }
    return VR_OK;
  }
  /* The smallest cell that does not fit, and what would do. */
  int worst = big;
  for (int c = 0; c < f->ncells; c++) {
    size_t p = vr_domains_cell_load_peak(f->d, c);
    if (p > f->cells_cap && p < vr_domains_cell_load_peak(f->d, worst))
      worst = c;
  }
  int nfit = 0;
  for (int c = 0; c < f->ncells; c++)
    nfit += vr_domains_cell_load_peak(f->d, c) > f->cells_cap;
  char b[32], w[32], g[32], e[32], cap[32], q[32], fx[32], need[32];
  size_t wp = vr_domains_cell_load_peak(f->d, worst);
  mib(b, sizeof b, f->budget);
  mib(w, sizeof w, wp);
  mib(g, sizeof g, vr_domains_cell_bytes(f->d, worst));
  mib(e, sizeof e, wp - vr_domains_cell_bytes(f->d, worst));
  mib(cap, sizeof cap, f->cells_cap);
  mib(q, sizeof q, f->queue_cap);
  mib(fx, sizeof fx, fixed);
  mib(need, sizeof need, largest + other);
  return vr_error_set(err, VR_E_ARG,
                      "memory budget %s is too small: sub-domain %d needs %s to load (%s "
                      "kept, %s more while Embree builds it), and it is the smallest of the "
                      "%d sub-domain%s that do not fit in the %s left after ray queues (%s) "
                      "and the image, textures, photon and state maps (%s); this scene needs at least %s with %d "
                      "sub-domains (more sub-domains make smaller ones)",
                      b, worst, w, g, e, nfit, nfit == 1 ? "" : "s", cap, q, fx, need,
                      f->ncells);
}

/* Without a budget: the busiest cell, read without a lock. */
static int busiest(vr_flow *f) {
  int best = -1;
  long most = 0;
  for (int c = 0; c < f->ncells; c++) {
    long p = atomic_load_explicit(&f->q[c].pending, memory_order_relaxed);
    if (p > most) {
      most = p;
      best = c;
    }
  }
  return best;
}

/* Loads cell c for the worker (sched_lock held on entry and on return).
 * The other ranks are told at once, so that they send its rays here
 * rather than load it too. */
static bool load(vr_flow *f, vr_flow_worker *w, int c) {
  size_t peak = vr_domains_cell_load_peak(f->d, c);
  f->loading[c] = true;
  f->reserved += peak;
  vr_flow_net_resident(f, c, true);
  pthread_mutex_unlock(&f->sched_lock);
  vr_flow_net_flush(f); /* told before the load, which takes a while */
  vr_error e = {0};
  struct timespec t0, t1;
  clock_gettime(CLOCK_MONOTONIC, &t0);
  vr_status st = vr_domains_load(f->d, c, &e);
  clock_gettime(CLOCK_MONOTONIC, &t1);
  w->loads_since_idle += (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
  pthread_mutex_lock(&f->sched_lock);
  f->loading[c] = false;
  f->reserved -= peak;
  if (st) {
    if (!f->fail_err.status) f->fail_err = e;
    atomic_store(&f->failed, 1);
    return false;
  }
  f->reserved += vr_domains_cell_bytes(f->d, c);
  return true;
}

/* The cell an idle rank loads ahead of its rays (sched_lock held): one
 * that no rank holds or loads and that fits without unloading anything,
 * measured from the cell this rank traced most in (rays spread from
 * there), or -1. */
static int prefetch_pick(vr_flow *f) {
  int busy = -1;
  unsigned long long most = 0;
  for (int c = 0; c < f->ncells; c++) {
    unsigned long long t = atomic_load_explicit(&f->traced[c], memory_order_relaxed);
    if (t > most) most = t, busy = c;
  }
  double at[3] = {0, 0, 0};
  if (busy >= 0) {
    double lo[3], hi[3];
    vr_domains_cell_bounds(f->d, busy, lo, hi);
    for (int k = 0; k < 3; k++) at[k] = 0.5 * (lo[k] + hi[k]);
  }
  /* Its own cells nearest first; when none is left, another rank's that
   * no rank holds yet, farthest first: that rank loads its own nearest
   * first, so the two meet only at its last cell, which is left to it
   * (when they do meet, the cell is loaded twice: time, not
   * correctness). */
  int best = -1, other = -1;
  double nearest = INFINITY, farthest = -1;
  int *left = f->prefetch_left; /* per rank: its cells no rank holds */
  memset(left, 0, (size_t)f->nranks * sizeof *left);
  for (int c = 0; c < f->ncells; c++) {
    if (f->loading[c] || vr_domains_loaded(f->d, c) || vr_flow_holder(f, c) >= 0 ||
        !vr_domains_cell_primitives(f->d, c))
      continue;
    if (f->budget && f->reserved + vr_domains_cell_load_peak(f->d, c) > f->cells_cap) continue;
    double lo[3], hi[3], d2 = 0;
    vr_domains_cell_bounds(f->d, c, lo, hi);
    for (int k = 0; k < 3; k++) {
      double e = at[k] < lo[k] ? lo[k] - at[k] : at[k] > hi[k] ? at[k] - hi[k] : 0;
      d2 += e * e;
    }
    int home = vr_flow_home(f, c);
    left[home]++;
    if (home == f->rank) {
      if (d2 < nearest) nearest = d2, best = c;
    } else if (d2 > farthest) {
      farthest = d2, other = c;
    }
  }
  /* The last cell of another rank is left to it: it is loading it or
   * about to. */
  if (best < 0 && other >= 0 && left[vr_flow_home(f, other)] < 2) other = -1;
  return best >= 0 ? best : other;
}

int vr_flow_sched_pick(vr_flow *f, vr_flow_worker *w) {
  if (!f->budget && !f->lazy) return busiest(f);
  pthread_mutex_lock(&f->sched_lock);
  /* Maps may have grown since the last pick, and the process may hold
   * more than the run counts: the cells get what is left. */
  size_t maps = held(f), extra = uncounted(f, maps);
  size_t other = f->queue_cap + maps + extra;
  if (f->budget) f->cells_cap = f->budget > other ? f->budget - other : 0;
  if (f->budget && f->cells_cap < f->largest) {
    char b[32], h[32], x[32], l[32];
    mib(b, sizeof b, f->budget);
    mib(h, sizeof h, maps);
    mib(x, sizeof x, extra);
    mib(l, sizeof l, f->largest);
    if (!f->fail_err.status)
      vr_error_set(&f->fail_err, VR_E_ARG,
                   "memory budget %s exceeded: the image and photon and state maps grew to %s and the "
                   "process holds %s more than the run counts (the image's pages, allocator "
                   "slack), which leaves less than the largest sub-domain needs (%s); raise "
                   "--memory-budget, use more sub-domains, or shoot fewer photons",
                   b, h, x, l);
    atomic_store(&f->failed, 1);
    pthread_mutex_unlock(&f->sched_lock);
    return -1;
  }
  int best_l = -1, best_u = -1;
  long most_l = 0, most_u = 0;
  for (int c = 0; c < f->ncells; c++) {
    long p = atomic_load_explicit(&f->q[c].pending, memory_order_relaxed);
    if (p <= 0 || f->loading[c]) continue;
    if (vr_domains_loaded(f->d, c)) {
      if (p > most_l) most_l = p, best_l = c;
    } else if (p > most_u) {
      most_u = p, best_u = c;
    }
  }
  /* Load only when no loaded cell has a ray left (and, in the worker's
   * loop, no new work could be generated for them): a load costs as much
   * as tracing a hundred thousand rays, so rays for cells that are not
   * loaded wait, and a cell that a few stray rays reach is loaded once at
   * the end rather than each time some arrive. */
  bool want = best_u >= 0 && best_l < 0;
  /* Several ranks: rays that waited here for a cell another rank holds
   * go there, unless they are many and this rank has the room to load
   * the cell itself (a hot cell, replicated). */
  bool net = want && f->net;
  int holder = net ? vr_flow_holder(f, best_u) : -1;
  bool hot = net && vr_flow_hot(f, best_u) && vr_flow_sched_room(f, best_u);
  if (net && holder < 0 && !hot && vr_flow_home(f, best_u) != f->rank) holder = vr_flow_home(f, best_u);
  if (holder >= 0 && !hot) {
    f->loading[best_u] = true; /* no other worker takes or loads it meanwhile */
    pthread_mutex_unlock(&f->sched_lock);
    bool sent = vr_flow_net_forward(f, best_u, holder);
    pthread_mutex_lock(&f->sched_lock);
    f->loading[best_u] = false;
    want = !sent; /* no room to send them: this rank loads the cell */
  }
  if (want) {
    size_t need = vr_domains_cell_load_peak(f->d, best_u);
    while (f->reserved + need > f->cells_cap) {
      /* The loaded cell nobody traces in with the fewest pending rays
       * (fewer than the one to load), and of those the one that has
       * traced the fewest rays in this run: the cells a pass works in
       * most stay. */
      int victim = -1;
      long fewest = most_u;
      unsigned long long least = 0;
      for (int c = 0; c < f->ncells; c++) {
        if (!vr_domains_loaded(f->d, c) || f->pins[c] || f->loading[c]) continue;
        long p = atomic_load_explicit(&f->q[c].pending, memory_order_relaxed);
        unsigned long long t = atomic_load_explicit(&f->traced[c], memory_order_relaxed);
        if (p < fewest || (p == fewest && victim >= 0 && t < least)) fewest = p, least = t, victim = c;
      }
      if (victim < 0) break;
      f->reserved -= vr_domains_cell_bytes(f->d, victim);
      vr_domains_unload(f->d, victim);
      vr_flow_net_resident(f, victim, false);
      if (victim == best_l) best_l = -1;
      /* What the cell's Embree scene freed goes back to the system, not
       * to the heap's free lists: resident memory follows the budget. */
      malloc_trim(0);
    }
    if (f->reserved + need <= f->cells_cap) {
      if (!load(f, w, best_u)) {
        pthread_mutex_unlock(&f->sched_lock);
        return -1;
      }
      f->pins[best_u]++;
      pthread_mutex_unlock(&f->sched_lock);
      return best_u;
    }
  }
  /* Several ranks, and this one holds no ray at all: rather than wait,
   * it loads a cell no rank holds, if it has the room without unloading
   * anything.  The other ranks' rays reach those
   * cells sooner or later (when a few stray rays do, a rank that waited
   * would load it then, with every rank waiting on it). */
  if (f->net && best_l < 0 && best_u < 0) {
    int c = prefetch_pick(f);
    if (c >= 0 && load(f, w, c)) {
      pthread_mutex_unlock(&f->sched_lock);
      return -1;
    }
  }
  if (best_l >= 0) f->pins[best_l]++;
  pthread_mutex_unlock(&f->sched_lock);
  return best_l;
}

bool vr_flow_sched_room(vr_flow *f, int c) {
  if (!f->budget) return true;
  return f->reserved + vr_domains_cell_load_peak(f->d, c) <= f->cells_cap;
}

void vr_flow_sched_release(vr_flow *f, int c) {
  if (!f->budget && !f->lazy) return;
  pthread_mutex_lock(&f->sched_lock);
  f->pins[c]--;
  pthread_mutex_unlock(&f->sched_lock);
}

long vr_flow_loaded_pending(vr_flow *f) {
  long n = 0;
  for (int c = 0; c < f->ncells; c++)
    if (vr_domains_loaded(f->d, c)) n += atomic_load_explicit(&f->q[c].pending, memory_order_relaxed);
  return n;
}
