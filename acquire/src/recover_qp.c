/* A primal active-set solver for least squares with equalities and bounds
 * (see vr_rqp in recover_qp.h; Nocedal and Wright, "Numerical
 * Optimization", 2nd ed., algorithm 16.3, specialised to bound constraints
 * so that the working set is simply a set of fixed variables).
 *
 * Each iteration solves, on the free variables F with the others fixed,
 *
 *     minimise ||G_F p - (h - G x)||^2  subject to  E_F p = e - E x
 *
 * for the step p.  The equalities are first replaced by an equivalent set
 * with orthonormal rows: E_F = U S V^T, keep the k singular values above
 * rank_tol * e_ref, and write B = V_k^T, d = S_k^-1 U_k^T (e - E x).  The
 * reduced problem goes to LAPACKE_dgglse, whose preconditions (B of full
 * row rank k, [G_F; B] of full column rank, k <= |F| <= rows(G) + k) then
 * fail only when the objective is flat along a direction the constraints
 * leave free; in that case a ridge of 1e-8 * max|G_F| on the step picks
 * the smallest such step.  Without equalities the minimum-norm step comes
 * from LAPACKE_dgelsd.
 *
 * Degenerate vertices need two guards.  When the free variables are fully
 * determined by the equalities (k = |F|) and E_F has fewer independent rows
 * than E, the equality multipliers are not unique and the computed bound
 * multipliers are no certificate: releasing such a bound gives a step that
 * runs straight back into it.  A variable released since x last moved that
 * blocks a zero-length step is therefore marked stuck and not released
 * again until x moves; when only stuck variables have wrongly signed
 * multipliers, no feasible direction decreases the objective and the loop
 * stops.  While x stands still, each variable can be released at most once
 * (if it then blocks, it is stuck), so no stall outlasts a few n
 * iterations; the iteration cap remains as a backstop and is reported.
 * After any zero-length step the next release follows Bland's rule (lowest
 * index).
 *
 * At the minimum of a working set the gradient g = 2 G^T (G x - h) and the
 * equality multipliers mu = B g_F (B has orthonormal rows) give each fixed
 * variable's bound multiplier nu_j = g_j - (T E)_j^T mu, T = S_k^-1 U_k^T;
 * the KKT conditions need nu_j >= 0 at a lower bound and nu_j <= 0 at an
 * upper one.  A full step that meets no bound lands at the working set's
 * minimum by construction, so the multipliers are checked there without a
 * second solve (which, on an ill-conditioned E, could jitter above the step
 * tolerance forever). */
#include "recover_qp.h"
#include "recover_linalg.h"

#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { FREE = 0, AT_LO = 1, AT_HI = 2 };

typedef struct rqp_work {
  size_t n, mg, me;
  signed char *state;
  unsigned char *stuck;    /* released, then bounced back at once: not again until x moves */
  unsigned char *released; /* released since x last moved */
  size_t *free_idx;
  double *gf, *rg, *re, *p, *pf, *grad, *u, *s, *vt, *b, *d, *tmp, *big, *bigc;
  size_t k; /* kept equality directions in the last solve */
} rqp_work;

static void work_free(rqp_work *w) {
  free(w->state);
  free(w->stuck);
  free(w->released);
  free(w->free_idx);
  free(w->gf);
  free(w->rg);
  free(w->re);
  free(w->p);
  free(w->pf);
  free(w->grad);
  free(w->u);
  free(w->s);
  free(w->vt);
  free(w->b);
  free(w->d);
  free(w->tmp);
  free(w->big);
  free(w->bigc);
}

