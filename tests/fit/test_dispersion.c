/* Dispersion models against published values (CompleteEase output shipped
 * with refellips, pyElli's regression vectors, the SCHOTT catalogue), the
 * Kramers-Kronig consistency of every oscillator, the effective-medium rules,
 * and the edge cases and errors of each model. */
#include "vr_test.h"
#include <pthread.h>
#include "vr/dispersion.h"
#include "dispersion_internal.h"

/* pyElli converts with hc = c * scipy.constants.value("Planck constant in
 * eV/Hz"), and SciPy's CODATA 2018 table holds that constant cut to
 * 4.135667696e-15, so pyElli's hc is 1239.8419840550368 eV nm (2e-10 below
 * the exact value, which shows at 1e-8 on steep peaks).  pyelli_nm gives
 * the wavelength at which our VR_HC_EV_NM yields pyElli's photon energy. */
#define PYELLI_HC 1239.8419840550368
static double pyelli_nm(double nm) { return nm * VR_HC_EV_NM / PYELLI_HC; }
static double nm_of_ev(double E) { return VR_HC_EV_NM / E; }

static vr_dispersion *genosc(double eps_inf, size_t nterms, const vr_osc_kind *kinds,
                             const double *params) {
  vr_error err = {0};
  vr_dispersion *d = vr_dispersion_create(VR_DISP_GENOSC, &err);
  assert_non_null(d);
  for (size_t t = 0; t < nterms; t++)
    assert_int_equal(vr_dispersion_add_term(d, kinds[t], &err), VR_OK);
  double *p = vr_dispersion_params(d);
  p[0] = eps_inf;
  for (size_t i = 1; i < vr_dispersion_nparams(d); i++) p[i] = params[i - 1];
  return d;
}

static vr_complex eps_at(const vr_dispersion *d, double nm) {
  vr_error err = {0};
  vr_complex e = 0;
  vr_status st = vr_dispersion_eps(d, nm, &e, &err);
  if (st != VR_OK) fail_msg("eps at %g nm: %s", nm, err.message);
  return e;
}

/* ---- published reference values ------------------------------------------- */

static void tauc_lorentz_against_complete_ease(void **state) {
  (void)state;
  /* refellips, tests/test_refellips.py test_TaucLorentz_against_CompleteEase
   * and tests/TaucLorentz_fromCompleteEase.txt (J.A. Woollam CompleteEase):
   * Am = [22, 154], C = [0.9, 1.6], En = [1.2, 3.4], shared Eg = 1.1,
   * eps_inf = 1.  Rows E, eps1, eps2.  (The file's 2.296296 eV row is the
   * one meant by "2.296 eV"; at 2.296 eV itself eps1 is 8e-5 lower.) */
  static const vr_osc_kind kinds[] = {VR_OSC_TAUC_LORENTZ, VR_OSC_TAUC_LORENTZ};
  static const double p[] = {22, 1.2, 0.9, 1.1, 154, 3.4, 1.6, 1.1};
  static const double ref[][3] = {
      {4.96, -11.960728, 10.926159},    {3.1, 24.94788, 38.46854},
      {2.296296, 30.564774, 10.627457}, {1.69863, 24.873669, 3.271291},
      {1.252525, 21.773237, 0.492656},
  };
  vr_dispersion *d = genosc(1, 2, kinds, p);
  for (size_t i = 0; i < sizeof ref / sizeof ref[0]; i++) {
    vr_complex e = eps_at(d, nm_of_ev(ref[i][0]));
    assert_rel(creal(e), ref[i][1], 1e-5);
    assert_rel(cimag(e), ref[i][2], 1e-5);
  }
  vr_dispersion_destroy(d);
}

static void tauc_lorentz_against_pyelli(void **state) {
  (void)state;
  /* pyElli tests/test_dispersions.py, TaucLorentz custom values: Eg = 2,
   * (A, E, C) = (100, 2.5, 0.1), (150, 3, 0.05), (300, 4.5, 0.02), no
   * eps_inf; tests/test_dispersions/TaucLorentz_custom_values.csv.  Narrow
   * widths make this a hard case for the closed form. */
  static const vr_osc_kind kinds[] = {VR_OSC_TAUC_LORENTZ, VR_OSC_TAUC_LORENTZ,
                                      VR_OSC_TAUC_LORENTZ};
  static const double p[] = {100, 2.5, 0.1, 2, 150, 3, 0.05, 2, 300, 4.5, 0.02, 2};
  static const double ref[][3] = {
      {400.0, -40.67006475806415, 23.276498948468173},
      {413.22645290581164, 39.0645616272613, 334.5409129879007},
      {499.7995991983968, 65.8814921576357, 33.159943411731454},
      {618.8376753507014, 39.83128602466663, 3.6511799674489147e-05},
      {620.0400801603207, 39.74618527790294, 0.0},
      {794.3887775551102, 33.46386428774407, 0.0},
  };
  vr_dispersion *d = genosc(0, 3, kinds, p);
  for (size_t i = 0; i < sizeof ref / sizeof ref[0]; i++) {
    vr_complex e = eps_at(d, pyelli_nm(ref[i][0]));
    assert_rel(creal(e), ref[i][1], 1e-8);
    assert_rel(cimag(e), ref[i][2], 1e-7);
  }
  vr_dispersion_destroy(d);
}

