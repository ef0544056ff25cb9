/* The scene's objects as the renderer intersects them: one world-space
 * triangle soup (rects, boxes and meshes) plus analytic spheres, with the
 * object each primitive belongs to, per-corner (u,v) for the photochromic
 * state maps, per-object areas and uniform area sampling of emitters.
 *
 * Building is deterministic: triangles come in object order, then in the
 * order of the mesh file (after Assimp's triangulation).  Every triangle is
 * wound counter-clockwise seen from the side its geometric normal points to,
 * which is the rect's given normal, a box's outside, or a mesh's own
 * winding; a mirroring transform keeps that side by swapping two corners. */
#ifndef VR_GEOMETRY_H
#define VR_GEOMETRY_H

#include <stddef.h>
#include <stdint.h>

#include "vr/error.h"
#include "vr/scene.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vr_geometry {
  size_t nverts;  float *verts;      /* xyz, world space */
  size_t ntris;   uint32_t *tris;    /* 3 vertex indices per triangle */
  uint32_t *tri_object;              /* object index (into vr_scene.objects) per triangle */
  float *tri_uv;                     /* 6 per triangle: object-local (u,v) at each corner, for the
                                        photochromic state map: rect -> [0,1]^2 over the rectangle
                                        (u along the width, v along the height); box -> per-face
                                        [0,1]^2; mesh -> its first UV set or 0 */
  uint8_t *tri_rgb;                  /* 9 per triangle: 8-bit sRGB colour codes at each corner
                                        (a mesh's vertex colours, 255 where an object has
                                        none), or NULL when no object uses any */
  float *vnormals;                   /* per-vertex shading normals (3 per vertex, unit, world
                                        space), or NULL when no object has any (all flat).  A
                                        vertex without one (rect, box, mesh without normals) holds
                                        (0,0,0): use the geometric normal there. */
  size_t nspheres; double *spheres;  /* cx, cy, cz, r per sphere, world space */
  uint32_t *sphere_object;
  double bmin[3], bmax[3];           /* bounds of everything (empty scene: all zero) */
  /* per object: */
  size_t nobjects; double *object_area;   /* m^2, world space */
  size_t *object_tri_begin, *object_tri_end; /* triangle range of each object (spheres: 0,0) */
  size_t degenerate_dropped;         /* zero-area triangles removed from meshes */
  /* for sampling: */
  double *tri_cdf;                   /* per triangle: area of its object's triangles up to and
                                        including it (the last one of an object: its area) */
  size_t *object_sphere;             /* index into spheres, or SIZE_MAX for a triangle object */
} vr_geometry;

/* Builds the geometry of every object of the scene, reading mesh files with
 * Assimp.  Errors name the scene line ("room.scn:12: ..."):
 *   VR_E_IO     a mesh file that cannot be opened (with Assimp's message);
 *   VR_E_PARSE  a mesh file Assimp cannot read (its message), a PLY header
 *               that is cut short or a binary PLY body shorter than its
 *               header announces, a mesh with no triangles;
 *   VR_E_RANGE  a non-finite vertex, a mesh whose triangles are all degenerate,
 *               a non-uniform scale on a sphere, a singular transform, a
 *               non-positive size, radius or box extent, a zero rect normal.
 * Mesh triangles of zero area, or of area < 1e-12 x (diagonal of the mesh's
 * world bounds)^2, are dropped and counted in degenerate_dropped.
 * The rect's u axis (width) is v x normal, its v axis (height) the up hint
 * made perpendicular to the normal; a hint that is zero or parallel to the
 * normal falls back to the parser's default (world z, or world y when the
 * normal is within ~2.6 degrees of vertical). */
vr_status vr_geometry_build(const vr_scene *scene, vr_geometry **out, vr_error *err);

/* The same for objects [first, last) only: the per-object arrays still have
 * one entry per object of the scene (zero area and no triangles for the
 * others), triangles keep their objects' scene indices, and the bounds are
 * those of what was built.  This is how the geometry cache reads a scene
 * larger than memory: one object at a time.  meshes (may be NULL) keeps
 * mesh files read once for later objects that name them again. */
struct vr_mesh_cache;
vr_status vr_geometry_build_range(const vr_scene *scene, size_t first, size_t last,
                                  struct vr_mesh_cache *meshes, vr_geometry **out,
                                  vr_error *err);
void vr_geometry_destroy(vr_geometry *g);

/* Uniform area sampling of an emissive object (triangles by area, then
 * uniform in the triangle; spheres uniform on the surface): point, geometric
 * normal, pdf per unit area = 1/object_area[object].  u1 picks the triangle
 * (unused for spheres), u2 and u3 the point; all in [0,1).  An object index
 * out of range gives p = n = 0. */
void vr_geometry_sample_object(const vr_geometry *g, uint32_t object, double u1, double u2,
                               double u3, double p[3], double n[3]);

/* The six faces of a box from lo to hi in its own coordinates, as the
 * geometry builds them: corner, edge u, edge v, u x v pointing outwards,
 * in the order +x, -x, +y, -y, +z, -z. */
void vr_box_faces(const double lo[3], const double hi[3], double face[6][9]);

#ifdef __cplusplus
}
#endif
#endif
