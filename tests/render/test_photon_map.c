/* The spectral photon map (vr/photon_map.h): density estimates on a uniform
 * field against their analytic expectation, the kd-tree's neighbourhoods
 * against brute force, the side and disc rules, bit-identical results for
 * any order of stores, and degenerate input; sparse maps
 * (vr_photon_map_create_sparse) against the same analytic values, against
 * dense maps fed the same photons (bit for bit), their refusal of photons
 * with too many non-zero bins, and their cost.
 *
 * Every random number comes from a counter-based generator (a hash of a
 * stream and a counter), so each test sees the same photons on every run. */
#include "vr_test.h"
#include "vr/photon_map.h"

#include <pthread.h>

/* The splitmix64 finaliser (Steele, Lea, Flood 2014), a bijection of 64-bit
 * words; hashing (stream, counter) through it twice gives independent
 * uniforms for any counter. */
static uint64_t mix64(uint64_t z) {
  z += 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}
static double u01(uint64_t stream, uint64_t i) {
  return (double)(mix64(mix64(i) ^ (stream * 0xD1B54A32D192ED03ull)) >> 11) * 0x1.0p-53;
}
static void unit_vector(uint64_t stream, uint64_t i, double v[3]) {
  double z = 2.0 * u01(stream, 2 * i) - 1.0, phi = 2.0 * M_PI * u01(stream, 2 * i + 1);
  double s = sqrt(1.0 - z * z);
  v[0] = s * cos(phi);
  v[1] = s * sin(phi);
  v[2] = z;
}

static const double DOWN[3] = {0, 0, -1}, UP[3] = {0, 0, 1};

/* --- (a) a uniform field ------------------------------------------------- */

/* N = n^2 photons, one per cell of an n x n grid on the unit square at z = 0
 * (jittered stratification), all travelling straight down, carrying
 * PHI[b] / N each: the irradiance is PHI[b] W/m^2 everywhere inside.  The
 * dense map has three bins; the sparse one 47 (10 nm over 360-830 nm), of
 * which each photon fills the three of UBIN, and keeps at most 4. */
#define GRID 256
#define KNN 100
#define UNB 47
static const double PHI[3] = {1.0, 2.0, 0.5};
static const int UBIN[3] = {5, 23, 46};

static double jitter(int i, int j, int axis) {
  return u01(11 + (uint64_t)axis, (uint64_t)j * GRID + (uint64_t)i);
}

static vr_photon_map *uniform_square(bool sparse) {
  vr_error err;
  vr_photon_map *m = sparse ? vr_photon_map_create_sparse(UNB, 360, 830, 4, &err)
                            : vr_photon_map_create(3, 400, 700, &err);
  assert_non_null(m);
  const double N = (double)GRID * GRID;
  float p[UNB] = {0};
  for (int c = 0; c < 3; c++) p[sparse ? UBIN[c] : c] = (float)(PHI[c] / N);
  for (int j = 0; j < GRID; j++)
    for (int i = 0; i < GRID; i++) {
      double pos[3] = {(i + jitter(i, j, 0)) / GRID, (j + jitter(i, j, 1)) / GRID, 0.0};
      assert_int_equal(vr_photon_map_store(m, (uint64_t)j * GRID + (uint64_t)i, pos, DOWN, UP,
                                           p, &err),
                       VR_OK);
    }
  assert_int_equal(vr_photon_map_build(m, &err), VR_OK);
  assert_int_equal(vr_photon_map_count(m), GRID * GRID);
  return m;
}

/* The spread of the photon count in a disc of radius r at x: each cell c
 * holds one photon, inside the disc with probability p_c (the fraction of
 * the cell the disc covers), so Var = sum p_c (1 - p_c).  p_c by a 16 x 16
 * midpoint rule. */
static double count_sigma(const double x[2], double r) {
  double var = 0.0;
  int i0 = (int)floor((x[0] - r) * GRID), i1 = (int)floor((x[0] + r) * GRID);
  int j0 = (int)floor((x[1] - r) * GRID), j1 = (int)floor((x[1] + r) * GRID);
  for (int j = j0; j <= j1; j++)
    for (int i = i0; i <= i1; i++) {
      int in = 0;
      for (int b = 0; b < 16; b++)
        for (int a = 0; a < 16; a++) {
          double px = (i + (a + 0.5) / 16) / GRID - x[0], py = (j + (b + 0.5) / 16) / GRID - x[1];
          in += px * px + py * py <= r * r;
        }
      double p = in / 256.0;
      var += p * (1.0 - p);
    }
  return sqrt(var);
}

/* The expected k-nearest estimate on an evenly spread field, relative to
 * the true density.  The photons' squared distances sit on average at the
 * midpoints pi sigma rho_j^2 = j - 1/2, so the k-th (which fixes r) gives
 * pi sigma r^2 = k - 1/2, and
 *   E = [k - (1/kc) sum_j sqrt((j - 1/2)/(k - 1/2))] / [(1 - 2/(3 kc)) (k - 1/2)],
 * which is k / (k - 1/2) for the box filter (+0.50 % at k = 100) and
 * within 0.01 % of 1 for the cone with kc = 1, whose weight vanishes at the
 * photon that sets r.  (For Poisson photons the same reasoning gives
 * k / (k - 1) and 1 + (1 - 1/kc) / ((k - 1)(1 - 2/(3 kc))).)  Fixed-radius
 * estimates have expectation exactly 1: jittered sampling is unbiased for
 * the count in any fixed region, and the normalisation 1 - 2/(3 kc) is the
 * cone's integral over the disc (Jensen 2001, eq. 7.6). */
static double knn_expectation(int k, double kc) {
  if (kc <= 0.0) return k / (k - 0.5);
  double s = 0.0;
  for (int j = 1; j <= k; j++) s += sqrt((j - 0.5) / (k - 0.5));
  return (k - s / kc) / ((1.0 - 2.0 / (3.0 * kc)) * (k - 0.5));
}