static void gaussian_against_pyelli(void **state) {
  (void)state;
  /* pyElli tests/test_dispersions.py, Gaussian custom values: (A, E, sigma
   * = FWHM) = (100, 3, 0.1), (150, 1.5, 0.05), (300, 0.3, 0.02), no eps_inf;
   * tests/test_dispersions/Gaussian_custom_values.csv. */
  static const vr_osc_kind kinds[] = {VR_OSC_GAUSSIAN, VR_OSC_GAUSSIAN, VR_OSC_GAUSSIAN};
  static const double p[] = {100, 3, 0.1, 150, 1.5, 0.05, 300, 0.3, 0.02};
  static const double ref[][3] = {
      {400.0, -43.91081577811, 6.388144540964682},
      {413.22645290581164, -1.4409363608247854, 99.99570585881557},
      {424.0480961923848, 54.66009413307467, 20.011266783562608},
      {550.3006012024048, 2.2510254003793504, 6.513828538847326e-66},
      {724.6492985971944, -8.460062918229001, 5.519331610091654e-20},
  };
  vr_dispersion *d = genosc(0, 3, kinds, p);
  for (size_t i = 0; i < sizeof ref / sizeof ref[0]; i++) {
    vr_complex e = eps_at(d, pyelli_nm(ref[i][0]));
    assert_rel(creal(e), ref[i][1], 1e-9);
    assert_rel(cimag(e), ref[i][2], 1e-9);
  }
  vr_dispersion_destroy(d);
}

static void cauchy_value(void **state) {
  (void)state;
  /* Cauchy(A = 1.47, B = 0.00495 um^2), as in refellips' test_mixedslab:
   * n(300 nm) = 1.47 + 0.00495 / 0.3^2 = 1.525 by hand. */
  vr_error err = {0};
  vr_dispersion *d = vr_dispersion_create(VR_DISP_CAUCHY, &err);
  assert_int_equal(vr_dispersion_nparams(d), 6);
  double *p = vr_dispersion_params(d);
  assert_near(p[0], 1.5, 0); /* documented default */
  p[vr_dispersion_param_index(d, "A")] = 1.47;
  p[vr_dispersion_param_index(d, "B")] = 0.00495;
  vr_complex N;
  assert_int_equal(vr_dispersion_index(d, 300, &N, &err), VR_OK);
  assert_near(creal(N), 1.525, 1e-12);
  assert_near(cimag(N), 0, 0);
  vr_complex e = eps_at(d, 300);
  assert_near(creal(e), 1.525 * 1.525, 1e-12);
  /* Urbach tail: k = k_amp exp(k_exp (E - band_edge)), at E = band_edge it
   * is k_amp. */
  p[3] = 0.01;
  p[4] = 1.5;
  p[5] = VR_HC_EV_NM / 300;
  assert_int_equal(vr_dispersion_index(d, 300, &N, &err), VR_OK);
  assert_near(cimag(N), 0.01, 1e-15);
  vr_dispersion_destroy(d);
}

static void sellmeier_nbk7(void **state) {
  (void)state;
  /* SCHOTT N-BK7 data sheet: B1..3 = 1.03961212, 0.231792344, 1.01046945,
   * C1..3 = 0.00600069867, 0.0200179144, 103.560653 um^2; nd = 1.51680 at
   * 587.56 nm (the helium d line). */
  static const double B[] = {1.03961212, 0.231792344, 1.01046945};
  static const double C[] = {0.00600069867, 0.0200179144, 103.560653};
  vr_error err = {0};
  vr_dispersion *d2 = vr_dispersion_create(VR_DISP_SELLMEIER2, &err);
  vr_dispersion *d1 = vr_dispersion_create(VR_DISP_SELLMEIER, &err);
  for (int t = 0; t < 3; t++) {
    assert_int_equal(vr_dispersion_add_term(d2, VR_OSC_LORENTZ, &err), VR_OK);
    assert_int_equal(vr_dispersion_add_term(d1, VR_OSC_LORENTZ, &err), VR_OK);
  }
  assert_int_equal(vr_dispersion_nparams(d2), 7);
  assert_string_equal(vr_dispersion_param_name(d2, 5), "B3");
  assert_string_equal(vr_dispersion_param_name(d2, 6), "C3");
  double *p2 = vr_dispersion_params(d2), *p1 = vr_dispersion_params(d1);
  for (int t = 0; t < 3; t++) {
    p2[1 + 2 * t] = p1[1 + 2 * t] = B[t];
    p2[2 + 2 * t] = C[t];
    p1[2 + 2 * t] = sqrt(C[t]); /* the plain form takes C in um */
  }
  vr_complex N;
  assert_int_equal(vr_dispersion_index(d2, 587.56, &N, &err), VR_OK);
  assert_near(creal(N), 1.516800, 1e-6);
  assert_true(cimag(N) == 0);
  assert_int_equal(vr_dispersion_index(d1, 587.56, &N, &err), VR_OK);
  assert_near(creal(N), 1.516800, 1e-6);
  vr_dispersion_destroy(d1);
  vr_dispersion_destroy(d2);
}

