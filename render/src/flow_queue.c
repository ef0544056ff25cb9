/* The per-cell ray queues of the flow (flow_internal.h).
 *
 * A queue holds rays in memory, and under a memory budget spills what the
 * budget's share for queues cannot hold to an unnamed file (created in
 * the spill folder and unlinked at once, so nothing is left behind even
 * if the process is killed).  The file is a stack of vr_ray records:
 * spilling appends at the end, taking reads back from the end.  Rays of
 * loaded cells are kept in memory while there is room; rays of cells that
 * are not loaded are the first to go to disk, since they will wait anyway. */
#define _GNU_SOURCE /* O_TMPFILE */
#include "flow_internal.h"

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
  q->rays = NULL;
  q->n = q->cap = 0;
  q->spill_fd = -1;
  q->spilled = 0;
  atomic_store(&q->pending, 0);
}

void vr_flow_queue_free(vr_flow_queue *q) {
  free(q->rays);
  if (q->spill_fd >= 0) close(q->spill_fd);
  pthread_mutex_destroy(&q->lock);
}

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

bool vr_flow_queue_put(vr_flow *f, int c, const vr_ray *rays, int n, vr_flow_worker *w) {
  vr_flow_queue *q = &f->q[c];
  pthread_mutex_lock(&q->lock);
  bool ok = true;
  if (q->n + (size_t)n > q->cap) {
    size_t cap = q->cap ? q->cap : 1024;
    while (cap < q->n + (size_t)n) cap *= 2;
    long long more = (long long)((cap - q->cap) * sizeof *q->rays);
    /* Under a budget, memory for queues is capped: past the cap the rays
     * go to disk (the cell's own queue keeps what it already holds). */
    bool room = !f->budget || atomic_load(&f->queue_bytes) + more <= (long long)f->queue_cap;
    vr_ray *r = room ? realloc(q->rays, cap * sizeof *r) : NULL;
    if (r) {
      q->rays = r;
      q->cap = cap;
      vr_flow_note_bytes(&f->queue_bytes, &f->peak_queue_bytes, more);
    } else {
      ok = f->budget && spill(f, q, rays, n, w);
      goto counted;
    }
  }
  if (f->budget && q->n && !vr_domains_loaded(f->d, c) &&
      atomic_load(&f->queue_bytes) > (long long)(f->queue_cap / 2)) {
    /* Over half the share: rays of a cell that is not loaded wait on disk. */
    ok = spill(f, q, rays, n, w);
    goto counted;
  }
  memcpy(q->rays + q->n, rays, (size_t)n * sizeof *rays);
  q->n += (size_t)n;
counted:
  if (ok) {
    atomic_fetch_add(&q->pending, n);
    atomic_fetch_add(&f->queued, n);
  }
  pthread_mutex_unlock(&q->lock);
  return ok;
}

int vr_flow_queue_take(vr_flow *f, int c, vr_ray *batch, vr_flow_worker *w) {
  (void)w;
  vr_flow_queue *q = &f->q[c];
  pthread_mutex_lock(&q->lock);
  int n = 0;
  if (q->n) {
    n = q->n < (size_t)f->batch ? (int)q->n : f->batch;
    q->n -= (size_t)n;
    memcpy(batch, q->rays + q->n, (size_t)n * sizeof *batch);
  } else if (q->spilled) {
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
