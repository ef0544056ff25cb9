/* The workers of the streaming spectral writer (vr_spectral_exr_write_rows).
 *
 * Each worker claims the next chunk (a block of scanlines, 1 to 32 lines by
 * compression), has the caller fill its rows into the worker's own
 * buffers, checks the values, and runs its own OpenEXR encode pipeline on
 * them: conversion to half when asked, packing, compression.  The
 * pipeline's yield_until_ready_fn then holds it until every chunk above
 * has been written, so chunks reach the file in increasing y whatever the
 * number of threads and their timing, and the file is the same bytes for
 * any count.  OpenEXR 3.1's core locks nothing once the header is written,
 * so that turn is also what keeps two exr_write_scanline_chunk calls apart;
 * the mutex that passes it on orders each write after the one before.
 *
 * A failure (callback error, bad value, OpenEXR or write error) stops the
 * claiming of chunks, releases the workers waiting for a turn that will
 * not come, and keeps the error of the lowest failing chunk: chunks above
 * it may fail or be skipped depending on timing, the ones below are still
 * filled and checked, so the error reported does not depend on timing
 * when the callback's failures do not. */
#include <float.h>
#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "half_convert.h"
#include "spectral_exr_internal.h"

/* Where a pipeline channel's values come from: band b >= 0, -1 - c for
 * R, G, B (c = 0, 1, 2), or the flags. */
#define FROM_FLAGS (-4)

/* From this magnitude on a float rounds to infinity as an IEEE 754-2008
 * binary16: the largest finite half is 65504, the spacing there 32, so
 * 65520 is halfway to the next power of two and the tie goes to the even
 * significand, which is infinity's. */
#define HALF_OVERFLOW 65520.0f

typedef struct shared {
  const vr_spectral_rows_job *job;
  int lines, nchunks;
  int f16c;             /* the workers convert half channels themselves */
  pthread_mutex_t lock; /* guards what follows */
  pthread_cond_t turn;  /* next_write or failed changed */
  int next_claim;       /* next chunk to hand out */
  int next_write;       /* the chunk whose turn it is to be written */
  int failed;           /* lowest failing chunk; nchunks while none */
  vr_status status;     /* and its error */
  vr_error err;
} shared;

typedef struct worker {
  shared *sh;
  int index;  /* the callback's thread argument */
  int chunk;  /* the chunk being encoded */
  int aborted; /* its wait for a turn ended on a lower chunk's failure */
  float *spectra, *rgb;
  uint16_t *hspectra, *hrgb; /* half copies when the worker converts (F16C) */
  int halved;                /* this chunk's half copies are filled */
  uint32_t *flags;
  int32_t *from; /* per pipeline channel, see FROM_FLAGS */
  exr_encode_pipeline_t enc;
  int initialised, routines;
  exr_result_t (*default_pack)(exr_encode_pipeline_t *); /* OpenEXR's, chosen once */
} worker;

static int claim(shared *sh) {
  pthread_mutex_lock(&sh->lock);
  int k = sh->failed == sh->nchunks && sh->next_claim < sh->nchunks ? sh->next_claim++ : -1;
  pthread_mutex_unlock(&sh->lock);
  return k;
}

static void fail(shared *sh, int k, vr_status st, const vr_error *e) {
  pthread_mutex_lock(&sh->lock);
  if (k < sh->failed) {
    sh->failed = k;
    sh->status = st;
    sh->err = *e;
    pthread_cond_broadcast(&sh->turn);
  }
  pthread_mutex_unlock(&sh->lock);
}

/* The pipeline's yield_until_ready_fn: returns when the chunks above this
 * one are all in the file, or with an error when one of them failed. */
static exr_result_t wait_turn(exr_encode_pipeline_t *enc) {
  worker *w = enc->encoding_user_data;
  shared *sh = w->sh;
  pthread_mutex_lock(&sh->lock);
  while (sh->next_write != w->chunk && sh->failed > w->chunk)
    pthread_cond_wait(&sh->turn, &sh->lock);
  int mine = sh->next_write == w->chunk;
  pthread_mutex_unlock(&sh->lock);
  if (mine) return EXR_ERR_SUCCESS;
  w->aborted = 1;
  return EXR_ERR_INCORRECT_CHUNK;
}

static void pass_turn(shared *sh, int k) {
  pthread_mutex_lock(&sh->lock);
  sh->next_write = k + 1;
  pthread_cond_broadcast(&sh->turn);
  pthread_mutex_unlock(&sh->lock);
}

