/* ISO 15099 centre-of-glass heat balance (vr/glazing_thermal.h). */
#include "vr/glazing_thermal.h"

#include <math.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>

#define G_ACC 9.807          /* m/s2, as Windows-CalcEngine */
#define RELAX 0.65
#define TOL 1e-8
#define MAX_ITER 5000
#define EMIS_FLOOR 1e-6

const vr_thermal_env VR_ENV_NFRC_U = {"NFRC 100 winter", 294.15, 255.15, 255.15, 5.5, 0.0, 101325};
const vr_thermal_env VR_ENV_NFRC_SHGC = {"NFRC 200 summer", 297.15, 305.15, 305.15, 2.75, 783.0,
                                         101325};

static const vr_gas_mix AIR = {1, {VR_GAS_AIR}, {1.0}};

static double deg(double d) { return d * M_PI / 180.0; }

/* ISO 15099 5.3.3.3-5: Nusselt numbers of a cavity at 0-60, 60 and 90
 * degrees. */
static double nu_low(double Ra, double tilt) {
  double t = deg(tilt), rc = Ra * cos(t);
  double a = 1.0 - 1708.0 / rc;
  double b = pow(rc / 5830.0, 1.0 / 3.0) - 1.0;
  return 1.0 + 1.44 * (a > 0 ? a : 0) * (1.0 - 1708.0 * pow(sin(1.8 * t), 1.6) / rc) +
         (b > 0 ? b : 0);
}

static double nu_60(double Ra, double A) {
  double G = 0.5 / pow(1.0 + pow(Ra / 3160.0, 20.6), 0.1);
  double nu1 = pow(1.0 + pow(0.0936 * pow(Ra, 0.314) / (1.0 + G), 7.0), 1.0 / 7.0);
  double nu2 = (0.104 + 0.175 / A) * pow(Ra, 0.283);
  return fmax(nu1, nu2);
}

static double nu_90(double Ra, double A) {
  double nu1 = Ra > 5e4   ? 0.0673838 * pow(Ra, 1.0 / 3.0)
               : Ra > 1e4 ? 0.028154 * pow(Ra, 0.4134)
                          : 1.0 + 1.7596678e-10 * pow(Ra, 2.2984755);
  double nu2 = 0.242 * pow(Ra / A, 0.272);
  return fmax(nu1, nu2);
}

double vr_cavity_nusselt(double Ra, double A, double tilt) {
  if (!(Ra > 0)) return 1.0;
  if (tilt < 60) return nu_low(Ra, tilt);
  if (tilt == 60) return nu_60(Ra, A);
  if (tilt < 90) {
    double w = (tilt - 60.0) / 30.0;
    return (1.0 - w) * nu_60(Ra, A) + w * nu_90(Ra, A);
  }
  if (tilt == 90) return nu_90(Ra, A);
  return 1.0 + (nu_90(Ra, A) - 1.0) * sin(deg(tilt));
}

/* Gap convective coefficient between faces at Ta, Tb (ISO 15099 5.3). */
static double gap_h(const vr_thermal_gap *g, double H, double tilt, double Ta, double Tb,
                    double *Ra_out, double *Nu_out) {
  double Tm = 0.5 * (Ta + Tb), d = g->thickness_m;
  vr_gas_props p;
  vr_gas_properties(&g->gas, Tm, g->pressure_pa, &p);
  double Ra = G_ACC * d * d * d * fabs(Ta - Tb) * p.cp * p.rho * p.rho / (Tm * p.mu * p.lambda);
  double Nu = vr_cavity_nusselt(Ra, H / d, tilt);
  *Ra_out = Ra, *Nu_out = Nu;
  return Nu * p.lambda / d;
}

