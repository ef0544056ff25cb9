/* The replicated tables a chunk of objects adds to while the geometry cache
 * is built (cache_tables.h). */
#include "geometry/cache_tables.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

void vr_cache_tri_box(const float *verts, const uint32_t *ix, double lo[3], double hi[3]) {
  for (int a = 0; a < 3; a++) {
    lo[a] = INFINITY;
    hi[a] = -INFINITY;
  }
  for (int k = 0; k < 3; k++) {
    const float *v = verts + 3 * (size_t)ix[k];
    for (int a = 0; a < 3; a++) {
      if (v[a] < lo[a]) lo[a] = v[a];
      if (v[a] > hi[a]) hi[a] = v[a];
    }
  }
}

void vr_cache_sphere_box(const double *s, double lo[3], double hi[3]) {
  for (int a = 0; a < 3; a++) {
    lo[a] = s[a] - s[3];
    hi[a] = s[a] + s[3];
  }
}

bool vr_cache_tables_alloc(vr_scene_tables *t, size_t nobjects) {
  t->nobjects = nobjects;
  size_t n = nobjects ? nobjects : 1;
  t->object_area = calloc(n, sizeof *t->object_area);
  t->object_box = calloc(n, sizeof *t->object_box);
  t->object_prims = calloc(n, sizeof *t->object_prims);
  t->is_rect = calloc(n, 1);
  t->rect_frame = calloc(n, sizeof *t->rect_frame);
  t->emit_begin = calloc(n, sizeof *t->emit_begin);
  t->emit_end = calloc(n, sizeof *t->emit_end);
  t->sphere = calloc(n, sizeof *t->sphere);
  return t->object_area && t->object_box && t->object_prims && t->is_rect && t->rect_frame &&
         t->emit_begin && t->emit_end && t->sphere;
}

static bool add_emitter_tris(vr_scene_tables *t, size_t *emit_cap, const vr_geometry *g, size_t o) {
  size_t lo = g->object_tri_begin[o], hi = g->object_tri_end[o];
  if (t->nemit + (hi - lo) > *emit_cap) {
    size_t cap = *emit_cap ? 2 * *emit_cap : 64;
    while (cap < t->nemit + (hi - lo)) cap *= 2;
    float *v = realloc(t->emit_verts, cap * 9 * sizeof *v);
    if (!v) return false;
    t->emit_verts = v;
    double *c = realloc(t->emit_cdf, cap * sizeof *c);
    if (!c) return false;
    t->emit_cdf = c;
    *emit_cap = cap;
  }
  t->emit_begin[o] = t->nemit;
  for (size_t i = lo; i < hi; i++, t->nemit++) {
    for (int k = 0; k < 3; k++)
      memcpy(t->emit_verts + 9 * t->nemit + 3 * k, g->verts + 3 * (size_t)g->tris[3 * i + k],
             3 * sizeof(float));
    t->emit_cdf[t->nemit] = g->tri_cdf[i];
  }
  t->emit_end[o] = t->nemit;
  return true;
}

/* The frame of a rect's (u, v) from its first triangle's corners and their
 * (u, v): p = corner + u eu + v ev. */
static void rect_frame(const vr_geometry *g, size_t t0, double f[9]) {
  const uint32_t *ix = g->tris + 3 * t0;
  const float *uv = g->tri_uv + 6 * t0;
  double P[3][3];
  for (int k = 0; k < 3; k++)
    for (int a = 0; a < 3; a++) P[k][a] = g->verts[3 * (size_t)ix[k] + a];
  double du1 = uv[2] - uv[0], dv1 = uv[3] - uv[1], du2 = uv[4] - uv[0], dv2 = uv[5] - uv[1];
  double det = du1 * dv2 - du2 * dv1;
  for (int a = 0; a < 3; a++) {
    double d1 = P[1][a] - P[0][a], d2 = P[2][a] - P[0][a];
    f[3 + a] = (d1 * dv2 - d2 * dv1) / det;
    f[6 + a] = (du1 * d2 - du2 * d1) / det;
    f[a] = P[0][a] - uv[0] * f[3 + a] - uv[1] * f[6 + a];
  }
}

vr_status vr_cache_tables_take(vr_scene_tables *t, size_t *emit_cap, const vr_geometry *g,
                               const vr_scene *s, size_t first, size_t last, vr_error *err) {
  double lo[3], hi[3];
  t->ntris += g->ntris;
  t->nspheres += g->nspheres;
  t->degenerate_dropped += g->degenerate_dropped;
  for (size_t o = first; o < last; o++) {
    t->object_area[o] = g->object_area[o];
    /* The object's own bounds and primitive count, for the decision lines. */
    bool any = false;
    for (size_t i = g->object_tri_begin[o]; i < g->object_tri_end[o]; i++) {
      vr_cache_tri_box(g->verts, g->tris + 3 * i, lo, hi);
      for (int a = 0; a < 3; a++) {
        if (!any || lo[a] < t->object_box[o][a]) t->object_box[o][a] = lo[a];
        if (!any || hi[a] > t->object_box[o][3 + a]) t->object_box[o][3 + a] = hi[a];
      }
      any = true;
    }
    t->object_prims[o] = g->object_tri_end[o] - g->object_tri_begin[o];
    if (g->object_sphere[o] != SIZE_MAX) {
      vr_cache_sphere_box(g->spheres + 4 * g->object_sphere[o], lo, hi);
      for (int a = 0; a < 3; a++) t->object_box[o][a] = lo[a], t->object_box[o][3 + a] = hi[a];
      t->object_prims[o] = 1;
      memcpy(t->sphere[o], g->spheres + 4 * g->object_sphere[o], 4 * sizeof(double));
    }
    bool tris = g->object_tri_end[o] > g->object_tri_begin[o];
    if (!s || !tris) continue;
    if (s->objects[o].shape == VR_SHAPE_RECT) {
      t->is_rect[o] = 1;
      rect_frame(g, g->object_tri_begin[o], t->rect_frame[o]);
    }
    if (s->objects[o].emission.value != 0.0 && !add_emitter_tris(t, emit_cap, g, o))
      return vr_error_set(err, VR_E_NOMEM, "out of memory for the emitters' triangles");
  }
  return VR_OK;
}
