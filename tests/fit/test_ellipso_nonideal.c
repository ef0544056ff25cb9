/* Thickness non-uniformity and spectral bandwidth against the analytic
 * single-film reflection (Airy's sum; Heavens, "Optical Properties of Thin
 * Solid Films", 1955, ch. 4) averaged in intensity by brute-force quadrature
 * here, independently of the model's Gauss-Legendre sums.
 *
 * Film n1 = 1.46 (non-dispersive) on a substrate n2 = 3.5 in air, at 70°.
 * Amplitudes in the exp(-iωt) convention, Woollam's Δ = -arg(r_p r_s*):
 *   r = (r01 + r12 e^{2iβ}) / (1 + r01 r12 e^{2iβ}), β = 2π n1 d cos θ1 / λ,
 *   r_s = (n_a cos θ_a - n_b cos θ_b) / (...), r_p = (n_b cos θ_a - n_a cos θ_b) / (...).
 * A second check needs no quadrature: averaged over one whole period of
 * the phase 2β, |r|² equals the incoherent sum
 *   (r01² + r12² - 2 r01² r12²) / (1 - r01² r12²)
 * (the mean of 1 / (a + b cos x) over a period is 1 / sqrt(a² - b²)). */
#include "vr_test.h"
#include "vr/ellipso_fit.h"

#define N1 1.46
#define N2 3.5
#define AOI 70.0

typedef struct sums {
  double pp, ss;
  double complex x;
} sums;

static void fresnel(double na, double ca, double nb, double cb, double *rs, double *rp) {
  *rs = (na * ca - nb * cb) / (na * ca + nb * cb);
  *rp = (nb * ca - na * cb) / (nb * ca + na * cb);
}

static void airy(double d, double lambda, sums *out) {
  double s0 = sin(AOI * M_PI / 180), c0 = cos(AOI * M_PI / 180);
  double c1 = sqrt(1 - s0 * s0 / (N1 * N1)), c2 = sqrt(1 - s0 * s0 / (N2 * N2));
  double r01s, r01p, r12s, r12p;
  fresnel(1.0, c0, N1, c1, &r01s, &r01p);
  fresnel(N1, c1, N2, c2, &r12s, &r12p);
  double complex e = cexp(2 * I * 2 * M_PI * N1 * d * c1 / lambda);
  double complex rs = (r01s + r12s * e) / (1 + r01s * r12s * e);
  double complex rp = (r01p + r12p * e) / (1 + r01p * r12p * e);
  out->pp = creal(rp * conj(rp));
  out->ss = creal(rs * conj(rs));
  out->x = rp * conj(rs);
}

static void psi_delta_of(const sums *s, double *psi, double *delta, double *depol) {
  *psi = atan(sqrt(s->pp / s->ss)) * 180 / M_PI;
  *delta = vr_delta_normalise(-carg(s->x) * 180 / M_PI);
  double t = s->pp + s->ss, N = (s->ss - s->pp) / t, C = 2 * creal(s->x) / t, S = -2 * cimag(s->x) / t;
  *depol = 1 - sqrt(N * N + C * C + S * S);
}

/* Composite Simpson over u in [-w/2, w/2] (uniform) and v in [-1, 1]
 * (weight 1 - |v|, λ = λ0 + b v), 2000 intervals each. */
static void brute(double d, double lambda, double w, double b, sums *out) {
  const int n = 2000;
  memset(out, 0, sizeof *out);
  int nv = b > 0 ? n : 0;
  for (int j = 0; j <= nv; j++) {
    double v = nv ? -1 + 2.0 * j / nv : 0;
    double wv = nv ? (j == 0 || j == nv ? 1 : j % 2 ? 4 : 2) * (2.0 / nv) / 3 * (1 - fabs(v)) : 1;
    int nu = w > 0 ? n : 0;
    for (int i = 0; i <= nu; i++) {
      double u = nu ? -w / 2 + w * i / nu : 0;
      double wu = nu ? (i == 0 || i == nu ? 1 : i % 2 ? 4 : 2) * (1.0 / nu) / 3 : 1;
      sums s;
      airy(d * (1 + u), lambda + b * v, &s);
      out->pp += wu * wv * s.pp;
      out->ss += wu * wv * s.ss;
      out->x += wu * wv * s.x;
    }
  }
}

