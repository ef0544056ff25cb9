/* The regularised method for noisy responses (8-bit photos):
 *
 *     minimise ||W (A r - c)||^2 + lambda ||D2 r||^2,
 *
 * W the noise weights of the chosen model (vr_noise_model), D2 the second
 * differences, lambda chosen by generalised cross-validation (Golub, Heath
 * and Wahba, Technometrics 21, 1979), then the bounds 0 <= r <= 1 and the
 * clip inequalities imposed with the same lambda by the active-set solver.
 *
 * GCV in standard form (Eldén 1977; Hansen, "Rank-Deficient and Discrete
 * Ill-Posed Problems", 1998, section 2.3).  With A' = W A (m unclipped rows),
 * c' = W c, L = D2 = U_L S_L V_L^T, L^+ its pseudo-inverse and N_L (N x 2)
 * an orthonormal basis of its null space (straight lines), write
 * r = L^+ y + N_L z.  Then L r = y, and minimising over z leaves the
 * standard-form problem
 *
 *     minimise ||Abar y - cbar||^2 + lambda ||y||^2,
 *     Abar = (I - P_T) A' L^+,  cbar = (I - P_T) c',  T = A' N_L,
 *
 * P_T the projector on range(T), with r = L^+ y + N_L T^+ (c' - A' L^+ y).
 * With Abar = U S V^T (singular values s_i above rank_tol * s_1, k of them),
 * beta = U^T cbar, filter factors f_i = s_i^2 / (s_i^2 + lambda) and
 * n0 = rank T (2 unless the lights miss the straight lines), the influence
 * matrix H(lambda) = P_T + Abar (Abar^T Abar + lambda I)^-1 Abar^T has
 * trace n0 + sum f_i, and
 *
 *     GCV(lambda) = m ||(I - H) c'||^2 / (m - rho trace H)^2
 *                 = m [sum_i ((1 - f_i) beta_i)^2 + r_perp^2]
 *                   / (m - rho (n0 + sum_i f_i))^2,
 *
 * r_perp^2 = ||cbar||^2 - sum beta_i^2 (zero when k = m - n0, the usual case
 * with fewer observations than samples).  rho = 1 is the classical GCV of
 * Golub, Heath and Wahba.  With as few observations as here (3 per light)
 * classical GCV often prefers lambda -> 0, i.e. interpolating the noise: on
 * 8-bit ColorChecker data under 4 lights it did so for 5 of 24 patches and
 * gave a mean spectral RMSE of 0.068, against 0.025 for the best fixed
 * lambda.  The default rho = 1.4 is the "modified GCV" of Kim and Gu (J. R.
 * Stat. Soc. B 66, 2004), who recommend that value against this
 * undersmoothing; it gives 0.026 there (vr_recovery_options.gcv_rho).  The
 * score is minimised over 161 values
 * of lambda spaced evenly in log between s_k^2 / 10^6 and 100 s_1^2, then
 * by golden section between the best value's neighbours; ties go to the
 * smaller lambda.  With m - n0 <= 1 (a single light) GCV does not depend on
 * lambda at all, so the smallest value is taken: the smoothest exact fit. */
#include "recover_system.h"
#include "recover_gcv.h"
#include "recover_linalg.h"
#include "recover_qp.h"
#include "vr/colour.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define GCV_GRID 161

typedef struct gcv_data {
  size_t k, m;
  double dof0, rperp2, rho;
  const double *s, *beta;
} gcv_data;

/* m ||(I - H) c'||^2 / (m - rho tr H)^2, the denominator written as
 * (m - rho (n0 + k)) + rho sum (1 - f_i) so that it keeps its digits when
 * rho = 1 and lambda is small. */
static double gcv_eval(const gcv_data *g, double lambda) {
  double m = (double)g->m, n0 = m - g->dof0;
  double num = g->rperp2, tr = m - g->rho * (n0 + (double)g->k);
  for (size_t i = 0; i < g->k; i++) {
    double s2 = g->s[i] * g->s[i], one_minus_f = lambda / (s2 + lambda);
    num += one_minus_f * one_minus_f * g->beta[i] * g->beta[i];
    tr += g->rho * one_minus_f;
  }
  if (!(tr > 0.0)) return INFINITY;
  return m * num / (tr * tr);
}

