/* Computing the geometry cache's key (cache_key.h). */
#include "geometry/cache_key.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "geometry/cache_format.h"
#include "geometry/rad_read.h"
#include "vr/sha256.h"

static void from_hex(const char hex[65], uint8_t key[32]) {
  for (int i = 0; i < 32; i++) {
    unsigned v = 0;
    sscanf(hex + 2 * i, "%2x", &v);
    key[i] = (uint8_t)v;
  }
}

static void add(vr_sha256 *c, const void *p, size_t n) { vr_sha256_update(c, p, n); }
static void add_u64(vr_sha256 *c, uint64_t v) { add(c, &v, sizeof v); }

static void begin(vr_sha256 *c, const char *what, int S) {
  vr_sha256_init(c);
  add(c, what, strlen(what) + 1);
  add_u64(c, VR_CACHE_VERSION);
  add_u64(c, (uint64_t)S);
}

vr_status vr_cache_key_scene(const vr_scene *s, int S, uint8_t key[32], vr_error *err) {
  vr_sha256 c;
  begin(&c, "vr-geometry-cache/scene", S);
  add_u64(&c, s->nobjects);
  /* Each distinct mesh file is hashed once, however many objects name it. */
  char **paths = calloc(s->nobjects + 1, sizeof *paths);
  char (*digests)[65] = calloc(s->nobjects + 1, sizeof *digests);
  size_t npaths = 0;
  vr_status st = VR_OK;
  if (!paths || !digests) st = vr_error_set(err, VR_E_NOMEM, "out of memory");
  for (size_t i = 0; !st && i < s->nobjects; i++) {
    const vr_scene_object *o = &s->objects[i];
    add_u64(&c, (uint64_t)o->shape);
    add(&c, o->center, sizeof o->center);
    add(&c, &o->radius, sizeof o->radius);
    add(&c, o->normal, sizeof o->normal);
    add(&c, o->up, sizeof o->up);
    add(&c, o->size, sizeof o->size);
    add(&c, o->bmin, sizeof o->bmin);
    add(&c, o->bmax, sizeof o->bmax);
    add(&c, o->xform.m, sizeof o->xform.m);
    add_u64(&c, o->emission.value != 0.0);
    if (o->shape != VR_SHAPE_MESH || !o->mesh_path) continue;
    /* A file material's part of the mesh (keys of whole meshes unchanged). */
    if (o->mesh_material >= 0) add_u64(&c, (uint64_t)o->mesh_material);
    size_t j = 0;
    while (j < npaths && strcmp(paths[j], o->mesh_path)) j++;
    if (j == npaths) {
      paths[npaths] = o->mesh_path;
      /* A Radiance scene's key covers the files its !xform lines read. */
      if ((st = vr_rad_is(o->mesh_path) ? vr_rad_digest(o->mesh_path, digests[npaths], err)
                                        : vr_sha256_file(o->mesh_path, digests[npaths], err))) {
        vr_error_prefix(err, "%s:%ld: mesh: ", s->path ? s->path : "<input>", o->loc.line);
        break;
      }
      npaths++;
    }
    add(&c, digests[j], 64);
  }
  free(paths);
  free(digests);
  if (st) return st;
  char hex[65];
  vr_sha256_final(&c, hex);
  from_hex(hex, key);
  return VR_OK;
}

void vr_cache_key_geometry(const vr_geometry *g, int S, uint8_t key[32]) {
  vr_sha256 c;
  begin(&c, "vr-geometry-cache/arrays", S);
  add_u64(&c, g->nverts);
  add_u64(&c, g->ntris);
  add_u64(&c, g->nspheres);
  add_u64(&c, g->nobjects);
  add(&c, g->verts, g->nverts * 3 * sizeof *g->verts);
  if (g->vnormals) add(&c, g->vnormals, g->nverts * 3 * sizeof *g->vnormals);
  add(&c, g->tris, g->ntris * 3 * sizeof *g->tris);
  add(&c, g->tri_object, g->ntris * sizeof *g->tri_object);
  if (g->tri_uv) add(&c, g->tri_uv, g->ntris * 6 * sizeof *g->tri_uv);
  if (g->tri_rgb) add(&c, g->tri_rgb, g->ntris * 9);
  add(&c, g->spheres, g->nspheres * 4 * sizeof *g->spheres);
  add(&c, g->sphere_object, g->nspheres * sizeof *g->sphere_object);
  char hex[65];
  vr_sha256_final(&c, hex);
  from_hex(hex, key);
}

void vr_cache_key_short(const uint8_t key[32], char out[17]) {
  for (int i = 0; i < 8; i++) snprintf(out + 2 * i, 3, "%02x", key[i]);
}
