/* XXH64 (Collet, xxHash specification v0.1.1, doc/xxhash_spec.md of
 * Cyan4973/xxHash): a fast 64-bit checksum, for detecting damaged or
 * truncated cache files, not for security (use vr/sha256.h where a hash
 * stands for content that someone could forge).  It reads about 8 bytes a
 * cycle, so checking a 100 MB geometry cache file costs milliseconds, not
 * the 0.3 s of SHA-256.
 *
 * The result is the specification's canonical value: the same bytes and
 * seed give the same 64-bit number on any machine (inputs are read as
 * little-endian words whatever the host's byte order). */
#ifndef VR_HASH64_H
#define VR_HASH64_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Streaming state: init, update any number of times with any split of the
 * input, final (which does not change the state, so it may be read at any
 * point). */
typedef struct vr_hash64 {
  uint64_t v[4];
  uint64_t total;
  unsigned char buf[32];
  size_t used;
  uint64_t seed;
} vr_hash64;

void vr_hash64_init(vr_hash64 *h, uint64_t seed);
void vr_hash64_update(vr_hash64 *h, const void *data, size_t len);
uint64_t vr_hash64_final(const vr_hash64 *h);

/* One call: XXH64(data[0..len), seed). */
uint64_t vr_hash64_buffer(const void *data, size_t len, uint64_t seed);

#ifdef __cplusplus
}
#endif
#endif
