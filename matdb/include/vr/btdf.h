/* Reading the specular angle x wavelength tables of a pane (materials of
 * kind "btdf", written by vr-spectro btdf): roles "Ts@ANGLE", "Tp@..",
 * "Rfs@..", "Rfp@..", "Rbs@..", "Rbp@.." and the property "angles". */
#ifndef VR_BTDF_H
#define VR_BTDF_H

#include "vr/material.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum vr_btdf_quantity { VR_BTDF_T = 0, VR_BTDF_RF, VR_BTDF_RB } vr_btdf_quantity;
typedef enum vr_btdf_pol { VR_BTDF_S = 0, VR_BTDF_P = 1, VR_BTDF_UNPOLARISED = 2 } vr_btdf_pol;

/* The value at angle_deg (linear between the tabulated angles, held beyond
 * the last one up to 90) and nm (linear; VR_E_RANGE outside the tables).
 * VR_E_ARG when m is not a btdf table or a role is missing. */
vr_status vr_btdf_eval(const vr_material *m, vr_btdf_quantity q, vr_btdf_pol pol,
                       double angle_deg, double nm, double *value, vr_error *err);

#ifdef __cplusplus
}
#endif
#endif
