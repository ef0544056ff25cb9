/* The small tables every sub-domain sees, replicated rather than cut into
 * cells (DESIGN §6.3): the scene's bounds, each object's area and, for
 * rects, the frame of its (u, v) coordinates (the photochromic state map is
 * laid over it), and the geometry of emissive objects, which next-event
 * estimation and photon emission sample wherever the path is.  They are
 * built once, with the geometry cache, and stored in its manifest. */
#ifndef VR_SCENE_TABLES_H
#define VR_SCENE_TABLES_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vr_scene_tables {
  double bmin[3], bmax[3];      /* bounds of every primitive (empty scene: all zero) */
  uint64_t ntris, nspheres;     /* in the whole scene, each counted once */
  uint64_t degenerate_dropped;  /* zero-area mesh triangles removed */
  size_t nobjects;
  double *object_area;          /* m², world space, per object */
  double (*object_box)[6];      /* per object: its primitives' bounds, lo then hi (all
                                   zero for an object without any) */
  uint64_t *object_prims;       /* per object: its triangles, or 1 for a sphere */
  /* Rect objects: world point = corner + u eu + v ev for (u, v) in [0,1]². */
  uint8_t *is_rect;
  double (*rect_frame)[9];      /* corner, eu, ev */
  /* Emissive objects, for uniform area sampling: triangles [emit_begin,
   * emit_end) of emit_verts (9 floats each, the corners as the renderer
   * intersects them) with emit_cdf their cumulative area within the
   * object; or a sphere (sphere[3] > 0: centre and radius). */
  uint64_t *emit_begin, *emit_end;
  uint64_t nemit;
  float *emit_verts;
  double *emit_cdf;
  double (*sphere)[4];
} vr_scene_tables;

void vr_scene_tables_free(vr_scene_tables *t);

/* Uniform area sampling of an emissive object, as vr_geometry_sample_object
 * does on the whole geometry (the same triangle for the same u1 and the
 * same point for the same u2, u3): point, unit geometric normal; p = n = 0
 * for an object out of range or not emissive. */
void vr_scene_tables_sample_object(const vr_scene_tables *t, uint32_t object, double u1,
                                   double u2, double u3, double p[3], double n[3]);

#ifdef __cplusplus
}
#endif
#endif
