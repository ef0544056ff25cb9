/* Centre-of-glass heat balance of a glazing: U-factor and solar heat gain
 * coefficient (SHGC, the g-value) by ISO 15099 (2003) for specular panes
 * separated by gas gaps, under the NFRC 100/200 environments, as LBNL's
 * WINDOW and Windows-CalcEngine (Tarcog) compute them.
 *
 * Each pane i has two faces with temperatures Tf, Tb and radiosities Jf, Jb;
 * G is the radiation falling on a face (the facing radiosity, or the
 * environment's sigma T^4).  Per pane, with h the convective coefficient in
 * front of / behind it (outdoor, gap, indoor), c = k/t the pane's
 * conductance, S its absorbed solar power (split half to each face) and
 * tau its IR transmittance:
 *     h_f (Tf - T_prev) + c (Tf - Tb) + Jf - (1 - tau) Gf - tau Gb = S/2
 *     eps_f sigma Tf^4 - Jf + (1 - eps_f - tau) Gf + tau Gb       = 0
 *     eps_b sigma Tb^4 - Jb + tau Gf + (1 - eps_b - tau) Gb       = 0
 *     h_b (Tb - T_next) + c (Tb - Tf) + Jb - (1 - tau) Gb - tau Gf = S/2
 * (ISO 15099 section 8).  The system is solved by repeated linear solves
 * with T^3 and the h taken from the previous iterate, relaxed 0.65/0.35, to
 * a change below 1e-8 K or W/m2.
 *
 * Convection: outdoors h = 4 + 4 v (ISO 15099 8.3.3, windward); indoors
 * natural convection on a plate of the glazing's height (ISO 15099 8.3.2,
 * properties of air at Tair + (Tsurf - Tair)/4); in a gap h = Nu lambda / d
 * with ISO 15099's Nusselt correlations for an inclined cavity (5.3.3.2-6,
 * aspect ratio height / d), properties at the mean of the two faces.
 * Outdoor radiation: sky and ground blended by the view factors of the tilt
 * (ISO 15099 8.3.1), both black at their temperatures.
 *
 * Domain: panes 1 to 8, emissivities in [0, 1] (below 1e-6 taken as 1e-6:
 * two facing perfect mirrors would leave their radiosities undetermined),
 * gas gaps above 13.3 Pa, any tilt; the heat balance is refused, not
 * guessed, when it does not converge.
 *
 * U = q_in / (Tin - Tout) without sun (q_in: the heat leaving the room
 * through the inner face, convective plus radiative); SHGC = Tsol +
 * (q_in,sun - q_in,dark) / I under the SHGC environment. */
#ifndef VR_GLAZING_THERMAL_H
#define VR_GLAZING_THERMAL_H

#include <stddef.h>
#include "vr/error.h"
#include "vr/gas.h"

#ifdef __cplusplus
extern "C" {
#endif

#define VR_THERMAL_MAX_PANES 8
#define VR_SIGMA 5.6697e-8   /* W/(m2 K4), as Windows-CalcEngine carries it */

typedef struct vr_thermal_pane {
  double thickness_m;
  double conductivity;   /* W/(m K) */
  double emis[2];        /* hemispherical, front (outside) and back */
  double tir;            /* IR transmittance (0 for glass) */
  double absorptance;    /* of solar, in the system (vr/glazing_layers.h) */
} vr_thermal_pane;

typedef struct vr_thermal_gap {
  double thickness_m;
  vr_gas_mix gas;
  double pressure_pa;
} vr_thermal_gap;

typedef struct vr_thermal_env {
  const char *name;
  double T_in, T_out;    /* air, K; the room's surfaces radiate at T_in */
  double T_sky;          /* outdoor radiant (sky) temperature, K */
  double wind_ms;        /* outdoor air speed */
  double solar_wm2;      /* incident, direct */
  double pressure_pa;
} vr_thermal_env;

/* NFRC 100-2010 / 200-2010 (WINDOW and Windows-CalcEngine's): winter for U,
 * summer for SHGC. */
extern const vr_thermal_env VR_ENV_NFRC_U, VR_ENV_NFRC_SHGC;

typedef struct vr_thermal_system {
  size_t n;                                  /* panes, outside first */
  vr_thermal_pane pane[VR_THERMAL_MAX_PANES];
  vr_thermal_gap gap[VR_THERMAL_MAX_PANES - 1];
  double height_m;                           /* for natural convection (1 m: NFRC) */
  double tilt_deg;                           /* 90: vertical */
} vr_thermal_system;

typedef struct vr_thermal_state {
  double T[2 * VR_THERMAL_MAX_PANES];        /* face temperatures, K, outside first */
  double J[2 * VR_THERMAL_MAX_PANES];        /* radiosities, W/m2 */
  double q_in;                               /* W/m2, room -> glazing positive */
  double h_in, h_out;                        /* convective + radiative film coefficients */
  double gap_h[VR_THERMAL_MAX_PANES - 1];    /* convective, W/(m2 K) */
  double gap_Ra[VR_THERMAL_MAX_PANES - 1], gap_Nu[VR_THERMAL_MAX_PANES - 1];
  int iterations;
} vr_thermal_state;

/* The balance of the system in env, with the sun (with_sun: env's solar
 * power absorbed in the panes by their absorptances) or without.
 * VR_E_ARG for a system outside the model's domain (named); VR_E_NUMERIC
 * when the iteration does not converge. */
vr_status vr_thermal_solve(const vr_thermal_system *s, const vr_thermal_env *env, int with_sun,
                           vr_thermal_state *out, vr_error *err);

typedef struct vr_thermal_figures {
  double U;              /* W/(m2 K), NFRC U environment */
  double SHGC;           /* NFRC SHGC environment */
  vr_thermal_state winter, summer;
} vr_thermal_figures;

/* U and SHGC under NFRC 100/200; Tsol the system's normal solar
 * transmittance. */
vr_status vr_thermal_nfrc(const vr_thermal_system *s, double Tsol, vr_thermal_figures *out,
                          vr_error *err);

/* ISO 15099 Nusselt number of a gas cavity: Ra its Rayleigh number, A its
 * height / thickness, tilt in degrees as ISO 15099 measures it (90:
 * vertical; 0: horizontal with the warm side below; above 90 the warm side
 * above); 1 (conduction) for Ra <= 0. */
double vr_cavity_nusselt(double Ra, double A, double tilt_deg);

#ifdef __cplusplus
}
#endif
#endif
