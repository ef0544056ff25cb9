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
  /* Several ranks (render_ranks.c). */
  struct vr_comm *comm;
  int rank, nranks;
  bool failure_agreed; /* a failure all ranks know of: not agreed again */
  vr_rank_stats mine;  /* this rank's share */
} run;

double vr_run_now(void);
void vr_run_say(const run *r, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* Appends a pass record (NULL when VR_MAX_PASSES are taken) and logs it. */
vr_pass_record *vr_run_record(run *r, const char *name, bool ran, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
/* Runs `units` work units of ops through the ray flow, adding its ray counts
 * to the result (units unit_list[0 .. units) when unit_list is given).
 * With several ranks it first agrees that every rank is ready and gives
 * the cells owners. */
vr_status vr_run_flow(run *r, rscene *rs, const vr_flow_ops *ops, pass_ctx *c, long units,
                      const char *name, vr_error *err);
vr_status vr_run_flow_units(run *r, rscene *rs, const vr_flow_ops *ops, pass_ctx *c,
                            const long *unit_list, long units, const char *name, vr_error *err);
/* Traces `photons` photons into c's maps: global (and, with direct, the
 * direct map) and/or caustic, then builds them and counts their photons. */
vr_status vr_run_photon_pass(run *r, rscene *rs, pass_ctx *c, long photons, bool caustic,
                             bool global, bool direct, vr_error *err);
void vr_run_free_maps(pass_ctx *c);

/* Several ranks (render_ranks.c; every function is collective and does
 * nothing more than return st with one rank). */
/* Every rank passes its status; all return the first failing rank's. */
vr_status vr_ranks_sync(run *r, vr_status st, vr_error *err);
/* Refuses ranks that render different scenes, meshes or options. */
vr_status vr_ranks_check_scene(run *r, const rscene *rs, vr_error *err);
/* Gives every cell an owner: longest first to the least loaded rank, by
 * the time each cell took in the last run (summed over ranks), or by its
 * bytes before anything was measured. */
vr_status vr_ranks_assign(run *r, rscene *rs, vr_error *err);
enum { RANKS_FILM = 1, RANKS_SENSORS = 2, RANKS_TEXELS = 4 };
/* Sums the accumulators' parts over the ranks (each rank adds only what
 * its own rays delivered, so the sums are the single process's values). */
vr_status vr_ranks_sum_accum(run *r, accum *a, unsigned parts, vr_error *err);
/* Gives every rank every photon of c's maps (staged, before the build). */
vr_status vr_ranks_share_photons(run *r, pass_ctx *c, vr_error *err);
/* The result's counters summed over the ranks, each rank's share kept. */
vr_status vr_ranks_finish(run *r, rscene *rs, vr_render_result *res, vr_error *err);

/* Sensors (render_sensors.c): their points, and the pass that reads them
 * by the scene's estimator. */
vr_status vr_sensor_points(const vr_scene *s, pass_ctx *c, vr_render_result *res, vr_error *err);
vr_status vr_sensor_pass(run *r, rscene *rs, pass_ctx *c, vr_error *err);

#endif
