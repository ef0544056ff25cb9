/* The Radiance scene reader (render/src/geometry/rad_read.c, rad_shapes.c,
 * rad_materials.c) against values from outside it:
 *   - honeybee-radiance's sample office (tests/data/radiance/SOURCES.md),
 *     a real model as Honeybee writes it: every material's surface area
 *     equals the sum of its polygons' areas by Newell's formula (computed
 *     independently from the file, listed below), including a wall whose
 *     two window holes are cut by seams (20 vertices, 12 - 1.5 - 4.2 =
 *     6.3 m2 from its dimensions);
 *   - the areas of Radiance's quadrics (sphere 4 pi r^2, cylinder 2 pi r h,
 *     cone pi (r0 + r1) s, ring pi (r1^2 - r0^2)) short by the inscribed
 *     facets' leading-order deficit (x^2 / 6 per angular half-step x), and their orientation by the divergence theorem (the
 *     signed volume of a sphere is +4/3 pi r^3 facing out, minus that for
 *     a bubble, and stays positive through a mirroring !xform);
 *   - !xform's transforms in the order written (Radiance's xform(1)): -rz 90
 *     then -t 1 0 0 takes (1, 0, 0) to (1, 1, 0);
 *   - Honeybee's glass "generic_exterior_window_vis_0.64" (transmissivity
 *     0.6975761815 from Radiance's formula for a visible transmittance of
 *     0.64 at n 1.52) transmits 0.64 at normal incidence;
 *   - an integrating sphere (a bubble of reflectance rho lit by a small
 *     emitting sphere at its centre): E = Phi / (4 pi R^2 (1 - rho)) on its
 *     wall, Phi = pi L A of the lamp, L = 179 lm/W times Radiance's
 *     radiance (Radiance's luminous efficacy of its white);
 *   - Radiance's trans as a translucent diffuser: transmitted and reflected
 *     illuminance under a uniform sky, analytic (and Radiance's own);
 *   - a distant source (gensky's sun) gives E = L * 2 pi (1 - cos(a / 2))
 *     on a surface facing it;
 *   - coinciding polygons found: the sample office's floor (21.6 and
 *     7.2 m2) under its context ground, and squares that share half their
 *     area, not those 1 mm apart or touching along an edge;
 *   - bad files refused with the file, the line and the primitive. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "render_test_util.h"
/* After the helpers: vr/bsdf.h brings complex.h's I. */
#include "geometry/rad_read.h"
#include "vr/bsdf.h"
#include "vr/models.h"

#define OFFICE VR_TEST_DATA "/radiance/sample_office/office.rad"

