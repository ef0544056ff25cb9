/* The tables of a thin element: unpolarised T, Rf, Rb over cos(theta) x
 * wavelength, computed once at creation from each source, so that a ray
 * hitting a pane costs two bilinear look-ups.
 *
 * Why tables: vr_slab runs a coherent probe and two interface solves per
 * call, about 0.7 us of CPU; a look-up of T and R costs about 20 ns per
 * wavelength (measured -O2, a busy 2-core machine, so both are upper
 * figures).  The nodes and the interpolation error against direct vr_slab
 * are described in bsdf_internal.h and asserted in
 * tests/render/test_bsdf_pane.c.
 * Polarisation: each node averages s and p (unpolarised light in, the
 * renderer carries no Stokes vector).  btdf tables: bsdf_btdf.c. */
#include <complex.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "materials/bsdf_internal.h"
#include "vr/optics.h"

#define NC VR_BSDF_PANE_NODES

vr_status vr_bsdfi_tables_alloc(vr_bsdf *b, vr_error *err) {
  size_t count = b->nl * NC;
  b->T = malloc(count * sizeof *b->T);
  b->Rf = malloc(count * sizeof *b->Rf);
  b->Rb = malloc(count * sizeof *b->Rb);
  if (!b->T || !b->Rf || !b->Rb) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  return VR_OK;
}

double vr_bsdfi_node_cos(size_t j) {
  double u = (double)j / (double)(NC - 1);
  return u * u; /* uniform in sqrt(cos): see bsdf_internal.h */
}
/* Node 0 is grazing incidence, where every face is a mirror: T = 0, R = 1
 * (the limit; vr_slab's series is 0 / 0 there for a lossless slab), so the
 * builders store it without calling a solver. */
static double node_theta(size_t j) { return acos(vr_bsdfi_node_cos(j)); }
static double node_nm(const vr_bsdf *b, size_t i) { return b->lmin + (double)i; }

/* Every node in [0, 1] with R + T <= 1 (bilinear interpolation then keeps
 * both properties everywhere). */
void vr_bsdfi_store(vr_bsdf *b, size_t i, size_t j, double T, double Rf, double Rb) {
  size_t at = i * NC + j;
  /* A NaN from a solver must never reach the hot path. */
  if (isnan(T) || isnan(Rf) || isnan(Rb)) T = Rf = Rb = 0.0;
  T = vr_bsdfi_clamp01(T);
  Rf = vr_bsdfi_clamp01(Rf);
  Rb = vr_bsdfi_clamp01(Rb);
  b->T[at] = T;
  b->Rf[at] = T + Rf > 1.0 ? 1.0 - T : Rf;
  b->Rb[at] = T + Rb > 1.0 ? 1.0 - T : Rb;
}

vr_status vr_bsdfi_table_slab(vr_bsdf *b, double d_nm, vr_error *err) {
  vr_status st = vr_bsdfi_tables_alloc(b, err);
  for (size_t i = 0; i < b->nl && !st; i++) {
    vr_complex N = b->n[i] + I * b->k[i];
    vr_bsdfi_store(b, i, 0, 0.0, 1.0, 1.0);
    for (size_t j = 1; j < NC && !st; j++) {
      vr_slab_result s;
      if ((st = vr_slab(1.0, N, d_nm, node_theta(j), node_nm(b, i), &s, err))) break;
      double R = 0.5 * (s.R[0] + s.R[1]);
      vr_bsdfi_store(b, i, j, 0.5 * (s.T[0] + s.T[1]), R, R);
    }
  }
  return st;
}

/* k of the slab whose single-pass transmittance is a at normal incidence. */
static double k_of(double a, double d_nm, double nm) {
  return -nm * log(fmax(a, 1e-300)) / (4.0 * M_PI * d_nm);
}

/* The normal-incidence node (cos = 1) moved onto the measurement, the rest
 * of the column with it (vr_bsdfi_match). */
