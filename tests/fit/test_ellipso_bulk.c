/* Bulk samples without a model (issue: never silently wrong): a Drude
 * metal, an ITO-like Drude + Lorentz absorber and crystalline Si, simulated
 * at 65, 70 and 75 deg over 300-820 nm (the range of the Si table) and fitted by vr_ellipso_fit_bulk.
 * The truth is the simulating model's n, k; the exact two-phase inversion
 * <eps> = sin²θ [1 + tan²θ ((1 - ρ)/(1 + ρ))²] (Azzam & Bashara,
 * "Ellipsometry and Polarized Light", eq. 4.94) returns it, so the answer
 * must be within 1e-3 of it, or flagged. */
#include "vr_test.h"
#include "vr/ellipso_fit.h"

#include <complex.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

static vr_sample_model *model(const char *text) {
  vr_sample_model *m = NULL;
  vr_error err = {0};
  if (vr_model_parse(text, strlen(text), "truth.model", VR_SOURCE_DIR, NULL, &m, &err))
    fail_msg("%s", err.message);
  return m;
}

/* Ψ, Δ of the truth at 3 angles x 300..820 nm step 10, with Gaussian
 * noise of s degrees (0: none). */
static void simulate(const vr_sample_model *m, double s, vr_ellipso_data *d) {
  memset(d, 0, sizeof *d);
  d->p = calloc(3 * 53, sizeof *d->p);
  assert_non_null(d->p);
  d->source = strdup("simulated");
  d->has_sigma = s > 0;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 7);
  const double angles[3] = {65, 70, 75};
  for (int a = 0; a < 3; a++)
    for (int i = 0; i <= 52; i++) {
      vr_ellipso_point *p = &d->p[d->n++];
      p->nm = 300 + 10 * i;
      p->aoi_deg = angles[a];
      vr_error err = {0};
      if (vr_model_psi_delta(m, p->nm, p->aoi_deg, &p->psi_deg, &p->delta_deg, NULL, &err))
        fail_msg("%s", err.message);
      if (s > 0) {
        p->psi_deg += gsl_ran_gaussian(rng, s);
        p->delta_deg += gsl_ran_gaussian(rng, 5 * s);
      }
      p->sigma_psi = s > 0 ? s : 1.0;
      p->sigma_delta = s > 0 ? 5 * s : 1.0;
      p->depolarisation = p->sigma_depolarisation = p->bandwidth_nm = NAN;
      p->line = d->n;
    }
  gsl_rng_free(rng);
}

/* The truth's data with noise (simulate), fitted without a model: the
 * truth *t, its data *d, the fitted model *m and the result *r. */
static void fit_simulated(const char *truth, double noise, vr_sample_model **t, vr_ellipso_data *d,
                          vr_sample_model **m, vr_fit_result *r) {
  *t = model(truth);
  simulate(*t, noise, d);
  *m = NULL;
  memset(r, 0, sizeof *r);
  vr_error err = {0};
  if (vr_ellipso_fit_bulk(d, NULL, m, r, &err)) fail_msg("%s", err.message);
}

/* Fits without a model; returns the largest |N_fit - N_true| over the
 * data wavelengths, or -1 when the fit flagged itself. */
static double bulk_error(const char *truth, double noise, bool *inverted) {
  vr_sample_model *t, *m;
  vr_ellipso_data d;
  vr_fit_result r;
  fit_simulated(truth, noise, &t, &d, &m, &r);
  vr_error err = {0};
  *inverted = r.exact_inversion;
  double worst = 0;
  for (int i = 0; i <= 52; i++) {
    double nm = 300 + 10 * i;
    vr_complex a = 0, b = 0;
    if (vr_model_layer_index(m, VR_OWNER_SUBSTRATE, nm, &a, &err) ||
        vr_model_layer_index(t, VR_OWNER_SUBSTRATE, nm, &b, &err))
      fail_msg("%s", err.message);
    worst = fmax(worst, cabs(a - b));
  }
  print_message("%s (noise %g deg): %s, |dN| <= %.2e, %s\n", truth, noise,
                r.exact_inversion ? "exact inversion" : "smooth fit", worst, r.verdict);
  bool flagged = !r.describes;
  vr_fit_result_free(&r);
  vr_model_destroy(m);
  vr_model_destroy(t);
  vr_ellipso_data_free(&d);
  return flagged ? -1 : worst;
}

static void drude_metal(void **state) {
  (void)state;
  bool inv;
  /* A free-electron metal: plasma energy 9 eV, damping 0.1 eV. */
  double e = bulk_error("substrate genosc:drude\nparam substrate.Amp1 = 81\nparam substrate.Br1 = 0.1\n", 0, &inv);
  assert_true(e >= 0 && e <= 1e-3);
}

static void ito_like(void **state) {
  (void)state;
  bool inv;
  /* ITO-like: eps_inf 3.8, Drude (plasma 1.8 eV, damping 0.12 eV) and a UV
   * Lorentz band at 5.5 eV. */
  double e = bulk_error("substrate genosc:drude+lorentz\nparam substrate.eps_inf = 3.8\n"
                        "param substrate.Amp1 = 3.24\nparam substrate.Br1 = 0.12\n"
                        "param substrate.Amp2 = 2\nparam substrate.En2 = 5.5\nparam substrate.Br2 = 1\n",
                        0, &inv);
  assert_true(e >= 0 && e <= 1e-3);
}

