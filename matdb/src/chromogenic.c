/* Evaluation of stored tint-state models (vr/chromogenic.h). */
#include "vr/chromogenic.h"

#include <math.h>
#include <string.h>

static const vr_parameter *param(const vr_material *m, const char *name) {
  for (size_t i = 0; i < m->nparams; i++)
    if (strcmp(m->params[i].name, name) == 0) return &m->params[i];
  return NULL;
}

vr_status vr_chromo_type_of(const vr_material *m, vr_chromo_type *type, vr_error *err) {
  if (m->kind != VR_KIND_CHROMOGENIC)
    return vr_error_set(err, VR_E_ARG, "material %s is a %s, not a chromogenic glass", m->name,
                        vr_kind_name(m->kind));
  const vr_property *p = vr_material_property(m, "chromogenic_type");
  if (p && p->text && strcmp(p->text, "electrochromic") == 0) *type = VR_CHROMO_ELECTRO;
  else if (p && p->text && strcmp(p->text, "photochromic") == 0) *type = VR_CHROMO_PHOTO;
  else
    return vr_error_set(err, VR_E_ARG,
                        "material %s: property chromogenic_type must be electrochromic or "
                        "photochromic", m->name);
  return VR_OK;
}

vr_status vr_chromo_eval(const vr_material *m, double s, double nm, double *T, double *Rf,
                         double *Rb, vr_error *err) {
  if (!(s >= 0 && s <= 1))
    return vr_error_set(err, VR_E_RANGE, "material %s: state %g outside [0, 1]", m->name, s);
  vr_chromo_type type;
  vr_status st = vr_chromo_type_of(m, &type, err);
  if (st) return st;
  if (T) {
    double t0, dod;
    if ((st = vr_material_eval(m, "T0", nm, false, &t0, NULL, err)) ||
        (st = vr_material_eval(m, "dOD", nm, false, &dod, NULL, err)))
      return st;
    *T = t0 * pow(10.0, -s * dod);
  }
  const char *base[2] = {"Rf0", "Rb0"}, *delta[2] = {"dRf", "dRb"};
  double *out[2] = {Rf, Rb};
  for (int i = 0; i < 2; i++) {
    if (!out[i]) continue;
    *out[i] = NAN;
    if (!vr_material_spectrum(m, base[i])) continue;
    double r0, dr = 0;
    if ((st = vr_material_eval(m, base[i], nm, false, &r0, NULL, err))) return st;
    if (vr_material_spectrum(m, delta[i]) &&
        (st = vr_material_eval(m, delta[i], nm, false, &dr, NULL, err)))
      return st;
    *out[i] = fmin(fmax(r0 + s * dr, 0.0), 1.0);
  }
  return VR_OK;
}

vr_status vr_chromo_state_of_charge(const vr_material *m, double q, double *s, vr_error *err) {
  vr_chromo_type type;
  vr_status st = vr_chromo_type_of(m, &type, err);
  if (st) return st;
  const vr_parameter *qf = param(m, "Q_full");
  if (type != VR_CHROMO_ELECTRO || !qf || !(qf->value > 0))
    return vr_error_set(err, VR_E_NOT_FOUND,
                        "material %s has no charge scale (electrochromic parameter Q_full)", m->name);
  if (!isfinite(q)) return vr_error_set(err, VR_E_ARG, "charge density must be finite");
  /* The model is fitted between the bleached state (no charge) and Q_full;
   * a charge outside that range is not extrapolated, nor clamped. */
  if (q < 0.0 || q > qf->value * (1.0 + 1e-9))
    return vr_error_set(err, VR_E_RANGE,
                        "charge %g mC/cm2: outside the calibrated range of %s, 0 to %g mC/cm2 "
                        "(the charges its states were fitted on); the model is not extrapolated",
                        q, m->name, qf->value);
  *s = fmin(q / qf->value, 1.0);
  return VR_OK;
}

