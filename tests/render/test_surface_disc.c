/* A density estimate's disc on its sheet of surface
 * (render/src/integrators/surface_disc.c) against plane geometry:
 *
 *   - the share of a disc of radius r inside a straight edge at distance d
 *     from its centre is 1 - (acos(d/r) - (d/r) sqrt(1 - d^2/r^2)) / pi
 *     (the circular segment's area over the disc's); 1/2 on the edge, 1/4
 *     at a right-angled corner, for the box and for the cone filter alike
 *     (both are radial);
 *   - which edges of a rect end: a wall cut around a window carries on
 *     across its seams with its coplanar pieces of the same material, not
 *     across the window (no photon lands on glass) nor at the floor, and a
 *     floor does not carry on into the coplanar ground under its wall;
 *   - which photons belong to a point's sheet;
 *   - a box's faces: each a rect whose edges all end, its photons told
 *     apart by their normals. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "bsdf_test_util.h"
#include "integrators/surface_disc.h"

/* The unit square in the plane z = 0. */
static const double SQUARE[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};

static double segment_share(double d, double r) {
  double q = d / r;
  return 1 - (acos(q) - q * sqrt(1 - q * q)) / M_PI;
}

static void test_share_of_straight_edges(void **state) {
  (void)state;
  double mid[3] = {0.5, 0.5, 0}, edge[3] = {0, 0.5, 0}, corner[3] = {0, 0, 0};
  for (int kind = 0; kind < 2; kind++) {
    double kc = kind ? 1.1 : 0;
    assert_float_equal(vr_rect_disc_share(SQUARE, VR_EDGE_ALL, mid, 0.4, kc), 1.0, 1e-12);
    assert_float_equal(vr_rect_disc_share(SQUARE, VR_EDGE_ALL, edge, 0.2, kc), 0.5, 1e-12);
    assert_float_equal(vr_rect_disc_share(SQUARE, VR_EDGE_ALL, corner, 0.2, kc), 0.25, 1e-12);
    /* An edge that carries on cuts nothing off. */
    assert_float_equal(vr_rect_disc_share(SQUARE, VR_EDGE_ALL & ~VR_EDGE_U0, edge, 0.2, kc), 1.0,
                       1e-12);
    assert_float_equal(vr_rect_disc_share(SQUARE, VR_EDGE_V0, corner, 0.2, kc), 0.5, 1e-12);
  }
  /* The box filter at d = r/4, r/2 and 3r/4 from the edge u = 0: the
   * segment formula, to the 128 directions' quadrature (4e-4). */
  for (int i = 1; i <= 3; i++) {
    double r = 0.2, d = 0.25 * i * r, x[3] = {d, 0.5, 0};
    assert_float_equal(vr_rect_disc_share(SQUARE, VR_EDGE_ALL, x, r, 0), segment_share(d, r), 4e-4);
  }
  /* A point outside its rect (a float's rounding) reads as on its edge,
   * and a tiny sliver is held at 0.05, not divided by nearly zero. */
  double out[3] = {-0.01, 0.5, 0};
  assert_float_equal(vr_rect_disc_share(SQUARE, VR_EDGE_ALL, out, 0.2, 0), 0.5, 1e-12);
  double sliver[9] = {0, 0, 0, 1e-4, 0, 0, 0, 1e-4, 0};
  assert_float_equal(vr_rect_disc_share(sliver, VR_EDGE_ALL, (double[3]){0, 0, 0}, 1, 0), 0.05,
                     1e-12);
}

static void test_sheet_holds(void **state) {
  (void)state;
  unsigned ends = VR_EDGE_U0 | VR_EDGE_V0 | VR_EDGE_V1; /* carries on past u = 1 */
  assert_true(vr_rect_sheet_holds(SQUARE, ends, (double[3]){0.5, 0.5, 0.003}));
  assert_true(vr_rect_sheet_holds(SQUARE, ends, (double[3]){1.1, 0.5, 0}));
  assert_false(vr_rect_sheet_holds(SQUARE, ends, (double[3]){-0.1, 0.5, 0}));
  assert_false(vr_rect_sheet_holds(SQUARE, ends, (double[3]){1.1, 1.1, 0}));
  assert_false(vr_rect_sheet_holds(SQUARE, ends, (double[3]){0.5, -0.1, 0}));
}

