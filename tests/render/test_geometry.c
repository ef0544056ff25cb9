/* Scene objects to triangles and spheres: areas against their closed forms,
 * winding and normals, the sample meshes in four formats with the triangle
 * counts samples/meshes/make_meshes.py wrote, transforms, the errors, and
 * uniform area sampling.  Scenes are filled in by hand, not parsed. */
#include "vr_test.h"
#include "vr/geometry.h"

#include <stdint.h>

#define PI 3.14159265358979323846
#define MESHES VR_SOURCE_DIR "/samples/meshes/"

/* ---- scene building helpers ---- */

typedef struct tscene {
  vr_scene s;
  vr_scene_object obj[8];
} tscene;

static void tscene_init(tscene *t) {
  memset(t, 0, sizeof *t);
  t->s.path = "room.scn";
  t->s.objects = t->obj;
}

static vr_scene_object *add(tscene *t, vr_shape_kind k, long line) {
  vr_scene_object *o = &t->obj[t->s.nobjects++];
  memset(o, 0, sizeof *o);
  o->shape = k;
  o->loc.line = line;
  o->loc.col = 1;
  vr_xform_identity(&o->xform);
  return o;
}

static vr_scene_object *add_rect(tscene *t, double cx, double cy, double cz, double nx, double ny,
                                 double nz, double w, double h) {
  vr_scene_object *o = add(t, VR_SHAPE_RECT, 10 + (long)t->s.nobjects);
  o->center[0] = cx, o->center[1] = cy, o->center[2] = cz;
  o->normal[0] = nx, o->normal[1] = ny, o->normal[2] = nz;
  o->up[2] = 1.0;
  o->size[0] = w, o->size[1] = h;
  return o;
}

static vr_scene_object *add_box(tscene *t, const double lo[3], const double hi[3]) {
  vr_scene_object *o = add(t, VR_SHAPE_BOX, 10 + (long)t->s.nobjects);
  memcpy(o->bmin, lo, 3 * sizeof *lo);
  memcpy(o->bmax, hi, 3 * sizeof *hi);
  return o;
}

static vr_scene_object *add_sphere(tscene *t, double cx, double cy, double cz, double r) {
  vr_scene_object *o = add(t, VR_SHAPE_SPHERE, 10 + (long)t->s.nobjects);
  o->center[0] = cx, o->center[1] = cy, o->center[2] = cz;
  o->radius = r;
  return o;
}

static vr_scene_object *add_mesh(tscene *t, const char *path) {
  vr_scene_object *o = add(t, VR_SHAPE_MESH, 10 + (long)t->s.nobjects);
  o->mesh_path = (char *)path;
  return o;
}

static void then_scale(vr_xform *x, double sx, double sy, double sz) {
  vr_xform s;
  vr_xform_identity(&s);
  s.m[0][0] = sx, s.m[1][1] = sy, s.m[2][2] = sz;
  vr_xform_then(x, &s, x);
}

/* Rotation about axis 0, 1 or 2 by deg degrees, right-handed. */
static void then_rotate(vr_xform *x, int axis, double deg) {
  vr_xform r;
  vr_xform_identity(&r);
  double c = cos(deg * PI / 180.0), s = sin(deg * PI / 180.0);
  int i = (axis + 1) % 3, j = (axis + 2) % 3;
  r.m[i][i] = c, r.m[i][j] = -s, r.m[j][i] = s, r.m[j][j] = c;
  vr_xform_then(x, &r, x);
}

static void then_translate(vr_xform *x, double tx, double ty, double tz) {
  x->m[0][3] += tx, x->m[1][3] += ty, x->m[2][3] += tz;
}

/* ---- small vector helpers ---- */

static void tri_corner(const vr_geometry *g, size_t t, int c, double p[3]) {
  const float *v = g->verts + 3 * (size_t)g->tris[3 * t + (size_t)c];
  for (int k = 0; k < 3; k++) p[k] = v[k];
}

/* Unit geometric normal from the winding; returns twice the area. */
static double tri_normal(const vr_geometry *g, size_t t, double n[3]) {
  double a[3], b[3], c[3];
  tri_corner(g, t, 0, a), tri_corner(g, t, 1, b), tri_corner(g, t, 2, c);
  double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  double e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  n[0] = e1[1] * e2[2] - e1[2] * e2[1];
  n[1] = e1[2] * e2[0] - e1[0] * e2[2];
  n[2] = e1[0] * e2[1] - e1[1] * e2[0];
  double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (int k = 0; k < 3; k++) n[k] /= len;
  return len;
}

static double sum_tri_area(const vr_geometry *g, size_t begin, size_t end) {
  double s = 0.0, n[3];
  for (size_t t = begin; t < end; t++) s += 0.5 * tri_normal(g, t, n);
  return s;
}

