/* Sub-domains (DESIGN §6.3): the scene cut into S axis-aligned cells by a
 * kd-tree of S leaves.  Each cell owns its data: its triangles with
 * cell-local vertex indices, vertices, shading normals, (u, v), object ids,
 * spheres, and its own Embree scene.  Hit records are computed from the
 * cell's arrays alone; what every cell must see (bounds, object areas, rect
 * frames, emitters) is in the small replicated vr_scene_tables.
 *
 * The cells live in a geometry cache on disk (docs/ddm.md): one file per
 * cell, written once per scene and reused until the geometry changes.  A
 * cell is loaded (its file read into one block and its Embree scene built
 * over it in place) and unloaded on demand, so a process may hold only some
 * cells: vr_domains_open reads no cell, vr_domains_load_all loads them all.
 * Embree's own allocations are counted by its device memory monitor, so
 * the bytes a loaded cell costs are known exactly.
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
 * (sun and sky photons) need no special case.  Locating needs only the
 * kd-tree (2S - 1 nodes), never a cell's data.
 *
 * Hits are accepted only inside the current cell's interval: a triangle
 * spanning two cells is stored in both, and the cell whose interval holds
 * the hit is the one that reports it, so the closest hit is the same for any
 * S.  Embree computes in float; the interval ends are rounded once, to the
 * same float on both sides of an interface, so no hit falls between cells.
 *
 * Threads: locate and intersect (in a loaded cell) from any number of
 * threads; load and unload from any thread, the caller guaranteeing that
 * nobody intersects in a cell while it is unloaded. */
#ifndef VR_DOMAINS_H
#define VR_DOMAINS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include "vr/error.h"
#include "vr/geometry.h"
#include "vr/scene.h"
#include "vr/scene_tables.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The most sub-domains a geometry is cut into, and worker threads a
 * process runs (the command line checks them before any work). */
#define VR_MAX_SUBDOMAINS 4096
#define VR_MAX_THREADS 1024

typedef struct vr_domains vr_domains;

typedef struct vr_hit {
  double t;
  uint32_t object;   /* index into the scene's objects */
  uint32_t prim;     /* triangle or sphere index within the cell that reported the hit */
  int32_t cell;      /* that cell */
  bool sphere;
  double p[3];       /* org + t dir, in double */
  double ng[3];      /* unit geometric normal, facing where the geometry says (not flipped) */
  double ns[3];      /* unit shading normal (interpolated vertex normals, else ng) */
  double uv[2];      /* object-local surface coordinates (state maps, textures) */
  double uv_rate;    /* (u, v) units per unit of length there: sqrt(uv area / area) of
                        the triangle (texture footprints); 0 when the uv are degenerate */
  double dpdu[3], dpdv[3]; /* the surface's derivatives along u and v (normal maps' tangent
                              frame); zero when the uv are degenerate, and on spheres */
  bool has_rgb;      /* the cell keeps vertex colours (some PLY file's own) */
  double rgb[3];     /* then: the triangle's, linear, interpolated (white for a triangle
                        of an object without any) */
} vr_hit;

typedef struct vr_domains_options {
  int subdomains;          /* S >= 1 (default 1) */
  /* Folder of the geometry cache (made if missing; the cells of each S in
   * its own subfolder).  NULL: a private temporary folder that
   * vr_domains_destroy removes. */
  const char *cache_dir;
  int threads;             /* threads Embree may use to build a cell (default 1) */
  size_t mesh_cache_bytes; /* meshes kept while building the cache (default 256 MiB) */
  void (*log)(void *user, const char *line); /* cache decisions; may be NULL */
  void *user;
} vr_domains_options;

void vr_domains_options_default(vr_domains_options *o);

/* Opens the sub-domains of a scene: finds its geometry cache for S in
 * o->cache_dir, checks it (manifest and every cell file: header, key,
 * size, checksum) and builds it again when it is missing, stale (the
 * geometry changed), damaged or truncated, saying why through o->log.  No
 * cell is loaded.  The scene must outlive the domains.  Errors name the
 * scene line of a mesh that cannot be read, or the cache folder. */
