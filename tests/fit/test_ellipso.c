/* vr-ellipso's library: the sample model against published values, model
 * files and their errors, pseudo-optical constants, and fits whose 90 %
 * limits are honest: over 100 noisy synthetic data sets per case the true
 * value falls inside them 85-95 % of the time. */
#include "vr_test.h"
#include "vr/ellipso_fit.h"

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

static vr_sample_model *model_from(const char *text) {
  vr_sample_model *m;
  vr_error err = {0};
  if (vr_model_parse(text, strlen(text), "test.model", VR_SOURCE_DIR, NULL, &m, &err))
    fail_msg("%s", err.message);
  return m;
}

static void bare_silicon(void **state) {
  (void)state;
  /* Bare Si at 70 deg and 632.8 nm: Psi 10.58, Delta 179.2 in Woollam's
   * convention (issue "vr-ellipso"); N = 3.879 + 0.016444i (Green 2008, 630 nm). */
  vr_sample_model *m = model_from("substrate constant n=3.879 k=0.016444\n");
  double psi, delta, depol;
  assert_int_equal(vr_model_psi_delta(m, 632.8, 70, &psi, &delta, &depol, NULL), VR_OK);
  assert_near(psi, 10.58, 0.05);
  assert_near(delta, 179.2, 0.3);
  assert_near(depol, 0, 0);
  vr_model_destroy(m);
}

static void thermal_oxide_periodicity(void **state) {
  (void)state;
  /* A transparent film repeats its Psi, Delta when its thickness grows by
   * lambda / (2 sqrt(n^2 - sin^2 theta)) (Azzam and Bashara, "Ellipsometry
   * and polarized light", section 4.3): n = 1.46 at 70 deg and 633 nm gives
   * a period of 283.3 nm. */
  vr_sample_model *m = model_from("layer ox constant thickness=50 n=1.46\nsubstrate constant n=3.879 k=0.016444\n");
  double p1, d1, p2, d2;
  double period = 633.0 / (2.0 * sqrt(1.46 * 1.46 - pow(sin(70 * M_PI / 180), 2)));
  vr_model_psi_delta(m, 633, 70, &p1, &d1, NULL, NULL);
  m->layers[0].thickness_nm = 50 + period;
  vr_model_psi_delta(m, 633, 70, &p2, &d2, NULL, NULL);
  assert_near(p2, p1, 1e-9);
  assert_near(d2, d1, 1e-9);
  vr_model_destroy(m);
}

static void pseudo_dielectric_function(void **state) {
  (void)state;
  /* For a bulk sample the two-phase inversion returns N^2 exactly
   * (Azzam and Bashara eq. 4.95), at any angle. */
  vr_sample_model *m = model_from("substrate constant n=3.879 k=0.016444\n");
  vr_complex N = 3.879 + 0.016444 * I;
  for (double a = 40; a < 85; a += 11) {
    double psi, delta;
    vr_model_psi_delta(m, 630, a, &psi, &delta, NULL, NULL);
    vr_complex e = vr_pseudo_epsilon(psi, delta, a);
    assert_near(creal(e), creal(N * N), 1e-9);
    assert_near(cimag(e), cimag(N * N), 1e-9);
  }
  vr_model_destroy(m);
}

static void model_file_errors_name_the_line(void **state) {
  (void)state;
  struct { const char *text, *expect; } cases[] = {
      {"layer a cauchy thickness=-3\nsubstrate constant\n", "test.model:1: layer 'a': negative thickness -3 nm"},
      {"substrate constant\nparam substrate.q = 3\n", "test.model:2: unknown parameter 'substrate.q'"},
      {"layer a warp thickness=3\n", "test.model:1: unknown material 'warp'"},
      {"layer a cauchy\nsubstrate constant\n", "test.model:1: layer 'a' needs thickness=NM"},
      {"layer a cauchy thickness=10\n", "no 'substrate' line"},
      {"substrate constant\nparam substrate.n = 3 fit min=4\n", "test.model:2: parameter substrate.n: start value 3 is outside [4, inf]"},
      {"frobnicate\n", "test.model:1: unknown statement 'frobnicate'"},
      {"substrate db:Si\n", "test.model:1: material 'db:Si' needs the material database"},
      {"layer r ema=bruggeman(x,void) thickness=2\nsubstrate constant\n", "test.model:1: effective medium of layer 'r': no layer 'x'"},
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
    vr_sample_model *m;
    vr_error err = {0};
    vr_status st = vr_model_parse(cases[i].text, strlen(cases[i].text), "test.model", ".", NULL, &m, &err);
    if (st == VR_OK) fail_msg("case %zu parsed", i);
    assert_contains(err.message, cases[i].expect);
  }
}

/* Synthetic data from model m at angles x wavelengths, noise sigma. */
static void synth(vr_sample_model *m, const double *angles, size_t na, double w0, double w1, size_t nw,
                  double spsi, double sdelta, gsl_rng *rng, vr_ellipso_data *d) {
  d->n = na * nw;
  d->p = calloc(d->n, sizeof *d->p);
  d->source = strdup("synthetic");
  d->has_sigma = 1;
  size_t k = 0;
  for (size_t i = 0; i < nw; i++)
    for (size_t j = 0; j < na; j++, k++) {
      vr_ellipso_point *p = &d->p[k];
      p->nm = w0 + (w1 - w0) * (double)i / (double)(nw - 1);
      p->aoi_deg = angles[j];
      vr_model_psi_delta(m, p->nm, p->aoi_deg, &p->psi_deg, &p->delta_deg, NULL, NULL);
      p->psi_deg += gsl_ran_gaussian(rng, spsi);
      p->delta_deg = vr_delta_normalise(p->delta_deg + gsl_ran_gaussian(rng, sdelta));
      p->sigma_psi = spsi;
      p->sigma_delta = sdelta;
      p->line = (long)k + 2;
      p->depolarisation = NAN;
    }
}

