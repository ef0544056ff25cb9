/* Tests of the least-squares layer (fit/src/lsq.cpp): NIST StRD nonlinear
 * regression problems solved from both certified starts with analytic and
 * finite-difference Jacobians, checked against NIST's certified parameters
 * and standard deviations; then bounds, fixed parameters, a robust loss,
 * a model with a restricted domain, a rank-deficient problem and bad
 * arguments. */
#include "vr_test.h"

#include "vr/lsq.h"

/* ---- NIST StRD problems -------------------------------------------------
 * Data, starts, certified values and certified standard deviations copied
 * from the NIST Statistical Reference Datasets, nonlinear regression:
 *   https://www.itl.nist.gov/div898/strd/nls/data/LINKS/DATA/Misra1a.dat
 *   https://www.itl.nist.gov/div898/strd/nls/data/LINKS/DATA/Thurber.dat
 *   https://www.itl.nist.gov/div898/strd/nls/data/LINKS/DATA/MGH09.dat
 * NIST's "Standard Deviation" column is sqrt(diag((J^T J)^-1) * RSS/(m-n)),
 * which is vr_lsq_covariance with scale_by_reduced_chi2. */

typedef struct nist_problem {
  const char *name;
  size_t n, m;
  const double *x, *y;
  /* f_i = model(x_i) - y_i; J row-major when jac is not NULL. */
  void (*model)(const double *b, double x, double *value, double *grad);
  double start1[8], start2[8], certified[8], sd[8];
  double rss;
} nist_problem;

/* Misra1a: y = b1*(1-exp[-b2*x]), lower difficulty. */
static const double misra1a_x[14] = {77.6,  114.9, 141.1, 190.8, 239.9, 289.0, 332.8,
                                     378.4, 434.8, 477.3, 536.8, 593.1, 689.1, 760.0};
static const double misra1a_y[14] = {10.07, 14.73, 17.94, 23.93, 29.61, 35.18, 40.02,
                                     44.82, 50.76, 55.05, 61.01, 66.40, 75.47, 81.78};

static void misra1a_model(const double *b, double x, double *v, double *g) {
  double e = exp(-b[1] * x);
  *v = b[0] * (1 - e);
  if (g) {
    g[0] = 1 - e;
    g[1] = b[0] * x * e;
  }
}

static const nist_problem misra1a = {
    "Misra1a", 2, 14, misra1a_x, misra1a_y, misra1a_model,
    {500, 0.0001}, {250, 0.0005},
    {2.3894212918E+02, 5.5015643181E-04},
    {2.7070075241E+00, 7.2668688436E-06},
    1.2455138894E-01};

/* Thurber: y = (b1 + b2 x + b3 x^2 + b4 x^3) / (1 + b5 x + b6 x^2 + b7 x^3),
 * higher difficulty. */
static const double thurber_x[37] = {
    -3.067, -2.981, -2.921, -2.912, -2.840, -2.797, -2.702, -2.699, -2.633, -2.481,
    -2.363, -2.322, -1.501, -1.460, -1.274, -1.212, -1.100, -1.046, -0.915, -0.714,
    -0.566, -0.545, -0.400, -0.309, -0.109, -0.103, 0.010,  0.119,  0.377,  0.790,
    0.963,  1.006,  1.115,  1.572,  1.841,  2.047,  2.200};
static const double thurber_y[37] = {
    80.574,   84.248,   87.264,   87.195,   89.076,   89.608,   89.868,   90.101,
    92.405,   95.854,   100.696,  101.060,  401.672,  390.724,  567.534,  635.316,
    733.054,  759.087,  894.206,  990.785,  1090.109, 1080.914, 1122.643, 1178.351,
    1260.531, 1273.514, 1288.339, 1327.543, 1353.863, 1414.509, 1425.208, 1421.384,
    1442.962, 1464.350, 1468.705, 1447.894, 1457.628};

