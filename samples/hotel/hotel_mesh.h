/* Triangle meshes for the hotel generator: parametric surfaces tessellated
 * on a grid (rounded boxes, surfaces of revolution, draped and pleated
 * cloth), area-weighted vertex normals, and binary PLY output. */
#ifndef HOTEL_MESH_H
#define HOTEL_MESH_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct mesh {
  size_t nv, nt, capv, capt;
  float *p;    /* 3 per vertex */
  float *n;    /* 3 per vertex, filled by mesh_normals */
  float *uv;   /* 2 per vertex: the surface's (u, v) on grids, metres along a box's faces */
  uint32_t *t; /* 3 per triangle */
} mesh;

/* A point of a surface at (u, v) in [0,1]^2. */
typedef void (*surface_fn)(const void *ctx, double u, double v, double p[3]);

/* Tessellates f on an nu x nv grid of quads (two triangles each);
 * wrap_u joins u = 1 to u = 0 (a closed ring). */
bool mesh_grid(mesh *m, surface_fn f, const void *ctx, int nu, int nv, bool wrap_u);
/* An axis-aligned box [lo, hi] (12 triangles). */
bool mesh_box(mesh *m, const double lo[3], const double hi[3]);
/* A rounded box: a superellipsoid of half sizes (a, b, c) about centre,
 * exponent e (small = boxy, 1 = ellipsoid), on an n x n/2 grid. */
bool mesh_rounded_box(mesh *m, const double centre[3], double a, double b, double c, double e,
                      int n);
/* A surface of revolution about the vertical through (cx, cy): profile
 * radius r[i] at height z[i], i = 0..np-1, interpolated on nv rows. */
bool mesh_lathe(mesh *m, double cx, double cy, const double *r, const double *z, int np, int nu,
                int nv);
/* Drops the triangles of (near) zero area that a pole of a grid makes. */
void mesh_drop_degenerate(mesh *m);
/* Vertex normals: the area-weighted mean of the triangles around each. */
void mesh_normals(mesh *m);
/* Binary little-endian PLY with positions, normals and texture coordinates
 * (s, t); false on an I/O error. */
bool mesh_write_ply(const mesh *m, const char *path);
void mesh_free(mesh *m);

#endif