static double tri_area(const vr_mesh_data *m, size_t t, double n[3]) {
  const double *a = m->pos + 3 * m->tris[3 * t], *b = m->pos + 3 * m->tris[3 * t + 1],
               *c = m->pos + 3 * m->tris[3 * t + 2];
  double u[3], v[3];
  for (int k = 0; k < 3; k++) u[k] = b[k] - a[k], v[k] = c[k] - a[k];
  double x[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
  if (n) memcpy(n, x, sizeof x);
  return 0.5 * sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
}

/* The area of material mat's triangles. */
static double area_of(const vr_rad_model *m, size_t mat) {
  double s = 0;
  for (size_t t = 0; t < m->mesh.ntris; t++)
    if (m->mesh.tri_material[t] == mat) s += tri_area(&m->mesh, t, NULL);
  return s;
}

/* Signed volume enclosed (divergence theorem: sum of p . n dA / 3). */
static double signed_volume(const vr_mesh_data *m) {
  double v = 0;
  for (size_t t = 0; t < m->ntris; t++) {
    double n[3];
    tri_area(m, t, n);
    const double *a = m->pos + 3 * m->tris[3 * t];
    v += (a[0] * n[0] + a[1] * n[1] + a[2] * n[2]) / 6.0;
  }
  return v;
}

static size_t mat_index(const vr_rad_model *m, const char *name) {
  for (size_t i = 0; i < m->nmats; i++)
    if (!strcmp(m->mats[i].name, name)) return i;
  fail_msg("no material %s", name);
  return 0;
}

static void test_sample_office_areas(void **state) {
  (void)state;
  vr_rad_model m;
  vr_error e = {0};
  if (vr_rad_read(OFFICE, &m, &e)) fail_msg("%s", e.message);
  assert_int_equal(m.files, 5);
  assert_int_equal(m.nmats, 7);
  assert_int_equal(m.degenerate, 0);
  /* Newell areas of the file's polygons, summed by material (computed
   * from the file with a separate script; the room's own dimensions give
   * the same: floor 4 x 7.2 = 28.8 m2). */
  static const struct {
    const char *name;
    double area;
  } A[] = {{"generic_wall_0.50", 912.64},          {"generic_ceiling_0.80", 26.4},
           {"generic_floor_0.20", 28.8},           {"skylight_45_59c8c160", 2.4},
           {"partition_glass_35_8b15eb64", 4.8},   {"south_glass_top_45_08dc6264", 4.2},
           {"south_glass_top_60_23327281", 1.5}};
  for (size_t i = 0; i < sizeof A / sizeof *A; i++) {
    double got = area_of(&m, mat_index(&m, A[i].name));
    if (fabs(got - A[i].area) > 1e-9 * A[i].area)
      fail_msg("%s: %.12g m2, the file's polygons %.12g m2", A[i].name, got, A[i].area);
  }
  vr_rad_free(&m);
}

/* Reads path and finds its coinciding polygons. */
static void overlaps_of(const char *path, vr_rad_model *m, vr_rad_overlap **o, size_t *n) {
  vr_error e = {0};
  if (vr_rad_read(path, m, &e)) fail_msg("%s", e.message);
  if (vr_rad_overlaps(m, o, n, &e)) fail_msg("%s", e.message);
}

/* The sample office's floor (two polygons, 21.6 + 7.2 m2: the room's
 * 4 x 7.2 m) lies in the plane of its context ground and under it. */
static void test_sample_office_overlaps(void **state) {
  (void)state;
  vr_rad_model m;
  vr_rad_overlap *o;
  size_t n;
  overlaps_of(OFFICE, &m, &o, &n);
  assert_int_equal(n, 2);
  assert_string_equal(m.polys[o[0].a].id, "context_e3bb11d6_0");
  assert_string_equal(m.polys[o[0].b].id, "room_geometry_cd906227_8");
  assert_float_equal(o[0].area, 21.6, 1e-9);
  assert_string_equal(m.polys[o[1].b].id, "room_geometry_cd906227_9");
  assert_float_equal(o[1].area, 7.2, 1e-9);
  free(o);
  vr_rad_free(&m);
}

/* Synthetic cases: unit squares at z = 0 shifted by 0.5 in x share 0.5 m2
 * whichever way they face; one 1 mm above shares nothing (beyond the
 * 0.1 mm tolerance); one that only touches along an edge shares 0. */
static void write_rad(char path[64], const char *name, const char *text);
static void test_overlap_cases(void **state) {
  (void)state;
  char p[64];
  write_rad(p, "ov.rad",
            "void plastic w 0 0 5 .5 .5 .5 0 0\n"
            "w polygon a 0 0 12 0 0 0 1 0 0 1 1 0 0 1 0\n"
            "w polygon b 0 0 12 0.5 0 0 0.5 1 0 1.5 1 0 1.5 0 0\n" /* facing down */
            "w polygon c 0 0 12 0 0 0.001 1 0 0.001 1 1 0.001 0 1 0.001\n"
            "w polygon d 0 0 12 -1 0 0 0 0 0 0 1 0 -1 1 0\n");
  vr_rad_model m;
  vr_rad_overlap *o;
  size_t n;
  overlaps_of(p, &m, &o, &n);
  assert_int_equal(n, 1);
  assert_string_equal(m.polys[o[0].a].id, "a");
  assert_string_equal(m.polys[o[0].b].id, "b");
  assert_float_equal(o[0].area, 0.5, 1e-12);
  free(o);
  vr_rad_free(&m);
  unlink(p);
}

/* The seamed wall alone, its triangles facing -y as its vertices do. */
static void test_seamed_wall(void **state) {
  (void)state;
  static const double v[] = {2.0,  -3.2, 0.0,  2.0,  -3.2, 3.0,  1.0,  -3.2, 3.0,  -1.0, -3.2,
                             3.0,  -2.0, -3.2, 3.0,  -1.5, -3.2, 2.75, 1.5,  -3.2, 2.75, 1.5,
                             -3.2, 2.25, -1.5, -3.2, 2.25, -1.5, -3.2, 2.0,  1.5,  -3.2, 2.0,
                             1.5,  -3.2, 0.6,  -1.5, -3.2, 0.6,  -1.5, -3.2, 2.0,  -1.5, -3.2,
                             2.25, -1.5, -3.2, 2.75, -2.0, -3.2, 3.0,  -2.0, -3.2, 0.0,  -1.0,
                             -3.2, 0.0,  1.0,  -3.2, 0.0};
  vr_mesh_data m;
  memset(&m, 0, sizeof m);
  bool deg;
  vr_error e = {0};
  assert_int_equal(vr_rad_polygon(&m, v, 20, 0, &deg, &e), VR_OK);
  assert_false(deg);
  double total = 0;
  for (size_t t = 0; t < m.ntris; t++) {
    double n[3];
    total += tri_area(&m, t, n);
    assert_true(n[1] <= 0 && fabs(n[0]) < 1e-12 && fabs(n[2]) < 1e-12);
  }
  assert_float_equal(total, 12.0 - 1.5 - 4.2, 1e-12);
  vr_mesh_data_free(&m);
}

/* Writes text to a temporary .rad file (its path in path). */
static void write_rad(char path[64], const char *name, const char *text) {
  snprintf(path, 64, "/tmp/vr_rad_%d_%s", (int)getpid(), name);
  FILE *f = fopen(path, "w");
  assert_non_null(f);
  fputs(text, f);
  fclose(f);
}

static void test_quadrics(void **state) {
  (void)state;
  char p[64];
  write_rad(p, "q.rad",
            "void plastic w 0 0 5 .5 .5 .5 0 0\n"
            "w sphere s 0 0 4 1 2 3 0.5\n"
            "w cylinder c 0 0 7 0 0 0 0 0 2 0.3\n"
            "w cone k 0 0 8 0 0 0 1 0 0 0.2 0.4\n"
            "w ring r 0 0 8 0 0 5 0 0 1 0.1 0.6\n");
  vr_rad_model m;
  vr_error e = {0};
  if (vr_rad_read(p, &m, &e)) fail_msg("%s", e.message);
  /* One material: split the triangles by primitive through their order. */
  double areas[4] = {0};
  size_t per = m.mesh.ntris, t = 0;
  (void)per;
  /* Sphere: 2 * 128 * 64 - 2 * 128 (pole fans lose one each); the others
   * 2 * 128 (a ring's inner radius > 0, a cone's two radii > 0). */
  size_t counts[4] = {2 * 128 * 64 - 2 * 128, 256, 256, 256};
  assert_int_equal(m.mesh.ntris, counts[0] + counts[1] + counts[2] + counts[3]);
  for (int k = 0; k < 4; k++)
    for (size_t i = 0; i < counts[k]; i++, t++) areas[k] += tri_area(&m.mesh, t, NULL);
  double want[4] = {4 * M_PI * 0.25, 2 * M_PI * 0.3 * 2, M_PI * 0.6 * sqrt(1 + 0.04),
                    M_PI * (0.36 - 0.01)};
  /* Inscribed facets fall short of the surface by, to leading order,
   * x^2 / 6 for each angular step x subtended by a facet edge's half:
   * pi/128 around (a chord over its arc, sin x / x), pi/64 along a
   * meridian of the sphere, and 2 pi/128 for a ring's area (an n-gon's
   * n/2 sin(2 pi/n) over pi); a cone's trapezoids are also lower than
   * its slant s, their chords' midpoints being dr cos x apart radially
   * instead of dr: a further dr^2 x^2 / (2 s^2). */
  double a128 = M_PI / 128, a64 = M_PI / 64;
  double expect[4] = {(a128 * a128 + a64 * a64) / 6, a128 * a128 / 6,
                      a128 * a128 / 6 + 0.04 * a128 * a128 / (2 * 1.04), 4 * a128 * a128 / 6};
  for (int k = 0; k < 4; k++) {
    double rel = 1 - areas[k] / want[k];
    if (!(fabs(rel - expect[k]) < 0.1 * expect[k]))
      fail_msg("primitive %d: area %.9g vs %.9g (%.3e short, expected %.3e)", k, areas[k], want[k],
               rel, expect[k]);
  }
  vr_rad_free(&m);
  unlink(p);
}

static void test_orientation_and_xform(void **state) {
  (void)state;
  char a[64], b[64], c[64];
  write_rad(a, "inner.rad", "void plastic w 0 0 5 .5 .5 .5 0 0\nw sphere s 0 0 4 0 0 0 1\n");
  write_rad(b, "bub.rad", "void plastic w 0 0 5 .5 .5 .5 0 0\nw bubble s 0 0 4 0 0 0 1\n");
  char text[300];
  snprintf(text, sizeof text, "!xform -mx -t 3 0 0 %s\n", strrchr(a, '/') + 1);
  write_rad(c, "outer.rad", text);
  vr_rad_model m;
  vr_error e = {0};
  double V = 4.0 / 3.0 * M_PI;
  if (vr_rad_read(a, &m, &e)) fail_msg("%s", e.message);
  double sv = signed_volume(&m.mesh);
  /* Short by about twice the area's 5.0e-4 (the facets' distance from
   * the centre is short by as much as their area). */
  if (!(sv > 0.998 * V && sv < V)) fail_msg("sphere: signed volume %.9g, 4/3 pi %.9g", sv, V);
  vr_rad_free(&m);
  if (vr_rad_read(b, &m, &e)) fail_msg("%s", e.message);
  assert_true(-signed_volume(&m.mesh) > 0.998 * V);
  vr_rad_free(&m);
  /* Mirrored and moved: still facing out, centred on (3, 0, 0). */
  if (vr_rad_read(c, &m, &e)) fail_msg("%s", e.message);
  double cx = 0;
  for (size_t i = 0; i < m.mesh.nverts; i++) cx += m.mesh.pos[3 * i];
  assert_float_equal(cx / (double)m.mesh.nverts, 3.0, 1e-9);
  double vol = 0;
  for (size_t i = 0; i < m.mesh.nverts; i++) m.mesh.pos[3 * i] -= 3; /* about the origin */
  vol = signed_volume(&m.mesh);
  assert_true(vol > 0.998 * V);
  vr_rad_free(&m);
  /* -rz 90 then -t 1 0 0: (1, 0, 0) -> (0, 1, 0) -> (1, 1, 0). */
  write_rad(a, "tri.rad", "void plastic w 0 0 5 .5 .5 .5 0 0\nw polygon t 0 0 9 1 0 0 0 0 0 0 0 1\n");
  snprintf(text, sizeof text, "!xform -rz 90 -t 1 0 0 %s\n", strrchr(a, '/') + 1);
  write_rad(c, "outer.rad", text);
  if (vr_rad_read(c, &m, &e)) fail_msg("%s", e.message);
  assert_float_equal(m.mesh.pos[0], 1.0, 1e-12);
  assert_float_equal(m.mesh.pos[1], 1.0, 1e-12);
  assert_float_equal(m.mesh.pos[2], 0.0, 1e-12);
  vr_rad_free(&m);
  unlink(a), unlink(b), unlink(c);
}

/* Honeybee's "vis 0.64" glass transmits 0.64 at normal incidence. */
static void test_honeybee_glass(void **state) {
  (void)state;
  char p[64];
  write_rad(p, "g.rad",
            "void glass generic_exterior_window_vis_0.64\n0\n0\n3 0.6975761815384331 "
            "0.6975761815384331 0.6975761815384331\n"
            "generic_exterior_window_vis_0.64 polygon w 0 0 12 0 0 0 1 0 0 1 1 0 0 1 0\n");
  char scene[200];
  snprintf(scene, sizeof scene, "mesh %s\nsensor s point position=0.5,0.5,-1 normal=0,0,1\n", p);
  vr_scene *s = parse_text(scene, "glass.scn");
  vr_error e = {0};
  if (vr_scene_load_models(s, &e)) fail_msg("%s", e.message);
  assert_int_equal(s->nmaterials, 1);
  const vr_scene_material *sm = &s->materials[0];
  assert_int_equal(sm->source, VR_MATSRC_GLASS);
  vr_bsdf *b;
  if (vr_bsdf_create(sm, NULL, NULL, 360, 830, &b, &e)) fail_msg("%s", e.message);
  double R, T, A;
  for (double nm = 400; nm <= 700; nm += 100) {
    vr_bsdf_rta(b, NAN, 1.0, nm, &R, &T, &A);
    assert_float_equal(T, 0.64, 5e-4);
  }
  vr_bsdf_destroy(b);
  vr_scene_destroy(s);
  unlink(p);
}

/* A dielectric's transmission is per unit of the file's length (Radiance's
 * reference manual: "the transmission per unit length"): a file in
 * centimetres read with units=cm has 0.99 per cm, 0.99^100 = 0.366032 per
 * metre, and as metres 0.99 per metre. */
static void test_dielectric_units(void **state) {
  (void)state;
  char p[64];
  write_rad(p, "d.rad",
            "void dielectric water\n0\n0\n5 0.99 0.99 0.99 1.33 0\n"
            "water polygon w 0 0 12 0 0 0 100 0 0 100 100 0 0 100 0\n");
  const char *units[2] = {"units=cm", ""};
  const double want[2] = {0.366032341, 0.99};
  for (int i = 0; i < 2; i++) {
    char scene[200];
    snprintf(scene, sizeof scene, "mesh %s %s\nsensor s point position=0.5,0.5,-1 normal=0,0,1\n", p,
             units[i]);
    vr_scene *s = parse_text(scene, "water.scn");
    vr_error e = {0};
    if (vr_scene_load_models(s, &e)) fail_msg("%s", e.message);
    const vr_scene_material *sm = &s->materials[0];
    assert_int_equal(sm->source, VR_MATSRC_GLASS);
    vr_spectrum *sp = vr_scene_inline_spectrum(sm->transmission, &e);
    assert_non_null(sp);
    assert_float_equal(vr_spectrum_eval(sp, 550, VR_INTERP_LINEAR), want[i], 1e-9);
    vr_spectrum_destroy(sp);
    vr_scene_destroy(s);
  }
  unlink(p);
}

/* The integrating sphere and a distant source, rendered. */
static void test_integrating_sphere(void **state) {
  (void)state;
  char p[64];
  write_rad(p, "is.rad",
            "void plastic wall 0 0 5 0.5 0.5 0.5 0 0\n"
            "void light lamp 0 0 3 100 100 100\n"
            "wall bubble shell 0 0 4 0 0 0 1\n"
            "lamp sphere bulb 0 0 4 0 0 0 0.02\n");
  char scene[300];
  snprintf(scene, sizeof scene,
           "mesh %s\nsensor s point position=0,0,-0.999 normal=0,0,1\n"
           "render integrator=path sensor_samples=16384 depth=40 seed=3\n", p);
  vr_render_result *r = render_text_models(scene, "is.scn");
  double L = 179 * 100, phi = M_PI * L * 4 * M_PI * 0.02 * 0.02;
  double want = phi / (4 * M_PI * (1 - 0.5));
  double got = r->readings[0].illuminance_lx, se = r->readings[0].stderr_lx;
  /* 4 standard errors; the lamp blocks (0.02)^2 / 4 = 1e-4 of the
   * wall's view of itself and the tessellation loses 2e-4 of the lamp's
   * area, both far below. */
  if (fabs(got - want) > 4 * se) fail_msg("E %.4f lx vs %.4f (se %.3g)", got, want, se);
  vr_render_result_destroy(r);
  /* gensky's sun: radiance 1e6 in each channel, 0.5 deg: on a horizontal
   * sensor with the sun at the zenith E = 179e6 * 2 pi (1 - cos 0.25 deg). */
  write_rad(p, "sun.rad",
            "void light solar 0 0 3 1e6 1e6 1e6\nsolar source sun 0 0 4 0 0 1 0.5\n"
            "void plastic g 0 0 5 .2 .2 .2 0 0\ng polygon far 0 0 9 100 100 -50 101 100 -50 100 101 -50\n");
  snprintf(scene, sizeof scene,
           "mesh %s\nsensor s point position=0,0,0 normal=0,0,1\n"
           "render integrator=path sensor_samples=256\n", p);
  r = render_text_models(scene, "sun.scn");
  want = 179e6 * 2 * M_PI * (1 - cos(0.25 * M_PI / 180));
  got = r->readings[0].illuminance_lx;
  if (fabs(got / want - 1) > 1e-3) fail_msg("sun: E %.2f lx vs %.2f", got, want);
  vr_render_result_destroy(r);
  unlink(p);
}

/* Radiance's trans without specular parts, R G B 0.8, trans 0.6: a
 * Lambertian reflectance 0.8 x 0.4 = 0.32 and transmittance 0.8 x 0.6 =
 * 0.48 (Radiance's trans: of the colour, the fraction trans is
 * transmitted).  A 200 x 200 m horizontal sheet of it 1 m above a sensor
 * under a sky of uniform luminance (CIE general sky 5) of 10 000 lx and no
 * ground: the sensor facing up reads 0.48 x 10 000 lx, one 1 m above the
 * sheet facing down 0.32 x 10 000 lx, short by the sky the sheet's edges
 * leave in view (1e-4).  Radiance 6.1's rtrace (-ab 4 -ad 65536 -aa 0)
 * gives 4804.4 and 3199.5 lx for the same scene. */
static void test_translucent(void **state) {
  (void)state;
  char p[64];
  write_rad(p, "trans.rad",
            "void trans diffuser 0 0 7 0.8 0.8 0.8 0 0 0.6 0\n"
            "diffuser polygon sheet 0 0 12 -100 -100 1 100 -100 1 100 100 1 -100 100 1\n");
  char scene[400];
  snprintf(scene, sizeof scene,
           "mesh %s\nsky cie type=5 illuminance=10000 ground=0\n"
           "sensor below point position=0,0,0 normal=0,0,1\n"
           "sensor above point position=0,0,2 normal=0,0,-1\n"
           "render integrator=path sensor_samples=16384 seed=5\n", p);
  vr_render_result *r = render_text_models(scene, "trans.scn");
  double want[2] = {4800, 3200};
  for (int k = 0; k < 2; k++) {
    double got = r->readings[k].illuminance_lx, se = r->readings[k].stderr_lx;
    if (fabs(got - want[k]) > 4 * se + 2e-4 * want[k])
      fail_msg("sensor %d: %.2f lx vs %.0f (se %.2f)", k, got, want[k], se);
  }
  vr_render_result_destroy(r);
  /* A specular part is refused, naming the material's file and line. */
  write_rad(p, "trans.rad",
            "void plastic w 0 0 5 .5 .5 .5 0 0\n"
            "void trans t 0 0 7 .5 .5 .5 0.05 0 .5 0\nt polygon q 0 0 9 0 0 0 1 0 0 0 1 0\n");
  snprintf(scene, sizeof scene, "mesh %s\nsensor s point position=0,0,1 normal=0,0,1\n", p);
  vr_scene *s = parse_text(scene, "trans.scn");
  vr_error e = {0};
  assert_int_not_equal(vr_scene_load_models(s, &e), VR_OK);
  if (!strstr(e.message, "trans.rad:2: trans 't'") || !strstr(e.message, "specular part"))
    fail_msg("%s", e.message);
  vr_scene_destroy(s);
  unlink(p);
}

/* Bad files: the file, the line and what is wrong. */
static void test_refusals(void **state) {
  (void)state;
  static const struct {
    const char *text, *line, *needle;
  } C[] = {
      {"void brightfunc skyfunc 2 skybr skybright.cal 0 0\n", ":1:", "patterns"},
      {"\nvoid plasfunc p 2 refl f.cal 0 4 .5 .5 .5 0\n", ":2:", "not modelled"},
      {"!gensky 3 21 12\n", ":1:", "never run"},
      {"void plastic w 0 0 5 .5 .5 .5 0 0\nx polygon p 0 0 9 0 0 0 1 0 0 0 1 0\n", ":2:",
       "'x' is not defined"},
      {"void plastic w 0 0 5 .5 .5 .5 0 0\nw polygon p 0 0 10 0 0 0 1 0 0 0 1 0 0\n", ":2:",
       "3 per vertex"},
      {"void plastic w 0 0 5 .5 .5 nan 0 0\n", ":1:", "not a finite number"},
      {"void plastic w 0 0 5 .5 .5 .5 0 0\nw cylinder c 0 0 7 0 0 0 0 0 1 -1\n", ":2:", "radii"},
      {"!xform -a 3 -t 1 0 0 x.rad\n", ":1:", "option '-a'"},
      {"!xform nowhere.rad\n", ":1:", "cannot open"},
      {"void plastic w 1 a 0 5 .5 .5 .5 0 0\n", ":1:", "string arguments"},
      {"void plastic w 0 2 1 1 5 .5 .5 .5 0 0\n", ":1:", "integer arguments"},
      {"void plastic w 0 0 5 .5 .5\n", ":1:", "file ends"},
      {"void BSDF b 6 0.01 blind.xml 0 0 1 . 0 0\n", ":1:", "thickness"},
      {"void plastic w 0 0 5 .5 .5 .5 0 0\nw instance i 1 x.oct 0 0\n", ":2:", "octree"},
      {"void light l 0 0 3 1 1 1\nl source s 0 0 4 0 0 1 180\n", ":2:", "sky line"},
      {"void light l 0 0 3 1 1 1\nl source s 0 0 4 0 0 1 0.5\n", "", "no surfaces"},
  };
  for (size_t i = 0; i < sizeof C / sizeof *C; i++) {
    char p[64];
    write_rad(p, "bad.rad", C[i].text);
    vr_rad_model m;
    vr_error e = {0};
    vr_status st = vr_rad_read(p, &m, &e);
    if (st == VR_OK) fail_msg("case %zu read", i);
    if (!strstr(e.message, "bad.rad") || !strstr(e.message, C[i].line) ||
        !strstr(e.message, C[i].needle))
      fail_msg("case %zu: '%s' lacks the file, '%s' or '%s'", i, e.message, C[i].line, C[i].needle);
    unlink(p);
  }
  /* A file that includes itself. */
  char p[64];
  snprintf(p, sizeof p, "/tmp/vr_rad_%d_loop.rad", (int)getpid());
  char text[200];
  snprintf(text, sizeof text, "!xform %s\n", strrchr(p, '/') + 1);
  write_rad(p, "loop.rad", text);
  vr_rad_model m;
  vr_error e = {0};
  assert_int_not_equal(vr_rad_read(p, &m, &e), VR_OK);
  assert_non_null(strstr(e.message, "nested"));
  unlink(p);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_sample_office_areas), cmocka_unit_test(test_sample_office_overlaps),
      cmocka_unit_test(test_overlap_cases),       cmocka_unit_test(test_seamed_wall),
      cmocka_unit_test(test_quadrics),            cmocka_unit_test(test_orientation_and_xform),
      cmocka_unit_test(test_dielectric_units),
      cmocka_unit_test(test_honeybee_glass),      cmocka_unit_test(test_integrating_sphere),
      cmocka_unit_test(test_translucent),
      cmocka_unit_test(test_refusals),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