/* xorshift64*: a fixed sequence for the sampling tests. */
static double rnd(uint64_t *s) {
  *s ^= *s >> 12, *s ^= *s << 25, *s ^= *s >> 27;
  return (double)((*s * 2685821657736338717ULL) >> 11) * 0x1.0p-53;
}

static void build_ok(tscene *t, vr_geometry **g) {
  vr_error err = {0};
  vr_status st = vr_geometry_build(&t->s, g, &err);
  if (st != VR_OK) fail_msg("vr_geometry_build: %s", err.message);
}

/* A temporary folder holding a file with the given name and text. */
static const char *temp_file(char dir[64], const char *name, const char *text) {
  static char path[128];
  snprintf(dir, 64, "/tmp/vr_geom_XXXXXX");
  assert_non_null(mkdtemp(dir));
  snprintf(path, sizeof path, "%s/%s", dir, name);
  FILE *f = fopen(path, "w");
  assert_non_null(f);
  fputs(text, f);
  fclose(f);
  return path;
}

static void temp_remove(const char *dir, const char *path) {
  remove(path);
  rmdir(dir);
}

/* ---- tests ---- */

static void empty_scene_is_ok(void **state) {
  (void)state;
  tscene t;
  tscene_init(&t);
  vr_geometry *g;
  build_ok(&t, &g);
  assert_int_equal(g->nverts, 0);
  assert_int_equal(g->ntris, 0);
  assert_int_equal(g->nspheres, 0);
  assert_int_equal(g->nobjects, 0);
  assert_null(g->vnormals);
  for (int k = 0; k < 3; k++) {
    assert_near(g->bmin[k], 0.0, 0.0);
    assert_near(g->bmax[k], 0.0, 0.0);
  }
  vr_geometry_destroy(g);
  vr_geometry_destroy(NULL);
}

static void rect_area_winding_and_uv(void **state) {
  (void)state;
  tscene t;
  tscene_init(&t);
  /* A 2 m x 1.5 m window facing -y, up along z: u = v x n = +x. */
  add_rect(&t, 1, 2, 3, 0, -1, 0, 2.0, 1.5);
  vr_geometry *g;
  build_ok(&t, &g);
  assert_int_equal(g->ntris, 2);
  assert_int_equal(g->nverts, 4);
  assert_null(g->vnormals);
  assert_near(g->object_area[0], 3.0, 1e-12);
  assert_near(sum_tri_area(g, 0, 2), 3.0, 1e-12);
  assert_int_equal(g->object_tri_begin[0], 0);
  assert_int_equal(g->object_tri_end[0], 2);
  for (size_t i = 0; i < 2; i++) {
    double n[3];
    tri_normal(g, i, n);
    assert_near(n[0], 0.0, 1e-12);
    assert_near(n[1], -1.0, 1e-12);
    assert_near(n[2], 0.0, 1e-12);
    assert_int_equal(g->tri_object[i], 0);
    /* (u,v) maps linearly to the rectangle's corners. */
    for (int c = 0; c < 3; c++) {
      double p[3];
      tri_corner(g, i, c, p);
      double u = g->tri_uv[6 * i + 2 * (size_t)c], v = g->tri_uv[6 * i + 2 * (size_t)c + 1];
      assert_near(p[0], 0.0 + 2.0 * u, 1e-6);
      assert_near(p[1], 2.0, 1e-6);
      assert_near(p[2], 2.25 + 1.5 * v, 1e-6);
    }
  }
  const double lo[3] = {0, 2, 2.25}, hi[3] = {2, 2, 3.75};
  for (int k = 0; k < 3; k++) {
    assert_near(g->bmin[k], lo[k], 1e-6);
    assert_near(g->bmax[k], hi[k], 1e-6);
  }
  vr_geometry_destroy(g);
}

static void transformed_rect(void **state) {
  (void)state;
  tscene t;
  tscene_init(&t);
  /* 1 x 1 floor tile, scaled by 2, turned 90 degrees about x (z -> -y),
   * lifted by 5: a 4 m^2 wall facing -y. */
  vr_scene_object *o = add_rect(&t, 0, 0, 0, 0, 0, 1, 1.0, 1.0);
  then_scale(&o->xform, 2, 2, 2);
  then_rotate(&o->xform, 0, 90);
  then_translate(&o->xform, 0, 0, 5);
  /* A mirrored tile (x -> -x) keeps facing +z. */
  o = add_rect(&t, 3, 0, 0, 0, 0, 1, 1.0, 3.0);
  then_scale(&o->xform, -1, 1, 1);
  vr_geometry *g;
  build_ok(&t, &g);
  assert_int_equal(g->ntris, 4);
  assert_near(g->object_area[0], 4.0, 1e-9);
  assert_near(g->object_area[1], 3.0, 1e-9);
  double n[3];
  for (size_t i = 0; i < 2; i++) {
    tri_normal(g, i, n);
    assert_near(n[1], -1.0, 1e-9);
  }
  for (size_t i = 2; i < 4; i++) {
    tri_normal(g, i, n);
    assert_near(n[2], 1.0, 1e-9);
    assert_int_equal(g->tri_object[i], 1);
  }
  /* Wall: x in [-1,1], y = 0, z in [4,6]; mirrored tile: x in [-3.5,-2.5]. */
  assert_near(g->bmin[0], -3.5, 1e-6);
  assert_near(g->bmax[0], 1.0, 1e-6);
  assert_near(g->bmin[2], 0.0, 1e-6);
  assert_near(g->bmax[2], 6.0, 1e-6);
  vr_geometry_destroy(g);
}

