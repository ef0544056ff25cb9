/* Illuminance sensors (sensors.c): the scene's sensor points and grids,
 * read by the scene's estimator (render sensors=path|photon) into the
 * result's readings, spectra, daylight-factor components and sky-patch
 * tallies. */
#ifndef VR_INTEGRATORS_SENSORS_H
#define VR_INTEGRATORS_SENSORS_H

#include "run/run.h"

vr_status vr_sensors_run(vr_run *r, vr_error *err);

#endif
