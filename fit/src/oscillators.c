/* The terms of the general-oscillator (genosc) model: Lorentz, Drude,
 * Tauc-Lorentz, Cody-Lorentz and Gaussian contributions to ε(E), each from
 * its own short parameter vector, with E the photon energy in eV.  Every
 * term is Kramers-Kronig consistent: ε1 comes from a closed form where the
 * literature has one and from the numerical transform (bspline_kk.c)
 * otherwise. */
#include "dispersion_internal.h"

#include <gsl/gsl_sf_dawson.h>
#include <math.h>

typedef struct osc_info {
  const char *name;
  size_t nparams;
  const char *params[7];
  double defaults[7];
} osc_info;

/* Defaults are typical values (pyElli's templates for the Tauc-Lorentz,
 * Cody-Lorentz and Gaussian terms), so a new term evaluates at once. */
static const osc_info INFO[] = {
    [VR_OSC_LORENTZ] = {"lorentz", 3, {"Amp", "En", "Br"}, {1, 5, 1}},
    [VR_OSC_DRUDE] = {"drude", 2, {"Amp", "Br"}, {1, 0.1}},
    [VR_OSC_TAUC_LORENTZ] = {"tauc_lorentz", 4, {"Amp", "En", "C", "Eg"}, {20, 1.5, 1, 1}},
    [VR_OSC_CODY_LORENTZ] = {"cody_lorentz",
                             7,
                             {"Amp", "En", "Br", "Eg", "Ep", "Et", "Eu"},
                             {100, 3.6, 2.4, 1.6, 0.8, 1.8, 0.05}},
    [VR_OSC_GAUSSIAN] = {"gaussian", 3, {"Amp", "En", "Br"}, {1, 1, 1}},
};

static int known(vr_osc_kind kind) {
  return (int)kind >= 0 && (size_t)kind < sizeof INFO / sizeof INFO[0];
}

size_t vr_osc_nparams(vr_osc_kind kind) { return known(kind) ? INFO[kind].nparams : 0; }

const char *vr_osc_param_base(vr_osc_kind kind, size_t i) {
  return known(kind) && i < INFO[kind].nparams ? INFO[kind].params[i] : NULL;
}

const char *vr_osc_kind_name(vr_osc_kind kind) { return known(kind) ? INFO[kind].name : "?"; }

void vr_osc_defaults(vr_osc_kind kind, double *p) {
  for (size_t i = 0; i < vr_osc_nparams(kind); i++) p[i] = INFO[kind].defaults[i];
}

/* ---- parameter domains --------------------------------------------------- */

/* Which parameters must be >= 0 and which > 0: a negative amplitude gives
 * ε2 < 0 (a gain medium), a negative width or energy has no meaning, and
 * the Tauc-Lorentz C and Cody-Lorentz Br must be > 0 because those models
 * keep a finite oscillator strength as the width goes to 0 (a lossless pole,
 * infinite at En).  Lorentz, Gaussian and Drude terms stay finite as Br -> 0
 * (the first two vanish, Drude becomes the free-electron -Amp/E²). */
enum { NONNEG = 0, POSITIVE = 1 };
static const unsigned char DOMAIN[][7] = {
    [VR_OSC_LORENTZ] = {NONNEG, NONNEG, NONNEG},
    [VR_OSC_DRUDE] = {NONNEG, NONNEG},
    [VR_OSC_TAUC_LORENTZ] = {NONNEG, POSITIVE, POSITIVE, NONNEG},
    [VR_OSC_CODY_LORENTZ] = {NONNEG, POSITIVE, POSITIVE, NONNEG, NONNEG, NONNEG, NONNEG},
    [VR_OSC_GAUSSIAN] = {NONNEG, NONNEG, NONNEG},
};

vr_status vr_osc_check(vr_osc_kind kind, const double *p, size_t term, vr_error *err) {
  if (!known(kind)) return vr_error_set(err, VR_E_ARG, "genosc: unknown oscillator kind %d", kind);
  for (size_t i = 0; i < INFO[kind].nparams; i++) {
    const char *name = INFO[kind].params[i];
    int positive = DOMAIN[kind][i] == POSITIVE;
    if (!isfinite(p[i]) || p[i] < 0 || (positive && p[i] == 0))
      return vr_error_set(err, VR_E_RANGE, "genosc term %zu (%s): %s%zu = %g must be %s", term,
                          INFO[kind].name, name, term, p[i],
                          !isfinite(p[i]) ? "finite" : positive ? "> 0" : ">= 0");
  }
  return VR_OK;
}

/* ---- ε2 of each term ----------------------------------------------------- */

/* Tauc-Lorentz, Jellison and Modine, APL 69, 371 (1996), eq. 4:
 * ε2 = A E0 C (E - Eg)² / ((E² - E0²)² + C² E²) / E above Eg, 0 below. */
static double tl_eps2(const double *p, double E) {
  double A = p[0], E0 = p[1], C = p[2], Eg = p[3];
  if (!(E > Eg)) return 0;
  double d = E * E - E0 * E0;
  return A * E0 * C * (E - Eg) * (E - Eg) / ((d * d + C * C * E * E) * E);
}

