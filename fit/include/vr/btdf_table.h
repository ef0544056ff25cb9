/* Angle x wavelength tables of the specular transmittance and reflectance
 * of a pane, per polarisation, for the renderer (stored as a material of
 * kind "btdf"; vr/btdf.h in matdb reads them back).
 *
 * Three sources, each with its method recorded in the table:
 *  - a dielectric with n(λ), k(λ) and a thickness: the exact thick-slab
 *    series per polarisation (vr_slab);
 *  - a coated pane given as a layer stack on an incoherent glass substrate
 *    (the model-file grammar of vr/ellipso_model.h: "layer" lines, then
 *    "substrate MATERIAL thickness=MM backside"): coherent thin films on the
 *    coated face and power addition across the substrate (vr_stack_solve);
 *    the back reflectance from the stack turned over;
 *  - a measured pane (T, Rf, Rb at normal incidence): the angular routes of
 *    vr/glazing.h (physical for uncoated glass, Windows-CalcEngine's
 *    polynomials for coated glass, which give s = p). */
#ifndef VR_BTDF_TABLE_H
#define VR_BTDF_TABLE_H

#include <stddef.h>
#include "vr/ellipso_model.h"
#include "vr/error.h"
#include "vr/glazing.h"
#include "vr/material.h"
#include "vr/spectro_data.h"

#ifdef __cplusplus
extern "C" {
#endif

enum { VR_BT_TS = 0, VR_BT_TP, VR_BT_RFS, VR_BT_RFP, VR_BT_RBS, VR_BT_RBP, VR_BT_COUNT };

typedef struct vr_btdf_table {
  size_t na, nl;
  double *angles;              /* degrees, increasing, in [0, 90] */
  double *nm;                  /* increasing */
  double *q[VR_BT_COUNT];      /* na x nl each, row per angle */
  double thickness_nm;
  char method[160];
} vr_btdf_table;

void vr_btdf_table_free(vr_btdf_table *t);

vr_status vr_btdf_from_material(const vr_material *dielectric, double thickness_nm,
                                const double *angles, size_t na, const double *nm, size_t nl,
                                vr_btdf_table *out, vr_error *err);
vr_status vr_btdf_from_model(const vr_sample_model *model, const double *angles, size_t na,
                             const double *nm, size_t nl, vr_btdf_table *out, vr_error *err);
vr_status vr_btdf_from_curve(const vr_spectro_curve *c, double thickness_nm,
                             vr_angular_route route, double solar_T0, const double *angles,
                             size_t na, vr_btdf_table *out, vr_error *err);

/* A material of kind btdf: roles "Ts@ANGLE", "Tp@ANGLE", "Rfs@..", "Rfp@..",
 * "Rbs@..", "Rbp@.." (ANGLE as %g degrees), property "angles" (the list as
 * text), "thickness" (mm) when known, provenance model = the method. */
vr_status vr_btdf_table_material(const vr_btdf_table *t, const char *name, vr_material **out,
                                 vr_error *err);

#ifdef __cplusplus
}
#endif
#endif
