/* The OpenEXR core streams both EXR files of image/ use: reading from a
 * whole file held in memory, whose user data also catches OpenEXR's first
 * error message so ours can name the file, and writing onto the temporary
 * file of a vr_atomic_file, keeping the errno that matters. */
#ifndef VR_EXR_STREAM_H
#define VR_EXR_STREAM_H

#include "vr/atomic_file.h"
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include <openexr.h>

#include "vr/error.h"
#include "vr/image.h"

typedef struct exr_direct exr_direct;

typedef struct exr_stream {
  const unsigned char *buf; /* reading: the whole file */
  size_t len;
  FILE *fp;                 /* writing: the temporary file */
  vr_atomic_file *af;       /* writing: if set, its writeback is started as chunks land */
  exr_direct *direct;       /* writing: if set, bytes are staged and written past the page cache */
  int write_errno;
  char message[256];        /* first error OpenEXR reported while reading */
} exr_stream;

/* Large outputs (expected_bytes of 64 MiB or more) past the page cache.
 * Copying hundreds of megabytes into the kernel's page cache costs CPU time
 * that the pixels need, and its writeback ran at about half the disk's
 * direct speed on the 2-core guest of docs/benchmarks.md, so the final
 * fsync waited for it.  Instead the bytes are staged in two 8 MiB buffers;
 * each full one is written by a thread of the stream's own with O_DIRECT
 * (aligned offsets and lengths) while the other fills.  Writes below the
 * staged part (the chunk offset table at exr_finish) and the last partial
 * buffer go through the stream's own descriptor, after the disk has what
 * lies below.  Anything refused (a file system without O_DIRECT: the
 * stream stays as it is; O_DIRECT writes refused: that buffer through the
 * page cache) falls back to the page cache.  After begin, every write goes
 * through vr_exr_stream_write until vr_exr_stream_direct_end. */
void vr_exr_stream_direct_begin(exr_stream *s, const char *tmp_path, uint64_t expected_bytes);
/* Writes what is still staged, waits for the writer thread and closes the
 * O_DIRECT descriptor; the first failure's errno goes to s->write_errno.
 * Nothing to do when direct is NULL. */
void vr_exr_stream_direct_end(exr_stream *s);

int64_t vr_exr_stream_read(exr_const_context_t ctxt, void *user, void *buffer, uint64_t sz,
                           uint64_t offset, exr_stream_error_func_ptr_t error_cb);
int64_t vr_exr_stream_size(exr_const_context_t ctxt, void *user);
int64_t vr_exr_stream_write(exr_const_context_t ctxt, void *user, const void *buffer, uint64_t sz,
                            uint64_t offset, exr_stream_error_func_ptr_t error_cb);
/* Read contexts are not locked, so asking for the user data is safe there. */
void vr_exr_on_read_error(exr_const_context_t ctxt, exr_result_t code, const char *msg);
/* Write contexts hold their lock while reporting: no call back into OpenEXR. */
void vr_exr_on_write_error(exr_const_context_t ctxt, exr_result_t code, const char *msg);

/* A read failure naming the file: OpenEXR's own message when the stream
 * caught one, else its default text for rv. */
vr_status vr_exr_read_failed(vr_error *err, const char *path, const exr_stream *s,
                             exr_result_t rv, const char *doing);
/* After exr_encoding_choose_default_routines on a ZIP or ZIPS part: wraps
 * its deflate step so that a chunk whose deflated size equals its packed
 * size is stored raw, as the reader takes it (exr_zip_guard.c; OpenEXR
 * issue #2306).  Other parts are left as they are. */
exr_result_t vr_exr_guard_zip(exr_context_t ctxt, int part, exr_encode_pipeline_t *enc);
/* Index in the channel list of a channel called name, or -1. */
int vr_exr_find_channel(const exr_attr_chlist_t *ch, const char *name);

/* The colour attributes of vr/image.h (exr_colour.c; checked first with
 * vr_exr_colour_check of image_internal.h): written into a part's header
 * before exr_write_header (c may be NULL). */
exr_result_t vr_exr_colour_set(exr_context_t ctxt, int part, const vr_exr_colour *c);
/* Whether name is one of the attributes vr_exr_colour_set writes. */
int vr_exr_colour_attr(const char *name);

#endif