/* ---------------------------------------------------------------- values */

/* NaN says nothing a reader could use and -infinity no physical quantity;
 * with half storage, a finite value that would round to infinity is lost
 * as well.  +infinity is kept. */
static int bad_value(float v, int half) {
  return half ? !(fabsf(v) < HALF_OVERFLOW) & (v != INFINITY) : !(v >= -FLT_MAX);
}

/* Index of the first bad value of v[0..n), or n.  Blocks without a branch
 * per value keep the common case (all good) fast. */
typedef float v4f_ __attribute__((vector_size(16)));
typedef int v4i_ __attribute__((vector_size(16)));

/* Whether any of v[0..m) is bad, four values a step (GCC/Clang vector
 * extensions, SSE2): the same tests as bad_value without a branch. */
static int any_bad(const float *v, size_t m, int half) {
  const v4f_ inf = {INFINITY, INFINITY, INFINITY, INFINITY};
  const float l = half ? (float)HALF_OVERFLOW : -FLT_MAX;
  const v4f_ lim = {l, l, l, l};
  const v4i_ abs_mask = {0x7fffffff, 0x7fffffff, 0x7fffffff, 0x7fffffff};
  v4i_ bad = {0, 0, 0, 0};
  size_t i = 0;
  for (; i + 4 <= m; i += 4) {
    v4f_ x;
    memcpy(&x, v + i, sizeof x);
    if (half) {
      v4f_ ax = (v4f_)((v4i_)x & abs_mask);
      bad |= ~((ax < lim) | (x == inf)); /* NaN compares false: bad */
    } else {
      bad |= ~(x >= lim);
    }
  }
  int any = bad[0] | bad[1] | bad[2] | bad[3];
  for (; i < m; i++) any |= bad_value(v[i], half);
  return any != 0;
}

static size_t first_bad(const float *v, size_t n, int half) {
  for (size_t i0 = 0; i0 < n; i0 += 1024) {
    const size_t m = n - i0 < 1024 ? n - i0 : 1024;
    int any = any_bad(v + i0, m, half);
    if (any)
      for (size_t i = 0; i < m; i++)
        if (bad_value(v[i0 + i], half)) return i0 + i;
  }
  return n;
}

static const char *describe(float v, char buf[64]) {
  if (isnan(v)) return "NaN";
  if (v == -INFINITY) return "-infinity";
  snprintf(buf, 64, "%g, beyond half's range (largest 65504)", (double)v);
  return buf;
}

/* The first bad value in rows y0..y0+rows-1, pixel by pixel, its bands
 * before its R, G, B, as VR_E_RANGE naming the pixel and the band. */
static vr_status check_values(const worker *w, int y0, int rows, vr_error *err) {
  const vr_spectral_rows_job *job = w->sh->job;
  const vr_spectral_exr_layout *L = job->layout;
  const size_t nb = L->nbands, n = (size_t)rows * (size_t)L->width;
  const size_t s = first_bad(w->spectra, n * nb, L->half);
  const size_t c = w->rgb ? first_bad(w->rgb, n * 3, L->half) : n * 3;
  if (s == n * nb && c == n * 3) return VR_OK;
  char what[64];
  if (s / nb <= c / 3) {
    const size_t p = s / nb, b = s % nb;
    const double nm = L->wavelengths_nm[b];
    return vr_error_at(err, VR_E_RANGE, job->path, 0, 0,
                       "pixel (%d, %d), band %zu (%g nm, channel %s) is %s; nothing written",
                       (int)(p % (size_t)L->width), y0 + (int)(p / (size_t)L->width), b, nm,
                       job->names[b], describe(w->spectra[s], what));
  }
  const size_t p = c / 3;
  return vr_error_at(err, VR_E_RANGE, job->path, 0, 0,
                     "RGB preview pixel (%d, %d), channel %c is %s; nothing written",
                     (int)(p % (size_t)L->width), y0 + (int)(p / (size_t)L->width),
                     "RGB"[c % 3], describe(w->rgb[c], what));
}

/* ------------------------------------------------------------- encoding */

/* OpenEXR keeps channels sorted by name ("S0.1000,..." before
 * "S0.380,..."), so each one is looked up once by its name. */
