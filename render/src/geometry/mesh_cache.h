/* Meshes read once per run: a scene that places the same mesh file many
 * times (a hotel floor with one bed model in every room) reads and
 * triangulates it with Assimp once.  Least recently used files are dropped
 * when the cache would hold more than its byte limit.  Not thread-safe:
 * one cache per building thread.  Private to render/. */
#ifndef VR_MESH_CACHE_H
#define VR_MESH_CACHE_H

#include <stddef.h>

#include "geometry/mesh_assimp.h"
#include "vr/error.h"

typedef struct vr_mesh_cache vr_mesh_cache;

vr_mesh_cache *vr_mesh_cache_create(size_t max_bytes);
void vr_mesh_cache_destroy(vr_mesh_cache *c);

/* The mesh of path, read now or earlier; valid until the next call on c
 * (which may drop it).  Errors are vr_mesh_read's. */
vr_status vr_mesh_cache_get(vr_mesh_cache *c, const char *path, const vr_mesh_data **out,
                            vr_error *err);

/* What a mesh holds in memory. */
size_t vr_mesh_data_bytes(const vr_mesh_data *m);

#endif