static int work_alloc(rqp_work *w, size_t n, size_t mg, size_t me) {
  memset(w, 0, sizeof *w);
  w->n = n;
  w->mg = mg;
  w->me = me;
  size_t q = me < n ? me : n, rows = mg + n, big_rows = rows > me ? rows : me;
  w->state = calloc(n, 1);
  w->stuck = calloc(n, 1);
  w->released = calloc(n, 1);
  w->free_idx = malloc(n * sizeof *w->free_idx);
  w->gf = malloc((mg > 0 ? mg : 1) * n * sizeof(double));
  w->rg = malloc((mg > 0 ? mg : 1) * sizeof(double));
  w->re = malloc((me > 0 ? me : 1) * sizeof(double));
  w->p = malloc(n * sizeof(double));
  w->pf = malloc(n * sizeof(double));
  w->grad = malloc(n * sizeof(double));
  w->u = malloc((me > 0 ? me : 1) * (q > 0 ? q : 1) * sizeof(double));
  w->s = malloc((q > 0 ? q : 1) * sizeof(double));
  w->vt = malloc((q > 0 ? q : 1) * n * sizeof(double));
  w->b = malloc((q > 0 ? q : 1) * n * sizeof(double));
  w->d = malloc((q > 0 ? q : 1) * sizeof(double));
  w->tmp = malloc((me > n ? me : n) * sizeof(double) + sizeof(double));
  w->big = malloc(big_rows * n * sizeof(double));
  w->bigc = malloc((rows > n ? rows : n) * sizeof(double));
  return w->state && w->stuck && w->released && w->free_idx && w->gf && w->rg && w->re && w->p && w->pf && w->grad && w->u &&
         w->s && w->vt && w->b && w->d && w->tmp && w->big && w->bigc;
}

/* Minimum-norm least squares min ||a x - rhs|| (a is rows x nf, destroyed;
 * rhs has room for max(rows, nf) values and returns x). */
static int lsq_min_norm(size_t rows, size_t nf, double *a, double *rhs, double rcond) {
  size_t q = rows < nf ? rows : nf;
  double *sv = malloc((q > 0 ? q : 1) * sizeof *sv);
  if (!sv) return -1000;
  lapack_int rank;
  int info = LAPACKE_dgelsd(LAPACK_ROW_MAJOR, (lapack_int)rows, (lapack_int)nf, 1, a,
                            (lapack_int)nf, rhs, 1, sv, rcond, &rank);
  free(sv);
  return info;
}

