/* Fill gases of insulating glazing units and their properties, as ISO 15099
 * (2003) section 5.1 and annex B give them: conductivity, viscosity and
 * specific heat linear in temperature, density of an ideal gas, and the
 * mixing rules of equations 62-68 for several gases.  Coefficients (SI,
 * T in K) as Windows-CalcEngine carries them (Gases/src/GasCreator.cpp):
 *
 *            M (kg/kmol)  cp a, b            lambda a, b          mu a, b
 *   air      28.97        1002.737, 0.012324  2.8733e-3, 7.76e-5   3.7233e-6, 4.94e-8
 *   argon    39.948       521.929, 0          2.2848e-3, 5.1486e-5 3.3786e-6, 6.4514e-8
 *   krypton  83.8         248.09, 0           9.443e-4, 2.826e-5   2.213e-6, 7.777e-8
 *   xenon    131.3        158.34, 0           4.538e-4, 1.723e-5   1.069e-6, 7.414e-8
 *
 * Domain: the correlations are fitted for 200-400 K near atmospheric
 * pressure; vacuum gaps (below 13.3 Pa, molecular conduction) are not
 * modelled and are refused by the caller. */
#ifndef VR_GAS_H
#define VR_GAS_H

#include <stddef.h>
#include "vr/error.h"

#ifdef __cplusplus
extern "C" {
#endif

#define VR_GAS_R 8314.462175   /* J/(kmol K) */
#define VR_GAS_MAX 4

typedef enum vr_gas_id { VR_GAS_AIR, VR_GAS_ARGON, VR_GAS_KRYPTON, VR_GAS_XENON } vr_gas_id;

/* A fill: mole fractions summing to 1. */
typedef struct vr_gas_mix {
  size_t n;
  vr_gas_id id[VR_GAS_MAX];
  double frac[VR_GAS_MAX];
} vr_gas_mix;

typedef struct vr_gas_props {
  double lambda;  /* conductivity, W/(m K) */
  double mu;      /* dynamic viscosity, Pa s */
  double cp;      /* specific heat, J/(kg K) */
  double rho;     /* density, kg/m3 */
  double M;       /* molar mass, kg/kmol */
} vr_gas_props;

/* Properties of the fill at temperature T (K) and pressure p (Pa). */
void vr_gas_properties(const vr_gas_mix *g, double T, double p, vr_gas_props *out);

/* "air", "argon", "krypton", "xenon", or a mixture "argon:0.9+air:0.1"
 * (fractions must sum to 1 within 1e-6).  VR_E_PARSE naming what is wrong. */
vr_status vr_gas_parse(const char *s, vr_gas_mix *out, vr_error *err);
const char *vr_gas_name(vr_gas_id id);

#ifdef __cplusplus
}
#endif
#endif
