/* What a ray of the camera, sensor, UV and photon passes carries through
 * the ray flow (vr_ray.payload): its random-number stream, what it serves
 * (a pixel, a sensor point, a texel), its wavelengths and throughput, and
 * the facts of its path so far that later vertices need. */
#ifndef VR_INTEGRATORS_PAYLOAD_H
#define VR_INTEGRATORS_PAYLOAD_H

#include <stdint.h>

#include "lights/light.h"
#include "run/run.h"
#include "vr/flow.h"

/* What a path's contributions go to. */
enum {
  VR_TARGET_PIXEL = 0,
  VR_TARGET_SENSOR,
  VR_TARGET_TEXEL,
  VR_TARGET_PHOTON,
  VR_TARGET_GATHER /* a final-gather ray of the photon integrator */
};

/* Facts of the path so far (vr_payload.flags), one meaning per bit. */
enum {
  VR_PF_SPECULAR_LAST = 1,   /* the last vertex was the camera or a delta lobe: emission counts */
  VR_PF_HAS_DIFFUSE = 2,     /* photons: a diffuse bounce before */
  VR_PF_HAS_SPECULAR = 4,    /* photons: a specular or glossy bounce before */
  VR_PF_TERMINATED = 8,      /* a dispersive refraction kept the hero wavelength only */
  VR_PF_CAUSTIC_TAKEN = 16,  /* a photon sensor's path added the caustic map at a sparse
                                diffuse vertex: what reaches it through a BSDF XML layer
                                is the map's (those photons are caustic ones) */
  VR_PF_REFLECTED = 32,      /* a sensor path met a non-delta vertex */
  VR_PF_OUTSIDE_LAST = 64,   /* ... and the last one was an exterior surface */
  VR_PF_FAR_DIRECT = 128,    /* a far source's usual photon, not yet scattered (portals) */
  VR_PF_PORTAL_PATH = 256,   /* a portal photon that has not yet reached its portal */
  VR_PF_VISIBLE_SET = 512,   /* SPPM: the pixel's visible point is set (a pbr surface's path
                                went on by its specular part): later vertices are traced */
  VR_PF_FEATURED = 1024,     /* a camera path recorded the denoiser's features */
  VR_PF_SEES_SUN = 2048,     /* a camera path whose every vertex so far was delta (or a pane
                                crossed straight): the eye sees the sun's disc along it */
  VR_PF_SPLIT = 4096         /* photons: a copy of a photon split outside (photon_trace.c) */
};

/* Where the random-number streams of each kind of path begin
 * (vr_payload.stream): a camera path's is its pixel, a sensor path's
 * VR_STREAM_SENSOR + its point, a photon's VR_STREAM_PHOTON + its number,
 * a UV path's VR_STREAM_UV + its unit; the wire form names the camera's,
 * the sensors' and the photons' (payload_wire.c), a UV stream goes whole. */
#define VR_STREAM_SENSOR 0x5E450000000ull
#define VR_STREAM_PHOTON 0x9000000000000ull
#define VR_STREAM_UV 0x0F000000000ull

/* No sky patch (vr_payload.patch). */
#define VR_NO_PATCH 0xFF

typedef struct vr_payload {
  uint64_t stream;
  uint32_t sample;
  uint32_t index;          /* pixel, sensor point, texel */
  uint8_t depth, target, nwl;
  uint8_t source;          /* sensor paths: vr_source_class of the light a shadow ray carries */
  uint16_t flags;          /* VR_PF_* */
  uint8_t patch;           /* sky light: its Tregenza patch (vr/skypatch.h), the ground
                              VR_SKY_GROUND_PATCH; VR_NO_PATCH otherwise */
  uint8_t holes;           /* alpha cut-outs passed through since the last vertex: keys
                              each see-through test's number apart */
  int32_t medium;          /* object whose inside the path is in, -1 outside */
  double weight;           /* sample weight (1/spp, ...), applied on delivery */
  double wl[VR_MAX_WL];
  double beta[VR_MAX_WL];  /* throughput, photon power, or a shadow ray's contribution */
  double portal_t;         /* portal photons: distance left to the portal */
  /* The ray's footprint for texture filtering (a ray cone): its width at
   * the origin and its spread angle (radians), both 0 in a scene without
   * textures (so they cost nothing on the wire: payload_wire.c sends
   * them only when not zero). */
  float cone_w, cone_a;
} vr_payload;
_Static_assert(sizeof(vr_payload) <= VR_RAY_PAYLOAD, "a payload must fit in a ray");

#endif
