/* A path's payload on the wire between ranks (vr_flow_ops round, pack and
 * unpack of every pass that carries a vr_payload).  The form:
 *   - a varint of flags (PW_*);
 *   - the stream as a varint, unless it is the index (camera paths) or
 *     VR_STREAM_SENSOR + the index (sensor paths), or as its offset from
 *     VR_STREAM_PHOTON (photons); the sample and the index as varints; the depth as a byte; target and source in one byte when nwl
 *     is the scene's and there is no sky patch and no hole (PW_USUAL),
 *     else target, nwl, source, patch and holes as a byte each; the flags
 *     as a varint; the medium zigzagged;
 *   - the weight, the wavelengths (the first alone when the others follow
 *     from it, vr_wavelength_at) and the throughputs, each as a float
 *     where a float holds it exactly, else as a double (a flag bit each);
 *   - the portal distance and the ray cone when they are not zero.
 * round() rounds the weight, the throughputs and the portal distance to
 * float at each push, so that they go in 4 bytes, and zeroes the unused
 * slots from nwl on; the wavelengths are made so (vr_wavelengths).  A path ray with four wavelengths takes 33
 * bytes (41 with a ray cone). */
#include <math.h>
#include <string.h>

#include "integrators/pass.h"
#include "vr/wire.h"

enum { /* the usual ones in the low 7 bits: a varint of one byte */
  PW_PORTAL = 1u << 0,        /* portal_t follows */
  PW_USUAL = 1u << 1,         /* nwl the scene's, no patch, no holes, target and source
                                 below 16: one byte for the four */
  PW_CONE = 1u << 2,          /* cone_w, cone_a follow */
  PW_WL_RULE = 1u << 3,       /* only wl[0]: the others follow from it */
  PW_STREAM_SHIFT = 4,        /* bits 4-5: how the stream goes (STREAM_*) */
  PW_WEIGHT_DOUBLE = 1u << 6,
  PW_ALL_SLOTS = 1u << 7,     /* all VR_MAX_WL slots follow, not nwl */
  PW_PORTAL_DOUBLE = 1u << 8,
  PW_WL_DOUBLE_SHIFT = 9,     /* bit PW_WL_DOUBLE_SHIFT + i: wl[i] as a double */
  PW_BETA_DOUBLE_SHIFT = 9 + VR_MAX_WL
};
enum {
  STREAM_RAW = 0,    /* a varint */
  STREAM_INDEX = 1,  /* the index (a camera path's pixel) */
  STREAM_SENSOR = 2, /* VR_STREAM_SENSOR + the index (a sensor point's path) */
  STREAM_PHOTON = 3  /* VR_STREAM_PHOTON + a varint */
};
_Static_assert(PW_BETA_DOUBLE_SHIFT + VR_MAX_WL <= 63, "the flags fit in 64 bits");
/* The longest form: the flags' varint (4 bytes for 25 bits), the stream
 * (10), sample and index (5 each), the six small fields (6), the flags
 * (3), the medium (5), then weight, every wavelength and throughput and
 * the portal distance as doubles, and the cone (8). */
_Static_assert(4 + 10 + 5 + 5 + 6 + 3 + 5 + 8 * (2 + 2 * VR_MAX_WL) + 8 <= VR_RAY_PAYLOAD_WIRE_MAX,
               "a payload's longest form fits the wire's bound");

static bool zero_tail(const double *v, int from) {
  for (int i = from; i < VR_MAX_WL; i++)
    if (v[i] != 0 || signbit(v[i])) return false;
  return true;
}

void vr_payload_round(const void *ctx, unsigned char *payload) {
  (void)ctx;
  vr_payload p;
  memcpy(&p, payload, sizeof p);
  p.weight = vr_wire_round(p.weight);
  /* The slots from nwl on are not read by any pass: zeros (they go as
   * nothing), where a contribution copied whole may have left anything. */
  int n = p.nwl < VR_MAX_WL ? p.nwl : VR_MAX_WL;
  for (int i = 0; i < VR_MAX_WL; i++) {
    p.beta[i] = i < n ? vr_wire_round(p.beta[i]) : 0.0;
    if (i >= n) p.wl[i] = 0.0;
  }
  p.portal_t = vr_wire_round(p.portal_t);
  memcpy(payload, &p, sizeof p);
}

