/* Coinciding polygons of a Radiance model (rad_read.h): pairs in one plane
 * that share area.  Each polygon's plane (unit normal n, offset d = n.p,
 * the sign fixed so that n's largest component is positive) is rounded to
 * a key; polygons are sorted by key and only neighbours in that order whose
 * planes agree within the tolerances are compared, triangle by triangle:
 * the area two triangles share is that of one clipped by the other
 * (Sutherland-Hodgman on convex polygons), in the plane's own 2-D frame. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "geometry/rad_read.h"

#define PLANE_D_TOL 1e-4  /* m: 0.1 mm between the planes */
#define PLANE_N_TOL 1e-4  /* between the unit normals */
#define AREA_MIN 1e-4     /* m2: 1 cm2 shared before it is said */

typedef struct plane {
  double n[3], d;
  double lo[3], hi[3]; /* bounds */
  size_t poly;
} plane;

static const double *vtx(const vr_mesh_data *m, size_t t, int k) {
  return m->pos + 3 * m->tris[3 * t + k];
}

static void plane_of(const vr_rad_model *m, size_t i, plane *pl) {
  const vr_rad_poly *p = &m->polys[i];
  double n[3] = {0, 0, 0};
  for (int k = 0; k < 3; k++) pl->lo[k] = INFINITY, pl->hi[k] = -INFINITY;
  for (size_t t = p->first; t < p->first + p->count; t++) {
    const double *a = vtx(&m->mesh, t, 0), *b = vtx(&m->mesh, t, 1), *c = vtx(&m->mesh, t, 2);
    double u[3], v[3];
    for (int k = 0; k < 3; k++) u[k] = b[k] - a[k], v[k] = c[k] - a[k];
    n[0] += u[1] * v[2] - u[2] * v[1];
    n[1] += u[2] * v[0] - u[0] * v[2];
    n[2] += u[0] * v[1] - u[1] * v[0];
    for (int q = 0; q < 3; q++)
      for (int k = 0; k < 3; k++) {
        double x = vtx(&m->mesh, t, q)[k];
        pl->lo[k] = fmin(pl->lo[k], x), pl->hi[k] = fmax(pl->hi[k], x);
      }
  }
  double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  int big = fabs(n[0]) >= fabs(n[1]) && fabs(n[0]) >= fabs(n[2]) ? 0 : fabs(n[1]) >= fabs(n[2]) ? 1 : 2;
  double s = n[big] < 0 ? -1.0 / l : 1.0 / l;
  for (int k = 0; k < 3; k++) pl->n[k] = n[k] * s;
  const double *a = vtx(&m->mesh, p->first, 0);
  pl->d = pl->n[0] * a[0] + pl->n[1] * a[1] + pl->n[2] * a[2];
  pl->poly = i;
}

static int by_plane(const void *x, const void *y) {
  const plane *a = x, *b = y;
  for (int k = 0; k < 3; k++) {
    double qa = round(a->n[k] / PLANE_N_TOL), qb = round(b->n[k] / PLANE_N_TOL);
    if (qa != qb) return qa < qb ? -1 : 1;
  }
  double qa = round(a->d / PLANE_D_TOL), qb = round(b->d / PLANE_D_TOL);
  return qa < qb ? -1 : qa > qb;
}

static bool same_plane(const plane *a, const plane *b) {
  for (int k = 0; k < 3; k++)
    if (fabs(a->n[k] - b->n[k]) > PLANE_N_TOL) return false;
  return fabs(a->d - b->d) <= PLANE_D_TOL;
}

/* Clips the convex polygon p (n points, 2-D) by the half-plane left of
 * the edge e0 -> e1; the result in out, its count returned. */
static int clip(const double (*p)[2], int n, const double e0[2], const double e1[2],
                double (*out)[2]) {
  int k = 0;
  for (int i = 0; i < n; i++) {
    const double *a = p[i], *b = p[(i + 1) % n];
    double sa = (e1[0] - e0[0]) * (a[1] - e0[1]) - (e1[1] - e0[1]) * (a[0] - e0[0]);
    double sb = (e1[0] - e0[0]) * (b[1] - e0[1]) - (e1[1] - e0[1]) * (b[0] - e0[0]);
    if (sa >= 0) out[k][0] = a[0], out[k][1] = a[1], k++;
    if ((sa >= 0) != (sb >= 0)) {
      double t = sa / (sa - sb);
      out[k][0] = a[0] + t * (b[0] - a[0]), out[k][1] = a[1] + t * (b[1] - a[1]);
      k++;
    }
  }
  return k;
}