/* The squared weighted residual ||(I - H) c'||^2 at lambda. */
static double residual2(const gcv_data *g, double lambda) {
  double num = g->rperp2;
  for (size_t i = 0; i < g->k; i++) {
    double s2 = g->s[i] * g->s[i], one_minus_f = lambda / (s2 + lambda);
    num += one_minus_f * one_minus_f * g->beta[i] * g->beta[i];
  }
  return num;
}

/* trace H = n0 + sum f_i and trace H^2 = n0 + sum f_i^2 at lambda. */
static void traces(const gcv_data *g, double lambda, double *tr, double *tr2) {
  double n0 = (double)g->m - g->dof0;
  *tr = n0;
  *tr2 = n0;
  for (size_t i = 0; i < g->k; i++) {
    double f = g->s[i] * g->s[i] / (g->s[i] * g->s[i] + lambda);
    *tr += f;
    *tr2 += f * f;
  }
}

/* Unbiased predictive risk (Mallows' C_L; Vogel, "Computational Methods
 * for Inverse Problems", SIAM 2002, section 7.1) with unit noise in the
 * weighted units: ||(I - H) c'||^2 + 2 tr H - m. */
static double upre_eval(const gcv_data *g, double lambda) {
  double tr, tr2;
  traces(g, lambda, &tr, &tr2);
  return residual2(g, lambda) + 2.0 * tr - (double)g->m;
}

/* Expected predictive risk of one pixel with unit noise whose noise-free
 * responses are c' (a region's mean, whose own noise is far smaller):
 * ||(I - H) c'||^2 + tr H^2, bias plus the variance the smoother lets
 * through. */
static double pixel_risk_eval(const gcv_data *g, double lambda) {
  double tr, tr2;
  traces(g, lambda, &tr, &tr2);
  return residual2(g, lambda) + tr2;
}

typedef double (*score_fn)(const gcv_data *g, double lambda);

/* The lambda that minimises score over the search range, and its value. */
static double score_minimise(const gcv_data *g, score_fn score, double *value) {
  double lo = log10(g->s[g->k - 1] * g->s[g->k - 1]) - 6.0;
  double hi = log10(g->s[0] * g->s[0]) + 2.0;
  double step = (hi - lo) / (GCV_GRID - 1), best = INFINITY;
  int at = 0;
  for (int i = 0; i < GCV_GRID; i++) {
    double v = score(g, pow(10.0, lo + step * i));
    if (v < best) {
      best = v;
      at = i;
    }
  }
  double a = lo + step * (at > 0 ? at - 1 : 0), b = lo + step * (at < GCV_GRID - 1 ? at + 1 : at);
  const double phi = 0.5 * (sqrt(5.0) - 1.0);
  double x1 = b - phi * (b - a), x2 = a + phi * (b - a);
  double f1 = score(g, pow(10.0, x1)), f2 = score(g, pow(10.0, x2));
  for (int it = 0; it < 60 && b - a > 1e-6; it++) {
    if (f1 <= f2) {
      b = x2;
      x2 = x1;
      f2 = f1;
      x1 = b - phi * (b - a);
      f1 = score(g, pow(10.0, x1));
    } else {
      a = x1;
      x1 = x2;
      f1 = f2;
      x2 = a + phi * (b - a);
      f2 = score(g, pow(10.0, x2));
    }
  }
  double xm = f1 <= f2 ? x1 : x2, fm = fmin(f1, f2);
  if (fm < best) {
    *value = fm;
    return pow(10.0, xm);
  }
  *value = best;
  return pow(10.0, lo + step * at);
}

/* Morozov's discrepancy principle: the largest lambda whose weighted
 * residual is no more than tau m, the misfit that noise of unit variance
 * per weighted observation explains (Morozov 1966; Hansen 1998, section
 * 7.2).  The residual grows with lambda, so the root is bracketed in
 * log lambda over the search range and found by bisection.  When even the
 * smallest lambda misses the target (the data ask for more than the prior
 * can give) the smallest is taken; when even the largest stays within it
 * (a straight line explains the data) the largest. */
static double discrepancy_lambda(const gcv_data *g, double tau) {
  double target = tau * (double)g->m;
  double lo = log10(g->s[g->k - 1] * g->s[g->k - 1]) - 6.0;
  double hi = log10(g->s[0] * g->s[0]) + 2.0;
  if (residual2(g, pow(10.0, lo)) >= target) return pow(10.0, lo);
  if (residual2(g, pow(10.0, hi)) <= target) return pow(10.0, hi);
  for (int it = 0; it < 80 && hi - lo > 1e-9; it++) {
    double mid = 0.5 * (lo + hi);
    if (residual2(g, pow(10.0, mid)) <= target) lo = mid;
    else hi = mid;
  }
  return pow(10.0, lo);
}

