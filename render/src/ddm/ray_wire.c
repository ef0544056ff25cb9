/* A ray's wire form (ray_wire.h). */
#include "ddm/ray_wire.h"

#include <string.h>

#include "vr/wire.h"

enum {
  WF_PAYLOAD_CODEC = 1u << 8, /* the payload in its pass's form */
  WF_KIND_PURPOSE = 1u << 9,  /* kind (< 2) and purpose (< 128) in one byte */
  WF_ALL = (1u << 10) - 1
};
#define PAYLOAD_WORDS (VR_RAY_PAYLOAD / 8)
_Static_assert(VR_RAY_PAYLOAD % 8 == 0 && PAYLOAD_WORDS <= 32,
               "a payload is whole 8-byte words, at most 32 of them");

/* The eight numbers in their wire order. */
static void numbers(vr_ray *r, double *n[8]) {
  for (int a = 0; a < 3; a++) {
    n[a] = &r->org[a];
    n[3 + a] = &r->dir[a];
  }
  n[6] = &r->tnear;
  n[7] = &r->tmax;
}

void vr_ray_round(vr_ray *r) {
  double *n[8];
  numbers(r, n);
  for (int i = 0; i < 8; i++) *n[i] = vr_wire_round(*n[i]);
}

/* Whether the pass writes its payload in its own form. */
static bool has_codec(const vr_flow_ops *ops) { return ops && ops->pack && ops->unpack; }

size_t vr_ray_pack(const vr_flow_ops *ops, const void *ctx, const vr_ray *r0,
                   unsigned char *out) {
  vr_ray r = *r0;
  double *n[8];
  numbers(&r, n);
  unsigned flags = 0;
  for (int i = 0; i < 8; i++)
    if (!vr_wire_is_float(*n[i])) flags |= 1u << i;
  bool codec = has_codec(ops);
  if (codec) flags |= WF_PAYLOAD_CODEC;
  if (r.kind < 2 && r.purpose < 128) flags |= WF_KIND_PURPOSE;
  unsigned char *o = vr_wire_put_u64(out, flags);
  o = vr_wire_put_u64(o, (uint32_t)r.cell); /* a ray's cell is never negative: the flow sets it */
  if (flags & WF_KIND_PURPOSE) {
    *o++ = (unsigned char)(r.kind | r.purpose << 1);
  } else {
    *o++ = r.kind;
    *o++ = r.purpose;
  }
  o = vr_wire_put_u64(o, r.crossings);
  for (int i = 0; i < 8; i++) o = vr_wire_put_num(o, *n[i], flags >> i & 1);
  if (codec) return (size_t)(o - out) + ops->pack(ctx, r.payload, o);
  uint64_t w[PAYLOAD_WORDS];
  memcpy(w, r.payload, sizeof w);
  uint32_t mask = 0;
  unsigned char *m = o;
  o += 4;
  for (int i = 0; i < PAYLOAD_WORDS; i++)
    if (w[i]) {
      mask |= 1u << i;
      memcpy(o, &w[i], 8);
      o += 8;
    }
  memcpy(m, &mask, 4);
  return (size_t)(o - out);
}

size_t vr_ray_unpack(const vr_flow_ops *ops, const void *ctx, const unsigned char *in,
                     size_t avail, vr_ray *r) {
  vr_wire_in rd = {in, in + avail};
  uint64_t flags, cell, crossings;
  if (!vr_wire_get_u64(&rd, &flags) || flags & ~(uint64_t)WF_ALL) return 0;
  if (!vr_wire_get_u64(&rd, &cell) || cell > INT32_MAX) return 0;
  unsigned char kp[2];
  if (flags & WF_KIND_PURPOSE) {
    if (!vr_wire_get_bytes(&rd, kp, 1)) return 0;
    kp[1] = kp[0] >> 1;
    kp[0] &= 1;
  } else if (!vr_wire_get_bytes(&rd, kp, 2)) {
    return 0;
  }
  if (!vr_wire_get_u64(&rd, &crossings) || crossings > UINT16_MAX) return 0;
  vr_ray t;
  memset(&t, 0, sizeof t);
  t.cell = (int32_t)cell;
  t.kind = kp[0];
  t.purpose = kp[1];
  t.crossings = (uint16_t)crossings;
  double *n[8];
  numbers(&t, n);
  for (int i = 0; i < 8; i++)
    if (!vr_wire_get_num(&rd, n[i], flags >> i & 1)) return 0;
  bool codec = has_codec(ops);
  if (!(flags & WF_PAYLOAD_CODEC) != !codec) return 0; /* not the form this pass writes */
  if (codec) {
    size_t used = ops->unpack(ctx, rd.p, (size_t)(rd.end - rd.p), t.payload);
    if (!used || used > (size_t)(rd.end - rd.p)) return 0;
    rd.p += used;
  } else {
    uint32_t mask;
    if (!vr_wire_get_bytes(&rd, &mask, 4)) return 0;
    if (PAYLOAD_WORDS < 32 && mask >> PAYLOAD_WORDS) return 0;
    for (int i = 0; i < PAYLOAD_WORDS; i++)
      if (mask >> i & 1 && !vr_wire_get_bytes(&rd, t.payload + 8 * i, 8)) return 0;
  }
  *r = t;
  return (size_t)(rd.p - in);
}
