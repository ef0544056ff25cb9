/* Coherent thin-film stacks by Rouard's recursion.
 *
 * The effective reflection coefficient Gamma_j at the bottom face of layer j
 * (seen from inside j) obeys
 *     Gamma_j = (r_j + Gamma_{j+1} P_{j+1}^2) / (1 + r_j Gamma_{j+1} P_{j+1}^2),
 * with r_j the Fresnel coefficient of interface j|j+1 and P = exp(i k0 q d)
 * the one-way phase factor (|P| <= 1 because Im q >= 0).  The forward
 * amplitude entering layer j+1 is F_{j+1} = t_j B_j / (1 + r_j Gamma_{j+1}
 * P_{j+1}^2), where B_j is the forward amplitude at the bottom of layer j.
 * This is the characteristic-matrix solution rewritten with decaying
 * exponentials only, so a millimetre of absorbing glass or a metal with
 * k = 1e3 gives underflow to zero, never overflow.  Absorption per layer
 * comes from the Poynting flux at both faces of each layer (Byrnes,
 * arXiv:1603.02720, eq. 15-16), independently of R and T. */
#include "vr/optics.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define STACK_LAYERS 32

static double abs2(vr_complex z) { return creal(z) * creal(z) + cimag(z) * cimag(z); }

static vr_status validate(const vr_layer *L, size_t count, double theta0, double lambda,
                          vr_error *err) {
  if (count < 2)
    return vr_error_set(err, VR_E_ARG, "a stack needs an ambient and an exit medium (got %zu layers)",
                        count);
  if (!(lambda > 0.0) || !isfinite(lambda))
    return vr_error_set(err, VR_E_ARG, "wavelength must be positive and finite (got %g nm)", lambda);
  if (!(theta0 >= 0.0 && theta0 <= M_PI / 2 + 1e-15))
    return vr_error_set(err, VR_E_ARG, "angle of incidence must lie in [0, 90] degrees (got %g)",
                        theta0 * 180.0 / M_PI);
  for (size_t j = 0; j < count; j++) {
    if (!isfinite(creal(L[j].n)) || !isfinite(cimag(L[j].n)))
      return vr_error_set(err, VR_E_ARG, "layer %zu: refractive index is not finite", j);
    if (cimag(L[j].n) < 0.0)
      return vr_error_set(err, VR_E_ARG, "layer %zu: extinction coefficient k = %g is negative", j,
                          cimag(L[j].n));
    if (creal(L[j].n) == 0.0 && cimag(L[j].n) == 0.0)
      return vr_error_set(err, VR_E_ARG, "layer %zu: refractive index is zero", j);
    if (j > 0 && j + 1 < count && (!(L[j].thickness_nm >= 0.0) || !isfinite(L[j].thickness_nm)))
      return vr_error_set(err, VR_E_ARG, "layer %zu: thickness %g nm must be finite and >= 0", j,
                          L[j].thickness_nm);
  }
  return VR_OK;
}

/* Fresnel amplitude coefficients of interface a|b for the given q values. */
static int interface(vr_complex na, vr_complex nb, vr_complex qa, vr_complex qb, vr_pol pol,
                     vr_complex *r, vr_complex *t) {
  vr_complex num, den, tn;
  if (pol == VR_POL_S) {
    num = qa - qb;
    den = qa + qb;
    tn = 2.0 * qa;
  } else {
    num = nb * nb * qa - na * na * qb;
    den = nb * nb * qa + na * na * qb;
    tn = 2.0 * na * nb * qa;
  }
  if (den == 0.0) {
    if (na == nb) { /* identical media at exact grazing: no interface at all */
      *r = 0.0;
      *t = 1.0;
      return 0;
    }
    return -1;
  }
  *r = num / den;
  *t = tn / den;
  return 0;
}

/* Normalised z-component of the Poynting vector for amplitudes ef, eb. */
static double flux(vr_complex n, vr_complex q, vr_complex ef, vr_complex eb, vr_pol pol) {
  if (pol == VR_POL_S) return creal(q * conj(ef + eb) * (ef - eb));
  return creal(n * conj(q / n) * (ef + eb) * conj(ef - eb));
}