/* ---- closed forms of the simple oscillators ------------------------------- */

static void lorentz_and_drude(void **state) {
  (void)state;
  /* Woollam Lorentz Amp En Br / (En^2 - E^2 - i Br E): at E = En it is
   * i Amp exactly (Amp is the peak eps2). */
  static const vr_osc_kind lor[] = {VR_OSC_LORENTZ};
  static const double pl[] = {7.5, 2.5, 0.3};
  vr_dispersion *d = genosc(2.1, 1, lor, pl);
  vr_complex e;
  assert_int_equal(vr_osc_eps(VR_OSC_LORENTZ, pl, 2.5, &e, NULL), VR_OK);
  assert_near(creal(e), 0, 1e-15);
  assert_near(cimag(e), 7.5, 1e-14);
  e = eps_at(d, nm_of_ev(2.5));
  assert_near(creal(e), 2.1, 1e-8);
  assert_near(cimag(e), 7.5, 1e-8);
  vr_dispersion_destroy(d);

  /* Drude, silver-like plasma energy 9 eV (Amp = 81 eV^2), Br = 0.02 eV,
   * eps_inf = 1: eps = 1 - 81 / (E^2 + i Br E), by hand at 2 eV. */
  static const vr_osc_kind dru[] = {VR_OSC_DRUDE};
  double pd[] = {81, 0.02};
  d = genosc(1, 1, dru, pd);
  e = eps_at(d, nm_of_ev(2.0));
  vr_complex hand = 1 - 81 / (4.0 + 0.04 * I);
  assert_rel(creal(e), creal(hand), 1e-12);
  assert_rel(cimag(e), cimag(hand), 1e-12);
  assert_true(cimag(e) > 0);
  /* Free-electron limit Br = 0: eps = 1 - (Ep/E)^2 vanishes at the plasma
   * energy and is real. */
  vr_dispersion_params(d)[2] = 0;
  e = eps_at(d, nm_of_ev(9.0));
  assert_near(creal(e), 0, 1e-12);
  assert_true(cimag(e) == 0);
  vr_dispersion_destroy(d);
}

/* ---- Kramers-Kronig consistency ---------------------------------------------- */

static void kk_matches_closed_forms(void **state) {
  (void)state;
  /* Each closed-form eps1 against the numerical transform of the same term's
   * eps2, at energies below, on and above the features (Eg and En exactly
   * included for Tauc-Lorentz). */
  static const struct {
    vr_osc_kind kind;
    double p[4];
  } cases[] = {
      {VR_OSC_GAUSSIAN, {5, 3, 0.8}},
      {VR_OSC_GAUSSIAN, {300, 0.3, 0.02}},
      {VR_OSC_TAUC_LORENTZ, {154, 3.4, 1.6, 1.1}},
      {VR_OSC_TAUC_LORENTZ, {22, 1.2, 0.9, 1.1}},
      {VR_OSC_TAUC_LORENTZ, {300, 4.5, 0.02, 2}},
      {VR_OSC_TAUC_LORENTZ, {50, 2, 3.99, 1}}, /* nearly critically damped */
      {VR_OSC_LORENTZ, {10, 3, 0.3}},
      {VR_OSC_LORENTZ, {1, 0.2, 2}},
      {VR_OSC_DRUDE, {81, 0.5}},
  };
  static const double energies[] = {0.05, 0.5, 1.1, 1.2, 2, 2.9, 3, 3.4, 4.5, 4.96, 9, 30};
  for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++)
    for (size_t i = 0; i < sizeof energies / sizeof energies[0]; i++) {
      double E = energies[i], kk;
      vr_complex closed;
      vr_error err = {0};
      assert_int_equal(vr_osc_eps(cases[c].kind, cases[c].p, E, &closed, &err), VR_OK);
      if (vr_osc_eps1_kk(cases[c].kind, cases[c].p, E, &kk, &err) != VR_OK)
        fail_msg("case %zu E %g: %s", c, E, err.message);
      double scale = fmax(fabs(creal(closed)), 1e-3 * cases[c].p[0]);
      if (fabs(kk - creal(closed)) > 1e-7 * scale)
        fail_msg("case %zu (%s) at %g eV: closed %.12g, KK %.12g", c,
                 vr_osc_kind_name(cases[c].kind), E, creal(closed), kk);
    }
}