static void uniform_field_of(bool sparse) {
  vr_photon_map *m = uniform_square(sparse);
  const int nb = sparse ? UNB : 3, b0 = sparse ? UBIN[0] : 0, b1 = sparse ? UBIN[1] : 1,
            b2 = sparse ? UBIN[2] : 2;
  const double N = (double)GRID * GRID, r0 = sqrt(KNN / (M_PI * N));
  struct {
    const char *name;
    int k;
    double kc;
  } f[] = {{"box, k = 100", KNN, 0.0},         {"box, r fixed", 0, 0.0},
           {"cone kc = 1, k = 100", KNN, 1.0}, {"cone kc = 1.1, k = 100", KNN, 1.1},
           {"cone kc = 1, r fixed", 0, 1.0}};
  enum { NF = sizeof f / sizeof f[0], Q = 1000 };
  double sum[NF] = {0}, sum2[NF] = {0}, worst[NF] = {0}, z2 = 0.0;
  int within3[NF] = {0};
  for (int q = 0; q < Q; q++) {
    /* interior points: the disc (r ~ 0.022 m) never reaches an edge */
    double x[3] = {0.15 + 0.7 * u01(21, (uint64_t)q), 0.15 + 0.7 * u01(22, (uint64_t)q), 0.0};
    double sigma = count_sigma(x, r0) / KNN; /* relative, ~2.4 % */
    for (int i = 0; i < NF; i++) {
      double out[UNB], r;
      int used = vr_photon_map_irradiance(m, x, UP, f[i].k, f[i].k ? 0.5 : r0, f[i].kc, out, &r);
      if (f[i].k) {
        assert_int_equal(used, KNN);
        assert_true(r < 0.05);
      } else {
        assert_true(used > 50 && used < 150);
        assert_true(r == r0);
      }
      /* the bins differ by exact factors of two: so must the estimates */
      assert_true(out[b1] == 2.0 * out[b0] && out[b2] == 0.5 * out[b0]);
      for (int b = 0; b < nb; b++)
        if (b != b0 && b != b1 && b != b2) assert_true(out[b] == 0.0);
      double e = out[b0] / PHI[0] - 1.0;
      sum[i] += e;
      sum2[i] += e * e;
      if (fabs(e) / sigma > worst[i]) worst[i] = fabs(e) / sigma;
      within3[i] += fabs(e) <= 0.03;
      if (i == 1) z2 += (e / sigma) * (e / sigma);
    }
  }
  for (int i = 0; i < NF; i++) {
    double mean = sum[i] / Q, sd = sqrt(sum2[i] / Q - mean * mean);
    double expect = f[i].k ? knn_expectation(f[i].k, f[i].kc) - 1.0 : 0.0;
    print_message("  %-24s mean %+.3f %% (expected %+.3f %%), rms spread %.2f %%, "
                  "worst %.1f sigma, %.0f %% of points within 3 %%\n",
                  f[i].name, 100 * mean, 100 * expect, 100 * sd, worst[i], 100.0 * within3[i] / Q);
    /* Means over Q points: within 3 % of Phi as asked, and within 0.3 % of
     * the expectation above (4 standard errors of a 2.5 % spread). */
    assert_near(mean, 0.0, 0.03);
    assert_near(mean, expect, 0.003);
    /* Points one by one: the spread is the stratification's count noise
     * (2.4 % rms at k = 100, computed by count_sigma), so no single point
     * can be held to 3 %; each stays within 5 of its own sigma. */
    assert_true(worst[i] < 5.0);
  }
  /* The fixed-radius box counts are exactly the jittered-grid counts: their
   * standardised errors must have unit variance (chi-square / Q). */
  print_message("  box, r fixed: mean z^2 = %.3f\n", z2 / Q);
  assert_true(z2 / Q > 0.85 && z2 / Q < 1.15);
  vr_photon_map_destroy(m);
}

static void uniform_field(void **state) {
  (void)state;
  uniform_field_of(false);
}

static void uniform_field_sparse(void **state) {
  (void)state;
  uniform_field_of(true);
}

/* --- (b) neighbourhoods against brute force ------------------------------ */

typedef struct photon_copy {
  double p[3], d[3], n[3];
  float pw[3];
} photon_copy;

/* Reads every photon back as stored; power[2] carries the photon's id. */
static photon_copy *read_back(const vr_photon_map *m, size_t n) {
  photon_copy *c = malloc(n * sizeof *c);
  assert_non_null(c);
  for (size_t i = 0; i < n; i++)
    assert_int_equal(vr_photon_map_get(m, i, c[i].p, c[i].d, c[i].n, c[i].pw), VR_OK);
  return c;
}

typedef struct brute {
  double g2, d2;
  uint64_t key;
  size_t index;
} brute;

static int brute_cmp(const void *a, const void *b) {
  const brute *x = a, *y = b;
  if (x->g2 != y->g2) return x->g2 < y->g2 ? -1 : 1;
  return x->key < y->key ? -1 : x->key > y->key;
}

/* Every photon in the disc of radius R at x (with the side rule), sorted by
 * disc distance then key: the reference for the tree's searches. */
static size_t brute_force(const photon_copy *c, size_t n, uint64_t (*key_of)(uint64_t),
                          const double x[3], const double nin[3], double R, brute *out) {
  double l = sqrt(nin[0] * nin[0] + nin[1] * nin[1] + nin[2] * nin[2]);
  double nn[3] = {nin[0] / l, nin[1] / l, nin[2] / l};
  size_t cnt = 0;
  for (size_t i = 0; i < n; i++) {
    double v[3] = {c[i].p[0] - x[0], c[i].p[1] - x[1], c[i].p[2] - x[2]};
    double d2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    double t = (v[0] * nn[0] + v[1] * nn[1] + v[2] * nn[2]) / VR_PHOTON_MAP_DISC;
    double g2 = fmax(d2, t * t);
    if (g2 > R * R) continue;
    if (!(c[i].d[0] * nn[0] + c[i].d[1] * nn[1] + c[i].d[2] * nn[2] < 0.0)) continue;
    out[cnt++] = (brute){g2, d2, key_of((uint64_t)c[i].pw[2]), i};
  }
  qsort(out, cnt, sizeof *out, brute_cmp);
  return cnt;
}

static uint64_t hashed_key(uint64_t id) { return mix64(id); }

/* Checks locate, the k-nearest estimates and the fixed-radius estimate at x
 * against brute force. */
