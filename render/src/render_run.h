/* What the passes of vr_render_scene share: the run (options, result, the
 * current pass's name), logging of decisions, pass records, running one
 * pass through the ray flow with its statistics, and the photon pass that
 * both the camera and photon-mapped sensors use. */
#ifndef VR_RENDER_RUN_H
#define VR_RENDER_RUN_H

#include "render_internal.h"

typedef struct run {
  const vr_render_options *opt;
  vr_render_result *res;
  const char *pass;
} run;

double vr_run_now(void);
void vr_run_say(const run *r, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* Appends a pass record (NULL when VR_MAX_PASSES are taken) and logs it. */
vr_pass_record *vr_run_record(run *r, const char *name, bool ran, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
/* Runs `units` work units of ops through the ray flow, adding its ray counts
 * to the result. */
vr_status vr_run_flow(run *r, rscene *rs, const vr_flow_ops *ops, pass_ctx *c, long units,
                      const char *name, vr_error *err);
/* Traces `photons` photons into c's maps: global (and, with direct, the
 * direct map) and/or caustic, then builds them and counts their photons. */
vr_status vr_run_photon_pass(run *r, rscene *rs, pass_ctx *c, long photons, bool caustic,
                             bool global, bool direct, vr_error *err);
void vr_run_free_maps(pass_ctx *c);

/* Sensors (render_sensors.c): their points, and the pass that reads them
 * by the scene's estimator. */
vr_status vr_sensor_points(const vr_scene *s, pass_ctx *c, vr_render_result *res, vr_error *err);
vr_status vr_sensor_pass(run *r, rscene *rs, pass_ctx *c, vr_error *err);

#endif
