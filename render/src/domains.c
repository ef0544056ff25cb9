/* Sub-domains: the kd-tree of cells, one Embree scene per cell, and the
 * parameter-based walk of a ray through them (see vr/domains.h for why the
 * walk uses no epsilon and why the hit is the same for any number of cells). */
#include "vr/domains.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <embree3/rtcore.h>

typedef struct kd_node {
  int axis;       /* -1 for a leaf */
  double split;
  int child[2];   /* nodes below (0) and above (1) the split */
  int cell;       /* leaf: cell index */
} kd_node;

typedef struct cell {
  double lo[3], hi[3];   /* box used to assign primitives (infinite sides clipped to the scene) */
  size_t ntris, nspheres;
  uint32_t *tris;        /* global triangle indices */
  uint32_t *spheres;     /* global sphere indices */
  RTCScene scene;
} cell;

struct vr_domains {
  const vr_geometry *g;
  RTCDevice device;
  float *verts;          /* padded copy: Embree reads 16 bytes at the last vertex */
  int ncells;
  cell *cells;
  int nnodes;
  kd_node *nodes;
  int error_code;
};

static void tri_bounds(const vr_geometry *g, uint32_t t, double lo[3], double hi[3]) {
  for (int a = 0; a < 3; a++) {
    lo[a] = INFINITY;
    hi[a] = -INFINITY;
  }
  for (int k = 0; k < 3; k++) {
    const float *v = g->verts + 3 * (size_t)g->tris[3 * (size_t)t + k];
    for (int a = 0; a < 3; a++) {
      if (v[a] < lo[a]) lo[a] = v[a];
      if (v[a] > hi[a]) hi[a] = v[a];
    }
  }
}

static void sphere_bounds(const vr_geometry *g, uint32_t s, double lo[3], double hi[3]) {
  const double *c = g->spheres + 4 * (size_t)s;
  for (int a = 0; a < 3; a++) {
    lo[a] = c[a] - c[3];
    hi[a] = c[a] + c[3];
  }
}

static bool overlaps(const double lo[3], const double hi[3], const double blo[3],
                     const double bhi[3]) {
  for (int a = 0; a < 3; a++)
    if (hi[a] < blo[a] || lo[a] > bhi[a]) return false;
  return true;
}

