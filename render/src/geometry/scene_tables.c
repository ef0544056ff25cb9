/* Sampling an emissive object from the replicated tables (vr/scene_tables.h):
 * the arithmetic of vr_geometry_sample_object, on the emitter triangles the
 * cache builder copied out of the geometry. */
#include "vr/scene_tables.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void vr_scene_tables_free(vr_scene_tables *t) {
  if (!t) return;
  free(t->object_area);
  free(t->object_box);
  free(t->object_prims);
  free(t->is_rect);
  free(t->rect_frame);
  free(t->emit_begin);
  free(t->emit_end);
  free(t->emit_verts);
  free(t->emit_cdf);
  free(t->sphere);
  memset(t, 0, sizeof *t);
}

void vr_scene_tables_sample_object(const vr_scene_tables *t, uint32_t object, double u1,
                                   double u2, double u3, double p[3], double n[3]) {
  memset(p, 0, 3 * sizeof *p);
  memset(n, 0, 3 * sizeof *n);
  if (!t || object >= t->nobjects) return;
  const double *sp = t->sphere[object];
  if (sp[3] > 0.0) {
    double z = 1.0 - 2.0 * u2, r = sqrt(fmax(0.0, 1.0 - z * z)), phi = 2.0 * M_PI * u3;
    n[0] = r * cos(phi);
    n[1] = r * sin(phi);
    n[2] = z;
    for (int k = 0; k < 3; k++) p[k] = sp[k] + sp[3] * n[k];
    return;
  }
  uint64_t lo = t->emit_begin[object], hi = t->emit_end[object];
  if (hi <= lo) return;
  /* The first triangle whose cumulative area exceeds u1 * area. */
  double target = u1 * t->emit_cdf[hi - 1];
  uint64_t a = lo, b = hi - 1;
  while (a < b) {
    uint64_t mid = a + (b - a) / 2;
    if (t->emit_cdf[mid] > target)
      b = mid;
    else
      a = mid + 1;
  }
  const float *v0 = t->emit_verts + 9 * a, *v1 = v0 + 3, *v2 = v0 + 6;
  double su = sqrt(u2), b0 = 1.0 - su, b1 = u3 * su, b2 = 1.0 - b0 - b1;
  for (int k = 0; k < 3; k++) p[k] = b0 * v0[k] + b1 * v1[k] + b2 * v2[k];
  double e1[3], e2[3], nn[3];
  for (int k = 0; k < 3; k++) {
    e1[k] = (double)v1[k] - (double)v0[k];
    e2[k] = (double)v2[k] - (double)v0[k];
  }
  nn[0] = e1[1] * e2[2] - e1[2] * e2[1];
  nn[1] = e1[2] * e2[0] - e1[0] * e2[2];
  nn[2] = e1[0] * e2[1] - e1[1] * e2[0];
  double len = sqrt(nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]);
  if (len > 0.0)
    for (int k = 0; k < 3; k++) n[k] = nn[k] / len;
}
