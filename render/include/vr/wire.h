/* The pieces of a ray's form in a message between ranks (ddm/ray_wire.c
 * for the flow's own fields, the passes' codecs for their payloads):
 * unsigned integers as LEB128 varints (7 bits a byte, low bits first),
 * signed ones zigzagged first, and doubles as 4-byte floats when the float
 * holds them exactly, else as all 8 bytes, a flag bit saying which.  Every
 * piece is exact: what is read back is bit for bit what was written.
 *
 * A writer is given room for the most its record can take; a reader is
 * given the bytes left and fails (returns false, reads nothing more)
 * rather than read past them. */
#ifndef VR_WIRE_H
#define VR_WIRE_H

#include <float.h>
#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vr_wire_in {
  const unsigned char *p, *end;
} vr_wire_in;

static inline unsigned char *vr_wire_put_u64(unsigned char *o, uint64_t v) {
  while (v >= 0x80) {
    *o++ = (unsigned char)(v | 0x80);
    v >>= 7;
  }
  *o++ = (unsigned char)v;
  return o;
}

/* Reads a varint of at most 10 bytes whose value fits in 64 bits. */
static inline bool vr_wire_get_u64(vr_wire_in *in, uint64_t *v) {
  uint64_t x = 0;
  for (int shift = 0; shift < 64; shift += 7) {
    if (in->p >= in->end) return false;
    unsigned char b = *in->p++;
    if (shift == 63 && b > 1) return false; /* past 64 bits */
    x |= (uint64_t)(b & 0x7F) << shift;
    if (!(b & 0x80)) {
      *v = x;
      return true;
    }
  }
  return false;
}

static inline unsigned char *vr_wire_put_i64(unsigned char *o, int64_t v) {
  return vr_wire_put_u64(o, ((uint64_t)v << 1) ^ (uint64_t)(v >> 63));
}

static inline bool vr_wire_get_i64(vr_wire_in *in, int64_t *v) {
  uint64_t z;
  if (!vr_wire_get_u64(in, &z)) return false;
  *v = (int64_t)((z >> 1) ^ (~(z & 1) + 1));
  return true;
}

static inline bool vr_wire_get_bytes(vr_wire_in *in, void *dst, size_t n) {
  if ((size_t)(in->end - in->p) < n) return false;
  memcpy(dst, in->p, n);
  in->p += n;
  return true;
}

/* Whether d goes as a float: the float's bits widen back to d's exactly
 * (zeros of both signs, infinities and every float value; a NaN only if
 * its payload survives the round trip). */
static inline bool vr_wire_is_float(double d) {
  if (isfinite(d) && fabs(d) > FLT_MAX) return false; /* (float)d would be undefined */
  float f = (float)d;
  double back = (double)f;
  return memcmp(&back, &d, sizeof d) == 0;
}

/* Writes d as a float if as_double is false, else as a double. */
static inline unsigned char *vr_wire_put_num(unsigned char *o, double d, bool as_double) {
  if (as_double) {
    memcpy(o, &d, 8);
    return o + 8;
  }
  float f = (float)d;
  memcpy(o, &f, 4);
  return o + 4;
}

static inline bool vr_wire_get_num(vr_wire_in *in, double *d, bool as_double) {
  if (as_double) return vr_wire_get_bytes(in, d, 8);
  float f;
  if (!vr_wire_get_bytes(in, &f, 4)) return false;
  *d = (double)f;
  return true;
}

/* d rounded to the nearest float, as a double (the form that goes in 4
 * bytes); infinities stay, NaN stays NaN, a finite value beyond the
 * float's range stays as it is (it goes in 8 bytes). */
static inline double vr_wire_round(double d) {
  if (isfinite(d) && fabs(d) > FLT_MAX) return d;
  return (double)(float)d;
}

#ifdef __cplusplus
}
#endif

#endif
