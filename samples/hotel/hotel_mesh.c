/* Meshes for the hotel generator (hotel_mesh.h). */
#include "hotel_mesh.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static bool reserve(mesh *m, size_t nv, size_t nt) {
  if (m->nv + nv > m->capv) {
    size_t cap = m->capv ? m->capv : 1024;
    while (cap < m->nv + nv) cap *= 2;
    float *p = realloc(m->p, cap * 3 * sizeof *p);
    if (!p) return false;
    m->p = p;
    float *uv = realloc(m->uv, cap * 2 * sizeof *uv);
    if (!uv) return false;
    m->uv = uv;
    m->capv = cap;
  }
  if (m->nt + nt > m->capt) {
    size_t cap = m->capt ? m->capt : 1024;
    while (cap < m->nt + nt) cap *= 2;
    uint32_t *t = realloc(m->t, cap * 3 * sizeof *t);
    if (!t) return false;
    m->t = t;
    m->capt = cap;
  }
  return true;
}

static void tri(mesh *m, uint32_t a, uint32_t b, uint32_t c) {
  uint32_t *t = m->t + 3 * m->nt++;
  t[0] = a, t[1] = b, t[2] = c;
}

bool mesh_grid(mesh *m, surface_fn f, const void *ctx, int nu, int nv, bool wrap_u) {
  int cols = wrap_u ? nu : nu + 1;
  if (!reserve(m, (size_t)cols * (size_t)(nv + 1), 2 * (size_t)nu * (size_t)nv)) return false;
  uint32_t base = (uint32_t)m->nv;
  for (int j = 0; j <= nv; j++)
    for (int i = 0; i < cols; i++) {
      double p[3];
      f(ctx, (double)i / nu, (double)j / nv, p);
      m->uv[2 * m->nv] = (float)i / (float)nu, m->uv[2 * m->nv + 1] = (float)j / (float)nv;
      float *q = m->p + 3 * m->nv++;
      q[0] = (float)p[0], q[1] = (float)p[1], q[2] = (float)p[2];
    }
  for (int j = 0; j < nv; j++)
    for (int i = 0; i < nu; i++) {
      uint32_t a = base + (uint32_t)(j * cols + i), b = base + (uint32_t)(j * cols + (i + 1) % cols);
      uint32_t c = a + (uint32_t)cols, d = b + (uint32_t)cols;
      if (!wrap_u) b = a + 1, d = c + 1;
      tri(m, a, b, d);
      tri(m, a, d, c);
    }
  return true;
}

bool mesh_box(mesh *m, const double lo[3], const double hi[3]) {
  if (!reserve(m, 24, 12)) return false;
  /* Each face with its own four corners, so normals stay flat. */
  static const int face[6][4][3] = {
      {{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}}, {{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}},
      {{0, 1, 0}, {0, 1, 1}, {1, 1, 1}, {1, 1, 0}}, {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}},
      {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}, {{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}}};
  for (int f = 0; f < 6; f++) {
    uint32_t base = (uint32_t)m->nv;
    /* (u, v): metres along the face's first and second varying axes. */
    int fixed = face[f][0][0] == face[f][2][0] ? 0 : face[f][0][1] == face[f][2][1] ? 1 : 2;
    int au = (fixed + 1) % 3, av = (fixed + 2) % 3;
    for (int k = 0; k < 4; k++) {
      float *q = m->p + 3 * m->nv;
      for (int a = 0; a < 3; a++) q[a] = (float)(face[f][k][a] ? hi[a] : lo[a]);
      m->uv[2 * m->nv] = q[au], m->uv[2 * m->nv + 1] = q[av];
      m->nv++;
    }
    tri(m, base, base + 1, base + 2);
    tri(m, base, base + 2, base + 3);
  }
  return true;
}

typedef struct rbox {
  double c[3], a, b, h, e;
} rbox;

static double spow(double x, double e) { return copysign(pow(fabs(x), e), x); }

static void rbox_at(const void *ctx, double u, double v, double p[3]) {
  const rbox *r = ctx;
  double phi = 2 * M_PI * u, th = M_PI * (v - 0.5);
  double ct = spow(cos(th), r->e), st = spow(sin(th), r->e);
  p[0] = r->c[0] + r->a * ct * spow(cos(phi), r->e);
  p[1] = r->c[1] + r->b * ct * spow(sin(phi), r->e);
  p[2] = r->c[2] + r->h * st;
}

bool mesh_rounded_box(mesh *m, const double centre[3], double a, double b, double c, double e,
                      int n) {
  rbox r = {{centre[0], centre[1], centre[2]}, a, b, c, e};
  return mesh_grid(m, rbox_at, &r, n, n / 2, true);
}