static void check_query(const vr_photon_map *m, const photon_copy *c, size_t n, brute *bf,
                        const double x[3], const double nrm[3], int k, double R) {
  size_t cnt = brute_force(c, n, hashed_key, x, nrm, R, bf);
  size_t want = cnt < (size_t)k ? cnt : (size_t)k;
  vr_photon_hit *hits = malloc((size_t)k * sizeof *hits);
  double r;
  int got = vr_photon_map_locate(m, x, nrm, k, R, hits, &r);
  assert_int_equal(got, want);
  for (size_t j = 0; j < want; j++) {
    if (hits[j].index != bf[j].index)
      fail_msg("k = %d, R = %g: neighbour %zu is photon %zu, brute force says %zu", k, R, j,
               hits[j].index, bf[j].index);
    assert_near(hits[j].dist, sqrt(bf[j].d2), 1e-12);
  }
  double rr = want == (size_t)k ? sqrt(bf[k - 1].g2) : R;
  assert_near(r, rr, 1e-12 * rr);

  /* the estimates, box and cone, from the same neighbourhood */
  for (int f = 0; f < 2; f++) {
    double kc = f ? 1.1 : 0.0, out[3], r2;
    int used = vr_photon_map_irradiance(m, x, nrm, k, R, kc, out, &r2);
    if (rr == 0.0) {
      assert_int_equal(used, -1);
      continue;
    }
    assert_int_equal(used, want);
    assert_true(r2 == r);
    double s[2] = {0, 0};
    for (size_t j = 0; j < want; j++) {
      double w = kc > 0 ? 1.0 - sqrt(bf[j].d2) / (kc * rr) : 1.0;
      s[0] += w * c[bf[j].index].pw[0];
      s[1] += w * c[bf[j].index].pw[1];
    }
    double norm = (kc > 0 ? 1.0 - 2.0 / (3.0 * kc) : 1.0) * M_PI * rr * rr;
    assert_near(out[0] * norm, s[0], 1e-9 * (s[0] + 1));
    assert_near(out[1] * norm, s[1], 1e-9 * (s[1] + 1));
  }

  /* fixed radius: every photon of the disc of radius R, no more */
  double out[3], r3, s1 = 0.0;
  int used = vr_photon_map_irradiance(m, x, nrm, 0, R, 0.0, out, &r3);
  assert_int_equal(used, cnt);
  assert_true(r3 == R);
  for (size_t j = 0; j < cnt; j++) s1 += c[bf[j].index].pw[1];
  assert_near(out[0] * M_PI * R * R, (double)cnt, 1e-9 * (cnt + 1));
  assert_near(out[1] * M_PI * R * R, s1, 1e-9 * (s1 + 1));
  free(hits);
}

static void knn_matches_brute_force(void **state) {
  (void)state;
  enum { M = 6000 };
  vr_error err;
  vr_photon_map *m = vr_photon_map_create(3, 380, 780, &err);
  assert_non_null(m);
  for (uint64_t i = 0; i < M; i++) {
    /* a third on the plane z = 0, the rest in a 10 cm slab around it, so
     * the disc rule has work to do */
    double pos[3] = {u01(31, i), u01(32, i), i % 3 == 0 ? 0.0 : 0.1 * u01(33, i) - 0.05};
    double dir[3], nrm[3];
    unit_vector(34, i, dir);
    unit_vector(35, i, nrm);
    float p[3] = {1.0f, (float)u01(36, i), (float)i};
    assert_int_equal(vr_photon_map_store(m, hashed_key(i), pos, dir, nrm, p, &err), VR_OK);
  }
  assert_int_equal(vr_photon_map_build(m, &err), VR_OK);
  photon_copy *c = read_back(m, M);
  brute *bf = malloc(M * sizeof *bf);
  static const int ks[] = {1, 2, 7, 50, 100, 256, 257, 400};
  for (uint64_t q = 0; q < 700; q++) {
    double x[3] = {u01(41, q), u01(42, q), 0.04 * u01(43, q) - 0.02}, nrm[3];
    if (q % 2)
      unit_vector(44, q, nrm);
    else
      nrm[0] = 0, nrm[1] = 0, nrm[2] = q % 4 ? 1.0 : -3.0; /* any length */
    check_query(m, c, M, bf, x, nrm, ks[q % 8], 0.02 + 0.5 * u01(45, q));
  }
  free(bf);
  free(c);
  vr_photon_map_destroy(m);
}

/* Photons on a lattice, three to a site: distances tie exactly (the
 * coordinates are multiples of 1/8 and the bounding-box centre is exact),
 * and the key decides. */
static void ties_broken_by_key(void **state) {
  (void)state;
  vr_error err;
  vr_photon_map *m = vr_photon_map_create(3, 380, 780, &err);
  size_t n = 0;
  for (int j = 0; j <= 16; j++)
    for (int i = 0; i <= 16; i++)
      for (int copy = 0; copy < 3; copy++, n++) {
        double pos[3] = {i / 8.0, j / 8.0, 0.0};
        float p[3] = {1.0f, (float)copy, (float)n};
        assert_int_equal(vr_photon_map_store(m, hashed_key(n), pos, DOWN, UP, p, &err), VR_OK);
      }
  assert_int_equal(vr_photon_map_build(m, &err), VR_OK);
  photon_copy *c = read_back(m, n);
  for (size_t i = 0; i < n; i++) {
    size_t id = (size_t)c[i].pw[2];
    assert_true(c[i].p[0] == (double)(id / 3 % 17) / 8.0 && c[i].p[1] == (double)(id / 51) / 8.0);
  }
  brute *bf = malloc(n * sizeof *bf);
  for (uint64_t q = 0; q < 300; q++) {
    double x[3] = {(double)(q % 33) / 16.0, (double)(q * 7 % 33) / 16.0, 0.0};
    check_query(m, c, n, bf, x, UP, 1 + (int)(q % 40), q % 5 ? 0.6 : 0.25);
  }
  free(bf);
  free(c);
  vr_photon_map_destroy(m);
}

/* --- (c) which photons count --------------------------------------------- */

static void side_and_disc(void **state) {
  (void)state;
  vr_error err;
  vr_photon_map *m = vr_photon_map_create(2, 380, 780, &err);
  float top[2] = {1, 0}, bottom[2] = {0, 1};
  /* a thin sheet at z = 0 lit from both sides: photons coming down land on
   * its top face, photons going up on its bottom face */
  for (uint64_t i = 0; i < 400; i++) {
    double pos[3] = {u01(51, i), u01(52, i), 0.0};
    double up[3] = {0.3, -0.2, 1.0}, down[3] = {0.1, 0.5, -1.0}, nb[3] = {0, 0, -1};
    assert_int_equal(vr_photon_map_store(m, 2 * i, pos, down, UP, top, &err), VR_OK);
    assert_int_equal(vr_photon_map_store(m, 2 * i + 1, pos, up, nb, bottom, &err), VR_OK);
  }
  /* beside a query point at the origin, off the sheet: one photon just
   * inside the disc of radius 2 (|dz| = 0.19 <= 0.1 r), one just outside */
  double in[3] = {-1.5, -1.0, 0.19}, out_[3] = {-1.5, -1.0, 0.21};
  float third[2] = {4, 4};
  assert_int_equal(vr_photon_map_store(m, 5000, in, DOWN, UP, third, &err), VR_OK);
  assert_int_equal(vr_photon_map_store(m, 5001, out_, DOWN, UP, third, &err), VR_OK);
  assert_int_equal(vr_photon_map_build(m, &err), VR_OK);

  double x[3] = {0.5, 0.5, 0.0}, nb[3] = {0, 0, -1}, o[2], r;
  for (int k = 0; k <= 50; k += 50) {
    int n = vr_photon_map_irradiance(m, x, UP, k, k ? 2.0 : 0.3, 0.0, o, &r);
    assert_true(n > 0);
    assert_true(o[0] > 0 && o[1] == 0.0);
    n = vr_photon_map_irradiance(m, x, nb, k, k ? 2.0 : 0.3, 0.0, o, &r);
    assert_true(n > 0);
    assert_true(o[1] > 0 && o[0] == 0.0);
  }
  /* all 400 top photons and the one inside the disc, nothing else */
  double origin[3] = {0, 0, 0};
  assert_int_equal(vr_photon_map_irradiance(m, origin, UP, 0, 2.0, 0.0, o, &r), 401);
  assert_near(o[0] * M_PI * 4.0, 404.0, 1e-9);
  assert_near(o[1] * M_PI * 4.0, 4.0, 1e-9); /* the disc photon's second bin */
  vr_photon_map_destroy(m);
}