static void tauc_lorentz_overdamped_is_continuous(void **state) {
  (void)state;
  /* Above C = 2 En the closed form has no real alpha and the numerical
   * transform takes over; the two must meet at the switch. */
  double below[] = {50, 1.2, 2.4 * (1 - 1e-7), 0.8}, above[] = {50, 1.2, 2.4 * (1 + 1e-7), 0.8};
  double over[] = {50, 1.2, 5, 0.8};
  for (double E = 0.3; E < 8; E += 0.7) {
    vr_complex a, b, o;
    assert_int_equal(vr_osc_eps(VR_OSC_TAUC_LORENTZ, below, E, &a, NULL), VR_OK);
    assert_int_equal(vr_osc_eps(VR_OSC_TAUC_LORENTZ, above, E, &b, NULL), VR_OK);
    assert_near(creal(a), creal(b), 1e-5 * fmax(1, fabs(creal(a))));
    assert_int_equal(vr_osc_eps(VR_OSC_TAUC_LORENTZ, over, E, &o, NULL), VR_OK);
    assert_true(isfinite(creal(o)) && cimag(o) >= 0);
  }
}

static void tauc_lorentz_removable_points(void **state) {
  (void)state;
  /* E = Eg (where the printed closed form is inf - inf) and E = En must be
   * ordinary points: finite and continuous with their neighbours. */
  const double p[] = {154, 3.4, 1.6, 1.1};
  const double at[] = {1.1, 3.4};
  for (int i = 0; i < 2; i++) {
    vr_complex e0, em, ep;
    assert_int_equal(vr_osc_eps(VR_OSC_TAUC_LORENTZ, p, at[i], &e0, NULL), VR_OK);
    assert_int_equal(vr_osc_eps(VR_OSC_TAUC_LORENTZ, p, at[i] * (1 - 1e-9), &em, NULL), VR_OK);
    assert_int_equal(vr_osc_eps(VR_OSC_TAUC_LORENTZ, p, at[i] * (1 + 1e-9), &ep, NULL), VR_OK);
    assert_true(isfinite(creal(e0)) && isfinite(cimag(e0)));
    assert_near(creal(e0), creal(em), 1e-6);
    assert_near(creal(e0), creal(ep), 1e-6);
    assert_near(cimag(e0), cimag(ep), 1e-6);
  }
  vr_complex e;
  assert_int_equal(vr_osc_eps(VR_OSC_TAUC_LORENTZ, p, 1.1, &e, NULL), VR_OK);
  assert_true(cimag(e) == 0); /* eps2 = 0 at and below the gap */
  assert_int_equal(vr_osc_eps(VR_OSC_TAUC_LORENTZ, p, 0.7, &e, NULL), VR_OK);
  assert_true(cimag(e) == 0 && creal(e) > 0);
  /* Through the model, at the wavelengths of Eg and En. */
  static const vr_osc_kind k[] = {VR_OSC_TAUC_LORENTZ};
  vr_dispersion *d = genosc(1, 1, k, p);
  for (int i = 0; i < 2; i++) {
    vr_complex N;
    assert_int_equal(vr_dispersion_index(d, nm_of_ev(at[i]), &N, NULL), VR_OK);
    assert_true(isfinite(creal(N)) && cimag(N) >= 0);
  }
  vr_dispersion_destroy(d);
}

static void narrow_widths(void **state) {
  (void)state;
  /* Br -> 0.  Lorentz and Gaussian terms vanish (Amp is their peak eps2, so
   * their strength goes with Br); Tauc-Lorentz keeps its strength and
   * becomes a lossless pole: from the closed form, C -> 0 gives
   * eps1 = A (E0 - Eg)^2 / (E0 (E0^2 - E^2)) (derived by hand). */
  vr_complex e;
  const double lz[] = {5, 2, 0}, ga[] = {5, 2, 0};
  assert_int_equal(vr_osc_eps(VR_OSC_LORENTZ, lz, 2, &e, NULL), VR_OK);
  assert_true(e == 0);
  assert_int_equal(vr_osc_eps(VR_OSC_GAUSSIAN, ga, 2, &e, NULL), VR_OK);
  assert_true(e == 0);
  const double tl[] = {154, 3.4, 1e-7, 1.1};
  double E = 2, pole = 154 * 2.3 * 2.3 / (3.4 * (3.4 * 3.4 - E * E));
  assert_int_equal(vr_osc_eps(VR_OSC_TAUC_LORENTZ, tl, E, &e, NULL), VR_OK);
  assert_rel(creal(e), pole, 1e-6);
  assert_near(cimag(e), 0, 1e-6);
  /* Right on the pole it is large but finite for any C > 0. */
  assert_int_equal(vr_osc_eps(VR_OSC_TAUC_LORENTZ, tl, 3.4, &e, NULL), VR_OK);
  assert_true(isfinite(creal(e)) && isfinite(cimag(e)) && cimag(e) > 1e6);
}

