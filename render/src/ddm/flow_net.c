/* Rays between ranks (flow_internal.h, docs/ddm.md "Ranks").
 *
 * Sub-domains are data, ranks are workers (the paper's load/unload policy
 * across ranks, DESIGN §6.8).  Any rank may load any cell; a cell may be
 * resident on several ranks at once.  A ray that reaches a cell goes:
 *   - to this rank's queue of the cell when the cell is loaded here (or
 *     being loaded), or when no other rank is known to hold it (then this
 *     rank's scheduler loads it when its turn comes);
 *   - otherwise to a rank that holds it, unless this rank has already sent
 *     that cell more rays than a load of it costs and has the memory for
 *     it: then the cell's rays stay and it is loaded here too (ownership
 *     follows the work; hot cells end up replicated where memory allows,
 *     cold ones live on one rank).
 * Each rank tells the others which cells it loads and unloads; what a rank
 * knows of the others may be late, so a ray may reach a rank that has just
 * unloaded its cell: it waits there like any ray for a cell that is not
 * loaded.  With no budget every rank loads what its own rays need and
 * little or nothing moves: image space with cells loaded on demand.
 *
 * Messages carry a header (its kind and count): rays, credits, or
 * residency changes.  Communication is done by the workers themselves, one
 * at a time (vr_flow_net_progress, under a lock it only tries to take),
 * after each batch and while they wait: no thread spins on MPI while the
 * workers trace, which matters when ranks share a machine's cores.
 *
 * Flow control.  A sender holds credit for each rank, RAY_CREDIT rays to
 * start with; it sends at most as many rays as it has credit for, and the
 * rest wait in its outbox (counted in its pending rays, so it generates no
 * more work while they wait).  A receiver gives the credit back once the
 * rays are out of its memory's way: when its queues hold less than their
 * share (QUEUE_MARK bytes, or the queues' part of the budget), and a
 * spilled ray is out of the way too.  So a rank that receives faster than
 * it traces holds at most its own queues' share plus RAY_CREDIT rays from
 * each other rank, whatever the number of samples.
 *
 * Counting.  Rays in an outbox are still in this rank's in-flight count;
 * when the message is handed to MPI they leave it and `sent` grows; on
 * receipt the receiver adds them to its in-flight count and `received`
 * grows.  A rank is passive when all its units have been generated and its
 * in-flight count is 0 (then no ray exists on it, flow.c shows why, and it
 * can only become active by receiving).
 *
 * Termination is detected, never guessed: the communication threads run
 * waves, each a non-blocking sum over all ranks of (active ranks, rays
 * sent, rays received, failed ranks), every rank contributing the values
 * it sees when it joins the wave.  A rank joins only when it is passive
 * (or failed): a wave waits for the busy ranks instead of costing them a
 * collective each time.  The run is over when two successive
 * waves both find no active rank and sent = received, with the same sums.
 * Why that is enough: a rank joins wave k+1 only after wave k has
 * completed, and wave k completes only once every rank has joined it, so
 * every sample of wave k+1 is taken after every sample of wave k.  The
 * counts never decrease, so equal sums mean that no rank sent or received
 * anything between its two samples; a passive rank becomes active only by
 * receiving, so every rank stayed passive from its first sample to its
 * second.  Let T be the time of the last sample of wave k: every rank is
 * between its two samples then, so at T the rays sent so far number S and
 * those received number R = S: none is in transit, and every rank is
 * passive.  Nothing can happen after that, and every rank draws the same
 * conclusion from the same sums in the same wave.  A wave that counts a
 * failed rank stops every rank in the same way.  Credit and residency
 * messages are not rays: a rank with rays waiting for credit is active. */
#include "ddm/flow_internal.h"

#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "ddm/ray_wire.h"
#include "vr/comm.h"

/* Rays a sender may have sent to one rank and not had credited back. */
#define RAY_CREDIT 4096
/* Without a budget, the bytes of queued rays under which a receiver gives
 * credit back. */