static exr_result_t map_channels(worker *w) {
  const vr_spectral_rows_job *job = w->sh->job;
  const vr_spectral_exr_layout *L = job->layout;
  w->from = malloc((size_t)w->enc.channel_count * sizeof *w->from);
  if (!w->from) return EXR_ERR_OUT_OF_MEMORY;
  for (int c = 0; c < w->enc.channel_count; c++) {
    const char *n = w->enc.channels[c].channel_name;
    int32_t f = INT32_MIN;
    if (L->flags_channel && strcmp(n, L->flags_channel) == 0)
      f = FROM_FLAGS;
    else if (L->rgb && n[0] && !n[1] && strchr("RGB", n[0]))
      f = -1 - (int32_t)(strchr("RGB", n[0]) - "RGB");
    for (size_t b = 0; b < L->nbands && f == INT32_MIN; b++)
      if (strcmp(n, job->names[b]) == 0) f = (int32_t)b;
    if (f == INT32_MIN) return EXR_ERR_INVALID_ARGUMENT; /* cannot happen: we added them */
    w->from[c] = f;
  }
  return EXR_ERR_SUCCESS;
}

/* Every channel reads the worker's buffers as floats (or 32-bit unsigned
 * integers for the flags); OpenEXR converts floats to half channels. */
static void point_channels(worker *w) {
  const vr_spectral_exr_layout *L = w->sh->job->layout;
  const size_t nb = L->nbands, wd = (size_t)L->width;
  for (int c = 0; c < w->enc.channel_count; c++) {
    exr_coding_channel_info_t *ci = &w->enc.channels[c];
    const int32_t f = w->from[c];
    ci->user_bytes_per_element = 4;
    if (f >= 0 && w->halved) {
      /* Band-major per line (vr_half_convert_planar): band f's run. */
      ci->encode_from_ptr = (const uint8_t *)(w->hspectra + (size_t)f * wd);
      ci->user_pixel_stride = (int32_t)sizeof(uint16_t);
      ci->user_data_type = EXR_PIXEL_HALF;
      ci->user_bytes_per_element = 2;
      ci->user_line_stride = (int32_t)(nb * wd * sizeof(uint16_t));
      continue;
    } else if (f >= 0) {
      ci->encode_from_ptr = (const uint8_t *)(w->spectra + f);
      ci->user_pixel_stride = (int32_t)(nb * sizeof(float));
      ci->user_data_type = EXR_PIXEL_FLOAT;
    } else if (f == FROM_FLAGS) {
      ci->encode_from_ptr = (const uint8_t *)w->flags;
      ci->user_pixel_stride = (int32_t)sizeof(uint32_t);
      ci->user_data_type = EXR_PIXEL_UINT;
    } else if (w->halved) {
      ci->encode_from_ptr = (const uint8_t *)(w->hrgb + (-1 - f));
      ci->user_pixel_stride = 3 * (int32_t)sizeof(uint16_t);
      ci->user_data_type = EXR_PIXEL_HALF;
      ci->user_bytes_per_element = 2;
    } else {
      ci->encode_from_ptr = (const uint8_t *)(w->rgb + (-1 - f));
      ci->user_pixel_stride = 3 * (int32_t)sizeof(float);
      ci->user_data_type = EXR_PIXEL_FLOAT;
    }
    ci->user_line_stride = ci->user_pixel_stride * (int32_t)wd;
  }
}

/* Our own packing, in place of OpenEXR's generic one (which converts and
 * byte-swaps element by element through a switch on the types): every
 * channel's buffer already holds the file's type (half, float or uint, see
 * point_channels), so on a little-endian host, whose byte order is the
 * file's, packing is a copy of each line's channel runs: one memcpy for a
 * contiguous run (the half spectra, written band-major by
 * vr_half_convert_planar; the flags), a gather of 2- or 4-byte elements
 * for an interleaved one (float spectra, the RGB preview).  Same bytes as
 * OpenEXR's pack (tests/image/test_spectral_exr_stream.c). */