static void rect_up_hint_fallback(void **state) {
  (void)state;
  tscene t;
  tscene_init(&t);
  vr_scene_object *o = add_rect(&t, 0, 0, 0, 0, 0, 1, 2.0, 1.0); /* up (0,0,1) parallel */
  (void)o;
  o = add_rect(&t, 0, 0, 0, 1, 0, 0, 2.0, 1.0);
  o->up[2] = 0.0; /* no hint at all */
  vr_geometry *g;
  build_ok(&t, &g);
  assert_near(g->object_area[0], 2.0, 1e-12);
  assert_near(g->object_area[1], 2.0, 1e-12);
  /* Facing x with world z up: the 1 m height runs along z. */
  double zmin = INFINITY, zmax = -INFINITY;
  for (size_t i = 2; i < 4; i++)
    for (int c = 0; c < 3; c++) {
      double p[3];
      tri_corner(g, i, c, p);
      zmin = fmin(zmin, p[2]), zmax = fmax(zmax, p[2]);
    }
  assert_near(zmax - zmin, 1.0, 1e-6);
  vr_geometry_destroy(g);
}

static void box_area_and_outward_normals(void **state) {
  (void)state;
  tscene t;
  tscene_init(&t);
  const double lo[3] = {-0.5, -1.0, 0.0}, hi[3] = {0.5, 1.0, 3.0}; /* 1 x 2 x 3 */
  add_box(&t, lo, hi);
  vr_scene_object *o = add_box(&t, lo, hi);
  then_rotate(&o->xform, 2, 30);
  then_rotate(&o->xform, 0, -20);
  then_translate(&o->xform, 4, 5, 6);
  o = add_box(&t, lo, hi);
  then_scale(&o->xform, 1, -2, 1); /* mirrored and stretched: 1 x 4 x 3 */
  vr_geometry *g;
  build_ok(&t, &g);
  assert_int_equal(g->ntris, 36);
  assert_near(g->object_area[0], 2 * (1 * 2 + 2 * 3 + 3 * 1), 1e-9);
  assert_near(g->object_area[1], 22.0, 1e-5);
  assert_near(g->object_area[2], 2 * (1 * 4 + 4 * 3 + 3 * 1), 1e-9);
  for (size_t ob = 0; ob < 3; ob++) {
    assert_int_equal(g->object_tri_begin[ob], 12 * ob);
    assert_int_equal(g->object_tri_end[ob], 12 * (ob + 1));
    assert_near(sum_tri_area(g, 12 * ob, 12 * ob + 12), g->object_area[ob], 1e-9);
    /* The box centre in world space. */
    double c[3] = {0, 0, 1.5};
    vr_xform_point(&t.obj[ob].xform, c, c);
    for (size_t i = 12 * ob; i < 12 * ob + 12; i++) {
      double n[3], a[3], b[3], d[3];
      tri_normal(g, i, n);
      tri_corner(g, i, 0, a), tri_corner(g, i, 1, b), tri_corner(g, i, 2, d);
      double out = 0.0;
      for (int k = 0; k < 3; k++) out += n[k] * ((a[k] + b[k] + d[k]) / 3.0 - c[k]);
      if (!(out > 0.1)) fail_msg("object %zu triangle %zu faces inwards (%g)", ob, i, out);
      for (int k = 0; k < 6; k++) {
        float uv = g->tri_uv[6 * i + (size_t)k];
        assert_true(uv >= 0.0f && uv <= 1.0f);
      }
    }
  }
  vr_geometry_destroy(g);
}

