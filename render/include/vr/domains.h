/* Sub-domains (DESIGN §6.3): the scene cut into S axis-aligned cells by a
 * kd-tree of S leaves, each leaf owning the triangles and spheres that touch
 * it in its own Embree scene.
 *
 * A ray is followed through the cells by parameter, never by a point: its
 * origin and direction stay what they were when it was created, and only
 * the start of its parameter interval moves to the interface where it
 * enters the next cell.  vr_domains_locate finds the cell holding the ray
 * just after a parameter t by descending the tree with t against each split
 * plane's crossing parameter, so the cells met by one ray form a strictly
 * increasing sequence of intervals without any epsilon: a ray starting on an
 * interface goes to the side it is heading for, a ray lying in a split plane
 * stays on the upper side, and a ray parallel to a plane never crosses it.
 * The outermost cells extend to infinity, so rays from outside the scene
 * (sun and sky photons) need no special case.
 *
 * Hits are accepted only inside the current cell's interval: a triangle
 * spanning two cells is stored in both, and the cell whose interval holds
 * the hit is the one that reports it, so the closest hit is the same for any
 * S.  Embree computes in float; the interval ends are rounded once, to the
 * same float on both sides of an interface, so no hit falls between cells.
 *
 * Thread-safe after vr_domains_build: any number of threads may locate and
 * intersect at once.  Loading and unloading of cells under a memory budget
 * (and MPI ranks owning cells) would replace the per-leaf scenes built here
 * by ones built on demand; the interface below does not change. */
#ifndef VR_DOMAINS_H
#define VR_DOMAINS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include "vr/error.h"
#include "vr/geometry.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vr_domains vr_domains;

typedef struct vr_hit {
  double t;
  uint32_t object;   /* index into the scene's objects */
  uint32_t prim;     /* global triangle index, or sphere index when sphere */
  bool sphere;
  double p[3];       /* org + t dir, in double */
  double ng[3];      /* unit geometric normal, facing where the geometry says (not flipped) */
  double ns[3];      /* unit shading normal (interpolated vertex normals, else ng) */
  double uv[2];      /* object-local surface coordinates (photochromic state map) */
} vr_hit;

/* Cuts the geometry into S >= 1 cells: the cell with the most primitives is
 * split at the median of their centroids along the longest axis of its box
 * (the spatial middle when that would leave a side empty), until there are
 * S.  g must outlive the domains. */
vr_status vr_domains_build(const vr_geometry *g, int S, vr_domains **out, vr_error *err);
void vr_domains_destroy(vr_domains *d);

int vr_domains_count(const vr_domains *d);
/* Primitives (triangles + spheres) stored in a cell, counting the shared ones. */
size_t vr_domains_cell_primitives(const vr_domains *d, int cell);
/* Axis-aligned box of a cell, clipped to the scene bounds. */
void vr_domains_cell_bounds(const vr_domains *d, int cell, double lo[3], double hi[3]);

/* The cell holding org + s dir for s just above t, and the parameter at
 * which the ray leaves it (+inf if never).  dir need not be unit. */
int vr_domains_locate(const vr_domains *d, const double org[3], const double dir[3], double t,
                      double *t_exit);

/* Closest hit in cell with t in [tnear, tfar]; false if none. */
bool vr_domains_intersect(const vr_domains *d, int cell, const double org[3], const double dir[3],
                          double tnear, double tfar, vr_hit *hit);

#ifdef __cplusplus
}
#endif
#endif
