/* n, k of an uncoated pane from its T and R; vr/slab_invert.h has the
 * equations and the choice of root. */
#include "vr/slab_invert.h"

#include <math.h>
#include <string.h>

#include "vr/lsq.h"
#include "vr/optics.h"

/* The algebra alone, no derivatives. */
static int invert(double T, double R, double d_nm, double lambda_nm, vr_slab_nk *o) {
  o->n = o->k = o->n_minus = o->r = o->a = NAN;
  o->flags = VR_SLAB_OK;
  if (!(T > 0) || !(R > 0) || T + R > 1.0 + VR_SLAB_A_EXCESS) return o->flags = VR_SLAB_NO_ROOT;
  double B = 2.0 + T * T - (1.0 - R) * (1.0 - R);
  double disc = B * B - 4.0 * R * (2.0 - R);
  if (disc < 0) return o->flags = VR_SLAB_NO_ROOT;
  /* The smaller root, written without cancellation: r = 2 c / (B + sqrt). */
  double r = 2.0 * R / (B + sqrt(disc));
  double a = (R - r) / (r * T);
  if (a > 1.0) {
    /* Noise on nearly lossless glass pushes a above 1; n still follows
     * from r, so clamp (k = 0) unless the excess is beyond any noise. */
    if (a > 1.0 + VR_SLAB_A_EXCESS) return o->flags = VR_SLAB_NO_ROOT;
    a = 1.0;
    o->flags |= VR_SLAB_CLAMPED_A;
  }
  if (!(a > 0)) return o->flags = VR_SLAB_NO_ROOT;
  double k = -lambda_nm * log(a) / (4.0 * M_PI * d_nm);
  double base = (1.0 + r) / (1.0 - r);
  double q = 4.0 * r / ((1.0 - r) * (1.0 - r)) - k * k;
  o->r = r;
  o->a = a;
  o->k = k;
  if (q < 0) {
    o->flags |= VR_SLAB_NO_INDEX;
    return o->flags;
  }
  o->n = base + sqrt(q);
  o->n_minus = base - sqrt(q);
  return o->flags;
}

vr_status vr_slab_invert_normal(double T, double R, double d_nm, double lambda_nm, vr_slab_nk *out,
                                vr_error *err) {
  if (!isfinite(T) || !isfinite(R))
    return vr_error_set(err, VR_E_ARG, "T and R must be finite (T = %g, R = %g)", T, R);
  if (!(d_nm > 0) || !isfinite(d_nm))
    return vr_error_set(err, VR_E_ARG, "thickness must be positive (%g nm)", d_nm);
  if (!(lambda_nm > 0) || !isfinite(lambda_nm))
    return vr_error_set(err, VR_E_ARG, "wavelength must be positive (%g nm)", lambda_nm);
  invert(T, R, d_nm, lambda_nm, out);
  out->dn_dT = out->dn_dR = out->dk_dT = out->dk_dR = NAN;
  if (out->flags & (VR_SLAB_NO_ROOT | VR_SLAB_NO_INDEX)) return VR_OK;
  /* Sensitivities by central differences with a step well above rounding
   * (1e-7 of a unit photometric scale) and below any real noise. */
  const double h = 1e-7;
  vr_slab_nk p, m;
  int fp = invert(T + h, R, d_nm, lambda_nm, &p), fm = invert(T - h, R, d_nm, lambda_nm, &m);
  if (!(fp & ~VR_SLAB_CLAMPED_A) && !(fm & ~VR_SLAB_CLAMPED_A)) {
    out->dn_dT = (p.n - m.n) / (2 * h);
    out->dk_dT = (p.k - m.k) / (2 * h);
  }
  fp = invert(T, R + h, d_nm, lambda_nm, &p);
  fm = invert(T, R - h, d_nm, lambda_nm, &m);
  if (!(fp & ~VR_SLAB_CLAMPED_A) && !(fm & ~VR_SLAB_CLAMPED_A)) {
    out->dn_dR = (p.n - m.n) / (2 * h);
    out->dk_dR = (p.k - m.k) / (2 * h);
  }
  return VR_OK;
}

typedef struct angles_ctx {
  const vr_slab_obs *obs;
  size_t count;
  double d_nm, lambda_nm, sigma_T, sigma_R;
} angles_ctx;

static int angles_residual(const double *p, double *res, double *jac, void *user) {
  (void)jac;
  const angles_ctx *c = user;
  if (!(p[0] > 0) || !(p[1] >= 0)) return 1;
  for (size_t i = 0; i < c->count; i++) {
    vr_slab_result s;
    if (vr_slab(1.0, p[0] + I * p[1], c->d_nm, c->obs[i].angle_deg * M_PI / 180.0, c->lambda_nm,
                &s, NULL))
      return 1;
    res[2 * i] = (0.5 * (s.T[0] + s.T[1]) - c->obs[i].T) / c->sigma_T;
    res[2 * i + 1] = (0.5 * (s.R[0] + s.R[1]) - c->obs[i].R) / c->sigma_R;
  }
  return 0;
}

