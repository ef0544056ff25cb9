/* A ray's form in a message between ranks (flow_net.c). */
#ifndef VR_DDM_RAY_WIRE_H
#define VR_DDM_RAY_WIRE_H

#include <string.h>

#include "vr/flow.h"

/* Bytes of one ray in a message. */
#define VR_RAY_WIRE sizeof(vr_ray)

static inline void vr_ray_pack(const vr_ray *r, unsigned char *out) { memcpy(out, r, sizeof *r); }
static inline void vr_ray_unpack(const unsigned char *in, vr_ray *r) { memcpy(r, in, sizeof *r); }

#endif
