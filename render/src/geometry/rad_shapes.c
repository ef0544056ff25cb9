/* Radiance's surfaces as triangles (rad_read.h).  Every triangle keeps
 * the orientation Radiance gives the surface: a polygon's normal follows
 * its vertices counter-clockwise (right-hand rule), a sphere, cone and
 * cylinder face out and a bubble, cup and tube in, a ring faces its
 * normal.  Curved surfaces are cut into RAD_SEGMENTS facets around (and
 * RAD_STACKS along a sphere's meridians), inscribed: their area falls short
 * of the surface's by x^2 / 6 for each angular half-step x, 1.0e-4 for a
 * cylinder or cone, 4.0e-4 for a ring and 5.0e-4 for a sphere, which is
 * what an emitting sphere or disc loses in power; Radiance's own are
 * exact quadrics.  Vertices are not shared between primitives. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "geometry/rad_read.h"

#define RAD_SEGMENTS 128
#define RAD_STACKS 64

/* The capacity an array of count elements has: arrays grow by doubling
 * from 64, so it follows from the count alone. */
static size_t cap_of(size_t count) {
  if (!count) return 0;
  size_t c = 64;
  while (c < count) c *= 2;
  return c;
}

static bool grow(void **p, size_t count, size_t add, size_t elem) {
  size_t cap = cap_of(count);
  if (count + add <= cap) return true;
  size_t nc = cap ? cap : 64;
  while (nc < count + add) nc *= 2;
  void *q = realloc(*p, nc * elem);
  if (!q) return false;
  *p = q;
  return true;
}

static vr_status nomem(vr_error *err) { return vr_error_set(err, VR_E_NOMEM, "out of memory"); }

static vr_status too_big(vr_error *err) {
  return vr_error_set(err, VR_E_RANGE, "more than 2^32 vertices: too large for 32-bit indices");
}

/* Appends vertex p; its index in *out. */
static vr_status vertex(vr_mesh_data *m, const double p[3], uint32_t *out, vr_error *err) {
  if (m->nverts >= UINT32_MAX) return too_big(err);
  if (!grow((void **)&m->pos, 3 * m->nverts, 3, sizeof *m->pos)) return nomem(err);
  memcpy(m->pos + 3 * m->nverts, p, 3 * sizeof *p);
  *out = (uint32_t)m->nverts++;
  return VR_OK;
}