/* The solver proper, on the invariant beta; used by the incoherent code for
 * sub-stacks whose first medium is a thick layer. */
vr_status vr_tmm_coherent_beta(const vr_layer *L, size_t count, vr_complex beta, double lambda,
                               vr_pol pol, vr_tmm_result *res, double *absorbed, vr_error *err) {
  vr_complex stackbuf[5 * STACK_LAYERS];
  vr_complex *buf = stackbuf;
  if (count > STACK_LAYERS) {
    buf = malloc(5 * count * sizeof(vr_complex));
    if (!buf) return vr_error_set(err, VR_E_NOMEM, "out of memory for a %zu-layer stack", count);
  }
  vr_complex *q = buf, *P = buf + count, *r = buf + 2 * count, *t = buf + 3 * count,
             *G = buf + 4 * count;
  double k0 = 2.0 * M_PI / lambda;
  for (size_t j = 0; j < count; j++) {
    q[j] = vr_optics_q(L[j].n, beta);
    P[j] = (j > 0 && j + 1 < count) ? cexp(I * k0 * q[j] * L[j].thickness_nm) : 1.0;
  }
  vr_status st = VR_OK;
  for (size_t j = 0; j + 1 < count; j++)
    if (interface(L[j].n, L[j + 1].n, q[j], q[j + 1], pol, &r[j], &t[j])) {
      st = vr_error_set(err, VR_E_NUMERIC,
                        "interface %zu|%zu is singular (a lossless surface-plasmon pole)", j, j + 1);
      goto done;
    }
  G[count - 2] = r[count - 2];
  for (size_t j = count - 2; j-- > 0;) {
    vr_complex g = G[j + 1] * P[j + 1] * P[j + 1];
    G[j] = (r[j] + g) / (1.0 + r[j] * g);
  }
  /* Forward amplitudes; stored over r[] once each interface is used. */
  vr_complex F = 1.0;          /* forward amplitude at the top of layer j */
  vr_complex *Fj = r;          /* reuse: Fj[j] = forward amplitude at top of layer j */
  vr_complex r0 = G[0];
  for (size_t j = 0; j + 1 < count; j++) {
    vr_complex B = j == 0 ? 1.0 : F * P[j];
    vr_complex g = (j + 2 < count) ? G[j + 1] * P[j + 1] * P[j + 1] : 0.0;
    vr_complex next = t[j] * B / (1.0 + r[j] * g);
    Fj[j] = F;
    F = next;
  }
  Fj[count - 1] = F;
  res->r = r0;
  res->t = F;
  res->R = abs2(r0);
  double in = flux(L[0].n, q[0], 1.0, 0.0, pol);
  if (!(in > 0.0)) { /* exactly grazing */
    res->R = 1.0;
    res->T = res->A = 0.0;
    if (absorbed) memset(absorbed, 0, count * sizeof(double));
    goto done;
  }
  res->T = flux(L[count - 1].n, q[count - 1], F, 0.0, pol) / in;
  double A = 0.0;
  if (absorbed) absorbed[0] = 0.0;
  for (size_t j = 1; j + 1 < count; j++) {
    vr_complex f = Fj[j], gp = G[j] * P[j];
    double top = flux(L[j].n, q[j], f, f * gp * P[j], pol);
    double bottom = flux(L[j].n, q[j], f * P[j], f * gp, pol);
    double a = (top - bottom) / in;
    if (absorbed) absorbed[j] = a;
    A += a;
  }
  if (absorbed) absorbed[count - 1] = res->T;
  res->A = A;
  /* A transparent stack over an evanescent exit reflects everything; say so
   * exactly rather than to the last rounding error. */
  if (creal(q[count - 1]) == 0.0) {
    int lossless = 1;
    for (size_t j = 1; j + 1 < count; j++) lossless &= cimag(L[j].n) == 0.0;
    if (lossless && cimag(L[count - 1].n) == 0.0) {
      res->R = 1.0;
      res->T = res->A = 0.0;
    }
  }
done:
  if (buf != stackbuf) free(buf);
  return st;
}