/* The step on the free variables for the current working set, into w->p. */
static int solve_step(const vr_rqp *q, rqp_work *w, const double *x, size_t nf) {
  size_t n = q->n, mg = q->mg, me = q->me;
  memset(w->p, 0, n * sizeof *w->p);
  w->k = 0;
  if (nf == 0) return 0;
  for (size_t i = 0; i < mg; i++) {
    double v = q->h[i];
    for (size_t j = 0; j < n; j++) v -= q->g[i * n + j] * x[j];
    w->rg[i] = v;
    for (size_t f = 0; f < nf; f++) w->gf[i * nf + f] = q->g[i * n + w->free_idx[f]];
  }
  size_t k = 0;
  if (me > 0) {
    size_t qd = me < nf ? me : nf;
    double *ef = w->big; /* me x nf, borrowed */
    for (size_t i = 0; i < me; i++) {
      double v = q->ev[i];
      for (size_t j = 0; j < n; j++) v -= q->e[i * n + j] * x[j];
      w->re[i] = v;
      for (size_t f = 0; f < nf; f++) ef[i * nf + f] = q->e[i * n + w->free_idx[f]];
    }
    int info = vr_recover_svd(me, nf, ef, w->u, w->s, w->vt);
    if (info != 0) return info;
    double cut = q->rank_tol * q->e_ref;
    while (k < qd && w->s[k] > cut) k++;
    for (size_t i = 0; i < k; i++) {
      double v = 0.0;
      for (size_t l = 0; l < me; l++) v += w->u[l * qd + i] * w->re[l];
      w->d[i] = v / w->s[i];
      memcpy(w->b + i * nf, w->vt + i * nf, nf * sizeof(double));
    }
  }
  w->k = k;
  double rcond = q->rank_tol;
  if (k == 0) {
    if (mg == 0) return 0;
    memcpy(w->big, w->gf, mg * nf * sizeof(double));
    memset(w->bigc, 0, (mg > nf ? mg : nf) * sizeof(double));
    memcpy(w->bigc, w->rg, mg * sizeof(double));
    int info = lsq_min_norm(mg, nf, w->big, w->bigc, rcond);
    if (info != 0) return info;
    memcpy(w->pf, w->bigc, nf * sizeof(double));
  } else if (k == nf) {
    /* The equalities alone fix the step: p = B^T d. */
    for (size_t f = 0; f < nf; f++) {
      double v = 0.0;
      for (size_t i = 0; i < k; i++) v += w->b[i * nf + f] * w->d[i];
      w->pf[f] = v;
    }
  } else {
    int info = 2;
    double dcopy[64], *dd = k <= 64 ? dcopy : malloc(k * sizeof *dd);
    double *bcopy = malloc(k * nf * sizeof *bcopy);
    if (!dd || !bcopy) {
      if (dd != dcopy) free(dd);
      free(bcopy);
      return -1000;
    }
    if (mg + k >= nf) {
      memcpy(w->big, w->gf, mg * nf * sizeof(double));
      memcpy(w->bigc, w->rg, mg * sizeof(double));
      memcpy(dd, w->d, k * sizeof *dd);
      memcpy(bcopy, w->b, k * nf * sizeof *bcopy);
      info = LAPACKE_dgglse(LAPACK_ROW_MAJOR, (lapack_int)mg, (lapack_int)nf, (lapack_int)k,
                            w->big, (lapack_int)nf, bcopy, (lapack_int)nf, w->bigc, dd, w->pf);
    }
    if (info > 0) {
      /* [G_F; B] is rank deficient: the objective is flat along a direction
       * the constraints leave free.  A small ridge on the step makes the
       * solve well posed and picks the shortest step along it. */
      double gmax = 0.0;
      for (size_t i = 0; i < mg * nf; i++) gmax = fmax(gmax, fabs(w->gf[i]));
      double eps = 1e-8 * (gmax > 0.0 ? gmax : 1.0);
      size_t rows = mg + nf;
      memcpy(w->big, w->gf, mg * nf * sizeof(double));
      memset(w->big + mg * nf, 0, nf * nf * sizeof(double));
      for (size_t f = 0; f < nf; f++) w->big[(mg + f) * nf + f] = eps;
      memcpy(w->bigc, w->rg, mg * sizeof(double));
      memset(w->bigc + mg, 0, nf * sizeof(double));
      memcpy(dd, w->d, k * sizeof *dd);
      memcpy(bcopy, w->b, k * nf * sizeof *bcopy);
      info = LAPACKE_dgglse(LAPACK_ROW_MAJOR, (lapack_int)rows, (lapack_int)nf, (lapack_int)k,
                            w->big, (lapack_int)nf, bcopy, (lapack_int)nf, w->bigc, dd, w->pf);
    }
    if (dd != dcopy) free(dd);
    free(bcopy);
    if (info != 0) return info;
  }
  for (size_t f = 0; f < nf; f++) w->p[w->free_idx[f]] = w->pf[f];
  return 0;
}

/* The fixed variable whose bound multiplier has the most wrong sign, or -1
 * when all are right (within a tolerance relative to the gradient).  After a
 * degenerate (zero-length) step, the lowest-index wrong one instead: Bland's
 * rule, which keeps the loop from cycling among working sets at a vertex
 * where more bounds are active than the constraints need. */
static long worst_multiplier(const vr_rqp *q, rqp_work *w, const double *x, size_t nf,
                             int bland) {
  size_t n = q->n, mg = q->mg, me = q->me, k = w->k;
  double *g = w->grad;
  memset(g, 0, n * sizeof *g);
  for (size_t i = 0; i < mg; i++) {
    double r = -q->h[i];
    for (size_t j = 0; j < n; j++) r += q->g[i * n + j] * x[j];
    for (size_t j = 0; j < n; j++) g[j] += 2.0 * q->g[i * n + j] * r;
  }
  double gmax = 0.0;
  for (size_t j = 0; j < n; j++) gmax = fmax(gmax, fabs(g[j]));
  /* wv = T^T mu = U_k S_k^-1 mu, mu = B g_F. */
  double *wv = w->tmp;
  memset(wv, 0, (me > 0 ? me : 1) * sizeof *wv);
  if (k > 0) {
    size_t qd = me < nf ? me : nf;
    for (size_t i = 0; i < k; i++) {
      double mu = 0.0;
      for (size_t f = 0; f < nf; f++) mu += w->b[i * nf + f] * g[w->free_idx[f]];
      mu /= w->s[i];
      for (size_t l = 0; l < me; l++) wv[l] += w->u[l * qd + i] * mu;
    }
  }
  double tol = 1e-9 * gmax, worst = tol;
  long at = -1;
  for (size_t j = 0; j < n; j++) {
    if (w->state[j] == FREE || w->stuck[j]) continue;
    double nu = g[j];
    if (k > 0)
      for (size_t l = 0; l < me; l++) nu -= wv[l] * q->e[l * n + j];
    double wrong = w->state[j] == AT_LO ? -nu : nu;
    if (wrong > worst) {
      worst = wrong;
      at = (long)j;
      if (bland) break;
    }
  }
  return at;
}