static void thurber_model(const double *b, double x, double *v, double *g) {
  double x2 = x * x, x3 = x2 * x;
  double num = b[0] + b[1] * x + b[2] * x2 + b[3] * x3;
  double den = 1 + b[4] * x + b[5] * x2 + b[6] * x3;
  *v = num / den;
  if (g) {
    g[0] = 1 / den;
    g[1] = x / den;
    g[2] = x2 / den;
    g[3] = x3 / den;
    g[4] = -num * x / (den * den);
    g[5] = -num * x2 / (den * den);
    g[6] = -num * x3 / (den * den);
  }
}

static const nist_problem thurber = {
    "Thurber", 7, 37, thurber_x, thurber_y, thurber_model,
    {1000, 1000, 400, 40, 0.7, 0.3, 0.03},
    {1300, 1500, 500, 75, 1, 0.4, 0.05},
    {1.2881396800E+03, 1.4910792535E+03, 5.8323836877E+02, 7.5416644291E+01,
     9.6629502864E-01, 3.9797285797E-01, 4.9727297349E-02},
    {4.6647963344E+00, 3.9571156086E+01, 2.8698696102E+01, 5.5675370270E+00,
     3.1333340687E-02, 1.4984928198E-02, 6.5842344623E-03},
    5.6427082397E+03};

/* MGH09 (Kowalik and Osborne): y = b1 (x^2 + x b2) / (x^2 + x b3 + b4),
 * higher difficulty. */
static const double mgh09_x[11] = {4.0,   2.0,   1.0,    0.5,    0.25,  0.167,
                                   0.125, 0.1,   0.0833, 0.0714, 0.0625};
static const double mgh09_y[11] = {0.1957, 0.1947, 0.1735, 0.1600, 0.0844, 0.0627,
                                   0.0456, 0.0342, 0.0323, 0.0235, 0.0246};

static void mgh09_model(const double *b, double x, double *v, double *g) {
  double num = x * x + x * b[1];
  double den = x * x + x * b[2] + b[3];
  *v = b[0] * num / den;
  if (g) {
    g[0] = num / den;
    g[1] = b[0] * x / den;
    g[2] = -b[0] * num * x / (den * den);
    g[3] = -b[0] * num / (den * den);
  }
}

static const nist_problem mgh09 = {
    "MGH09", 4, 11, mgh09_x, mgh09_y, mgh09_model,
    {25, 39, 41.5, 39}, {0.25, 0.39, 0.415, 0.39},
    {1.9280693458E-01, 1.9128232873E-01, 1.2305650693E-01, 1.3606233068E-01},
    {1.1435312227E-02, 1.9633220911E-01, 8.0842031232E-02, 9.0025542308E-02},
    3.0750560385E-04};

static int nist_residuals(const double *b, double *f, double *jac, void *user) {
  const nist_problem *p = user;
  for (size_t i = 0; i < p->m; ++i) {
    double v;
    p->model(b, p->x[i], &v, jac ? jac + i * p->n : NULL);
    f[i] = v - p->y[i];
  }
  return 0;
}

/* Certified parameters to 6 significant digits (relative 5e-7), certified
 * standard deviations to 4 (relative 5e-5), and the certified residual sum
 * of squares to 9. */
