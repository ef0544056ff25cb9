/* Private pieces of the sample model. */
#ifndef VR_MODEL_INTERNAL_H
#define VR_MODEL_INTERNAL_H

#include "vr/ellipso_model.h"
#include "vr/material.h"

vr_dispersion *vr_dispersion_from_material(const vr_material *m, vr_error *err);
/* vr_model_layer_index once the couplings are applied (the response code
 * applies them once per point, not once per layer). */
vr_status vr_model_layer_index_coupled(const vr_sample_model *m, long i, double nm, vr_complex *N,
                                       vr_error *err);

#endif
