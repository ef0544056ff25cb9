/* The replicated tables (vr/scene_tables.h) as the geometry cache's build
 * fills them, one chunk of objects at a time (cache_build.c), and the
 * primitives' bounding boxes both use.  Private to render/. */
#ifndef VR_CACHE_TABLES_H
#define VR_CACHE_TABLES_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "vr/error.h"
#include "vr/geometry.h"
#include "vr/scene.h"
#include "vr/scene_tables.h"

void vr_cache_tri_box(const float *verts, const uint32_t *ix, double lo[3], double hi[3]);
void vr_cache_sphere_box(const double *s, double lo[3], double hi[3]);
/* The per-object arrays of nobjects objects, zeroed; false when out of
 * memory (what was allocated is freed with the tables). */
bool vr_cache_tables_alloc(vr_scene_tables *t, size_t nobjects);
/* Adds objects [first, last) of g: the counts, each object's area, bounds,
 * primitive count, sphere, rect frame and (s given) emitter triangles;
 * emit_cap is the emitter arrays' capacity, grown as needed. */
vr_status vr_cache_tables_take(vr_scene_tables *t, size_t *emit_cap, const vr_geometry *g,
                               const vr_scene *s, size_t first, size_t last, vr_error *err);

#endif