static void run_nist_mode(const nist_problem *p, int start, bool analytic, bool forward) {
  vr_error err = {0};
  vr_lsq *lsq = vr_lsq_create(p->n, p->m, nist_residuals, (void *)p, analytic, &err);
  assert_non_null(lsq);
  if (forward) {
    assert_int_equal(vr_lsq_set_forward_differences(lsq, true, &err), VR_OK);
    for (size_t j = 0; j < p->n; ++j) assert_int_equal(vr_lsq_set_step(lsq, j, 1e-8, &err), VR_OK);
  }
  double b[8], cov[64];
  memcpy(b, start == 1 ? p->start1 : p->start2, p->n * sizeof(double));
  vr_lsq_summary s;
  /* NIST certifies the minimum itself, so the cost has to settle to
   * rounding: the default 1e-12 stops where the parameters are still off
   * by ~1e-6 of their standard deviation (fine for a measurement, short
   * of 6 digits on MGH09). */
  vr_lsq_options o = vr_lsq_default_options();
  o.function_tolerance = 1e-15;
  vr_status st = vr_lsq_solve(lsq, b, &o, &s, &err);
  if (st != VR_OK) fail_msg("%s start %d: %s", p->name, start, err.message);
  if (s.termination != VR_LSQ_CONVERGED)
    fail_msg("%s start %d (%s Jacobian): did not converge: %s", p->name, start,
             analytic ? "analytic" : "numeric", s.message);
  double digits = 99;
  for (size_t j = 0; j < p->n; ++j)
    digits = fmin(digits, -log10(fabs(b[j] / p->certified[j] - 1) + 1e-99));
  print_message("%s start %d, %s Jacobian: %d iterations, %d evaluations, %.1f digits\n",
                p->name, start, analytic ? "analytic" : "numeric", s.iterations,
                s.residual_evaluations, digits);
  for (size_t j = 0; j < p->n; ++j) assert_rel(b[j], p->certified[j], 5e-7);
  assert_rel(s.chi2, p->rss, 1e-9);
  assert_int_equal(s.free_parameters, p->n);

  assert_int_equal(vr_lsq_covariance(lsq, b, true, cov, &err), VR_OK);
  double sd_digits = 99;
  for (size_t j = 0; j < p->n; ++j)
    sd_digits = fmin(sd_digits, -log10(fabs(sqrt(cov[j * p->n + j]) / p->sd[j] - 1) + 1e-99));
  print_message("  standard deviations: %.1f digits\n", sd_digits);
  for (size_t j = 0; j < p->n; ++j) assert_rel(sqrt(cov[j * p->n + j]), p->sd[j], 5e-5);
  vr_lsq_destroy(lsq);
}

static void run_nist(const nist_problem *p, int start, bool analytic) {
  run_nist_mode(p, start, analytic, false);
}

/* Forward differences (the ellipsometry fits' choice) reach the same
 * certified minimum; only the path there is cheaper. */
static void test_forward_differences(void **state) {
  (void)state;
  run_nist_mode(&misra1a, 1, false, true);
  run_nist_mode(&misra1a, 2, false, true);
  run_nist_mode(&thurber, 2, false, true);
}

static void test_misra1a_analytic(void **state) {
  (void)state;
  run_nist(&misra1a, 1, true);
  run_nist(&misra1a, 2, true);
}

static void test_misra1a_numeric(void **state) {
  (void)state;
  run_nist(&misra1a, 1, false);
  run_nist(&misra1a, 2, false);
}

static void test_thurber_analytic(void **state) {
  (void)state;
  run_nist(&thurber, 1, true);
  run_nist(&thurber, 2, true);
}

static void test_thurber_numeric(void **state) {
  (void)state;
  run_nist(&thurber, 1, false);
  run_nist(&thurber, 2, false);
}

static void test_mgh09_analytic(void **state) {
  (void)state;
  run_nist(&mgh09, 1, true);
  run_nist(&mgh09, 2, true);
}

static void test_mgh09_numeric(void **state) {
  (void)state;
  run_nist(&mgh09, 1, false);
  run_nist(&mgh09, 2, false);
}

/* The iteration limit is not an error: the best point so far comes back. */
static void test_iteration_limit(void **state) {
  (void)state;
  vr_error err = {0};
  vr_lsq *lsq = vr_lsq_create(thurber.n, thurber.m, nist_residuals, (void *)&thurber, true, &err);
  double b[7];
  memcpy(b, thurber.start1, sizeof b);
  vr_lsq_options o = vr_lsq_default_options();
  o.max_iterations = 5;
  vr_lsq_summary s;
  assert_int_equal(vr_lsq_solve(lsq, b, &o, &s, &err), VR_OK);
  assert_int_equal(s.termination, VR_LSQ_NO_CONVERGENCE);
  assert_int_equal(s.iterations, 5);
  assert_true(s.final_cost < s.initial_cost);
  assert_true(s.message[0] != '\0');
  assert_true(memcmp(b, thurber.start1, sizeof b) != 0);
  vr_lsq_destroy(lsq);
}

/* Ceres' threads only assemble and factor the linear systems: the answer
 * may move by rounding (sums in another order), not more.  Asking for more
 * threads than the machine has is not an error. */