static void sphere_with_uniform_transform(void **state) {
  (void)state;
  tscene t;
  tscene_init(&t);
  add_rect(&t, 0, 0, 0, 0, 0, 1, 1.0, 1.0);
  vr_scene_object *o = add_sphere(&t, 1, 0, 0, 0.5);
  then_scale(&o->xform, 2, 2, 2);
  then_rotate(&o->xform, 2, 30);
  then_translate(&o->xform, 0, 0, 1);
  vr_geometry *g;
  build_ok(&t, &g);
  assert_int_equal(g->nspheres, 1);
  assert_int_equal(g->sphere_object[0], 1);
  assert_int_equal(g->object_tri_begin[1], 0);
  assert_int_equal(g->object_tri_end[1], 0);
  assert_near(g->spheres[0], 2 * cos(PI / 6), 1e-12);
  assert_near(g->spheres[1], 2 * sin(PI / 6), 1e-12);
  assert_near(g->spheres[2], 1.0, 1e-12);
  assert_near(g->spheres[3], 1.0, 1e-12);
  assert_near(g->object_area[1], 4 * PI, 1e-12);
  assert_near(g->bmax[0], 2 * cos(PI / 6) + 1.0, 1e-12);
  assert_near(g->bmax[2], 2.0, 1e-12);
  assert_near(g->bmin[2], -0.0, 1e-12); /* the floor tile at z = 0 */
  vr_geometry_destroy(g);
}

static void non_uniform_sphere_is_an_error(void **state) {
  (void)state;
  tscene t;
  tscene_init(&t);
  vr_scene_object *o = add_sphere(&t, 0, 0, 0, 1);
  o->loc.line = 7;
  o->name = "ball";
  then_rotate(&o->xform, 2, 45);
  then_scale(&o->xform, 1, 2, 1);
  vr_geometry *g = (vr_geometry *)&t; /* must be reset to NULL */
  vr_error err = {0};
  assert_int_equal(vr_geometry_build(&t.s, &g, &err), VR_E_RANGE);
  assert_null(g);
  assert_contains(err.message, "room.scn:7: sphere 'ball': ");
  assert_contains(err.message, "non-uniform");
}

static void bad_shapes_are_errors(void **state) {
  (void)state;
  vr_error err = {0};
  vr_geometry *g;
  tscene t;
  tscene_init(&t);
  add_rect(&t, 0, 0, 0, 0, 0, 0, 1, 1); /* no normal */
  assert_int_equal(vr_geometry_build(&t.s, &g, &err), VR_E_RANGE);
  assert_contains(err.message, "room.scn:10: rect: normal");
  tscene_init(&t);
  add_rect(&t, 0, 0, 0, 0, 0, 1, 0, 1);
  assert_int_equal(vr_geometry_build(&t.s, &g, &err), VR_E_RANGE);
  assert_contains(err.message, "size");
  tscene_init(&t);
  const double lo[3] = {0, 0, 0}, hi[3] = {1, 0, 1};
  add_box(&t, lo, hi);
  assert_int_equal(vr_geometry_build(&t.s, &g, &err), VR_E_RANGE);
  assert_contains(err.message, "room.scn:10: box: min");
  tscene_init(&t);
  vr_scene_object *o = add_rect(&t, 0, 0, 0, 0, 0, 1, 1, 1);
  then_scale(&o->xform, 1, 0, 1);
  assert_int_equal(vr_geometry_build(&t.s, &g, &err), VR_E_RANGE);
  assert_contains(err.message, "singular");
  tscene_init(&t);
  add_sphere(&t, 0, 0, 0, -1);
  assert_int_equal(vr_geometry_build(&t.s, &g, &err), VR_E_RANGE);
  assert_contains(err.message, "radius");
}

typedef struct sample_mesh {
  const char *file;
  size_t ntris;  /* as printed by make_meshes.py */
  size_t nverts; /* after Assimp joins identical vertices: as in the file */
  bool normals;
  double lo[3], hi[3];
} sample_mesh;

static const sample_mesh samples[] = {
    {"bed.obj", 120, 80, false, {-0.8, -1.03, 0.0}, {0.8, 1.03, 1.10}},
    {"lamp.obj", 600, 521, true, {-0.16, -0.16, 0.0}, {0.16, 0.16, 0.48}},
    {"table.ply", 108, 64, false, {-0.6, -0.3, 0.0}, {0.6, 0.3, 0.75}},
    {"chair.gltf", 108, 216, true, {-0.225, -0.225, 0.0}, {0.225, 0.225, 0.90}},
};