#define QUEUE_MARK (64ll << 20)

enum { MSG_RAYS = 1, MSG_CREDIT = 2, MSG_RESIDENT = 3 };

typedef struct msg_head {
  uint32_t kind, n;
} msg_head;

typedef struct vr_outbox {
  pthread_mutex_t lock;
  vr_ray *rays;
  size_t n, cap;
  double since; /* when its oldest ray came */
} vr_outbox;

typedef struct vr_pending {
  vr_comm_req *req;
  void *buf;
} vr_pending;

struct vr_flow_net {
  vr_comm *comm;
  int batch;
  pthread_mutex_t lock; /* one worker at a time talks to MPI */
  vr_outbox *out;
  long *credit;         /* rays this rank may still send to each rank */
  long *owed;           /* rays received from each rank and not yet credited back */
  long credit0;         /* the credit each rank starts with */
  long peak_owed;
  vr_pending *pend;
  size_t npend, cappend;
  /* Residency changes of this rank not yet told (cell, 1 loaded / 0 not). */
  pthread_mutex_t news_lock;
  int32_t *news;
  size_t nnews, capnews;
  vr_flow_worker self; /* a worker record for queue puts (spill counts) */
  int64_t sent, received;
  uint64_t messages, bytes, waves, credit_waits, ray_messages, ray_bytes;
  bool other_failed, over;
  /* The termination wave under way and the last one's sums. */
  bool waving, have_prev;
  vr_comm_req *wave;
  int64_t in[4], res[4], prev[4];
  double last_wave;
};

static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void fail(vr_flow *f, vr_status st, const char *msg) {
  vr_error e = {0};
  vr_error_set(&e, st, "%s", msg);
  vr_flow_fail(f, &e);
}

static bool send_control(vr_flow *f);

/* ---- residency ---- */

void vr_flow_net_flush(vr_flow *f) {
  vr_flow_net *net = f->net;
  if (!net) return;
  pthread_mutex_lock(&net->lock);
  send_control(f);
  pthread_mutex_unlock(&net->lock);
}

void vr_flow_net_resident(vr_flow *f, int c, bool loaded) {
  vr_flow_net *net = f->net;
  if (!net) return;
  atomic_store_explicit(&f->held_by[(size_t)c * (size_t)f->nranks + (size_t)f->rank],
                        (unsigned char)loaded, memory_order_relaxed);
  pthread_mutex_lock(&net->news_lock);
  if (net->nnews + 2 > net->capnews) {
    size_t cap = net->capnews ? 2 * net->capnews : 64;
    int32_t *n = realloc(net->news, cap * sizeof *n);
    if (!n) {
      pthread_mutex_unlock(&net->news_lock);
      return; /* the others learn late: rays still reach a holder or wait */
    }
    net->news = n;
    net->capnews = cap;
  }
  net->news[net->nnews++] = c;
  net->news[net->nnews++] = loaded;
  pthread_mutex_unlock(&net->news_lock);
}

int vr_flow_home(const vr_flow *f, int c) { return c % f->nranks; }

int vr_flow_holder(vr_flow *f, int c) {
  if (!f->net) return -1;
  const _Atomic unsigned char *h = f->held_by + (size_t)c * (size_t)f->nranks;
  int R = f->nranks, best = -1;
  /* Among the holders, the one this rank has the most credit with, so
   * that rays spread over the copies of a hot cell. */
  long most = -1;
  for (int k = 1; k < R; k++) {
    int r = (f->rank + k) % R;
    if (!atomic_load_explicit(&h[r], memory_order_relaxed)) continue;
    long cr = f->net->credit[r];
    if (cr > most) most = cr, best = r;
  }
  return best;
}