static vr_sample_model *film(double d, double w_pct, double b_nm) {
  char text[512];
  snprintf(text, sizeof text,
           "layer film constant n=%.17g thickness=%.17g\nsubstrate constant n=%.17g\n"
           "param sample.thickness_nonuniformity = %.17g\n%s",
           N1, d, N2, w_pct, "");
  if (b_nm > 0) {
    size_t l = strlen(text);
    snprintf(text + l, sizeof text - l, "param sample.bandwidth = %.17g\n", b_nm);
  }
  vr_sample_model *m = NULL;
  vr_error err = {0};
  if (vr_model_parse(text, strlen(text), "nonideal.model", ".", NULL, &m, &err)) fail_msg("%s", err.message);
  return m;
}

static void check(double d, double lambda, double w_pct, double b_nm) {
  vr_sample_model *m = film(d, w_pct, b_nm);
  vr_model_response r;
  vr_error err = {0};
  if (vr_model_measure(m, lambda, AOI, NAN, &r, &err)) fail_msg("%s", err.message);
  sums s;
  brute(d, lambda, w_pct / 100, b_nm, &s);
  double psi, delta, depol;
  psi_delta_of(&s, &psi, &delta, &depol);
  assert_near(r.psi, psi, 1e-7);
  assert_near(vr_delta_difference(r.delta - delta), 0, 1e-6);
  assert_near(r.depolarisation, depol, 1e-7);
  /* N, C, S are consistent with Ψ, Δ and the depolarisation. */
  assert_near(r.N, cos(2 * r.psi * M_PI / 180), 1e-12);
  assert_near(hypot(r.C, r.S), sqrt(fmax(0, pow(1 - r.depolarisation, 2) - r.N * r.N)), 1e-9);
  vr_model_destroy(m);
}

static void nonuniformity_matches_airy_average(void **state) {
  (void)state;
  check(500, 633, 0, 0);    /* the coherent path */
  check(500, 633, 1e-7, 0); /* the averaged path at no width */
  check(500, 633, 5, 0);    /* mild: a little depolarisation */
  check(2000, 450, 20, 0);  /* several fringes across the spot */
  check(120, 300, 1, 0);
}

static void bandwidth_matches_airy_average(void **state) {
  (void)state;
  check(3000, 500, 0, 5);   /* a thick film, fringes 40 nm apart */
  check(800, 700, 0, 2);
  check(1500, 400, 3, 4);   /* both at once */
}

static void full_period_is_incoherent(void **state) {
  (void)state;
  double d = 2000, lambda = 600;
  double s0 = sin(AOI * M_PI / 180), c0 = cos(AOI * M_PI / 180);
  double c1 = sqrt(1 - s0 * s0 / (N1 * N1)), c2 = sqrt(1 - s0 * s0 / (N2 * N2));
  /* u spans one period of 2β: 4π n1 d c1 w / λ = 2π. */
  double w = lambda / (2 * N1 * d * c1);
  vr_sample_model *m = film(d, 100 * w, 0);
  vr_model_response r;
  vr_error err = {0};
  if (vr_model_measure(m, lambda, AOI, NAN, &r, &err)) fail_msg("%s", err.message);
  double r01s, r01p, r12s, r12p;
  fresnel(1.0, c0, N1, c1, &r01s, &r01p);
  fresnel(N1, c1, N2, c2, &r12s, &r12p);
  double a = r01s * r01s, b = r12s * r12s, Rs = (a + b - 2 * a * b) / (1 - a * b);
  a = r01p * r01p, b = r12p * r12p;
  double Rp = (a + b - 2 * a * b) / (1 - a * b);
  assert_near(r.psi, atan(sqrt(Rp / Rs)) * 180 / M_PI, 1e-9);
  assert_true(r.depolarisation > 0.01); /* a whole fringe across the spot depolarises */
  vr_model_destroy(m);
}