static void test_same_sheet(void **state) {
  (void)state;
  double p[3] = {0, 0, 0}, up[3] = {0, 0, 1};
  /* A wall's photon beside a floor's point. */
  assert_false(vr_same_sheet(p, up, (double[3]){0.1, 0, 0.05}, (double[3]){-1, 0, 0}, 0.2));
  /* The floor's other side (a thin slab's) faces the other way: the side
   * test, not this one, tells them apart. */
  assert_true(vr_same_sheet(p, up, (double[3]){0.1, 0, 0}, (double[3]){0, 0, -1}, 0.2));
  /* Facets of a smooth mesh: 25 degrees apart are one sheet, 26 are not
   * (|cos| >= 0.9: 25.84 degrees). */
  double a25 = 25 * M_PI / 180, a26 = 26 * M_PI / 180;
  assert_true(vr_same_sheet(p, up, (double[3]){0.1, 0, 0}, (double[3]){sin(a25), 0, cos(a25)}, 0.2));
  assert_false(vr_same_sheet(p, up, (double[3]){0.1, 0, 0}, (double[3]){sin(a26), 0, cos(a26)}, 0.2));
  /* A step: 2 cm above is off the plane for a disc of 4 cm (within 1 cm),
   * on it for one of 20 cm (within 5 cm). */
  assert_false(vr_same_sheet(p, up, (double[3]){0.01, 0, 0.02}, up, 0.04));
  assert_true(vr_same_sheet(p, up, (double[3]){0.01, 0, 0.02}, up, 0.2));
}

/* A south wall (y = 0, 5 x 2.7 m) cut around a 1.4 m window into sill,
 * lintel and piers (the east pier of brick, the rest paint), a glass pane
 * in the hole, the floor (y 0-4) and, coplanar with the floor and of its
 * material, the ground outside (y -3-0): the paint pieces carry on into
 * each other, not into the brick, the glass (no photon lands on it) or
 * the floor; the floor does not carry on into the ground, since the wall
 * stands on that edge. */
static void test_edges_ending(void **state) {
  (void)state;
  enum { N = 7 };
  /* corner, eu, ev of each rect. */
  double frames[N][9] = {
      {0, 0, 0, 5, 0, 0, 0, 0, 0.9},       /* sill: z 0-0.9 */
      {0, 0, 2.3, 5, 0, 0, 0, 0, 0.4},     /* lintel: z 2.3-2.7 */
      {0, 0, 0.9, 1.8, 0, 0, 0, 0, 1.4},   /* west pier: x 0-1.8 */
      {3.2, 0, 0.9, 1.8, 0, 0, 0, 0, 1.4}, /* east pier: x 3.2-5, brick */
      {1.8, 0, 0.9, 1.4, 0, 0, 0, 0, 1.4}, /* the pane */
      {0, 0, 0, 5, 0, 0, 0, 4, 0},         /* the floor (y 0-4) */
      {-2, -3, 0, 9, 0, 0, 0, 3, 0},       /* the ground outside (y -3-0) */
  };
  uint8_t is_rect[N] = {1, 1, 1, 1, 1, 1, 1};
  vr_scene_tables t;
  memset(&t, 0, sizeof t);
  t.nobjects = N;
  t.is_rect = is_rect;
  t.rect_frame = frames;
  vr_scene_material paint_sm = test_sm(NULL), brick_sm = test_sm(NULL);
  paint_sm.source = brick_sm.source = VR_MATSRC_LAMBERT_CONST;
  paint_sm.reflectance = 0.6;
  brick_sm.reflectance = 0.3;
  vr_scene_material glass_sm = test_sm("clear");
  glass_sm.thickness_m = 0.004;
  vr_material *glass = flat_nk("clear", VR_KIND_DIELECTRIC, 1.52, 0);
  vr_rmaterial mats[3];
  memset(mats, 0, sizeof mats);
  mats[0].bsdf = make_bsdf(&paint_sm, NULL, NULL);
  mats[1].bsdf = make_bsdf(&glass_sm, glass, NULL);
  mats[2].bsdf = make_bsdf(&brick_sm, NULL, NULL);
  vr_robject objs[N];
  memset(objs, 0, sizeof objs);
  objs[3].material = 2;
  objs[4].material = 1;
  vr_rscene rs;
  memset(&rs, 0, sizeof rs);
  rs.t = &t;
  rs.obj = objs;
  rs.mat = mats;
  rs.nmat = 3;
  uint8_t *ends = vr_rect_edges_ending(&rs);
  assert_non_null(ends);
  /* The sill's top (v = 1) meets the west pier, the glass and the brick
   * pier at its probes: one of three is its sheet, so it ends; so do its
   * sides and its foot, where the floor stands. */
  assert_int_equal(ends[0], VR_EDGE_ALL);
  /* The west pier: paint sill below and lintel above carry it on; the
   * glass to the east and nothing to the west do not. */
  assert_int_equal(ends[2], VR_EDGE_U0 | VR_EDGE_U1);
  /* The brick pier carries on into nothing. */
  assert_int_equal(ends[3], VR_EDGE_ALL);
  /* The floor: the ground is coplanar and of its paint past its south
   * edge (v = 0), but the wall stands there. */
  assert_int_equal(ends[5], VR_EDGE_ALL);
  /* Without the wall's pieces, the floor would carry on into the ground
   * there (and nowhere else). */
  for (int o = 0; o < 5; o++) is_rect[o] = 0;
  free(ends);
  ends = vr_rect_edges_ending(&rs);
  assert_int_equal(ends[5], VR_EDGE_ALL & ~VR_EDGE_V0);
  free(ends);
  for (int m = 0; m < 3; m++) vr_bsdf_destroy(mats[m].bsdf);
  vr_material_destroy(glass);
}