/* The rank a ray for cell c goes to (this one, or a holder of c). */
int vr_flow_route(vr_flow *f, int c, int n) {
  if (!f->net || vr_domains_loaded(f->d, c) || f->loading[c]) return f->rank;
  /* Outboxes count in the queues' share of the budget: when it is full,
   * the rays wait here (spilled), for this rank to load their cell. */
  if (f->budget && atomic_load_explicit(&f->queue_bytes, memory_order_relaxed) +
                           (long long)n * (long long)sizeof(vr_ray) >
                       (long long)f->queue_cap)
    return f->rank;
  int best = vr_flow_holder(f, c);
  if (best < 0) best = vr_flow_home(f, c);
  if (best == f->rank) return f->rank;
  /* Ownership follows the work: the rays of a cold cell go to a holder
   * (loading it costs far more than sending a few thousand rays), but a
   * cell that takes much of this rank's work is loaded here too when there
   * is room: a hot cell ends up on every rank with room for it (without a
   * budget, every rank that works in it), a cold one on one. */
  atomic_fetch_add_explicit(&f->routed[c], n, memory_order_relaxed);
  if (vr_flow_hot(f, c) && vr_flow_sched_room(f, c)) return f->rank;
  return best;
}

bool vr_flow_hot(vr_flow *f, int c) {
  long r = atomic_load_explicit(&f->routed[c], memory_order_relaxed) +
           atomic_load_explicit(&f->q[c].pending, memory_order_relaxed);
  if (r <= f->adopt_rays) return false;
  /* Hot: a large share of this rank's work, or more rays than a load
   * costs.  A load costs about a byte of the cell per 64 rays sent (an
   * Embree build of ~1e-8 s a byte against ~0.6 us a ray sent and traced
   * elsewhere, docs/ddm.md): small cells are loaded wherever their rays
   * are, large ones only where they take much of the work.  The share is
   * an eighth, or 1/N on N > 8 ranks: every rank sends a holder about as
   * many rays as this one, so a cell with more than 1/N of the work would
   * give its holder more than a rank's part (the simulation of 16 ranks
   * put 13 % of the hotel's tracing on one rank under a fixed eighth,
   * docs/ddm.md). */
  long share = f->nranks > 8 ? f->nranks : 8;
  return share * r > atomic_load_explicit(&f->put_rays, memory_order_relaxed) ||
         (double)r > (double)vr_domains_cell_bytes(f->d, c) / 64.0;
}

bool vr_flow_net_forward(vr_flow *f, int c, int dest) {
  vr_ray batch[VR_FLOW_BATCH];
  bool any = false;
  int n;
  /* Under a budget the outbox counts in the queues' share: what does not
   * fit stays queued here (the caller loads the cell if nothing went). */
  long long room = (long long)f->batch * (long long)sizeof batch[0];
  while ((!f->budget ||
          atomic_load_explicit(&f->queue_bytes, memory_order_relaxed) + room <= (long long)f->queue_cap) &&
         (n = vr_flow_queue_take(f, c, batch, &f->net->self)) > 0) {
    if (!vr_flow_net_put(f, dest, batch, n)) {
      fail(f, VR_E_NOMEM, "ray flow: out of memory for a message");
      return any;
    }
    any = true;
  }
  return any;
}

/* ---- rays out ---- */

bool vr_flow_net_put(vr_flow *f, int dest, const vr_ray *rays, int n) {
  vr_outbox *o = &f->net->out[dest];
  pthread_mutex_lock(&o->lock);
  if (o->n + (size_t)n > o->cap) {
    size_t cap = o->cap ? 2 * o->cap : 2 * (size_t)f->net->batch;
    while (cap < o->n + (size_t)n) cap *= 2;
    vr_ray *r = realloc(o->rays, cap * sizeof *r);
    if (!r) {
      pthread_mutex_unlock(&o->lock);
      return false;
    }
    o->rays = r;
    o->cap = cap;
  }
  if (!o->n) o->since = now();
  memcpy(o->rays + o->n, rays, (size_t)n * sizeof *rays);
  o->n += (size_t)n;
  pthread_mutex_unlock(&o->lock);
  vr_flow_note_bytes(&f->queue_bytes, &f->peak_queue_bytes, (long long)n * (long long)sizeof *rays);
  atomic_fetch_add(&f->outbox_rays, n);
  return true;
}

