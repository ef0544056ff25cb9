/* Figures of the layers of a glazing system, for its heat balance
 * (vr/glazing_thermal.h):
 *
 * Layer absorptance.  Light of unit power falls on the front of pane 0 (or
 * on the back of the last pane); at each wavelength the forward flux in the
 * gap before pane j is
 *     F_j = T_P / (1 - Rb_P Rf_S)
 * with P the system of panes 0..j-1 and S that of panes j..n-1 (vr/glazing.h's
 * combination), and the backward flux behind pane j is F_{j+1} Rf of the
 * system j+1..n-1; pane j absorbs
 *     A_j = F_j (1 - T_j - Rf_j) + B_j (1 - T_j - Rb_j).
 * The spectral A_j (mean of s and p) is averaged under the standard's method
 * (SOLAR for the heat balance) like any other figure, so
 * sum_j A_j + T + R = 1 to the integration's rounding.  This is the
 * specular multilayer of ISO 15099 section 7 and Windows-CalcEngine.
 *
 * Emissivity.  The normal emissivity of each face is 1 - T - R averaged under
 * the standard's THERMAL IR method (NFRC: a 300 K blackbody over the data's
 * own wavelengths from 5 um); the hemispherical emissivity follows by the
 * NFRC 301 polynomials in the normal one, one for coated and one for
 * uncoated faces. */
#ifndef VR_GLAZING_LAYERS_H
#define VR_GLAZING_LAYERS_H

#include <stdbool.h>
#include <stddef.h>
#include "vr/error.h"
#include "vr/glazing.h"
#include "vr/optical_standard.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A[count]: absorptance of each pane (outside first) under the method, for
 * light falling on the front (from_back false) or on the back.  Panes need
 * reflectance (VR_E_NOT_FOUND); they are resampled onto the system's grid
 * (vr_pane_combine); VR_E_RANGE as vr_std_average when the data do not
 * cover the method. */
vr_status vr_glazing_layer_absorptance(const vr_standard *std, const char *method,
                                       vr_pane *const *panes, size_t count, bool from_back,
                                       double *A, vr_error *err);

/* normal[0] front, normal[1] back: normal emissivity of the pane's faces
 * under the THERMAL IR method, and *tir (may be NULL) its transmittance
 * there; VR_E_RANGE when the data do not reach the thermal infrared (the
 * message says how much is uncovered). */
vr_status vr_pane_emissivity(const vr_standard *std, const vr_pane *pane, double normal[2],
                             double *tir, vr_error *err);

/* Hemispherical emissivity from normal emissivity (NFRC 301). */
double vr_emissivity_hemispherical(double normal, bool coated);

#ifdef __cplusplus
}
#endif
#endif