/* Centroid coordinate of primitive i (triangles first, then spheres). */
static double centroid(const vr_geometry *g, const cell *c, size_t i, int axis) {
  double lo[3], hi[3];
  if (i < c->ntris)
    tri_bounds(g, c->tris[i], lo, hi);
  else
    sphere_bounds(g, c->spheres[i - c->ntris], lo, hi);
  return 0.5 * (lo[axis] + hi[axis]);
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* Distributes the primitives of parent into the child box lo..hi. */
static vr_status fill_child(const vr_geometry *g, const cell *parent, cell *child, vr_error *err) {
  child->tris = malloc((parent->ntris + 1) * sizeof *child->tris);
  child->spheres = malloc((parent->nspheres + 1) * sizeof *child->spheres);
  if (!child->tris || !child->spheres) return vr_error_set(err, VR_E_NOMEM, "sub-domains: out of memory");
  child->ntris = child->nspheres = 0;
  double lo[3], hi[3];
  for (size_t i = 0; i < parent->ntris; i++) {
    tri_bounds(g, parent->tris[i], lo, hi);
    if (overlaps(lo, hi, child->lo, child->hi)) child->tris[child->ntris++] = parent->tris[i];
  }
  for (size_t i = 0; i < parent->nspheres; i++) {
    sphere_bounds(g, parent->spheres[i], lo, hi);
    if (overlaps(lo, hi, child->lo, child->hi)) child->spheres[child->nspheres++] = parent->spheres[i];
  }
  return VR_OK;
}

/* Splits cell ci into itself (below) and a new cell (above). */
static vr_status split_cell(vr_domains *d, int ci, int leaf_node, vr_error *err) {
  const vr_geometry *g = d->g;
  cell *c = &d->cells[ci];
  int axis = 0;
  for (int a = 1; a < 3; a++)
    if (c->hi[a] - c->lo[a] > c->hi[axis] - c->lo[axis]) axis = a;
  size_t n = c->ntris + c->nspheres;
  double split = 0.5 * (c->lo[axis] + c->hi[axis]);
  if (n > 0) {
    double *cs = malloc(n * sizeof *cs);
    if (!cs) return vr_error_set(err, VR_E_NOMEM, "sub-domains: out of memory");
    for (size_t i = 0; i < n; i++) cs[i] = centroid(g, c, i, axis);
    qsort(cs, n, sizeof *cs, cmp_double);
    double med = cs[n / 2];
    free(cs);
    /* A median on the box's face would leave one side without volume. */
    if (med > c->lo[axis] && med < c->hi[axis]) split = med;
  }
  cell below = {0}, above = {0};
  memcpy(below.lo, c->lo, sizeof below.lo);
  memcpy(below.hi, c->hi, sizeof below.hi);
  memcpy(above.lo, c->lo, sizeof above.lo);
  memcpy(above.hi, c->hi, sizeof above.hi);
  below.hi[axis] = split;
  above.lo[axis] = split;
  vr_status st = fill_child(g, c, &below, err);
  if (!st) st = fill_child(g, c, &above, err);
  if (st) {
    free(below.tris), free(below.spheres), free(above.tris), free(above.spheres);
    return st;
  }
  free(c->tris);
  free(c->spheres);
  int ai = d->ncells++;
  d->cells[ci] = below;
  d->cells[ai] = above;
  int nb = d->nnodes++, na = d->nnodes++;
  d->nodes[nb] = (kd_node){.axis = -1, .cell = ci};
  d->nodes[na] = (kd_node){.axis = -1, .cell = ai};
  d->nodes[leaf_node] = (kd_node){.axis = axis, .split = split, .child = {nb, na}, .cell = -1};
  return VR_OK;
}

static void on_embree_error(void *user, enum RTCError code, const char *str) {
  (void)str;
  vr_domains *d = user;
  if (!d->error_code) d->error_code = (int)code;
}

static vr_status build_scene(vr_domains *d, cell *c, vr_error *err) {
  c->scene = rtcNewScene(d->device);
  if (!c->scene) return vr_error_set(err, VR_E_NOMEM, "Embree: cannot create a scene");
  /* Robust mode makes the triangle test watertight, so a ray never slips
   * through the shared edge of two triangles. */
  rtcSetSceneFlags(c->scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(c->scene, RTC_BUILD_QUALITY_HIGH);
  const vr_geometry *g = d->g;
  if (c->ntris) {
    RTCGeometry geom = rtcNewGeometry(d->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, d->verts, 0,
                               3 * sizeof(float), g->nverts);
    unsigned *idx = rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                            3 * sizeof(unsigned), c->ntris);
    if (!idx) {
      rtcReleaseGeometry(geom);
      return vr_error_set(err, VR_E_NOMEM, "Embree: cannot allocate an index buffer");
    }
    for (size_t i = 0; i < c->ntris; i++)
      for (int k = 0; k < 3; k++) idx[3 * i + k] = g->tris[3 * (size_t)c->tris[i] + k];
    rtcCommitGeometry(geom);
    rtcAttachGeometryByID(c->scene, geom, 0);
    rtcReleaseGeometry(geom);
  }
  if (c->nspheres) {
    RTCGeometry geom = rtcNewGeometry(d->device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
    float *v = rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                                       4 * sizeof(float), c->nspheres);
    if (!v) {
      rtcReleaseGeometry(geom);
      return vr_error_set(err, VR_E_NOMEM, "Embree: cannot allocate a sphere buffer");
    }
    for (size_t i = 0; i < c->nspheres; i++)
      for (int k = 0; k < 4; k++) v[4 * i + k] = (float)g->spheres[4 * (size_t)c->spheres[i] + k];
    rtcCommitGeometry(geom);
    rtcAttachGeometryByID(c->scene, geom, 1);
    rtcReleaseGeometry(geom);
  }
  rtcCommitScene(c->scene);
  if (d->error_code)
    return vr_error_set(err, VR_E_NUMERIC, "Embree: error %d while building a sub-domain",
                        d->error_code);
  return VR_OK;
}

vr_status vr_domains_build(const vr_geometry *g, int S, vr_domains **out, vr_error *err) {
  *out = NULL;
  if (S < 1 || S > 4096)
    return vr_error_set(err, VR_E_ARG, "sub-domains: S = %d, expected 1 to 4096", S);
  vr_domains *d = calloc(1, sizeof *d);
  if (!d) return vr_error_set(err, VR_E_NOMEM, "sub-domains: out of memory");
  d->g = g;
  vr_status st = VR_OK;
  d->cells = calloc((size_t)S, sizeof *d->cells);
  d->nodes = calloc(2 * (size_t)S, sizeof *d->nodes);
  d->verts = malloc((3 * g->nverts + 4) * sizeof(float));
  if (!d->cells || !d->nodes || !d->verts) {
    st = vr_error_set(err, VR_E_NOMEM, "sub-domains: out of memory");
    goto fail;
  }
  if (g->nverts) memcpy(d->verts, g->verts, 3 * g->nverts * sizeof(float));
  memset(d->verts + 3 * g->nverts, 0, 4 * sizeof(float));
  d->device = rtcNewDevice("threads=1,verbose=0");
  if (!d->device) {
    st = vr_error_set(err, VR_E_NUMERIC, "Embree: cannot create a device (error %d)",
                      (int)rtcGetDeviceError(NULL));
    goto fail;
  }
  rtcSetDeviceErrorFunction(d->device, on_embree_error, d);

  cell *root = &d->cells[0];
  memcpy(root->lo, g->bmin, sizeof root->lo);
  memcpy(root->hi, g->bmax, sizeof root->hi);
  root->ntris = g->ntris;
  root->nspheres = g->nspheres;
  root->tris = malloc((g->ntris + 1) * sizeof *root->tris);
  root->spheres = malloc((g->nspheres + 1) * sizeof *root->spheres);
  if (!root->tris || !root->spheres) {
    st = vr_error_set(err, VR_E_NOMEM, "sub-domains: out of memory");
    goto fail;
  }
  for (size_t i = 0; i < g->ntris; i++) root->tris[i] = (uint32_t)i;
  for (size_t i = 0; i < g->nspheres; i++) root->spheres[i] = (uint32_t)i;
  d->ncells = 1;
  d->nnodes = 1;
  d->nodes[0] = (kd_node){.axis = -1, .cell = 0};
  while (d->ncells < S) {
    /* The leaf with the most primitives; the lowest index among equals. */
    int best = 0;
    for (int n = 0; n < d->nnodes; n++) {
      if (d->nodes[n].axis >= 0) continue;
      const cell *c = &d->cells[d->nodes[n].cell];
      const cell *b = &d->cells[d->nodes[best].cell];
      if (d->nodes[best].axis >= 0 || c->ntris + c->nspheres > b->ntris + b->nspheres) best = n;
    }
    st = split_cell(d, d->nodes[best].cell, best, err);
    if (st) goto fail;
  }
  for (int i = 0; i < d->ncells; i++) {
    st = build_scene(d, &d->cells[i], err);
    if (st) goto fail;
  }
  *out = d;
  return VR_OK;
fail:
  vr_domains_destroy(d);
  return st;
}

void vr_domains_destroy(vr_domains *d) {
  if (!d) return;
  for (int i = 0; d->cells && i < d->ncells; i++) {
    if (d->cells[i].scene) rtcReleaseScene(d->cells[i].scene);
    free(d->cells[i].tris);
    free(d->cells[i].spheres);
  }
  if (d->device) rtcReleaseDevice(d->device);
  free(d->cells);
  free(d->nodes);
  free(d->verts);
  free(d);
}

int vr_domains_count(const vr_domains *d) { return d->ncells; }

size_t vr_domains_cell_primitives(const vr_domains *d, int cell) {
  return d->cells[cell].ntris + d->cells[cell].nspheres;
}

void vr_domains_cell_bounds(const vr_domains *d, int cell, double lo[3], double hi[3]) {
  memcpy(lo, d->cells[cell].lo, 3 * sizeof *lo);
  memcpy(hi, d->cells[cell].hi, 3 * sizeof *hi);
}

int vr_domains_locate(const vr_domains *d, const double org[3], const double dir[3], double t,
                      double *t_exit) {
  double te = INFINITY;
  int n = 0;
  while (d->nodes[n].axis >= 0) {
    const kd_node *k = &d->nodes[n];
    int a = k->axis, side;
    if (dir[a] == 0.0) {
      side = org[a] >= k->split; /* in the plane: the upper side, always */
    } else {
      double ts = (k->split - org[a]) / dir[a];
      if (ts > t) {
        side = dir[a] < 0; /* not yet crossed: on the side it comes from */
        if (ts < te) te = ts;
      } else {
        side = dir[a] > 0; /* crossed at or before t */
      }
    }
    n = k->child[side];
  }
  *t_exit = te;
  return d->nodes[n].cell;
}

static void normalise(double v[3]) {
  double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (l > 0)
    for (int a = 0; a < 3; a++) v[a] /= l;
}

bool vr_domains_intersect(const vr_domains *d, int ci, const double org[3], const double dir[3],
                          double tnear, double tfar, vr_hit *hit) {
  const cell *c = &d->cells[ci];
  if (!c->ntris && !c->nspheres) return false;
  if (!(tfar >= tnear)) return false;
  struct RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  struct RTCRayHit rh;
  rh.ray.org_x = (float)org[0];
  rh.ray.org_y = (float)org[1];
  rh.ray.org_z = (float)org[2];
  rh.ray.dir_x = (float)dir[0];
  rh.ray.dir_y = (float)dir[1];
  rh.ray.dir_z = (float)dir[2];
  rh.ray.tnear = (float)tnear;
  rh.ray.tfar = isinf(tfar) ? INFINITY : (float)tfar;
  rh.ray.time = 0.0f;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(c->scene, &ctx, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;

  const vr_geometry *g = d->g;
  hit->t = rh.ray.tfar;
  for (int a = 0; a < 3; a++) hit->p[a] = org[a] + hit->t * dir[a];
  if (rh.hit.geomID == 0) {
    uint32_t t = c->tris[rh.hit.primID];
    hit->sphere = false;
    hit->prim = t;
    hit->object = g->tri_object[t];
    const uint32_t *ix = g->tris + 3 * (size_t)t;
    const float *v0 = g->verts + 3 * (size_t)ix[0], *v1 = g->verts + 3 * (size_t)ix[1],
                *v2 = g->verts + 3 * (size_t)ix[2];
    double e1[3], e2[3];
    for (int a = 0; a < 3; a++) {
      e1[a] = (double)v1[a] - v0[a];
      e2[a] = (double)v2[a] - v0[a];
    }
    hit->ng[0] = e1[1] * e2[2] - e1[2] * e2[1];
    hit->ng[1] = e1[2] * e2[0] - e1[0] * e2[2];
    hit->ng[2] = e1[0] * e2[1] - e1[1] * e2[0];
    normalise(hit->ng);
    double u = rh.hit.u, v = rh.hit.v, w = 1.0 - u - v;
    const float *n0 = NULL, *n1 = NULL, *n2 = NULL;
    if (g->vnormals) {
      n0 = g->vnormals + 3 * (size_t)ix[0];
      n1 = g->vnormals + 3 * (size_t)ix[1];
      n2 = g->vnormals + 3 * (size_t)ix[2];
    }
    /* A vertex without a normal holds (0,0,0): the triangle is flat then. */
    if (n0 && (n0[0] || n0[1] || n0[2]) && (n1[0] || n1[1] || n1[2]) && (n2[0] || n2[1] || n2[2])) {
      for (int a = 0; a < 3; a++) hit->ns[a] = w * n0[a] + u * n1[a] + v * n2[a];
      normalise(hit->ns);
      /* Interpolated normals may lean across the geometric one; keep the side. */
      if (hit->ns[0] * hit->ng[0] + hit->ns[1] * hit->ng[1] + hit->ns[2] * hit->ng[2] <= 0)
        memcpy(hit->ns, hit->ng, sizeof hit->ns);
    } else {
      memcpy(hit->ns, hit->ng, sizeof hit->ns);
    }
    if (g->tri_uv) {
      const float *q = g->tri_uv + 6 * (size_t)t;
      hit->uv[0] = w * q[0] + u * q[2] + v * q[4];
      hit->uv[1] = w * q[1] + u * q[3] + v * q[5];
    } else {
      hit->uv[0] = hit->uv[1] = 0.0;
    }
  } else {
    uint32_t s = c->spheres[rh.hit.primID];
    const double *sc = g->spheres + 4 * (size_t)s;
    hit->sphere = true;
    hit->prim = s;
    hit->object = g->sphere_object[s];
    for (int a = 0; a < 3; a++) hit->ng[a] = hit->p[a] - sc[a];
    normalise(hit->ng);
    memcpy(hit->ns, hit->ng, sizeof hit->ns);
    hit->uv[0] = 0.5 + atan2(hit->ng[1], hit->ng[0]) / (2.0 * M_PI);
    hit->uv[1] = acos(fmax(-1.0, fmin(1.0, hit->ng[2]))) / M_PI;
  }
  return true;
}