/* Noise weight of observation i: 1 / sigma_i when the caller measured the
 * noise, else from the system's noise model (vr_noise_model). */
static double noise_weight(vr_noise_model model, const double *sigma, size_t i, double c) {
  if (sigma) return 1.0 / sigma[i];
  if (model != VR_NOISE_SRGB8) return 1.0;
  double lin = fmin(fmax(c, 0.0), 1.0), v = vr_srgb_encode(lin);
  double slope = v <= 0.04045 ? 1.0 / 12.92 : 2.4 / 1.055 * pow((v + 0.055) / 1.055, 1.4);
  return 255.0 * sqrt(12.0) / slope; /* 1 / (step / sqrt 12), step = slope / 255 */
}

typedef struct reg_work {
  double *e, *t, *ut, *st, *vtt, *abar, *cbar, *ua, *sa, *vta, *beta, *y, *z;
} reg_work;

static void reg_free(reg_work *w) {
  free(w->e);
  free(w->t);
  free(w->ut);
  free(w->st);
  free(w->vtt);
  free(w->abar);
  free(w->cbar);
  free(w->ua);
  free(w->sa);
  free(w->vta);
  free(w->beta);
  free(w->y);
  free(w->z);
}

vr_status vr_recover_gcv_solve(const vr_gcv_problem *q, double *r, vr_gcv_result *res,
                               vr_error *err) {
  size_t n = q->n, mu = q->m, p = n - 2, qa = mu < p ? mu : p, qt = mu < 2 ? mu : 2;
  const double *au = q->a, *cu = q->c;
  res->flat = 0;
  reg_work w = {0};
  w.e = malloc(mu * p * sizeof(double));
  w.t = malloc(mu * 2 * sizeof(double));
  w.ut = malloc(mu * 2 * sizeof(double));
  w.st = malloc(2 * sizeof(double));
  w.vtt = malloc(4 * sizeof(double));
  w.abar = malloc(mu * p * sizeof(double));
  w.cbar = malloc(mu * sizeof(double));
  w.ua = malloc(mu * qa * sizeof(double));
  w.sa = malloc(qa * sizeof(double));
  w.vta = malloc(qa * p * sizeof(double));
  w.beta = malloc(qa * sizeof(double));
  w.y = malloc(p * sizeof(double));
  w.z = malloc((mu > n ? mu : n) * sizeof(double));
  if (!w.e || !w.t || !w.ut || !w.st || !w.vtt || !w.abar || !w.cbar || !w.ua || !w.sa ||
      !w.vta || !w.beta || !w.y || !w.z) {
    reg_free(&w);
    return vr_error_set(err, VR_E_NOMEM, "%s: out of memory", q->what);
  }
  /* E = A' L^+, T = A' N_L. */
  for (size_t i = 0; i < mu; i++) {
    for (size_t col = 0; col < p; col++) {
      double v = 0.0;
      for (size_t j = 0; j < n; j++) v += au[i * n + j] * q->lpinv[j * p + col];
      w.e[i * p + col] = v;
    }
    for (size_t col = 0; col < 2; col++) {
      double v = 0.0;
      for (size_t j = 0; j < n; j++) v += au[i * n + j] * q->nl[j * 2 + col];
      w.t[i * 2 + col] = v;
    }
  }
  /* Rank cuts are relative to the scale of the whole weighted problem, not
   * to each factor's own largest singular value: Abar can be zero up to
   * rounding (two unclipped rows, both absorbed by the straight lines). */
  double scale2 = 0.0;
  for (size_t i = 0; i < mu * p; i++) scale2 += w.e[i] * w.e[i];
  for (size_t i = 0; i < mu * 2; i++) scale2 += w.t[i] * w.t[i];
  double cut = q->rank_tol * sqrt(scale2);
  vr_status st = VR_OK;
  int info_l = vr_recover_svd(mu, 2, w.t, w.ut, w.st, w.vtt);
  size_t n0 = 0;
  if (info_l == 0)
    while (n0 < qt && w.st[n0] > cut) n0++;
  /* Abar = (I - Q Q^T) E, cbar = (I - Q Q^T) c', Q the first n0 columns of U_T. */
  if (info_l == 0) {
    memcpy(w.abar, w.e, mu * p * sizeof(double));
    memcpy(w.cbar, cu, mu * sizeof(double));
    for (size_t a = 0; a < n0; a++) {
      double qc = 0.0;
      for (size_t i = 0; i < mu; i++) qc += w.ut[i * qt + a] * cu[i];
      for (size_t i = 0; i < mu; i++) w.cbar[i] -= w.ut[i * qt + a] * qc;
      for (size_t col = 0; col < p; col++) {
        double qe = 0.0;
        for (size_t i = 0; i < mu; i++) qe += w.ut[i * qt + a] * w.e[i * p + col];
        for (size_t i = 0; i < mu; i++) w.abar[i * p + col] -= w.ut[i * qt + a] * qe;
      }
    }
    info_l = vr_recover_svd(mu, p, w.abar, w.ua, w.sa, w.vta);
  }
  if (info_l != 0) {
    st = info_l == -1000 ? vr_error_set(err, VR_E_NOMEM, "%s: out of memory", q->what)
                         : vr_error_set(err, VR_E_NUMERIC, "%s: LAPACK failed (info %d)",
                                        q->what, info_l);
    reg_free(&w);
    return st;
  }
  size_t kq = 0;
  while (kq < qa && w.sa[kq] > cut) kq++;
  double cb2 = 0.0, b2 = 0.0;
  for (size_t i = 0; i < mu; i++) cb2 += w.cbar[i] * w.cbar[i];
  for (size_t a = 0; a < kq; a++) {
    double v = 0.0;
    for (size_t i = 0; i < mu; i++) v += w.ua[i * qa + a] * w.cbar[i];
    w.beta[a] = v;
    b2 += v * v;
  }
  gcv_data g = {.k = kq, .m = mu, .dof0 = (double)(mu - n0),
                .rperp2 = kq + n0 >= mu ? 0.0 : fmax(0.0, cb2 - b2), .rho = q->rho,
                .s = w.sa, .beta = w.beta};
  double lambda = 0.0, gcv = 0.0;
  if (q->lambda >= 0.0) {
    lambda = q->lambda;
    gcv = kq ? gcv_eval(&g, lambda) : 0.0;
  } else if (kq > 0 && mu - n0 <= 1 && (q->rule == VR_LAMBDA_GCV || q->rule == VR_LAMBDA_AUTO)) {
    lambda = w.sa[kq - 1] * w.sa[kq - 1] * 1e-6;
    gcv = gcv_eval(&g, lambda);
    res->flat = 1;
  } else if (kq > 0 && q->rule == VR_LAMBDA_DISCREPANCY) {
    lambda = discrepancy_lambda(&g, q->tau);
    gcv = gcv_eval(&g, lambda);
  } else if (kq > 0 && q->rule == VR_LAMBDA_UPRE) {
    double ignored;
    lambda = score_minimise(&g, upre_eval, &ignored);
    gcv = gcv_eval(&g, lambda);
  } else if (kq > 0 && q->rule == VR_LAMBDA_PIXEL_RISK) {
    double ignored;
    lambda = score_minimise(&g, pixel_risk_eval, &ignored);
    gcv = gcv_eval(&g, lambda);
  } else if (kq > 0) {
    lambda = score_minimise(&g, gcv_eval, &gcv);
  } else {
    /* No direction left for lambda to act on: the fit is the straight line
     * through the data whatever lambda is, and lambda only matters once the
     * bounds bite.  Keep it as small relative to the data as in the flat
     * case. */
    lambda = 1e-6 * scale2;
    res->flat = 1;
  }
  /* Effective degrees of freedom: trace H = n0 + sum f_i. */
  double dof = (double)n0;
  for (size_t a = 0; a < kq; a++) dof += w.sa[a] * w.sa[a] / (w.sa[a] * w.sa[a] + lambda);
  /* y = sum f_i beta_i / s_i v_i, r = L^+ y + N_L T^+ (c' - E y). */
  memset(w.y, 0, p * sizeof(double));
  for (size_t a = 0; a < kq; a++) {
    double coef = w.sa[a] * w.beta[a] / (w.sa[a] * w.sa[a] + lambda);
    for (size_t col = 0; col < p; col++) w.y[col] += coef * w.vta[a * p + col];
  }
  for (size_t j = 0; j < n; j++) {
    double v = 0.0;
    for (size_t col = 0; col < p; col++) v += q->lpinv[j * p + col] * w.y[col];
    r[j] = v;
  }
  for (size_t i = 0; i < mu; i++) {
    double v = cu[i];
    for (size_t col = 0; col < p; col++) v -= w.e[i * p + col] * w.y[col];
    w.z[i] = v;
  }
  double zt[2] = {0.0, 0.0};
  for (size_t a = 0; a < n0; a++) {
    double v = 0.0;
    for (size_t i = 0; i < mu; i++) v += w.ut[i * qt + a] * w.z[i];
    v /= w.st[a];
    for (size_t col = 0; col < 2; col++) zt[col] += w.vtt[a * 2 + col] * v;
  }
  for (size_t j = 0; j < n; j++) r[j] += q->nl[j * 2] * zt[0] + q->nl[j * 2 + 1] * zt[1];
  res->lambda = lambda;
  res->gcv = gcv;
  res->dof = dof;
  reg_free(&w);
  return VR_OK;
}

