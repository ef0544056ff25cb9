/* The cells of the geometry cache (cache_split.h). */
#include "geometry/cache_split.h"

#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* Planes tried along each axis when a cell is split: centroid quantiles. */
#define SPLIT_CANDIDATES 64

typedef struct vr_split_cell {
  uint32_t *idx;
  size_t n;
} vr_split_cell;

static bool overlaps(const vr_cache_sample *s, const double lo[3], const double hi[3]) {
  for (int a = 0; a < 3; a++)
    if ((double)s->hi[a] < lo[a] || (double)s->lo[a] > hi[a]) return false;
  return true;
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

typedef struct vr_split_chooser {
  const vr_cache_sample *s;
  vr_cache_cells *c;
  vr_error *err;
} vr_split_chooser;

static vr_status nomem(vr_split_chooser *C) {
  return vr_error_set(C->err, VR_E_NOMEM, "geometry cache: out of memory");
}

static vr_status fill(vr_split_chooser *C, const vr_split_cell *parent, vr_split_cell *child, const double lo[3],
                      const double hi[3]) {
  child->idx = malloc((parent->n + 1) * sizeof *child->idx);
  if (!child->idx) return nomem(C);
  child->n = 0;
  for (size_t i = 0; i < parent->n; i++)
    if (overlaps(&C->s[parent->idx[i]], lo, hi)) child->idx[child->n++] = parent->idx[i];
  return VR_OK;
}

/* Primitives of sorted v[0..n) that are <= x (upper bound). */
static size_t count_le(const double *v, size_t n, double x) {
  size_t lo = 0, hi = n;
  while (lo < hi) {
    size_t mid = lo + (hi - lo) / 2;
    if (v[mid] <= x)
      lo = mid + 1;
    else
      hi = mid;
  }
  return lo;
}

/* Splits cell ci where the larger side holds the fewest primitives,
 * counting a primitive that straddles the plane on both sides: the cells
 * balance what they hold, duplicates included, so no cell is much larger
 * than the others.  Candidates are, along each axis, SPLIT_CANDIDATES
 * quantiles of the primitives' centroids and the middle of the box; ties go to the plane
 * that duplicates fewer primitives, then to the longer axis. */
static vr_status split(vr_split_chooser *C, vr_split_cell *kc, int ci, int leaf) {
  vr_cache_cells *B = C->c;
  double *lo = B->lo[ci], *hi = B->hi[ci];
  int axis = 0;
  for (int a = 1; a < 3; a++)
    if (hi[a] - lo[a] > hi[axis] - lo[axis]) axis = a;
  vr_split_cell *c = &kc[ci];
  double at = 0.5 * (lo[axis] + hi[axis]);
  size_t n = c->n;
  if (n > 0) {
    double *cs = malloc(n * sizeof *cs), *vlo = malloc(n * sizeof *vlo),
           *vhi = malloc(n * sizeof *vhi);
    if (!cs || !vlo || !vhi) {
      free(cs), free(vlo), free(vhi);
      return nomem(C);
    }
    size_t best_max = SIZE_MAX, best_sum = SIZE_MAX;
    double best_len = -1;
    for (int a = 0; a < 3; a++) {
      double len = hi[a] - lo[a];
      if (!(len > 0)) continue;
      for (size_t i = 0; i < n; i++) {
        const vr_cache_sample *p = &C->s[c->idx[i]];
        vlo[i] = p->lo[a];
        vhi[i] = p->hi[a];
        cs[i] = 0.5 * ((double)p->lo[a] + (double)p->hi[a]);
      }
      qsort(cs, n, sizeof *cs, cmp_double);
      qsort(vlo, n, sizeof *vlo, cmp_double);
      qsort(vhi, n, sizeof *vhi, cmp_double);
      for (int q = 0; q <= SPLIT_CANDIDATES; q++) {
        double x = q < SPLIT_CANDIDATES ? cs[(size_t)q * n / SPLIT_CANDIDATES] : 0.5 * (lo[a] + hi[a]);
        if (q == 0 || !(x > lo[a] && x < hi[a])) continue; /* both sides need volume */
        size_t below = count_le(vlo, n, x);            /* lo <= x */
        size_t above = n - count_le(vhi, n, nextafter(x, -INFINITY)); /* hi >= x */
        size_t mx = below > above ? below : above, sum = below + above;
        if (mx < best_max || (mx == best_max && (sum < best_sum || (sum == best_sum && len > best_len)))) {
          best_max = mx, best_sum = sum, best_len = len, axis = a, at = x;
        }
      }
    }
    free(cs), free(vlo), free(vhi);
  }
  int ai = B->ncells++;
  double blo[3], bhi[3], alo[3], ahi[3];
  memcpy(blo, lo, sizeof blo);
  memcpy(bhi, hi, sizeof bhi);
  memcpy(alo, lo, sizeof alo);
  memcpy(ahi, hi, sizeof ahi);
  bhi[axis] = at;
  alo[axis] = at;
  vr_split_cell below = {0}, above = {0};
  vr_status st = fill(C, c, &below, blo, bhi);
  if (!st) st = fill(C, c, &above, alo, ahi);
  if (st) {
    free(below.idx);
    free(above.idx);
    return st;
  }
  free(c->idx);
  kc[ci] = below;
  kc[ai] = above;
  memcpy(B->lo[ci], blo, sizeof blo);
  memcpy(B->hi[ci], bhi, sizeof bhi);
  memcpy(B->lo[ai], alo, sizeof alo);
  memcpy(B->hi[ai], ahi, sizeof ahi);
  int nb = B->nnodes++, na = B->nnodes++;
  B->nodes[nb] = (vr_kd_node){.axis = -1, .cell = ci};
  B->nodes[na] = (vr_kd_node){.axis = -1, .cell = ai};
  B->nodes[leaf] = (vr_kd_node){.axis = axis, .split = at, .child = {nb, na}, .cell = -1};
  return VR_OK;
}

vr_status vr_cache_choose_cells(const vr_cache_sample *s, size_t n, const double lo[3],
                                const double hi[3], int S, vr_cache_cells *B, vr_error *err) {
  memset(B, 0, sizeof *B);
  vr_split_chooser C = {s, B, err};
  B->nodes = calloc(2 * (size_t)S, sizeof *B->nodes);
  B->lo = calloc((size_t)S, sizeof *B->lo);
  B->hi = calloc((size_t)S, sizeof *B->hi);
  vr_split_cell *kc = calloc((size_t)S, sizeof *kc);
  if (!B->nodes || !B->lo || !B->hi || !kc) {
    free(kc);
    return nomem(&C);
  }
  vr_status st = VR_OK;
  memcpy(B->lo[0], lo, sizeof B->lo[0]);
  memcpy(B->hi[0], hi, sizeof B->hi[0]);
  kc[0].idx = malloc((n + 1) * sizeof *kc[0].idx);
  if (!kc[0].idx) st = nomem(&C);
  for (size_t i = 0; !st && i < n; i++) kc[0].idx[i] = (uint32_t)i;
  kc[0].n = n;
  B->ncells = 1;
  B->nnodes = 1;
  B->nodes[0] = (vr_kd_node){.axis = -1, .cell = 0};
  while (!st && B->ncells < S) {
    /* The leaf with the most primitives; the first such node among equals. */
    int best = -1;
    for (int k = 0; k < B->nnodes; k++) {
      if (B->nodes[k].axis >= 0) continue;
      if (best < 0 || kc[B->nodes[k].cell].n > kc[B->nodes[best].cell].n) best = k;
    }
    st = split(&C, kc, B->nodes[best].cell, best);
  }
  for (int c = 0; c < S; c++) free(kc[c].idx);
  free(kc);
  return st;
}

void vr_cache_cells_free(vr_cache_cells *c) {
  free(c->nodes);
  free(c->lo);
  free(c->hi);
  memset(c, 0, sizeof *c);
}