static exr_result_t pack_native(exr_encode_pipeline_t *e) {
  uint8_t *dst = e->packed_buffer;
  const size_t wd = (size_t)e->chunk.width;
  for (int y = 0; y < e->chunk.height; y++)
    for (int c = 0; c < e->channel_count; c++) {
      const exr_coding_channel_info_t *ch = &e->channels[c];
      const size_t ps = (size_t)ch->user_pixel_stride, bpe = (size_t)ch->bytes_per_element;
      const uint8_t *src = ch->encode_from_ptr + (size_t)y * (size_t)ch->user_line_stride;
      if (ps == bpe)
        memcpy(dst, src, wd * bpe);
      else if (bpe == 2)
        for (size_t x = 0; x < wd; x++) memcpy(dst + 2 * x, src + x * ps, 2);
      else
        for (size_t x = 0; x < wd; x++) memcpy(dst + 4 * x, src + x * ps, 4);
      dst += wd * bpe;
    }
  e->packed_bytes = (uint64_t)(dst - (uint8_t *)e->packed_buffer);
  return EXR_ERR_SUCCESS;
}

/* Every channel handed over in its file type, on a little-endian host:
 * pack_native applies.  Else (floats for half channels when the processor
 * lacks F16C) OpenEXR's packer converts. */
static int native_types(const exr_encode_pipeline_t *e) {
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
  for (int c = 0; c < e->channel_count; c++)
    if (e->channels[c].user_data_type != e->channels[c].data_type ||
        e->channels[c].user_bytes_per_element != e->channels[c].bytes_per_element ||
        e->channels[c].x_samples != 1 || e->channels[c].y_samples != 1)
      return 0;
  return 1;
#else
  (void)e;
  return 0;
#endif
}

static exr_result_t encode_chunk(worker *w, int y0) {
  const vr_spectral_rows_job *job = w->sh->job;
  exr_chunk_info_t cinfo;
  exr_result_t rv = exr_write_scanline_chunk_info(job->ctxt, job->part, y0, &cinfo);
  if (rv != EXR_ERR_SUCCESS) return rv;
  if (w->initialised) {
    rv = exr_encoding_update(job->ctxt, job->part, &cinfo, &w->enc);
  } else {
    rv = exr_encoding_initialize(job->ctxt, job->part, &cinfo, &w->enc);
    if (rv != EXR_ERR_SUCCESS) return rv;
    w->initialised = 1;
    rv = map_channels(w);
  }
  if (rv != EXR_ERR_SUCCESS) return rv;
  point_channels(w);
  if (!w->routines) {
    rv = exr_encoding_choose_default_routines(job->ctxt, job->part, &w->enc);
    if (rv == EXR_ERR_SUCCESS) rv = vr_exr_guard_zip(job->ctxt, job->part, &w->enc);
    if (rv != EXR_ERR_SUCCESS) return rv;
    w->routines = 1;
    w->enc.yield_until_ready_fn = wait_turn; /* the default write_fn stays */
    w->default_pack = w->enc.convert_and_pack_fn;
  }
  w->enc.convert_and_pack_fn = native_types(&w->enc) ? pack_native : w->default_pack;
  w->enc.encoding_user_data = w;
  return exr_encoding_run(job->ctxt, job->part, &w->enc);
}

/* --------------------------------------------------------------- chunks */

static vr_status alloc_buffers(worker *w, vr_error *err) {
  const vr_spectral_exr_layout *L = w->sh->job->layout;
  const size_t n = (size_t)w->sh->lines * (size_t)L->width;
  w->spectra = malloc(n * L->nbands * sizeof(float));
  w->rgb = L->rgb ? malloc(n * 3 * sizeof(float)) : NULL;
  w->flags = L->flags_channel ? malloc(n * sizeof(uint32_t)) : NULL;
  if (L->half) {
    w->hspectra = malloc(n * L->nbands * sizeof(uint16_t));
    w->hrgb = L->rgb ? malloc(n * 3 * sizeof(uint16_t)) : NULL;
  }
  if (!w->spectra || (L->rgb && !w->rgb) || (L->flags_channel && !w->flags) ||
      (L->half && (!w->hspectra || (L->rgb && !w->hrgb))))
    return vr_error_at(err, VR_E_NOMEM, w->sh->job->path, 0, 0,
                       "out of memory for %d lines of %d pixels x %zu bands", w->sh->lines,
                       L->width, L->nbands);
  return VR_OK;
}