typedef struct coverage_case {
  const char *model;                  /* the truth, with the free parameters marked */
  const char *names[6];               /* parameters checked */
  void (*perturb)(vr_sample_model *m, gsl_rng *rng, int draw); /* the truth of each draw */
} coverage_case;

static void run_coverage(const coverage_case *c, int draws, unsigned long seed) {
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, seed);
  const double angles[3] = {65, 70, 75};
  int inside[6] = {0}, fits = 0;
  size_t nnames = 0;
  while (nnames < 6 && c->names[nnames]) nnames++;
  for (int draw = 0; draw < draws; draw++) {
    vr_sample_model *truth = model_from(c->model);
    if (c->perturb) c->perturb(truth, rng, draw);
    vr_ellipso_data d;
    synth(truth, angles, 3, 400, 1000, 31, 0.02, 0.08, rng, &d);
    vr_sample_model *m = vr_model_copy(truth, NULL);
    /* Start away from the truth: thickness +8 %, other parameters +2 %. */
    for (size_t i = 0; i < m->nparams; i++)
      if (m->params[i].free) *vr_model_param_value(m, i) *= m->params[i].slot == VR_SLOT_THICKNESS ? 1.08 : 1.02;
    vr_fit_result r;
    vr_error err = {0};
    if (vr_ellipso_fit(m, &d, NULL, &r, &err)) fail_msg("draw %d: %s", draw, err.message);
    fits++;
    for (size_t q = 0; q < nnames; q++) {
      long ti = vr_model_param_index(truth, c->names[q]);
      double t = vr_model_param_get(truth, (size_t)ti);
      for (size_t j = 0; j < r.nfree; j++)
        if (!strcmp(r.names[j], c->names[q]) && t >= r.ci_lo[j] && t <= r.ci_hi[j]) inside[q]++;
    }
    vr_fit_result_free(&r);
    vr_model_destroy(m);
    vr_model_destroy(truth);
    vr_ellipso_data_free(&d);
  }
  for (size_t q = 0; q < nnames; q++) {
    print_message("%-22s true value inside the 90%% limits in %d of %d fits\n", c->names[q], inside[q], fits);
    if (inside[q] < 85 * fits / 100 || inside[q] > 95 * fits / 100)
      fail_msg("%s: coverage %d/%d outside 85-95 %%", c->names[q], inside[q], fits);
  }
  gsl_rng_free(rng);
}

static void oxide_thickness(vr_sample_model *m, gsl_rng *rng, int draw) {
  (void)rng;
  /* 1 nm to 1000 nm, log-spaced over the draws. */
  m->layers[0].thickness_nm = pow(10.0, 3.0 * draw / 99.0);
}

static void coverage_oxide_on_silicon(void **state) {
  (void)state;
  /* Thermal SiO2 (Malitson 1965 Sellmeier) on Si (Green 2008); thickness free. */
  coverage_case c = {
      "layer oxide file:matdb/data/fused_silica_malitson.yml thickness=100 fit\n"
      "substrate file:matdb/data/si_green2008.yml\n",
      {"oxide.thickness", NULL}, oxide_thickness};
  run_coverage(&c, 100, 11);
}

static void coverage_cauchy_on_glass(void **state) {
  (void)state;
  /* A 180 nm Cauchy film (A = 1.9, B = 0.02 um^2) on N-BK7-like glass; all three free. */
  coverage_case c = {
      "layer film cauchy thickness=180 fit\n"
      "param film.A = 1.9 fit min=1.2 max=3\n"
      "param film.B = 0.02 fit min=-0.5 max=0.5\n"
      "substrate sellmeier2:3\n"
      "param substrate.A = 1\n"
      "param substrate.B1 = 1.03961212\nparam substrate.C1 = 0.00600069867\n"
      "param substrate.B2 = 0.231792344\nparam substrate.C2 = 0.0200179144\n"
      "param substrate.B3 = 1.01046945\nparam substrate.C3 = 103.560653\n",
      {"film.thickness", "film.A", "film.B", NULL}, NULL};
  /* With 100 draws the count itself scatters by about 3 around 90 (binomial);
   * over 400 draws of this case the three counts were 91.8 %, 88.5 % and
   * 89.5 % (docs/vr-ellipso.md), so the limits are calibrated, not lucky. */
  run_coverage(&c, 100, 99);
}

static void coverage_tauc_lorentz_film(void **state) {
  (void)state;
  /* An amorphous film described by one Tauc-Lorentz oscillator (a-Si-like:
   * Amp 120, En 3.6, C 2.4, Eg 1.5 eV, eps_inf 1) on Si, 60 nm thick;
   * thickness, Amp and Eg free. */
  coverage_case c = {
      "layer film genosc:tauc_lorentz thickness=60 fit\n"
      "param film.eps_inf = 1\n"
      "param film.Amp1 = 120 fit min=1 max=500\nparam film.En1 = 3.6\nparam film.C1 = 2.4\n"
      "param film.Eg1 = 1.5 fit min=0.5 max=3\n"
      "substrate file:matdb/data/si_green2008.yml\n",
      {"film.thickness", "film.Amp1", "film.Eg1", NULL}, NULL};
  run_coverage(&c, 100, 37);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(bare_silicon),
      cmocka_unit_test(thermal_oxide_periodicity),
      cmocka_unit_test(pseudo_dielectric_function),
      cmocka_unit_test(model_file_errors_name_the_line),
      cmocka_unit_test(coverage_oxide_on_silicon),
      cmocka_unit_test(coverage_cauchy_on_glass),
      cmocka_unit_test(coverage_tauc_lorentz_film),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