/* Hands one message (buf, freed when MPI is done with it) to MPI; false
 * (the flow failed, buf freed) if it cannot. */
static bool send_msg(vr_flow *f, int dest, void *buf, size_t bytes) {
  vr_flow_net *net = f->net;
  if (net->npend == net->cappend) {
    size_t cap = net->cappend ? 2 * net->cappend : 16;
    vr_pending *p = realloc(net->pend, cap * sizeof *p);
    if (!p) {
      free(buf);
      fail(f, VR_E_NOMEM, "ray flow: out of memory for a message");
      return false;
    }
    net->pend = p;
    net->cappend = cap;
  }
  vr_error e = {0};
  vr_comm_req *req = NULL;
  if (vr_comm_isend(net->comm, dest, buf, bytes, &req, &e)) {
    free(buf);
    vr_flow_fail(f, &e);
    return false;
  }
  net->pend[net->npend++] = (vr_pending){req, buf};
  net->messages++;
  net->bytes += bytes;
  return true;
}

/* A message of k rays to dest, in their wire form. */
static bool send_rays(vr_flow *f, int dest, const vr_ray *rays, size_t k) {
  unsigned char *buf = malloc(sizeof(msg_head) + k * VR_RAY_WIRE_MAX);
  if (!buf) {
    fail(f, VR_E_NOMEM, "ray flow: out of memory for a message");
    return false;
  }
  msg_head h = {MSG_RAYS, (uint32_t)k};
  memcpy(buf, &h, sizeof h);
  size_t bytes = sizeof h;
  for (size_t i = 0; i < k; i++) bytes += vr_ray_pack(f->ops, f->ctx, &rays[i], buf + bytes);
  if (!send_msg(f, dest, buf, bytes)) return false;
  f->net->sent += (int64_t)k;
  f->net->ray_messages++;
  f->net->ray_bytes += bytes;
  f->net->credit[dest] -= (long)k;
  atomic_fetch_sub(&f->in_flight, (long)k); /* they are in transit now */
  return true;
}

/* Sends what the outboxes hold, as far as the credit goes: full messages
 * at once, a partial one after it has waited 200 us. */
static bool send_outboxes(vr_flow *f) {
  vr_flow_net *net = f->net;
  bool did = false;
  double t = now();
  for (int dest = 0; dest < f->nranks; dest++) {
    if (dest == f->rank) continue;
    vr_outbox *o = &net->out[dest];
    pthread_mutex_lock(&o->lock);
    size_t n = o->n, sent = 0;
    bool old = n && t - o->since >= 200e-6;
    while (n - sent >= (size_t)net->batch || (old && sent < n)) {
      long cr = net->credit[dest];
      if (cr <= 0) {
        net->credit_waits++;
        break;
      }
      size_t k = n - sent;
      if (k > (size_t)net->batch) k = (size_t)net->batch;
      if ((long)k > cr) k = (size_t)cr;
      if (!send_rays(f, dest, o->rays + sent, k)) break;
      sent += k;
    }
    if (sent) {
      memmove(o->rays, o->rays + sent, (n - sent) * sizeof *o->rays);
      o->n = n - sent;
      if (o->n) o->since = t;
      did = true;
    }
    pthread_mutex_unlock(&o->lock);
    if (sent) {
      vr_flow_note_bytes(&f->queue_bytes, &f->peak_queue_bytes,
                         -(long long)sent * (long long)sizeof(vr_ray));
      atomic_fetch_sub(&f->outbox_rays, (long)sent);
    }
  }
  return did;
}