static void crystalline_si(void **state) {
  (void)state;
  bool inv;
  /* c-Si (Aspnes & Studna 1983, refractiveindex.info), k up to 5 below 400 nm. */
  double e = bulk_error("substrate file:samples/ellipsometry/Si_Aspnes.yml\n", 0, &inv);
  assert_true(e >= 0 && e <= 1e-3);
}

/* The two-phase inversion of the header, written here on its own (air
 * ambient): n and |k| of the substrate from one (Ψ, Δ) at angle aoi. */
static void invert(double psi_deg, double delta_deg, double aoi_deg, double *n, double *k) {
  double d2r = M_PI / 180, th = aoi_deg * d2r;
  double complex rho = tan(psi_deg * d2r) * cexp(I * delta_deg * d2r);
  double complex q = (1 - rho) / (1 + rho);
  double complex N = csqrt(sin(th) * sin(th) * (1 + tan(th) * tan(th) * q * q));
  *n = creal(N);
  *k = fabs(cimag(N));
}

/* With noise of s = 0.01 deg in Ψ and 5 s in Δ, the answer is the exact
 * inversion (a Drude metal is no smooth B-spline ε2), and its n, k at each
 * wavelength scatter by the noise propagated through the inversion.  That
 * deviation is computed here, apart from the code: at each angle the
 * derivatives of the inversion above by central differences, σ_n² =
 * (∂n/∂Ψ s)² + (∂n/∂Δ 5s)² (the same for k), and the three angles combined
 * as the code combines them, weighted by 1/σ², σ = (Σ σ_a^-2)^-1/2.  Each of
 * the 106 values (n and k at 53 wavelengths) must be within K_NK of its σ:
 * for Gaussian errors the chance that any of 106 lies beyond 4.9 σ is at
 * most 106 x 9.6e-7 = 1e-4 (the noise is linearised: s is 1e-4 rad).  The
 * scatter is about 2e-3 in n and k. */
#define K_NK 4.9
static void noisy_metal(void **state) {
  (void)state;
  const char *truth = "substrate genosc:drude\nparam substrate.Amp1 = 81\nparam substrate.Br1 = 0.1\n";
  const double s = 0.01;
  vr_sample_model *t, *m;
  vr_ellipso_data d;
  vr_fit_result r;
  fit_simulated(truth, s, &t, &d, &m, &r);
  vr_error err = {0};
  assert_true(r.exact_inversion);
  assert_true(r.describes);
  double worst = 0, worst_abs = 0;
  for (int i = 0; i <= 52; i++) {
    double nm = 300 + 10 * i, wn = 0, wk = 0;
    for (int a = 0; a < 3; a++) {
      double aoi = 65 + 5 * a, psi, delta;
      if (vr_model_psi_delta(t, nm, aoi, &psi, &delta, NULL, &err)) fail_msg("%s", err.message);
      /* The inversion here reproduces the truth it is differentiated at. */
      double n0, k0;
      vr_complex N0 = 0;
      invert(psi, delta, aoi, &n0, &k0);
      if (vr_model_layer_index(t, VR_OWNER_SUBSTRATE, nm, &N0, &err)) fail_msg("%s", err.message);
      assert_true(fabs(n0 - creal(N0)) < 1e-9 && fabs(k0 - fabs(cimag(N0))) < 1e-9);
      const double h = 1e-4;
      double np, kp, nq, kq, dn[2], dk[2];
      invert(psi + h, delta, aoi, &np, &kp);
      invert(psi - h, delta, aoi, &nq, &kq);
      dn[0] = (np - nq) / (2 * h), dk[0] = (kp - kq) / (2 * h);
      invert(psi, delta + h, aoi, &np, &kp);
      invert(psi, delta - h, aoi, &nq, &kq);
      dn[1] = (np - nq) / (2 * h), dk[1] = (kp - kq) / (2 * h);
      double vn = pow(dn[0] * s, 2) + pow(dn[1] * 5 * s, 2);
      double vk = pow(dk[0] * s, 2) + pow(dk[1] * 5 * s, 2);
      wn += 1 / vn, wk += 1 / vk;
    }
    vr_complex a = 0, b = 0;
    if (vr_model_layer_index(m, VR_OWNER_SUBSTRATE, nm, &a, &err) ||
        vr_model_layer_index(t, VR_OWNER_SUBSTRATE, nm, &b, &err))
      fail_msg("%s", err.message);
    double en = fabs(creal(a) - creal(b)), ek = fabs(fabs(cimag(a)) - fabs(cimag(b)));
    worst = fmax(worst, fmax(en * sqrt(wn), ek * sqrt(wk)));
    worst_abs = fmax(worst_abs, cabs(a - b));
  }
  print_message("noisy Drude metal (0.01 deg): |dN| <= %.2e, largest error %.2f of its propagated "
                "deviation (bound %.1f)\n",
                worst_abs, worst, K_NK);
  assert_true(worst <= K_NK);
  vr_fit_result_free(&r);
  vr_model_destroy(m);
  vr_model_destroy(t);
  vr_ellipso_data_free(&d);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(drude_metal),
      cmocka_unit_test(ito_like),
      cmocka_unit_test(crystalline_si),
      cmocka_unit_test(noisy_metal),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