vr_status vr_tmm_coherent(const vr_layer *L, size_t count, double theta0, double lambda,
                          vr_pol pol, vr_tmm_result *res, double *absorbed, vr_error *err) {
  vr_status st = validate(L, count, theta0, lambda, err);
  if (st) return st;
  if (theta0 > M_PI / 2) theta0 = M_PI / 2;
  return vr_tmm_coherent_beta(L, count, L[0].n * sin(theta0), lambda, pol, res, absorbed, err);
}

/* Reflection coefficients of both polarisations in one pass: the q values
 * and phase factors are shared, and only Rouard's Gamma recursion is needed
 * (no transmitted amplitude, no absorption), which makes the ellipsometric
 * forward model about twice as cheap as two full solves. */
static vr_status reflect_both(const vr_layer *L, size_t count, vr_complex beta, double lambda,
                              vr_complex *rs, vr_complex *rp, vr_error *err) {
  vr_complex qbuf[STACK_LAYERS], *q = qbuf;
  if (count > STACK_LAYERS && !(q = malloc(count * sizeof *q)))
    return vr_error_set(err, VR_E_NOMEM, "out of memory for a %zu-layer stack", count);
  double k0 = 2.0 * M_PI / lambda;
  for (size_t j = 0; j < count; j++) q[j] = vr_optics_q(L[j].n, beta);
  vr_complex gs = 0.0, gp = 0.0; /* Gamma below the current interface, times P^2 */
  vr_status st = VR_OK;
  for (size_t j = count - 1; j-- > 0;) {
    vr_complex ts, tp, r_s, r_p;
    if (interface(L[j].n, L[j + 1].n, q[j], q[j + 1], VR_POL_S, &r_s, &ts) ||
        interface(L[j].n, L[j + 1].n, q[j], q[j + 1], VR_POL_P, &r_p, &tp)) {
      st = vr_error_set(err, VR_E_NUMERIC, "interface %zu|%zu is singular", j, j + 1);
      break;
    }
    vr_complex Gs = (r_s + gs) / (1.0 + r_s * gs), Gp = (r_p + gp) / (1.0 + r_p * gp);
    if (j == 0) {
      *rs = Gs;
      *rp = Gp;
      break;
    }
    vr_complex P = cexp(I * k0 * q[j] * L[j].thickness_nm);
    gs = Gs * P * P;
    gp = Gp * P * P;
  }
  if (q != qbuf) free(q);
  return st;
}

vr_status vr_tmm_ellipsometry(const vr_layer *L, size_t count, double theta0, double lambda,
                              double *psi_deg, double *delta_deg, vr_complex *rho_out,
                              vr_error *err) {
  vr_status st = validate(L, count, theta0, lambda, err);
  if (st) return st;
  if (theta0 > M_PI / 2) theta0 = M_PI / 2;
  vr_complex rs, rp;
  if ((st = reflect_both(L, count, L[0].n * sin(theta0), lambda, &rs, &rp, err))) return st;
  if (rs == 0.0)
    return vr_error_set(err, VR_E_NUMERIC, "r_s = 0: the stack reflects no s light, rho is undefined");
  /* The amplitudes use exp(-i w t) with N = n + i k; ellipsometers report
   * rho in the exp(+i w t) phase convention (Nebraska convention, as in
   * Woollam's software), which is the complex conjugate. */
  vr_complex rho = conj(rp / rs);
  if (rho_out) *rho_out = rho;
  if (psi_deg) *psi_deg = atan(cabs(rho)) * 180.0 / M_PI;
  if (delta_deg) {
    double d = carg(rho) * 180.0 / M_PI;
    if (d < 0.0) d += 360.0;
    if (d >= 360.0) d -= 360.0;
    *delta_deg = d;
  }
  return VR_OK;
}
