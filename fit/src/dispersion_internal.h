/* Private declarations shared by the dispersion sources (dispersion.c,
 * oscillators.c, bspline_kk.c) and their unit test: the layout of a
 * vr_dispersion, the per-oscillator routines, and the numerical
 * Kramers-Kronig transform that Cody-Lorentz, the B-spline model and the
 * tests rely on.  Nothing here keeps state between calls. */
#ifndef VR_DISPERSION_INTERNAL_H
#define VR_DISPERSION_INTERNAL_H

#include <stddef.h>
#include "vr/dispersion.h"

#include <complex.h>

/* clang 14 with glibc has no CMPLX (it needs __builtin_complex); the
 * arithmetic fallback is exact for the finite values built here. */
#ifndef CMPLX
#define CMPLX(x, y) ((double _Complex)((double)(x) + _Complex_I * (double)(y)))
#endif

#define VR_PARAM_NAME_MAX 32

struct vr_dispersion {
  vr_disp_kind kind;
  size_t nparams;
  double *p;                          /* the parameter vector */
  char (*names)[VR_PARAM_NAME_MAX];   /* one name per parameter */
  size_t nterms;                      /* Sellmeier (B, C) pairs or genosc terms */
  vr_osc_kind *osc;                   /* genosc: kind of each term */
  size_t *off;                        /* genosc: index of each term's first parameter */
  size_t nknots;                      /* bspline: knot count (0 until set) */
  double *knots;                      /* bspline: knot energies, eV */
  vr_spectrum *tab_n, *tab_k;         /* tabulated (tab_k may be NULL) */
};

/* ---- oscillators.c: one genosc term ------------------------------------ */

/* Number of parameters of a term and their base names ("Amp", "En", ...);
 * the model appends the 1-based term number. */
size_t vr_osc_nparams(vr_osc_kind kind);
const char *vr_osc_param_base(vr_osc_kind kind, size_t i);
const char *vr_osc_kind_name(vr_osc_kind kind);
/* Default parameters of a new term (valid, typical values). */
void vr_osc_defaults(vr_osc_kind kind, double *p);
/* VR_E_RANGE naming the parameter (with its term number) when the values
 * make the term unphysical (negative amplitude, width, energy, ...). */
vr_status vr_osc_check(vr_osc_kind kind, const double *p, size_t term, vr_error *err);
/* The term's contribution to ε at photon energy E > 0 (eV); p checked. */
vr_status vr_osc_eps(vr_osc_kind kind, const double *p, double E, vr_complex *eps,
                     vr_error *err);
/* The term's ε2 alone. */
double vr_osc_eps2(vr_osc_kind kind, const double *p, double E);
/* The term's ε1 from the numerical Kramers-Kronig transform of its ε2,
 * whatever closed form the term has (a cross-check for the tests). */
vr_status vr_osc_eps1_kk(vr_osc_kind kind, const double *p, double E, double *eps1,
                         vr_error *err);

/* ---- bspline_kk.c: Kramers-Kronig transform ----------------------------- */

typedef double (*vr_eps2_fn)(double E, const void *ctx);

/* An ε2(E) to transform: it vanishes outside [lo, hi] (hi may be INFINITY,
 * then ε2 must fall at least as fast as 1/E² at large E); breaks lists
 * energies where ε2 has a kink or a narrow feature (peak positions, the
 * edges of a peak) so that the quadrature starts with them as panel ends. */
typedef struct vr_kk_spec {
  vr_eps2_fn eps2;
  const void *ctx;
  double lo, hi;
  const double *breaks;
  size_t nbreaks;
} vr_kk_spec;

/* (2/π) P∫_0^∞ E' ε2(E') / (E'² - E²) dE' at E > 0, to about 1e-9 relative.
 * VR_E_NUMERIC when the integral diverges (ε2 jumping from 0 to a non-zero
 * value exactly at E) or the quadrature does not converge. */
vr_status vr_kk_transform(const vr_kk_spec *spec, double E, double *eps1, vr_error *err);

/* The B-spline model's ε at E (the parameter vector starts with eps_inf). */
vr_status vr_bspline_eps(const vr_dispersion *d, double E, vr_complex *eps, vr_error *err);

#endif