static void match_column(vr_bsdf *b, size_t i, double Tn, double Rfn, double Rbn) {
  double *T = b->T + i * NC, *Rf = b->Rf + i * NC, *Rb = b->Rb + i * NC;
  double T1 = T[NC - 1], Rf1 = Rf[NC - 1], Rb1 = Rb[NC - 1];
  for (size_t j = 0; j < NC; j++) {
    double t = T[j], r = Rf[j];
    vr_bsdfi_match(Tn, Rfn, T1, Rf1, &t, &r);
    double tb = T[j], rb = Rb[j];
    vr_bsdfi_match(Tn, Rbn, T1, Rb1, &tb, &rb);
    vr_bsdfi_store(b, i, j, t, r, rb);
  }
}

vr_status vr_bsdfi_table_glazing(vr_bsdf *b, const vr_material *m, double d_nm, vr_error *err) {
  vr_status st = vr_bsdfi_tables_alloc(b, err);
  const char *rb_role = vr_material_spectrum(m, "Rb") ? "Rb" : "Rf";
  for (size_t i = 0; i < b->nl && !st; i++) {
    double nm = node_nm(b, i), Tn, Rfn, Rbn;
    bool e1 = false, e2 = false, e3 = false;
    if ((st = vr_material_eval(m, "T", nm, true, &Tn, &e1, err)) ||
        (st = vr_material_eval(m, "Rf", nm, true, &Rfn, &e2, err)) ||
        (st = vr_material_eval(m, rb_role, nm, true, &Rbn, &e3, err)))
      break;
    if (e1 || e2 || e3) b->extrapolated = true;
    Tn = vr_bsdfi_clamp01(Tn);
    Rfn = vr_bsdfi_clamp01(Rfn);
    Rbn = vr_bsdfi_clamp01(Rbn);
    /* Front and back are separate slabs (a coated pane reflects
     * differently on each side); T comes from the front one. */
    double nf, af, nb, ab;
    vr_bsdf_equivalent_slab(Tn, Rfn, &nf, &af);
    vr_bsdf_equivalent_slab(Tn, Rbn, &nb, &ab);
    vr_complex Nf = nf + I * k_of(af, d_nm, nm), Nb = nb + I * k_of(ab, d_nm, nm);
    vr_bsdfi_store(b, i, 0, 0.0, 1.0, 1.0);
    for (size_t j = 1; j < NC && !st; j++) {
      vr_slab_result f, r;
      if ((st = vr_slab(1.0, Nf, d_nm, node_theta(j), nm, &f, err)) ||
          (st = vr_slab(1.0, Nb, d_nm, node_theta(j), nm, &r, err)))
        break;
      vr_bsdfi_store(b, i, j, 0.5 * (f.T[0] + f.T[1]), 0.5 * (f.R[0] + f.R[1]),
                     0.5 * (r.R[0] + r.R[1]));
    }
    if (!st) match_column(b, i, Tn, Rfn, Rbn);
  }
  return st;
}

vr_status vr_bsdfi_table_coated(vr_bsdf *b, const vr_material *film, double film_nm,
                                double d_nm, vr_error *err) {
  vr_status st = vr_bsdfi_tables_alloc(b, err);
  for (size_t i = 0; i < b->nl && !st; i++) {
    double nm = node_nm(b, i), nf, kf;
    bool ext = false;
    if ((st = vr_material_nk(film, nm, true, &nf, &kf, &ext, err))) break;
    if (ext) b->extrapolated = true;
    /* Coherent film on the front face, the glass incoherent (its
     * thickness is far beyond the coherence length of daylight). */
    vr_layer front[4] = {{1.0, 0, 0}, {nf + I * kf, film_nm, 0},
                         {b->n[i] + I * b->k[i], d_nm, 1}, {1.0, 0, 0}};
    vr_layer back[4] = {front[0], front[2], front[1], front[3]};
    vr_bsdfi_store(b, i, 0, 0.0, 1.0, 1.0);
    for (size_t j = 1; j < NC && !st; j++) {
      double T = 0, Rf = 0, Rb = 0;
      for (int p = 0; p < 2 && !st; p++) {
        vr_tmm_result f, r;
        if ((st = vr_stack_solve(front, 4, node_theta(j), nm, (vr_pol)p, &f, err)) ||
            (st = vr_stack_solve(back, 4, node_theta(j), nm, (vr_pol)p, &r, err)))
          break;
        T += 0.5 * f.T;
        Rf += 0.5 * f.R;
        Rb += 0.5 * r.R;
      }
      if (!st) vr_bsdfi_store(b, i, j, T, Rf, Rb);
    }
  }
  return st;
}