/* --- (d) order independence -------------------------------------------- */

enum { ORDER_M = 5000, ORDER_NB = 40 };

/* Photon i of the order test; keys repeat (pairs share one) and the last
 * ten photons duplicate earlier ones exactly.  With nb = 4 every bin has
 * power; with more, four wavelengths' worth land in bins that vary from
 * photon to photon (sometimes the same one twice), and one photon in nine
 * has only two. */
static void order_photon(uint64_t i, int nb, uint64_t *key, double pos[3], double dir[3],
                         double nrm[3], float *p) {
  uint64_t s = i >= ORDER_M - 10 ? i - 100 : i;
  *key = mix64(s / 2);
  pos[0] = u01(61, s);
  pos[1] = u01(62, s);
  pos[2] = s % 4 ? 0.0 : 0.02 * u01(63, s);
  if (s % 7 == 0) pos[0] = pos[1] = 0.5; /* coincident positions too */
  unit_vector(64, s, dir);
  unit_vector(65, s, nrm);
  if (nb == 4) {
    for (int b = 0; b < 4; b++) p[b] = (float)u01(66 + (uint64_t)b, s);
    return;
  }
  for (int b = 0; b < nb; b++) p[b] = 0.0f;
  for (uint64_t w = 0; w < (s % 9 ? 4u : 2u); w++)
    p[(s * 13 + w * (1 + s % 11)) % (uint64_t)nb] += (float)u01(66 + w, s);
}

typedef struct store_job {
  vr_photon_map *m;
  int phase; /* 0: even i upwards, 1: odd i downwards */
  int failures;
  int nb;
} store_job;

static void *store_thread(void *arg) {
  store_job *j = arg;
  for (int t = 0; t < ORDER_M / 2; t++) {
    uint64_t i = j->phase ? (uint64_t)(ORDER_M - 1 - 2 * t) : (uint64_t)(2 * t), key;
    double pos[3], dir[3], nrm[3];
    float p[ORDER_NB];
    order_photon(i, j->nb, &key, pos, dir, nrm, p);
    if (vr_photon_map_store(j->m, key, pos, dir, nrm, p, NULL) != VR_OK) j->failures++;
  }
  return NULL;
}

/* nb = 4: dense; nb = ORDER_NB: sparse with 4 pairs if sparse, else dense. */
static vr_photon_map *order_map(int how, int nb, bool sparse) {
  vr_error err;
  vr_photon_map *m = sparse ? vr_photon_map_create_sparse(nb, 380, 780, 4, &err)
                            : vr_photon_map_create(nb, 380, 780, &err);
  assert_non_null(m);
  if (how == 2) {
    pthread_t th[2];
    store_job jobs[2] = {{m, 0, 0, nb}, {m, 1, 0, nb}};
    for (int t = 0; t < 2; t++) assert_int_equal(pthread_create(&th[t], NULL, store_thread, &jobs[t]), 0);
    for (int t = 0; t < 2; t++) pthread_join(th[t], NULL);
    assert_int_equal(jobs[0].failures + jobs[1].failures, 0);
  } else {
    for (uint64_t t = 0; t < ORDER_M; t++) {
      /* how 0: in order; how 1: a permutation (3001 is prime to 5000) */
      uint64_t i = how == 0 ? t : t * 3001 % ORDER_M, key;
      double pos[3], dir[3], nrm[3];
      float p[ORDER_NB];
      order_photon(i, nb, &key, pos, dir, nrm, p);
      assert_int_equal(vr_photon_map_store(m, key, pos, dir, nrm, p, &err), VR_OK);
    }
  }
  assert_int_equal(vr_photon_map_build(m, &err), VR_OK);
  return m;
}

/* Maps 0-2 take the same photons in order, permuted and from two threads;
 * a sparse run adds map 3, dense, stored in order: all must agree bit for
 * bit, photon by photon and estimate by estimate. */
static void order_independent_of(int nb, bool sparse) {
  int nm = sparse ? 4 : 3;
  vr_photon_map *m[4] = {order_map(0, nb, sparse), order_map(1, nb, sparse),
                         order_map(2, nb, sparse), sparse ? order_map(0, nb, false) : NULL};
  if (sparse) /* the sparse maps are smaller (a check that they are sparse) */
    assert_true(vr_photon_map_bytes_per_photon(m[0]) < vr_photon_map_bytes_per_photon(m[3]));
  for (int a = 1; a < nm; a++) {
    assert_int_equal(vr_photon_map_count(m[a]), ORDER_M);
    for (size_t i = 0; i < ORDER_M; i++) {
      double p0[9], p1[9];
      float w0[ORDER_NB], w1[ORDER_NB];
      vr_photon_map_get(m[0], i, p0, p0 + 3, p0 + 6, w0);
      vr_photon_map_get(m[a], i, p1, p1 + 3, p1 + 6, w1);
      assert_memory_equal(p0, p1, sizeof p0);
      assert_memory_equal(w0, w1, (size_t)nb * sizeof(float));
    }
  }
  for (uint64_t q = 0; q < 400; q++) {
    double x[3] = {u01(71, q), u01(72, q), 0.0}, nrm[3] = {0, 0, 1};
    if (q % 10 == 0) x[0] = x[1] = 0.5;
    if (q % 3 == 0) unit_vector(73, q, nrm);
    int k = (int)(q % 60);
    double kc = q % 2 ? 1.0 : 0.0, R = 0.05 + 0.3 * u01(74, q);
    double out[4][ORDER_NB], r[4];
    int used[4];
    vr_photon_hit hits[4][64];
    int found[4];
    for (int a = 0; a < nm; a++) {
      used[a] = vr_photon_map_irradiance(m[a], x, nrm, k, R, kc, out[a], &r[a]);
      found[a] = vr_photon_map_locate(m[a], x, nrm, k ? k : 64, R, hits[a], NULL);
    }
    for (int a = 1; a < nm; a++) {
      assert_int_equal(used[a], used[0]);
      assert_memory_equal(out[a], out[0], (size_t)nb * sizeof(double));
      assert_memory_equal(&r[a], &r[0], sizeof r[0]);
      assert_int_equal(found[a], found[0]);
      for (int j = 0; j < found[0]; j++) {
        assert_int_equal(hits[a][j].index, hits[0][j].index);
        assert_memory_equal(&hits[a][j].dist, &hits[0][j].dist, sizeof(double));
      }
    }
  }
  for (int a = 0; a < nm; a++) vr_photon_map_destroy(m[a]);
}