static void test_threads(void **state) {
  (void)state;
  vr_error err = {0};
  vr_lsq *lsq = vr_lsq_create(thurber.n, thurber.m, nist_residuals, (void *)&thurber, false, &err);
  double b1[7], b4[7];
  memcpy(b1, thurber.start2, sizeof b1);
  memcpy(b4, thurber.start2, sizeof b4);
  vr_lsq_options o = vr_lsq_default_options();
  vr_lsq_summary s;
  assert_int_equal(vr_lsq_solve(lsq, b1, &o, &s, &err), VR_OK);
  o.num_threads = 64;
  assert_int_equal(vr_lsq_solve(lsq, b4, &o, &s, &err), VR_OK);
  for (size_t j = 0; j < 7; ++j) assert_rel(b4[j], b1[j], 1e-8);
  assert_true(s.seconds >= 0 && s.seconds < 60);
  vr_lsq_destroy(lsq);
}

/* ---- bounds -------------------------------------------------------------
 * Misra1a with b1 <= 200, well below the certified 238.9: the fit must end
 * exactly on the bound.  The callback refuses any point outside the bounds,
 * so the finite differences must also stay inside (one-sided at the
 * bound). */
typedef struct bounded {
  double upper_b1;
  int outside_calls;
} bounded;

static int bounded_residuals(const double *b, double *f, double *jac, void *user) {
  bounded *u = user;
  if (b[0] > u->upper_b1) {
    u->outside_calls++;
    return 1;
  }
  return nist_residuals(b, f, jac, (void *)&misra1a);
}

static void test_bounds(void **state) {
  (void)state;
  for (int analytic = 0; analytic <= 1; ++analytic) {
    bounded u = {200, 0};
    vr_error err = {0};
    vr_lsq *lsq = vr_lsq_create(2, 14, bounded_residuals, &u, analytic, &err);
    assert_int_equal(vr_lsq_set_bounds(lsq, 0, 0, 200, &err), VR_OK);
    assert_int_equal(vr_lsq_set_bounds(lsq, 1, 0, INFINITY, &err), VR_OK);
    double b[2] = {150, 0.0005};
    vr_lsq_summary s;
    assert_int_equal(vr_lsq_solve(lsq, b, NULL, &s, &err), VR_OK);
    assert_int_equal(s.termination, VR_LSQ_CONVERGED);
    assert_true(b[0] == 200);
    assert_true(b[1] > 0);
    assert_int_equal(u.outside_calls, 0);
    /* With b1 pinned by the bound, b2 is the 1-D least-squares optimum:
     * the residual gradient along b2 vanishes. */
    double grad = 0;
    for (size_t i = 0; i < 14; ++i) {
      double v, g[2];
      misra1a_model(b, misra1a_x[i], &v, g);
      grad += (v - misra1a_y[i]) * g[1];
    }
    double scale = 0;
    for (size_t i = 0; i < 14; ++i) scale += misra1a_y[i] * 200 * misra1a_x[i];
    assert_contains(s.message, "held on its bound: parameter 0");
    assert_true(fabs(grad) < 1e-8 * scale);
    /* Covariance at the bound: the differences must be one-sided. */
    double cov[4];
    assert_int_equal(vr_lsq_covariance(lsq, b, true, cov, &err), VR_OK);
    assert_int_equal(u.outside_calls, 0);
    vr_lsq_destroy(lsq);
  }
}

/* ---- fixed parameters ---------------------------------------------------
 * Misra1a with b2 held: b1 enters linearly, so its least-squares value is
 * sum(g y) / sum(g^2) with g = 1 - exp(-b2 x), and its variance is
 * s^2 / sum(g^2) with s^2 = RSS / (14 - 1). */
