/* Private pieces of the sample model. */
#ifndef VR_MODEL_INTERNAL_H
#define VR_MODEL_INTERNAL_H

#include "vr/ellipso_model.h"
#include "vr/material.h"

vr_dispersion *vr_dispersion_from_material(const vr_material *m, vr_error *err);

#endif
