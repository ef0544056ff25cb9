/* One sub-domain's own data as the renderer holds it while the cell is
 * loaded: the arrays of its cache file used in place (vertices, normals,
 * triangles with cell-local indices, objects, (u, v), spheres) and the
 * Embree scene built over them, and the hit record computed from them
 * alone.  Nothing here reaches another cell or a global array.  Private to
 * render/. */
#ifndef VR_CELL_DATA_H
#define VR_CELL_DATA_H

#include <stdbool.h>
#include <stdint.h>

#include <embree3/rtcore.h>

#include "geometry/cache_format.h"
#include "vr/domains.h"
#include "vr/error.h"

typedef struct vr_cell_view {
  uint64_t nverts, ntris, nspheres;
  const float *verts;      /* 3 per vertex (+ 16 zero bytes after the last) */
  const float *normals;    /* 3 per vertex, or NULL; (0,0,0) where a vertex has none */
  const uint32_t *tris;    /* 3 per triangle */
  const uint32_t *objects; /* per triangle */
  const float *uv;         /* 6 per triangle */
  const uint8_t *colours;  /* 9 per triangle (8-bit sRGB at each corner), or NULL */
  const double *spheres;   /* 4 per sphere */
  const uint32_t *sphere_objects;
} vr_cell_view;

/* The sections of a payload laid out as meta says (cache_format.h). */
void vr_cell_view_of(const void *payload, const vr_cell_meta *meta, vr_cell_view *v);

/* An Embree scene over v's triangles (geometry 0, buffers shared with the
 * payload) and spheres (geometry 1), robust and of high quality; NULL scene
 * for an empty cell. */
vr_status vr_cell_scene_build(RTCDevice device, const vr_cell_view *v, RTCScene *out,
                              vr_error *err);

/* Closest hit in the cell's scene with t in [tnear, tfar], with the hit
 * record filled from the cell's own arrays (prim is the cell-local index). */
bool vr_cell_intersect(RTCScene scene, const vr_cell_view *v, const double org[3],
                       const double dir[3], double tnear, double tfar, vr_hit *hit);

#endif