size_t vr_payload_pack(const void *ctx, const unsigned char *payload, unsigned char *out) {
  const vr_pass *c = ctx;
  vr_payload p;
  memcpy(&p, payload, sizeof p);
  uint64_t fl = 0;
  int n = p.nwl <= VR_MAX_WL ? p.nwl : VR_MAX_WL;
  if (p.nwl > VR_MAX_WL || (n < VR_MAX_WL && !(zero_tail(p.wl, n) && zero_tail(p.beta, n)))) {
    fl |= PW_ALL_SLOTS;
    n = VR_MAX_WL;
  }
  if (!vr_wire_is_float(p.weight)) fl |= PW_WEIGHT_DOUBLE;
  if (p.portal_t != 0 || signbit(p.portal_t)) {
    fl |= PW_PORTAL;
    if (!vr_wire_is_float(p.portal_t)) fl |= PW_PORTAL_DOUBLE;
  }
  uint32_t cw, ca;
  memcpy(&cw, &p.cone_w, 4);
  memcpy(&ca, &p.cone_a, 4);
  if (cw | ca) fl |= PW_CONE;
  int nwl_sent = n;
  if (n > 1 && c && c->rs) {
    bool rule = true;
    for (int i = 1; i < n && rule; i++) {
      double x = vr_wavelength_at(c->rs, p.wl[0], i);
      rule = memcmp(&x, &p.wl[i], sizeof x) == 0;
    }
    if (rule) {
      fl |= PW_WL_RULE;
      nwl_sent = 1;
    }
  }
  for (int i = 0; i < nwl_sent; i++)
    if (!vr_wire_is_float(p.wl[i])) fl |= 1ull << (PW_WL_DOUBLE_SHIFT + i);
  for (int i = 0; i < n; i++)
    if (!vr_wire_is_float(p.beta[i])) fl |= 1ull << (PW_BETA_DOUBLE_SHIFT + i);
  uint64_t stream_code = STREAM_RAW;
  if (p.stream == p.index)
    stream_code = STREAM_INDEX;
  else if (p.stream == VR_STREAM_SENSOR + p.index)
    stream_code = STREAM_SENSOR;
  else if (p.stream >= VR_STREAM_PHOTON)
    stream_code = STREAM_PHOTON;
  fl |= stream_code << PW_STREAM_SHIFT;
  if (c && c->rs && p.nwl == c->rs->nwl && p.patch == VR_NO_PATCH && !p.holes && p.target < 16 &&
      p.source < 16)
    fl |= PW_USUAL;

  unsigned char *o = vr_wire_put_u64(out, fl);
  if (stream_code == STREAM_RAW) o = vr_wire_put_u64(o, p.stream);
  if (stream_code == STREAM_PHOTON) o = vr_wire_put_u64(o, p.stream - VR_STREAM_PHOTON);
  o = vr_wire_put_u64(o, p.sample);
  o = vr_wire_put_u64(o, p.index);
  *o++ = p.depth;
  if (fl & PW_USUAL) {
    *o++ = (unsigned char)(p.target | p.source << 4);
  } else {
    *o++ = p.target;
    *o++ = p.nwl;
    *o++ = p.source;
    *o++ = p.patch;
    *o++ = p.holes;
  }
  o = vr_wire_put_u64(o, p.flags);
  o = vr_wire_put_i64(o, p.medium);
  o = vr_wire_put_num(o, p.weight, fl & PW_WEIGHT_DOUBLE);
  for (int i = 0; i < nwl_sent; i++) o = vr_wire_put_num(o, p.wl[i], fl >> (PW_WL_DOUBLE_SHIFT + i) & 1);
  for (int i = 0; i < n; i++) o = vr_wire_put_num(o, p.beta[i], fl >> (PW_BETA_DOUBLE_SHIFT + i) & 1);
  if (fl & PW_PORTAL) o = vr_wire_put_num(o, p.portal_t, fl & PW_PORTAL_DOUBLE);
  if (fl & PW_CONE) {
    memcpy(o, &cw, 4);
    memcpy(o + 4, &ca, 4);
    o += 8;
  }
  return (size_t)(o - out);
}

