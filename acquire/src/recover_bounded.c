/* The bounded smooth method: the smoothest reflectance in [0, 1] with the
 * recorded responses,
 *
 *     minimise ||D2 r||^2  subject to  A r = c,  0 <= r <= 1,
 *
 * D2 the (N-2) x N second differences of the grid (rows (1, -2, 1) on a
 * uniform grid), whose null space is the straight lines: among all metamers
 * of the data that are physical reflectances, the one with the least
 * curvature.  Rows use exposure-normalised units (each light's block
 * divided by its exposure), which changes neither the constraint set nor
 * the minimiser.
 *
 * Clipped observations leave the equations and become inequalities,
 * A_i r >= c_i for a saturated channel (and <= for one cut at the bottom),
 * written as A_i r + sign s_i = c_i with a slack s_i >= 0, so that the
 * bound-constrained solver handles them as it handles 0 <= r <= 1.
 *
 * Two phases, both by the active-set solver of recover_qp.c:
 *   1. feasibility: minimise ||A r - c||^2 over the bounds from r = 1/2.  If
 *      the minimum exceeds feas_tol * max(1, ||c||), no reflectance in
 *      [0, 1] has these responses (c lies outside the object-colour solid of
 *      the lights, or noise pushed it there): flag VR_RECOVER_FLAG_OUT_OF_GAMUT
 *      and replace c by the closest reachable responses A r1 (unique: the
 *      reachable set is convex).
 *   2. smoothness: minimise ||D2 r||^2 with A r = c (or A r1) and the bounds,
 *      from the feasible point of phase 1.
 * The loop ends at a KKT point (every bound multiplier of the right sign);
 * the iteration cap (10 N + 50 by default) only guards against cycling on
 * degenerate vertices, and is flagged. */
#include "recover_system.h"
#include "recover_qp.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

vr_status vr_recover_bounded(const vr_recovery_system *s, const double *c,
                             const unsigned char *clipped, double *r, vr_recover_info *info,
                             vr_error *err) {
  size_t n = s->n, m = s->m, nc = info->clipped, nv = n + nc;
  double *e = calloc(m * nv, sizeof *e), *ev = malloc(m * sizeof *ev),
         *g2 = calloc((n - 2) * nv, sizeof *g2), *h2 = calloc(n - 2, sizeof *h2),
         *lo = malloc(nv * sizeof *lo), *hi = malloc(nv * sizeof *hi), *x = malloc(nv * sizeof *x),
         *x1 = malloc(nv * sizeof *x1);
  vr_status st = VR_OK;
  if (!e || !ev || !g2 || !h2 || !lo || !hi || !x || !x1) {
    st = vr_error_set(err, VR_E_NOMEM, "bounded recovery: out of memory");
    goto done;
  }
  for (size_t j = 0; j < n; j++) {
    lo[j] = 0.0;
    hi[j] = 1.0;
    x[j] = 0.5;
  }
  size_t slack = n;
  for (size_t i = 0; i < m; i++) {
    memcpy(e + i * nv, s->an + i * n, n * sizeof *e);
    ev[i] = c[i] / s->rowscale[i];
    unsigned char mark = clipped ? clipped[i] : VR_CLIP_NONE;
    if (mark == VR_CLIP_NONE) continue;
    double sign = vr_recover_slack_sign(mark), ar = 0.0;
    for (size_t j = 0; j < n; j++) ar += s->an[i * n + j] * x[j];
    e[i * nv + slack] = sign;
    lo[slack] = 0.0;
    hi[slack] = INFINITY;
    x[slack] = fmax(0.0, (ev[i] - ar) / sign);
    slack++;
  }
  if (info->used == 0) info->flags |= VR_RECOVER_FLAG_NO_DATA;

  /* Phase 1: the closest responses a reflectance in [0, 1] can give. */
  vr_rqp q1 = {.n = nv, .mg = m, .g = e, .h = ev, .me = 0, .lo = lo, .hi = hi,
               .rank_tol = s->opt.rank_tol, .e_ref = s->sv[0], .max_iter = s->opt.max_iter};
  int it1 = 0, it2 = 0;
  vr_rqp_result res = vr_recover_rqp(&q1, x, &it1);
  if (res < 0) {
    st = res == VR_RQP_NOMEM ? vr_error_set(err, VR_E_NOMEM, "bounded recovery: out of memory")
                             : vr_error_set(err, VR_E_NUMERIC,
                                            "bounded recovery: LAPACK failed in the feasibility phase");
    goto done;
  }
  if (res == VR_RQP_MAX_ITER) info->flags |= VR_RECOVER_FLAG_MAX_ITER;
  double resid = 0.0, cnorm = 0.0;
  for (size_t i = 0; i < m; i++) {
    double v = -ev[i];
    for (size_t j = 0; j < nv; j++) v += e[i * nv + j] * x[j];
    resid += v * v;
    cnorm += ev[i] * ev[i];
  }
  resid = sqrt(resid);
  cnorm = sqrt(cnorm);
  if (resid > s->opt.feas_tol * fmax(1.0, cnorm)) {
    info->flags |= VR_RECOVER_FLAG_OUT_OF_GAMUT;
    for (size_t i = 0; i < m; i++) {
      double v = 0.0;
      for (size_t j = 0; j < nv; j++) v += e[i * nv + j] * x[j];
      ev[i] = v;
    }
  }
  memcpy(x1, x, nv * sizeof *x);

  /* Phase 2: the smoothest of them.  Slacks carry no cost. */
  for (size_t i = 0; i + 2 < n; i++) memcpy(g2 + i * nv, s->d2 + i * n, n * sizeof *g2);
  vr_rqp q2 = {.n = nv, .mg = n - 2, .g = g2, .h = h2, .me = m, .e = e, .ev = ev, .lo = lo,
               .hi = hi, .rank_tol = s->opt.rank_tol,
               .e_ref = nc ? fmax(s->sv[0], 1.0) : s->sv[0], .max_iter = s->opt.max_iter};
  res = vr_recover_rqp(&q2, x, &it2);
  if (res < 0) {
    if (res == VR_RQP_NOMEM) {
      st = vr_error_set(err, VR_E_NOMEM, "bounded recovery: out of memory");
      goto done;
    }
    /* A failed smoothing pass still leaves phase 1's admissible answer. */
    memcpy(x, x1, nv * sizeof *x);
    info->flags |= VR_RECOVER_FLAG_MAX_ITER;
  } else if (res == VR_RQP_MAX_ITER) {
    info->flags |= VR_RECOVER_FLAG_MAX_ITER;
  }
  info->iterations = it1 + it2;
  info->bounds_active = 0;
  for (size_t j = 0; j < n; j++) {
    r[j] = x[j];
    if (x[j] <= 0.0 || x[j] >= 1.0) info->bounds_active++;
  }
  info->rank = s->rank;
done:
  free(e);
  free(ev);
  free(g2);
  free(h2);
  free(lo);
  free(hi);
  free(x);
  free(x1);
  return st;
}
