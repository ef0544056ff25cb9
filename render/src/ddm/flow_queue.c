/* The per-cell ray queues of the flow (flow_internal.h).
 *
 * A queue is a stack of blocks of f->batch rays taken from a pool that all
 * queues share.  Under a memory budget the pool stops growing at the
 * queues' share of the budget, and what no block can take is spilled to an
 * unnamed file (created in the spill folder and unlinked at once, so
 * nothing is left behind even if the process is killed).  The file is a
 * stack of vr_ray records: spilling appends at the end, taking reads back
 * from the end.  Rays of cells that are not loaded are the first to go to
 * disk, since they will wait anyway; rays of loaded cells keep the blocks
 * while there are any. */
#define _GNU_SOURCE /* O_TMPFILE */
#include "ddm/flow_internal.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

void vr_flow_note_bytes(_Atomic long long *now, _Atomic long long *peak, long long delta) {
  long long v = atomic_fetch_add(now, delta) + delta;
  long long p = atomic_load(peak);
  while (v > p && !atomic_compare_exchange_weak(peak, &p, v)) {
  }
}

void vr_flow_queue_init(vr_flow_queue *q) {
  pthread_mutex_init(&q->lock, NULL);
  q->top = NULL;
  q->spill_fd = -1;
  q->spilled = 0;
  atomic_store(&q->pending, 0);
}

/* ---- the block pool ---- */

static vr_flow_block *block_get(vr_flow *f) {
  pthread_mutex_lock(&f->pool_lock);
  vr_flow_block *b = f->free_blocks;
  if (b) {
    f->free_blocks = b->next;
  } else if (!f->max_blocks || f->nblocks < f->max_blocks) {
    b = malloc(f->block_bytes);
    if (b) {
      f->nblocks++;
      vr_flow_note_bytes(&f->queue_bytes, &f->peak_queue_bytes, (long long)f->block_bytes);
    }
  }
  pthread_mutex_unlock(&f->pool_lock);
  if (b) {
    b->next = NULL;
    b->n = 0;
  }
  return b;
}

static void block_put(vr_flow *f, vr_flow_block *b) {
  pthread_mutex_lock(&f->pool_lock);
  b->next = f->free_blocks;
  f->free_blocks = b;
  pthread_mutex_unlock(&f->pool_lock);
}

void vr_flow_queue_free(vr_flow *f, vr_flow_queue *q) {
  while (q->top) {
    vr_flow_block *b = q->top;
    q->top = b->next;
    free(b);
    f->nblocks--;
  }
  if (q->spill_fd >= 0) close(q->spill_fd);
  pthread_mutex_destroy(&q->lock);
}

void vr_flow_pool_free(vr_flow *f) {
  while (f->free_blocks) {
    vr_flow_block *b = f->free_blocks;
    f->free_blocks = b->next;
    free(b);
  }
}

/* ---- spilling ---- */

static int open_spill(const vr_flow *f) {
  const char *dir = f->spill_dir;
  if (!dir || !*dir) dir = getenv("TMPDIR");
  if (!dir || !*dir) dir = "/tmp";
  int fd = open(dir, O_TMPFILE | O_RDWR | O_CLOEXEC, 0600);
  if (fd >= 0) return fd;
  /* File systems without O_TMPFILE: a named file, unlinked at once. */
  char path[4200];
  snprintf(path, sizeof path, "%s/vr-spill-XXXXXX", dir);
  fd = mkstemp(path);
  if (fd >= 0) unlink(path);
  return fd;
}

static bool write_at(int fd, const void *p, size_t n, off_t at) {
  const unsigned char *b = p;
  while (n) {
    ssize_t w = pwrite(fd, b, n, at);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) return false;
    b += w;
    n -= (size_t)w;
    at += w;
  }
  return true;
}

static bool read_at(int fd, void *p, size_t n, off_t at) {
  unsigned char *b = p;
  while (n) {
    ssize_t r = pread(fd, b, n, at);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) return false;
    b += r;
    n -= (size_t)r;
    at += r;
  }
  return true;
}