/* A box of 2 x 1 x 0.5 m turned 90 degrees about z and moved to (5, 0, 1):
 * a world point on each face finds that face (its frame holds the point
 * at (u, v) = (1/2, 1/2) and its normal is the face's), and a disc at a
 * face's corner keeps a quarter (the right-angled corner above). */
static void test_box_faces(void **state) {
  (void)state;
  vr_scene_object o;
  memset(&o, 0, sizeof o);
  o.shape = VR_SHAPE_BOX;
  double lo[3] = {0, 0, 0}, hi[3] = {2, 1, 0.5};
  memcpy(o.bmin, lo, sizeof lo);
  memcpy(o.bmax, hi, sizeof hi);
  /* (x, y, z) -> (5 - y, x, z + 1). */
  vr_xform_identity(&o.xform);
  o.xform.m[0][0] = 0, o.xform.m[0][1] = -1, o.xform.m[0][3] = 5;
  o.xform.m[1][0] = 1, o.xform.m[1][1] = 0;
  o.xform.m[2][3] = 1;
  /* Each face's centre in the box's own coordinates, and its outward normal. */
  const double centre[6][3] = {{2, 0.5, 0.25}, {0, 0.5, 0.25}, {1, 1, 0.25},
                               {1, 0, 0.25},   {1, 0.5, 0.5},  {1, 0.5, 0}};
  const double normal[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (int k = 0; k < 6; k++) {
    double x[3], n[3], f[9], fn[3];
    vr_xform_point(&o.xform, centre[k], x);
    vr_xform_vector(&o.xform, normal[k], n);
    vr_box_face_frame(&o, x, f);
    vr_cross3(f + 3, f + 6, fn);
    double l = sqrt(vr_dot3(fn, fn));
    assert_float_equal(fabs(vr_dot3(fn, n)) / l, 1.0, 1e-12);
    /* (u, v) of x in the frame: the face's middle. */
    double d[3] = {x[0] - f[0], x[1] - f[1], x[2] - f[2]};
    assert_float_equal(vr_dot3(d, f + 3) / vr_dot3(f + 3, f + 3), 0.5, 1e-12);
    assert_float_equal(vr_dot3(d, f + 6) / vr_dot3(f + 6, f + 6), 0.5, 1e-12);
    assert_float_equal(vr_rect_disc_share(f, VR_EDGE_ALL, x, 0.2, 0), 1.0, 1e-12);
    /* The face's corner: a quarter of the disc. */
    assert_float_equal(vr_rect_disc_share(f, VR_EDGE_ALL, f, 0.2, 0), 0.25, 1e-12);
  }
  /* Photons on the point's face only: parallel normals, not the faces at
   * right angles, not the opposite face; the facets' 25.8 degrees. */
  double up[3] = {0, 0, 1}, side[3] = {1, 0, 0}, down[3] = {0, 0, -1};
  double t20[3] = {sin(20 * M_PI / 180), 0, cos(20 * M_PI / 180)};
  double t30[3] = {sin(30 * M_PI / 180), 0, cos(30 * M_PI / 180)};
  assert_true(vr_box_same_face(up, up));
  assert_false(vr_box_same_face(up, side));
  assert_false(vr_box_same_face(up, down));
  assert_true(vr_box_same_face(up, t20));
  assert_false(vr_box_same_face(up, t30));
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_share_of_straight_edges),
      cmocka_unit_test(test_sheet_holds),
      cmocka_unit_test(test_same_sheet),
      cmocka_unit_test(test_edges_ending),
      cmocka_unit_test(test_box_faces),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
