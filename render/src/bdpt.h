/* Bidirectional path tracing (render integrator=bdpt): what vr_render_scene
 * calls.  The integrator and its limits are described in bdpt.c and in
 * docs/vr-render.md ("Bidirectional path tracing"). */
#ifndef VR_BDPT_H
#define VR_BDPT_H

#include "render_run.h"

/* Whether a render of s with opt on nranks processes can use BDPT for its
 * camera pass: it needs the whole scene in one cell (no --subdomains above
 * 1 outside image space, no memory budget, one process) and a pinhole or
 * thin-lens camera.  VR_E_ARG naming the reason otherwise; VR_OK when the
 * scene does not ask for BDPT or renders no image. */
vr_status vr_bdpt_check(const vr_scene *s, const vr_render_options *opt, int nranks,
                        vr_error *err);

/* The camera pass by BDPT: c->spp samples per pixel of a W x H image into
 * c->acc, on the run's threads, each thread tracing whole tiles. */
vr_status vr_bdpt_camera_pass(run *r, rscene *rs, pass_ctx *c, int W, int H, vr_error *err);

/* lights.c, for BDPT: the intensity of point or spot light i towards the
 * unit direction d (from the light), relative to its on-axis value. */
double vr_light_distribution(const rscene *rs, size_t i, const double d[3]);

#endif
