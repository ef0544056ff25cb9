/* From the scene's objects to what the renderer intersects: rects and boxes
 * become triangles, meshes are read through Assimp (mesh_assimp.c), spheres
 * stay analytic.  Every object's transform is applied here, once, so the
 * rest of the renderer only sees world space.  Per-triangle cumulative areas
 * make the uniform area sampling of emitters a binary search. */
#include "vr/vec3.h"
#include "vr/geometry.h"

#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "geometry/mesh_assimp.h"
#include "geometry/mesh_cache.h"

/* Relative tolerance of "uniform scale" for a sphere's transform: rotations
 * built from degrees are orthogonal to ~1e-16, so this only rejects scales
 * a user wrote. */
#define SPHERE_SCALE_TOL 1e-9
/* A mesh triangle is degenerate below this fraction of the squared diagonal
 * of the mesh's bounds. */
#define DEGENERATE_REL_AREA 1e-12

typedef struct vr_mesh_builder {
  vr_geometry *g;
  const vr_scene *scene;
  vr_error *err;
  size_t vcap, tcap, scap;
  size_t obj_begin; /* first triangle of the object being built */
  bool any_normals;
  vr_mesh_cache *meshes; /* NULL: every mesh read from its file */
} vr_mesh_builder;

static const char *shape_word(vr_shape_kind k) {
  switch (k) {
  case VR_SHAPE_SPHERE: return "sphere";
  case VR_SHAPE_RECT: return "rect";
  case VR_SHAPE_BOX: return "box";
  case VR_SHAPE_MESH: return "mesh";
  }
  return "object";
}

