/* OpenEXR core streams shared by image_exr.c and spectral_exr.c (see
 * exr_stream.h). */
#define _GNU_SOURCE /* O_DIRECT */
#include "exr_stream.h"

#include <errno.h>
#include <fcntl.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <unistd.h>

#include "image_internal.h"

/* ------------------------------------------- large outputs with O_DIRECT */

/* A multiple of any logical block size (O_DIRECT aligns offsets, lengths
 * and addresses to it) and large enough for the disk to stream. */
#define DIRECT_BUF ((size_t)8 << 20)
#define DIRECT_MIN ((uint64_t)64 << 20)
/* What the disk is asked to make stable at a time (see direct_flusher). */
#define DIRECT_FLUSH ((uint64_t)64 << 20)

struct exr_direct {
  int dfd, bfd;           /* the O_DIRECT descriptor; the stream's own */
  unsigned char *buf[2];  /* 2 MiB aligned (vr_image_pixels_alloc) */
  int cur;                /* the buffer being filled */
  uint64_t base;          /* file offset of buf[cur][0] */
  size_t fill;            /* bytes of buf[cur] in use (gaps zeroed) */
  pthread_t io, flusher;
  pthread_mutex_t lock;   /* guards what follows */
  pthread_cond_t cv;
  int job, job_buf;       /* a full buffer handed to the thread, and which */
  uint64_t job_off;
  uint64_t written, asked; /* bytes written by the thread; when a flush was last asked */
  int flush;              /* a flush is asked for */
  int quit, err;          /* err: the first errno */
};

static int write_all(int fd, const unsigned char *p, size_t n, uint64_t off) {
  while (n) {
    ssize_t w = pwrite(fd, p, n, (off_t)off);
    if (w < 0 && errno == EINTR) continue;
    if (w < 0) return errno ? errno : EIO;
    if (w == 0) return EIO;
    p += w, n -= (size_t)w, off += (uint64_t)w;
  }
  return 0;
}

static void *direct_main(void *arg) {
  exr_direct *d = arg;
  pthread_mutex_lock(&d->lock);
  for (;;) {
    while (!d->job && !d->quit) pthread_cond_wait(&d->cv, &d->lock);
    if (!d->job) break;
    const unsigned char *p = d->buf[d->job_buf];
    const uint64_t off = d->job_off;
    pthread_mutex_unlock(&d->lock);
    int e = write_all(d->dfd, p, DIRECT_BUF, off);
    if (e == EINVAL) e = write_all(d->bfd, p, DIRECT_BUF, off); /* O_DIRECT refused */
    pthread_mutex_lock(&d->lock);
    if (e && !d->err) d->err = e;
    d->job = 0;
    d->written += DIRECT_BUF;
    if (d->written - d->asked >= DIRECT_FLUSH) d->flush = 1, d->asked = d->written;
    pthread_cond_broadcast(&d->cv);
  }
  pthread_mutex_unlock(&d->lock);
  return NULL;
}

/* O_DIRECT bypasses the guest's page cache, not a disk's (or a virtual
 * disk's host's) write cache: the fsync of the commit then waits for all
 * that cache holds, 0.45 s for 824 MiB on the guest of docs/benchmarks.md.
 * This thread asks the disk to make the file stable every 64 MiB as it is
 * written, on a thread of its own so the writes go on meanwhile, and the
 * final fsync finds little left.  Its failures are left to that fsync. */
static void *direct_flusher(void *arg) {
  exr_direct *d = arg;
  pthread_mutex_lock(&d->lock);
  for (;;) {
    while (!d->flush && !d->quit) pthread_cond_wait(&d->cv, &d->lock);
    if (!d->flush) break;
    d->flush = 0;
    pthread_mutex_unlock(&d->lock);
    (void)fdatasync(d->dfd);
    pthread_mutex_lock(&d->lock);
  }
  pthread_mutex_unlock(&d->lock);
  return NULL;
}

