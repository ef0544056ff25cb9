/* Multi-sample fits: two films of one material (Cauchy A = 1.46,
 * B = 0.004 µm²) at 12 nm and 180 nm on Si (Aspnes), simulated, fitted
 * together with A, B shared and the thicknesses per sample.  Noise-free,
 * the fit must return the simulated values (an analytic truth: the data are
 * the model's).  With noise, the thin film alone cannot separate its
 * thickness from its index (the well-known thin-film correlation; Woollam's
 * multi-sample analysis exists for it), and the shared fit can: the
 * thickness-A correlation must drop and the thin film's thickness must come
 * back within its 90 % limits. */
#include "vr_test.h"
#include "vr/ellipso_fit.h"

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

static vr_sample_model *model(const char *text) {
  vr_sample_model *m = NULL;
  vr_error err = {0};
  if (vr_model_parse(text, strlen(text), "multi.model", VR_SOURCE_DIR, NULL, &m, &err)) fail_msg("%s", err.message);
  return m;
}

static vr_sample_model *truth(double thickness) {
  char text[512];
  snprintf(text, sizeof text,
           "layer film cauchy A=1.46 B=0.004 thickness=%g\nsubstrate file:samples/ellipsometry/Si_Aspnes.yml\n",
           thickness);
  return model(text);
}

static void simulate(vr_ellipso_data *d, const char *name, double thickness, double noise, gsl_rng *rng) {
  vr_sample_model *m = truth(thickness);
  memset(d, 0, sizeof *d);
  d->p = calloc(2 * 61, sizeof *d->p);
  d->source = strdup(name);
  d->record_time_s = NAN;
  const double angles[2] = {65, 75};
  for (int a = 0; a < 2; a++)
    for (int i = 0; i < 61; i++) {
      vr_ellipso_point *p = &d->p[d->n++];
      p->nm = 300 + 8 * i;
      p->aoi_deg = angles[a];
      p->sigma_psi = p->sigma_delta = noise > 0 ? noise : 1;
      p->depolarisation = p->sigma_depolarisation = p->bandwidth_nm = NAN;
      p->line = d->n;
      vr_error err = {0};
      if (vr_model_psi_delta(m, p->nm, p->aoi_deg, &p->psi_deg, &p->delta_deg, NULL, &err)) fail_msg("%s", err.message);
      if (noise > 0) {
        p->psi_deg += gsl_ran_gaussian(rng, noise);
        p->delta_deg = vr_delta_normalise(p->delta_deg + gsl_ran_gaussian(rng, noise));
      }
    }
  vr_model_destroy(m);
}

static const char *FIT = "layer film cauchy A=1.5 B=0.002 thickness=100 fit per-sample min=0 max=400\n"
                         "param film.A = 1.5 fit min=1.2 max=2\nparam film.B = 0.002 fit min=-0.1 max=0.1\n"
                         "substrate file:samples/ellipsometry/Si_Aspnes.yml\n";

static size_t index_of(const vr_fit_result *r, const char *name) {
  for (size_t i = 0; i < r->nfree; i++)
    if (!strcmp(r->names[i], name)) return i;
  fail_msg("no parameter %s", name);
  return 0;
}

static void shared_and_per_sample_recovered(void **state) {
  (void)state;
  vr_ellipso_data d[2];
  simulate(&d[0], "thin.csv", 12, 0, NULL);
  simulate(&d[1], "thick.csv", 180, 0, NULL);
  vr_sample_model *m[2] = {model(FIT), model(FIT)};
  vr_fit_result r;
  vr_error err = {0};
  if (vr_ellipso_fit_samples(m, d, 2, NULL, &r, &err)) fail_msg("%s", err.message);
  assert_int_equal(r.nfree, 4); /* thickness[1], thickness[2], A, B */
  assert_near(r.value[index_of(&r, "film.thickness[1]")], 12, 1e-5);
  assert_near(r.value[index_of(&r, "film.thickness[2]")], 180, 1e-5);
  assert_near(r.value[index_of(&r, "film.A")], 1.46, 1e-7);
  assert_near(r.value[index_of(&r, "film.B")], 0.004, 1e-7);
  /* Each model holds its own solution; the samples are reported apart. */
  assert_near(m[0]->layers[0].thickness_nm, 12, 1e-5);
  assert_near(m[1]->layers[0].thickness_nm, 180, 1e-5);
  assert_int_equal(r.nsamples, 2);
  assert_int_equal(r.samples[1].first, d[0].n);
  assert_string_equal(r.samples[1].source, "thick.csv");
  assert_int_equal(r.npoints, d[0].n + d[1].n);
  assert_int_equal(r.dof, (int)(2 * r.npoints - 4));
  assert_true(r.describes);
  vr_fit_result_free(&r);
  for (int s = 0; s < 2; s++) {
    vr_model_destroy(m[s]);
    vr_ellipso_data_free(&d[s]);
  }
}

