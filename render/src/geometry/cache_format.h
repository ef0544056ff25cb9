/* The geometry cache on disk (docs/ddm.md, "The geometry cache"): one
 * manifest and one file per sub-domain (cell), each with a header that
 * names what it is (magic, format version, the cache key, counts) and an
 * XXH64 checksum of its bytes, so that a damaged, truncated or foreign file
 * is recognised and never trusted.  Private to render/.
 *
 * A cell file is a 128-byte header and a payload that is the cell's arrays
 * in the order of vr_cell_layout, each section 64-byte aligned, so loading
 * a cell is one read into one aligned block whose sections are used in
 * place (Embree reads the vertices and indices from it without a copy). */
#ifndef VR_CACHE_FORMAT_H
#define VR_CACHE_FORMAT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "vr/error.h"
#include "vr/scene_tables.h"

/* Bumped whenever the layout, the build or the key's contents change. */
#define VR_CACHE_VERSION 5u
#define VR_CELL_HEADER 128
#define VR_CELL_NORMALS 1u
#define VR_CELL_COLOURS 2u /* the cell keeps vertex colours (tri_rgb) */

/* A node of the kd-tree of cells: axis -1 for a leaf. */
typedef struct vr_kd_node {
  int32_t axis, child[2], cell;
  double split;
} vr_kd_node;

/* What the manifest knows of a cell without reading it. */
typedef struct vr_cell_meta {
  double lo[3], hi[3];     /* the box its primitives were assigned by (clipped to the scene) */
  double glo[3], ghi[3];   /* the bounds of its primitives within that box (empty: lo > hi) */
  uint64_t nverts, ntris, nspheres;
  uint32_t flags;          /* VR_CELL_NORMALS, VR_CELL_COLOURS */
  uint64_t payload_bytes, payload_hash;
  uint64_t embree_bytes;   /* what Embree keeps for its BVH, measured when the cache was built */
  uint64_t embree_peak;    /* the most Embree held while building it */
  uint32_t nobjects;
  uint32_t *objects;       /* objects with primitives in the cell, increasing */
} vr_cell_meta;

typedef struct vr_cache_manifest {
  uint8_t key[32];
  int32_t ncells, nnodes;
  vr_kd_node *nodes;
  vr_cell_meta *cells;
  vr_scene_tables tables;
} vr_cache_manifest;

void vr_cache_manifest_free(vr_cache_manifest *m);
/* Written whole or not at all (temporary name, fsync, rename). */
vr_status vr_cache_manifest_write(const char *path, const vr_cache_manifest *m, vr_error *err);
/* VR_E_IO when it cannot be read; VR_E_PARSE naming what is wrong when it
 * is not a manifest of this version, is cut short or fails its checksum. */
vr_status vr_cache_manifest_read(const char *path, vr_cache_manifest **out, vr_error *err);

/* Offsets of a cell payload's sections. */
typedef struct vr_cell_layout {
  size_t verts;    /* float[3 nverts], then 16 zero bytes (Embree reads past the last vertex) */
  size_t normals;  /* float[3 nverts] when VR_CELL_NORMALS, else absent */
  size_t tris;     /* uint32[3 ntris], cell-local vertex indices */
  size_t objects;  /* uint32[ntris], scene object of each triangle */
  size_t uv;       /* float[6 ntris], object-local (u, v) at each corner */
  size_t colours;  /* uint8[9 ntris] when VR_CELL_COLOURS: 8-bit sRGB codes at each corner */
  size_t spheres;  /* double[4 nspheres]: centre, radius */
  size_t sphere_objects; /* uint32[nspheres] */
  size_t total;
} vr_cell_layout;
bool vr_cell_layout_of(uint64_t nverts, uint64_t ntris, uint64_t nspheres, uint32_t flags,
                       vr_cell_layout *L);

/* Writes a cell file whole or not at all; *hash gets the payload's XXH64. */
vr_status vr_cell_file_write(const char *path, uint32_t cell, const uint8_t key[32],
                             const vr_cell_meta *meta, const void *payload, uint64_t *hash,
                             vr_error *err);
/* Maps and verifies a cell file against the manifest's record of it:
 * header, key, counts, size and checksum.  *payload is the file's
 * meta->payload_bytes after its header, 64-byte aligned, mapped read-only
 * from the page cache: no copy of the file and no fresh memory to clear (a
 * load of the hotel's 67 MB cells took 0.30 s to read into new memory and
 * check, 0.03 s mapped); where the file system cannot map files, read
 * into anonymous memory.  Release it with vr_cell_file_release.  The
 * cache's writers replace files by rename, so a mapping keeps the file it
 * mapped; a file changed or cut short in place while mapped would change
 * the geometry or fault.  VR_E_PARSE says what is wrong. */
vr_status vr_cell_file_read(const char *path, uint32_t cell, const uint8_t key[32],
                            const vr_cell_meta *meta, void **payload, vr_error *err);
/* Releases a payload of vr_cell_file_read (NULL: nothing). */
void vr_cell_file_release(void *payload, const vr_cell_meta *meta);
/* The same checks without keeping the payload (streamed in 1 MiB pieces). */
vr_status vr_cell_file_check(const char *path, uint32_t cell, const uint8_t key[32],
                             const vr_cell_meta *meta, vr_error *err);

#endif
