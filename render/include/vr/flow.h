/* The domain-decomposed ray flow (DESIGN §6.4): every ray, whatever made it
 * (camera, photon, shadow, sensor, UV pass), waits in the queue of the
 * sub-domain that holds it; P worker threads each take the cell with the
 * most pending rays, trace a batch of its rays inside that cell only, and
 * either hand a result to the integrator (a hit, an escape, an unoccluded
 * shadow ray) or pass the ray to the next cell along its path, with every
 * property unchanged and its parameter interval starting at the interface.
 *
 * The integrator is a set of callbacks: it never traces a ray itself, so it
 * does not know how many cells or threads there are, or in which process a
 * cell lives.  Work enters as numbered units (a tile of pixels, a batch of
 * photons) that workers generate when the queues run low, which bounds the
 * rays held in memory.
 *
 * Termination is counted, not guessed: a ray is in flight from its push
 * until its callback returns (after any rays it spawned were pushed), so
 * when every unit has been generated and nothing is in flight, the run is
 * over.  Rays created equals rays finished at the end, and both are in the
 * statistics.  The count is kept without a shared update per ray: each
 * worker reserves in-flight count in chunks and gives back what it did not
 * use when it runs out of work, so the shared count is never below the
 * rays really in flight (flow.c explains why that suffices).
 *
 * The image-space scheduler (vr_flow_run_image_space) runs the same
 * callbacks the classic way, for comparison: each worker claims whole units
 * and traces every ray they make to its end on a private stack, walking
 * the cells itself, with no queue and no hand-over.  vr-render uses it with
 * one cell, i.e. every thread sees the whole scene.
 *
 * Under a memory budget (vr_flow_options.memory_budget, docs/ddm.md) the
 * workers also decide which cells are loaded: a worker loads the cell with
 * the most pending rays that fits, unloading cells no worker is tracing in
 * and for which fewer rays wait; rays for a cell that is not loaded wait in
 * its queue, and queues that outgrow their share of the budget spill to an
 * unnamed file.  Without a budget every cell is loaded before the run and
 * stays loaded.  The integrators see none of this: a cell is reached only
 * through its index. */
#ifndef VR_FLOW_H
#define VR_FLOW_H

#include <stdbool.h>
#include <stdint.h>
#include "vr/domains.h"
#include "vr/error.h"