static void test_fixed(void **state) {
  (void)state;
  for (int analytic = 0; analytic <= 1; ++analytic) {
    vr_error err = {0};
    vr_lsq *lsq = vr_lsq_create(2, 14, nist_residuals, (void *)&misra1a, analytic, &err);
    const double b2 = 5.0e-4;
    assert_int_equal(vr_lsq_set_fixed(lsq, 1, true, &err), VR_OK);
    double b[2] = {100, b2};
    vr_lsq_summary s;
    assert_int_equal(vr_lsq_solve(lsq, b, NULL, &s, &err), VR_OK);
    assert_int_equal(s.free_parameters, 1);
    assert_true(b[1] == b2);

    double sgy = 0, sgg = 0;
    for (size_t i = 0; i < 14; ++i) {
      double g = 1 - exp(-b2 * misra1a_x[i]);
      sgy += g * misra1a_y[i];
      sgg += g * g;
    }
    double b1 = sgy / sgg, rss = 0;
    for (size_t i = 0; i < 14; ++i) {
      double r = b1 * (1 - exp(-b2 * misra1a_x[i])) - misra1a_y[i];
      rss += r * r;
    }
    /* The default function tolerance (1e-12 relative cost change) leaves
     * b1 within ~1e-6 of its standard deviation, a few 1e-9 relative. */
    assert_rel(b[0], b1, 1e-8);
    assert_rel(s.chi2, rss, 1e-12);

    double cov[4];
    assert_int_equal(vr_lsq_covariance(lsq, b, true, cov, &err), VR_OK);
    assert_rel(cov[0], rss / 13 / sgg, 1e-7);
    assert_true(cov[1] == 0 && cov[2] == 0 && cov[3] == 0);
    assert_int_equal(vr_lsq_covariance(lsq, b, false, cov, &err), VR_OK);
    assert_rel(cov[0], 1 / sgg, 1e-7);

    /* Every parameter fixed: nothing moves, the summary still reports. */
    assert_int_equal(vr_lsq_set_fixed(lsq, 0, true, &err), VR_OK);
    double c[2] = {b[0], b2};
    assert_int_equal(vr_lsq_solve(lsq, c, NULL, &s, &err), VR_OK);
    assert_int_equal(s.termination, VR_LSQ_CONVERGED);
    assert_int_equal(s.free_parameters, 0);
    assert_true(c[0] == b[0] && c[1] == b2);
    assert_rel(s.chi2, rss, 1e-10);
    vr_lsq_destroy(lsq);
  }
}

/* ---- robust loss ---------------------------------------------------------
 * A straight line y = a + b x through 21 points with small, known noise
 * and one gross outlier.  Plain least squares is dragged by the outlier;
 * the Huber fit stays close to the ordinary least-squares line of the 20
 * clean points (computed here in closed form). */
#define LINE_N 21
#define LINE_OUTLIER 6

typedef struct line_data {
  double x[LINE_N], y[LINE_N];
} line_data;

static int line_residuals(const double *p, double *f, double *jac, void *user) {
  const line_data *d = user;
  for (size_t i = 0; i < LINE_N; ++i) {
    f[i] = p[0] + p[1] * d->x[i] - d->y[i];
    if (jac) {
      jac[2 * i] = 1;
      jac[2 * i + 1] = d->x[i];
    }
  }
  return 0;
}

static void line_fit(const line_data *d, vr_lsq_loss loss, double scale, double *p) {
  vr_error err = {0};
  vr_lsq *lsq = vr_lsq_create(2, LINE_N, line_residuals, (void *)d, false, &err);
  vr_lsq_options o = vr_lsq_default_options();
  o.loss = loss;
  o.loss_scale = scale;
  p[0] = 0;
  p[1] = 0;
  vr_lsq_summary s;
  assert_int_equal(vr_lsq_solve(lsq, p, &o, &s, &err), VR_OK);
  assert_int_equal(s.termination, VR_LSQ_CONVERGED);
  if (loss != VR_LOSS_NONE) assert_true(s.final_cost < 0.5 * s.chi2);
  vr_lsq_destroy(lsq);
}

