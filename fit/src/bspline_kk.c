/* Numerical Kramers-Kronig transform, and the B-spline dispersion model
 * that depends on it.
 *
 * ε1(E) = ε∞ + (2/π) P∫_0^∞ E' ε2(E') / (E'² - E²) dE'
 * (e.g. Fujiwara, Spectroscopic Ellipsometry, Wiley 2007, eq. 5.73).
 *
 * The principal value is taken by singularity subtraction: with
 * g(x) = x ε2(x) / (x + E) the integrand is g(x) / (x - E), and
 *   P∫_a^b g/(x-E) dx = ∫_a^b (g(x) - g(E)) / (x - E) dx + g(E) ln((b-E)/(E-a)),
 * whose remaining integrand is bounded, so an ordinary adaptive
 * Gauss-Kronrod rule with E as a panel end converges fast.  An algebraic tail
 * above a cut-off Ec is mapped by u = 1/E' onto (0, 1/Ec], where the integrand
 * ε2(1/u) / (u (1 - E²u²)) is smooth and finite, so the tail is exact too.
 *
 * The adaptive driver below uses GSL's 21-point Gauss-Kronrod rule
 * (gsl_integration_qk21) on a panel list of its own, instead of
 * gsl_integration_qawc: GSL's adaptive routines report failure through the
 * process-wide error handler, which aborts unless a global switch is flipped,
 * and a library must neither abort nor touch global state (DESIGN.md §7).
 * Everything here is reentrant. */
#include "dispersion_internal.h"

#include <gsl/gsl_integration.h>
#include <math.h>
#include <stdlib.h>

/* ---- adaptive Gauss-Kronrod on a list of panels ------------------------- */

#define KK_MAX_SPLITS 400
#define KK_EPSREL 1e-10

typedef struct panel {
  double a, b, result, error, resabs;
} panel;

static void apply_rule(const gsl_function *f, panel *p) {
  double resasc;
  gsl_integration_qk21(f, p->a, p->b, &p->result, &p->error, &p->resabs, &resasc);
}

/* ∫ f over [pts[0], pts[n-1]], the points being panel ends; the panel with
 * the largest error estimate is halved until the total error is within
 * tolerance (QUADPACK's QAG strategy).  Returns 0 on success, -1 when the
 * tolerance is not met (the best estimate is still stored), -2 when out of
 * memory. */
static int adaptive(const gsl_function *f, const double *pts, size_t npts, double *out) {
  size_t cap = npts + KK_MAX_SPLITS, n = 0;
  panel *pan = malloc(cap * sizeof *pan);
  if (!pan) return -2;
  for (size_t i = 0; i + 1 < npts; i++) {
    if (!(pts[i + 1] > pts[i])) continue;
    pan[n].a = pts[i];
    pan[n].b = pts[i + 1];
    apply_rule(f, &pan[n]);
    n++;
  }
  int status;
  for (;;) {
    double total = 0, err = 0, rabs = 0;
    size_t worst = 0;
    for (size_t i = 0; i < n; i++) {
      total += pan[i].result;
      err += pan[i].error;
      rabs += pan[i].resabs;
      if (pan[i].error > pan[worst].error) worst = i;
    }
    *out = total;
    if (!isfinite(total)) {
      status = -1;
      break;
    }
    /* The absolute floor keeps an integral that is nearly zero by
     * cancellation from demanding digits it cannot have. */
    if (err <= fmax(KK_EPSREL * fabs(total), 1e-13 * rabs)) {
      status = 0;
      break;
    }
    panel *w = &pan[worst];
    double mid = 0.5 * (w->a + w->b);
    if (n == cap || !(mid > w->a && mid < w->b)) {
      status = err <= 1e-7 * (fabs(total) + rabs) ? 0 : -1;
      break;
    }
    pan[n].a = mid;
    pan[n].b = w->b;
    w->b = mid;
    apply_rule(f, w);
    apply_rule(f, &pan[n]);
    n++;
  }
  free(pan);
  return status;
}

/* ---- the Kramers-Kronig integrands --------------------------------------- */

typedef struct kk_ctx {
  const vr_kk_spec *spec;
  double E;   /* the energy at which ε1 is wanted */
  double gE;  /* g(E), subtracted in the panels around E */
} kk_ctx;