/* The unconstrained regularised solution on the mu unclipped rows. */
static vr_status solve_unbounded(const vr_recovery_system *s, const double *c,
                                 const double *sigma, const unsigned char *clipped, size_t mu,
                                 double *r,
                                 double *lambda_out, vr_recover_info *info, vr_error *err) {
  size_t n = s->n, m = s->m;
  double *au = malloc(mu * n * sizeof *au), *cu = malloc(mu * sizeof *cu);
  if (!au || !cu) {
    free(au);
    free(cu);
    return vr_error_set(err, VR_E_NOMEM, "regularised recovery: out of memory");
  }
  size_t k = 0;
  for (size_t i = 0; i < m; i++) {
    if (clipped && clipped[i] != VR_CLIP_NONE) continue;
    double wt = noise_weight(s->opt.noise, sigma, i, c[i]);
    for (size_t j = 0; j < n; j++) au[k * n + j] = wt * s->a[i * n + j];
    cu[k++] = wt * c[i];
  }
  vr_gcv_problem q = {.m = mu, .n = n, .a = au, .c = cu, .lpinv = s->lpinv, .nl = s->nl,
                      .rank_tol = s->opt.rank_tol, .rho = s->opt.gcv_rho,
                      .lambda = s->opt.lambda, .tau = s->opt.discrepancy_tau,
                      .rule = s->opt.lambda_rule == VR_LAMBDA_AUTO
                                  ? (sigma ? VR_LAMBDA_UPRE : VR_LAMBDA_GCV)
                                  : (int)s->opt.lambda_rule,
                      .what = "regularised recovery"};
  vr_gcv_result res;
  vr_status st = vr_recover_gcv_solve(&q, r, &res, err);
  free(au);
  free(cu);
  if (st != VR_OK) return st;
  if (res.flat) info->flags |= VR_RECOVER_FLAG_GCV_FLAT;
  *lambda_out = res.lambda;
  info->gcv = res.gcv;
  return VR_OK;
}