static void test_huber_outlier(void **state) {
  (void)state;
  line_data d;
  for (size_t i = 0; i < LINE_N; ++i) {
    d.x[i] = (double)i;
    /* Deterministic noise of amplitude 0.05. */
    d.y[i] = 1.0 + 0.5 * d.x[i] + 0.05 * sin(1.7 * (double)i + 0.3);
  }
  d.y[LINE_OUTLIER] += 30;

  /* Closed-form least squares without the outlier. */
  double sx = 0, sy = 0, sxx = 0, sxy = 0, k = 0;
  for (size_t i = 0; i < LINE_N; ++i) {
    if (i == LINE_OUTLIER) continue;
    sx += d.x[i];
    sy += d.y[i];
    sxx += d.x[i] * d.x[i];
    sxy += d.x[i] * d.y[i];
    k += 1;
  }
  double b_clean = (k * sxy - sx * sy) / (k * sxx - sx * sx);
  double a_clean = (sy - b_clean * sx) / k;

  double plain[2], huber[2], cauchy[2];
  line_fit(&d, VR_LOSS_NONE, 1, plain);
  line_fit(&d, VR_LOSS_HUBER, 0.1, huber);
  line_fit(&d, VR_LOSS_CAUCHY, 0.1, cauchy);
  /* The outlier drags plain least squares by about 3 in the intercept. */
  double da = plain[0] - a_clean, db = plain[1] - b_clean;
  assert_true(fabs(da) > 1 && fabs(db) > 0.1);
  /* Huber caps the outlier's pull at a = 0.1 where least squares lets its
   * ~28 residual pull, so the displacement shrinks ~280 times; ask for
   * 100. */
  assert_near(huber[0], a_clean, 0.01 * fabs(da));
  assert_near(huber[1], b_clean, 0.01 * fabs(db));
  /* Cauchy's influence decays towards zero: smaller still. */
  assert_near(cauchy[0], a_clean, 0.001 * fabs(da));
  assert_near(cauchy[1], b_clean, 0.001 * fabs(db));
}

/* ---- a model with a restricted domain -----------------------------------
 * f_i = sqrt(p) x_i - y_i, data from p = 0.01, start p = 4: the first
 * Gauss-Newton step lands near p = -3.6 where the model is undefined.  The
 * callback refuses p < 0 and the solver must back off and still converge. */
typedef struct sqrt_model {
  int refused;
} sqrt_model;

static int sqrt_residuals(const double *p, double *f, double *jac, void *user) {
  sqrt_model *u = user;
  if (p[0] < 0) {
    u->refused++;
    return 1;
  }
  for (size_t i = 0; i < 5; ++i) {
    double x = 1.0 + (double)i;
    f[i] = sqrt(p[0]) * x - 0.1 * x;
    if (jac) jac[i] = x / (2 * sqrt(p[0]));
  }
  return 0;
}

static void test_domain_failure(void **state) {
  (void)state;
  for (int analytic = 0; analytic <= 1; ++analytic) {
    sqrt_model u = {0};
    vr_error err = {0};
    vr_lsq *lsq = vr_lsq_create(1, 5, sqrt_residuals, &u, analytic, &err);
    double p = 4;
    vr_lsq_summary s;
    assert_int_equal(vr_lsq_solve(lsq, &p, NULL, &s, &err), VR_OK);
    assert_int_equal(s.termination, VR_LSQ_CONVERGED);
    assert_true(u.refused > 0);
    assert_rel(p, 0.01, 1e-8);

    /* A start outside the domain is the caller's mistake. */
    p = -1;
    assert_int_equal(vr_lsq_solve(lsq, &p, NULL, &s, &err), VR_E_ARG);
    assert_contains(err.message, "start");
    assert_int_equal(s.termination, VR_LSQ_FAILURE);
    assert_true(p == -1);
    vr_lsq_destroy(lsq);
  }
}

/* ---- rank deficiency ------------------------------------------------------
 * f_i = (p0 + p1) x_i + p2 - y_i: only p0 + p1 is determined.  The solve
 * succeeds (Levenberg-Marquardt damps the singular direction); the
 * covariance must refuse and name parameters 0 and 1, not 2. */
static int sum_residuals(const double *p, double *f, double *jac, void *user) {
  (void)user;
  for (size_t i = 0; i < 6; ++i) {
    double x = (double)i;
    f[i] = (p[0] + p[1]) * x + p[2] - (3 * x + 1 + 0.01 * cos((double)i));
    if (jac) {
      jac[3 * i] = x;
      jac[3 * i + 1] = x;
      jac[3 * i + 2] = 1;
    }
  }
  return 0;
}

