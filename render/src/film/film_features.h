/* A film's feature sums into the result's features, and the denoised
 * display image (film_features.c). */
#ifndef VR_FILM_FEATURES_H
#define VR_FILM_FEATURES_H

#include "film/accum.h"
#include "vr/render.h"

/* Fills res->features from acc's feature sums (summed over the ranks), and,
 * when display, res->xyz_display by vr_denoise on threads threads.
 * res->xyz must hold the film's means;
 * a pixel's samples are res->pixel_samples[p] when set, else spp; the
 * second half's mean is 2 / passes times acc->half_xyz (a film whose sums
 * are over `passes` passes: 1 for a film of weighted means, spp for SPPM's
 * iterations), or 2 / n for an adaptive film of sums, to which half_extra
 * (unless NULL) adds what the integrator kept apart of that half (SPPM's second
 * chain's photon radiance). */
vr_status vr_film_features(vr_render_result *res, const vr_accum *acc, int spp, int passes,
                           bool display,
                           void (*half_extra)(const void *ctx, double *xyz), const void *ctx,
                           int threads, vr_error *err);

#endif