/* Chunk k, from the callback to the file (or w->aborted). */
static vr_status write_chunk(worker *w, int k, vr_error *err) {
  const vr_spectral_rows_job *job = w->sh->job;
  const vr_spectral_exr_layout *L = job->layout;
  const int y0 = k * w->sh->lines;
  const int y1 = L->height - y0 < w->sh->lines ? L->height : y0 + w->sh->lines;
  vr_status st = w->spectra ? VR_OK : alloc_buffers(w, err);
  if (st != VR_OK) return st;
  vr_error_clear(err);
  st = job->fill(job->user, w->index, y0, y1, w->spectra, w->rgb, w->flags, err);
  if (st != VR_OK) {
    if (!err->message[0])
      vr_error_set(err, st, "the row callback failed (%s) without a message",
                   vr_status_name(st));
    vr_error_prefix(err, "%s: rows %d to %d: ", job->path, y0, y1 - 1);
    return st;
  }
  st = check_values(w, y0, y1 - y0, err);
  if (st != VR_OK) return st;
  /* Half channels: converted here when the processor can (F16C), else by
   * OpenEXR from the floats; the same bytes either way. */
  const size_t npx = (size_t)(y1 - y0) * (size_t)job->layout->width;
  w->halved = job->layout->half && w->sh->f16c;
  if (w->halved) {
    vr_half_convert_planar(w->spectra, w->hspectra, (size_t)(y1 - y0),
                           (size_t)job->layout->width, job->layout->nbands);
    if (w->rgb) vr_half_convert(w->rgb, w->hrgb, npx * 3);
  }
  w->chunk = k;
  exr_result_t rv = encode_chunk(w, y0);
  if (rv == EXR_ERR_SUCCESS) {
    pass_turn(w->sh, k);
    return VR_OK;
  }
  if (w->aborted) return VR_OK;
  /* Only the worker holding the turn writes, so a write errno is ours. */
  if (job->stream->write_errno)
    return vr_error_at(err, VR_E_IO, job->path, 0, 0, "write failed: %s",
                       strerror(job->stream->write_errno));
  return vr_error_at(err, VR_E_IO, job->path, 0, 0,
                     "OpenEXR could not write the spectral image (rows %d to %d): %s", y0,
                     y1 - 1, exr_get_default_error_message(rv));
}

static void *work(void *arg) {
  worker *w = arg;
  vr_error e;
  for (int k; !w->aborted && (k = claim(w->sh)) >= 0;) {
    vr_status st = write_chunk(w, k, &e);
    if (st != VR_OK) fail(w->sh, k, st, &e);
  }
  if (w->initialised) exr_encoding_destroy(w->sh->job->ctxt, &w->enc);
  free(w->from);
  free(w->spectra);
  free(w->rgb);
  free(w->hspectra);
  free(w->hrgb);
  free(w->flags);
  return NULL;
}

vr_status vr_spectral_exr_write_chunks(const vr_spectral_rows_job *job, vr_error *err) {
  shared sh = {.job = job, .f16c = vr_half_available()};
  exr_result_t rv = exr_get_scanlines_per_chunk(job->ctxt, job->part, &sh.lines);
  if (rv != EXR_ERR_SUCCESS || sh.lines < 1)
    return vr_error_at(err, VR_E_IO, job->path, 0, 0, "OpenEXR gives no chunk size: %s",
                       exr_get_default_error_message(rv));
  sh.nchunks = (job->layout->height - 1) / sh.lines + 1;
  sh.failed = sh.nchunks;
  const int n = job->layout->threads < sh.nchunks ? job->layout->threads : sh.nchunks;
  worker *ws = calloc((size_t)n, sizeof *ws);
  pthread_t *tids = calloc((size_t)n, sizeof *tids);
  if (!ws || !tids) {
    free(ws);
    free(tids);
    return vr_error_at(err, VR_E_NOMEM, job->path, 0, 0, "out of memory for %d workers", n);
  }
  pthread_mutex_init(&sh.lock, NULL);
  pthread_cond_init(&sh.turn, NULL);
  for (int i = 0; i < n; i++) ws[i] = (worker){.sh = &sh, .index = i};
  /* The calling thread is worker 0.  A thread that cannot be started
   * leaves its share to the others: fewer workers, same file. */
  int started = 1;
  while (started < n && pthread_create(&tids[started], NULL, work, &ws[started]) == 0) started++;
  work(&ws[0]);
  for (int i = 1; i < started; i++) pthread_join(tids[i], NULL);
  pthread_cond_destroy(&sh.turn);
  pthread_mutex_destroy(&sh.lock);
  free(ws);
  free(tids);
  if (sh.failed == sh.nchunks) return VR_OK;
  if (err) *err = sh.err;
  return sh.status;
}