static void file_bandwidth_used_unless_model_sets_it(void **state) {
  (void)state;
  vr_sample_model *plain = film(3000, 0, 0), *set = film(3000, 0, 1e-9);
  vr_model_response a, b, c;
  vr_error err = {0};
  assert_int_equal(vr_model_measure(plain, 500, AOI, 5, &a, &err), VR_OK);
  assert_int_equal(vr_model_measure(plain, 500, AOI, NAN, &b, &err), VR_OK);
  assert_int_equal(vr_model_measure(set, 500, AOI, 5, &c, &err), VR_OK);
  sums s;
  double psi, delta, depol;
  brute(3000, 500, 0, 5, &s);
  psi_delta_of(&s, &psi, &delta, &depol);
  assert_near(a.psi, psi, 1e-7);               /* the point's 5 nm */
  assert_true(fabs(b.psi - a.psi) > 1e-3);     /* none */
  assert_near(c.psi, b.psi, 1e-9);             /* the model's ~0 nm wins */
  /* Out of range: a bandwidth reaching 0 nm, a negative one. */
  assert_int_equal(vr_model_measure(plain, 50, AOI, 60, &a, &err), VR_E_RANGE);
  vr_model_destroy(plain);
  vr_model_destroy(set);
  vr_sample_model *m = NULL;
  const char *bad = "substrate constant n=1.5\nparam sample.thickness_nonuniformity = -1\n";
  assert_int_not_equal(vr_model_parse(bad, strlen(bad), "bad.model", ".", NULL, &m, &err), VR_OK);
  assert_contains(err.message, "bad.model:2");
}

/* A thick film whose thickness varies by 3 % across the spot, simulated
 * with its depolarisation (the model's own: an analytic truth), then
 * fitted with the thickness and the non-uniformity free: both come back,
 * the depolarisation values enter the fit and the MSE's degrees of freedom
 * (2N + D - M, Woollam's definition with depolarisation). */
static void nonuniformity_fitted_with_depolarisation(void **state) {
  (void)state;
  vr_sample_model *truth = film(1500, 3, 0);
  vr_ellipso_data d = {0};
  d.p = calloc(2 * 80, sizeof *d.p);
  d.source = strdup("nonuniform.dat");
  d.record_time_s = NAN;
  for (int a = 0; a < 2; a++)
    for (int i = 0; i < 80; i++) {
      vr_ellipso_point *p = &d.p[d.n++];
      p->nm = 400 + 5 * i;
      p->aoi_deg = a ? 75 : 65;
      p->sigma_psi = p->sigma_delta = 0.01;
      p->sigma_depolarisation = 0.1;
      p->bandwidth_nm = NAN;
      p->line = (long)d.n;
      vr_model_response r;
      vr_error err = {0};
      if (vr_model_measure(truth, p->nm, p->aoi_deg, NAN, &r, &err)) fail_msg("%s", err.message);
      p->psi_deg = r.psi;
      p->delta_deg = r.delta;
      p->depolarisation = 100 * r.depolarisation;
    }
  char text[512];
  snprintf(text, sizeof text,
           "layer film constant n=%.17g thickness=1490 fit min=1400 max=1600\nsubstrate constant n=%.17g\n"
           "param sample.thickness_nonuniformity = 1 fit min=0 max=10\n",
           N1, N2);
  vr_sample_model *m = NULL;
  vr_error err = {0};
  if (vr_model_parse(text, strlen(text), "fit.model", ".", NULL, &m, &err)) fail_msg("%s", err.message);
  vr_fit_result r;
  if (vr_ellipso_fit(m, &d, NULL, &r, &err)) fail_msg("%s", err.message);
  /* The measurement's parameters come first in the list. */
  assert_string_equal(r.names[0], "sample.thickness_nonuniformity");
  assert_string_equal(r.names[1], "film.thickness");
  assert_near(r.value[1], 1500, 1e-4);
  assert_near(r.value[0], 3, 1e-5);
  assert_int_equal(r.ndepol, d.n);
  assert_int_equal(r.dof, (int)(3 * d.n - 2));
  assert_true(r.depol_model[10] > 0);
  vr_fit_result_free(&r);
  /* --no-depolarisation: Ψ, Δ only. */
  vr_fit_options o = vr_fit_default_options();
  o.fit_depolarisation = false;
  *vr_model_param_value(m, (size_t)vr_model_param_index(m, "film.thickness")) = 1490;
  if (vr_ellipso_fit(m, &d, &o, &r, &err)) fail_msg("%s", err.message);
  assert_int_equal(r.ndepol, 0);
  assert_int_equal(r.dof, (int)(2 * d.n - 2));
  assert_near(r.value[0], 3, 1e-4);
  vr_fit_result_free(&r);
  vr_model_destroy(m);
  vr_model_destroy(truth);
  vr_ellipso_data_free(&d);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(nonuniformity_matches_airy_average),
      cmocka_unit_test(bandwidth_matches_airy_average),
      cmocka_unit_test(full_period_is_incoherent),
      cmocka_unit_test(file_bandwidth_used_unless_model_sets_it),
      cmocka_unit_test(nonuniformity_fitted_with_depolarisation),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
