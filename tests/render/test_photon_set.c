/* Per-cell photon maps answering as one (vr/photon_set.h): the estimate
 * over photons split into several maps is bit for bit the estimate over
 * one map holding them all, for k-nearest and fixed-radius queries, box and
 * cone filters, queries right on the planes that split the maps, photons
 * tied in distance across two maps, and photons from the wrong side; and it
 * agrees with the single-map vr_photon_map_irradiance (which sums in tree
 * order, not key order) to rounding.
 *
 * The analytic anchor: a uniform field of N photons of power 1 W on the
 * unit square, read with the box filter by fixed radius r in the middle,
 * has expected irradiance (photons in the disc) / (pi r^2); the count in
 * the disc is checked against brute force, so the set must return exactly
 * that count and that sum.  The same brute force checks an estimate that
 * takes another surface's photons where its callback says so (a rect's
 * sheet, integrators/surface_disc.h). */
#include "vr_test.h"
#include "vr/photon_map.h"
#include "vr/photon_set.h"

static uint64_t mix64(uint64_t z) {
  /* splitmix64's finaliser (Steele, Lea, Flood 2014) */
  z += 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}
static double u01(uint64_t stream, uint64_t i) {
  return (double)(mix64(mix64(i) ^ (stream * 0xD1B54A32D192ED03ull)) >> 11) * 0x1.0p-53;
}

static const double UP[3] = {0, 0, 1}, DOWN[3] = {0, 0, -1};
static const double CENTRE[3] = {0.5, 0.5, 0.0};
#define NB 6

/* Which of the 2 x 2 x 2 = 8 cells (split at x = 0.5, y = 0.37, z = 0.5)
 * holds pos; with cells = 1, always 0. */
static int cell_of(const double pos[3], int cells) {
  if (cells == 1) return 0;
  return (pos[0] >= 0.5) | (pos[1] >= 0.37) << 1 | (cells > 4 && pos[2] >= 0.5) << 2;
}

typedef struct photon {
  uint64_t key;
  double pos[3], dir[3];
  float power[NB];
} photon;

/* Photons on the floor z = 0 (most), on a wall x = 0.5 (some, on the
 * split plane itself) and on a shelf z = 0.5; a few arrive from below.
 * Positions on a 1/64 grid for a third of them, so distances tie. */
static photon make_photon(uint64_t i) {
  photon p = {.key = mix64(i + 17)};
  double u = u01(1, i), v = u01(2, i);
  if (i % 3 == 0) {
    u = floor(u * 64) / 64;
    v = floor(v * 64) / 64;
  }
  int where = (int)(u01(3, i) * 10);
  if (where < 7) {
    p.pos[0] = u, p.pos[1] = v, p.pos[2] = 0;
  } else if (where < 9) {
    p.pos[0] = 0.5, p.pos[1] = v, p.pos[2] = u * 0.6;
  } else {
    p.pos[0] = u, p.pos[1] = v, p.pos[2] = 0.5;
  }
  double dz = i % 13 == 0 ? 1.0 : -1.0; /* a few from below */
  p.dir[0] = u01(4, i) - 0.5, p.dir[1] = u01(5, i) - 0.5, p.dir[2] = dz;
  memset(p.power, 0, sizeof p.power);
  p.power[i % NB] = (float)(0.5 + u01(6, i));
  p.power[(i + 2) % NB] = (float)u01(7, i);
  return p;
}

static vr_photon_set *make_set(int cells, size_t n) {
  vr_error err = {0};
  vr_photon_set *s = vr_photon_set_create(cells, NB, 400, 700, 2, CENTRE, &err);
  assert_non_null(s);
  for (uint64_t i = 0; i < n; i++) {
    photon p = make_photon(i);
    assert_int_equal(vr_photon_set_store(s, cell_of(p.pos, cells), p.key, p.pos, p.dir, UP,
                                         p.power, &err),
                     VR_OK);
  }
  assert_int_equal(vr_photon_set_build(s, &err), VR_OK);
  assert_int_equal(vr_photon_set_count(s), n);
  return s;
}