/* Indoor natural convection on the inner face at Ts (ISO 15099 8.3.2.2). */
static double indoor_h(const vr_thermal_env *e, double H, double tilt, double Ts) {
  double Tmf = e->T_in + 0.25 * (Ts - e->T_in);
  vr_gas_props p;
  vr_gas_properties(&AIR, Tmf, e->pressure_pa, &p);
  double Gr = G_ACC * H * H * H * fabs(Ts - e->T_in) * p.rho * p.rho / (Tmf * p.mu * p.mu);
  double Ra = Gr * p.mu * p.cp / p.lambda;
  double t = deg(tilt), s = sin(t), Nu;
  double Rcv = 2.5e5 * pow(exp(0.72 * tilt) / s, 0.2);
  if (tilt < 15) Nu = 0.13 * pow(Ra, 1.0 / 3.0);
  else if (tilt <= 90)
    Nu = Ra <= Rcv ? 0.56 * pow(Ra * s, 0.25)
                   : 0.13 * (pow(Ra, 1.0 / 3.0) - pow(Rcv, 1.0 / 3.0)) + 0.56 * pow(Rcv * s, 0.25);
  else if (tilt <= 179) Nu = 0.56 * pow(Ra * s, 0.25);
  else Nu = 0.58 * pow(Ra, 0.2);
  return Nu * p.lambda / H;
}

/* Solves the n x n system a x = b (row-major a, b replaced by x) by GSL's
 * LU decomposition with partial pivoting; -1 when singular. */
static int solve_linear(double *a, double *b, int n) {
  gsl_matrix_view A = gsl_matrix_view_array(a, (size_t)n, (size_t)n);
  gsl_vector_view B = gsl_vector_view_array(b, (size_t)n);
  size_t pidx[4 * VR_THERMAL_MAX_PANES];
  gsl_permutation P = {(size_t)n, pidx};
  int sign;
  if (gsl_linalg_LU_decomp(&A.matrix, &P, &sign)) return -1;
  for (int k = 0; k < n; k++)
    if (!(fabs(a[k * n + k]) > 1e-300)) return -1;
  return gsl_linalg_LU_svx(&A.matrix, &P, &B.vector) ? -1 : 0;
}

static vr_status check_system(const vr_thermal_system *s, const vr_thermal_env *e, vr_error *err) {
  if (s->n < 1 || s->n > VR_THERMAL_MAX_PANES)
    return vr_error_set(err, VR_E_ARG, "%zu panes: 1 to %d", s->n, VR_THERMAL_MAX_PANES);
  if (!(s->height_m > 0) || !(s->tilt_deg >= 0 && s->tilt_deg <= 180))
    return vr_error_set(err, VR_E_ARG, "height %g m, tilt %g deg: need height > 0, tilt 0-180",
                        s->height_m, s->tilt_deg);
  for (size_t i = 0; i < s->n; i++) {
    const vr_thermal_pane *p = &s->pane[i];
    if (!(p->thickness_m > 0) || !(p->conductivity > 0))
      return vr_error_set(err, VR_E_ARG, "pane %zu: thickness %g m and conductivity %g W/(m K) "
                                         "must be positive", i + 1, p->thickness_m,
                          p->conductivity);
    for (int f = 0; f < 2; f++)
      if (!(p->emis[f] >= 0 && p->emis[f] + p->tir <= 1 && p->tir >= 0))
        return vr_error_set(err, VR_E_ARG, "pane %zu: %s emissivity %g with IR transmittance %g: "
                                           "each in [0, 1] and their sum at most 1",
                            i + 1, f ? "back" : "front", p->emis[f], p->tir);
    if (!(p->absorptance >= 0 && p->absorptance <= 1))
      return vr_error_set(err, VR_E_ARG, "pane %zu: solar absorptance %g outside [0, 1]", i + 1,
                          p->absorptance);
  }
  for (size_t i = 0; i + 1 < s->n; i++)
    if (!(s->gap[i].thickness_m > 0) || !(s->gap[i].pressure_pa > 13.3322))
      return vr_error_set(err, VR_E_ARG, "gap %zu: thickness %g m and pressure %g Pa: a gas gap "
                                         "needs both positive (vacuum glazing, below 13.3 Pa, is "
                                         "not modelled)", i + 1, s->gap[i].thickness_m,
                          s->gap[i].pressure_pa);
  if (!(e->T_in > 0 && e->T_out > 0 && e->T_sky > 0 && e->wind_ms >= 0 && e->solar_wm2 >= 0))
    return vr_error_set(err, VR_E_ARG, "environment %s: temperatures must be positive kelvin, wind "
                                       "and sun not negative", e->name);
  return VR_OK;
}

