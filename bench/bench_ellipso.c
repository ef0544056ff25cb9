/* Prints how long vr-ellipso's fit takes for the reference problem:
 * 3 angles x 500 wavelengths of a Cauchy film on native oxide on Si, global
 * thickness search included, one thread.  Figures go to docs/benchmarks.md. */
#include "vr/ellipso_fit.h"

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static const char *MODEL =
    "layer film cauchy thickness=%g %s\n"
    "param film.A = %g %s\nparam film.B = %g %s\n"
    "layer native file:matdb/data/fused_silica_malitson.yml thickness=1.5\n"
    "substrate file:matdb/data/si_green2008.yml\n";

static vr_sample_model *make(double d, double A, double B, const char *fit) {
  char text[1024];
  snprintf(text, sizeof text, MODEL, d, fit, A, fit, B, fit);
  vr_sample_model *m;
  vr_error err = {0};
  if (vr_model_parse(text, strlen(text), "bench.model", VR_SOURCE_DIR, NULL, &m, &err)) {
    fprintf(stderr, "%s\n", err.message);
    exit(1);
  }
  return m;
}

int main(void) {
  vr_sample_model *truth = make(123.4, 1.62, 0.008, "");
  vr_ellipso_data d = {0};
  d.n = 1500;
  d.p = calloc(d.n, sizeof *d.p);
  d.source = strdup("bench");
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  const double angles[3] = {65, 70, 75};
  for (size_t i = 0, k = 0; i < 500; i++)
    for (size_t j = 0; j < 3; j++, k++) {
      vr_ellipso_point *p = &d.p[k];
      p->nm = 300.0 + 1.4 * (double)i;
      p->aoi_deg = angles[j];
      vr_model_psi_delta(truth, p->nm, p->aoi_deg, &p->psi_deg, &p->delta_deg, NULL, NULL);
      p->psi_deg += gsl_ran_gaussian(rng, 0.02);
      p->delta_deg = vr_delta_normalise(p->delta_deg + gsl_ran_gaussian(rng, 0.08));
      p->sigma_psi = 0.02;
      p->sigma_delta = 0.08;
      p->depolarisation = NAN;
    }
  const int runs = 5;
  double total = 0, best = 1e9;
  vr_fit_result r = {0};
  for (int run = 0; run < runs; run++) {
    vr_sample_model *m = make(80, 1.55, 0.005, "fit");
    long k = vr_model_param_index(m, "film.thickness");
    m->params[k].lower = 0;
    m->params[k].upper = 1000;
    struct timespec a, b;
    clock_gettime(CLOCK_MONOTONIC, &a);
    vr_error err = {0};
    vr_fit_result_free(&r);
    vr_fit_options o = vr_fit_default_options();
    if (getenv("NOGLOBAL")) o.global_search = false;
    if (vr_ellipso_fit(m, &d, &o, &r, &err)) {
      fprintf(stderr, "%s\n", err.message);
      return 1;
    }
    clock_gettime(CLOCK_MONOTONIC, &b);
    double t = (double)(b.tv_sec - a.tv_sec) + 1e-9 * (double)(b.tv_nsec - a.tv_nsec);
    total += t;
    if (t < best) best = t;
    vr_model_destroy(m);
  }
  printf("fit: 3 angles x 500 wavelengths, Cauchy film (d, A, B free) on 1.5 nm oxide on Si\n");
  printf("  thickness %.3f nm (truth 123.4), A %.5f (1.62), B %.6f (0.008), MSE %.3f\n", r.value[0], r.value[1],
         r.value[2], r.mse);
  printf("  grid evaluations %d (on %s), LM iterations %d, residual evaluations %d\n", r.grid_evaluations,
         "a 60-wavelength subset", r.summary.iterations, r.summary.residual_evaluations);
  printf("  time per fit: best %.1f ms, mean %.1f ms over %d runs (one thread)\n", best * 1e3, total / runs * 1e3, runs);
  vr_fit_result_free(&r);
  vr_model_destroy(truth);
  vr_ellipso_data_free(&d);
  gsl_rng_free(rng);
  return 0;
}
