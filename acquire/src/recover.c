/* The recovery system (the stacked camera matrix A of several lights, its
 * SVD and pseudo-inverse, the smoothness operator) and the Matrix-R method
 * of Cohen and Kappauf: r* = A^T (A A^T)^-1 c, computed as the SVD
 * pseudo-inverse so that a rank-deficient A (two identical lights) still
 * gives the minimum-norm spectrum instead of a singular solve. */
#include "recover_linalg.h"
#include "recover_system.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void vr_recovery_options_default(vr_recovery_options *opt) {
  opt->rank_tol = 1e-10;
  opt->feas_tol = 1e-9;
  opt->noise = VR_NOISE_UNIFORM;
  opt->lambda = -1.0;
  opt->gcv_rho = 1.4;
  opt->lambda_rule = VR_LAMBDA_AUTO;
  opt->discrepancy_tau = 1.0;
  opt->max_iter = 0;
}

const char *vr_recover_method_name(vr_recover_method m) {
  switch (m) {
    case VR_RECOVER_MATRIX_R: return "matrix-r";
    case VR_RECOVER_BOUNDED: return "bounded";
    case VR_RECOVER_REGULARISED: return "regularised";
  }
  return "unknown";
}

static vr_status lapack_failed(vr_error *err, const char *what, int info) {
  if (info == -1000) return vr_error_set(err, VR_E_NOMEM, "%s: out of memory", what);
  return vr_error_set(err, VR_E_NUMERIC, "%s: LAPACK failed (info %d)", what, info);
}

/* ---- the system --------------------------------------------------------- */

void vr_recovery_system_destroy(vr_recovery_system *s) {
  if (!s) return;
  free(s->grid);
  free(s->a);
  free(s->an);
  free(s->rowscale);
  free(s->sv);
  free(s->p);
  free(s->d2);
  free(s->lpinv);
  free(s->nl);
  free(s);
}

