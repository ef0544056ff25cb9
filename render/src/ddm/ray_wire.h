/* A ray's form in a message between ranks (flow_net.c): the record with
 * its zero 8-byte words left out.  A mask of 64 bits says which of the
 * record's words follow, in order; the words are copied bit for bit, so a
 * ray arrives exactly as it left (the image does not depend on where a ray
 * was traced).  Unused wavelength slots, a payload's tail, a ray at the
 * origin of an axis: all zeros, all left out.  A camera or path ray with
 * four wavelengths is about 190 bytes instead of 304. */
#ifndef VR_DDM_RAY_WIRE_H
#define VR_DDM_RAY_WIRE_H

#include <stdint.h>
#include <string.h>

#include "vr/flow.h"

#define VR_RAY_WORDS (sizeof(vr_ray) / 8)
_Static_assert(sizeof(vr_ray) % 8 == 0 && sizeof(vr_ray) / 8 <= 64,
               "a ray record is whole 8-byte words, at most 64 of them");
/* The most bytes one ray takes in a message (the mask and every word). */
#define VR_RAY_WIRE_MAX (8 + sizeof(vr_ray))

/* Writes r at out (room for VR_RAY_WIRE_MAX bytes); returns the bytes. */
static inline size_t vr_ray_pack(const vr_ray *r, unsigned char *out) {
  uint64_t w[VR_RAY_WORDS], mask = 0;
  memcpy(w, r, sizeof *r);
  size_t n = 8;
  for (size_t i = 0; i < VR_RAY_WORDS; i++)
    if (w[i]) {
      mask |= (uint64_t)1 << i;
      memcpy(out + n, &w[i], 8);
      n += 8;
    }
  memcpy(out, &mask, 8);
  return n;
}

/* Reads one ray from in (avail bytes left); returns the bytes it took, or
 * 0 if they are not a ray record (a mask naming words a ray does not have,
 * or fewer bytes than the mask says). */
static inline size_t vr_ray_unpack(const unsigned char *in, size_t avail, vr_ray *r) {
  if (avail < 8) return 0;
  uint64_t mask;
  memcpy(&mask, in, 8);
  if (VR_RAY_WORDS < 64 && (mask >> VR_RAY_WORDS)) return 0;
  size_t need = 8 + 8 * (size_t)__builtin_popcountll(mask);
  if (need > avail) return 0;
  uint64_t w[VR_RAY_WORDS];
  size_t n = 8;
  for (size_t i = 0; i < VR_RAY_WORDS; i++) {
    w[i] = 0;
    if (mask >> i & 1) {
      memcpy(&w[i], in + n, 8);
      n += 8;
    }
  }
  memcpy(r, w, sizeof *r);
  return n;
}

#endif