static void same_bits(const double *a, const double *b, int n, const char *what, int q) {
  for (int i = 0; i < n; i++)
    if (memcmp(&a[i], &b[i], sizeof a[i]))
      fail_msg("%s, query %d, bin %d: %.17g vs %.17g", what, q, i, a[i], b[i]);
}

static void split_maps_answer_as_one(void **state) {
  (void)state;
  const size_t N = 20000;
  vr_photon_set *one = make_set(1, N), *four = make_set(4, N), *eight = make_set(8, N);
  /* The single map, for the comparison to rounding. */
  vr_error err = {0};
  vr_photon_map *m = vr_photon_map_create_sparse(NB, 400, 700, 2, &err);
  assert_int_equal(vr_photon_map_set_centre(m, CENTRE, &err), VR_OK);
  for (uint64_t i = 0; i < N; i++) {
    photon p = make_photon(i);
    assert_int_equal(vr_photon_map_store(m, p.key, p.pos, p.dir, UP, p.power, &err), VR_OK);
  }
  assert_int_equal(vr_photon_map_build(m, &err), VR_OK);
  int cells_hit = 0;
  for (int q = 0; q < 600; q++) {
    /* Query points on the floor, many on or next to the split planes. */
    double x[3] = {u01(10, (uint64_t)q), u01(11, (uint64_t)q), 0.0};
    if (q % 4 == 0) x[0] = 0.5;
    if (q % 4 == 1) x[1] = 0.37 + (q % 8 == 1 ? 1e-9 : -1e-9);
    if (q % 7 == 0) x[0] = floor(x[0] * 64) / 64, x[1] = floor(x[1] * 64) / 64;
    const double *nrm = q % 11 == 0 ? DOWN : UP;
    int k = q % 5 == 0 ? 0 : (int[]){1, 7, 50, 400}[q % 4];
    double rmax = q % 3 == 0 ? 0.05 : 0.2, kc = q % 2 ? 1.1 : 0.0;
    double a[NB], b[NB], c[NB], d[NB], ra, rb, rc, rd;
    int na = vr_photon_set_irradiance(one, x, nrm, k, rmax, kc, a, &ra);
    int nb = vr_photon_set_irradiance(four, x, nrm, k, rmax, kc, b, &rb);
    int nc = vr_photon_set_irradiance(eight, x, nrm, k, rmax, kc, c, &rc);
    int nd = vr_photon_map_irradiance(m, x, nrm, k, rmax, kc, d, &rd);
    assert_int_equal(na, nb);
    assert_int_equal(na, nc);
    assert_int_equal(na, nd);
    if (!(ra == rb && ra == rc && ra == rd))
      fail_msg("query %d: radii %.17g %.17g %.17g %.17g", q, ra, rb, rc, rd);
    same_bits(a, b, NB, "4 maps", q);
    same_bits(a, c, NB, "8 maps", q);
    for (int i = 0; i < NB; i++) assert_near(a[i], d[i], 1e-12 * fabs(d[i]));
    if (na > 0) cells_hit++;
  }
  assert_true(cells_hit > 400);
  vr_photon_map_destroy(m);
  vr_photon_set_destroy(one);
  vr_photon_set_destroy(four);
  vr_photon_set_destroy(eight);
}

/* The analytic case: a uniform 200 x 200 grid of 1 W photons on the unit
 * square split into four maps; the box-filter estimate at radius r is the
 * number of grid points within r (counted here by brute force, and within
 * 1 % of pi r^2 N) times 1 W over pi r^2. */