/* Cody-Lorentz, Ferlauto et al., JAP 92, 2424 (2002), eqs. 5-7:
 * ε2 = G(E) L(E) above Et, with the Cody gap factor
 * G = (E - Eg)² / ((E - Eg)² + Ep²) and L = A E0 Γ E / ((E² - E0²)² + Γ² E²);
 * below Et an Urbach tail (E1 / E) exp((E - Et) / Eu), E1 = Et G(Et) L(Et),
 * which makes ε2 continuous at Et. */
static double cl_gl(const double *p, double E) {
  double A = p[0], E0 = p[1], G = p[2], Eg = p[3], Ep = p[4];
  double dg = (E - Eg) * (E - Eg), den = dg + Ep * Ep;
  double gap = den > 0 ? dg / den : 0;
  double d = E * E - E0 * E0;
  return gap * A * E0 * G * E / (d * d + G * G * E * E);
}

static double cl_eps2(const double *p, double E) {
  double Et = p[5], Eu = p[6];
  if (E >= Et) return cl_gl(p, E);
  if (!(Eu > 0)) return 0;
  return Et * cl_gl(p, Et) / E * exp((E - Et) / Eu);
}

/* Gaussian with Br the full width at half maximum, antisymmetric in E so
 * that it is Kramers-Kronig consistent (De Sousa Meneses et al., J.
 * Non-Cryst. Solids 351, 769 (2005); as in pyElli and CompleteEase):
 * ε2 = A [exp(-((E - En)/σ)²) - exp(-((E + En)/σ)²)], σ = Br / (2 √ln 2). */
static double gauss_sigma(const double *p) { return p[2] / (2 * sqrt(log(2.0))); }

static double gauss_eps2(const double *p, double E) {
  double A = p[0], En = p[1], s = gauss_sigma(p);
  if (A == 0 || s == 0) return 0;
  double xm = (E - En) / s, xp = (E + En) / s;
  return A * (exp(-xm * xm) - exp(-xp * xp));
}

double vr_osc_eps2(vr_osc_kind kind, const double *p, double E) {
  switch (kind) {
  case VR_OSC_LORENTZ: {
    double A = p[0], En = p[1], Br = p[2], d = En * En - E * E;
    if (A * En * Br == 0) return 0;
    return A * En * Br * Br * E / (d * d + Br * Br * E * E);
  }
  case VR_OSC_DRUDE: {
    double A = p[0], Br = p[1];
    if (A * Br == 0) return 0;
    return A * Br / (E * (E * E + Br * Br));
  }
  case VR_OSC_TAUC_LORENTZ: return tl_eps2(p, E);
  case VR_OSC_CODY_LORENTZ: return cl_eps2(p, E);
  case VR_OSC_GAUSSIAN: return gauss_eps2(p, E);
  }
  return 0;
}

/* ---- numerical Kramers-Kronig of one term -------------------------------- */

typedef struct term_ctx {
  vr_osc_kind kind;
  const double *p;
} term_ctx;

static double term_eps2(double E, const void *ctx) {
  const term_ctx *t = ctx;
  return vr_osc_eps2(t->kind, t->p, E);
}

vr_status vr_osc_eps1_kk(vr_osc_kind kind, const double *p, double E, double *eps1,
                         vr_error *err) {
  term_ctx ctx = {kind, p};
  double breaks[5];
  size_t nb = 0;
  double lo = 0;
  switch (kind) {
  case VR_OSC_LORENTZ:
  case VR_OSC_GAUSSIAN: {
    double w = kind == VR_OSC_GAUSSIAN ? 3 * gauss_sigma(p) : p[2];
    breaks[nb++] = p[1] - w;
    breaks[nb++] = p[1];
    breaks[nb++] = p[1] + w;
    break;
  }
  case VR_OSC_DRUDE: breaks[nb++] = p[1]; break;
  case VR_OSC_TAUC_LORENTZ:
    lo = p[3];
    breaks[nb++] = p[1] - p[2];
    breaks[nb++] = p[1];
    breaks[nb++] = p[1] + p[2];
    break;
  case VR_OSC_CODY_LORENTZ:
    breaks[nb++] = p[5];
    breaks[nb++] = p[3];
    breaks[nb++] = p[1] - p[2];
    breaks[nb++] = p[1];
    breaks[nb++] = p[1] + p[2];
    break;
  }
  vr_kk_spec spec = {term_eps2, &ctx, lo, INFINITY, breaks, nb};
  return vr_kk_transform(&spec, E, eps1, err);
}

/* ---- closed-form ε1 -------------------------------------------------------- */