static void store_order_independent(void **state) {
  (void)state;
  order_independent_of(4, false);
}

static void store_order_independent_sparse(void **state) {
  (void)state;
  order_independent_of(ORDER_NB, true);
}

/* --- (e) degenerate input ------------------------------------------------ */

static void empty_map(void **state) {
  (void)state;
  vr_error err;
  vr_photon_map *m = vr_photon_map_create(5, 380, 780, &err);
  double x[3] = {0, 0, 0}, out[5] = {1, 1, 1, 1, 1}, r;
  vr_photon_hit hits[4];
  /* not built yet: refused */
  assert_int_equal(vr_photon_map_irradiance(m, x, UP, 10, 1.0, 0.0, out, &r), -1);
  assert_true(out[0] == 0.0 && out[4] == 0.0);
  assert_int_equal(vr_photon_map_build(m, &err), VR_OK);
  assert_int_equal(vr_photon_map_count(m), 0);
  for (int k = 0; k <= 10; k += 10) {
    for (int b = 0; b < 5; b++) out[b] = 1.0;
    assert_int_equal(vr_photon_map_irradiance(m, x, UP, k, 1.0, 1.1, out, &r), 0);
    for (int b = 0; b < 5; b++) assert_true(out[b] == 0.0);
    assert_true(r == 1.0);
  }
  assert_int_equal(vr_photon_map_locate(m, x, UP, 4, 1.0, hits, &r), 0);
  assert_int_equal(vr_photon_map_get(m, 0, NULL, NULL, NULL, NULL), VR_E_ARG);
  vr_photon_map_destroy(m);
  vr_photon_map_destroy(NULL);
}

static void coincident_photons(void **state) {
  (void)state;
  vr_error err;
  vr_photon_map *m = vr_photon_map_create(1, 380, 780, &err);
  double at[3] = {1, 2, 3};
  float p = 0.5f;
  for (uint64_t i = 0; i < 20000; i++)
    assert_int_equal(vr_photon_map_store(m, i, at, DOWN, UP, &p, &err), VR_OK);
  assert_int_equal(vr_photon_map_build(m, &err), VR_OK);
  double o, r, beside[3] = {1, 2.05, 3};
  /* every photon at distance 0.05 in the plane: the 10 of smallest key */
  vr_photon_hit hits[10];
  assert_int_equal(vr_photon_map_locate(m, beside, UP, 10, 1.0, hits, &r), 10);
  assert_near(r, 0.05, 1e-12);
  for (int j = 0; j < 10; j++) {
    float w;
    double pos[3];
    vr_photon_map_get(m, hits[j].index, pos, NULL, NULL, &w);
    assert_true(pos[0] == 1 && pos[1] == 2 && pos[2] == 3 && w == 0.5f);
  }
  assert_int_equal(vr_photon_map_irradiance(m, beside, UP, 10, 1.0, 0.0, &o, &r), 10);
  assert_near(o, 10 * 0.5 / (M_PI * 0.05 * 0.05), 1e-9);
  /* at the point itself: fixed radius sees all, k-nearest has r = 0 */
  assert_int_equal(vr_photon_map_irradiance(m, at, UP, 0, 0.1, 0.0, &o, &r), 20000);
  assert_near(o, 20000 * 0.5 / (M_PI * 0.01), 1e-6);
  assert_int_equal(vr_photon_map_irradiance(m, at, UP, 10, 0.1, 0.0, &o, &r), -1);
  assert_true(o == 0.0);
  vr_photon_map_destroy(m);
}

