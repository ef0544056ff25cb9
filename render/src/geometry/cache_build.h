/* Building the geometry cache of a scene (docs/ddm.md, "The geometry
 * cache") without ever holding the whole scene: one object at a time is
 * read and written to a spill file, a sample of primitive bounds chooses
 * the kd-tree of cells, the spill file is then dealt out to per-cell parts,
 * and each part becomes a cell file.  Peak memory is one object, the
 * sample (at most VR_CACHE_SAMPLE primitives) and one cell.  Private to
 * render/. */
#ifndef VR_CACHE_BUILD_H
#define VR_CACHE_BUILD_H

#include <stddef.h>
#include <stdint.h>

#include "geometry/cache_format.h"
#include "vr/error.h"
#include "vr/geometry.h"
#include "vr/scene.h"

/* Primitives whose bounds choose the splits: all of them up to this many,
 * else this many chosen by a hash of their index (the same for every run). */
#define VR_CACHE_SAMPLE (1u << 20)

typedef struct vr_cache_build {
  const char *dir;              /* the cache's folder for this S; replaced whole */
  const uint8_t *key;           /* 32 bytes */
  int subdomains;
  const vr_scene *scene;        /* the objects to read, or NULL: */
  const vr_geometry *geometry;  /* an in-memory geometry instead */
  size_t mesh_cache_bytes;      /* meshes kept between objects that repeat them */
  /* Measures what Embree keeps (and the most it holds while building) for
   * a cell's scene, built as vr_domains builds it when it loads the cell. */
  vr_status (*measure)(void *ctx, const void *payload, const vr_cell_meta *meta,
                       uint64_t *retained, uint64_t *peak, vr_error *err);
  void *measure_ctx;
  void (*log)(void *user, const char *line);
  void *user;
} vr_cache_build;

/* Builds the cache in a temporary folder beside b->dir and puts it in
 * b->dir's place; returns its manifest.  On failure b->dir is as it was. */
vr_status vr_cache_build_run(const vr_cache_build *b, vr_cache_manifest **out, vr_error *err);

#endif