static void test_rank_deficient(void **state) {
  (void)state;
  for (int analytic = 0; analytic <= 1; ++analytic) {
    vr_error err = {0};
    vr_lsq *lsq = vr_lsq_create(3, 6, sum_residuals, NULL, analytic, &err);
    double p[3] = {1, 1, 0}, cov[9];
    vr_lsq_summary s;
    assert_int_equal(vr_lsq_solve(lsq, p, NULL, &s, &err), VR_OK);
    assert_near(p[0] + p[1], 3, 0.01);
    assert_int_equal(vr_lsq_covariance(lsq, p, true, cov, &err), VR_E_NUMERIC);
    assert_contains(err.message, "parameters 0 and 1");
    assert_contains(err.message, "correlated");
    print_message("%s\n", err.message);
    /* Holding one of the pair makes the rest determined. */
    assert_int_equal(vr_lsq_set_fixed(lsq, 1, true, &err), VR_OK);
    assert_int_equal(vr_lsq_covariance(lsq, p, true, cov, &err), VR_OK);
    assert_true(cov[0] > 0 && cov[8] > 0 && cov[4] == 0);
    vr_lsq_destroy(lsq);
  }
}

/* A parameter the residuals ignore is named as undetermined. */
static int ignores_p1(const double *p, double *f, double *jac, void *user) {
  (void)user;
  (void)jac;
  for (size_t i = 0; i < 4; ++i) f[i] = p[0] - (double)i;
  return 0;
}

static void test_unused_parameter(void **state) {
  (void)state;
  vr_error err = {0};
  vr_lsq *lsq = vr_lsq_create(2, 4, ignores_p1, NULL, false, &err);
  double p[2] = {1.5, 2}, cov[4];
  assert_int_equal(vr_lsq_covariance(lsq, p, false, cov, &err), VR_E_NUMERIC);
  assert_contains(err.message, "parameter 1");
  vr_lsq_destroy(lsq);
}

/* ---- bad arguments ------------------------------------------------------ */
static int two_residuals(const double *p, double *f, double *jac, void *user) {
  (void)user;
  (void)jac;
  f[0] = p[0] - 1;
  f[1] = p[1] + p[2] - 2;
  return 0;
}