static void bad_input(void **state) {
  (void)state;
  vr_error err;
  assert_null(vr_photon_map_create(0, 380, 780, &err));
  assert_int_equal(err.status, VR_E_ARG);
  assert_null(vr_photon_map_create(3, 780, 380, &err));
  assert_null(vr_photon_map_create(3, NAN, 380, &err));
  vr_photon_map *m = vr_photon_map_create(2, 400, 700, &err);
  double ok[3] = {0.5, 0.5, 0}, bad[3] = {0.5, NAN, 0}, inf[3] = {INFINITY, 0, 0},
         zero[3] = {0, 0, 0};
  float p[2] = {1, 1}, pn[2] = {1, NAN}, pneg[2] = {-1, 1};
  assert_int_equal(vr_photon_map_store(m, 1, bad, DOWN, UP, p, &err), VR_E_RANGE);
  assert_contains(err.message, "position");
  assert_int_equal(vr_photon_map_store(m, 1, inf, DOWN, UP, p, &err), VR_E_RANGE);
  assert_int_equal(vr_photon_map_store(m, 1, (double[3]){0, 0, 1e19}, DOWN, UP, p, &err),
                   VR_E_RANGE);
  assert_int_equal(vr_photon_map_store(m, 1, ok, bad, UP, p, &err), VR_E_RANGE);
  assert_int_equal(vr_photon_map_store(m, 1, ok, zero, UP, p, &err), VR_E_RANGE);
  assert_contains(err.message, "direction");
  assert_int_equal(vr_photon_map_store(m, 1, ok, DOWN, zero, p, &err), VR_E_RANGE);
  assert_contains(err.message, "normal");
  assert_int_equal(vr_photon_map_store(m, 1, ok, DOWN, UP, pn, &err), VR_E_RANGE);
  assert_contains(err.message, "power[1]");
  assert_int_equal(vr_photon_map_store(m, 1, ok, DOWN, UP, pneg, &err), VR_E_RANGE);
  assert_int_equal(vr_photon_map_store(m, 1, NULL, DOWN, UP, p, &err), VR_E_ARG);
  assert_int_equal(vr_photon_map_store(NULL, 1, ok, DOWN, UP, p, &err), VR_E_ARG);
  assert_int_equal(vr_photon_map_count(m), 0); /* nothing refused was kept */
  assert_int_equal(vr_photon_map_store(m, 1, ok, DOWN, UP, p, &err), VR_OK);
  assert_int_equal(vr_photon_map_build(m, &err), VR_OK);
  assert_int_equal(vr_photon_map_build(m, &err), VR_OK); /* twice is harmless */
  assert_int_equal(vr_photon_map_store(m, 2, ok, DOWN, UP, p, &err), VR_E_ARG);
  assert_contains(err.message, "already built");
  assert_int_equal(vr_photon_map_count(m), 1);

  double out[2], r;
  assert_int_equal(vr_photon_map_irradiance(m, ok, UP, -1, 1.0, 0.0, out, &r), -1);
  assert_int_equal(vr_photon_map_irradiance(m, ok, UP, 5, 0.0, 0.0, out, &r), -1);
  assert_int_equal(vr_photon_map_irradiance(m, ok, UP, 5, NAN, 0.0, out, &r), -1);
  assert_int_equal(vr_photon_map_irradiance(m, ok, UP, 5, INFINITY, 0.0, out, &r), -1);
  assert_int_equal(vr_photon_map_irradiance(m, ok, UP, 5, 1.0, 0.5, out, &r), -1);
  assert_int_equal(vr_photon_map_irradiance(m, ok, UP, 5, 1.0, NAN, out, &r), -1);
  assert_int_equal(vr_photon_map_irradiance(m, bad, UP, 5, 1.0, 0.0, out, &r), -1);
  assert_int_equal(vr_photon_map_irradiance(m, ok, zero, 5, 1.0, 0.0, out, &r), -1);
  assert_int_equal(vr_photon_map_irradiance(m, ok, UP, 5, 1.0, 0.0, NULL, &r), -1);
  assert_int_equal(vr_photon_map_irradiance(m, ok, UP, 5, 1.0, -1.0, out, NULL), 1);
  assert_int_equal(vr_photon_map_locate(m, ok, UP, 0, 1.0, (vr_photon_hit[1]){{0, 0}}, &r), -1);

  /* bins: 20 nm wide over 400-700 nm here would be 15; this map has 2 */
  assert_int_equal(vr_photon_map_bin(m, 400), 0);
  assert_int_equal(vr_photon_map_bin(m, 549.999), 0);
  assert_int_equal(vr_photon_map_bin(m, 550), 1);
  assert_int_equal(vr_photon_map_bin(m, 700), 1);
  assert_int_equal(vr_photon_map_bin(m, 399.9), -1);
  assert_int_equal(vr_photon_map_bin(m, 700.1), -1);
  assert_int_equal(vr_photon_map_bin(m, NAN), -1);
  double lo, hi;
  assert_true(vr_photon_map_bin_range(m, 1, &lo, &hi));
  assert_true(lo == 550 && hi == 700);
  assert_false(vr_photon_map_bin_range(m, 2, &lo, &hi));
  assert_int_equal(vr_photon_map_nbins(m), 2);
  assert_int_equal(vr_photon_map_bytes_per_photon(m), 36 + 4 * 2);
  vr_photon_map_destroy(m);
}

/* What the map gives back: positions to float resolution of the scene's
 * extent, directions to the octahedral code's resolution. */
static void stored_precision(void **state) {
  (void)state;
  vr_error err;
  vr_photon_map *m = vr_photon_map_create(1, 380, 780, &err);
  enum { M = 20000 };
  /* a 10 m room far from the origin: resolution follows the extent */
  const double base[3] = {5.0e5, -3.0e5, 120.0};
  for (uint64_t i = 0; i < M; i++) {
    double pos[3] = {base[0] + 10 * u01(81, i), base[1] + 10 * u01(82, i), base[2] + 3 * u01(83, i)};
    double dir[3], nrm[3];
    unit_vector(84, i, dir);
    unit_vector(85, i, nrm);
    float p = (float)i;
    assert_int_equal(vr_photon_map_store(m, i, pos, dir, nrm, &p, &err), VR_OK);
  }
  assert_int_equal(vr_photon_map_build(m, &err), VR_OK);
  double worst_pos = 0.0, worst_dir = 0.0;
  for (size_t j = 0; j < M; j++) {
    double pos[3], dir[3], nrm[3];
    float p;
    vr_photon_map_get(m, j, pos, dir, nrm, &p);
    uint64_t i = (uint64_t)p;
    double want[3] = {base[0] + 10 * u01(81, i), base[1] + 10 * u01(82, i), base[2] + 3 * u01(83, i)};
    double wd[3], wn[3];
    unit_vector(84, i, wd);
    unit_vector(85, i, wn);
    for (int a = 0; a < 3; a++) worst_pos = fmax(worst_pos, fabs(pos[a] - want[a]));
    double cd = dir[0] * wd[0] + dir[1] * wd[1] + dir[2] * wd[2];
    double cn = nrm[0] * wn[0] + nrm[1] * wn[1] + nrm[2] * wn[2];
    worst_dir = fmax(worst_dir, acos(fmin(1.0, fmin(cd, cn))));
  }
  print_message("  worst position error %.2g m, worst direction error %.2g deg\n", worst_pos,
                worst_dir * 180 / M_PI);
  assert_true(worst_pos <= 5.0 * 0x1.0p-24); /* half-extent 5 m, float ulp/2 */
  assert_true(worst_dir * 180 / M_PI < 0.004);
  vr_photon_map_destroy(m);
}

/* --- (f) sparse maps ---------------------------------------------------- */

/* Photon i of the sparse comparison, over nb bins of 360-830 nm: four hero
 * wavelengths 117.5 nm apart (one in seven photons loses one, one in
 * thirteen has all four in one bin), with key pairs as above.  Photons
 * i >= M form a cluster at one point, all of one key, direction and normal,
 * told apart by their power alone (values whose bytes order differently
 * from their magnitudes, a subnormal among them), so the order of equal
 * keys by content is put to the test. */
enum { SD_M = 6000, SD_CLUSTER = 24 };
static const double CLUSTER_AT[3] = {0.5, 0.5, 0.0};