/* ---- Cody-Lorentz -------------------------------------------------------------- */

static void cody_lorentz(void **state) {
  (void)state;
  /* pyElli's defaults (src/elli/dispersions/cody_lorentz.py): Amp = 100,
   * En = 3.6, Br = 2.4, Eg = 1.6, Ep = 0.8, Et = 1.8, Eu = 0.05.  No
   * published eps(E) vector was found (pyElli has no regression file for it),
   * so the checks are the definition, continuity, and a reduction to the
   * Lorentz closed form. */
  const double p[] = {100, 3.6, 2.4, 1.6, 0.8, 1.8, 0.05};
  /* eps2 above Et from Ferlauto et al. JAP 92, 2424, eqs. 5-6, by hand. */
  double E = 3, G = (E - 1.6) * (E - 1.6) / ((E - 1.6) * (E - 1.6) + 0.64);
  double L = 100 * 3.6 * 2.4 * E / ((E * E - 12.96) * (E * E - 12.96) + 5.76 * E * E);
  assert_rel(vr_osc_eps2(VR_OSC_CODY_LORENTZ, p, E), G * L, 1e-14);
  /* Continuous at Et, with no jump either side. */
  double at = vr_osc_eps2(VR_OSC_CODY_LORENTZ, p, 1.8);
  assert_rel(vr_osc_eps2(VR_OSC_CODY_LORENTZ, p, 1.8 * (1 - 1e-10)), at, 1e-8);
  assert_rel(vr_osc_eps2(VR_OSC_CODY_LORENTZ, p, 1.8 * (1 + 1e-10)), at, 1e-8);
  /* The Urbach tail keeps eps2 > 0 below Eg, falling with slope 1/Eu in ln. */
  double a = vr_osc_eps2(VR_OSC_CODY_LORENTZ, p, 1.5), b = vr_osc_eps2(VR_OSC_CODY_LORENTZ, p, 1.4);
  assert_true(a > 0 && b > 0);
  assert_rel(log(a * 1.5 / (b * 1.4)), 0.1 / 0.05, 1e-12);
  /* eps1 finite everywhere, including on Et and Eg exactly. */
  static const double energies[] = {0.2, 1.4, 1.6, 1.8, 2.5, 3.6, 6, 40};
  for (size_t i = 0; i < sizeof energies / sizeof energies[0]; i++) {
    vr_complex e;
    vr_error err = {0};
    if (vr_osc_eps(VR_OSC_CODY_LORENTZ, p, energies[i], &e, &err) != VR_OK)
      fail_msg("%g eV: %s", energies[i], err.message);
    assert_true(isfinite(creal(e)) && cimag(e) >= 0);
  }
  /* With Eg = Ep = Et = Eu = 0 the gap factor is 1 and there is no tail, so
   * eps2 is the Lorentz A E0 Br E / ((E^2 - E0^2)^2 + Br^2 E^2), i.e. the
   * Woollam Lorentz term with Amp = A / Br, whose closed-form eps1 the
   * numerical eps1 must reproduce. */
  const double bare[] = {100, 3.6, 2.4, 0, 0, 0, 0}, lor[] = {100 / 2.4, 3.6, 2.4};
  for (double e = 0.25; e < 12; e *= 1.7) {
    vr_complex c, l;
    assert_int_equal(vr_osc_eps(VR_OSC_CODY_LORENTZ, bare, e, &c, NULL), VR_OK);
    assert_int_equal(vr_osc_eps(VR_OSC_LORENTZ, lor, e, &l, NULL), VR_OK);
    assert_rel(creal(c), creal(l), 1e-8);
    assert_rel(cimag(c), cimag(l), 1e-12);
  }
}

/* ---- B-spline ------------------------------------------------------------------- */

static double bump(double E) { return exp(-((E - 3) / 0.5) * ((E - 3) / 0.5)); }

