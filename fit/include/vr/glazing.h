/* Glazing figures: visible, solar and UV transmittance and reflectance of a
 * pane or of several panes with gaps, under an optical standard
 * (vr/optical_standard.h), at normal incidence or at an angle, and the
 * colour of the transmitted and reflected light.
 *
 * Panes are spectral T, Rf, Rb per polarisation on one wavelength grid.
 * Panes combine in power with every inter-reflection across the gaps (the
 * gaps hold a non-absorbing gas, so only the geometric series remains; the
 * first pane faces the outside):
 *     T   = T1 T2 / (1 - Rb1 Rf2)
 *     Rf  = Rf1 + T1^2 Rf2 / (1 - Rb1 Rf2)
 *     Rb  = Rb2 + T2^2 Rb1 / (1 - Rb1 Rf2)
 * applied pane by pane, for s and p separately, then averaged
 * (unpolarised light).  This is the spectral method of ISO 9050 section 4
 * and of LBNL WINDOW for specular layers.
 *
 * At an angle, a pane is taken there by one of two routes:
 *  - physical (uncoated glass): n and k are back-solved from its normal-
 *    incidence T and R and its thickness (vr/slab_invert.h), then Fresnel and
 *    the slab series give T and R for s and p; front and back are solved
 *    separately (T with Rf, T with Rb).  Exact for uncoated glass, and the
 *    method of LBNL WINDOW and Windows-CalcEngine for it.
 *  - coated (Rf and Rb differ by more than VR_COATED_ASYMMETRY somewhere in
 *    the visible): a coating is not a change of the glass's index, so the
 *    physical route does not apply.  Windows-CalcEngine's coated-glazing
 *    polynomials are used, as LBNL WINDOW does: with c = cos(theta),
 *    T = T0 P_T(c), R = R0 (1 - r) + r, r = P_R(c) - P_T(c), both clipped to
 *    [0, 1], P fourth-order polynomials whose "clear" set applies when the
 *    pane's normal solar transmittance exceeds 0.645, the "bronze" set
 *    otherwise (Windows-CalcEngine, SpectralAveraging/src/
 *    AngularProperties.cpp; from WINDOW 4).  Unpolarised only (s = p).
 *    Where the coating's stack is known, vr-spectro btdf computes the
 *    coated pane exactly with thin-film optics instead of either route.
 */
#ifndef VR_GLAZING_H
#define VR_GLAZING_H

#include <stdbool.h>
#include <stddef.h>
#include "vr/error.h"
#include "vr/optical_standard.h"
#include "vr/spectro_data.h"
#include "vr/spectrum.h"

#ifdef __cplusplus
extern "C" {
#endif

#define VR_COATED_ASYMMETRY 0.01

typedef enum vr_angular_route {
  VR_ROUTE_AUTO = 0,  /* coated polynomials for coated panes, else physical */
  VR_ROUTE_PHYSICAL,
  VR_ROUTE_COATED
} vr_angular_route;

/* One pane (or a combined system) on a grid: index 0 = s, 1 = p. */
typedef struct vr_pane {
  size_t n;
  double *nm;
  double *T[2], *Rf[2], *Rb[2];
  bool coated;             /* Rf and Rb differ (VR_COATED_ASYMMETRY) */
  bool has_R;              /* false: a transmittance-only pane (R arrays NAN) */
  vr_angular_route route;  /* the route used to reach the angle (AUTO at 0) */
} vr_pane;

void vr_pane_destroy(vr_pane *p);

/* Windows-CalcEngine's coated route for one wavelength (see above). */
void vr_coated_angular(double T0, double R0, double angle_deg, double solar_T0, double *T,
                       double *R);

/* A measured normal-incidence curve of an uncoated or coated pane (Rb taken
 * equal to Rf when it was not measured) at angle_deg, by the route asked for
 * (thickness_nm required for the physical route when angle_deg > 0;
 * solar_T0, the pane's normal solar transmittance, chooses the coated
 * polynomial set).  Wavelengths where the
 * inversion has no root (data no slab can give, e.g. T + R = 1 within
 * rounding with k = 0) keep their normal-incidence values scaled the way a
 * lossless slab of the fitted neighbouring index would be; their count is
 * returned in *unsolved (may be NULL).
 * A curve without reflectance gives a transmittance-only pane (has_R
 * false) at normal incidence; at an angle it is refused (VR_E_NOT_FOUND:
 * both routes start from T and R). */
vr_status vr_pane_from_curve(const vr_spectro_curve *c, double thickness_nm, double angle_deg,
                             vr_angular_route route, double solar_T0, vr_pane **out,
                             size_t *unsolved, vr_error *err);

/* The system of panes[0] (outside) .. panes[count-1] (inside), each
 * resampled linearly onto the union of their wavelengths inside the range
 * they all cover (as Windows-CalcEngine combines layers measured on
 * different grids; VR_E_RANGE, naming each pane's span, when they share
 * none: a standard whose range the system does not cover is refused where
 * it is applied).  Every pane needs its
 * reflectance when there are several (the inter-reflections): a
 * transmittance-only pane among them is VR_E_NOT_FOUND. */
vr_status vr_pane_combine(vr_pane *const *panes, size_t count, vr_pane **out, vr_error *err);

typedef struct vr_glazing_metrics {
  double Tvis, Rvis_front, Rvis_back;
  double Tsol, Rsol_front, Rsol_back;
  double Tuv;                  /* NAN when the standard has no UV method */
  double T_xyz[3], T_lab[3];   /* transmitted colour (the standard's colour
                                  methods: NFRC gives D65 and CIE 1964 10 deg),
                                  L*a*b* against the perfect transmitter */
  double Rf_lab[3], Rb_lab[3];  /* NAN without reflectance */
  bool has_colour;
  bool has_R;                  /* false: transmittance-only pane, R figures NAN */
  /* Colour rendering in transmission, EN 410 (4.9): the light D65 sends
   * through the glazing rendered against D65 by CIE 13.3 (vr/cri.h),
   * whatever the standard; NAN when the pane does not cover 380-780 nm. */
  double Ra;
  double R_i[8];               /* the special indices R1..R8 it averages */
} vr_glazing_metrics;

/* Figures of a pane (unpolarised) under the standard's SOLAR, PHOTOPIC,
 * TUV and COLOR_TRISTIMX/Y/Z methods (missing colour or UV methods leave
 * those fields NAN / has_colour false), and its colour rendering index
 * (EN 410, above). */
vr_status vr_glazing_metrics_compute(const vr_standard *std, const vr_pane *pane,
                                     vr_glazing_metrics *out, vr_error *err);

#ifdef __cplusplus
}
#endif
#endif