static void test_bad_arguments(void **state) {
  (void)state;
  vr_error err = {0};
  assert_null(vr_lsq_create(2, 14, NULL, NULL, false, &err));
  assert_int_equal(err.status, VR_E_ARG);
  assert_null(vr_lsq_create(0, 14, nist_residuals, (void *)&misra1a, false, &err));
  assert_int_equal(err.status, VR_E_ARG);

  vr_lsq *lsq = vr_lsq_create(2, 14, nist_residuals, (void *)&misra1a, true, &err);
  assert_non_null(lsq);
  vr_lsq_summary s;

  /* Start outside the bounds: the index is in the message. */
  assert_int_equal(vr_lsq_set_bounds(lsq, 1, 0, 1e-3, &err), VR_OK);
  double b[2] = {250, 0.002};
  assert_int_equal(vr_lsq_solve(lsq, b, NULL, &s, &err), VR_E_ARG);
  assert_contains(err.message, "parameter 1");
  assert_contains(err.message, "outside its bounds");
  assert_int_equal(s.termination, VR_LSQ_FAILURE);
  assert_true(b[0] == 250 && b[1] == 0.002);

  /* Non-finite start. */
  b[0] = NAN;
  b[1] = 0.0005;
  assert_int_equal(vr_lsq_solve(lsq, b, NULL, &s, &err), VR_E_ARG);
  assert_contains(err.message, "parameter 0");
  b[0] = INFINITY;
  assert_int_equal(vr_lsq_solve(lsq, b, NULL, &s, &err), VR_E_ARG);
  assert_contains(err.message, "parameter 0");

  /* Index out of range, inverted or NaN bounds, bad steps. */
  assert_int_equal(vr_lsq_set_bounds(lsq, 2, 0, 1, &err), VR_E_ARG);
  assert_contains(err.message, "parameter 2");
  assert_int_equal(vr_lsq_set_bounds(lsq, 0, 1, 0, &err), VR_E_ARG);
  assert_contains(err.message, "parameter 0");
  assert_int_equal(vr_lsq_set_bounds(lsq, 0, NAN, 0, &err), VR_E_ARG);
  assert_int_equal(vr_lsq_set_fixed(lsq, 5, true, &err), VR_E_ARG);
  assert_contains(err.message, "parameter 5");
  assert_int_equal(vr_lsq_set_step(lsq, 0, 0, &err), VR_E_ARG);
  assert_contains(err.message, "parameter 0");
  assert_int_equal(vr_lsq_set_step(lsq, 3, 1e-6, &err), VR_E_ARG);
  assert_contains(err.message, "parameter 3");

  /* Bad options. */
  vr_lsq_options o = vr_lsq_default_options();
  o.loss = VR_LOSS_HUBER;
  o.loss_scale = 0;
  b[0] = 250;
  b[1] = 0.0005;
  assert_int_equal(vr_lsq_solve(lsq, b, &o, &s, &err), VR_E_ARG);
  o = vr_lsq_default_options();
  o.num_threads = 0;
  assert_int_equal(vr_lsq_solve(lsq, b, &o, &s, &err), VR_E_ARG);
  vr_lsq_destroy(lsq);

  /* Fewer residuals than free parameters. */
  lsq = vr_lsq_create(3, 2, two_residuals, NULL, false, &err);
  assert_non_null(lsq);
  double p[3] = {1, 1, 1}, cov[9];
  assert_int_equal(vr_lsq_solve(lsq, p, NULL, &s, &err), VR_E_ARG);
  assert_contains(err.message, "2 residuals");
  assert_contains(err.message, "3 free parameters");
  assert_int_equal(vr_lsq_covariance(lsq, p, false, cov, &err), VR_E_ARG);
  /* Holding one parameter makes it well-posed in size. */
  assert_int_equal(vr_lsq_set_fixed(lsq, 2, true, &err), VR_OK);
  assert_int_equal(vr_lsq_solve(lsq, p, NULL, &s, &err), VR_OK);
  /* ...but scaling by the reduced chi-square needs a degree of freedom. */
  assert_int_equal(vr_lsq_covariance(lsq, p, true, cov, &err), VR_E_ARG);
  assert_contains(err.message, "degree of freedom");
  vr_lsq_destroy(lsq);

  /* NULL arguments never crash. */
  assert_int_equal(vr_lsq_solve(NULL, b, NULL, NULL, &err), VR_E_ARG);
  vr_lsq_destroy(NULL);
}

/* The finite-difference step is a per-parameter setting that matters: an
 * absurd step gives a visibly worse Jacobian, a sensible one none. */
static void test_step(void **state) {
  (void)state;
  vr_error err = {0};
  vr_lsq *lsq = vr_lsq_create(2, 14, nist_residuals, (void *)&misra1a, false, &err);
  double b[2] = {misra1a.certified[0], misra1a.certified[1]}, cov[4], cov_small[4];
  assert_int_equal(vr_lsq_covariance(lsq, b, true, cov, &err), VR_OK);
  assert_rel(sqrt(cov[3]), misra1a.sd[1], 5e-5);
  assert_int_equal(vr_lsq_set_step(lsq, 1, 0.5, &err), VR_OK);
  assert_int_equal(vr_lsq_covariance(lsq, b, true, cov_small, &err), VR_OK);
  assert_true(fabs(sqrt(cov_small[3]) / misra1a.sd[1] - 1) > 1e-3);
  vr_lsq_destroy(lsq);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_misra1a_analytic),  cmocka_unit_test(test_misra1a_numeric),
      cmocka_unit_test(test_thurber_analytic),  cmocka_unit_test(test_thurber_numeric),
      cmocka_unit_test(test_mgh09_analytic),    cmocka_unit_test(test_mgh09_numeric),
      cmocka_unit_test(test_forward_differences),
      cmocka_unit_test(test_iteration_limit),   cmocka_unit_test(test_threads),
      cmocka_unit_test(test_bounds),
      cmocka_unit_test(test_fixed),             cmocka_unit_test(test_huber_outlier),
      cmocka_unit_test(test_domain_failure),    cmocka_unit_test(test_rank_deficient),
      cmocka_unit_test(test_unused_parameter),  cmocka_unit_test(test_bad_arguments),
      cmocka_unit_test(test_step),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