vr_recovery_system *vr_recovery_system_create(const vr_camera *cam, size_t lights,
                                              const vr_spectrum *const *spd, const double *scale,
                                              const vr_recovery_options *opt, vr_error *err) {
  if (!cam || !spd || lights == 0) {
    vr_error_set(err, VR_E_ARG, "recovery system: need a camera and at least one light");
    return NULL;
  }
  vr_recovery_options o;
  vr_recovery_options_default(&o);
  if (opt) o = *opt;
  if (o.discrepancy_tau == 0.0) o.discrepancy_tau = 1.0; /* options zeroed by hand */
  if (!(o.discrepancy_tau > 0.0 && o.discrepancy_tau < 1e6) ||
      (o.lambda_rule != VR_LAMBDA_AUTO && o.lambda_rule != VR_LAMBDA_GCV &&
       o.lambda_rule != VR_LAMBDA_DISCREPANCY && o.lambda_rule != VR_LAMBDA_UPRE)) {
    vr_error_set(err, VR_E_ARG, "recovery options: need a known lambda rule and 0 < "
                                "discrepancy_tau < 1e6");
    return NULL;
  }
  if (!(o.rank_tol > 0.0 && o.rank_tol < 1.0) || !(o.feas_tol > 0.0) || o.max_iter < 0 ||
      !(o.gcv_rho >= 1.0 && o.gcv_rho < 10.0) ||
      (o.noise != VR_NOISE_UNIFORM && o.noise != VR_NOISE_SRGB8) || isnan(o.lambda) ||
      isinf(o.lambda)) {
    vr_error_set(err, VR_E_ARG,
                 "recovery options: need 0 < rank_tol < 1, feas_tol > 0, 1 <= gcv_rho < 10, "
                 "max_iter >= 0, a known noise model and a finite lambda");
    return NULL;
  }
  for (size_t l = 0; l < lights; l++) {
    if (!spd[l]) {
      vr_error_set(err, VR_E_ARG, "recovery system: light %zu is NULL", l);
      return NULL;
    }
    if (scale && !(isfinite(scale[l]) && scale[l] > 0.0)) {
      vr_error_set(err, VR_E_ARG, "recovery system: exposure of light %zu is %g, need > 0", l,
                   scale[l]);
      return NULL;
    }
  }
  size_t n = vr_camera_samples(cam), m = 3 * lights, q = m < n ? m : n;
  vr_recovery_system *s = calloc(1, sizeof *s);
  if (!s) {
    vr_error_set(err, VR_E_NOMEM, "recovery system: out of memory");
    return NULL;
  }
  s->n = n;
  s->m = m;
  s->lights = lights;
  s->opt = o;
  s->nsv = q;
  s->grid = malloc(n * sizeof *s->grid);
  s->a = malloc(m * n * sizeof *s->a);
  s->an = malloc(m * n * sizeof *s->an);
  s->rowscale = malloc(m * sizeof *s->rowscale);
  s->sv = malloc(q * sizeof *s->sv);
  s->p = malloc(n * m * sizeof *s->p);
  s->d2 = malloc((n - 2) * n * sizeof *s->d2);
  s->lpinv = malloc(n * (n - 2) * sizeof *s->lpinv);
  s->nl = malloc(n * 2 * sizeof *s->nl);
  if (!s->grid || !s->a || !s->an || !s->rowscale || !s->sv || !s->p || !s->d2 || !s->lpinv ||
      !s->nl) {
    vr_recovery_system_destroy(s);
    vr_error_set(err, VR_E_NOMEM, "recovery system: out of memory");
    return NULL;
  }
  memcpy(s->grid, vr_camera_grid(cam), n * sizeof *s->grid);
  for (size_t l = 0; l < lights; l++) {
    if (vr_camera_response(cam, spd[l], s->an + 3 * l * n, err) != VR_OK) {
      vr_error_prefix(err, "light %zu: ", l);
      vr_recovery_system_destroy(s);
      return NULL;
    }
    double k = scale ? scale[l] : 1.0;
    for (size_t i = 0; i < 3; i++) s->rowscale[3 * l + i] = k;
  }
  for (size_t i = 0; i < m; i++)
    for (size_t j = 0; j < n; j++) s->a[i * n + j] = s->an[i * n + j] * s->rowscale[i];

  /* Singular values and pseudo-inverse of the exposure-normalised A; the
   * pseudo-inverse of A itself is then P = An^+ diag(1 / exposure). */
  int info = vr_recover_svd(m, n, s->an, NULL, s->sv, NULL);
  if (info != 0) {
    lapack_failed(err, "recovery system: SVD of A", info);
    vr_recovery_system_destroy(s);
    return NULL;
  }
  s->cond = s->sv[q - 1] > 0.0 ? s->sv[0] / s->sv[q - 1] : INFINITY;
  info = vr_recover_pinv(m, n, s->an, o.rank_tol, 0.0, s->p, &s->rank);
  if (info != 0) {
    lapack_failed(err, "recovery system: pseudo-inverse of A", info);
    vr_recovery_system_destroy(s);
    return NULL;
  }
  for (size_t j = 0; j < n; j++)
    for (size_t i = 0; i < m; i++) s->p[j * m + i] /= s->rowscale[i];

  info = vr_recover_smoothness(n, s->grid, s->d2, s->lpinv, s->nl);
  if (info != 0) {
    lapack_failed(err, "recovery system: SVD of the second differences", info);
    vr_recovery_system_destroy(s);
    return NULL;
  }
  return s;
}

size_t vr_recovery_system_samples(const vr_recovery_system *s) { return s->n; }
size_t vr_recovery_system_rows(const vr_recovery_system *s) { return s->m; }
size_t vr_recovery_system_lights(const vr_recovery_system *s) { return s->lights; }
const double *vr_recovery_system_grid(const vr_recovery_system *s) { return s->grid; }
const double *vr_recovery_system_matrix(const vr_recovery_system *s) { return s->a; }
const double *vr_recovery_system_singular_values(const vr_recovery_system *s, size_t *count) {
  if (count) *count = s->nsv;
  return s->sv;
}
double vr_recovery_system_condition(const vr_recovery_system *s) { return s->cond; }
size_t vr_recovery_system_rank(const vr_recovery_system *s) { return s->rank; }

vr_status vr_recovery_matrix(const vr_recovery_system *s, double *P) {
  if (!s || !P) return VR_E_ARG;
  memcpy(P, s->p, s->n * s->m * sizeof *P);
  return VR_OK;
}

void vr_render_rgb(const vr_recovery_system *s, const double *r, double *c) {
  for (size_t i = 0; i < s->m; i++) {
    double v = 0.0;
    for (size_t j = 0; j < s->n; j++) v += s->a[i * s->n + j] * r[j];
    c[i] = v;
  }
}

