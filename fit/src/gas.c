/* Fill-gas properties and mixtures (vr/gas.h). */
#include "vr/gas.h"

#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

static const struct {
  const char *name;
  double M, cp[2], lambda[2], mu[2];
} GAS[] = {
    {"air", 28.97, {1002.737, 0.012324}, {2.8733e-3, 7.76e-5}, {3.7233e-6, 4.94e-8}},
    {"argon", 39.948, {521.929, 0}, {2.2848e-3, 5.1486e-5}, {3.3786e-6, 6.4514e-8}},
    {"krypton", 83.8, {248.09, 0}, {9.443e-4, 2.826e-5}, {2.213e-6, 7.777e-8}},
    {"xenon", 131.3, {158.34, 0}, {4.538e-4, 1.723e-5}, {1.069e-6, 7.414e-8}},
};

const char *vr_gas_name(vr_gas_id id) { return GAS[id].name; }

void vr_gas_properties(const vr_gas_mix *g, double T, double p, vr_gas_props *out) {
  size_t n = g->n;
  double M[VR_GAS_MAX], cp[VR_GAS_MAX], lam[VR_GAS_MAX], mu[VR_GAS_MAX], x[VR_GAS_MAX];
  for (size_t i = 0; i < n; i++) {
    vr_gas_id id = g->id[i];
    M[i] = GAS[id].M;
    cp[i] = GAS[id].cp[0] + GAS[id].cp[1] * T;
    lam[i] = GAS[id].lambda[0] + GAS[id].lambda[1] * T;
    mu[i] = GAS[id].mu[0] + GAS[id].mu[1] * T;
    x[i] = g->frac[i];
  }
  double Mmix = 0, rho = 0;
  for (size_t i = 0; i < n; i++) {
    Mmix += x[i] * M[i];
    rho += x[i] * p * M[i] / (VR_GAS_R * T);
  }
  out->M = Mmix;
  out->rho = rho;
  if (n == 1) {
    out->lambda = lam[0], out->mu = mu[0], out->cp = cp[0];
    return;
  }
  /* ISO 15099 equations 62-68. */
  double mum = 0, cpm = 0, l1 = 0, l2 = 0;
  double lp[VR_GAS_MAX], lpp[VR_GAS_MAX];
  for (size_t i = 0; i < n; i++) {
    lp[i] = 15.0 / 4.0 * (VR_GAS_R / M[i]) * mu[i]; /* monatomic part */
    lpp[i] = lam[i] - lp[i];                       /* internal degrees of freedom */
    cpm += x[i] * cp[i] * M[i];
  }
  for (size_t i = 0; i < n; i++) {
    if (!(x[i] > 0)) continue;
    double smu = 0, spsi = 0, sphi = 0;
    for (size_t j = 0; j < n; j++) {
      if (j == i) continue;
      double den = 2.0 * sqrt(2.0) * sqrt(1.0 + M[i] / M[j]);
      double a = 1.0 + sqrt(mu[i] / mu[j]) * pow(M[j] / M[i], 0.25);
      double phimu = a * a / den;
      double b = 1.0 + sqrt(lp[i] / lp[j]) * pow(M[i] / M[j], 0.25);
      double philam = b * b / den;
      double psi = philam * (1.0 + 2.41 * (M[i] - M[j]) * (M[i] - 0.142 * M[j]) /
                                       ((M[i] + M[j]) * (M[i] + M[j])));
      smu += phimu * x[j] / x[i];
      spsi += psi * x[j] / x[i];
      sphi += philam * x[j] / x[i];
    }
    mum += mu[i] / (1.0 + smu);
    l1 += lp[i] / (1.0 + spsi);
    l2 += lpp[i] / (1.0 + sphi);
  }
  out->mu = mum;
  out->lambda = l1 + l2;
  out->cp = cpm / Mmix;
}

vr_status vr_gas_parse(const char *s, vr_gas_mix *out, vr_error *err) {
  memset(out, 0, sizeof *out);
  const char *p = s;
  double sum = 0;
  while (*p) {
    while (*p == ' ' || *p == '+') p++;
    if (!*p) break;
    size_t n = 0;
    while (isalpha((unsigned char)p[n])) n++;
    int id = -1;
    for (int g = 0; g < 4; g++)
      if (n == strlen(GAS[g].name) && !strncasecmp(p, GAS[g].name, n)) id = g;
    if (id < 0)
      return vr_error_set(err, VR_E_PARSE, "gas '%s': unknown gas '%.*s' (air, argon, krypton, "
                                           "xenon, or a mixture such as argon:0.9+air:0.1)",
                          s, (int)(n ? n : 1), p);
    if (out->n == VR_GAS_MAX)
      return vr_error_set(err, VR_E_PARSE, "gas '%s': at most %d gases", s, VR_GAS_MAX);
    for (size_t k = 0; k < out->n; k++)
      if (out->id[k] == (vr_gas_id)id)
        return vr_error_set(err, VR_E_PARSE, "gas '%s': %s named twice", s, GAS[id].name);
    p += n;
    double f = 1.0;
    if (*p == ':') {
      char *end;
      f = strtod(p + 1, &end);
      if (end == p + 1 || !(f > 0 && f <= 1))
        return vr_error_set(err, VR_E_PARSE, "gas '%s': the fraction of %s must be in (0, 1]", s,
                            GAS[id].name);
      p = end;
    }
    if (*p && *p != '+')
      return vr_error_set(err, VR_E_PARSE, "gas '%s': expected '+' after %s", s, GAS[id].name);
    out->id[out->n] = (vr_gas_id)id;
    out->frac[out->n++] = f;
    sum += f;
  }
  if (out->n == 0) return vr_error_set(err, VR_E_PARSE, "gas '%s': no gas named", s);
  if (fabs(sum - 1.0) > 1e-6)
    return vr_error_set(err, VR_E_PARSE, "gas '%s': the fractions sum to %g, not 1", s, sum);
  return VR_OK;
}