/* Waits until the thread has nothing in hand; returns the first errno. */
static int direct_wait(exr_direct *d) {
  pthread_mutex_lock(&d->lock);
  while (d->job) pthread_cond_wait(&d->cv, &d->lock);
  int e = d->err;
  pthread_mutex_unlock(&d->lock);
  return e;
}

/* Hands the full buffer to the thread and starts filling the other. */
static int direct_hand_off(exr_direct *d) {
  pthread_mutex_lock(&d->lock);
  while (d->job) pthread_cond_wait(&d->cv, &d->lock);
  d->job = 1;
  d->job_buf = d->cur;
  d->job_off = d->base;
  pthread_cond_broadcast(&d->cv);
  int e = d->err;
  pthread_mutex_unlock(&d->lock);
  d->cur ^= 1;
  d->base += DIRECT_BUF;
  d->fill = 0;
  return e;
}

static int direct_write(exr_direct *d, const unsigned char *p, size_t sz, uint64_t offset) {
  int e = 0;
  if (offset < d->base) { /* below what is staged: once the disk has it */
    const size_t below = d->base - offset < sz ? (size_t)(d->base - offset) : sz;
    if ((e = direct_wait(d)) || (e = write_all(d->bfd, p, below, offset))) return e;
    p += below, sz -= below, offset += below;
  }
  while (sz) {
    const uint64_t at = offset - d->base;
    unsigned char *b = d->buf[d->cur];
    if (at >= DIRECT_BUF) { /* past this buffer: it is complete with zeros */
      memset(b + d->fill, 0, DIRECT_BUF - d->fill);
      d->fill = DIRECT_BUF;
    } else {
      if (at > d->fill) memset(b + d->fill, 0, (size_t)at - d->fill);
      const size_t n = DIRECT_BUF - (size_t)at < sz ? DIRECT_BUF - (size_t)at : sz;
      memcpy(b + at, p, n);
      if ((size_t)at + n > d->fill) d->fill = (size_t)at + n;
      p += n, sz -= n, offset += n;
    }
    if (d->fill == DIRECT_BUF && (e = direct_hand_off(d))) return e;
  }
  return 0;
}

void vr_exr_stream_direct_begin(exr_stream *s, const char *tmp_path, uint64_t expected_bytes) {
  if (s->direct || !s->fp || !tmp_path || expected_bytes < DIRECT_MIN) return;
  exr_direct *d = calloc(1, sizeof *d);
  if (!d) return;
  d->bfd = fileno(s->fp);
  d->dfd = open(tmp_path, O_WRONLY | O_DIRECT | O_CLOEXEC);
  d->buf[0] = vr_image_pixels_alloc(DIRECT_BUF);
  d->buf[1] = vr_image_pixels_alloc(DIRECT_BUF);
  /* The stream's own FILE must hold nothing unwritten: from here on its
   * descriptor is written directly. */
  int ok = d->dfd >= 0 && d->buf[0] && d->buf[1] && fflush(s->fp) == 0;
  if (ok && pthread_mutex_init(&d->lock, NULL) != 0) ok = 0;
  if (ok && pthread_cond_init(&d->cv, NULL) != 0) {
    pthread_mutex_destroy(&d->lock);
    ok = 0;
  }
  if (ok && pthread_create(&d->io, NULL, direct_main, d) != 0) {
    pthread_cond_destroy(&d->cv);
    pthread_mutex_destroy(&d->lock);
    ok = 0;
  }
  if (ok && pthread_create(&d->flusher, NULL, direct_flusher, d) != 0) {
    pthread_mutex_lock(&d->lock);
    d->quit = 1;
    pthread_cond_broadcast(&d->cv);
    pthread_mutex_unlock(&d->lock);
    pthread_join(d->io, NULL);
    pthread_cond_destroy(&d->cv);
    pthread_mutex_destroy(&d->lock);
    ok = 0;
  }
  if (!ok) {
    if (d->dfd >= 0) close(d->dfd);
    free(d->buf[0]);
    free(d->buf[1]);
    free(d);
    return;
  }
  s->direct = d;
}

