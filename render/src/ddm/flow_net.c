/* Rays between ranks (flow_internal.h, docs/ddm.md "Ranks").
 *
 * Each rank owns some cells.  A ray for a cell another rank owns goes, in
 * the worker's flush, to the outbox of that rank.  Communication is done
 * by the workers themselves, one at a time (vr_flow_net_progress, under a
 * lock it only tries to take), after each batch and while they wait: no
 * thread spins on MPI while the workers trace, which matters when ranks
 * share a machine's cores.  An outbox is sent as one message of vr_ray
 * records (no header: a message of n rays is n x 304 bytes) when it holds
 * send_batch rays or its oldest ray has waited 200 us; received rays go to
 * the queues of their cells.  The ray keeps every property; its cell is
 * already set.
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
 * between its two samples then, so at T the messages sent so far number
 * S and those received number R = S: none is in transit, and every rank
 * is passive.  Nothing can happen after that, and every rank draws the
 * same conclusion from the same sums in the same wave.  A wave that counts
 * a failed rank stops every rank in the same way. */
#include "ddm/flow_internal.h"

#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "vr/comm.h"

typedef struct vr_outbox {
  pthread_mutex_t lock;
  vr_ray *rays;
  size_t n, cap;
  double since; /* when its oldest ray came */
} vr_outbox;

typedef struct vr_pending {
  vr_comm_req *req;
  vr_ray *rays;
} vr_pending;

struct vr_flow_net {
  vr_comm *comm;
  int batch;
  pthread_mutex_t lock; /* one worker at a time talks to MPI */
  vr_outbox *out;
  vr_pending *pend;
  size_t npend, cappend;
  vr_flow_worker self; /* a worker record for queue puts (spill counts) */
  int64_t sent, received;
  uint64_t messages, bytes, waves;
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
  return true;
}

static void fail(vr_flow *f, vr_status st, const char *msg) {
  vr_error e = {0};
  vr_error_set(&e, st, "%s", msg);
  vr_flow_fail(f, &e);
}

/* Hands one message of k rays (buf, freed when MPI is done with it) to
 * MPI; false (the flow failed, buf freed) if it cannot. */
static bool send_one(vr_flow *f, int dest, vr_ray *buf, size_t k) {
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
  if (vr_comm_isend(net->comm, dest, buf, k * sizeof *buf, &req, &e)) {
    free(buf);
    vr_flow_fail(f, &e);
    return false;
  }
  net->pend[net->npend++] = (vr_pending){req, buf};
  net->sent += (int64_t)k;
  net->messages++;
  net->bytes += k * sizeof *buf;
  atomic_fetch_sub(&f->in_flight, (long)k); /* they are in transit now */
  return true;
}

/* Sends the outboxes that are full enough or old enough. */
static bool send_outboxes(vr_flow *f) {
  vr_flow_net *net = f->net;
  bool did = false;
  double t = now();
  for (int dest = 0; dest < f->nranks; dest++) {
    if (dest == f->rank) continue;
    vr_outbox *o = &net->out[dest];
    pthread_mutex_lock(&o->lock);
    if (!o->n || (o->n < (size_t)net->batch && t - o->since < 200e-6)) {
      pthread_mutex_unlock(&o->lock);
      continue;
    }
    vr_ray *rays = o->rays;
    size_t n = o->n;
    o->rays = NULL;
    o->n = o->cap = 0;
    pthread_mutex_unlock(&o->lock);
    /* At most send_batch rays a message: a worker's flush can bring more
     * at once. */
    for (size_t at = 0; at < n;) {
      size_t k = n - at < (size_t)net->batch ? n - at : (size_t)net->batch;
      vr_ray *buf = k == n ? rays : malloc(k * sizeof *buf);
      if (buf && buf != rays) memcpy(buf, rays + at, k * sizeof *buf);
      if (!buf || !send_one(f, dest, buf, k)) {
        if (buf != rays) free(rays);
        if (!buf) fail(f, VR_E_NOMEM, "ray flow: out of memory for a message");
        return true;
      }
      at += k;
    }
    if (n > (size_t)net->batch) free(rays);
    did = true;
  }
  /* Messages MPI has finished with give their buffers back. */
  for (size_t i = 0; i < net->npend;) {
    if (vr_comm_test(net->pend[i].req)) {
      free(net->pend[i].rays);
      net->pend[i] = net->pend[--net->npend];
    } else {
      i++;
    }
  }
  return did;
}

/* Receives what has arrived into the queues of its cells. */
static bool receive(vr_flow *f) {
  vr_flow_net *net = f->net;
  bool did = false;
  int src;
  size_t bytes;
  while (vr_comm_poll(net->comm, &src, &bytes)) {
    vr_ray *rays = malloc(bytes ? bytes : 1);
    vr_error e = {0};
    if (!rays) {
      fail(f, VR_E_NOMEM, "ray flow: out of memory for a message");
      return true;
    }
    if (vr_comm_recv(net->comm, src, rays, bytes, &e)) {
      free(rays);
      vr_flow_fail(f, &e);
      return true;
    }
    size_t n = bytes / sizeof *rays;
    atomic_fetch_add(&f->in_flight, (long)n); /* here now: counted before they are visible */
    net->received += (int64_t)n;
    /* Senders flush cell by cell, so a message is runs of one cell. */
    for (size_t i = 0; i < n;) {
      size_t j = i + 1;
      while (j < n && rays[j].cell == rays[i].cell && j - i < (size_t)f->batch) j++;
      int c = rays[i].cell;
      if (c < 0 || c >= f->ncells || !vr_flow_mine(f, c) ||
          !vr_flow_queue_put(f, c, rays + i, (int)(j - i), &net->self)) {
        fail(f, VR_E_NOMEM, c >= 0 && c < f->ncells && vr_flow_mine(f, c)
                                ? "ray flow: a queue can neither grow nor spill"
                                : "ray flow: a message for a sub-domain this rank does not own");
        break;
      }
      i = j;
    }
    free(rays);
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

vr_status vr_flow_net_start(vr_flow *f, vr_comm *comm, int send_batch, vr_error *err) {
  vr_flow_net *net = calloc(1, sizeof *net);
  if (!net) return vr_error_set(err, VR_E_NOMEM, "ray flow: out of memory");
  net->comm = comm;
  net->batch = send_batch > 0 ? send_batch : 256;
  net->out = calloc((size_t)f->nranks, sizeof *net->out);
  if (!net->out) {
    free(net);
    return vr_error_set(err, VR_E_NOMEM, "ray flow: out of memory");
  }
  pthread_mutex_init(&net->lock, NULL);
  for (int r = 0; r < f->nranks; r++) pthread_mutex_init(&net->out[r].lock, NULL);
  net->self.f = f;
  net->self.index = f->threads;
  f->net = net;
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
  while (atomic_load(&f->terminated) && net->npend) send_outboxes(f);
  if (!atomic_load(&f->terminated)) net->npend = 0;
  pthread_mutex_unlock(&net->lock);
  if (stats) {
    stats->sent += (uint64_t)net->sent;
    stats->received += (uint64_t)net->received;
    stats->messages += net->messages;
    stats->bytes_sent += net->bytes;
    stats->waves += net->waves;
    stats->spilled += net->self.st.spilled;
    stats->other_rank_failed = net->other_failed;
  }
  for (int r = 0; r < f->nranks; r++) {
    free(net->out[r].rays);
    pthread_mutex_destroy(&net->out[r].lock);
  }
  pthread_mutex_destroy(&net->lock);
  free(net->out);
  free(net->pend);
  free(net);
  f->net = NULL;
}