static void bspline_spline_and_kk(void **state) {
  (void)state;
  /* Knot values sampled from a Gaussian bump; the spline reproduces it to
   * O(h^4) and its eps1 matches the Dawson closed form of that Gaussian
   * (the Gaussian term with Amp = 1, En = 3, FWHM = 2 sqrt(ln 2) 0.5; its
   * mirror term at -3 eV is e^-36 and the bump at the end knots e^-25). */
  enum { N = 111 };
  double knots[N];
  for (int i = 0; i < N; i++) knots[i] = 0.5 + 0.05 * i;
  vr_error err = {0};
  vr_dispersion *d = vr_dispersion_create(VR_DISP_BSPLINE, &err);
  vr_complex e;
  assert_int_equal(vr_dispersion_eps(d, 500, &e, &err), VR_E_ARG); /* no knots yet */
  assert_int_equal(vr_dispersion_set_knots(d, N, knots, &err), VR_OK);
  assert_int_equal(vr_dispersion_nparams(d), N + 1);
  assert_string_equal(vr_dispersion_param_name(d, 1), "eps2_1");
  double *p = vr_dispersion_params(d);
  p[0] = 1.7;
  for (int i = 0; i < N; i++) p[1 + i] = bump(knots[i]);
  const double g[] = {1, 3, 2 * sqrt(log(2.0)) * 0.5};
  for (double E = 0.6; E < 6.5; E += 0.1234) {
    e = eps_at(d, nm_of_ev(E));
    vr_complex ref;
    assert_int_equal(vr_osc_eps(VR_OSC_GAUSSIAN, g, E, &ref, NULL), VR_OK);
    /* Not-a-knot error bound (5/384) h^4 max|f''''| = 1.6e-5 here. */
    if (E <= 6) assert_near(cimag(e), bump(E), 1e-5);
    else assert_true(cimag(e) == 0); /* beyond the last knot */
    assert_near(creal(e), 1.7 + creal(ref), 1e-5);
  }
  /* A step at the last knot: the transform diverges exactly there. */
  p[N] = 0.5;
  assert_int_equal(vr_dispersion_eps(d, nm_of_ev(knots[N - 1]), &e, &err), VR_E_NUMERIC);
  assert_contains(err.message, "diverges");
  /* Knots must increase. */
  knots[5] = knots[4];
  assert_int_equal(vr_dispersion_set_knots(d, N, knots, &err), VR_E_ARG);
  assert_contains(err.message, "knot 5");
  vr_dispersion_destroy(d);
}

/* ---- effective media ------------------------------------------------------------- */

static void ema(void **state) {
  (void)state;
  vr_complex ea = 2.1 + 0.01 * I, eb = -15 + 1.2 * I; /* glass-like and silver-like */
  assert_true(vr_ema_bruggeman(ea, eb, 0) == ea);
  assert_true(vr_ema_bruggeman(ea, eb, 1) == eb);
  for (double f = 0.05; f < 1; f += 0.1) {
    vr_complex x = vr_ema_bruggeman(ea, eb, f), y = vr_ema_bruggeman(eb, ea, 1 - f);
    assert_near(creal(x), creal(y), 1e-12 * cabs(x));
    assert_near(cimag(x), cimag(y), 1e-12 * cabs(x));
    assert_true(cimag(x) >= 0);
    /* x solves the Bruggeman condition. */
    vr_complex r = f * (eb - x) / (eb + 2 * x) + (1 - f) * (ea - x) / (ea + 2 * x);
    assert_true(cabs(r) < 1e-12);
  }
  /* Small f: both rules are ea + 3 f ea (eb - ea) / (eb + 2 ea) + O(f^2)
   * (Aspnes, Thin Solid Films 89, 249 (1982)). */
  vr_complex a = 2.25, b = 1.0 + 0.5 * I;
  double f = 1e-4;
  vr_complex lin = a + 3 * f * a * (b - a) / (b + 2 * a);
  vr_complex br = vr_ema_bruggeman(a, b, f), mg = vr_ema_maxwell_garnett(a, b, f);
  assert_true(cabs(br - lin) < 10 * f * f);
  assert_true(cabs(mg - lin) < 10 * f * f);
  assert_true(cabs(vr_ema_maxwell_garnett(a, b, 0) - a) < 1e-15);
  assert_true(cabs(vr_ema_maxwell_garnett(a, b, 1) - b) < 1e-15);
  /* Known value, ea = 1, eb = 1.5^2, f = 0.5: b = 1.5 eb/2 + ... by hand,
   * 2e^2 - b e - ea eb = 0 with b = 0.5 * 2.25 + 0.5 * 1 = 1.625, so
   * e = (1.625 + sqrt(1.625^2 + 8 * 2.25)) / 4, the positive root. */
  double hand = (1.625 + sqrt(1.625 * 1.625 + 18)) / 4;
  vr_complex x = vr_ema_bruggeman(1, 2.25, 0.5);
  assert_near(creal(x), hand, 1e-14);
  assert_near(cimag(x), 0, 1e-14);
  assert_near(hand, 1.5420489, 1e-7);
  assert_true(isnan(creal(vr_ema_bruggeman(ea, eb, 1.5))));
}

static void eps_to_index_branch(void **state) {
  (void)state;
  vr_complex N = vr_eps_to_index(2.25);
  assert_near(creal(N), 1.5, 0);
  N = vr_eps_to_index(CMPLX(-4, -0.0)); /* a lossless metal, with a signed zero */
  assert_near(creal(N), 0, 0);
  assert_near(cimag(N), 2, 0);
  vr_complex n = 0.13 + 3.9 * I; /* silver-like */
  N = vr_eps_to_index(n * n);
  assert_near(creal(N), 0.13, 1e-14);
  assert_near(cimag(N), 3.9, 1e-14);
}

