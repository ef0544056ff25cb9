/* The nine dispersion formulas of the refractiveindex.info database
 * ("Dispersion formulas", database/doc of polyanskiy/refractiveindex.info-
 * database), evaluated with the coefficients exactly as published: the
 * wavelength λ in micrometres, C1 = c[0].  Coefficients a file does not give
 * count as 0, so a term whose coefficient is missing drops out. */
#include "vr/material.h"

#include <math.h>
#include <stdbool.h>

/* Coefficient C_i (1-based, as the documentation numbers them). */
static double C(const vr_formula *f, size_t i) {
  return i >= 1 && i <= f->ncoeffs && i <= VR_FORMULA_MAX_COEFFS ? f->c[i - 1] : 0.0;
}

/* Largest 1-based index given, for the formulas whose sums run over pairs. */
static size_t count(const vr_formula *f) {
  return f->ncoeffs < VR_FORMULA_MAX_COEFFS ? f->ncoeffs : VR_FORMULA_MAX_COEFFS;
}

/* Σ C(i) λ^C(i+1) for i = first, first+2, ... <= last; a zero coefficient
 * contributes nothing even where its power would overflow. */
static double power_terms(const vr_formula *f, size_t first, size_t last, double L) {
  double s = 0.0;
  for (size_t i = first; i <= last; i += 2)
    if (C(f, i) != 0.0) s += C(f, i) * pow(L, C(f, i + 1));
  return s;
}

static vr_status pole(const vr_formula *f, double nm, vr_error *err) {
  return vr_error_set(err, VR_E_NUMERIC,
                      "rii formula %d at %g nm: a denominator is zero (the wavelength sits on a "
                      "pole of the formula)",
                      f->type, nm);
}

/* a / b, or a pole.  A term whose numerator is 0 is absent altogether and
 * its denominator is not looked at: formula 4 files pad an unused term with
 * "0 0 0 1", and such padding must not turn into a pole (0/0) anywhere. */
static int term(double a, double b, double *out) {
  if (a == 0.0) {
    *out = 0.0;
    return 0;
  }
  if (b == 0.0) return -1;
  *out = a / b;
  return 0;
}

vr_status vr_formula_eval(const vr_formula *f, double nm, double *n, vr_error *err) {
  if (!f || !n) return vr_error_set(err, VR_E_ARG, "vr_formula_eval: NULL argument");
  if (!(nm > 0.0) || !isfinite(nm))
    return vr_error_set(err, VR_E_ARG, "rii formula %d: wavelength %g nm is not a positive number",
                        f->type, nm);
  const double L = nm / 1000.0, L2 = L * L;
  const size_t N = count(f);
  /* Formulas 1-4, 8 and 9 give n², formulas 5-7 give n itself. */
  bool squared = true;
  double v = NAN, t;
  switch (f->type) {
  case 1: /* Sellmeier: n² - 1 = C1 + Σ C(2i) λ² / (λ² - C(2i+1)²) */
    v = 1.0 + C(f, 1);
    for (size_t i = 2; i <= N; i += 2) {
      if (term(C(f, i) * L2, L2 - C(f, i + 1) * C(f, i + 1), &t)) return pole(f, nm, err);
      v += t;
    }
    break;
  case 2: /* Sellmeier-2: n² - 1 = C1 + Σ C(2i) λ² / (λ² - C(2i+1)) */
    v = 1.0 + C(f, 1);
    for (size_t i = 2; i <= N; i += 2) {
      if (term(C(f, i) * L2, L2 - C(f, i + 1), &t)) return pole(f, nm, err);
      v += t;
    }
    break;
  case 3: /* Polynomial: n² = C1 + Σ C(2i) λ^C(2i+1) */
    v = C(f, 1) + power_terms(f, 2, N, L);
    break;
  case 4: /* RefractiveIndex.INFO: n² = C1 + C2 λ^C3 / (λ² - C4^C5)
           *   + C6 λ^C7 / (λ² - C8^C9) + C10 λ^C11 + C12 λ^C13 + C14 λ^C15 + C16 λ^C17 */
    v = C(f, 1);
    for (size_t i = 2; i <= 6; i += 4) {
      if (C(f, i) == 0.0) continue;
      if (term(C(f, i) * pow(L, C(f, i + 1)), L2 - pow(C(f, i + 2), C(f, i + 3)), &t))
        return pole(f, nm, err);
      v += t;
    }
    v += power_terms(f, 10, 16, L);
    break;
  case 5: /* Cauchy: n = C1 + Σ C(2i) λ^C(2i+1) */
    squared = false;
    v = C(f, 1) + power_terms(f, 2, N, L);
    break;
  case 6: /* Gases: n - 1 = C1 + Σ C(2i) / (C(2i+1) - λ⁻²) */
    squared = false;
    v = 1.0 + C(f, 1);
    for (size_t i = 2; i <= N; i += 2) {
      if (term(C(f, i), C(f, i + 1) - 1.0 / L2, &t)) return pole(f, nm, err);
      v += t;
    }
    break;
  case 7: { /* Herzberger: n = C1 + C2/(λ² - 0.028) + C3 (1/(λ² - 0.028))²
             *   + C4 λ² + C5 λ⁴ + C6 λ⁶ */
    const double d = L2 - 0.028;
    if (d == 0.0 && (C(f, 2) != 0.0 || C(f, 3) != 0.0)) return pole(f, nm, err);
    const double inv = d == 0.0 ? 0.0 : 1.0 / d;
    squared = false;
    v = C(f, 1) + C(f, 2) * inv + C(f, 3) * inv * inv + C(f, 4) * L2 + C(f, 5) * L2 * L2 +
             C(f, 6) * L2 * L2 * L2;
    break;
  }
  case 8: { /* Retro: (n² - 1)/(n² + 2) = C1 + C2 λ²/(λ² - C3) + C4 λ²,
             * so with r the right-hand side, n² = (1 + 2r)/(1 - r). */
    if (term(C(f, 2) * L2, L2 - C(f, 3), &t)) return pole(f, nm, err);
    const double r = C(f, 1) + t + C(f, 4) * L2;
    if (1.0 - r == 0.0) return pole(f, nm, err);
    v = (1.0 + 2.0 * r) / (1.0 - r);
    break;
  }
  case 9: { /* Exotic: n² = C1 + C2/(λ² - C3) + C4 (λ - C5)/((λ - C5)² + C6) */
    double t2;
    const double x = L - C(f, 5);
    if (term(C(f, 2), L2 - C(f, 3), &t) || term(C(f, 4) * x, x * x + C(f, 6), &t2))
      return pole(f, nm, err);
    v = C(f, 1) + t + t2;
    break;
  }
  default:
    return vr_error_set(err, VR_E_ARG, "unknown rii dispersion formula type %d (1 to 9)", f->type);
  }
  /* NaN (from a negative base to a fractional power, say) fails here too. */
  if (!(v > 0.0) || !isfinite(v))
    return vr_error_set(err, VR_E_NUMERIC, "rii formula %d at %g nm gives %s = %g, %s", f->type,
                        nm, squared ? "n²" : "n", v,
                        squared ? "which has no positive real root" : "not a positive index");
  *n = squared ? sqrt(v) : v;
  return VR_OK;
}
