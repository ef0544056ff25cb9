/* The OpenEXR core streams both EXR files of image/ use: reading from a
 * whole file held in memory, whose user data also catches OpenEXR's first
 * error message so ours can name the file, and writing onto the temporary
 * file of a vr_atomic_file, keeping the errno that matters. */
#ifndef VR_EXR_STREAM_H
#define VR_EXR_STREAM_H

#include "vr/atomic_file.h"
#include <stddef.h>
#include <stdio.h>

#include <openexr.h>

#include "vr/error.h"
#include "vr/image.h"

typedef struct exr_stream {
  const unsigned char *buf; /* reading: the whole file */
  size_t len;
  FILE *fp;                 /* writing: the temporary file */
  vr_atomic_file *af;       /* writing: if set, its writeback is started as chunks land */
  int write_errno;
  char message[256];        /* first error OpenEXR reported while reading */
} exr_stream;

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
/* Index in the channel list of a channel called name, or -1. */
int vr_exr_find_channel(const exr_attr_chlist_t *ch, const char *name);

/* The colour attributes of vr/image.h (exr_colour.c; checked first with
 * vr_exr_colour_check of image_internal.h): written into a part's header
 * before exr_write_header (c may be NULL). */
exr_result_t vr_exr_colour_set(exr_context_t ctxt, int part, const vr_exr_colour *c);
/* Whether name is one of the attributes vr_exr_colour_set writes. */
int vr_exr_colour_attr(const char *name);

#endif
