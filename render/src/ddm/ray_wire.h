/* A ray's form in a message between ranks (flow_net.c), exact bit for bit
 * so that the image does not depend on where a ray was traced:
 *   - a varint of flags: bit i (0..7) says the i-th of origin x, y, z,
 *     direction x, y, z, tnear, tmax goes as a double (else as a float,
 *     which holds it exactly: vr_flow_push rounds them); bit 8 says the
 *     payload follows in its pass's form (vr_flow_ops.pack), else as a
 *     32-bit mask of its non-zero 8-byte words and those words; bit 9
 *     says kind and purpose share one byte (kind | purpose << 1);
 *   - the cell (varint), kind and purpose (one byte, or a byte each), the
 *     crossings (varint);
 *   - the eight numbers, 4 or 8 bytes each;
 *   - the payload.
 * A camera or path ray with four wavelengths handed over to another cell
 * takes 74 bytes (304 in memory); docs/ddm.md has the measured means. */
#ifndef VR_DDM_RAY_WIRE_H
#define VR_DDM_RAY_WIRE_H

#include <stddef.h>

#include "vr/flow.h"

/* The most bytes one ray takes in a message. */
#define VR_RAY_WIRE_MAX (3 + 5 + 2 + 3 + 8 * 8 + VR_RAY_PAYLOAD_WIRE_MAX)

/* Writes r at out (room for VR_RAY_WIRE_MAX bytes), its payload by ops'
 * pack if ops has one (ops may be NULL); returns the bytes written. */
size_t vr_ray_pack(const vr_flow_ops *ops, const void *ctx, const vr_ray *r,
                   unsigned char *out);

/* Reads one ray from in (avail bytes left); returns the bytes it took, or
 * 0 if they are not a ray record (flags or fields out of their range, a
 * payload in another form than ops writes, fewer bytes than the record
 * needs). */
size_t vr_ray_unpack(const vr_flow_ops *ops, const void *ctx, const unsigned char *in,
                     size_t avail, vr_ray *r);

/* Rounds r's origin, direction, tnear and tmax to float (the form the
 * wire carries in 4 bytes each). */
void vr_ray_round(vr_ray *r);

#endif