static void sample_meshes_load(void **state) {
  (void)state;
  for (size_t i = 0; i < sizeof samples / sizeof *samples; i++) {
    const sample_mesh *s = &samples[i];
    char path[512];
    snprintf(path, sizeof path, MESHES "%s", s->file);
    tscene t;
    tscene_init(&t);
    add_mesh(&t, path);
    vr_geometry *g;
    build_ok(&t, &g);
    if (g->ntris != s->ntris)
      fail_msg("%s: %zu triangles, expected %zu", s->file, g->ntris, s->ntris);
    if (g->nverts != s->nverts)
      fail_msg("%s: %zu vertices, expected %zu", s->file, g->nverts, s->nverts);
    assert_int_equal(g->degenerate_dropped, 0);
    assert_int_equal(g->object_tri_end[0], s->ntris);
    assert_true(g->object_area[0] > 0.0);
    assert_near(sum_tri_area(g, 0, g->ntris), g->object_area[0], 1e-9);
    for (int k = 0; k < 3; k++) {
      assert_near(g->bmin[k], s->lo[k], 1e-6);
      assert_near(g->bmax[k], s->hi[k], 1e-6);
    }
    assert_int_equal(g->vnormals != NULL, s->normals);
    if (g->vnormals) {
      /* The file's normals are unit and on the side the winding faces. */
      for (size_t tr = 0; tr < g->ntris; tr++) {
        double n[3];
        tri_normal(g, tr, n);
        for (int c = 0; c < 3; c++) {
          const float *vn = g->vnormals + 3 * (size_t)g->tris[3 * tr + (size_t)c];
          double len = sqrt(vn[0] * vn[0] + vn[1] * vn[1] + vn[2] * vn[2]);
          assert_near(len, 1.0, 1e-5);
          if (!(vn[0] * n[0] + vn[1] * n[1] + vn[2] * n[2] > 0.0))
            fail_msg("%s: triangle %zu: normal against the winding", s->file, tr);
        }
      }
    }
    vr_geometry_destroy(g);
  }
}

static void several_objects_keep_order(void **state) {
  (void)state;
  tscene t;
  tscene_init(&t);
  add_mesh(&t, MESHES "table.ply");
  add_rect(&t, 0, 0, 0, 0, 0, 1, 4, 4);
  add_sphere(&t, 0, 0, 1, 0.1);
  add_mesh(&t, MESHES "lamp.obj");
  vr_geometry *g, *h;
  build_ok(&t, &g);
  build_ok(&t, &h);
  assert_int_equal(g->ntris, 108 + 2 + 600);
  assert_int_equal(g->object_tri_begin[0], 0);
  assert_int_equal(g->object_tri_end[0], 108);
  assert_int_equal(g->object_tri_begin[1], 108);
  assert_int_equal(g->object_tri_end[1], 110);
  assert_int_equal(g->object_tri_begin[3], 110);
  assert_int_equal(g->object_tri_end[3], 710);
  for (size_t i = 0; i < g->ntris; i++) {
    uint32_t want = i < 108 ? 0 : i < 110 ? 1 : 3;
    assert_int_equal(g->tri_object[i], want);
  }
  /* Lamp normals present, the table's and the rect's vertices flat. */
  assert_non_null(g->vnormals);
  for (size_t v = 0; v < 3; v++) assert_true(g->vnormals[v] == 0.0f);
  /* Same scene, same bytes. */
  assert_int_equal(g->nverts, h->nverts);
  assert_memory_equal(g->verts, h->verts, 3 * g->nverts * sizeof *g->verts);
  assert_memory_equal(g->tris, h->tris, 3 * g->ntris * sizeof *g->tris);
  vr_geometry_destroy(g);
  vr_geometry_destroy(h);
}

static void mesh_transform(void **state) {
  (void)state;
  tscene t;
  tscene_init(&t);
  add_mesh(&t, MESHES "table.ply");
  vr_scene_object *o = add_mesh(&t, MESHES "table.ply");
  then_scale(&o->xform, 2, 2, 2);
  then_rotate(&o->xform, 2, 90); /* (x, y) -> (-y, x) */
  then_translate(&o->xform, 1, 2, 0);
  vr_geometry *g;
  build_ok(&t, &g);
  assert_near(g->object_area[1], 4.0 * g->object_area[0], 1e-5 * g->object_area[1]);
  /* Bounds of the transformed table alone. */
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (size_t i = g->object_tri_begin[1]; i < g->object_tri_end[1]; i++)
    for (int c = 0; c < 3; c++) {
      double p[3];
      tri_corner(g, i, c, p);
      for (int k = 0; k < 3; k++) lo[k] = fmin(lo[k], p[k]), hi[k] = fmax(hi[k], p[k]);
    }
  const double elo[3] = {0.4, 0.8, 0.0}, ehi[3] = {1.6, 3.2, 1.5};
  for (int k = 0; k < 3; k++) {
    assert_near(lo[k], elo[k], 1e-6);
    assert_near(hi[k], ehi[k], 1e-6);
  }
  assert_near(g->bmax[1], 3.2, 1e-6);
  assert_near(g->bmin[1], -0.3, 1e-6);
  vr_geometry_destroy(g);
}

static void mesh_normals_follow_a_mirror(void **state) {
  (void)state;
  tscene t;
  tscene_init(&t);
  vr_scene_object *o = add_mesh(&t, MESHES "lamp.obj");
  then_scale(&o->xform, 1, -1, 3); /* mirrored and stretched */
  vr_geometry *g;
  build_ok(&t, &g);
  assert_non_null(g->vnormals);
  for (size_t tr = 0; tr < g->ntris; tr++) {
    double n[3];
    tri_normal(g, tr, n);
    for (int c = 0; c < 3; c++) {
      const float *vn = g->vnormals + 3 * (size_t)g->tris[3 * tr + (size_t)c];
      if (!(vn[0] * n[0] + vn[1] * n[1] + vn[2] * n[2] > 0.0))
        fail_msg("triangle %zu: normal against the winding after a mirror", tr);
    }
  }
  vr_geometry_destroy(g);
}