/* Credit back to the ranks this one received from, once its queues have
 * room for more; and what it loaded or unloaded, to every rank. */
static bool send_control(vr_flow *f) {
  vr_flow_net *net = f->net;
  bool did = false;
  /* The rays waiting in this rank's queues in memory (not spilled, not in
   * outboxes: two ranks whose outboxes wait for each other would otherwise
   * wait for ever), against half the queues' share of the budget. */
  long long buffers = (long long)f->threads * f->ncells * f->batch * (long long)sizeof(vr_ray);
  long long mark = f->budget ? ((long long)f->queue_cap - buffers) / 2 : QUEUE_MARK;
  long long queued = (long long)atomic_load(&f->queued) * (long long)sizeof(vr_ray) -
                     (long long)atomic_load(&f->spill_bytes);
  if (queued < mark) {
    for (int r = 0; r < f->nranks; r++) {
      if (r == f->rank || !net->owed[r]) continue;
      msg_head *m = malloc(sizeof *m);
      if (!m) {
        fail(f, VR_E_NOMEM, "ray flow: out of memory for a message");
        return true;
      }
      *m = (msg_head){MSG_CREDIT, (uint32_t)net->owed[r]};
      if (!send_msg(f, r, m, sizeof *m)) return true;
      net->owed[r] = 0;
      did = true;
    }
  }
  pthread_mutex_lock(&net->news_lock);
  size_t nn = net->nnews;
  int32_t *news = net->news;
  if (nn) net->news = NULL, net->nnews = net->capnews = 0;
  pthread_mutex_unlock(&net->news_lock);
  for (int r = 0; nn && r < f->nranks; r++) {
    if (r == f->rank) continue;
    size_t bytes = sizeof(msg_head) + nn * sizeof *news;
    unsigned char *buf = malloc(bytes);
    if (!buf) {
      fail(f, VR_E_NOMEM, "ray flow: out of memory for a message");
      break;
    }
    msg_head h = {MSG_RESIDENT, (uint32_t)(nn / 2)};
    memcpy(buf, &h, sizeof h);
    memcpy(buf + sizeof h, news, nn * sizeof *news);
    if (!send_msg(f, r, buf, bytes)) break;
    did = true;
  }
  free(news);
  /* Messages MPI has finished with give their buffers back. */
  for (size_t i = 0; i < net->npend;) {
    if (vr_comm_test(net->pend[i].req)) {
      free(net->pend[i].buf);
      net->pend[i] = net->pend[--net->npend];
    } else {
      i++;
    }
  }
  return did;
}

/* ---- rays in ---- */

static void take_rays(vr_flow *f, int src, const unsigned char *body, size_t len, size_t n) {
  vr_flow_net *net = f->net;
  atomic_fetch_add(&f->in_flight, (long)n); /* here now: counted before they are visible */
  net->received += (int64_t)n;
  net->owed[src] += (long)n;
  if (net->owed[src] > net->peak_owed) net->peak_owed = net->owed[src];
  /* Senders flush cell by cell, so a message is runs of one cell. */
  vr_ray run[VR_FLOW_BATCH];
  size_t off = 0;
  for (size_t i = 0; i < n;) {
    int k = 0, c = -1;
    while (i < n && k < VR_FLOW_BATCH) {
      size_t used = vr_ray_unpack(f->ops, f->ctx, body + off, len - off, &run[k]);
      if (!used) {
        fail(f, VR_E_IO, "ray flow: a malformed message");
        return;
      }
      if (k && run[k].cell != c) break; /* read again as the next run's first */
      c = run[k++].cell;
      off += used;
      i++;
    }
    if (c < 0 || c >= f->ncells || !vr_flow_queue_put(f, c, run, k, &net->self)) {
      fail(f, VR_E_NOMEM, c >= 0 && c < f->ncells
                              ? "ray flow: a queue can neither grow nor spill"
                              : "ray flow: a message names a sub-domain the scene does not have");
      return;
    }
  }
  if (off != len) fail(f, VR_E_IO, "ray flow: a malformed message");
}

