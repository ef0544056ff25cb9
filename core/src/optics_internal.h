/* Entry points shared between the optics sources, not part of the API. */
#ifndef VR_OPTICS_INTERNAL_H
#define VR_OPTICS_INTERNAL_H
#include "vr/optics.h"

/* Coherent solve on the Snell invariant beta = n0 sin(theta0), without
 * argument validation (callers validate). */
vr_status vr_tmm_coherent_beta(const vr_layer *L, size_t count, vr_complex beta, double lambda,
                               vr_pol pol, vr_tmm_result *res, double *absorbed, vr_error *err);
#endif
