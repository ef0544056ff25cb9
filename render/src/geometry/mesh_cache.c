/* A small LRU of meshes by file path (see mesh_cache.h).  The list is
 * short (a scene names tens of distinct files), so lookups are a scan. */
#include "geometry/mesh_cache.h"

#include <stdlib.h>
#include <string.h>

typedef struct vr_mesh_entry {
  char *path;
  vr_mesh_data mesh;
  size_t bytes;
  unsigned long long used; /* clock of the last use */
} vr_mesh_entry;

struct vr_mesh_cache {
  size_t max_bytes, bytes;
  vr_mesh_entry *e;
  size_t n, cap;
  unsigned long long clock;
};

size_t vr_mesh_data_bytes(const vr_mesh_data *m) {
  size_t v = 3 + (m->nrm ? 3 : 0) + (m->uv ? 2 : 0);
  return m->nverts * (v * sizeof(double) + (m->rgb ? 3 : 0)) + m->ntris * 3 * sizeof(uint32_t);
}

vr_mesh_cache *vr_mesh_cache_create(size_t max_bytes) {
  vr_mesh_cache *c = calloc(1, sizeof *c);
  if (c) c->max_bytes = max_bytes;
  return c;
}

static void drop(vr_mesh_cache *c, size_t i) {
  free(c->e[i].path);
  vr_mesh_data_free(&c->e[i].mesh);
  c->bytes -= c->e[i].bytes;
  c->e[i] = c->e[--c->n];
}

void vr_mesh_cache_destroy(vr_mesh_cache *c) {
  if (!c) return;
  while (c->n) drop(c, c->n - 1);
  free(c->e);
  free(c);
}

vr_status vr_mesh_cache_get(vr_mesh_cache *c, const char *path, const vr_mesh_data **out,
                            vr_error *err) {
  *out = NULL;
  for (size_t i = 0; i < c->n; i++)
    if (!strcmp(c->e[i].path, path)) {
      c->e[i].used = ++c->clock;
      *out = &c->e[i].mesh;
      return VR_OK;
    }
  vr_mesh_data md;
  vr_status st = vr_mesh_read(path, &md, err);
  if (st) return st;
  size_t bytes = vr_mesh_data_bytes(&md);
  /* Room for it: drop the least recently used until it fits (a mesh larger
   * than the whole limit is still kept, alone, until the next call). */
  while (c->n && c->bytes + bytes > c->max_bytes) {
    size_t lru = 0;
    for (size_t i = 1; i < c->n; i++)
      if (c->e[i].used < c->e[lru].used) lru = i;
    drop(c, lru);
  }
  if (c->n == c->cap) {
    size_t cap = c->cap ? 2 * c->cap : 8;
    vr_mesh_entry *e = realloc(c->e, cap * sizeof *e);
    if (!e) {
      vr_mesh_data_free(&md);
      return vr_error_set(err, VR_E_NOMEM, "mesh cache: out of memory");
    }
    c->e = e;
    c->cap = cap;
  }
  char *p = strdup(path);
  if (!p) {
    vr_mesh_data_free(&md);
    return vr_error_set(err, VR_E_NOMEM, "mesh cache: out of memory");
  }
  c->e[c->n] = (vr_mesh_entry){p, md, bytes, ++c->clock};
  c->bytes += bytes;
  *out = &c->e[c->n++].mesh;
  return VR_OK;
}