void vr_recover_finish_info(const vr_recovery_system *s, const double *c, const double *sigma,
                            const unsigned char *clipped, const double *r, vr_recover_info *info) {
  double res = 0.0, resw = 0.0, viol = 0.0, chi2 = 0.0;
  for (size_t i = 0; i < s->m; i++) {
    double v = 0.0;
    for (size_t j = 0; j < s->n; j++) v += s->a[i * s->n + j] * r[j];
    double d = v - c[i];
    unsigned char mark = clipped ? clipped[i] : VR_CLIP_NONE;
    if (mark == VR_CLIP_NONE) {
      res += d * d;
      resw += (d / s->rowscale[i]) * (d / s->rowscale[i]);
      if (sigma) chi2 += (d / sigma[i]) * (d / sigma[i]);
    } else {
      double breach = mark == VR_CLIP_HIGH ? -d : d;
      if (breach > viol) viol = breach;
    }
  }
  info->residual = sqrt(res);
  info->residual_white = sqrt(resw);
  info->clip_violation = viol;
  info->chi2 = sigma ? chi2 : NAN;
  info->chi2_limit = sigma ? vr_recover_chi2_limit(info->used) : NAN;
}

/* ---- Matrix R ----------------------------------------------------------- */

vr_status vr_recover_matrix_r(const vr_recovery_system *s, const double *c,
                              const unsigned char *clipped, double *r, vr_recover_info *info,
                              vr_error *err) {
  size_t n = s->n, m = s->m;
  if (info->clipped == 0) {
    for (size_t j = 0; j < n; j++) {
      double v = 0.0;
      for (size_t i = 0; i < m; i++) v += s->p[j * m + i] * c[i];
      r[j] = v;
    }
    info->rank = s->rank;
  } else {
    /* Clipped rows are dropped: r* of the remaining observations, with the
     * rank still judged against the full system's largest singular value. */
    size_t mu = info->used;
    if (mu == 0) {
      memset(r, 0, n * sizeof *r);
      info->flags |= VR_RECOVER_FLAG_NO_DATA;
      info->rank = 0;
    } else {
      double *au = malloc(mu * n * sizeof *au), *cu = malloc(mu * sizeof *cu),
             *pu = malloc(n * mu * sizeof *pu);
      if (!au || !cu || !pu) {
        free(au);
        free(cu);
        free(pu);
        return vr_error_set(err, VR_E_NOMEM, "matrix R: out of memory");
      }
      size_t k = 0;
      for (size_t i = 0; i < m; i++) {
        if (clipped[i] != VR_CLIP_NONE) continue;
        memcpy(au + k * n, s->an + i * n, n * sizeof *au);
        cu[k++] = c[i] / s->rowscale[i];
      }
      int st = vr_recover_pinv(mu, n, au, s->opt.rank_tol, s->sv[0], pu, &info->rank);
      if (st == 0)
        for (size_t j = 0; j < n; j++) {
          double v = 0.0;
          for (size_t i = 0; i < mu; i++) v += pu[j * mu + i] * cu[i];
          r[j] = v;
        }
      free(au);
      free(cu);
      free(pu);
      if (st != 0) return lapack_failed(err, "matrix R", st);
      if (info->rank < (mu < n ? mu : n)) info->flags |= VR_RECOVER_FLAG_RANK_DEFICIENT;
    }
  }
  if (info->clipped == 0 && s->rank < s->nsv) info->flags |= VR_RECOVER_FLAG_RANK_DEFICIENT;
  for (size_t j = 0; j < n; j++)
    if (r[j] < 0.0 || r[j] > 1.0) {
      info->flags |= VR_RECOVER_FLAG_OUTSIDE_UNIT;
      break;
    }
  return VR_OK;
}

/* ---- entry point -------------------------------------------------------- */

/* The 99.9 % point of chi-squared with k degrees of freedom, by the cube
 * root approximation of Wilson and Hilferty (PNAS 17, 1931): 3 % above the
 * exact quantile at k = 1 (11.16 against 10.83), within 1 % from k = 6 on
 * (k = 12: 33.07 against 32.91), erring on the side of fewer flags. */