/* (g(x) - g(E)) / (x - E) with g(x) = x ε2(x) / (x + E); with gE = 0 this is
 * the plain integrand x ε2(x) / (x² - E²). */
static double kk_sub(double x, void *vctx) {
  const kk_ctx *c = vctx;
  double g = x * c->spec->eps2(x, c->spec->ctx) / (x + c->E);
  return (g - c->gE) / (x - c->E);
}

/* The tail above the cut-off in u = 1/E'. */
static double kk_tail(double u, void *vctx) {
  const kk_ctx *c = vctx;
  double eu = c->E * u;
  return c->spec->eps2(1.0 / u, c->spec->ctx) / (u * (1.0 - eu) * (1.0 + eu));
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

vr_status vr_kk_transform(const vr_kk_spec *spec, double E, double *eps1, vr_error *err) {
  if (!(E > 0) || !isfinite(E))
    return vr_error_set(err, VR_E_ARG, "Kramers-Kronig: photon energy %g eV must be > 0", E);
  double lo = spec->lo > 0 ? spec->lo : 0;
  double hi = spec->hi;
  int has_tail = !isfinite(hi);
  if (!(hi > lo)) {
    *eps1 = 0;
    return VR_OK;
  }
  /* The cut-off sits well above every feature (so the mapped tail is smooth)
   * and above E (so the tail integrand has no pole). */
  double cut = hi;
  if (has_tail) {
    double top = lo;
    for (size_t i = 0; i < spec->nbreaks; i++)
      if (isfinite(spec->breaks[i]) && spec->breaks[i] > top) top = spec->breaks[i];
    cut = fmax(fmax(4 * top, 2 * E), 1.0);
  }

  double *pts = malloc((spec->nbreaks + 3) * sizeof *pts);
  if (!pts) return vr_error_set(err, VR_E_NOMEM, "Kramers-Kronig: out of memory");
  size_t n = 0;
  pts[n++] = lo;
  pts[n++] = cut;
  for (size_t i = 0; i < spec->nbreaks; i++)
    if (spec->breaks[i] > lo && spec->breaks[i] < cut) pts[n++] = spec->breaks[i];
  if (E > lo && E < cut) pts[n++] = E;
  qsort(pts, n, sizeof *pts, cmp_double);

  kk_ctx ctx = {spec, E, 0};
  double log_term = 0;
  if (E > lo && E < cut) {
    ctx.gE = E * spec->eps2(E, spec->ctx) / (2 * E);
    log_term = ctx.gE * log((cut - E) / (E - lo));
  } else if (E == lo || E == cut) {
    /* A step of ε2 at E gives a logarithmically infinite ε1. */
    double e2 = spec->eps2(E, spec->ctx);
    if (e2 != 0) {
      free(pts);
      return vr_error_set(err, VR_E_NUMERIC,
                          "Kramers-Kronig: eps1 diverges at %g eV, where eps2 steps from 0 "
                          "to %g (the edge of its support)",
                          E, e2);
    }
  }
  gsl_function f = {kk_sub, &ctx};
  double finite = 0;
  int bad = adaptive(&f, pts, n, &finite);
  free(pts);

  double tail = 0;
  if (has_tail && !bad) {
    double upts[2] = {0, 1.0 / cut};
    gsl_function t = {kk_tail, &ctx};
    bad = adaptive(&t, upts, 2, &tail);
  }
  if (bad == -2) return vr_error_set(err, VR_E_NOMEM, "Kramers-Kronig: out of memory");
  if (bad)
    return vr_error_set(err, VR_E_NUMERIC,
                        "Kramers-Kronig: the integral did not converge at %g eV", E);
  *eps1 = (2 / M_PI) * (finite + log_term + tail);
  return VR_OK;
}

/* ---- B-spline ε2 ------------------------------------------------------------
 *
 * ε2 between the knots is the cubic spline through the knot values with
 * not-a-knot ends (de Boor, A Practical Guide to Splines, ch. IV; the slope
 * equations as in SciPy's CubicSpline), which is a cubic B-spline on those
 * knots; its error for smooth data is O(h⁴).  Outside [first, last knot] ε2
 * is 0, so unless the end values are 0 there is a step, and ε1 has a
 * logarithmic singularity at that knot: keep the end knots beyond the data,
 * or fix their values to 0. */

/* Slopes s[] of the not-a-knot cubic spline through (x[i], y[i]), n >= 4:
 * a tridiagonal system solved by elimination without pivoting, which is safe
 * here because every pivot stays positive (the first is x2 - x1, the next
 * x2 - x0, then the interior rows dominate).  work holds 3n doubles. */
static void spline_slopes(size_t n, const double *x, const double *y, double *s,
                          double *work) {
  double *lower = work, *diag = work + n, *upper = work + 2 * n, *rhs = s;
#define DX(i) (x[(i) + 1] - x[(i)])
#define SLOPE(i) ((y[(i) + 1] - y[(i)]) / DX(i))
  double d = x[2] - x[0];
  lower[0] = 0;
  diag[0] = DX(1);
  upper[0] = d;
  rhs[0] = ((DX(0) + 2 * d) * DX(1) * SLOPE(0) + DX(0) * DX(0) * SLOPE(1)) / d;
  for (size_t i = 1; i + 1 < n; i++) {
    lower[i] = DX(i);
    diag[i] = 2 * (DX(i - 1) + DX(i));
    upper[i] = DX(i - 1);
    rhs[i] = 3 * (DX(i) * SLOPE(i - 1) + DX(i - 1) * SLOPE(i));
  }
  d = x[n - 1] - x[n - 3];
  lower[n - 1] = d;
  diag[n - 1] = DX(n - 3);
  upper[n - 1] = 0;
  rhs[n - 1] =
      (DX(n - 2) * DX(n - 2) * SLOPE(n - 3) + (2 * d + DX(n - 2)) * DX(n - 3) * SLOPE(n - 2)) / d;
#undef DX
#undef SLOPE
  for (size_t i = 1; i < n; i++) {
    double m = lower[i] / diag[i - 1];
    diag[i] -= m * upper[i - 1];
    rhs[i] -= m * rhs[i - 1];
  }
  s[n - 1] = rhs[n - 1] / diag[n - 1];
  for (size_t i = n - 1; i-- > 0;) s[i] = (rhs[i] - upper[i] * s[i + 1]) / diag[i];
}

typedef struct spline {
  size_t n;
  const double *x, *y, *s;
} spline;

/* The cubic Hermite form of the spline on the knot interval holding E;
 * 0 outside the knots. */
static double spline_eval(double E, const void *vsp) {
  const spline *sp = vsp;
  size_t n = sp->n;
  if (!(E >= sp->x[0] && E <= sp->x[n - 1])) return 0;
  size_t lo = 0, hi = n - 1;
  while (hi - lo > 1) {
    size_t mid = lo + (hi - lo) / 2;
    if (sp->x[mid] <= E) lo = mid; else hi = mid;
  }
  double h = sp->x[lo + 1] - sp->x[lo], t = (E - sp->x[lo]) / h;
  double t2 = t * t, t3 = t2 * t;
  return (2 * t3 - 3 * t2 + 1) * sp->y[lo] + (t3 - 2 * t2 + t) * h * sp->s[lo] +
         (3 * t2 - 2 * t3) * sp->y[lo + 1] + (t3 - t2) * h * sp->s[lo + 1];
}

vr_status vr_bspline_eps(const vr_dispersion *d, double E, vr_complex *eps, vr_error *err) {
  size_t n = d->nknots;
  if (n < 4)
    return vr_error_set(err, VR_E_ARG, "bspline: knots not set (vr_dispersion_set_knots)");
  double *mem = malloc(4 * n * sizeof *mem);
  if (!mem) return vr_error_set(err, VR_E_NOMEM, "bspline: out of memory");
  spline sp = {n, d->knots, d->p + 1, mem};
  spline_slopes(n, d->knots, d->p + 1, mem, mem + n);
  vr_kk_spec spec = {spline_eval, &sp, d->knots[0], d->knots[n - 1], d->knots, n};
  double e1 = 0;
  vr_status st = vr_kk_transform(&spec, E, &e1, err);
  double e2 = spline_eval(E, &sp);
  free(mem);
  if (st != VR_OK) {
    vr_error_prefix(err, "bspline at %g nm: ", VR_HC_EV_NM / E);
    return st;
  }
  *eps = CMPLX(d->p[0] + e1, e2);
  return VR_OK;
}
