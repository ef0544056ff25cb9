/* Photochromic state maps: each cell holds the maps of the photochromic
 * objects it has primitives of (a cell is never reached through another's
 * data), and a hit reads the texel of its own cell's copy. */
#include <stdlib.h>

#include "world/resolve.h"

/* Each cell holds the state maps of the photochromic objects it has
 * primitives of, starting at the material's own state. */
vr_status vr_rscene_cell_maps(vr_rscene *rs, vr_error *err) {
  int S = vr_domains_count(rs->d);
  rs->cells = calloc((size_t)S, sizeof *rs->cells);
  if (!rs->cells) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  for (int c = 0; c < S; c++) {
    size_t n;
    const uint32_t *objs = vr_domains_cell_objects(rs->d, c, &n);
    vr_rcell *rc = &rs->cells[c];
    for (size_t i = 0; i < n; i++) rc->nmaps += rs->obj[objs[i]].nu > 0;
    if (!rc->nmaps) continue;
    rc->map_object = calloc(rc->nmaps, sizeof *rc->map_object);
    rc->map = calloc(rc->nmaps, sizeof *rc->map);
    if (!rc->map_object || !rc->map) return vr_error_set(err, VR_E_NOMEM, "out of memory");
    size_t k = 0;
    for (size_t i = 0; i < n; i++) {
      const vr_robject *o = &rs->obj[objs[i]];
      if (!o->nu) continue;
      size_t nt = (size_t)o->nu * (size_t)o->nv;
      rc->map_object[k] = objs[i];
      if (!(rc->map[k] = malloc(nt * sizeof **rc->map)))
        return vr_error_set(err, VR_E_NOMEM, "out of memory");
      for (size_t t = 0; t < nt; t++) rc->map[k][t] = rs->mat[o->material].state;
      k++;
    }
  }
  return VR_OK;
}

double *vr_cell_state_map(const vr_rscene *rs, int c, uint32_t o) {
  const vr_rcell *rc = &rs->cells[c];
  size_t lo = 0, hi = rc->nmaps;
  while (lo < hi) {
    size_t mid = lo + (hi - lo) / 2;
    if (rc->map_object[mid] < o)
      lo = mid + 1;
    else
      hi = mid;
  }
  return lo < rc->nmaps && rc->map_object[lo] == o ? rc->map[lo] : NULL;
}

size_t vr_rscene_map_bytes(const vr_rscene *rs) {
  size_t b = 0;
  for (int c = 0; rs->cells && c < vr_domains_count(rs->d); c++) {
    const vr_rcell *rc = &rs->cells[c];
    b += rc->nmaps * (sizeof *rc->map_object + sizeof *rc->map);
    for (size_t k = 0; k < rc->nmaps; k++) {
      const vr_robject *o = &rs->obj[rc->map_object[k]];
      b += (size_t)o->nu * (size_t)o->nv * sizeof **rc->map;
    }
  }
  return b;
}

double vr_hit_state(const vr_rscene *rs, const vr_hit *hit) {
  const vr_robject *o = &rs->obj[hit->object];
  const double *map = o->nu ? vr_cell_state_map(rs, hit->cell, hit->object) : NULL;
  if (map) {
    int i = (int)(hit->uv[0] * o->nu), j = (int)(hit->uv[1] * o->nv);
    i = i < 0 ? 0 : i >= o->nu ? o->nu - 1 : i;
    j = j < 0 ? 0 : j >= o->nv ? o->nv - 1 : j;
    return map[j * o->nu + i];
  }
  return rs->mat[o->material].state;
}