/* Called with q->lock held. */
static bool spill(vr_flow *f, vr_flow_queue *q, const vr_ray *rays, int n, vr_flow_worker *w) {
  if (q->spill_fd < 0 && (q->spill_fd = open_spill(f)) < 0) return false;
  if (!write_at(q->spill_fd, rays, (size_t)n * sizeof *rays, (off_t)(q->spilled * sizeof *rays)))
    return false;
  q->spilled += (size_t)n;
  w->st.spilled += (uint64_t)n;
  vr_flow_note_bytes(&f->spill_bytes, &f->peak_spill_bytes, (long long)n * (long long)sizeof *rays);
  return true;
}

/* ---- put and take ---- */

bool vr_flow_queue_put(vr_flow *f, int c, const vr_ray *rays, int n, vr_flow_worker *w) {
  vr_flow_queue *q = &f->q[c];
  int b = f->batch;
  pthread_mutex_lock(&q->lock);
  bool ok = true;
  /* Under a budget, rays of a cell that is not loaded go to disk once the
   * pool is half used: the blocks are kept for the cells being traced. */
  bool to_disk = f->budget && !vr_domains_loaded(f->d, c) &&
                 atomic_load(&f->queue_bytes) > (long long)(f->queue_cap / 2) &&
                 (!q->top || q->top->n == b);
  int done = 0;
  while (!to_disk && done < n) {
    if (!q->top || q->top->n == b) {
      vr_flow_block *nb = block_get(f);
      if (!nb) break;
      nb->next = q->top;
      q->top = nb;
    }
    int take = b - q->top->n < n - done ? b - q->top->n : n - done;
    memcpy(q->top->rays + q->top->n, rays + done, (size_t)take * sizeof *rays);
    q->top->n += take;
    done += take;
  }
  if (done < n) ok = f->budget && spill(f, q, rays + done, n - done, w);
  int added = ok ? n : done;
  atomic_fetch_add(&q->pending, added);
  atomic_fetch_add(&f->queued, added);
  pthread_mutex_unlock(&q->lock);
  if (added) vr_flow_wake(f);
  /* On failure the caller fails the run: rays are lost. */
  return ok;
}

int vr_flow_queue_take(vr_flow *f, int c, vr_ray *batch, vr_flow_worker *w) {
  (void)w;
  vr_flow_queue *q = &f->q[c];
  pthread_mutex_lock(&q->lock);
  int n = 0;
  while (n < f->batch && q->top) {
    vr_flow_block *t = q->top;
    int k = t->n < f->batch - n ? t->n : f->batch - n;
    t->n -= k;
    memcpy(batch + n, t->rays + t->n, (size_t)k * sizeof *batch);
    n += k;
    if (!t->n) {
      q->top = t->next;
      block_put(f, t);
    }
  }
  if (!n && q->spilled) {
    n = q->spilled < (size_t)f->batch ? (int)q->spilled : f->batch;
    off_t at = (off_t)((q->spilled - (size_t)n) * sizeof *batch);
    if (read_at(q->spill_fd, batch, (size_t)n * sizeof *batch, at)) {
      q->spilled -= (size_t)n;
      vr_flow_note_bytes(&f->spill_bytes, &f->peak_spill_bytes,
                         -(long long)n * (long long)sizeof *batch);
    } else {
      /* The spill file cannot be read back: those rays are lost. */
      vr_error e = {0};
      vr_error_set(&e, VR_E_IO, "ray flow: cannot read back rays spilled for sub-domain %d: %s",
                   c, strerror(errno));
      vr_flow_fail(f, &e);
      n = 0;
    }
  }
  if (n) {
    atomic_fetch_sub(&q->pending, n);
    atomic_fetch_sub(&f->queued, n);
  }
  pthread_mutex_unlock(&q->lock);
  return n;
}

void vr_flow_wake(vr_flow *f) {
  if (!atomic_load_explicit(&f->sleepers, memory_order_relaxed)) return;
  pthread_mutex_lock(&f->idle_lock);
  pthread_cond_broadcast(&f->idle_cv);
  pthread_mutex_unlock(&f->idle_lock);
}