static void sd_photon(const vr_photon_map *dense, int nb, uint64_t i, uint64_t *key,
                      double pos[3], double dir[3], double nrm[3], float *p) {
  for (int b = 0; b < nb; b++) p[b] = 0.0f;
  if (i >= SD_M) {
    static const float vals[5] = {1.0f, 0.5f, 1.5f, 3.0f, 1e-40f};
    uint64_t t = i - SD_M;
    *key = hashed_key(1000000007u);
    for (int a = 0; a < 3; a++) pos[a] = CLUSTER_AT[a], dir[a] = DOWN[a], nrm[a] = UP[a];
    for (uint64_t j = 0; j < 1 + t % 3; j++) p[(t * 5 + j * 3) % 7] = vals[(t + j) % 5];
    return;
  }
  *key = hashed_key(i / 2);
  pos[0] = u01(31, i);
  pos[1] = u01(32, i);
  pos[2] = i % 3 == 0 ? 0.0 : 0.1 * u01(33, i) - 0.05;
  unit_vector(34, i, dir);
  unit_vector(35, i, nrm);
  double h = 470.0 * u01(37, i);
  for (uint64_t w = 0; w < 4; w++) {
    if (i % 7 == 0 && w == 3) continue;
    double wl = 360.0 + fmod(h + (i % 13 ? 117.5 * (double)w : 0.0), 470.0);
    int b = vr_photon_map_bin(dense, wl);
    assert_true(b >= 0 && b < nb);
    p[b] += (float)(0.25 + u01(38 + w, i));
  }
}

static void sparse_vs_dense(int nb, int nz) {
  vr_error err;
  vr_photon_map *d = vr_photon_map_create(nb, 360, 830, &err);
  vr_photon_map *s = vr_photon_map_create_sparse(nb, 360, 830, nz, &err);
  assert_non_null(d);
  assert_non_null(s);
  assert_true(vr_photon_map_bytes_per_photon(s) < vr_photon_map_bytes_per_photon(d));
  enum { N = SD_M + SD_CLUSTER };
  float *p = malloc((size_t)nb * sizeof *p), *p2 = malloc((size_t)nb * sizeof *p2);
  double pos[3], dir[3], nrm[3];
  uint64_t key;
  /* the dense map in order, the sparse one the cluster first and backwards,
   * then a permutation (3001 is prime to 6000) */
  for (uint64_t i = 0; i < N; i++) {
    sd_photon(d, nb, i, &key, pos, dir, nrm, p);
    assert_int_equal(vr_photon_map_store(d, key, pos, dir, nrm, p, &err), VR_OK);
  }
  for (uint64_t t = 0; t < N; t++) {
    uint64_t i = t < SD_CLUSTER ? N - 1 - t : (t - SD_CLUSTER) * 3001 % SD_M;
    sd_photon(d, nb, i, &key, pos, dir, nrm, p);
    assert_int_equal(vr_photon_map_store(s, key, pos, dir, nrm, p, &err), VR_OK);
  }
  assert_int_equal(vr_photon_map_build(d, &err), VR_OK);
  assert_int_equal(vr_photon_map_build(s, &err), VR_OK);
  assert_int_equal(vr_photon_map_count(s), N);

  /* the same photons in the same places */
  for (size_t i = 0; i < N; i++) {
    double a[9], b[9];
    assert_int_equal(vr_photon_map_get(d, i, a, a + 3, a + 6, p), VR_OK);
    assert_int_equal(vr_photon_map_get(s, i, b, b + 3, b + 6, p2), VR_OK);
    assert_memory_equal(a, b, sizeof a);
    if (memcmp(p, p2, (size_t)nb * sizeof *p) != 0)
      fail_msg("nbins %d, max_nonzero %d: photon %zu has other powers in the sparse map", nb, nz,
               i);
  }

  /* the same estimates and neighbourhoods, bit for bit */
  static const int ks[] = {0, 1, 7, 50, 0, 300};
  static const double kcs[] = {0.0, 1.0, 1.1};
  double *od = malloc((size_t)nb * sizeof *od), *os = malloc((size_t)nb * sizeof *os);
  vr_photon_hit hd[300], hs[300];
  long total = 0;
  for (uint64_t q = 0; q < 600; q++) {
    double x[3] = {u01(41, q), u01(42, q), 0.04 * u01(43, q) - 0.02}, n[3] = {0, 0, 1};
    if (q % 10 == 0) /* at the cluster, or just beside it */
      for (int a = 0; a < 3; a++) x[a] = CLUSTER_AT[a] + (q % 20 ? 0.003 * (a == 0) : 0.0);
    if (q % 2) unit_vector(44, q, n);
    else if (q % 4 == 0) n[2] = -1.0;
    int k = ks[q % 6];
    double kc = kcs[q % 3], R = 0.02 + 0.3 * u01(45, q), rd, rs;
    int ud = vr_photon_map_irradiance(d, x, n, k, R, kc, od, &rd);
    int us = vr_photon_map_irradiance(s, x, n, k, R, kc, os, &rs);
    assert_int_equal(us, ud);
    if (memcmp(od, os, (size_t)nb * sizeof *od) != 0 || memcmp(&rd, &rs, sizeof rd) != 0)
      fail_msg("nbins %d, max_nonzero %d, query %d (k %d, kc %g): estimates differ", nb, nz,
               (int)q, k, kc);
    total += ud > 0 ? ud : 0;
    int kl = k ? k : 50;
    int fd = vr_photon_map_locate(d, x, n, kl, R, hd, &rd);
    int fs = vr_photon_map_locate(s, x, n, kl, R, hs, &rs);
    assert_int_equal(fs, fd);
    assert_memory_equal(&rd, &rs, sizeof rd);
    for (int j = 0; j < fd; j++) {
      assert_int_equal(hs[j].index, hd[j].index);
      assert_memory_equal(&hs[j].dist, &hd[j].dist, sizeof(double));
    }
  }
  print_message("  nbins %d, max_nonzero %d: %zu vs %zu bytes a photon, %.1f photons a query\n",
                nb, nz, vr_photon_map_bytes_per_photon(s), vr_photon_map_bytes_per_photon(d),
                total / 600.0);
  assert_true(total > 600 * 20); /* the queries do see photons */
  free(od);
  free(os);
  free(p);
  free(p2);
  vr_photon_map_destroy(d);
  vr_photon_map_destroy(s);
}

static void sparse_matches_dense(void **state) {
  (void)state;
  sparse_vs_dense(47, 4); /* bin indices of one byte */
  sparse_vs_dense(47, 8); /* slots left unused */
  sparse_vs_dense(300, 4); /* bin indices of two bytes */
}

