/* Interpolation in stored pane tables (vr/btdf.h). */
#include "vr/btdf.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static const char *const NAMES[3][2] = {{"Ts", "Tp"}, {"Rfs", "Rfp"}, {"Rbs", "Rbp"}};

static vr_status at_angle(const vr_material *m, vr_btdf_quantity q, vr_btdf_pol pol, double angle,
                          double nm, double *v, vr_error *err) {
  char role[32];
  double sum = 0;
  int first = pol == VR_BTDF_P ? 1 : 0, last = pol == VR_BTDF_S ? 0 : 1;
  for (int p = first; p <= last; p++) {
    snprintf(role, sizeof role, "%s@%g", NAMES[q][p], angle);
    if (!vr_material_spectrum(m, role))
      return vr_error_set(err, VR_E_ARG, "material %s has no table %s", m->name, role);
    double x;
    vr_status st = vr_material_eval(m, role, nm, false, &x, NULL, err);
    if (st) return st;
    sum += x;
  }
  *v = pol == VR_BTDF_UNPOLARISED ? 0.5 * sum : sum;
  return VR_OK;
}

vr_status vr_btdf_eval(const vr_material *m, vr_btdf_quantity q, vr_btdf_pol pol,
                       double angle_deg, double nm, double *value, vr_error *err) {
  if (m->kind != VR_KIND_BTDF)
    return vr_error_set(err, VR_E_ARG, "material %s is a %s, not a btdf table", m->name,
                        vr_kind_name(m->kind));
  if ((unsigned)q > VR_BTDF_RB || (unsigned)pol > VR_BTDF_UNPOLARISED)
    return vr_error_set(err, VR_E_ARG, "bad btdf quantity or polarisation");
  if (!(angle_deg >= 0 && angle_deg <= 90))
    return vr_error_set(err, VR_E_RANGE, "angle %g deg outside [0, 90]", angle_deg);
  const vr_property *p = vr_material_property(m, "angles");
  if (!p || !p->text) return vr_error_set(err, VR_E_ARG, "material %s lists no angles", m->name);
  /* The two tabulated angles around angle_deg. */
  double lo = NAN, hi = NAN;
  const char *s = p->text;
  while (*s) {
    char *end;
    double a = strtod(s, &end);
    if (end == s) return vr_error_set(err, VR_E_PARSE, "material %s: bad angle list", m->name);
    if (a <= angle_deg) lo = a;
    if (a >= angle_deg && isnan(hi)) hi = a;
    s = *end == ',' ? end + 1 : end;
  }
  if (isnan(lo)) lo = hi;
  if (isnan(hi)) hi = lo;
  double vlo, vhi;
  vr_status st = at_angle(m, q, pol, lo, nm, &vlo, err);
  if (!st) st = hi == lo ? (vhi = vlo, VR_OK) : at_angle(m, q, pol, hi, nm, &vhi, err);
  if (st) return st;
  double t = hi > lo ? (angle_deg - lo) / (hi - lo) : 0;
  *value = vlo + t * (vhi - vlo);
  return VR_OK;
}