/* ---- structure, tabulated, errors ----------------------------------------------- */

static void names_copy_and_tabulated(void **state) {
  (void)state;
  vr_error err = {0};
  static const vr_osc_kind kinds[] = {VR_OSC_TAUC_LORENTZ, VR_OSC_CODY_LORENTZ, VR_OSC_DRUDE};
  static const double p[] = {20, 3, 1, 1.2, 100, 3.6, 2.4, 1.6, 0.8, 1.8, 0.05, 4, 0.1};
  vr_dispersion *d = genosc(1.5, 3, kinds, p);
  assert_int_equal(vr_dispersion_nparams(d), 14);
  assert_string_equal(vr_dispersion_param_name(d, 0), "eps_inf");
  assert_string_equal(vr_dispersion_param_name(d, 3), "C1");
  assert_string_equal(vr_dispersion_param_name(d, 11), "Eu2");
  assert_string_equal(vr_dispersion_param_name(d, 13), "Br3");
  assert_null(vr_dispersion_param_name(d, 14));
  assert_int_equal(vr_dispersion_param_index(d, "Eg2"), 8);
  assert_int_equal(vr_dispersion_param_index(d, "nope"), -1);
  vr_dispersion *c = vr_dispersion_copy(d, &err);
  assert_non_null(c);
  vr_complex e1 = eps_at(d, 600), e2 = eps_at(c, 600);
  assert_true(e1 == e2);
  vr_dispersion_params(c)[0] = 3;
  assert_near(creal(eps_at(c, 600) - eps_at(d, 600)), 1.5, 1e-12);
  vr_dispersion_destroy(c);
  assert_int_equal(vr_dispersion_add_term(d, (vr_osc_kind)42, &err), VR_E_ARG);
  vr_dispersion_destroy(d);

  double nm[] = {400, 500, 600}, nv[] = {1.6, 1.55, 1.52}, kv[] = {0.1, 0.05, 0};
  vr_spectrum *sn = vr_spectrum_create(3, nm, nv, &err), *sk = vr_spectrum_create(3, nm, kv, &err);
  d = vr_dispersion_tabulated(sn, sk, &err);
  assert_non_null(d);
  assert_int_equal(vr_dispersion_nparams(d), 0);
  vr_complex N;
  assert_int_equal(vr_dispersion_index(d, 500, &N, &err), VR_OK);
  assert_near(creal(N), 1.55, 1e-15);
  assert_near(cimag(N), 0.05, 1e-15);
  assert_int_equal(vr_dispersion_index(d, 650, &N, &err), VR_E_RANGE);
  assert_contains(err.message, "650 nm");
  vr_dispersion *nk = vr_dispersion_tabulated(sn, NULL, &err); /* k = 0 */
  assert_int_equal(vr_dispersion_index(nk, 450, &N, &err), VR_OK);
  assert_true(cimag(N) == 0 && creal(N) > 1.55 && creal(N) < 1.6);
  vr_dispersion_destroy(nk);
  vr_dispersion *t = vr_dispersion_copy(d, &err);
  assert_int_equal(vr_dispersion_index(t, 450, &N, &err), VR_OK);
  vr_dispersion_destroy(t);
  vr_dispersion_destroy(d);
  kv[1] = -0.01;
  vr_spectrum *bad = vr_spectrum_create(3, nm, kv, &err);
  assert_null(vr_dispersion_tabulated(sn, bad, &err));
  assert_int_equal(err.status, VR_E_RANGE);
  assert_contains(err.message, "k = -0.01");
  vr_spectrum_destroy(bad);
  vr_spectrum_destroy(sn);
  vr_spectrum_destroy(sk);
}

