/* What an ellipsometer reports for a sample model: Ψ, Δ, N, C, S and
 * depolarisation, through the core thin-film solver, with an incoherent
 * substrate whose back face reflects, a thickness non-uniformity over the
 * light spot and the instrument's spectral bandwidth.
 *
 * Every effect is an incoherent sum of detected intensities.  For one
 * coherent beam the detector sees I_pp = |r_p|², I_ss = |r_s|² and the
 * cross term X = r_p r_s*; partially coherent light adds these over the
 * beams, the thicknesses or the wavelengths it contains.  Then
 *   tan Ψ = sqrt(I_pp / I_ss),  Δ = -arg X (Woollam's sign),
 *   N = (I_ss - I_pp) / (I_ss + I_pp), C = 2 Re X / (I_ss + I_pp),
 *   S = -2 Im X / (I_ss + I_pp), depolarisation = 1 - sqrt(N² + C² + S²).
 *
 * Back side: with film-stack amplitudes r0 (from the ambient), t_down (into
 * the substrate), r_up and t_up (from inside the substrate back out), the
 * back-face coefficient r_b and the single-pass intensity attenuation a,
 * the j-th beam that comes out after j round trips has amplitude
 *   A_j = t_down r_b (r_up r_b)^(j-1) t_up  (times a phase common to s and p).
 * Thick substrates decorrelate the beams, so the intensities and the cross
 * term add over j as geometric series:
 *   I_pp = |r0p|^2 + |g_p|^2 a^2 / (1 - |h_p|^2 a^2),
 *   X    = r0p r0s* + g_p g_s* a^2 / (1 - h_p h_s* a^2),
 * with g = t_down r_b t_up and h = r_up r_b.
 *
 * Non-uniformity: all layer thicknesses scale by 1 + u, u uniform over
 * [-w/2, w/2].  Bandwidth: the wavelength is λ + b v with v in [-1, 1]
 * weighted 1 - |v| (a triangular slit of FWHM b).  Both averages are
 * composite Gauss-Legendre sums (the triangle split at its apex, where its
 * weight has a kink) whose panels span at most π/2 of the interference
 * phase 4π Σ n_i d_i / λ, 8 nodes each (256 nodes at most per
 * dimension; beyond 128 quarter-waves the average is resolved coarser). */
#include "model_internal.h"
#include "vr/ellipso_data.h"
#include "vr/optics.h"

#include <math.h>
#include <string.h>

#define MAX_STACK 64
#define MAX_NODES 256

typedef struct intensity {
  double pp, ss;
  vr_complex x;
} intensity;

static double abs2(vr_complex z) { return creal(z) * creal(z) + cimag(z) * cimag(z); }

/* The stack at a wavelength, thicknesses scaled by scale. */
static vr_status stack(const vr_sample_model *m, double nm, double scale, vr_layer *L, size_t *count,
                       vr_error *err) {
  size_t c = m->nlayers + 2;
  if (c > MAX_STACK) return vr_error_set(err, VR_E_ARG, "more than %d layers", MAX_STACK - 2);
  vr_status st = vr_model_layer_index_coupled(m, VR_OWNER_AMBIENT, nm, &L[0].n, err);
  for (size_t i = 0; !st && i < m->nlayers; i++) {
    st = vr_model_layer_index_coupled(m, (long)i, nm, &L[i + 1].n, err);
    L[i + 1].thickness_nm = m->layers[i].thickness_nm * scale;
    L[i + 1].incoherent = 0;
  }
  if (!st) st = vr_model_layer_index_coupled(m, VR_OWNER_SUBSTRATE, nm, &L[c - 1].n, err);
  if (st) return st;
  L[0].thickness_nm = L[c - 1].thickness_nm = 0;
  L[0].incoherent = L[c - 1].incoherent = 0;
  *count = c;
  return VR_OK;
}

