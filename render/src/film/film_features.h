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
 * second half's mean is half_scale times acc->half_xyz (2 for a film of
 * means, 2 / n for an adaptive film of sums). */
vr_status vr_film_features(vr_render_result *res, const vr_accum *acc, int spp, bool display,
                           int threads, vr_error *err);

#endif