static void errors_name_the_parameter(void **state) {
  (void)state;
  vr_error err = {0};
  vr_complex e;
  /* A negative Tauc-Lorentz width. */
  static const vr_osc_kind k2[] = {VR_OSC_LORENTZ, VR_OSC_TAUC_LORENTZ};
  double p[] = {1, 3, 0.5, 20, 3, -0.5, 1.2};
  vr_dispersion *d = genosc(1, 2, k2, p);
  assert_int_equal(vr_dispersion_eps(d, 500, &e, &err), VR_E_RANGE);
  assert_contains(err.message, "C2");
  /* A negative amplitude in the first term. */
  double *q = vr_dispersion_params(d);
  q[6] = 0.5;
  q[1] = -1;
  assert_int_equal(vr_dispersion_eps(d, 500, &e, &err), VR_E_RANGE);
  assert_contains(err.message, "Amp1");
  q[1] = 1;
  q[vr_dispersion_param_index(d, "En2")] = 0;
  assert_int_equal(vr_dispersion_index(d, 500, &e, &err), VR_E_RANGE);
  assert_contains(err.message, "En2");
  vr_dispersion_destroy(d);

  /* A Sellmeier pole on the wavelength. */
  d = vr_dispersion_create(VR_DISP_SELLMEIER, &err);
  assert_int_equal(vr_dispersion_add_term(d, VR_OSC_LORENTZ, &err), VR_OK);
  q = vr_dispersion_params(d);
  q[1] = 1;
  q[2] = 0.5; /* um */
  assert_int_equal(vr_dispersion_eps(d, 500, &e, &err), VR_E_NUMERIC);
  assert_contains(err.message, "500 nm");
  assert_contains(err.message, "C1");
  /* Just short of the pole n^2 < 0: outside the model's domain. */
  assert_int_equal(vr_dispersion_eps(d, 450, &e, &err), VR_E_RANGE);
  assert_contains(err.message, "450 nm");
  vr_dispersion_destroy(d);

  d = vr_dispersion_create(VR_DISP_CONSTANT, &err);
  vr_dispersion_params(d)[1] = -0.2;
  assert_int_equal(vr_dispersion_index(d, 500, &e, &err), VR_E_RANGE);
  assert_contains(err.message, "k = -0.2");
  assert_int_equal(vr_dispersion_add_term(d, VR_OSC_LORENTZ, &err), VR_E_ARG);
  assert_int_equal(vr_dispersion_set_knots(d, 0, NULL, &err), VR_E_ARG);
  vr_dispersion_params(d)[1] = 0;
  assert_int_equal(vr_dispersion_eps(d, 0, &e, &err), VR_E_ARG);
  assert_int_equal(vr_dispersion_eps(d, NAN, &e, &err), VR_E_ARG);
  vr_dispersion_destroy(d);

  d = vr_dispersion_create(VR_DISP_CAUCHY, &err);
  vr_dispersion_params(d)[3] = -1e-3;
  assert_int_equal(vr_dispersion_eps(d, 500, &e, &err), VR_E_RANGE);
  assert_contains(err.message, "k_amp");
  vr_dispersion_destroy(d);

  assert_null(vr_dispersion_create(VR_DISP_TABULATED, &err));
  assert_int_equal(err.status, VR_E_ARG);
}

/* ---- thread safety ---------------------------------------------------------- */

enum { NWAVE = 40 };
typedef struct job {
  const vr_dispersion *d;
  vr_complex out[NWAVE];
} job;

static void *evaluate_all(void *arg) {
  job *j = arg;
  for (int i = 0; i < NWAVE; i++)
    if (vr_dispersion_eps(j->d, 250 + 20 * i, &j->out[i], NULL) != VR_OK) j->out[i] = NAN;
  return NULL;
}

static void concurrent_evaluation(void **state) {
  (void)state;
  /* One model read by several threads at once (the numerical transform
   * included) gives the same numbers as one thread: no shared scratch. */
  static const vr_osc_kind kinds[] = {VR_OSC_CODY_LORENTZ, VR_OSC_TAUC_LORENTZ,
                                      VR_OSC_GAUSSIAN};
  static const double p[] = {100, 3.6, 2.4, 1.6, 0.8, 1.8, 0.05, 20, 4, 2.5, 1.2, 1, 6, 0.5};
  vr_dispersion *d = genosc(1.2, 3, kinds, p);
  job serial = {d, {0}}, jobs[4];
  evaluate_all(&serial);
  pthread_t th[4];
  for (int t = 0; t < 4; t++) {
    jobs[t].d = d;
    assert_int_equal(pthread_create(&th[t], NULL, evaluate_all, &jobs[t]), 0);
  }
  for (int t = 0; t < 4; t++) {
    pthread_join(th[t], NULL);
    assert_memory_equal(jobs[t].out, serial.out, sizeof serial.out);
  }
  vr_dispersion_destroy(d);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(tauc_lorentz_against_complete_ease),
      cmocka_unit_test(tauc_lorentz_against_pyelli),
      cmocka_unit_test(gaussian_against_pyelli),
      cmocka_unit_test(cauchy_value),
      cmocka_unit_test(sellmeier_nbk7),
      cmocka_unit_test(lorentz_and_drude),
      cmocka_unit_test(kk_matches_closed_forms),
      cmocka_unit_test(tauc_lorentz_overdamped_is_continuous),
      cmocka_unit_test(tauc_lorentz_removable_points),
      cmocka_unit_test(narrow_widths),
      cmocka_unit_test(cody_lorentz),
      cmocka_unit_test(bspline_spline_and_kk),
      cmocka_unit_test(ema),
      cmocka_unit_test(eps_to_index_branch),
      cmocka_unit_test(names_copy_and_tabulated),
      cmocka_unit_test(errors_name_the_parameter),
      cmocka_unit_test(concurrent_evaluation),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