/* Receives what has arrived. */
static bool receive(vr_flow *f) {
  vr_flow_net *net = f->net;
  bool did = false;
  int src;
  size_t bytes;
  while (vr_comm_poll(net->comm, &src, &bytes)) {
    unsigned char *buf = malloc(bytes ? bytes : 1);
    vr_error e = {0};
    if (!buf) {
      fail(f, VR_E_NOMEM, "ray flow: out of memory for a message");
      return true;
    }
    if (vr_comm_recv(net->comm, src, buf, bytes, &e)) {
      free(buf);
      vr_flow_fail(f, &e);
      return true;
    }
    msg_head h;
    if (bytes < sizeof h) {
      free(buf);
      fail(f, VR_E_IO, "ray flow: a malformed message");
      return true;
    }
    memcpy(&h, buf, sizeof h);
    const unsigned char *body = buf + sizeof h;
    size_t rest = bytes - sizeof h;
    if (h.kind == MSG_RAYS && rest >= (size_t)h.n * 8 && rest <= (size_t)h.n * VR_RAY_WIRE_MAX) {
      take_rays(f, src, body, rest, h.n);
    } else if (h.kind == MSG_CREDIT && rest == 0) {
      net->credit[src] += h.n;
    } else if (h.kind == MSG_RESIDENT && rest == (size_t)h.n * 2 * sizeof(int32_t)) {
      for (uint32_t i = 0; i < h.n; i++) {
        int32_t cl[2];
        memcpy(cl, body + i * sizeof cl, sizeof cl);
        if (cl[0] >= 0 && cl[0] < f->ncells)
          atomic_store_explicit(&f->held_by[(size_t)cl[0] * (size_t)f->nranks + (size_t)src],
                                (unsigned char)(cl[1] != 0), memory_order_relaxed);
      }
    } else {
      fail(f, VR_E_IO, "ray flow: a malformed message");
    }
    free(buf);
    did = true;
  }
  return did;
}

/* One round: send, receive, and take the termination waves one step.
 * Called with net->lock held. */
static bool progress(vr_flow *f) {
  vr_flow_net *net = f->net;
  if (net->over) return false;
  bool did = send_outboxes(f);
  did |= receive(f);
  did |= send_control(f);
  /* A rank joins the next wave only when it has nothing left to do (or
   * has failed): a wave cannot end the run while any rank is active, and
   * waves cost every rank a collective.  At most one every 100 us. */
  bool passive = atomic_load(&f->done_units) >= f->units && atomic_load(&f->in_flight) == 0;
  bool failed = atomic_load(&f->failed) != 0;
  double t = now();
  if (!net->waving && (passive || failed) && t - net->last_wave >= 100e-6) {
    net->in[0] = !passive;
    net->in[1] = net->sent;
    net->in[2] = net->received;
    net->in[3] = failed;
    vr_error e = {0};
    if (vr_comm_isum_i64(net->comm, net->in, net->res, 4, &net->wave, &e)) {
      /* Without waves no rank can end: the job ends here (mpirun stops
       * the others). */
      vr_flow_fail(f, &e);
      vr_comm_abort(net->comm, 1);
    }
    net->waving = true;
    net->last_wave = t;
  }
  if (net->waving && vr_comm_test(net->wave)) {
    net->waving = false;
    net->wave = NULL;
    net->waves++;
    const int64_t *res = net->res, *prev = net->prev;
    if (res[3] > 0) { /* a rank failed: every rank stops at this wave */
      if (!atomic_load(&f->failed)) {
        net->other_failed = true;
        fail(f, VR_E_IO, "stopped: another rank failed");
      }
      net->over = true;
    } else if (res[0] == 0 && res[1] == res[2] && net->have_prev && prev[0] == 0 &&
               prev[1] == res[1] && prev[2] == res[2]) {
      atomic_store(&f->terminated, 1);
      net->over = true;
    }
    memcpy(net->prev, res, sizeof net->prev);
    net->have_prev = true;
    if (net->over) vr_flow_wake(f);
    did = true;
  }
  return did;
}