#ifdef __cplusplus
extern "C" {
#endif

#define VR_RAY_PAYLOAD 232 /* bytes of integrator state carried by each ray */
/* The most bytes a payload codec (vr_flow_ops.pack) may write for one ray. */
#define VR_RAY_PAYLOAD_WIRE_MAX (VR_RAY_PAYLOAD + 32)
/* A message of rays between ranks: an 8-byte header, then each ray in its
 * wire form (ddm/ray_wire.c): the flow's fields as varints and floats
 * where a float holds them exactly, the payload as its pass's codec writes
 * it (or its non-zero 8-byte words). */

typedef enum vr_ray_kind {
  VR_RAY_CLOSEST = 0, /* wants its closest hit (camera, bounce, photon, sensor) */
  VR_RAY_SHADOW = 1   /* wants to know whether it reaches tmax; may pass thin elements */
} vr_ray_kind;

typedef struct vr_ray {
  double org[3], dir[3];
  double tnear, tmax;      /* tnear moves to the interface on hand-over; tmax stays */
  int32_t cell;            /* set by the flow */
  uint8_t kind;            /* vr_ray_kind */
  uint8_t purpose;         /* integrator's own tag (camera, photon, ...) */
  uint16_t crossings;      /* interfaces crossed so far */
  _Alignas(8) unsigned char payload[VR_RAY_PAYLOAD];
} vr_ray;

typedef struct vr_flow_worker vr_flow_worker;

typedef struct vr_flow_ops {
  /* A closest-hit ray found hit (or escaped the scene: hit == NULL). */
  void (*closest)(void *ctx, vr_flow_worker *w, const vr_ray *r, const vr_hit *hit);
  /* A shadow ray met hit before tmax: return true to go on past it (a thin
   * element it crosses; the callback may change the payload, e.g. multiply
   * a transmittance), false if it is blocked. */
  bool (*shadow_hit)(void *ctx, vr_flow_worker *w, vr_ray *r, const vr_hit *hit);
  /* A shadow ray ended: reached tmax unblocked (reached) or was blocked. */
  void (*shadow_done)(void *ctx, vr_flow_worker *w, const vr_ray *r, bool reached);
  /* Creates the rays of work unit `unit` (0 .. units-1) by vr_flow_push. */
  void (*generate)(void *ctx, vr_flow_worker *w, long unit);
  /* Optional (NULL: a payload goes between ranks as its non-zero 8-byte
   * words, about 100 bytes for a path's).  The payload's compact form on
   * the wire:
   *   - round() is called on each ray pushed and after each shadow_hit
   *     that lets a ray go on, wherever the ray is traced, and leaves the
   *     payload in a form pack() writes in few bytes (its doubles rounded
   *     to float, say): a ray then carries the same numbers whether it
   *     stays on its rank or not, and the image does not depend on the
   *     ranks;
   *   - pack() writes at most VR_RAY_PAYLOAD_WIRE_MAX bytes and returns
   *     how many; it must be exact for any payload, rounded or not;
   *   - unpack() reads at most avail bytes, writes the whole payload and
   *     returns the bytes read, or 0 if they are not a payload.  Every
   *     field comes back bit for bit (padding between fields as zeros). */
  void (*round)(const void *ctx, unsigned char *payload);
  size_t (*pack)(const void *ctx, const unsigned char *payload, unsigned char *out);
  size_t (*unpack)(const void *ctx, const unsigned char *in, size_t avail,
                   unsigned char *payload);
} vr_flow_ops;

/* Counted by each worker on its own and summed when the run ends. */
typedef struct vr_flow_stats {
  uint64_t created, finished, crossings;
  uint64_t closest, shadow;           /* rays created of each kind */
  uint64_t traversals;                /* cell intersection queries */
  uint64_t by_purpose[8];             /* rays created per purpose tag (0..7) */
  uint64_t spilled;                   /* rays written to a queue's spill file */
  /* Several ranks (this rank's share; created and finished balance only
   * over all ranks, since a ray may be created on one and end on another). */
  uint64_t sent, received;            /* rays handed to and from other ranks */
  uint64_t messages, bytes_sent;      /* messages this rank sent, and their bytes */
  uint64_t waves;                     /* termination waves run */
  uint64_t credit_waits;              /* times an outbox waited for credit from its rank */
  uint64_t ray_messages, ray_bytes;   /* the messages of rays among them, and their bytes */
  uint64_t peak_uncredited;           /* the most rays received from one rank and not yet credited */
  double idle_seconds;                /* worker time with no ray to trace, summed over threads */
  bool other_rank_failed;             /* the run stopped because another rank failed */
  bool failure_shared;                /* the failure returned is every rank's, agreed already */
  uint64_t skipped;                   /* crossings into cells the segment could not hit in */
  size_t peak_queue_bytes;            /* rays held in memory by queues and push buffers */
  size_t peak_spill_bytes;            /* rays waiting on disk */
  size_t peak_uncounted_bytes;        /* budget: the most resident memory above the base and the counted bytes */
} vr_flow_stats;

/* This process's resident memory now, in bytes, from /proc/self/statm (0
 * if unknown): all of it, or only the anonymous pages (resident minus
 * file-backed and shared pages). */
long long vr_flow_rss_bytes(bool anon_only);

/* What a run's rays did, for a model of the flow (bench/sim): filled by
 * the workers when vr_flow_options.profile is given.  The caller
 * allocates it for the cells of d (vr_flow_profile_create). */
typedef struct vr_flow_profile {
  int ncells;
  /* (ncells + 1) x ncells: rays that cell a sent into cell b, by a new ray
   * (a child, a shadow ray) or a crossing; row ncells: rays generated by
   * the units (camera rays, photons) into cell b. */
  _Atomic uint64_t *moves;
  _Atomic uint64_t *rays[2];  /* per cell: rays traced there, closest (0) and shadow (1) */
  _Atomic uint64_t *ns[2];    /* per cell: their tracing time, in nanoseconds */
  _Atomic uint64_t gen_ns;    /* time the units took to generate their rays */
  _Atomic uint64_t units;     /* units generated */
} vr_flow_profile;

vr_flow_profile *vr_flow_profile_create(int ncells);
void vr_flow_profile_destroy(vr_flow_profile *p);

typedef struct vr_flow_options {
  int threads;            /* worker threads, >= 1 (the calling thread is one) */
  /* Bytes the run may hold in loaded cells (vr_domains_cell_bytes), ray
   * queues and what `held` reports; 0: no budget, every cell loaded. */
  size_t memory_budget;
  /* Bytes held besides, which may grow during the run (photon maps being
   * filled, state maps); NULL: none.  Called under the scheduler's lock. */
  size_t (*held)(void *hctx);
  void *hctx;
  /* The process's anonymous resident memory before the render added any
   * (vr_flow_rss_bytes(true), taken once per render), or 0.  Under a
   * budget, what the process holds beyond it and beyond what the run
   * counts (the film's pages as they are written, allocator slack, other
   * libraries' buffers) is taken from the cells' share, so that the
   * resident memory stays within the budget, not only the counted bytes. */
  long long rss_base;
  const char *spill_dir;  /* where queues spill (NULL: $TMPDIR, else /tmp) */
  long max_pending;       /* rays waiting, with a unit's, above which no unit is generated
                             (0: default) */
  /* Several ranks (docs/ddm.md, "Ranks"): comm, and the rays a message
   * carries at most (0: 256).  Each rank generates the units whose index
   * modulo the number of ranks is its rank; any rank may load any cell,
   * and a ray goes to a rank that holds its cell (ddm/flow_net.c).  NULL
   * comm: one process. */
  struct vr_comm *comm;
  int send_batch;
  int send_credit;        /* rays sent to a rank before it credits them back (0: 4096) */
  /* The units of this run: unit_list[0 .. units) when given (a part of a
   * pass), else 0 .. units - 1. */
  const long *unit_list;
  /* Run in image space (vr_flow_run_image_space) instead: every cell is
   * loaded, no ray moves between ranks; with several ranks each traces
   * its share of the units (the paper's image-space splitting). */
  bool image_space;
  /* If given (one per cell), each cell's tracing time is added to it, in
   * nanoseconds: the measured cost that decides which rank owns a cell. */
  uint64_t *cell_ns;
  /* If given: each ray's cell, kind, time and where its children and
   * crossings go are recorded (a clock read per ray), and rays wait in the
   * next cell's queue even when it is loaded, so that each cell's time is
   * its own. */
  vr_flow_profile *profile;
  void (*progress)(void *pctx, long done, long units); /* from one thread at a time; may be NULL */
  void *pctx;
} vr_flow_options;

void vr_flow_options_default(vr_flow_options *o);

/* Runs units 0..units-1 through the cells of d.  Errors: VR_E_ARG for a
 * bad option, or a budget too small for the largest cell (the message
 * names the smallest cell that does not fit and the budget needed), also
 * when what `held` reports grows past that point during the run;
 * VR_E_NOMEM when a queue can neither grow nor spill; a cell that cannot
 * be loaded fails the run with its loader's error. */
vr_status vr_flow_run_with(vr_domains *d, const vr_flow_ops *ops, void *ctx, long units,
                           const vr_flow_options *o, vr_flow_stats *stats, vr_error *err);

/* The same without a budget, on `threads` worker threads. */
vr_status vr_flow_run(vr_domains *d, const vr_flow_ops *ops, void *ctx, long units,
                      int threads, void (*progress)(void *pctx, long done, long units),
                      void *pctx, vr_flow_stats *stats, vr_error *err);

/* The same run scheduled in image space: workers claim units from a shared
 * counter, and the worker that generated a unit traces all its rays (and
 * the rays they spawn) depth first on a stack of its own until none is
 * left, walking from cell to cell itself when d has more than one.  Same
 * callbacks, same arguments, same statistics (crossings count the cells
 * walked into).  Each worker's stack holds at most the rays of one unit
 * plus path depth times the rays a vertex spawns. */
vr_status vr_flow_run_image_space(vr_domains *d, const vr_flow_ops *ops, void *ctx,
                                  long units, int threads,
                                  void (*progress)(void *pctx, long done, long units),
                                  void *pctx, vr_flow_stats *stats, vr_error *err);

/* Queues a new ray (from a callback or generate): into its cell's queue in
 * the queued flow, onto the calling worker's own stack in image space.
 * tnear is where it starts (usually 0, with the origin already offset from
 * any surface).  The ray's origin, direction, tnear and tmax are rounded
 * to float (the precision Embree traces in) and its payload by the ops'
 * round(), so that a ray is the same on every rank (its wire form is
 * exact and short). */
void vr_flow_push(vr_flow_worker *w, const vr_ray *r);

/* Index of the calling worker (0 .. threads-1), for per-thread scratch. */
int vr_flow_worker_index(const vr_flow_worker *w);

/* Image work units: square tiles of VR_FLOW_TILE x VR_FLOW_TILE pixels,
 * numbered row by row from the top left, the last column and row clipped
 * at the image's edges.  vr_flow_tile gives unit's pixels [x0, x1) x
 * [y0, y1).  Tiles rather than rows keep a unit's rays close together in
 * the scene and its units the same size whatever the image's shape. */
#define VR_FLOW_TILE 16
long vr_flow_tiles(int width, int height);
void vr_flow_tile(int width, int height, long unit, int *x0, int *y0, int *x1, int *y1);

#ifdef __cplusplus
}
#endif
#endif
