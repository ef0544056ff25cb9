/* The key of a geometry cache: SHA-256 of everything the cells depend on,
 * so that any change to the geometry makes a new cache and nothing else
 * does (a new spp or material keeps it).  Private to render/. */
#ifndef VR_CACHE_KEY_H
#define VR_CACHE_KEY_H

#include <stdint.h>

#include "vr/error.h"
#include "vr/geometry.h"
#include "vr/scene.h"

/* Over the format version, S and, per object: its shape and parameters,
 * its transform, whether it emits, and for a mesh the SHA-256 of the
 * file's bytes (not its name: the same file reached by another path keeps
 * the cache).  VR_E_IO when a mesh file cannot be read (the error
 * names the scene line). */
vr_status vr_cache_key_scene(const vr_scene *s, int S, uint8_t key[32], vr_error *err);
/* Over the format version, S and the arrays of an in-memory geometry. */
void vr_cache_key_geometry(const vr_geometry *g, int S, uint8_t key[32]);
/* The first 16 hex digits, for messages. */
void vr_cache_key_short(const uint8_t key[32], char out[17]);

#endif