static double area2d(const double (*p)[2], int n) {
  double s = 0;
  for (int i = 0; i < n; i++) s += p[i][0] * p[(i + 1) % n][1] - p[(i + 1) % n][0] * p[i][1];
  return 0.5 * s;
}

/* Triangle t of the mesh in the plane's frame (e1, e2), counter-clockwise. */
static void flat(const vr_mesh_data *m, size_t t, const double e1[3], const double e2[3],
                 double out[3][2]) {
  for (int q = 0; q < 3; q++) {
    const double *v = vtx(m, t, q);
    out[q][0] = v[0] * e1[0] + v[1] * e1[1] + v[2] * e1[2];
    out[q][1] = v[0] * e2[0] + v[1] * e2[1] + v[2] * e2[2];
  }
  if (area2d((const double(*)[2])out, 3) < 0) {
    double s[2] = {out[1][0], out[1][1]};
    out[1][0] = out[2][0], out[1][1] = out[2][1];
    out[2][0] = s[0], out[2][1] = s[1];
  }
}

static double shared_area(const vr_rad_model *m, const plane *pa, size_t a, size_t b) {
  const double *n = pa->n;
  double h[3] = {0, 0, 0};
  h[fabs(n[0]) < 0.6 ? 0 : fabs(n[1]) < 0.6 ? 1 : 2] = 1;
  double e1[3] = {h[1] * n[2] - h[2] * n[1], h[2] * n[0] - h[0] * n[2], h[0] * n[1] - h[1] * n[0]};
  double l = sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
  for (int k = 0; k < 3; k++) e1[k] /= l;
  double e2[3] = {n[1] * e1[2] - n[2] * e1[1], n[2] * e1[0] - n[0] * e1[2], n[0] * e1[1] - n[1] * e1[0]};
  const vr_rad_poly *A = &m->polys[a], *B = &m->polys[b];
  double sum = 0;
  for (size_t ta = A->first; ta < A->first + A->count; ta++) {
    double ra[3][2];
    flat(&m->mesh, ta, e1, e2, ra);
    for (size_t tb = B->first; tb < B->first + B->count; tb++) {
      double rb[3][2], p[9][2], q[9][2];
      flat(&m->mesh, tb, e1, e2, rb);
      memcpy(p, ra, sizeof ra);
      int np = 3;
      for (int e = 0; e < 3 && np > 0; e++) {
        np = clip((const double(*)[2])p, np, rb[e], rb[(e + 1) % 3], q);
        memcpy(p, q, (size_t)np * sizeof p[0]);
      }
      if (np >= 3) sum += area2d((const double(*)[2])p, np);
    }
  }
  return sum;
}

static bool boxes_meet(const plane *a, const plane *b) {
  for (int k = 0; k < 3; k++)
    if (a->lo[k] > b->hi[k] + PLANE_D_TOL || b->lo[k] > a->hi[k] + PLANE_D_TOL) return false;
  return true;
}

static int by_area(const void *x, const void *y) {
  const vr_rad_overlap *a = x, *b = y;
  return a->area > b->area ? -1 : a->area < b->area;
}

vr_status vr_rad_overlaps(const vr_rad_model *m, vr_rad_overlap **out, size_t *n, vr_error *err) {
  *out = NULL, *n = 0;
  if (m->npolys < 2) return VR_OK;
  plane *pl = malloc(m->npolys * sizeof *pl);
  if (!pl) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  for (size_t i = 0; i < m->npolys; i++) plane_of(m, i, &pl[i]);
  qsort(pl, m->npolys, sizeof *pl, by_plane);
  vr_rad_overlap *o = NULL;
  size_t no = 0;
  for (size_t i = 0; i < m->npolys; i++)
    /* Neighbours in key order: a plane that rounds across a key's edge
     * sits next to the key's last members. */
    for (size_t j = i + 1; j < m->npolys && same_plane(&pl[i], &pl[j]); j++) {
      if (!boxes_meet(&pl[i], &pl[j])) continue;
      double area = shared_area(m, &pl[i], pl[i].poly, pl[j].poly);
      if (!(area > AREA_MIN)) continue;
      vr_rad_overlap *g = realloc(o, (no + 1) * sizeof *g);
      if (!g) {
        free(o), free(pl);
        return vr_error_set(err, VR_E_NOMEM, "out of memory");
      }
      o = g;
      size_t a = pl[i].poly, b = pl[j].poly;
      o[no].a = a < b ? a : b, o[no].b = a < b ? b : a, o[no].area = area;
      no++;
    }
  free(pl);
  if (no) qsort(o, no, sizeof *o, by_area);
  *out = o, *n = no;
  return VR_OK;
}