typedef struct lathe {
  double cx, cy;
  const double *r, *z;
  int np;
} lathe;

static void lathe_at(const void *ctx, double u, double v, double p[3]) {
  const lathe *l = ctx;
  double s = v * (l->np - 1);
  int i = (int)s;
  if (i >= l->np - 1) i = l->np - 2;
  double f = s - i, r = l->r[i] * (1 - f) + l->r[i + 1] * f, z = l->z[i] * (1 - f) + l->z[i + 1] * f;
  double phi = 2 * M_PI * u;
  p[0] = l->cx + r * cos(phi);
  p[1] = l->cy + r * sin(phi);
  p[2] = z;
}

bool mesh_lathe(mesh *m, double cx, double cy, const double *r, const double *z, int np, int nu,
                int nv) {
  lathe l = {cx, cy, r, z, np};
  return mesh_grid(m, lathe_at, &l, nu, nv, true);
}

void mesh_drop_degenerate(mesh *m) {
  size_t kept = 0;
  for (size_t t = 0; t < m->nt; t++) {
    const uint32_t *ix = m->t + 3 * t;
    const float *a = m->p + 3 * ix[0], *b = m->p + 3 * ix[1], *c = m->p + 3 * ix[2];
    double e1[3], e2[3];
    for (int k = 0; k < 3; k++) e1[k] = (double)b[k] - a[k], e2[k] = (double)c[k] - a[k];
    double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                   e1[0] * e2[1] - e1[1] * e2[0]};
    /* the renderer's own threshold is relative; this one only drops the
     * rings a pole collapses into a point */
    if (n[0] * n[0] + n[1] * n[1] + n[2] * n[2] > 1e-24) memmove(m->t + 3 * kept++, ix, 12);
  }
  m->nt = kept;
}

void mesh_normals(mesh *m) {
  free(m->n);
  m->n = calloc(3 * m->nv + 1, sizeof *m->n);
  if (!m->n) return;
  double *acc = calloc(3 * m->nv + 1, sizeof *acc);
  if (!acc) return;
  for (size_t t = 0; t < m->nt; t++) {
    const uint32_t *ix = m->t + 3 * t;
    const float *a = m->p + 3 * ix[0], *b = m->p + 3 * ix[1], *c = m->p + 3 * ix[2];
    double e1[3], e2[3];
    for (int k = 0; k < 3; k++) e1[k] = (double)b[k] - a[k], e2[k] = (double)c[k] - a[k];
    double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                   e1[0] * e2[1] - e1[1] * e2[0]};
    for (int v = 0; v < 3; v++)
      for (int k = 0; k < 3; k++) acc[3 * ix[v] + k] += n[k];
  }
  for (size_t v = 0; v < m->nv; v++) {
    double l = sqrt(acc[3 * v] * acc[3 * v] + acc[3 * v + 1] * acc[3 * v + 1] +
                    acc[3 * v + 2] * acc[3 * v + 2]);
    for (int k = 0; k < 3; k++) m->n[3 * v + k] = l > 0 ? (float)(acc[3 * v + k] / l) : 0.0f;
  }
  free(acc);
}

bool mesh_write_ply(const mesh *m, const char *path) {
  FILE *f = fopen(path, "wb");
  if (!f) return false;
  fprintf(f,
          "ply\nformat binary_little_endian 1.0\ncomment written by vr-hotel (Virtuelium-C)\n"
          "element vertex %zu\nproperty float x\nproperty float y\nproperty float z\n"
          "property float nx\nproperty float ny\nproperty float nz\n"
          "property float s\nproperty float t\n"
          "element face %zu\nproperty list uchar int vertex_indices\nend_header\n",
          m->nv, m->nt);
  bool ok = true;
  for (size_t v = 0; ok && v < m->nv; v++) {
    float rec[8] = {m->p[3 * v], m->p[3 * v + 1], m->p[3 * v + 2], 0, 0, 1, m->uv[2 * v],
                    m->uv[2 * v + 1]};
    if (m->n) memcpy(rec + 3, m->n + 3 * v, 3 * sizeof *rec);
    ok = fwrite(rec, sizeof rec, 1, f) == 1;
  }
  for (size_t t = 0; ok && t < m->nt; t++) {
    unsigned char three = 3;
    int32_t ix[3] = {(int32_t)m->t[3 * t], (int32_t)m->t[3 * t + 1], (int32_t)m->t[3 * t + 2]};
    ok = fwrite(&three, 1, 1, f) == 1 && fwrite(ix, sizeof ix, 1, f) == 1;
  }
  return fclose(f) == 0 && ok;
}

void mesh_free(mesh *m) {
  free(m->p);
  free(m->n);
  free(m->t);
  free(m->uv);
  memset(m, 0, sizeof *m);
}