vr_status vr_recover_regularised(const vr_recovery_system *s, const double *c,
                                 const double *sigma, const unsigned char *clipped, double *r,
                                 vr_recover_info *info, vr_error *err) {
  size_t n = s->n, m = s->m, mu = info->used, nc = info->clipped, nv = n + nc;
  double lambda = 1.0;
  if (mu > 0) {
    vr_status st = solve_unbounded(s, c, sigma, clipped, mu, r, &lambda, info, err);
    if (st != VR_OK) return st;
  } else {
    /* Nothing but inequalities: lambda = 1 only balances them against
     * smoothness, from a mid-grey start. */
    info->flags |= VR_RECOVER_FLAG_NO_DATA;
    for (size_t j = 0; j < n; j++) r[j] = 0.5;
  }
  info->lambda = lambda;
  info->rank = s->rank;

  int inside = mu > 0;
  for (size_t j = 0; j < n && inside; j++) inside = r[j] >= 0.0 && r[j] <= 1.0;
  for (size_t i = 0; i < m && inside; i++) {
    unsigned char mark = clipped ? clipped[i] : VR_CLIP_NONE;
    if (mark == VR_CLIP_NONE) continue;
    double v = 0.0;
    for (size_t j = 0; j < n; j++) v += s->a[i * n + j] * r[j];
    inside = mark == VR_CLIP_HIGH ? v >= c[i] : v <= c[i];
  }
  if (inside) return VR_OK;

  /* The same objective over the bounds, clipped rows as one-sided terms:
   * G = [W A | W sign (slacks); sqrt(lambda) D2 | 0], h = [W c; 0]. */
  size_t mg = m + (n - 2);
  double *g = calloc(mg * nv, sizeof *g), *h = calloc(mg, sizeof *h),
         *lo = malloc(nv * sizeof *lo), *hi = malloc(nv * sizeof *hi), *x = malloc(nv * sizeof *x);
  vr_status st = VR_OK;
  if (!g || !h || !lo || !hi || !x) {
    st = vr_error_set(err, VR_E_NOMEM, "regularised recovery: out of memory");
    goto done;
  }
  for (size_t j = 0; j < n; j++) {
    lo[j] = 0.0;
    hi[j] = 1.0;
    x[j] = fmin(fmax(r[j], 0.0), 1.0);
  }
  size_t slack = n;
  for (size_t i = 0; i < m; i++) {
    double wt = noise_weight(s->opt.noise, sigma, i, c[i]), ar = 0.0;
    for (size_t j = 0; j < n; j++) {
      g[i * nv + j] = wt * s->a[i * n + j];
      ar += s->a[i * n + j] * x[j];
    }
    h[i] = wt * c[i];
    unsigned char mark = clipped ? clipped[i] : VR_CLIP_NONE;
    if (mark == VR_CLIP_NONE) continue;
    double sign = vr_recover_slack_sign(mark);
    g[i * nv + slack] = wt * sign;
    lo[slack] = 0.0;
    hi[slack] = INFINITY;
    x[slack] = fmax(0.0, (c[i] - ar) / sign);
    slack++;
  }
  double sl = sqrt(lambda);
  for (size_t i = 0; i + 2 < n; i++)
    for (size_t j = 0; j < n; j++) g[(m + i) * nv + j] = sl * s->d2[i * n + j];
  vr_rqp q = {.n = nv, .mg = mg, .g = g, .h = h, .me = 0, .lo = lo, .hi = hi,
              .rank_tol = s->opt.rank_tol, .e_ref = 1.0, .max_iter = s->opt.max_iter};
  vr_rqp_result res = vr_recover_rqp(&q, x, &info->iterations);
  if (res < 0) {
    st = res == VR_RQP_NOMEM ? vr_error_set(err, VR_E_NOMEM, "regularised recovery: out of memory")
                             : vr_error_set(err, VR_E_NUMERIC,
                                            "regularised recovery: LAPACK failed in the bounds");
    goto done;
  }
  if (res == VR_RQP_MAX_ITER) info->flags |= VR_RECOVER_FLAG_MAX_ITER;
  info->bounds_active = 0;
  for (size_t j = 0; j < n; j++) {
    r[j] = x[j];
    if (x[j] <= 0.0 || x[j] >= 1.0) info->bounds_active++;
  }
done:
  free(g);
  free(h);
  free(lo);
  free(hi);
  free(x);
  return st;
}

