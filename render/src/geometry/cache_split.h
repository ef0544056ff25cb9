/* The cells of the geometry cache: a kd-tree chosen on a sample of the
 * primitives' bounds (cache_build.c draws the sample in its first pass). */
#ifndef VR_CACHE_SPLIT_H
#define VR_CACHE_SPLIT_H

#include <stddef.h>
#include <stdint.h>

#include "geometry/cache_format.h"
#include "vr/error.h"

/* One sampled primitive: its hash (the sample keeps the smallest) and box. */
typedef struct vr_cache_sample {
  uint64_t h;
  float lo[3], hi[3];
} vr_cache_sample;

/* S cells as the leaves of a kd-tree: nodes[0..nnodes) (the root first),
 * and each cell's box. */
typedef struct vr_cache_cells {
  vr_kd_node *nodes;
  int nnodes, ncells;
  double (*lo)[3], (*hi)[3];
} vr_cache_cells;

/* Splits the box [lo, hi] into S cells: the cell holding the most sampled
 * primitives is split, again and again, at the plane whose larger side
 * holds the fewest primitives (straddling ones counted on both sides),
 * among SPLIT_CANDIDATES centroid quantiles per axis and the box's middle.
 * out is freed with vr_cache_cells_free, also after a failure. */
vr_status vr_cache_choose_cells(const vr_cache_sample *s, size_t n, const double lo[3],
                                const double hi[3], int S, vr_cache_cells *out, vr_error *err);
void vr_cache_cells_free(vr_cache_cells *c);

#endif