static double dot(const double a[3], const double b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross(const double a[3], const double b[3], double o[3]) {
  double r[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  memcpy(o, r, sizeof r);
}

/* The triangle a b c unless it has no area (a pole, an apex). */
static vr_status triangle(vr_mesh_data *m, uint32_t a, uint32_t b, uint32_t c, uint32_t mat,
                          vr_error *err) {
  const double *pa = m->pos + 3 * a, *pb = m->pos + 3 * b, *pc = m->pos + 3 * c;
  double e1[3], e2[3], n[3];
  for (int k = 0; k < 3; k++) e1[k] = pb[k] - pa[k], e2[k] = pc[k] - pa[k];
  cross(e1, e2, n);
  if (!(dot(n, n) > 0.0)) return VR_OK;
  if (!grow((void **)&m->tris, 3 * m->ntris, 3, sizeof *m->tris) ||
      !grow((void **)&m->tri_material, m->ntris, 1, sizeof *m->tri_material))
    return nomem(err);
  uint32_t *t = m->tris + 3 * m->ntris;
  t[0] = a, t[1] = b, t[2] = c;
  m->tri_material[m->ntris++] = mat;
  return VR_OK;
}

/* Two unit vectors e1, e2 with e1 x e2 = a (a unit). */
static void basis(const double a[3], double e1[3], double e2[3]) {
  double h[3] = {0, 0, 0};
  h[fabs(a[0]) < 0.6 ? 0 : fabs(a[1]) < 0.6 ? 1 : 2] = 1;
  cross(h, a, e1);
  double l = sqrt(dot(e1, e1));
  for (int k = 0; k < 3; k++) e1[k] /= l;
  cross(a, e1, e2);
}

/* Ear clipping in the polygon's plane.  The polygon may be concave and
 * may hold seams (Radiance's way to cut holes: an edge walked there and
 * back), so a vertex at the same place as an ear's corner does not stop
 * the ear. */
vr_status vr_rad_polygon(vr_mesh_data *m, const double *v, size_t n, uint32_t mat, bool *degenerate,
                         vr_error *err) {
  *degenerate = false;
  /* Newell's normal: twice the vector area. */
  double nn[3] = {0, 0, 0}, ext = 0;
  for (size_t i = 0; i < n; i++) {
    const double *a = v + 3 * i, *b = v + 3 * ((i + 1) % n);
    nn[0] += (a[1] - b[1]) * (a[2] + b[2]);
    nn[1] += (a[2] - b[2]) * (a[0] + b[0]);
    nn[2] += (a[0] - b[0]) * (a[1] + b[1]);
    for (int k = 0; k < 3; k++) ext = fmax(ext, fabs(a[k] - v[k]));
  }
  double len = sqrt(dot(nn, nn));
  if (!(len > 1e-12 * ext * ext) || !(ext > 0)) {
    *degenerate = true;
    return VR_OK;
  }
  for (int k = 0; k < 3; k++) nn[k] /= len;
  double e1[3], e2[3];
  basis(nn, e1, e2);
  uint32_t *id = malloc(n * sizeof *id);
  double *uv = malloc(2 * n * sizeof *uv);
  size_t *ring = malloc(n * sizeof *ring);
  if (!id || !uv || !ring) {
    free(id), free(uv), free(ring);
    return nomem(err);
  }
  vr_status st = VR_OK;
  for (size_t i = 0; i < n && !st; i++) {
    st = vertex(m, v + 3 * i, &id[i], err);
    double d[3] = {v[3 * i] - v[0], v[3 * i + 1] - v[1], v[3 * i + 2] - v[2]};
    uv[2 * i] = dot(d, e1), uv[2 * i + 1] = dot(d, e2);
    ring[i] = i;
  }
  double tol = 1e-12 * ext * ext;
  size_t left = n;
  while (!st && left > 3) {
    size_t best = SIZE_MAX;
    double best_turn = -INFINITY;
    for (size_t j = 0; j < left; j++) {
      size_t a = ring[(j + left - 1) % left], b = ring[j], c = ring[(j + 1) % left];
      double ax = uv[2 * a], ay = uv[2 * a + 1], bx = uv[2 * b], by = uv[2 * b + 1];
      double cx = uv[2 * c], cy = uv[2 * c + 1];
      double turn = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
      if (turn > best_turn) best_turn = turn, best = j; /* the fallback: the most convex corner */
      if (!(turn > tol)) continue;
      bool inside = false;
      for (size_t q = 0; q < left && !inside; q++) {
        size_t p = ring[q];
        if (p == a || p == b || p == c) continue;
        double px = uv[2 * p], py = uv[2 * p + 1];
        bool at_corner = (fabs(px - ax) + fabs(py - ay) <= 1e-9 * ext) ||
                         (fabs(px - bx) + fabs(py - by) <= 1e-9 * ext) ||
                         (fabs(px - cx) + fabs(py - cy) <= 1e-9 * ext);
        if (at_corner) continue;
        double d1 = (bx - ax) * (py - ay) - (by - ay) * (px - ax);
        double d2 = (cx - bx) * (py - by) - (cy - by) * (px - bx);
        double d3 = (ax - cx) * (py - cy) - (ay - cy) * (px - cx);
        inside = d1 >= -tol && d2 >= -tol && d3 >= -tol;
      }
      if (inside) continue;
      best = j;
      break;
    }
    size_t a = ring[(best + left - 1) % left], b = ring[best], c = ring[(best + 1) % left];
    st = triangle(m, id[a], id[b], id[c], mat, err);
    memmove(ring + best, ring + best + 1, (left - best - 1) * sizeof *ring);
    left--;
  }
  if (!st) st = triangle(m, id[ring[0]], id[ring[1]], id[ring[2]], mat, err);
  free(id), free(uv), free(ring);
  return st;
}

vr_status vr_rad_sphere(vr_mesh_data *m, const double c[3], double r, bool outward, uint32_t mat,
                        vr_error *err) {
  uint32_t first = 0;
  vr_status st = VR_OK;
  for (int i = 0; i <= RAD_STACKS && !st; i++) {
    double th = M_PI * i / RAD_STACKS;
    for (int j = 0; j < RAD_SEGMENTS && !st; j++) {
      double ph = 2 * M_PI * j / RAD_SEGMENTS;
      /* The poles exactly, so that their fans' empty triangles are dropped. */
      double st = i == 0 || i == RAD_STACKS ? 0 : sin(th), ct = i == RAD_STACKS ? -1 : cos(th);
      double p[3] = {c[0] + r * st * cos(ph), c[1] + r * st * sin(ph), c[2] + r * ct};
      uint32_t idx;
      st = vertex(m, p, &idx, err);
      if (i == 0 && j == 0) first = idx;
    }
  }
  /* d/dtheta x d/dphi points out: (i,j) (i+1,j) (i+1,j+1) faces out. */
  for (int i = 0; i < RAD_STACKS && !st; i++)
    for (int j = 0; j < RAD_SEGMENTS && !st; j++) {
      int j1 = (j + 1) % RAD_SEGMENTS;
      uint32_t a = first + (uint32_t)(i * RAD_SEGMENTS + j), b = first + (uint32_t)((i + 1) * RAD_SEGMENTS + j);
      uint32_t cc = first + (uint32_t)((i + 1) * RAD_SEGMENTS + j1), d = first + (uint32_t)(i * RAD_SEGMENTS + j1);
      st = outward ? triangle(m, a, b, cc, mat, err) : triangle(m, a, cc, b, mat, err);
      if (!st) st = outward ? triangle(m, a, cc, d, mat, err) : triangle(m, a, d, cc, mat, err);
    }
  return st;
}

/* Two circles of RAD_SEGMENTS vertices about the unit axis a, centres c0
 * and c1, radii r0 and r1, interleaved (circle 0's j-th vertex at
 * *first + 2 j, circle 1's after it). */
static vr_status circles(vr_mesh_data *m, const double a[3], const double c0[3],
                         const double c1[3], double r0, double r1, uint32_t *first,
                         vr_error *err) {
  double e1[3], e2[3];
  basis(a, e1, e2);
  vr_status st = VR_OK;
  for (int j = 0; j < RAD_SEGMENTS && !st; j++) {
    double ph = 2 * M_PI * j / RAD_SEGMENTS, cs = cos(ph), sn = sin(ph);
    double q0[3], q1[3];
    for (int k = 0; k < 3; k++) {
      double rho = cs * e1[k] + sn * e2[k];
      q0[k] = c0[k] + r0 * rho, q1[k] = c1[k] + r1 * rho;
    }
    uint32_t i0, i1;
    st = vertex(m, q0, &i0, err);
    if (!st) st = vertex(m, q1, &i1, err);
    if (j == 0) *first = i0;
  }
  return st;
}

/* The triangles between the two circles circles() made (first at
 * *first): circle 0 (j) circle 0 (j+1) circle 1 (j+1) faces along
 * d/dphi x (circle 1 - circle 0), out of a cone whose circle 1 is its
 * top; forward false turns them round. */
static vr_status band(vr_mesh_data *m, uint32_t first, bool forward, uint32_t mat, vr_error *err) {
  vr_status st = VR_OK;
  for (int j = 0; j < RAD_SEGMENTS && !st; j++) {
    uint32_t b0 = first + 2 * (uint32_t)j, t0 = b0 + 1;
    uint32_t b1 = first + 2 * (uint32_t)((j + 1) % RAD_SEGMENTS), t1 = b1 + 1;
    st = forward ? triangle(m, b0, b1, t1, mat, err) : triangle(m, b0, t1, b1, mat, err);
    if (!st) st = forward ? triangle(m, b0, t1, t0, mat, err) : triangle(m, b0, t0, t1, mat, err);
  }
  return st;
}

vr_status vr_rad_cone(vr_mesh_data *m, const double p0[3], const double p1[3], double r0, double r1,
                      bool outward, uint32_t mat, vr_error *err) {
  double a[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
  double l = sqrt(dot(a, a));
  for (int k = 0; k < 3; k++) a[k] /= l;
  uint32_t first = 0;
  vr_status st = circles(m, a, p0, p1, r0, r1, &first, err);
  return st ? st : band(m, first, outward, mat, err);
}

vr_status vr_rad_ring(vr_mesh_data *m, const double c[3], const double n[3], double r0, double r1,
                      uint32_t mat, vr_error *err) {
  double a[3] = {n[0], n[1], n[2]};
  double l = sqrt(dot(a, a));
  for (int k = 0; k < 3; k++) a[k] /= l;
  uint32_t first = 0;
  vr_status st = circles(m, a, c, c, r0, r1, &first, err);
  /* The inner circle as the band's first: counter-clockwise about the
   * normal is the band's inward order. */
  return st ? st : band(m, first, false, mat, err);
}