vr_status vr_thermal_solve(const vr_thermal_system *s, const vr_thermal_env *e, int with_sun,
                           vr_thermal_state *out, vr_error *err) {
  vr_status st = check_system(s, e, err);
  if (st) return st;
  memset(out, 0, sizeof *out);
  const int n = (int)s->n, N = 4 * n;
  const double H = s->height_m, tilt = s->tilt_deg, sg = VR_SIGMA;
  /* Outdoor radiation: sky and ground by the view factors of the tilt,
   * the ground at the air temperature (ISO 15099 8.3.1). */
  double fsky = 0.5 * (1.0 + cos(deg(tilt)));
  double e0 = (1.0 - fsky) + fsky * pow(e->T_sky / e->T_out, 4.0);
  double J_out = sg * e->T_out * e->T_out * e->T_out * e->T_out * e0;
  double J_in = sg * pow(e->T_in, 4.0);
  double hc_out = 4.0 + 4.0 * e->wind_ms;
  /* x[4i..4i+3] = Tf, Jf, Jb, Tb of pane i.  Start: a linear profile. */
  double x[4 * VR_THERMAL_MAX_PANES], xn[4 * VR_THERMAL_MAX_PANES];
  double a[16 * VR_THERMAL_MAX_PANES * VR_THERMAL_MAX_PANES];
  double total = 0;
  for (int i = 0; i < n; i++) total += s->pane[i].thickness_m;
  for (int i = 0; i + 1 < n; i++) total += s->gap[i].thickness_m;
  double slope = (e->T_in - e->T_out) / (total + 0.011), pos = 0.001;
  for (int i = 0; i < n; i++) {
    x[4 * i] = e->T_out + slope * pos;
    pos += s->pane[i].thickness_m;
    x[4 * i + 3] = e->T_out + slope * pos;
    if (i + 1 < n) pos += s->gap[i].thickness_m;
    x[4 * i + 1] = sg * pow(x[4 * i], 4.0);
    x[4 * i + 2] = sg * pow(x[4 * i + 3], 4.0);
  }
  double hc_in = 0, change = INFINITY;
  int it;
  for (it = 0; it < MAX_ITER && change > TOL; it++) {
    memset(a, 0, (size_t)(N * N) * sizeof *a);
    double hgap[VR_THERMAL_MAX_PANES];
    for (int i = 0; i + 1 < n; i++)
      hgap[i] = gap_h(&s->gap[i], H, tilt, x[4 * i + 3], x[4 * (i + 1)], &out->gap_Ra[i],
                      &out->gap_Nu[i]);
    hc_in = indoor_h(e, H, tilt, x[4 * (n - 1) + 3]);
    for (int i = 0; i < n; i++) {
      const vr_thermal_pane *p = &s->pane[i];
      double c = p->conductivity / p->thickness_m, tau = p->tir;
      double S = with_sun ? p->absorptance * e->solar_wm2 : 0.0;
      /* Two facing faces that are perfect mirrors (emissivity 0, opaque)
       * exchange nothing, but their radiosities are then undetermined (a
       * singular system): emissivities below EMIS_FLOOR count as it,
       * which adds under 1e-6 sigma T^4 (5e-4 W/m2) of exchange. */
      double ef = fmax(p->emis[0], EMIS_FLOOR), eb = fmax(p->emis[1], EMIS_FLOOR);
      double rf = fmax(0.0, 1.0 - ef - tau), rb = fmax(0.0, 1.0 - eb - tau);
      double Tf = x[4 * i], Tb = x[4 * i + 3];
      int r = 4 * i, iTf = r, iJf = r + 1, iJb = r + 2, iTb = r + 3;
      int iGf = i > 0 ? 4 * (i - 1) + 2 : -1, iGb = i + 1 < n ? 4 * (i + 1) + 1 : -1;
      double *row;
      double bf = 0, bb = 0, b1 = 0, b2 = 0;
      /* Front face balance. */
      double hf = i > 0 ? hgap[i - 1] : hc_out;
      row = a + (size_t)r * N;
      row[iTf] += hf + c, row[iTb] -= c, row[iJf] += 1.0;
      if (i > 0) row[4 * (i - 1) + 3] -= hf;
      else bf += hf * e->T_out;
      if (iGf >= 0) row[iGf] -= 1.0 - tau;
      else bf += (1.0 - tau) * J_out;
      if (iGb >= 0) row[iGb] -= tau;
      else bf += tau * J_in;
      xn[r] = bf + 0.5 * S;
      /* Front radiosity. */
      row = a + (size_t)(r + 1) * N;
      row[iTf] += ef * sg * Tf * Tf * Tf, row[iJf] -= 1.0;
      if (iGf >= 0) row[iGf] += rf;
      else b1 -= rf * J_out;
      if (iGb >= 0) row[iGb] += tau;
      else b1 -= tau * J_in;
      xn[r + 1] = b1;
      /* Back radiosity. */
      row = a + (size_t)(r + 2) * N;
      row[iTb] += eb * sg * Tb * Tb * Tb, row[iJb] -= 1.0;
      if (iGf >= 0) row[iGf] += tau;
      else b2 -= tau * J_out;
      if (iGb >= 0) row[iGb] += rb;
      else b2 -= rb * J_in;
      xn[r + 2] = b2;
      /* Back face balance. */
      double hb = i + 1 < n ? hgap[i] : hc_in;
      row = a + (size_t)(r + 3) * N;
      row[iTb] += hb + c, row[iTf] -= c, row[iJb] += 1.0;
      if (i + 1 < n) row[4 * (i + 1)] -= hb;
      else bb += hb * e->T_in;
      if (iGb >= 0) row[iGb] -= 1.0 - tau;
      else bb += (1.0 - tau) * J_in;
      if (iGf >= 0) row[iGf] -= tau;
      else bb += tau * J_out;
      xn[r + 3] = bb + 0.5 * S;
    }
    if (solve_linear(a, xn, N))
      return vr_error_set(err, VR_E_NUMERIC, "heat balance: singular system at iteration %d", it);
    change = 0;
    for (int k = 0; k < N; k++) {
      if (!isfinite(xn[k]))
        return vr_error_set(err, VR_E_NUMERIC, "heat balance: non-finite state at iteration %d",
                            it);
      change = fmax(change, fabs(xn[k] - x[k]));
      x[k] = RELAX * xn[k] + (1.0 - RELAX) * x[k];
    }
  }
  if (change > TOL)
    return vr_error_set(err, VR_E_NUMERIC, "heat balance did not converge in %d iterations (last "
                                           "change %g)", MAX_ITER, change);
  for (int i = 0; i < n; i++) {
    out->T[2 * i] = x[4 * i], out->T[2 * i + 1] = x[4 * i + 3];
    out->J[2 * i] = x[4 * i + 1], out->J[2 * i + 1] = x[4 * i + 2];
  }
  for (int i = 0; i + 1 < n; i++)
    out->gap_h[i] = gap_h(&s->gap[i], H, tilt, x[4 * i + 3], x[4 * (i + 1)], &out->gap_Ra[i],
                          &out->gap_Nu[i]);
  double Tsi = x[4 * (n - 1) + 3], Jsi = x[4 * (n - 1) + 2], Tso = x[0], Jso = x[1];
  hc_in = indoor_h(e, H, tilt, Tsi);
  out->q_in = (J_in - Jsi) + hc_in * (e->T_in - Tsi);
  /* Film coefficients, convective plus radiative (the radiative part is
   * undefined when the face sits at the environment's temperature). */
  double Trad_out = pow(J_out / sg, 0.25);
  out->h_in = hc_in + (fabs(e->T_in - Tsi) > 1e-9 ? (J_in - Jsi) / (e->T_in - Tsi) : 0.0);
  out->h_out = hc_out + (fabs(Tso - Trad_out) > 1e-9 ? (Jso - J_out) / (Tso - Trad_out) : 0.0);
  out->iterations = it;
  return VR_OK;
}

vr_status vr_thermal_nfrc(const vr_thermal_system *s, double Tsol, vr_thermal_figures *out,
                          vr_error *err) {
  vr_thermal_state dark;
  vr_status st = vr_thermal_solve(s, &VR_ENV_NFRC_U, 0, &out->winter, err);
  if (!st) st = vr_thermal_solve(s, &VR_ENV_NFRC_SHGC, 1, &out->summer, err);
  if (!st) st = vr_thermal_solve(s, &VR_ENV_NFRC_SHGC, 0, &dark, err);
  if (st) return st;
  out->U = out->winter.q_in / (VR_ENV_NFRC_U.T_in - VR_ENV_NFRC_U.T_out);
  out->SHGC = Tsol - (out->summer.q_in - dark.q_in) / VR_ENV_NFRC_SHGC.solar_wm2;
  return VR_OK;
}