static void missing_mesh_names_the_path(void **state) {
  (void)state;
  tscene t;
  tscene_init(&t);
  vr_scene_object *o = add_mesh(&t, "/nonexistent/furniture/sofa.obj");
  o->loc.line = 3;
  vr_geometry *g;
  vr_error err = {0};
  assert_int_equal(vr_geometry_build(&t.s, &g, &err), VR_E_IO);
  assert_null(g);
  assert_contains(err.message, "room.scn:3: mesh '/nonexistent/furniture/sofa.obj': ");
}

static void unreadable_mesh_is_a_parse_error(void **state) {
  (void)state;
  char dir[64];
  const char *path = temp_file(dir, "junk.gltf", "{ \"asset\": { \"version\": \"2.0\" }, \"buffers\": [ nope\n");
  tscene t;
  tscene_init(&t);
  add_mesh(&t, path);
  vr_geometry *g;
  vr_error err = {0};
  vr_status st = vr_geometry_build(&t.s, &g, &err);
  assert_true(st == VR_E_PARSE);
  assert_contains(err.message, "room.scn:10: mesh '");
  assert_contains(err.message, "junk.gltf");
  temp_remove(dir, path);
}

/* Assimp 5.2 hangs on a PLY header without end_header and reads past a
 * truncated binary body; mesh_assimp.c checks PLY headers first. */
static void truncated_ply_is_a_parse_error(void **state) {
  (void)state;
  static const char *const files[] = {
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n",
      "ply\nformat ascii 1.0\nelement vertex x\nend_header\n",
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\nabc",
  };
  static const char *const why[] = {"no end_header", "element 'vertex' has no valid count",
                                    "PLY body has 3 bytes, its header needs at least 37"};
  for (size_t i = 0; i < 3; i++) {
    char dir[64];
    const char *path = temp_file(dir, "cut.ply", files[i]);
    tscene t;
    tscene_init(&t);
    add_mesh(&t, path);
    vr_geometry *g;
    vr_error err = {0};
    assert_int_equal(vr_geometry_build(&t.s, &g, &err), VR_E_PARSE);
    assert_contains(err.message, "cut.ply': ");
    assert_contains(err.message, why[i]);
    temp_remove(dir, path);
  }
}

static void degenerate_triangles_are_dropped(void **state) {
  (void)state;
  char dir[64];
  /* Two good triangles (a unit square), a collinear one, a repeated corner
   * and a sliver of area 1e-14 in a mesh of diagonal ~1.4. */
  const char *path = temp_file(dir, "degenerate.obj",
                               "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                               "v 0.5 0 0\nv 0.5 0.00000000000002 0\n"
                               "f 1 2 3\nf 1 3 4\nf 1 5 2\nf 3 3 4\nf 1 6 2\n");
  tscene t;
  tscene_init(&t);
  add_mesh(&t, path);
  vr_geometry *g;
  build_ok(&t, &g);
  assert_int_equal(g->ntris, 2);
  assert_int_equal(g->degenerate_dropped, 3);
  assert_near(g->object_area[0], 1.0, 1e-9);
  vr_geometry_destroy(g);
  temp_remove(dir, path);

  path = temp_file(dir, "flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\nf 3 2 1\n");
  tscene_init(&t);
  add_mesh(&t, path);
  vr_error err = {0};
  assert_int_equal(vr_geometry_build(&t.s, &g, &err), VR_E_RANGE);
  assert_contains(err.message, "room.scn:10: mesh '");
  assert_contains(err.message, "all 2 triangles are degenerate");
  temp_remove(dir, path);
}

static void nan_vertex_is_an_error(void **state) {
  (void)state;
  char dir[64];
  const char *path = temp_file(dir, "nan.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n");
  tscene t;
  tscene_init(&t);
  add_mesh(&t, path);
  vr_geometry *g;
  vr_error err = {0};
  assert_int_equal(vr_geometry_build(&t.s, &g, &err), VR_E_RANGE);
  assert_contains(err.message, "nan.obj': a vertex is not finite");
  temp_remove(dir, path);
}

static void mesh_without_triangles_is_an_error(void **state) {
  (void)state;
  char dir[64];
  const char *path = temp_file(dir, "lines.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nl 1 2\nl 2 3\n");
  tscene t;
  tscene_init(&t);
  add_mesh(&t, path);
  vr_geometry *g;
  vr_error err = {0};
  assert_int_equal(vr_geometry_build(&t.s, &g, &err), VR_E_PARSE);
  assert_contains(err.message, "lines.obj'");
  temp_remove(dir, path);
}