vr_rqp_result vr_recover_rqp(const vr_rqp *q, double *x, int *iterations) {
  size_t n = q->n;
  rqp_work w;
  if (!work_alloc(&w, n, q->mg, q->me)) {
    work_free(&w);
    return VR_RQP_NOMEM;
  }
  for (size_t j = 0; j < n; j++) {
    if (x[j] <= q->lo[j]) {
      x[j] = q->lo[j];
      w.state[j] = AT_LO;
    } else if (x[j] >= q->hi[j]) {
      x[j] = q->hi[j];
      w.state[j] = AT_HI;
    }
  }
  int max_iter = q->max_iter > 0 ? q->max_iter : (int)(10 * n + 50);
  vr_rqp_result result = VR_RQP_MAX_ITER;
  int it = 0, degenerate = 0;
  while (it < max_iter) {
    it++;
    size_t nf = 0;
    for (size_t j = 0; j < n; j++)
      if (w.state[j] == FREE) w.free_idx[nf++] = j;
    int info = solve_step(q, &w, x, nf);
    if (info != 0) {
      result = info == -1000 ? VR_RQP_NOMEM : VR_RQP_LAPACK;
      break;
    }
    double pmax = 0.0, xmax = 1.0;
    for (size_t j = 0; j < n; j++) {
      pmax = fmax(pmax, fabs(w.p[j]));
      if (isfinite(x[j])) xmax = fmax(xmax, fabs(x[j]));
    }
    if (pmax > 1e-13 * xmax) {
      double alpha = 1.0;
      long block = -1;
      for (size_t f = 0; f < nf; f++) {
        size_t j = w.free_idx[f];
        double pj = w.p[j], a;
        if (pj < 0.0 && isfinite(q->lo[j]))
          a = (q->lo[j] - x[j]) / pj;
        else if (pj > 0.0 && isfinite(q->hi[j]))
          a = (q->hi[j] - x[j]) / pj;
        else
          continue;
        if (a < 0.0) a = 0.0;
        if (a < alpha) {
          alpha = a;
          block = (long)j;
        }
      }
      for (size_t j = 0; j < n; j++) x[j] += alpha * w.p[j];
      for (size_t f = 0; f < nf; f++) { /* rounding must not leave the box */
        size_t j = w.free_idx[f];
        if (x[j] < q->lo[j]) x[j] = q->lo[j];
        if (x[j] > q->hi[j]) x[j] = q->hi[j];
      }
      degenerate = alpha == 0.0;
      /* x moved (beyond the rounding noise of an ill-conditioned solve,
       * ~1e-11 at condition numbers near 1e5): every bound may be tried
       * again. */
      if (alpha * pmax > 1e-9 * xmax) {
        memset(w.stuck, 0, n);
        memset(w.released, 0, n);
      } else if (block >= 0 && w.released[block]) {
        w.stuck[block] = 1;
      }
      if (block >= 0) {
        size_t j = (size_t)block;
        int lower = w.p[j] < 0.0;
        x[j] = lower ? q->lo[j] : q->hi[j];
        w.state[j] = lower ? AT_LO : AT_HI;
        continue;
      }
    }
    long j = worst_multiplier(q, &w, x, nf, degenerate);
    if (j < 0) {
      result = VR_RQP_OK;
      break;
    }
    w.state[j] = FREE;
    w.released[j] = 1;
  }
  if (iterations) *iterations = it;
  work_free(&w);
  return result;
}
