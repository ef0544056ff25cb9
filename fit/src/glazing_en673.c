/* EN 673 thermal transmittance and EN 410's secondary heat transfer
 * (vr/glazing_en673.h). */
#include "vr/glazing_en673.h"

#include <math.h>
#include <stdbool.h>

/* EN 673's gas table at 10 C, the column its declared values use:
 * density kg/m3, dynamic viscosity kg/(m s), conductivity W/(m K),
 * specific heat J/(kg K).  In the order of vr_gas_id. */
static const vr_en673_gas TABLE_10C[4] = {
    {1.232, 1.761e-5, 2.496e-2, 1008.0}, /* air */
    {1.699, 2.164e-5, 1.684e-2, 519.0},  /* argon */
    {3.560, 2.400e-5, 0.900e-2, 245.0},  /* krypton */
    {5.689, 2.226e-5, 0.529e-2, 161.0},  /* xenon */
};

/* EN 673's Nusselt constants for vertical glazing. */
#define NU_A 0.035
#define NU_N 0.38

void vr_en673_gas_properties(const vr_gas_mix *g, vr_en673_gas *out) {
  *out = (vr_en673_gas){0, 0, 0, 0};
  for (size_t i = 0; i < g->n; i++) {
    const vr_en673_gas *t = &TABLE_10C[g->id[i]];
    double r = g->frac[i];
    out->rho += r * t->rho;
    out->mu += r * t->mu;
    out->lambda += r * t->lambda;
    out->c += r * t->c;
  }
}

void vr_en673_films(vr_en673_edition e, double ei, double *he, double *hi) {
  *he = e == VR_EN673_1997 ? 23.0 : 25.0;
  *hi = 3.6 + (e == VR_EN673_1997 ? 4.4 : 4.1) * ei / VR_EN673_UNCOATED;
}

/* A gap's conductance for a temperature difference dT across it. */
static void gap_conductance(const vr_en673_gas *p, double s, double e1, double e2, double dT,
                            double *hr, double *hg, double *Nu) {
  const double Tm = VR_EN673_TM;
  *hr = 4.0 * VR_EN673_SIGMA / (1.0 / e1 + 1.0 / e2 - 1.0) * Tm * Tm * Tm;
  double Gr = 9.81 * s * s * s * dT * p->rho * p->rho / (Tm * p->mu * p->mu);
  double Pr = p->mu * p->c / p->lambda;
  double nu = NU_A * pow(Gr * Pr, NU_N);
  *Nu = nu > 1.0 ? nu : 1.0;
  *hg = *Nu * p->lambda / s;
}

vr_status vr_en673_u(const vr_en673_system *s, vr_en673_result *out, vr_error *err) {
  *out = (vr_en673_result){0};
  size_t n = s->n;
  if (n < 1 || n > VR_EN673_MAX_PANES)
    return vr_error_set(err, VR_E_ARG, "%zu panes: EN 673 takes 1 to %d", n, VR_EN673_MAX_PANES);
  for (size_t i = 0; i < n; i++) {
    const vr_en673_pane *p = &s->pane[i];
    if (!(p->thickness_m > 0) || !isfinite(p->thickness_m) || !(p->conductivity > 0) ||
        !isfinite(p->conductivity))
      return vr_error_set(err, VR_E_RANGE, "pane %zu: thickness %g m and conductivity %g W/(m K) "
                                           "must be positive", i + 1, p->thickness_m,
                          p->conductivity);
    for (int f = 0; f < 2; f++)
      if (!(p->emis[f] > 0 && p->emis[f] <= 1))
        return vr_error_set(err, VR_E_RANGE, "pane %zu: %s emissivity %g outside (0, 1]", i + 1,
                            f ? "inner" : "outer", p->emis[f]);
  }
  vr_en673_gas gas[VR_EN673_MAX_PANES - 1];
  for (size_t k = 0; k + 1 < n; k++) {
    if (!(s->gap_m[k] > 0) || !isfinite(s->gap_m[k]))
      return vr_error_set(err, VR_E_RANGE, "gap %zu: thickness %g m must be positive", k + 1,
                          s->gap_m[k]);
    if (s->gas[k].n < 1 || s->gas[k].n > VR_GAS_MAX)
      return vr_error_set(err, VR_E_ARG, "gap %zu: no gas", k + 1);
    vr_en673_gas_properties(&s->gas[k], &gas[k]);
  }
  vr_en673_films(s->edition, s->pane[n - 1].emis[1], &out->he, &out->hi);
  double glass = 0.0;
  for (size_t i = 0; i < n; i++) glass += s->pane[i].thickness_m / s->pane[i].conductivity;
  /* The 15 K are shared by the gaps as their resistances are; start
   * evenly, then iterate (a gap's hg depends on its own dT). */
  size_t g = n - 1;
  for (size_t k = 0; k < g; k++) out->dT[k] = VR_EN673_DT / (double)g;
  double Rgaps = 0.0;
  bool settled = g <= 1;
  for (int it = 1; it <= 200; it++) {
    double R[VR_EN673_MAX_PANES - 1], sum = 0.0;
    for (size_t k = 0; k < g; k++) {
      gap_conductance(&gas[k], s->gap_m[k], s->pane[k].emis[1], s->pane[k + 1].emis[0], out->dT[k],
                      &out->hr[k], &out->hg[k], &out->Nu[k]);
      out->hs[k] = out->hr[k] + out->hg[k];
      R[k] = 1.0 / out->hs[k];
      sum += R[k];
    }
    double change = fabs(sum - Rgaps);
    Rgaps = sum;
    out->iterations = it;
    if (g <= 1) break;
    for (size_t k = 0; k < g; k++) out->dT[k] = VR_EN673_DT * R[k] / sum;
    if (change <= 1e-13 * sum) {
      settled = true;
      break;
    }
  }
  if (!settled)
    return vr_error_set(err, VR_E_NUMERIC, "EN 673: the gaps' shares of the 15 K did not settle in "
                                           "%d iterations", out->iterations);
  out->U = 1.0 / (1.0 / out->he + glass + Rgaps + 1.0 / out->hi);
  out->U_declared = round(out->U * 10.0) / 10.0;
  /* EN 410's nodes: the outer face of pane 1, the centres of the middle
   * panes, the inner face of pane n. */
  for (size_t k = 0; k < g; k++) {
    double left = s->pane[k].thickness_m / s->pane[k].conductivity;
    double right = s->pane[k + 1].thickness_m / s->pane[k + 1].conductivity;
    double R = (k == 0 ? left : 0.5 * left) + 1.0 / out->hs[k] +
               (k + 1 == n - 1 ? right : 0.5 * right);
    out->Lambda[k] = 1.0 / R;
  }
  return VR_OK;
}

double vr_en410_qi(size_t n, const double *a, double he, double hi, const double *Lambda) {
  if (n < 1 || !a || !(he > 0) || !(hi > 0) || (n > 1 && !Lambda)) return NAN;
  double total = 1.0 / he + 1.0 / hi;
  for (size_t k = 0; k + 1 < n; k++) {
    if (!(Lambda[k] > 0)) return NAN;
    total += 1.0 / Lambda[k];
  }
  /* Node i reaches the outside through 1/he and the conductances before
   * it; that share of its power over the whole flows in. */
  double q = 0.0, out = 1.0 / he;
  for (size_t i = 0; i < n; i++) {
    if (i) out += 1.0 / Lambda[i - 1];
    q += a[i] * out;
  }
  return q / total;
}
