/* A guard around OpenEXR Core's deflate step (ZIP and ZIPS parts).
 *
 * OpenEXR Core stores a chunk's deflated bytes when they are no longer
 * than the packed pixels, and its reader takes a chunk whose stored size
 * equals the packed size for the raw pixels.  So a chunk whose deflated
 * size comes out exactly equal to its packed size is written compressed and
 * read back as garbage: OpenEXR issue #2306, fixed in March 2026 by pull
 * request #2307 (">" became ">="), after the 3.1.5 of Debian 12.  It struck
 * here: a 40 x 40 render through a clear pane (sampler sobol, seed 1) had
 * 131 pixels of values up to 1e38 in its EXR while its PNG was right.
 *
 * The guard does what the fix does, whatever the library's version: after
 * the library's own compression, a chunk of equal size whose bytes are not
 * the packed pixels gets the packed pixels instead, so it is stored raw,
 * as the reader will take it. */
#include <stdatomic.h>
#include <string.h>

#include "exr_stream.h"

/* The library's deflate routine: one function for ZIP and ZIPS parts
 * (exr_encoding_choose_default_routines picks the same one every time). */
static _Atomic(exr_result_t (*)(exr_encode_pipeline_t *)) zip_compress;

static exr_result_t guarded_compress(exr_encode_pipeline_t *e) {
  exr_result_t (*inner)(exr_encode_pipeline_t *) = atomic_load(&zip_compress);
  exr_result_t rv = inner(e);
  if (rv == EXR_ERR_SUCCESS && e->compressed_bytes == e->packed_bytes && e->packed_bytes > 0 &&
      e->compressed_buffer != e->packed_buffer &&
      memcmp(e->compressed_buffer, e->packed_buffer, e->packed_bytes) != 0)
    memcpy(e->compressed_buffer, e->packed_buffer, e->packed_bytes);
  return rv;
}

exr_result_t vr_exr_guard_zip(exr_context_t ctxt, int part, exr_encode_pipeline_t *enc) {
  exr_compression_t c;
  exr_result_t rv = exr_get_compression(ctxt, part, &c);
  if (rv != EXR_ERR_SUCCESS) return rv;
  if ((c != EXR_COMPRESSION_ZIP && c != EXR_COMPRESSION_ZIPS) || !enc->compress_fn ||
      enc->compress_fn == guarded_compress)
    return EXR_ERR_SUCCESS;
  atomic_store(&zip_compress, enc->compress_fn);
  enc->compress_fn = guarded_compress;
  return EXR_ERR_SUCCESS;
}