double vr_recover_chi2_limit(size_t k) {
  if (k == 0) return 0.0;
  const double z = 3.090232306; /* standard normal 99.9 % point */
  double a = 2.0 / (9.0 * (double)k), t = 1.0 - a + z * sqrt(a);
  return (double)k * t * t * t;
}

vr_status vr_recover_noisy(const vr_recovery_system *s, vr_recover_method method, const double *c,
                           const double *sigma, const unsigned char *clipped, double *r_out,
                           vr_recover_info *info_out, vr_error *err) {
  if (!s || !c || !r_out) return vr_error_set(err, VR_E_ARG, "vr_recover: NULL argument");
  if (method != VR_RECOVER_MATRIX_R && method != VR_RECOVER_BOUNDED &&
      method != VR_RECOVER_REGULARISED)
    return vr_error_set(err, VR_E_ARG, "vr_recover: unknown method %d", (int)method);
  vr_recover_info info;
  memset(&info, 0, sizeof info);
  for (size_t i = 0; i < s->m; i++) {
    if (!isfinite(c[i]))
      return vr_error_set(err, VR_E_ARG,
                          "vr_recover: response %zu (light %zu, channel %c) is not a finite number",
                          i, i / 3, "RGB"[i % 3]);
    if (sigma && !(isfinite(sigma[i]) && sigma[i] > 0.0))
      return vr_error_set(err, VR_E_ARG,
                          "vr_recover: noise %zu (light %zu, channel %c) is %g, need a finite "
                          "value > 0", i, i / 3, "RGB"[i % 3], sigma[i]);
    unsigned char mark = clipped ? clipped[i] : VR_CLIP_NONE;
    if (mark != VR_CLIP_NONE && mark != VR_CLIP_HIGH && mark != VR_CLIP_LOW)
      return vr_error_set(err, VR_E_ARG, "vr_recover: clip mark %u of response %zu is not 0, 1 or 2",
                          (unsigned)mark, i);
    if (mark == VR_CLIP_NONE)
      info.used++;
    else
      info.clipped++;
  }
  if (info.clipped) info.flags |= VR_RECOVER_FLAG_CLIPPED;
  vr_status st;
  switch (method) {
    case VR_RECOVER_MATRIX_R: st = vr_recover_matrix_r(s, c, clipped, r_out, &info, err); break;
    case VR_RECOVER_BOUNDED: st = vr_recover_bounded(s, c, clipped, r_out, &info, err); break;
    default: st = vr_recover_regularised(s, c, sigma, clipped, r_out, &info, err); break;
  }
  if (st != VR_OK) return st;
  for (size_t j = 0; j < s->n; j++)
    if (!isfinite(r_out[j]))
      return vr_error_set(err, VR_E_NUMERIC, "vr_recover (%s): sample %zu came out non-finite",
                          vr_recover_method_name(method), j);
  vr_recover_finish_info(s, c, sigma, clipped, r_out, &info);
  if (method == VR_RECOVER_MATRIX_R && info.clipped) {
    /* Matrix R is linear and ignores the inequalities: say when it breaks one. */
    double tol = 1e-9;
    for (size_t i = 0; i < s->m; i++) tol = fmax(tol, 1e-9 * fabs(c[i]));
    if (info.clip_violation > tol) info.flags |= VR_RECOVER_FLAG_CLIP_VIOLATED;
  }
  if (sigma && info.used > 0 && info.chi2 > info.chi2_limit) info.flags |= VR_RECOVER_FLAG_MISFIT;
  if (info_out) *info_out = info;
  return VR_OK;
}

vr_status vr_recover(const vr_recovery_system *s, vr_recover_method method, const double *c,
                     const unsigned char *clipped, double *r_out, vr_recover_info *info_out,
                     vr_error *err) {
  return vr_recover_noisy(s, method, c, NULL, clipped, r_out, info_out, err);
}

double vr_recover_pixel_sigma(double sd, double step) {
  double q2 = step * step / 12.0, v = sd * sd + (sd < 0.5 * step ? q2 : 0.0);
  return fmax(sqrt(v), 1e-6);
}

double vr_recover_mean_sigma(double sd, long pixels, double step) {
  double n = pixels > 1 ? (double)pixels : 1.0, q2 = step * step / 12.0;
  double v = sd < 0.5 * step ? sd * sd / n + q2 : sd * sd / n;
  return fmax(sqrt(v), 1e-6);
}