static void mesh_uv_and_polygons(void **state) {
  (void)state;
  char dir[64];
  /* One quad with texture coordinates: triangulated into two. */
  const char *path = temp_file(dir, "quad.obj",
                               "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 0 1 0\n"
                               "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                               "f 1/1 2/2 3/3 4/4\n");
  tscene t;
  tscene_init(&t);
  add_mesh(&t, path);
  vr_geometry *g;
  build_ok(&t, &g);
  assert_int_equal(g->ntris, 2);
  assert_null(g->vnormals);
  assert_near(g->object_area[0], 2.0, 1e-9);
  for (size_t i = 0; i < 2; i++)
    for (int c = 0; c < 3; c++) {
      double p[3];
      tri_corner(g, i, c, p);
      assert_near(g->tri_uv[6 * i + 2 * (size_t)c], p[0] / 2.0, 1e-6);
      assert_near(g->tri_uv[6 * i + 2 * (size_t)c + 1], p[1], 1e-6);
    }
  vr_geometry_destroy(g);
  temp_remove(dir, path);
}

static void sampling_a_rect_is_uniform(void **state) {
  (void)state;
  tscene t;
  tscene_init(&t);
  /* 3 m x 1 m, tilted: normal (0, -0.6, 0.8). */
  add_rect(&t, 1, 2, 3, 0, -0.6, 0.8, 3.0, 1.0);
  vr_geometry *g;
  build_ok(&t, &g);
  const double c[3] = {1, 2, 3}, nrm[3] = {0, -0.6, 0.8};
  const int n = 40000;
  double mean[3] = {0}, quarter = 0;
  uint64_t s = 0x9E3779B97F4A7C15ULL;
  for (int i = 0; i < n; i++) {
    double u1 = rnd(&s), u2 = rnd(&s), u3 = rnd(&s), p[3], pn[3];
    vr_geometry_sample_object(g, 0, u1, u2, u3, p, pn);
    double d[3] = {p[0] - c[0], p[1] - c[1], p[2] - c[2]};
    assert_near(d[0] * nrm[0] + d[1] * nrm[1] + d[2] * nrm[2], 0.0, 1e-6);
    assert_near(pn[0] * nrm[0] + pn[1] * nrm[1] + pn[2] * nrm[2], 1.0, 1e-9);
    assert_true(fabs(d[0]) <= 1.5 + 1e-6);
    assert_true(d[0] * d[0] + d[1] * d[1] + d[2] * d[2] - d[0] * d[0] <= 0.25 + 1e-6);
    for (int k = 0; k < 3; k++) mean[k] += p[k] / n;
    quarter += d[0] > 0.75; /* the last quarter of the width */
  }
  /* Means: sigma of a uniform over a length L is L / sqrt(12). */
  double sig_x = 3.0 / sqrt(12.0 * n), sig_v = 1.0 / sqrt(12.0 * n);
  assert_near(mean[0], c[0], 3 * sig_x);
  assert_near(mean[1], c[1], 3 * sig_v * 0.8);
  assert_near(mean[2], c[2], 3 * sig_v * 0.6);
  assert_near(quarter / n, 0.25, 3 * sqrt(0.25 * 0.75 / n));
  /* Out of range: zeros, no crash. */
  double p[3], pn[3];
  vr_geometry_sample_object(g, 5, 0.5, 0.5, 0.5, p, pn);
  assert_near(p[0] + pn[0], 0.0, 0.0);
  vr_geometry_destroy(g);
}

static void sampling_a_box_follows_face_areas(void **state) {
  (void)state;
  tscene t;
  tscene_init(&t);
  const double lo[3] = {0, 0, 0}, hi[3] = {1, 2, 3};
  add_box(&t, lo, hi);
  vr_geometry *g;
  build_ok(&t, &g);
  const int n = 44000;
  int axis_count[3] = {0};
  uint64_t s = 12345;
  for (int i = 0; i < n; i++) {
    double p[3], pn[3];
    vr_geometry_sample_object(g, 0, rnd(&s), rnd(&s), rnd(&s), p, pn);
    int axis = fabs(pn[0]) > 0.5 ? 0 : fabs(pn[1]) > 0.5 ? 1 : 2;
    axis_count[axis]++;
    /* On the face the normal names, inside the box's extent. */
    double face = pn[axis] > 0 ? hi[axis] : lo[axis];
    assert_near(p[axis], face, 1e-6);
    for (int k = 0; k < 3; k++) assert_true(p[k] >= lo[k] - 1e-6 && p[k] <= hi[k] + 1e-6);
  }
  /* Pairs of faces: x faces 2*6 = 12, y faces 2*3 = 6, z faces 2*2 = 4 of 22. */
  const double share[3] = {12.0 / 22, 6.0 / 22, 4.0 / 22};
  for (int k = 0; k < 3; k++)
    assert_near((double)axis_count[k] / n, share[k], 3 * sqrt(share[k] * (1 - share[k]) / n));
  vr_geometry_destroy(g);
}

static void sampling_a_sphere(void **state) {
  (void)state;
  tscene t;
  tscene_init(&t);
  vr_scene_object *o = add_sphere(&t, 0, 0, 0, 0.25);
  then_scale(&o->xform, 2, 2, 2);
  then_translate(&o->xform, 1, -1, 2);
  vr_geometry *g;
  build_ok(&t, &g);
  const int n = 20000;
  double mean[3] = {0}, upper = 0;
  uint64_t s = 777;
  for (int i = 0; i < n; i++) {
    double p[3], pn[3];
    vr_geometry_sample_object(g, 0, rnd(&s), rnd(&s), rnd(&s), p, pn);
    double d[3] = {p[0] - 1, p[1] + 1, p[2] - 2};
    assert_near(sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]), 0.5, 1e-12);
    for (int k = 0; k < 3; k++) assert_near(pn[k], d[k] / 0.5, 1e-9);
    for (int k = 0; k < 3; k++) mean[k] += p[k] / n;
    upper += d[2] > 0.25; /* a cap of height r/2: a quarter of the area (Archimedes) */
  }
  double sig = 0.5 / sqrt(3.0 * n);
  assert_near(mean[0], 1.0, 3 * sig);
  assert_near(mean[1], -1.0, 3 * sig);
  assert_near(mean[2], 2.0, 3 * sig);
  assert_near(upper / n, 0.25, 3 * sqrt(0.25 * 0.75 / n));
  vr_geometry_destroy(g);
}

