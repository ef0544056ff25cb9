/* The European declared figures of a glazing: the thermal transmittance
 * U of EN 673 and the total solar energy transmittance g of EN 410, the
 * fixed-coefficient methods that glass makers declare (CE marking), beside
 * the ISO 15099 heat balance of vr/glazing_thermal.h.
 *
 * EN 673 (vertical glazing, centre of glass):
 *     1/U = 1/he + sum_j d_j / k_j + sum_gaps 1/hs + 1/hi
 *     hs = hr + hg
 *     hr = 4 sigma (1/e1 + 1/e2 - 1)^-1 Tm^3            (Tm = 283 K)
 *     hg = Nu lambda / s,  Nu = A (Gr Pr)^n, at least 1  (A 0.035, n 0.38)
 *     Gr = 9.81 s^3 dT rho^2 / (Tm mu^2),  Pr = mu c / lambda
 * with the gas properties at 10 C of EN 673's table (mixtures: each
 * property the volume-fraction-weighted sum), dT = 15 K over the glazing,
 * shared between several gaps in proportion to their resistances 1/hs
 * (iterated), e1, e2 the corrected emissivities of the faces bounding the
 * gap, and the film coefficients of the edition:
 *     2011: he = 25, hi = 3.6 + 4.1 ei / 0.837 W/(m2 K)  (7.7 uncoated)
 *     1997: he = 23, hi = 3.6 + 4.4 ei / 0.837           (8.0 uncoated)
 * (EN 410:2011 and EN 410:1998 use the same pairs), ei the corrected
 * emissivity of the innermost face.
 *
 * EN 410 g = tau_e + q_i.  The panes' absorbed solar powers alpha_e,i
 * (in the system, by the multiple-reflection sums) are taken at nodes
 * joined in series: the outer face of the outer pane, the centres of the
 * middle panes, the inner face of the inner pane; outside through 1/he,
 * inside through 1/hi, neighbouring nodes through the glass and gap
 * resistances between them (EN 410's Lambda for double glazing, Lambda_12
 * and Lambda_23 for triple).  The share of a node's power that flows in is
 * its resistance to the outside over the total, so
 *     q_i = sum_i alpha_e,i R_out,i / (1/he + sum 1/Lambda + 1/hi)
 * which for one pane is alpha_e hi / (he + hi) and for two is EN 410's
 * ((a1 + a2)/he + a2/Lambda) / (1/he + 1/hi + 1/Lambda).
 *
 * Domain: 1 to 8 panes, vertical, gaps of air, argon, krypton, xenon or
 * their mixtures at atmospheric pressure, emissivities in (0, 1]. */
#ifndef VR_GLAZING_EN673_H
#define VR_GLAZING_EN673_H

#include <stddef.h>
#include "vr/error.h"
#include "vr/gas.h"

#ifdef __cplusplus
extern "C" {
#endif

#define VR_EN673_MAX_PANES 8
#define VR_EN673_TM 283.0         /* K, the declared mean gas temperature */
#define VR_EN673_DT 15.0          /* K across the glazing's gaps */
#define VR_EN673_SIGMA 5.67e-8    /* W/(m2 K4), as EN 673 writes it */
#define VR_EN673_UNCOATED 0.837   /* corrected emissivity of uncoated soda-lime glass */

typedef enum vr_en673_edition { VR_EN673_2011 = 0, VR_EN673_1997 = 1 } vr_en673_edition;

typedef struct vr_en673_pane {
  double thickness_m;
  double conductivity;   /* W/(m K); 1.0 for soda-lime glass */
  double emis[2];        /* corrected emissivity, outer and inner face */
  double absorptance;    /* solar, in the system (EN 410 alpha_e) */
} vr_en673_pane;

typedef struct vr_en673_system {
  size_t n;
  vr_en673_pane pane[VR_EN673_MAX_PANES];
  double gap_m[VR_EN673_MAX_PANES - 1];
  vr_gas_mix gas[VR_EN673_MAX_PANES - 1];
  vr_en673_edition edition;
} vr_en673_system;

/* A gas at EN 673's mean temperature. */
typedef struct vr_en673_gas {
  double rho, mu, lambda, c;
} vr_en673_gas;

typedef struct vr_en673_result {
  double U;                                  /* W/(m2 K), not rounded */
  double U_declared;                         /* to one decimal */
  double he, hi;
  double hs[VR_EN673_MAX_PANES - 1], hr[VR_EN673_MAX_PANES - 1], hg[VR_EN673_MAX_PANES - 1];
  double Nu[VR_EN673_MAX_PANES - 1], dT[VR_EN673_MAX_PANES - 1];
  /* Conductance between neighbouring solar nodes (EN 410's Lambda). */
  double Lambda[VR_EN673_MAX_PANES - 1];
  int iterations;
} vr_en673_result;

/* The fill's properties at 10 C (EN 673's table; mixtures by volume). */
void vr_en673_gas_properties(const vr_gas_mix *g, vr_en673_gas *out);

/* The film coefficients of an edition; hi for the innermost face's
 * corrected emissivity ei. */
void vr_en673_films(vr_en673_edition e, double ei, double *he, double *hi);

/* U of the system by EN 673 and the conductances EN 410 needs.  VR_E_ARG /
 * VR_E_RANGE naming the pane or gap outside the domain. */
vr_status vr_en673_u(const vr_en673_system *s, vr_en673_result *out, vr_error *err);

/* EN 410's secondary heat transfer factor q_i of n panes with absorbed
 * solar powers a[0..n-1] (outside first), film coefficients he, hi and
 * the n - 1 node conductances Lambda; NAN for bad arguments. */
double vr_en410_qi(size_t n, const double *a, double he, double hi, const double *Lambda);

#ifdef __cplusplus
}
#endif
#endif