void vr_exr_stream_direct_end(exr_stream *s) {
  exr_direct *d = s->direct;
  if (!d) return;
  int e = direct_wait(d);
  if (!e && d->fill) e = write_all(d->bfd, d->buf[d->cur], d->fill, d->base);
  pthread_mutex_lock(&d->lock);
  d->quit = 1;
  pthread_cond_broadcast(&d->cv);
  pthread_mutex_unlock(&d->lock);
  pthread_join(d->io, NULL);
  pthread_join(d->flusher, NULL);
  pthread_cond_destroy(&d->cv);
  pthread_mutex_destroy(&d->lock);
  if (close(d->dfd) != 0 && !e) e = errno ? errno : EIO;
  free(d->buf[0]);
  free(d->buf[1]);
  free(d);
  s->direct = NULL;
  if (e && !s->write_errno) s->write_errno = e;
}

/* ------------------------------------------------------------ streams */

int64_t vr_exr_stream_read(exr_const_context_t ctxt, void *user, void *buffer, uint64_t sz,
                           uint64_t offset, exr_stream_error_func_ptr_t error_cb) {
  (void)ctxt;
  (void)error_cb;
  const exr_stream *s = user;
  if (offset >= s->len) return 0;
  uint64_t n = s->len - offset < sz ? s->len - offset : sz;
  memcpy(buffer, s->buf + offset, (size_t)n);
  return (int64_t)n;
}

int64_t vr_exr_stream_size(exr_const_context_t ctxt, void *user) {
  (void)ctxt;
  return (int64_t)((const exr_stream *)user)->len;
}

int64_t vr_exr_stream_write(exr_const_context_t ctxt, void *user, const void *buffer, uint64_t sz,
                            uint64_t offset, exr_stream_error_func_ptr_t error_cb) {
  (void)ctxt;
  (void)error_cb;
  exr_stream *s = user;
  if (s->direct) {
    int e = direct_write(s->direct, buffer, (size_t)sz, offset);
    if (e && !s->write_errno) s->write_errno = e;
    return e ? -1 : (int64_t)sz;
  }
  if (fseeko(s->fp, (off_t)offset, SEEK_SET) != 0 || fwrite(buffer, 1, sz, s->fp) != sz) {
    if (!s->write_errno) s->write_errno = errno ? errno : EIO;
    return -1;
  }
  if (s->af) vr_atomic_file_writeback(s->af, (long long)(offset + sz));
  return (int64_t)sz;
}

/* Read contexts are not locked, so asking for the user data here is safe. */
void vr_exr_on_read_error(exr_const_context_t ctxt, exr_result_t code, const char *msg) {
  void *user = NULL;
  if (!ctxt || exr_get_user_data(ctxt, &user) != EXR_ERR_SUCCESS || !user) return;
  exr_stream *s = user;
  if (!s->message[0])
    snprintf(s->message, sizeof s->message, "%s", msg ? msg : exr_get_default_error_message(code));
}

/* Write contexts hold their lock while reporting, so this one must not call
 * back into OpenEXR; stream_write keeps the errno that matters. */
void vr_exr_on_write_error(exr_const_context_t ctxt, exr_result_t code, const char *msg) {
  (void)ctxt;
  (void)code;
  (void)msg;
}

vr_status vr_exr_read_failed(vr_error *err, const char *path, const exr_stream *s,
                             exr_result_t rv, const char *doing) {
  return vr_error_at(err, VR_E_PARSE, path, 0, 0, "OpenEXR: %s: %s", doing,
                     s->message[0] ? s->message : exr_get_default_error_message(rv));
}

int vr_exr_find_channel(const exr_attr_chlist_t *ch, const char *name) {
  for (int i = 0; i < ch->num_channels; i++)
    if (strcmp(ch->entries[i].name.str, name) == 0) return i;
  return -1;
}