static void sampling_a_mesh_stays_on_it(void **state) {
  (void)state;
  tscene t;
  tscene_init(&t);
  add_rect(&t, 0, 0, 0, 0, 0, 1, 4, 4);
  add_mesh(&t, MESHES "lamp.obj");
  vr_geometry *g;
  build_ok(&t, &g);
  uint64_t s = 99;
  double z_mean = 0;
  const int n = 20000;
  for (int i = 0; i < n; i++) {
    double p[3], pn[3];
    vr_geometry_sample_object(g, 1, rnd(&s), rnd(&s), rnd(&s), p, pn);
    assert_true(hypot(p[0], p[1]) <= 0.16 + 1e-6);
    assert_true(p[2] >= -1e-6 && p[2] <= 0.48 + 1e-6);
    assert_near(sqrt(pn[0] * pn[0] + pn[1] * pn[1] + pn[2] * pn[2]), 1.0, 1e-9);
    z_mean += p[2] / n;
  }
  /* The area-weighted mean height from the triangles themselves. */
  double zw = 0.0, nn[3];
  for (size_t i = g->object_tri_begin[1]; i < g->object_tri_end[1]; i++) {
    double a[3], b[3], c[3];
    tri_corner(g, i, 0, a), tri_corner(g, i, 1, b), tri_corner(g, i, 2, c);
    zw += 0.5 * tri_normal(g, i, nn) * (a[2] + b[2] + c[2]) / 3.0;
  }
  zw /= g->object_area[1];
  assert_near(z_mean, zw, 3 * 0.48 / sqrt(12.0 * n));
  vr_geometry_destroy(g);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(empty_scene_is_ok),
      cmocka_unit_test(rect_area_winding_and_uv),
      cmocka_unit_test(transformed_rect),
      cmocka_unit_test(rect_up_hint_fallback),
      cmocka_unit_test(box_area_and_outward_normals),
      cmocka_unit_test(sphere_with_uniform_transform),
      cmocka_unit_test(non_uniform_sphere_is_an_error),
      cmocka_unit_test(bad_shapes_are_errors),
      cmocka_unit_test(sample_meshes_load),
      cmocka_unit_test(several_objects_keep_order),
      cmocka_unit_test(mesh_transform),
      cmocka_unit_test(mesh_normals_follow_a_mirror),
      cmocka_unit_test(missing_mesh_names_the_path),
      cmocka_unit_test(unreadable_mesh_is_a_parse_error),
      cmocka_unit_test(truncated_ply_is_a_parse_error),
      cmocka_unit_test(degenerate_triangles_are_dropped),
      cmocka_unit_test(nan_vertex_is_an_error),
      cmocka_unit_test(mesh_without_triangles_is_an_error),
      cmocka_unit_test(mesh_uv_and_polygons),
      cmocka_unit_test(sampling_a_rect_is_uniform),
      cmocka_unit_test(sampling_a_box_follows_face_areas),
      cmocka_unit_test(sampling_a_sphere),
      cmocka_unit_test(sampling_a_mesh_stays_on_it),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