vr_status vr_slab_invert_angles(const vr_slab_obs *obs, size_t count, double d_nm,
                                double lambda_nm, double sigma_T, double sigma_R, vr_slab_nk *out,
                                double *n_err, double *k_err, double *cond, vr_error *err) {
  if (count == 0) return vr_error_set(err, VR_E_ARG, "no observations");
  if (!(sigma_T > 0) || !(sigma_R > 0))
    return vr_error_set(err, VR_E_ARG, "photometric standard deviations must be positive");
  size_t first = 0;
  for (size_t i = 0; i < count; i++) {
    if (!(obs[i].angle_deg >= 0 && obs[i].angle_deg < 90))
      return vr_error_set(err, VR_E_ARG, "angle of incidence %g deg outside [0, 90)", obs[i].angle_deg);
    if (obs[i].angle_deg < obs[first].angle_deg) first = i;
  }
  vr_status st = vr_slab_invert_normal(obs[first].T, obs[first].R, d_nm, lambda_nm, out, err);
  if (st) return st;
  double p[2] = {out->n, out->k};
  if (!isfinite(p[0])) p[0] = 1.5;   /* start of a typical glass */
  if (!isfinite(p[1]) || p[1] < 0) p[1] = 0;
  angles_ctx c = {obs, count, d_nm, lambda_nm, sigma_T, sigma_R};
  vr_lsq *lsq = vr_lsq_create(2, 2 * count, angles_residual, &c, false, err);
  if (!lsq) return err ? err->status : VR_E_NOMEM;
  double cov[4];
  st = vr_lsq_set_bounds(lsq, 0, 1.0, 20.0, err);
  if (!st && p[0] <= 1.0) p[0] = 1.0 + 1e-6;
  if (!st) st = vr_lsq_set_bounds(lsq, 1, 0.0, 20.0, err);
  if (!st) st = vr_lsq_solve(lsq, p, NULL, NULL, err);
  if (!st && 2 * count > 2) st = vr_lsq_covariance(lsq, p, false, cov, err);
  else if (!st) {
    /* Two numbers, two unknowns: the uncertainty is the propagated noise. */
    cov[0] = pow(out->dn_dT * sigma_T, 2) + pow(out->dn_dR * sigma_R, 2);
    cov[3] = pow(out->dk_dT * sigma_T, 2) + pow(out->dk_dR * sigma_R, 2);
    cov[1] = cov[2] = out->dn_dT * out->dk_dT * sigma_T * sigma_T +
                      out->dn_dR * out->dk_dR * sigma_R * sigma_R;
  }
  vr_lsq_destroy(lsq);
  if (st) return st;
  out->n = p[0];
  out->k = p[1];
  if (n_err) *n_err = sqrt(cov[0]);
  if (k_err) *k_err = sqrt(cov[3]);
  if (cond) {
    /* Condition of the correlation matrix of (n, k): 1 for independent
     * estimates, large when T and R cannot tell n from k. */
    double rho = cov[1] / sqrt(cov[0] * cov[3]);
    rho = fmin(fabs(rho), 1.0);
    *cond = rho < 1.0 ? (1.0 + rho) / (1.0 - rho) : INFINITY;
  }
  return VR_OK;
}

vr_status vr_slab_angular(double T0, double R0, double d_nm, double lambda_nm, double angle_deg,
                          double *T, double *R, double pol[4], int *flags, vr_error *err) {
  vr_slab_nk nk = {.flags = VR_SLAB_NO_ROOT}; /* what an early error return leaves */
  vr_status st = vr_slab_invert_normal(T0, R0, d_nm, lambda_nm, &nk, err);
  if (st) return st;
  if (flags) *flags = nk.flags;
  if (nk.flags & (VR_SLAB_NO_ROOT | VR_SLAB_NO_INDEX))
    return vr_error_set(err, VR_E_NUMERIC,
                        "no uncoated pane of %g mm has T = %g and R = %g at %g nm",
                        d_nm * 1e-6, T0, R0, lambda_nm);
  vr_slab_result s;
  st = vr_slab(1.0, nk.n + I * nk.k, d_nm, angle_deg * M_PI / 180.0, lambda_nm, &s, err);
  if (st) return st;
  *T = 0.5 * (s.T[0] + s.T[1]);
  *R = 0.5 * (s.R[0] + s.R[1]);
  if (pol) {
    pol[0] = s.T[0];
    pol[1] = s.T[1];
    pol[2] = s.R[0];
    pol[3] = s.R[1];
  }
  return VR_OK;
}