vr_status vr_domains_open(const vr_scene *scene, const vr_domains_options *o, vr_domains **out,
                          vr_error *err);
/* The cells of an in-memory geometry (tests, benchmarks), in a private
 * temporary cache, every cell loaded. */
vr_status vr_domains_build(const vr_geometry *g, int S, vr_domains **out, vr_error *err);
void vr_domains_destroy(vr_domains *d);

int vr_domains_count(const vr_domains *d);
/* Primitives (triangles + spheres) stored in a cell, counting the shared ones. */
size_t vr_domains_cell_primitives(const vr_domains *d, int cell);
/* Axis-aligned box of a cell, clipped to the scene bounds. */
void vr_domains_cell_bounds(const vr_domains *d, int cell, double lo[3], double hi[3]);
/* The objects with primitives in a cell, increasing. */
const uint32_t *vr_domains_cell_objects(const vr_domains *d, int cell, size_t *n);
/* The geometry cache's key (SHA-256 of the geometry, vr_domains_open). */
void vr_domains_key(const vr_domains *d, uint8_t key[32]);
/* The replicated tables (bounds, areas, rect frames, emitters). */
const vr_scene_tables *vr_domains_tables(const vr_domains *d);

/* The cell holding org + s dir for s just above t, and the parameter at
 * which the ray leaves it (+inf if never).  dir need not be unit. */
int vr_domains_locate(const vr_domains *d, const double org[3], const double dir[3], double t,
                      double *t_exit);

/* Whether the segment org + t dir, t in [t0, t1], can meet any primitive
 * of the cell: it passes through the bounds of the cell's primitives
 * (widened a little, so that Embree's float arithmetic can never find a
 * hit this test ruled out).  Needs only the manifest, not the cell's
 * data: a ray whose segment in a cell misses them goes on to the next
 * cell without the cell being loaded (rays to the sky cross empty cells). */
bool vr_domains_may_hit(const vr_domains *d, int cell, const double org[3], const double dir[3],
                        double t0, double t1);

/* Closest hit in a loaded cell with t in [tnear, tfar]; false if none. */
bool vr_domains_intersect(const vr_domains *d, int cell, const double org[3], const double dir[3],
                          double tnear, double tfar, vr_hit *hit);

/* --- Loading and unloading -------------------------------------------- */

/* What a loaded cell holds: its arrays plus what Embree keeps for its BVH
 * (as measured when the cache was built, or at its last load); and the
 * most it holds while it is being loaded (Embree's build peak). */
size_t vr_domains_cell_bytes(const vr_domains *d, int cell);
size_t vr_domains_cell_load_peak(const vr_domains *d, int cell);
bool vr_domains_loaded(const vr_domains *d, int cell);
/* Seconds the last load of the cell took (reading, checking, building);
 * 0 if it was never loaded. */
double vr_domains_cell_load_seconds(const vr_domains *d, int cell);
/* Reads the cell's file, checks it again (a file changed since the open is
 * refused with VR_E_PARSE naming it) and builds its Embree scene.  Loads
 * of different cells may run at once; loading a loaded cell does nothing. */
vr_status vr_domains_load(vr_domains *d, int cell, vr_error *err);
/* Releases the cell's scene and arrays; nobody may intersect in it. */
void vr_domains_unload(vr_domains *d, int cell);
vr_status vr_domains_load_all(vr_domains *d, vr_error *err);

typedef struct vr_domains_stats {
  uint64_t loads, unloads, bytes_read;
  double load_seconds;            /* reading, checking and building, summed over loads */
  size_t geometry_bytes, embree_bytes;          /* held now */
  size_t peak_geometry, peak_embree, peak_cells; /* the most held at once (cells: both) */
  /* The cache. */
  bool cache_built;               /* built by this open (else reused) */
  char cache_reason[1024];        /* why it was built, or "reused" */
  double cache_seconds;           /* checking or building it */
  uint64_t cache_bytes;           /* its cell files' payloads */
} vr_domains_stats;
void vr_domains_get_stats(const vr_domains *d, vr_domains_stats *out);

#ifdef __cplusplus
}
#endif
#endif