/* Detected intensities of one monochromatic beam on one thickness. */
static vr_status intensities(const vr_sample_model *m, double nm, double theta, double scale, intensity *out,
                             vr_error *err) {
  vr_layer L[MAX_STACK];
  size_t count;
  vr_status st = stack(m, nm, scale, L, &count, err);
  if (st) return st;
  vr_complex beta = L[0].n * sin(theta);
  vr_tmm_result down[2];
  for (int p = 0; p < 2; p++)
    if ((st = vr_tmm_coherent_beta(L, count, beta, nm, (vr_pol)p, &down[p], NULL, err))) return st;
  out->pp = abs2(down[1].r);
  out->ss = abs2(down[0].r);
  out->x = down[1].r * conj(down[0].r);
  if (!m->backside || !(m->substrate_thickness_nm > 0)) return VR_OK;
  /* The film stack from inside the substrate, then the back face. */
  vr_tmm_result up[2], back[2];
  vr_layer rev[MAX_STACK], bf[2] = {{L[count - 1].n, 0, 0}, {L[0].n, 0, 0}};
  for (size_t i = 0; i < count; i++) rev[i] = L[count - 1 - i];
  for (int p = 0; p < 2; p++)
    if ((st = vr_tmm_coherent_beta(rev, count, beta, nm, (vr_pol)p, &up[p], NULL, err)) ||
        (st = vr_tmm_coherent_beta(bf, 2, beta, nm, (vr_pol)p, &back[p], NULL, err)))
      return st;
  double im_q = cimag(vr_optics_q(L[count - 1].n, beta));
  double a = exp(-4.0 * M_PI * im_q * m->substrate_thickness_nm / nm); /* single pass */
  vr_complex g[2], h[2];
  for (int p = 0; p < 2; p++) {
    g[p] = down[p].t * back[p].r * up[p].t;
    h[p] = up[p].r * back[p].r;
  }
  double a2 = a * a;
  out->pp += abs2(g[1]) * a2 / (1.0 - abs2(h[1]) * a2);
  out->ss += abs2(g[0]) * a2 / (1.0 - abs2(h[0]) * a2);
  out->x += g[1] * conj(g[0]) * a2 / (1.0 - h[1] * conj(h[0]) * a2);
  return VR_OK;
}

/* Gauss-Legendre nodes and weights on [-1, 1] for 4 and 8 nodes
 * (Abramowitz & Stegun, Table 25.4), the positive half; the rule is
 * symmetric. */
static const double GL4_X[2] = {0.3399810435848563, 0.8611363115940526};
static const double GL4_W[2] = {0.6521451548625461, 0.3478548451374538};
static const double GL8_X[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267, 0.9602898564975363};
static const double GL8_W[4] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763};

/* A composite Gauss-Legendre rule on [a, b] for a phase that moves by
 * span radians over it: panels of at most π/2 of phase, 8 nodes each (4
 * when the whole span is under π/4).  Writes at most MAX_NODES nodes x and
 * weights w (summing to b - a); returns their number. */
static int rule(double span, double a, double b, double *x, double *w) {
  int panels = span > M_PI / 2 ? (int)ceil(span / (M_PI / 2)) : 1;
  int per = span < M_PI / 4 ? 4 : 8;
  if (panels * per > MAX_NODES) panels = MAX_NODES / per;
  const double *hx = per == 4 ? GL4_X : GL8_X, *hw = per == 4 ? GL4_W : GL8_W;
  double gx[8], gw[8];
  for (int i = 0; i < per / 2; i++) {
    gx[per / 2 - 1 - i] = -hx[i], gw[per / 2 - 1 - i] = hw[i];
    gx[per / 2 + i] = hx[i], gw[per / 2 + i] = hw[i];
  }
  int n = 0;
  for (int p = 0; p < panels; p++) {
    double lo = a + (b - a) * p / panels, hi = a + (b - a) * (p + 1) / panels;
    for (int i = 0; i < per; i++, n++) {
      x[n] = (lo + hi) / 2 + (hi - lo) / 2 * gx[i];
      w[n] = (hi - lo) / 2 * gw[i];
    }
  }
  return n;
}

/* Σ Re(n_i) d_i of the films (nm) at a wavelength. */
static vr_status optical_thickness(const vr_sample_model *m, double nm, double *ot, vr_error *err) {
  *ot = 0;
  for (size_t i = 0; i < m->nlayers; i++) {
    vr_complex N;
    vr_status st = vr_model_layer_index_coupled(m, (long)i, nm, &N, err);
    if (st) return st;
    *ot += fabs(creal(N)) * m->layers[i].thickness_nm;
  }
  return VR_OK;
}

static void finish(const intensity *in, vr_model_response *r) {
  double tot = in->pp + in->ss;
  r->psi = atan(sqrt(in->pp / in->ss)) * 180.0 / M_PI;
  double d = -carg(in->x) * 180.0 / M_PI;
  r->delta = d < 0 ? d + 360.0 : d;
  r->N = (in->ss - in->pp) / tot;
  r->C = 2.0 * creal(in->x) / tot;
  r->S = -2.0 * cimag(in->x) / tot;
  r->depolarisation = fmax(0.0, 1.0 - sqrt(r->N * r->N + r->C * r->C + r->S * r->S));
}

/* The averaged intensities over non-uniformity w (fraction) and bandwidth
 * b (nm) at angle theta. */