static void sparse_refusal(void **state) {
  (void)state;
  vr_error err;
  double at[3] = {0.5, 0.5, 0.0};
  assert_null(vr_photon_map_create_sparse(30, 400, 700, 0, &err));
  assert_int_equal(err.status, VR_E_ARG);
  assert_contains(err.message, "max_nonzero");
  assert_null(vr_photon_map_create_sparse(30, 400, 700, -3, &err));
  assert_null(vr_photon_map_create_sparse(0, 400, 700, 4, &err));
  assert_null(vr_photon_map_create_sparse(30, 700, 400, 4, &err));

  vr_photon_map *m = vr_photon_map_create_sparse(30, 400, 700, 4, &err);
  assert_non_null(m);
  float five[30] = {0}, four[30] = {0}, negzero[30] = {0}, none[30] = {0}, nan_[30] = {0};
  for (int j = 0; j < 5; j++) five[3 + 6 * j] = 1.0f + (float)j;
  memcpy(four, five, sizeof four);
  four[27] = 0.0f;
  memcpy(negzero, five, sizeof negzero);
  negzero[9] = -0.0f; /* a zero: four non-zero bins remain */
  for (int j = 0; j < 6; j++) nan_[j] = 1.0f;
  nan_[20] = NAN;
  assert_int_equal(vr_photon_map_store(m, 1, at, DOWN, UP, five, &err), VR_E_RANGE);
  assert_contains(err.message, "5 non-zero");
  assert_contains(err.message, "at most 4");
  assert_int_equal(vr_photon_map_count(m), 0); /* not kept */
  assert_int_equal(vr_photon_map_store(m, 1, at, DOWN, UP, nan_, &err), VR_E_RANGE);
  assert_contains(err.message, "power[20]");
  assert_int_equal(vr_photon_map_store(m, 3, at, DOWN, UP, four, &err), VR_OK);
  assert_int_equal(vr_photon_map_store(m, 2, at, DOWN, UP, negzero, &err), VR_OK);
  assert_int_equal(vr_photon_map_store(m, 4, at, DOWN, UP, none, &err), VR_OK);
  assert_int_equal(vr_photon_map_count(m), 3);
  assert_int_equal(vr_photon_map_build(m, &err), VR_OK);
  float got[30];
  negzero[9] = 0.0f; /* given back as +0 */
  assert_int_equal(vr_photon_map_get(m, 0, NULL, NULL, NULL, got), VR_OK);
  assert_memory_equal(got, negzero, sizeof got);
  assert_int_equal(vr_photon_map_get(m, 1, NULL, NULL, NULL, got), VR_OK);
  assert_memory_equal(got, four, sizeof got);
  assert_int_equal(vr_photon_map_get(m, 2, NULL, NULL, NULL, got), VR_OK);
  assert_memory_equal(got, none, sizeof got);
  /* fixed radius, box: the three photons' powers over pi r^2, exactly
   * zero in the bins none of them has */
  double out[30], r;
  assert_int_equal(vr_photon_map_irradiance(m, at, UP, 0, 0.1, 0.0, out, &r), 3);
  for (int b = 0; b < 30; b++)
    assert_near(out[b] * M_PI * 0.01, (double)four[b] + (double)negzero[b], 1e-12);
  assert_true(r == 0.1);
  assert_true(out[0] == 0.0 && out[4] == 0.0 && out[29] == 0.0 && out[9] > 0.0);
  vr_photon_map_destroy(m);

  /* a dense map takes any number */
  m = vr_photon_map_create(30, 400, 700, &err);
  assert_int_equal(vr_photon_map_store(m, 1, at, DOWN, UP, five, &err), VR_OK);
  vr_photon_map_destroy(m);

  /* max_nonzero above nbins is nbins: dense storage, nothing refused */
  m = vr_photon_map_create_sparse(3, 400, 700, 10, &err);
  assert_non_null(m);
  assert_int_equal(vr_photon_map_bytes_per_photon(m), 36 + 4 * 3);
  assert_int_equal(vr_photon_map_store(m, 1, at, DOWN, UP, (float[3]){1, 2, 3}, &err), VR_OK);
  vr_photon_map_destroy(m);
  /* 7 pairs would cost more than 8 bins: stored densely, yet the bound holds */
  m = vr_photon_map_create_sparse(8, 400, 700, 7, &err);
  assert_int_equal(vr_photon_map_bytes_per_photon(m), 36 + 4 * 8);
  float eight[8] = {1, 1, 1, 1, 1, 1, 1, 1};
  assert_int_equal(vr_photon_map_store(m, 1, at, DOWN, UP, eight, &err), VR_E_RANGE);
  assert_contains(err.message, "8 non-zero");
  eight[5] = 0.0f;
  assert_int_equal(vr_photon_map_store(m, 1, at, DOWN, UP, eight, &err), VR_OK);
  assert_int_equal(vr_photon_map_count(m), 1);
  vr_photon_map_destroy(m);
}

/* What a photon costs: 36 bytes of position, key, direction, normal and surface, then
 * 4 nbins dense or max_nonzero (4 + 1) sparse (4 + 2 beyond 256 bins). */
static void sparse_bytes(void **state) {
  (void)state;
  static const struct {
    int nb, nz;
    size_t dense, sparse;
  } c[] = {{30, 4, 156, 56}, {47, 4, 224, 56},  {30, 8, 156, 76},
           {47, 8, 224, 76}, {300, 4, 1236, 60}, {300, 8, 1236, 84}};
  vr_error err;
  for (size_t i = 0; i < sizeof c / sizeof c[0]; i++) {
    vr_photon_map *d = vr_photon_map_create(c[i].nb, 360, 830, &err);
    vr_photon_map *s = vr_photon_map_create_sparse(c[i].nb, 360, 830, c[i].nz, &err);
    print_message("  nbins %3d, max_nonzero %d: dense %4zu, sparse %2zu bytes a photon\n",
                  c[i].nb, c[i].nz, vr_photon_map_bytes_per_photon(d),
                  vr_photon_map_bytes_per_photon(s));
    assert_int_equal(vr_photon_map_bytes_per_photon(d), c[i].dense);
    assert_int_equal(vr_photon_map_bytes_per_photon(s), c[i].sparse);
    assert_int_equal(vr_photon_map_build(s, &err), VR_OK); /* the same once built */
    assert_int_equal(vr_photon_map_bytes_per_photon(s), c[i].sparse);
    vr_photon_map_destroy(d);
    vr_photon_map_destroy(s);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(uniform_field),         cmocka_unit_test(knn_matches_brute_force),
      cmocka_unit_test(ties_broken_by_key),    cmocka_unit_test(side_and_disc),
      cmocka_unit_test(store_order_independent), cmocka_unit_test(empty_map),
      cmocka_unit_test(coincident_photons),    cmocka_unit_test(bad_input),
      cmocka_unit_test(stored_precision),      cmocka_unit_test(uniform_field_sparse),
      cmocka_unit_test(sparse_matches_dense),  cmocka_unit_test(sparse_refusal),
      cmocka_unit_test(sparse_bytes),          cmocka_unit_test(store_order_independent_sparse),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