/* "scene:line: sphere 'name': message"; meshes are named by their file. */
static vr_status fail(vr_mesh_builder *b, const vr_scene_object *o, vr_status st, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
static vr_status fail(vr_mesh_builder *b, const vr_scene_object *o, vr_status st, const char *fmt, ...) {
  char msg[VR_ERROR_MESSAGE_MAX];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(msg, sizeof msg, fmt, ap);
  va_end(ap);
  const char *label = o->shape == VR_SHAPE_MESH ? o->mesh_path : o->name;
  if (label)
    return vr_error_at(b->err, st, b->scene->path, o->loc.line, 0, "%s '%s': %s",
                       shape_word(o->shape), label, msg);
  return vr_error_at(b->err, st, b->scene->path, o->loc.line, 0, "%s: %s", shape_word(o->shape),
                     msg);
}

static vr_status nomem(vr_mesh_builder *b) {
  return vr_error_set(b->err, VR_E_NOMEM, "geometry: out of memory");
}

static double norm(const double a[3]) { return sqrt(vr_dot3(a, a)); }

static bool finite3(const double a[3]) {
  return isfinite(a[0]) && isfinite(a[1]) && isfinite(a[2]);
}

static double xform_det(const vr_xform *x) {
  const double(*m)[4] = x->m;
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
         m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

/* Twice the area of a stored triangle, in double from the float vertices
 * the renderer intersects, so areas and sampling match the geometry. */
static double tri_area2(const float *v, uint32_t a, uint32_t b, uint32_t c, double nrm[3]) {
  double e1[3], e2[3];
  const float *pa = v + 3 * (size_t)a, *pb = v + 3 * (size_t)b, *pc = v + 3 * (size_t)c;
  for (int i = 0; i < 3; i++) {
    e1[i] = (double)pb[i] - (double)pa[i];
    e2[i] = (double)pc[i] - (double)pa[i];
  }
  double n[3];
  vr_cross3(e1, e2, n);
  if (nrm) memcpy(nrm, n, sizeof n);
  return norm(n);
}

static vr_status reserve_verts(vr_mesh_builder *b, size_t extra) {
  vr_geometry *g = b->g;
  if (extra > UINT32_MAX || g->nverts + extra >= UINT32_MAX)
    return vr_error_set(b->err, VR_E_RANGE, "geometry: more than %u vertices", UINT32_MAX - 1);
  size_t need = g->nverts + extra;
  if (need <= b->vcap) return VR_OK;
  size_t cap = b->vcap ? 2 * b->vcap : 256;
  if (cap < need) cap = need;
  float *v = realloc(g->verts, 3 * cap * sizeof *v);
  if (!v) return nomem(b);
  g->verts = v;
  float *n = realloc(g->vnormals, 3 * cap * sizeof *n);
  if (!n) return nomem(b);
  g->vnormals = n;
  b->vcap = cap;
  return VR_OK;
}

static vr_status reserve_tris(vr_mesh_builder *b, size_t extra) {
  vr_geometry *g = b->g;
  if (extra > UINT32_MAX || g->ntris + extra >= UINT32_MAX)
    return vr_error_set(b->err, VR_E_RANGE, "geometry: more than %u triangles", UINT32_MAX - 1);
  size_t need = g->ntris + extra;
  if (need <= b->tcap) return VR_OK;
  size_t cap = b->tcap ? 2 * b->tcap : 256;
  if (cap < need) cap = need;
  uint32_t *t = realloc(g->tris, 3 * cap * sizeof *t);
  if (!t) return nomem(b);
  g->tris = t;
  uint32_t *o = realloc(g->tri_object, cap * sizeof *o);
  if (!o) return nomem(b);
  g->tri_object = o;
  float *uv = realloc(g->tri_uv, 6 * cap * sizeof *uv);
  if (!uv) return nomem(b);
  g->tri_uv = uv;
  if (g->tri_rgb) {
    uint8_t *rgb = realloc(g->tri_rgb, 9 * cap);
    if (!rgb) return nomem(b);
    g->tri_rgb = rgb;
  }
  double *cdf = realloc(g->tri_cdf, cap * sizeof *cdf);
  if (!cdf) return nomem(b);
  g->tri_cdf = cdf;
  b->tcap = cap;
  return VR_OK;
}

/* Appends a world-space vertex (room reserved); n is a unit shading normal
 * or NULL. */
static uint32_t add_vertex(vr_mesh_builder *b, const double p[3], const double n[3]) {
  vr_geometry *g = b->g;
  size_t i = g->nverts++;
  for (int k = 0; k < 3; k++) {
    g->verts[3 * i + k] = (float)p[k];
    g->vnormals[3 * i + k] = n ? (float)n[k] : 0.0f;
  }
  return (uint32_t)i;
}

/* Appends a triangle (room reserved).  flip swaps the last two corners, for
 * transforms that mirror. */
static void add_tri(vr_mesh_builder *b, uint32_t object, uint32_t i0, uint32_t i1, uint32_t i2,
                    const float uv[6], const uint8_t rgb[9], bool flip, double area) {
  vr_geometry *g = b->g;
  size_t t = g->ntris++;
  uint32_t c[3] = {i0, flip ? i2 : i1, flip ? i1 : i2};
  memcpy(g->tris + 3 * t, c, sizeof c);
  g->tri_object[t] = object;
  static const int plain[3] = {0, 1, 2}, swapped[3] = {0, 2, 1};
  const int *order = flip ? swapped : plain;
  for (int k = 0; k < 3; k++) {
    g->tri_uv[6 * t + 2 * k] = uv ? uv[2 * order[k]] : 0.0f;
    g->tri_uv[6 * t + 2 * k + 1] = uv ? uv[2 * order[k] + 1] : 0.0f;
    if (g->tri_rgb)
      for (int a = 0; a < 3; a++) g->tri_rgb[9 * t + 3 * k + a] = rgb ? rgb[3 * order[k] + a] : 255;
  }
  g->tri_cdf[t] = (t > b->obj_begin ? g->tri_cdf[t - 1] : 0.0) + area;
}

/* A parallelogram p0 + [0,1]u + [0,1]v in object space, CCW seen from the
 * side of u x v, as two triangles with (u,v) over [0,1]^2. */
static vr_status add_quad(vr_mesh_builder *b, uint32_t object, const vr_scene_object *o, bool flip,
                          const double p0[3], const double eu[3], const double ev[3]) {
  vr_status st;
  if ((st = reserve_verts(b, 4)) != VR_OK || (st = reserve_tris(b, 2)) != VR_OK) return st;
  double corner[4][3];
  for (int k = 0; k < 3; k++) {
    corner[0][k] = p0[k];
    corner[1][k] = p0[k] + eu[k];
    corner[2][k] = p0[k] + eu[k] + ev[k];
    corner[3][k] = p0[k] + ev[k];
  }
  uint32_t idx[4];
  for (int c = 0; c < 4; c++) {
    double w[3];
    vr_xform_point(&o->xform, corner[c], w);
    float f[3] = {(float)w[0], (float)w[1], (float)w[2]};
    if (!isfinite(f[0]) || !isfinite(f[1]) || !isfinite(f[2]))
      return fail(b, o, VR_E_RANGE, "a corner is not finite in world space (%g, %g, %g)", w[0],
                  w[1], w[2]);
    idx[c] = add_vertex(b, w, NULL);
  }
  static const float uv0[6] = {0, 0, 1, 0, 1, 1}, uv1[6] = {0, 0, 1, 1, 0, 1};
  const float *v = b->g->verts;
  add_tri(b, object, idx[0], idx[1], idx[2], uv0, NULL, flip,
          0.5 * tri_area2(v, idx[0], idx[1], idx[2], NULL));
  add_tri(b, object, idx[0], idx[2], idx[3], uv1, NULL, flip,
          0.5 * tri_area2(v, idx[0], idx[2], idx[3], NULL));
  return VR_OK;
}

static vr_status build_rect(vr_mesh_builder *b, uint32_t object, const vr_scene_object *o, bool flip) {
  double n[3] = {o->normal[0], o->normal[1], o->normal[2]};
  double len = norm(n);
  if (!(len > 0.0) || !isfinite(len))
    return fail(b, o, VR_E_RANGE, "normal (%g, %g, %g) has no direction", n[0], n[1], n[2]);
  for (int k = 0; k < 3; k++) n[k] /= len;
  if (!(o->size[0] > 0.0) || !(o->size[1] > 0.0) || !isfinite(o->size[0]) ||
      !isfinite(o->size[1]))
    return fail(b, o, VR_E_RANGE, "size %g x %g must be positive", o->size[0], o->size[1]);
  if (!finite3(o->center) || !finite3(o->up))
    return fail(b, o, VR_E_RANGE, "center and up must be finite");
  /* v: the up hint made perpendicular to the normal; u = v x n, so that
   * u x v = n and the corners run counter-clockwise seen from the normal. */
  double v[3], up[3] = {o->up[0], o->up[1], o->up[2]};
  double ulen = norm(up);
  for (int attempt = 0; attempt < 3; attempt++) {
    double d = vr_dot3(up, n);
    for (int k = 0; k < 3; k++) v[k] = up[k] - d * n[k];
    double vl = norm(v);
    if (ulen > 0.0 && vl > 1e-9 * ulen) {
      for (int k = 0; k < 3; k++) v[k] /= vl;
      break;
    }
    /* No usable hint (only in scenes not made by the parser, which always
     * gives one): the parser's default, world z, or world y when the
     * normal is within ~2.6 degrees of vertical. */
    bool facing_z = fabs(n[2]) >= 0.999;
    up[0] = 0.0;
    up[1] = facing_z ? 1.0 : 0.0;
    up[2] = facing_z ? 0.0 : 1.0;
    ulen = 1.0;
  }
  double u[3];
  vr_cross3(v, n, u);
  double w = o->size[0], h = o->size[1];
  double p0[3], eu[3], ev[3];
  for (int k = 0; k < 3; k++) {
    p0[k] = o->center[k] - 0.5 * w * u[k] - 0.5 * h * v[k];
    eu[k] = w * u[k];
    ev[k] = h * v[k];
  }
  return add_quad(b, object, o, flip, p0, eu, ev);
}

void vr_box_faces(const double lo[3], const double hi[3], double face[6][9]) {
  double dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
  const double f[6][9] = {
      {hi[0], lo[1], lo[2], 0, dy, 0, 0, 0, dz}, {lo[0], lo[1], lo[2], 0, 0, dz, 0, dy, 0},
      {lo[0], hi[1], lo[2], 0, 0, dz, dx, 0, 0}, {lo[0], lo[1], lo[2], dx, 0, 0, 0, 0, dz},
      {lo[0], lo[1], hi[2], dx, 0, 0, 0, dy, 0}, {lo[0], lo[1], lo[2], 0, dy, 0, dx, 0, 0},
  };
  memcpy(face, f, sizeof f);
}

static vr_status build_box(vr_mesh_builder *b, uint32_t object, const vr_scene_object *o, bool flip) {
  const double *lo = o->bmin, *hi = o->bmax;
  for (int k = 0; k < 3; k++)
    if (!(hi[k] > lo[k]) || !isfinite(lo[k]) || !isfinite(hi[k]))
      return fail(b, o, VR_E_RANGE, "min (%g, %g, %g) must be below max (%g, %g, %g)", lo[0],
                  lo[1], lo[2], hi[0], hi[1], hi[2]);
  double face[6][9];
  vr_box_faces(lo, hi, face);
  for (int f = 0; f < 6; f++) {
    vr_status st = add_quad(b, object, o, flip, face[f], face[f] + 3, face[f] + 6);
    if (st != VR_OK) return st;
  }
  return VR_OK;
}

static vr_status build_sphere(vr_mesh_builder *b, uint32_t object, const vr_scene_object *o) {
  if (!(o->radius > 0.0) || !isfinite(o->radius))
    return fail(b, o, VR_E_RANGE, "radius %g must be positive", o->radius);
  if (!finite3(o->center)) return fail(b, o, VR_E_RANGE, "center must be finite");
  /* The linear part must be a rotation (or mirror) times one scale. */
  const double(*m)[4] = o->xform.m;
  double col[3][3], len[3];
  for (int j = 0; j < 3; j++) {
    for (int i = 0; i < 3; i++) col[j][i] = m[i][j];
    len[j] = norm(col[j]);
  }
  double s = (len[0] + len[1] + len[2]) / 3.0;
  bool uniform = s > 0.0 && isfinite(s);
  for (int j = 0; j < 3 && uniform; j++) {
    if (fabs(len[j] - s) > SPHERE_SCALE_TOL * s) uniform = false;
    for (int k = j + 1; k < 3; k++)
      if (fabs(vr_dot3(col[j], col[k])) > SPHERE_SCALE_TOL * s * s) uniform = false;
  }
  if (!uniform)
    return fail(b, o, VR_E_RANGE,
                "non-uniform scale or shear (axes scaled by %g, %g, %g) cannot apply to an "
                "analytic sphere; use a mesh",
                len[0], len[1], len[2]);
  vr_geometry *g = b->g;
  if (g->nspheres == b->scap) {
    size_t cap = b->scap ? 2 * b->scap : 16;
    double *sp = realloc(g->spheres, 4 * cap * sizeof *sp);
    if (!sp) return nomem(b);
    g->spheres = sp;
    uint32_t *so = realloc(g->sphere_object, cap * sizeof *so);
    if (!so) return nomem(b);
    g->sphere_object = so;
    b->scap = cap;
  }
  double c[3];
  vr_xform_point(&o->xform, o->center, c);
  double r = o->radius * s;
  if (!finite3(c) || !isfinite(r) || !(r > 0.0))
    return fail(b, o, VR_E_RANGE, "not finite in world space");
  size_t i = g->nspheres++;
  memcpy(g->spheres + 4 * i, c, sizeof c);
  g->spheres[4 * i + 3] = r;
  g->sphere_object[i] = object;
  g->object_sphere[object] = i;
  g->object_area[object] = 4.0 * M_PI * r * r;
  return VR_OK;
}

/* Whether triangle t of md belongs to object o (all of them, or those of
 * its file material). */
static bool mesh_tri_in(const vr_scene_object *o, const vr_mesh_data *md, size_t t) {
  return o->mesh_material < 0 || (md->tri_material && md->tri_material[t] == (uint32_t)o->mesh_material);
}

static vr_status build_mesh_data(vr_mesh_builder *b, uint32_t object, const vr_scene_object *o,
                                 bool flip, const vr_mesh_data *md) {
  /* An object of one file material takes only the vertices its triangles
   * use: remap[i] is file vertex i's index here (UINT32_MAX if unused) and
   * order its inverse; a whole file keeps its vertices as they are (both
   * NULL). */
  uint32_t *remap = NULL, *order = NULL;
  size_t nv = md->nverts, nt = md->ntris;
  if (o->mesh_material >= 0) {
    remap = malloc((md->nverts ? md->nverts : 1) * sizeof *remap);
    if (!remap) return nomem(b);
    nv = nt = 0;
    for (size_t i = 0; i < md->nverts; i++) remap[i] = UINT32_MAX;
    for (size_t t = 0; t < md->ntris; t++) {
      if (!mesh_tri_in(o, md, t)) continue;
      nt++;
      for (int k = 0; k < 3; k++) {
        uint32_t v = md->tris[3 * t + (size_t)k];
        if (remap[v] == UINT32_MAX) remap[v] = (uint32_t)nv++;
      }
    }
    if (!(order = malloc((nv ? nv : 1) * sizeof *order))) {
      free(remap);
      return nomem(b);
    }
    for (size_t i = 0; i < md->nverts; i++)
      if (remap[i] != UINT32_MAX) order[remap[i]] = (uint32_t)i;
  }
  vr_status st;
  if ((st = reserve_verts(b, nv)) != VR_OK || (st = reserve_tris(b, nt)) != VR_OK) {
    free(remap), free(order);
    return st;
  }
  vr_geometry *g = b->g;
  /* Vertex colours: the per-corner table made when the first object uses
   * them, white for the triangles before it. */
  bool colours = o->vertex_colours && md->rgb;
  if (colours && !g->tri_rgb) {
    if (!(g->tri_rgb = malloc(9 * (b->tcap ? b->tcap : 1)))) {
      free(remap), free(order);
      return nomem(b);
    }
    memset(g->tri_rgb, 255, 9 * g->ntris);
  }
  size_t base = g->nverts;
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (size_t j = 0; j < nv; j++) {
    size_t i = order ? order[j] : j;
    double w[3];
    vr_xform_point(&o->xform, md->pos + 3 * i, w);
    float f[3] = {(float)w[0], (float)w[1], (float)w[2]};
    if (!finite3(md->pos + 3 * i) || !isfinite(f[0]) || !isfinite(f[1]) || !isfinite(f[2])) {
      const double *p = md->pos + 3 * i;
      free(remap), free(order);
      return fail(b, o, VR_E_RANGE, "a vertex is not finite (%g, %g, %g)", p[0], p[1], p[2]);
    }
    double n[3];
    bool has_n = md->nrm && vr_xform_normal(&o->xform, md->nrm + 3 * i, n) && finite3(n);
    if (has_n) b->any_normals = true;
    add_vertex(b, w, has_n ? n : NULL);
    for (int k = 0; k < 3; k++) {
      if (f[k] < lo[k]) lo[k] = f[k];
      if (f[k] > hi[k]) hi[k] = f[k];
    }
  }
  free(order);
  double diag2 = 0.0;
  for (int k = 0; k < 3; k++) diag2 += (hi[k] - lo[k]) * (hi[k] - lo[k]);
  double min_area = DEGENERATE_REL_AREA * diag2;
  size_t kept = 0, dropped = 0;
  for (size_t t = 0; t < md->ntris; t++) {
    if (!mesh_tri_in(o, md, t)) continue;
    uint32_t c[3];
    for (int k = 0; k < 3; k++) {
      uint32_t v = md->tris[3 * t + (size_t)k];
      c[k] = (uint32_t)(base + (remap ? remap[v] : v));
    }
    double area = 0.5 * tri_area2(g->verts, c[0], c[1], c[2], NULL);
    if (!(area > 0.0) || area < min_area) {
      dropped++;
      continue;
    }
    float uv[6] = {0};
    if (md->uv)
      for (int k = 0; k < 3; k++) {
        uv[2 * k] = (float)md->uv[2 * md->tris[3 * t + (size_t)k]];
        uv[2 * k + 1] = (float)md->uv[2 * md->tris[3 * t + (size_t)k] + 1];
      }
    uint8_t rgb[9];
    if (colours)
      for (int k = 0; k < 3; k++) memcpy(rgb + 3 * k, md->rgb + 3 * (size_t)md->tris[3 * t + (size_t)k], 3);
    add_tri(b, object, c[0], c[1], c[2], uv, colours ? rgb : NULL, flip, area);
    kept++;
  }
  free(remap);
  if (kept == 0)
    return fail(b, o, VR_E_RANGE, "all %zu triangles are degenerate (zero area)", nt);
  g->degenerate_dropped += dropped;
  return VR_OK;
}

static vr_status build_mesh(vr_mesh_builder *b, uint32_t object, const vr_scene_object *o, bool flip) {
  vr_mesh_data own;
  const vr_mesh_data *md = &own;
  vr_status st = b->meshes ? vr_mesh_cache_get(b->meshes, o->mesh_path, &md, b->err)
                           : vr_mesh_read(o->mesh_path, &own, b->err);
  if (st != VR_OK) {
    /* vr_mesh_read's message already says "mesh 'PATH': ...". */
    vr_error_prefix(b->err, "%s:%ld: ", b->scene->path ? b->scene->path : "<input>",
                    o->loc.line);
    return st;
  }
  st = build_mesh_data(b, object, o, flip, md);
  if (!b->meshes) vr_mesh_data_free(&own);
  return st;
}

static vr_status build_object(vr_mesh_builder *b, uint32_t object) {
  const vr_scene_object *o = &b->scene->objects[object];
  const double(*m)[4] = o->xform.m;
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 4; j++)
      if (!isfinite(m[i][j])) return fail(b, o, VR_E_RANGE, "transform is not finite");
  double det = xform_det(&o->xform);
  if (!(fabs(det) > 0.0) || !isfinite(det))
    return fail(b, o, VR_E_RANGE, "transform is singular (a scale of 0?)");
  bool flip = det < 0.0;
  vr_geometry *g = b->g;
  b->obj_begin = g->ntris;
  g->object_tri_begin[object] = g->object_tri_end[object] = 0;
  g->object_sphere[object] = SIZE_MAX;
  vr_status st;
  switch (o->shape) {
  case VR_SHAPE_SPHERE: return build_sphere(b, object, o);
  case VR_SHAPE_RECT: st = build_rect(b, object, o, flip); break;
  case VR_SHAPE_BOX: st = build_box(b, object, o, flip); break;
  case VR_SHAPE_MESH:
    if (!o->mesh_path) return fail(b, o, VR_E_ARG, "no file name");
    st = build_mesh(b, object, o, flip);
    break;
  default: return fail(b, o, VR_E_ARG, "unknown shape %d", (int)o->shape);
  }
  if (st != VR_OK) return st;
  g->object_tri_begin[object] = b->obj_begin;
  g->object_tri_end[object] = g->ntris;
  g->object_area[object] = g->ntris > b->obj_begin ? g->tri_cdf[g->ntris - 1] : 0.0;
  return VR_OK;
}

static void compute_bounds(vr_geometry *g) {
  bool any = false;
  double lo[3] = {0}, hi[3] = {0};
  for (size_t t = 0; t < g->ntris; t++)
    for (int c = 0; c < 3; c++) {
      const float *p = g->verts + 3 * (size_t)g->tris[3 * t + (size_t)c];
      for (int k = 0; k < 3; k++) {
        if (!any || p[k] < lo[k]) lo[k] = p[k];
        if (!any || p[k] > hi[k]) hi[k] = p[k];
      }
      any = true;
    }
  for (size_t s = 0; s < g->nspheres; s++) {
    const double *sp = g->spheres + 4 * s;
    for (int k = 0; k < 3; k++) {
      if (!any || sp[k] - sp[3] < lo[k]) lo[k] = sp[k] - sp[3];
      if (!any || sp[k] + sp[3] > hi[k]) hi[k] = sp[k] + sp[3];
    }
    any = true;
  }
  memcpy(g->bmin, lo, sizeof lo);
  memcpy(g->bmax, hi, sizeof hi);
}

void vr_geometry_destroy(vr_geometry *g) {
  if (!g) return;
  free(g->verts);
  free(g->tris);
  free(g->tri_object);
  free(g->tri_uv);
  free(g->tri_rgb);
  free(g->vnormals);
  free(g->spheres);
  free(g->sphere_object);
  free(g->object_area);
  free(g->object_tri_begin);
  free(g->object_tri_end);
  free(g->tri_cdf);
  free(g->object_sphere);
  free(g);
}

vr_status vr_geometry_build(const vr_scene *scene, vr_geometry **out, vr_error *err) {
  return vr_geometry_build_range(scene, 0, scene ? scene->nobjects : 0, NULL, out, err);
}

vr_status vr_geometry_build_range(const vr_scene *scene, size_t first, size_t last,
                                  struct vr_mesh_cache *meshes, vr_geometry **out,
                                  vr_error *err) {
  if (!out) return vr_error_set(err, VR_E_ARG, "vr_geometry_build: no output");
  *out = NULL;
  if (!scene) return vr_error_set(err, VR_E_ARG, "vr_geometry_build: no scene");
  if (first > last || last > scene->nobjects)
    return vr_error_set(err, VR_E_ARG, "vr_geometry_build: objects [%zu, %zu) of %zu", first,
                        last, scene->nobjects);
  if (scene->nobjects >= UINT32_MAX)
    return vr_error_set(err, VR_E_RANGE, "geometry: %zu objects, too many", scene->nobjects);
  vr_geometry *g = calloc(1, sizeof *g);
  if (!g) return vr_error_set(err, VR_E_NOMEM, "geometry: out of memory");
  vr_mesh_builder b = {.g = g, .scene = scene, .err = err, .meshes = meshes};
  size_t n = scene->nobjects;
  g->nobjects = n;
  if (n) {
    g->object_area = calloc(n, sizeof *g->object_area);
    g->object_tri_begin = calloc(n, sizeof *g->object_tri_begin);
    g->object_tri_end = calloc(n, sizeof *g->object_tri_end);
    g->object_sphere = calloc(n, sizeof *g->object_sphere);
    if (!g->object_area || !g->object_tri_begin || !g->object_tri_end || !g->object_sphere) {
      vr_geometry_destroy(g);
      return vr_error_set(err, VR_E_NOMEM, "geometry: out of memory");
    }
  }
  for (size_t i = 0; i < n; i++) g->object_sphere[i] = SIZE_MAX;
  for (size_t i = first; i < last; i++) {
    vr_status st = build_object(&b, (uint32_t)i);
    if (st != VR_OK) {
      vr_geometry_destroy(g);
      return st;
    }
  }
  if (!b.any_normals) {
    free(g->vnormals);
    g->vnormals = NULL;
  }
  compute_bounds(g);
  *out = g;
  return VR_OK;
}

void vr_geometry_sample_object(const vr_geometry *g, uint32_t object, double u1, double u2,
                               double u3, double p[3], double n[3]) {
  memset(p, 0, 3 * sizeof *p);
  memset(n, 0, 3 * sizeof *n);
  if (!g || object >= g->nobjects) return;
  size_t s = g->object_sphere[object];
  if (s != SIZE_MAX) {
    const double *sp = g->spheres + 4 * s;
    double z = 1.0 - 2.0 * u2, r = sqrt(fmax(0.0, 1.0 - z * z)), phi = 2.0 * M_PI * u3;
    n[0] = r * cos(phi);
    n[1] = r * sin(phi);
    n[2] = z;
    for (int k = 0; k < 3; k++) p[k] = sp[k] + sp[3] * n[k];
    return;
  }
  size_t lo = g->object_tri_begin[object], hi = g->object_tri_end[object];
  if (hi <= lo) return;
  /* The first triangle whose cumulative area exceeds u1 * area. */
  double target = u1 * g->tri_cdf[hi - 1];
  size_t a = lo, b = hi - 1;
  while (a < b) {
    size_t mid = a + (b - a) / 2;
    if (g->tri_cdf[mid] > target)
      b = mid;
    else
      a = mid + 1;
  }
  const uint32_t *t = g->tris + 3 * a;
  const float *v0 = g->verts + 3 * (size_t)t[0], *v1 = g->verts + 3 * (size_t)t[1],
              *v2 = g->verts + 3 * (size_t)t[2];
  double su = sqrt(u2), b0 = 1.0 - su, b1 = u3 * su, b2 = 1.0 - b0 - b1;
  for (int k = 0; k < 3; k++) p[k] = b0 * v0[k] + b1 * v1[k] + b2 * v2[k];
  double nn[3];
  double len = tri_area2(g->verts, t[0], t[1], t[2], nn);
  if (len > 0.0)
    for (int k = 0; k < 3; k++) n[k] = nn[k] / len;
}