static double corr(const vr_fit_result *r, const char *a, const char *b) {
  return r->correlation[index_of(r, a) * r->nfree + index_of(r, b)];
}

static void shared_fit_decorrelates_a_thin_film(void **state) {
  (void)state;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 7);
  vr_ellipso_data d[2];
  simulate(&d[0], "thin.csv", 12, 0.02, rng);
  simulate(&d[1], "thick.csv", 180, 0.02, rng);
  vr_fit_options o = vr_fit_default_options();
  vr_sample_model *alone = model(FIT);
  vr_fit_result one, both;
  vr_error err = {0};
  if (vr_ellipso_fit(alone, &d[0], &o, &one, &err)) fail_msg("%s", err.message);
  vr_sample_model *m[2] = {model(FIT), model(FIT)};
  if (vr_ellipso_fit_samples(m, d, 2, &o, &both, &err)) fail_msg("%s", err.message);
  double c1 = fabs(corr(&one, "film.thickness", "film.A")), c2 = fabs(corr(&both, "film.thickness[1]", "film.A"));
  print_message("|corr(thickness, A)| thin film alone %.4f, with the thick film %.4f\n", c1, c2);
  assert_true(c1 > 0.95);
  assert_true(c2 < c1);
  size_t t = index_of(&both, "film.thickness[1]");
  assert_true(both.ci_lo[t] <= 12 && 12 <= both.ci_hi[t]);
  assert_true(both.stderr_[t] < one.stderr_[index_of(&one, "film.thickness")] / 3);
  vr_fit_result_free(&one);
  vr_fit_result_free(&both);
  vr_model_destroy(alone);
  for (int s = 0; s < 2; s++) {
    vr_model_destroy(m[s]);
    vr_ellipso_data_free(&d[s]);
  }
  gsl_rng_free(rng);
}

static void a_sample_the_model_cannot_describe_is_named(void **state) {
  (void)state;
  /* The second file is of another material (A = 1.60): with A shared, the
   * joint fit cannot describe both, and the verdict names a sample. */
  vr_ellipso_data d[2];
  simulate(&d[0], "thin.csv", 12, 0, NULL);
  vr_sample_model *other = model("layer film cauchy A=1.60 B=0.004 thickness=180 fit\n"
                                 "substrate file:samples/ellipsometry/Si_Aspnes.yml\n");
  simulate(&d[1], "other.csv", 180, 0, NULL);
  for (size_t i = 0; i < d[1].n; i++)
    vr_model_psi_delta(other, d[1].p[i].nm, d[1].p[i].aoi_deg, &d[1].p[i].psi_deg, &d[1].p[i].delta_deg, NULL, NULL);
  for (int s = 0; s < 2; s++)
    for (size_t i = 0; i < d[s].n; i++) d[s].p[i].sigma_psi = d[s].p[i].sigma_delta = 0.01;
  vr_sample_model *m[2] = {model(FIT), model(FIT)};
  vr_fit_result r;
  vr_error err = {0};
  if (vr_ellipso_fit_samples(m, d, 2, NULL, &r, &err)) fail_msg("%s", err.message);
  print_message("%s; sample MSEs %g %g\n", r.verdict, r.samples[0].mse, r.samples[1].mse);
  assert_false(r.describes);
  assert_contains(r.verdict, "sample ");
  vr_fit_result_free(&r);
  /* Models whose parameter lists differ are refused. */
  vr_sample_model *m2[2] = {m[0], other};
  assert_int_equal(vr_ellipso_fit_samples(m2, d, 2, NULL, &r, &err), VR_E_ARG);
  vr_model_destroy(other);
  for (int s = 0; s < 2; s++) {
    vr_model_destroy(m[s]);
    vr_ellipso_data_free(&d[s]);
  }
}

static void per_sample_needs_a_free_parameter(void **state) {
  (void)state;
  vr_sample_model *m = NULL;
  vr_error err = {0};
  const char *bad = "layer film cauchy thickness=10 per-sample\nsubstrate constant n=3.8\n";
  assert_int_not_equal(vr_model_parse(bad, strlen(bad), "ps.model", ".", NULL, &m, &err), VR_OK);
  assert_contains(err.message, "ps.model:1");
  assert_contains(err.message, "per-sample applies to a fitted parameter");
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(shared_and_per_sample_recovered),
      cmocka_unit_test(shared_fit_decorrelates_a_thin_film),
      cmocka_unit_test(a_sample_the_model_cannot_describe_is_named),
      cmocka_unit_test(per_sample_needs_a_free_parameter),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
