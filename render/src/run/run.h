/* What every pass of vr_render_scene uses: the run (options, result, the
 * current pass's name, the ranks), logging of decisions, pass records,
 * running work units through the ray flow with their statistics, and the
 * sums over MPI ranks.  The integrators are above this; nothing here calls
 * them. */
#ifndef VR_RUN_RUN_H
#define VR_RUN_RUN_H

#include <stdbool.h>
#include <stddef.h>

#include "film/accum.h"
#include "vr/flow.h"
#include "vr/photon_set.h"
#include "vr/render.h"
#include "world/rscene.h"

/* What a ray is for (vr_ray.purpose): the statistics count them apart. */
enum {
  VR_PURPOSE_CAMERA = 0,
  VR_PURPOSE_SHADOW,
  VR_PURPOSE_PHOTON,
  VR_PURPOSE_SENSOR,
  VR_PURPOSE_UV,
  VR_PURPOSE_GATHER
};

typedef struct vr_run {
  const vr_render_options *opt;
  vr_render_result *res;
  vr_rscene *rs;
  const char *pass;
  double t_start;      /* when the render began (vr_run_now) */
  /* What the render holds besides cells, queues and state maps (photon
   * maps while a pass fills them), counted against the memory budget: the
   * integrator that holds it sets these (NULL: nothing). */
  size_t (*held)(const void *u);
  const void *held_ctx;
  /* Under a budget: the anonymous resident memory before the render
   * added to it (vr_flow_rss_bytes), which the budget is on top of. */
  long long rss_base;
  /* The camera pass's film (its accumulators), counted with the maps. */
  size_t film_bytes;
  /* Several ranks (ranks.c). */
  struct vr_comm *comm;
  int rank, nranks;
  bool failure_agreed; /* a failure all ranks know of: not agreed again */
  vr_rank_stats mine;  /* this rank's share */
} vr_run;

double vr_run_now(void);
void vr_run_say(const vr_run *r, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* Appends a pass record (NULL when VR_MAX_PASSES are taken) and logs it. */
vr_pass_record *vr_run_record(vr_run *r, const char *name, bool ran, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
/* Runs `units` work units of ops (with context ctx) through the ray flow,
 * adding its ray counts to the result (units unit_list[0 .. units) when
 * unit_list is given).  With several ranks it first agrees that every rank
 * is ready and gives the cells owners. */
vr_status vr_run_flow(vr_run *r, const vr_flow_ops *ops, void *ctx, long units, const char *name,
                      vr_error *err);
vr_status vr_run_flow_units(vr_run *r, const vr_flow_ops *ops, void *ctx, const long *unit_list,
                            long units, const char *name, vr_error *err);
/* Notes the bytes held now as a peak of the maps (a pass that builds maps
 * holds their staged and built photons at once). */
void vr_run_note_held(vr_run *r);

/* Several ranks (ranks.c; every function is collective and does nothing
 * more than return st with one rank). */
/* Every rank passes its status; all return the first failing rank's. */
vr_status vr_ranks_sync(vr_run *r, vr_status st, vr_error *err);
/* Refuses ranks that render different scenes, meshes or options. */
vr_status vr_ranks_check_scene(vr_run *r, const vr_rscene *rs, vr_error *err);
enum { RANKS_FILM = 1, RANKS_SENSORS = 2, RANKS_TEXELS = 4 };
/* Sums the accumulators' parts over the ranks (each rank adds only what
 * its own rays delivered, so the sums are the single process's values). */
vr_status vr_ranks_sum_accum(vr_run *r, vr_accum *a, unsigned parts, vr_error *err);
/* Gives every rank every photon of the n sets (staged, before the build;
 * NULL sets are skipped). */
vr_status vr_ranks_share_photons(vr_run *r, vr_photon_set *const *sets, int n, vr_error *err);
/* The result's counters summed over the ranks, each rank's share kept. */
vr_status vr_ranks_finish(vr_run *r, vr_rscene *rs, vr_render_result *res, vr_error *err);

#endif