static vr_status averaged(const vr_sample_model *m, double nm, double theta, double w, double b,
                          intensity *sum, vr_error *err) {
  double ot;
  vr_status st = optical_thickness(m, nm, &ot, err);
  if (st) return st;
  /* u over [-w/2, w/2] with weights of its mean; v over [-1, 0] then
   * [0, 1] with weights of the triangle 1 - |v| (area 1). */
  double xt[MAX_NODES], wt[MAX_NODES], xv[2 * MAX_NODES], wv[2 * MAX_NODES];
  int nt = 1, nv = 1;
  xt[0] = 0, wt[0] = 1, xv[0] = 0, wv[0] = 1;
  if (w > 0) {
    nt = rule(4 * M_PI * ot * w / nm, -w / 2, w / 2, xt, wt);
    for (int i = 0; i < nt; i++) wt[i] /= w;
  }
  if (b > 0) {
    int h = rule(4 * M_PI * ot * (1 + w / 2) * b / (nm * (nm - b)), -1, 0, xv, wv);
    for (int i = 0; i < h; i++) {
      xv[h + i] = -xv[i];
      wv[h + i] = wv[i];
    }
    nv = 2 * h;
    for (int i = 0; i < nv; i++) wv[i] *= 1 - fabs(xv[i]);
  }
  memset(sum, 0, sizeof *sum);
  for (int j = 0; j < nv; j++) {
    double lam = nm + b * xv[j], weight = wv[j];
    if (!(lam > 0)) return vr_error_set(err, VR_E_RANGE, "at %g nm: bandwidth %g nm reaches 0 nm", nm, b);
    for (int i = 0; i < nt; i++) {
      intensity one;
      if ((st = intensities(m, lam, theta, 1 + xt[i], &one, err))) {
        if (lam != nm && !m->bandwidth_set)
          vr_error_prefix(err, "within the data's bandwidth (%g nm; 'param sample.bandwidth = 0' ignores it): ", b);
        return st;
      }
      sum->pp += weight * wt[i] * one.pp;
      sum->ss += weight * wt[i] * one.ss;
      sum->x += weight * wt[i] * one.x;
    }
  }
  return VR_OK;
}

vr_status vr_model_measure(const vr_sample_model *m, double nm, double aoi_deg, double bandwidth_nm,
                           vr_model_response *r, vr_error *err) {
  vr_status st = vr_model_apply_couplings((vr_sample_model *)m, err);
  if (st) return st;
  double a = aoi_deg + m->aoi_offset_deg;
  if (!(a > 0 && a < 90))
    return vr_error_set(err, VR_E_RANGE, "at %g nm: angle %g deg + offset %g deg is outside (0, 90)", nm,
                        aoi_deg, m->aoi_offset_deg);
  double theta = a * M_PI / 180.0;
  double b = m->bandwidth_set ? m->bandwidth_nm : (isfinite(bandwidth_nm) && bandwidth_nm > 0 ? bandwidth_nm : 0);
  double w = m->nonuniformity_pct / 100.0;
  if (!(w >= 0 && w <= 1 && b >= 0 && b < nm))
    return vr_error_set(err, VR_E_RANGE, "at %g nm: non-uniformity %g %% or bandwidth %g nm out of range", nm,
                        m->nonuniformity_pct, b);
  if (w == 0 && b == 0 && !m->backside) {
    /* One coherent beam: the solver's own Ψ, Δ. */
    vr_layer L[MAX_STACK];
    size_t count;
    vr_complex rho;
    if (!(st = stack(m, nm, 1.0, L, &count, err)))
      st = vr_tmm_ellipsometry(L, count, theta, nm, &r->psi, &r->delta, &rho, err);
    if (st) {
      vr_error_prefix(err, "at %g nm, %g deg: ", nm, a);
      return st;
    }
    /* rho = tan Ψ e^{iΔ}: N = (1 - |rho|²)/(1 + |rho|²), C + iS = 2 rho/(1 + |rho|²). */
    double q = 1.0 + creal(rho) * creal(rho) + cimag(rho) * cimag(rho);
    r->N = (2.0 - q) / q;
    r->C = 2.0 * creal(rho) / q;
    r->S = 2.0 * cimag(rho) / q;
    r->depolarisation = 0;
  } else {
    intensity tot;
    if ((st = w == 0 && b == 0 ? intensities(m, nm, theta, 1.0, &tot, err) : averaged(m, nm, theta, w, b, &tot, err))) {
      vr_error_prefix(err, "at %g nm, %g deg: ", nm, a);
      return st;
    }
    if (!(tot.ss > 0)) return vr_error_set(err, VR_E_NUMERIC, "at %g nm: no s-polarised reflection", nm);
    finish(&tot, r);
  }
  if (m->delta_offset_deg != 0) {
    /* The offset turns the measured cross term: C, S rotate with Δ. */
    r->delta = vr_delta_normalise(r->delta + m->delta_offset_deg);
    double c = r->C, s = r->S, o = m->delta_offset_deg * M_PI / 180.0;
    r->C = c * cos(o) - s * sin(o);
    r->S = c * sin(o) + s * cos(o);
  }
  return VR_OK;
}

vr_status vr_model_psi_delta(const vr_sample_model *m, double nm, double aoi_deg, double *psi,
                             double *delta, double *depolarisation, vr_error *err) {
  vr_model_response r;
  vr_status st = vr_model_measure(m, nm, aoi_deg, 0.0, &r, err);
  if (st) return st;
  *psi = r.psi;
  *delta = r.delta;
  if (depolarisation) *depolarisation = r.depolarisation;
  return VR_OK;
}