static void uniform_grid_fixed_radius(void **state) {
  (void)state;
  vr_error err = {0};
  vr_photon_set *s = vr_photon_set_create(4, NB, 400, 700, 1, CENTRE, &err);
  int n = 200;
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n; i++) {
      double pos[3] = {(i + 0.5) / n, (j + 0.5) / n, 0};
      float pw[NB] = {0};
      pw[0] = 1.0f;
      assert_int_equal(
          vr_photon_set_store(s, cell_of(pos, 4), (uint64_t)(j * n + i), pos, DOWN, UP, pw, &err),
          VR_OK);
    }
  assert_int_equal(vr_photon_set_build(s, &err), VR_OK);
  double x[3] = {0.5, 0.37, 0}, r = 0.1, out[NB];
  int inside = 0;
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n; i++) {
      double dx = (i + 0.5) / n - x[0], dy = (j + 0.5) / n - x[1];
      inside += dx * dx + dy * dy <= r * r;
    }
  assert_near(inside, M_PI * r * r * n * n, 0.01 * M_PI * r * r * n * n);
  assert_int_equal(vr_photon_set_irradiance(s, x, UP, 0, r, 0.0, out, NULL), inside);
  assert_rel(out[0], inside / (M_PI * r * r), 1e-12);
  vr_photon_set_destroy(s);
}

/* Light leaking under a wall: a floor (surface 1, y in [0, 1)) and the
 * ground outside (surface 2, y in [-1, 0)) on one plane, both lit from
 * above, the ground 100 times brighter (sunlit against a shaded room).
 * Read on the floor 0.03 m from the wall with the 400 nearest photons,
 * the estimate restricted to surface 1 must be the floor's own density,
 * i.e. exactly (same photons, same bits) the estimate of a set holding the
 * floor's photons alone, and the one that mixes surfaces is many times
 * higher: the leak the surface rule removes. */
static void surfaces_do_not_mix(void **state) {
  (void)state;
  vr_error err = {0};
  vr_photon_set *both = vr_photon_set_create(4, NB, 400, 700, 1, CENTRE, &err);
  vr_photon_set *floor_only = vr_photon_set_create(4, NB, 400, 700, 1, CENTRE, &err);
  assert_non_null(both);
  assert_non_null(floor_only);
  int n = 100;
  for (int j = -n; j < n; j++)
    for (int i = 0; i < n; i++) {
      double pos[3] = {(i + 0.5) / n, (j + 0.5) / n, 0};
      float pw[NB] = {0};
      uint32_t surface = j >= 0 ? 1u : 2u;
      pw[0] = surface == 1 ? 1.0f : 100.0f;
      uint64_t key = (uint64_t)((j + n) * n + i);
      assert_int_equal(vr_photon_set_store_on(both, cell_of(pos, 4), key, pos, DOWN, UP, surface,
                                              pw, &err),
                       VR_OK);
      if (surface == 1)
        assert_int_equal(vr_photon_set_store_on(floor_only, cell_of(pos, 4), key, pos, DOWN, UP,
                                                surface, pw, &err),
                         VR_OK);
    }
  assert_int_equal(vr_photon_set_build(both, &err), VR_OK);
  assert_int_equal(vr_photon_set_build(floor_only, &err), VR_OK);
  double x[3] = {0.5, 0.03, 0}, on[NB], alone[NB], mixed[NB], r_on, r_alone;
  int got_on = vr_photon_set_irradiance_on(both, x, UP, 1, 400, 1.0, 0.0, on, &r_on);
  int got_alone = vr_photon_set_irradiance(floor_only, x, UP, 400, 1.0, 0.0, alone, &r_alone);
  assert_int_equal(got_on, 400);
  assert_int_equal(got_alone, 400);
  assert_true(r_on == r_alone);
  same_bits(on, alone, NB, "surface 1 of both against the floor alone", 0);
  assert_int_equal(vr_photon_set_irradiance(both, x, UP, 400, 1.0, 0.0, mixed, NULL), 400);
  print_message("  floor 0.03 m from the wall: %.0f W/m2 on its own surface, %.0f mixing the "
                "ground in\n", on[0], mixed[0]);
  assert_true(mixed[0] > 10.0 * on[0]);
  /* VR_PHOTON_ANY_SURFACE is the unrestricted estimate. */
  double any[NB];
  vr_photon_set_irradiance_on(both, x, UP, VR_PHOTON_ANY_SURFACE, 400, 1.0, 0.0, any, NULL);
  same_bits(any, mixed, NB, "any surface against the plain estimate", 0);
  vr_photon_set_destroy(both);
  vr_photon_set_destroy(floor_only);
}