/* b(T)/a (= K) and, when known, a and b(T). */
static vr_status rates(const vr_material *m, double T_K, double *K, double *a, double *b,
                       vr_error *err) {
  vr_chromo_type type;
  vr_status st = vr_chromo_type_of(m, &type, err);
  if (st) return st;
  if (type != VR_CHROMO_PHOTO)
    return vr_error_set(err, VR_E_ARG, "material %s is electrochromic: its state comes from "
                                       "charge, not UV", m->name);
  if (!(T_K > 0) || !isfinite(T_K))
    return vr_error_set(err, VR_E_ARG, "temperature must be a positive number of kelvin (%g)", T_K);
  const vr_parameter *pa = param(m, "a"), *pb = param(m, "b_ref"), *pk = param(m, "K_ref"),
                     *pe = param(m, "Ea"), *pt = param(m, "T_ref");
  double ea = pe ? pe->value : 0, tref = pt ? pt->value : 298.15;
  double arr = exp(-(ea / VR_GAS_CONSTANT) * (1.0 / T_K - 1.0 / tref));
  *a = *b = NAN;
  if (pa && pb && pa->value > 0 && pb->value > 0) {
    *a = pa->value;
    *b = pb->value * arr;
    *K = *b / *a;
  } else if (pk && pk->value > 0) {
    *K = pk->value * arr;
  } else {
    return vr_error_set(err, VR_E_NOT_FOUND,
                        "material %s has no photochromic rates (a and b_ref, or K_ref)", m->name);
  }
  return VR_OK;
}

vr_status vr_chromo_check_domain(const vr_material *m, double E_uv, double T_K, unsigned flags,
                                 vr_error *err) {
  double e_slack = flags & VR_CHROMO_ESTIMATE ? VR_CHROMO_E_SLACK : 1e-9;
  const vr_parameter *pe = param(m, "E_fit_max"), *t0 = param(m, "T_fit_min"),
                     *t1 = param(m, "T_fit_max");
  const char *how = "(the model is not extrapolated unless asked: --extrapolate in vr-spectro, "
                    "extrapolate=yes on the scene's material)";
  if (pe && isfinite(pe->value) && E_uv > pe->value * (1 + e_slack))
    return vr_error_set(err, VR_E_RANGE,
                        "material %s: UV irradiance %.4g W/m2 is outside the 0 to %.4g W/m2 its "
                        "states were fitted on %s", m->name, E_uv, pe->value, how);
  if (t0 && t1 && isfinite(t0->value) && isfinite(t1->value) &&
      (T_K < t0->value - VR_CHROMO_T_SLACK_K || T_K > t1->value + VR_CHROMO_T_SLACK_K)) {
    if (t1->value - t0->value <= 2 * VR_CHROMO_T_SLACK_K)
      return vr_error_set(err, VR_E_RANGE,
                          "material %s: temperature %.2f K (%.2f C): its states were fitted at "
                          "%.2f K only, so it has no activation energy; spectra at a second "
                          "temperature give one %s", m->name, T_K, T_K - 273.15, t0->value, how);
    return vr_error_set(err, VR_E_RANGE,
                        "material %s: temperature %.2f K (%.2f C) is outside the %.2f to %.2f K "
                        "its states were fitted on %s", m->name, T_K, T_K - 273.15, t0->value,
                        t1->value, how);
  }
  return VR_OK;
}

vr_status vr_chromo_steady_state(const vr_material *m, double E_uv, double T_K, unsigned flags,
                                 double *s, vr_error *err) {
  if (!(E_uv >= 0) || !isfinite(E_uv))
    return vr_error_set(err, VR_E_ARG, "UV irradiance must be >= 0 W/m2 (%g)", E_uv);
  double K, a, b;
  vr_status st = rates(m, T_K, &K, &a, &b, err);
  if (!st && !(flags & VR_CHROMO_EXTRAPOLATE)) st = vr_chromo_check_domain(m, E_uv, T_K, flags, err);
  if (st) return st;
  *s = E_uv / (E_uv + K);
  return VR_OK;
}

vr_status vr_chromo_state_after(const vr_material *m, double E_uv, double T_K, unsigned flags,
                                double s0, double t_s, double *s, vr_error *err) {
  if (!(E_uv >= 0) || !isfinite(E_uv) || !(t_s >= 0) || !isfinite(t_s) || !(s0 >= 0 && s0 <= 1))
    return vr_error_set(err, VR_E_ARG, "need E >= 0, t >= 0 and s0 in [0, 1]");
  double K, a, b;
  vr_status st = rates(m, T_K, &K, &a, &b, err);
  if (!st && !(flags & VR_CHROMO_EXTRAPOLATE)) st = vr_chromo_check_domain(m, E_uv, T_K, flags, err);
  if (st) return st;
  if (!isfinite(a))
    return vr_error_set(err, VR_E_NOT_FOUND,
                        "material %s knows only its steady states (K_ref): its rates a and b "
                        "need a time series", m->name);
  double ss = E_uv / (E_uv + K);
  *s = ss + (s0 - ss) * exp(-(a * E_uv + b) * t_s);
  return VR_OK;
}