size_t vr_payload_unpack(const void *ctx, const unsigned char *in, size_t avail,
                         unsigned char *payload) {
  const vr_pass *c = ctx;
  vr_wire_in rd = {in, in + avail};
  vr_payload p;
  memset(&p, 0, sizeof p);
  uint64_t fl, v;
  int64_t m;
  if (!vr_wire_get_u64(&rd, &fl) || fl >> (PW_BETA_DOUBLE_SHIFT + VR_MAX_WL)) return 0;
  uint64_t stream_code = fl >> PW_STREAM_SHIFT & 3;
  if (stream_code == STREAM_RAW || stream_code == STREAM_PHOTON) {
    if (!vr_wire_get_u64(&rd, &p.stream)) return 0;
    if (stream_code == STREAM_PHOTON) {
      if (p.stream > UINT64_MAX - VR_STREAM_PHOTON) return 0;
      p.stream += VR_STREAM_PHOTON;
    }
  }
  if (!vr_wire_get_u64(&rd, &v) || v > UINT32_MAX) return 0;
  p.sample = (uint32_t)v;
  if (!vr_wire_get_u64(&rd, &v) || v > UINT32_MAX) return 0;
  p.index = (uint32_t)v;
  if (stream_code == STREAM_INDEX) p.stream = p.index;
  if (stream_code == STREAM_SENSOR) p.stream = VR_STREAM_SENSOR + p.index;
  unsigned char b[6];
  if (fl & PW_USUAL) {
    if (!c || !c->rs || !vr_wire_get_bytes(&rd, b, 2)) return 0;
    p.depth = b[0];
    p.target = b[1] & 15;
    p.source = b[1] >> 4;
    p.nwl = (uint8_t)c->rs->nwl;
    p.patch = VR_NO_PATCH;
    p.holes = 0;
  } else {
    if (!vr_wire_get_bytes(&rd, b, 6)) return 0;
    p.depth = b[0];
    p.target = b[1];
    p.nwl = b[2];
    p.source = b[3];
    p.patch = b[4];
    p.holes = b[5];
  }
  if (!vr_wire_get_u64(&rd, &v) || v > UINT16_MAX) return 0;
  p.flags = (uint16_t)v;
  if (!vr_wire_get_i64(&rd, &m) || m < INT32_MIN || m > INT32_MAX) return 0;
  p.medium = (int32_t)m;
  if (!vr_wire_get_num(&rd, &p.weight, fl & PW_WEIGHT_DOUBLE)) return 0;
  int n = fl & PW_ALL_SLOTS ? VR_MAX_WL : p.nwl;
  if (n > VR_MAX_WL) return 0;
  int nwl_sent = n;
  if (fl & PW_WL_RULE) {
    if (n < 2 || !c || !c->rs) return 0;
    nwl_sent = 1;
  }
  /* Bits for slots the record does not have make it no record. */
  for (int i = 0; i < VR_MAX_WL; i++)
    if ((i >= nwl_sent && fl >> (PW_WL_DOUBLE_SHIFT + i) & 1) || (i >= n && fl >> (PW_BETA_DOUBLE_SHIFT + i) & 1))
      return 0;
  for (int i = 0; i < nwl_sent; i++)
    if (!vr_wire_get_num(&rd, &p.wl[i], fl >> (PW_WL_DOUBLE_SHIFT + i) & 1)) return 0;
  if (fl & PW_WL_RULE)
    for (int i = 1; i < n; i++) p.wl[i] = vr_wavelength_at(c->rs, p.wl[0], i);
  for (int i = 0; i < n; i++)
    if (!vr_wire_get_num(&rd, &p.beta[i], fl >> (PW_BETA_DOUBLE_SHIFT + i) & 1)) return 0;
  if (fl & PW_PORTAL && !vr_wire_get_num(&rd, &p.portal_t, fl & PW_PORTAL_DOUBLE)) return 0;
  if (!(fl & PW_PORTAL) && fl & PW_PORTAL_DOUBLE) return 0;
  if (fl & PW_CONE) {
    if (!vr_wire_get_bytes(&rd, &p.cone_w, 4) || !vr_wire_get_bytes(&rd, &p.cone_a, 4)) return 0;
  }
  memset(payload, 0, VR_RAY_PAYLOAD);
  memcpy(payload, &p, sizeof p);
  return (size_t)(rd.p - in);
}