/* One surface's photons at a fixed radius: the floor (surface 1, y >= 0)
 * and the ground (surface 2, y < 0) interleave about (0.5, 0.02).  Within
 * 0.1 m with the box filter the estimate on surface 1 must be the sum of
 * its photons' power in the disc over pi r^2, counted here photon by photon
 * from their positions; the ground's, 100 times brighter, take no part. */
static void one_surface_at_a_fixed_radius(void **state) {
  (void)state;
  vr_error err = {0};
  vr_photon_set *s = vr_photon_set_create(4, NB, 400, 700, 1, CENTRE, &err);
  assert_non_null(s);
  int n = 100;
  double x[3] = {0.5, 0.02, 0}, r = 0.1, want = 0, all = 0;
  for (int j = -n; j < n; j++)
    for (int i = 0; i < n; i++) {
      double pos[3] = {(i + 0.5) / n, (j + 0.5) / n, 0};
      uint32_t surface = j >= 0 ? 1u : 2u;
      float pw[NB] = {0};
      pw[0] = surface == 1 ? 1.0f : 100.0f;
      assert_int_equal(vr_photon_set_store_on(s, cell_of(pos, 4), (uint64_t)((j + n) * n + i), pos,
                                              DOWN, UP, surface, pw, &err),
                       VR_OK);
      double dx = pos[0] - x[0], dy = pos[1] - x[1];
      if (dx * dx + dy * dy <= r * r) {
        all += pw[0];
        if (surface == 1) want += pw[0];
      }
    }
  assert_int_equal(vr_photon_set_build(s, &err), VR_OK);
  double on1[NB], any[NB];
  assert_true(vr_photon_set_irradiance_on(s, x, UP, 1, 0, r, 0.0, on1, NULL) > 0);
  assert_rel(on1[0], want / (M_PI * r * r), 1e-12);
  assert_true(vr_photon_set_irradiance_on(s, x, UP, VR_PHOTON_ANY_SURFACE, 0, r, 0.0, any, NULL) >
              0);
  assert_rel(any[0], all / (M_PI * r * r), 1e-12);
  vr_photon_set_destroy(s);
}

static void bad_arguments(void **state) {
  (void)state;
  vr_error err = {0};
  assert_null(vr_photon_set_create(0, NB, 400, 700, 2, CENTRE, &err));
  double far[3] = {NAN, 0, 0};
  assert_null(vr_photon_set_create(2, NB, 400, 700, 2, far, &err));
  vr_photon_set *s = vr_photon_set_create(2, NB, 400, 700, 2, CENTRE, &err);
  float pw[NB] = {1};
  assert_int_equal(vr_photon_set_store(s, 2, 1, CENTRE, DOWN, UP, pw, &err), VR_E_ARG);
  double out[NB], x[3] = {0.5, 0.5, 0};
  /* not built yet */
  assert_int_equal(vr_photon_set_irradiance(s, x, UP, 5, 0.1, 0, out, NULL), -1);
  assert_int_equal(vr_photon_set_build(s, &err), VR_OK);
  assert_int_equal(vr_photon_set_irradiance(s, x, UP, -1, 0.1, 0, out, NULL), -1);
  assert_int_equal(vr_photon_set_irradiance(s, x, UP, 5, INFINITY, 0, out, NULL), -1);
  /* empty maps: nothing found, zero irradiance */
  assert_int_equal(vr_photon_set_irradiance(s, x, UP, 5, 0.1, 0, out, NULL), 0);
  assert_true(out[0] == 0.0);
  vr_photon_set_destroy(s);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(split_maps_answer_as_one),
      cmocka_unit_test(uniform_grid_fixed_radius),
      cmocka_unit_test(bad_arguments),
      cmocka_unit_test(surfaces_do_not_mix),
      cmocka_unit_test(one_surface_at_a_fixed_radius),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