bool vr_flow_net_progress(vr_flow *f) {
  vr_flow_net *net = f->net;
  if (pthread_mutex_trylock(&net->lock) != 0) return false;
  bool did = progress(f);
  pthread_mutex_unlock(&net->lock);
  return did;
}

vr_status vr_flow_net_start(vr_flow *f, vr_comm *comm, int send_batch, int send_credit,
                            vr_error *err) {
  vr_flow_net *net = calloc(1, sizeof *net);
  if (!net) return vr_error_set(err, VR_E_NOMEM, "ray flow: out of memory");
  net->comm = comm;
  net->batch = send_batch > 0 ? send_batch : 256;
  net->credit0 = send_credit > 0 ? send_credit : RAY_CREDIT;
  if (net->batch > net->credit0) net->batch = (int)net->credit0;
  net->out = calloc((size_t)f->nranks, sizeof *net->out);
  net->credit = calloc((size_t)f->nranks, sizeof *net->credit);
  net->owed = calloc((size_t)f->nranks, sizeof *net->owed);
  if (!net->out || !net->credit || !net->owed) {
    free(net->out), free(net->credit), free(net->owed), free(net);
    return vr_error_set(err, VR_E_NOMEM, "ray flow: out of memory");
  }
  pthread_mutex_init(&net->lock, NULL);
  pthread_mutex_init(&net->news_lock, NULL);
  for (int r = 0; r < f->nranks; r++) {
    pthread_mutex_init(&net->out[r].lock, NULL);
    net->credit[r] = net->credit0;
  }
  net->self.f = f;
  net->self.index = f->threads;
  f->net = net;
  /* What this rank holds from earlier passes, told to the others. */
  for (int c = 0; c < f->ncells; c++)
    if (vr_domains_loaded(f->d, c)) vr_flow_net_resident(f, c, true);
  return VR_OK;
}

void vr_flow_net_stop(vr_flow *f, vr_flow_stats *stats) {
  vr_flow_net *net = f->net;
  if (!net) return;
  /* The workers are gone.  After a failure here the other ranks learn of
   * it from the next wave; then (or after the end) the sends MPI still
   * holds are waited for: all were received when the run ended normally.
   * After a failure a receiver may never take a message; its buffer stays
   * MPI's (and the job is ended by the caller). */
  pthread_mutex_lock(&net->lock);
  while (!net->over) {
    if (!progress(f)) nanosleep(&(struct timespec){0, 50000}, NULL);
  }
  while (atomic_load(&f->terminated) && net->npend) send_control(f);
  if (!atomic_load(&f->terminated)) net->npend = 0;
  pthread_mutex_unlock(&net->lock);
  if (stats) {
    stats->sent += (uint64_t)net->sent;
    stats->received += (uint64_t)net->received;
    stats->messages += net->messages;
    stats->bytes_sent += net->bytes;
    stats->waves += net->waves;
    stats->credit_waits += net->credit_waits;
    stats->ray_messages += net->ray_messages;
    stats->peak_uncredited = (uint64_t)net->peak_owed;
    stats->ray_bytes += net->ray_bytes;
    stats->spilled += net->self.st.spilled;
    stats->other_rank_failed = net->other_failed;
  }
  for (int r = 0; r < f->nranks; r++) {
    free(net->out[r].rays);
    pthread_mutex_destroy(&net->out[r].lock);
  }
  pthread_mutex_destroy(&net->lock);
  pthread_mutex_destroy(&net->news_lock);
  free(net->out);
  free(net->credit);
  free(net->owed);
  free(net->news);
  free(net->pend);
  free(net);
  f->net = NULL;
}