/* Tauc-Lorentz ε1: Jellison and Modine, APL 69, 371 (1996), eq. 5 with the
 * erratum APL 69, 2137 (1996); the same terms as refellips and pyElli.  Three
 * rearrangements keep it finite and accurate where the printed form is not:
 *  - its two logarithms of |E - Eg| combine into (E - Eg)² ln|E - Eg| / E,
 *    so E = Eg is an ordinary point (the printed form is ∞ - ∞ there);
 *  - ln((s + αEg)/(s - αEg)) / (2α) = atanh(αEg/s) / α, and for γ² < Eg²
 *    π + 2 atan(2(γ² - Eg²)/(αC)) = -2 atan(αC / (2(γ² - Eg²))), so nothing
 *    cancels as α = √(4E0² - C²) -> 0;
 *  - ζ⁴ = (E² - γ²)² + α²C²/4 = (E² - E0²)² + C²E² > 0 for C > 0, so E = E0
 *    is an ordinary point too.
 * Valid for C < 2 E0 (α real); above that the caller uses the numerical
 * transform. */
static double tl_eps1(const double *p, double E) {
  double A = p[0], E0 = p[1], C = p[2], Eg = p[3];
  double E2 = E * E, E02 = E0 * E0, Eg2 = Eg * Eg, C2 = C * C;
  double alpha = sqrt(4 * E02 - C2);
  double gamma2 = E02 - C2 / 2;
  double zeta4 = (E2 - E02) * (E2 - E02) + C2 * E2;
  double a_ln = (Eg2 - E02) * E2 + Eg2 * C2 - E02 * (E02 + 3 * Eg2);
  double a_atan = (E2 - E02) * (E02 + Eg2) + Eg2 * C2;
  double k = A / (M_PI * zeta4);

  double t1 = k * C * a_ln / E0 * atanh(alpha * Eg / (E02 + Eg2)) / alpha;
  double t2 = -k * a_atan / E0 * (M_PI_2 + atan(C / (2 * Eg + alpha)) + atan((alpha - 2 * Eg) / C));
  double q = gamma2 - Eg2;
  double b3 = q >= 0 ? M_PI + 2 * atan(2 * q / (alpha * C)) : -2 * atan(alpha * C / (2 * q));
  double t3 = 2 * k * E0 * Eg * (E2 - gamma2) * b3 / alpha;
  double dm = E - Eg, dp = E + Eg;
  double xlogx = dm == 0 ? 0 : dm * dm * log(fabs(dm));
  double S2 = (E02 - Eg2) * (E02 - Eg2) + Eg2 * C2;
  double t45 = k * E0 * C * ((dp * dp * log(dp) - xlogx) / E - Eg * log(S2));
  return t1 + t2 + t3 + t45;
}

/* Dawson's integral without GSL's underflow error path (which would call the
 * process-wide error handler) for arguments beyond any physical use. */
static double dawson(double x) {
  if (fabs(x) > 1e100) return 0.5 / x;
  gsl_sf_result r;
  gsl_sf_dawson_e(x, &r);
  return r.val;
}

/* Gaussian ε1 = (2A/√π) [D((E + En)/σ) - D((E - En)/σ)], D Dawson's
 * integral: the Hilbert transform of the two Gaussians (same sources). */
static double gauss_eps1(const double *p, double E) {
  double A = p[0], En = p[1], s = gauss_sigma(p);
  if (A == 0 || s == 0) return 0;
  return 2 * A / sqrt(M_PI) * (dawson((E + En) / s) - dawson((E - En) / s));
}

vr_status vr_osc_eps(vr_osc_kind kind, const double *p, double E, vr_complex *eps,
                     vr_error *err) {
  double e1 = 0, e2 = vr_osc_eps2(kind, p, E);
  switch (kind) {
  case VR_OSC_LORENTZ: {
    /* Amp En Br / (En² - E² - i Br E): Amp is the peak ε2, reached at En. */
    double A = p[0], En = p[1], Br = p[2], d = En * En - E * E;
    e1 = A * En * Br == 0 ? 0 : A * En * Br * d / (d * d + Br * Br * E * E);
    break;
  }
  case VR_OSC_DRUDE: {
    /* -Amp / (E² + i Br E), Amp the squared (unscreened) plasma energy. */
    double A = p[0], Br = p[1];
    e1 = -A / (E * E + Br * Br);
    break;
  }
  case VR_OSC_TAUC_LORENTZ:
    /* The closed form loses its footing as α -> 0 (C -> 2 E0) and is
     * complex beyond; the overdamped case is rare, so integrate there. */
    if (p[2] < 2 * p[1] * (1 - 1e-9)) {
      e1 = tl_eps1(p, E);
      break;
    }
    /* fall through */
  case VR_OSC_CODY_LORENTZ: {
    vr_status st = vr_osc_eps1_kk(kind, p, E, &e1, err);
    if (st != VR_OK) return st;
    break;
  }
  case VR_OSC_GAUSSIAN: e1 = gauss_eps1(p, E); break;
  default: return vr_error_set(err, VR_E_ARG, "genosc: unknown oscillator kind %d", kind);
  }
  if (!isfinite(e1) || !isfinite(e2))
    return vr_error_set(err, VR_E_NUMERIC, "%s term: eps is not finite at %g eV",
                        vr_osc_kind_name(kind), E);
  *eps = CMPLX(e1, e2);
  return VR_OK;
}