vr_status vr_recover_pixel_lambda(const vr_recovery_system *s, const double *c_mean,
                                  const double *sigma_pixel, const unsigned char *clipped,
                                  double *lambda, vr_error *err) {
  if (!s || !c_mean || !sigma_pixel || !lambda)
    return vr_error_set(err, VR_E_ARG, "vr_recover_pixel_lambda: NULL argument");
  size_t n = s->n, m = s->m, mu = 0;
  for (size_t i = 0; i < m; i++) {
    if (!isfinite(c_mean[i]) || !(isfinite(sigma_pixel[i]) && sigma_pixel[i] > 0.0))
      return vr_error_set(err, VR_E_ARG, "vr_recover_pixel_lambda: response %zu or its noise "
                                         "is not a finite number (noise must be > 0)", i);
    if (!clipped || clipped[i] == VR_CLIP_NONE) mu++;
  }
  if (mu < 2)
    return vr_error_set(err, VR_E_ARG, "vr_recover_pixel_lambda: %zu unclipped responses, need 2",
                        mu);
  double *r = malloc(n * sizeof *r);
  if (!r) return vr_error_set(err, VR_E_NOMEM, "vr_recover_pixel_lambda: out of memory");
  vr_recovery_system tmp = *s;
  tmp.opt.lambda = -1.0;
  tmp.opt.lambda_rule = (vr_lambda_rule)VR_LAMBDA_PIXEL_RISK;
  vr_recover_info info = {0};
  double lam = 0.0;
  vr_status st = solve_unbounded(&tmp, c_mean, sigma_pixel, clipped, mu, r, &lam, &info, err);
  free(r);
  if (st == VR_OK) *lambda = lam;
  return st;
}
