/* The denoiser's features of camera samples (features.c): albedo, normal
 * and nearness at the first non-delta vertex, into the film's feature sums
 * when the film keeps them (vr_accum_keep_features). */
#ifndef VR_INTEGRATORS_FEATURES_H
#define VR_INTEGRATORS_FEATURES_H

#include "integrators/pass.h"

/* Whether p is a camera path that has not recorded its features yet, on a
 * film that keeps them. */
bool vr_features_wanted(const vr_pass *c, const vr_payload *p);
/* Records an escaped sample's features (and marks p). */
void vr_features_escape(vr_pass *c, vr_payload *p);
/* Records the features of surface se at hit (and marks p). */
void vr_features_hit(vr_pass *c, vr_payload *p, const vr_hit *hit, const vr_surface *se);

#endif
