/* What the three parts of the ray flow share (flow.c: workers, tracing,
 * termination; flow_queue.c: per-cell queues that spill to disk;
 * flow_sched.c: which cell a worker takes, and loading and unloading cells
 * under a memory budget).  Private to render/. */
#ifndef VR_FLOW_INTERNAL_H
#define VR_FLOW_INTERNAL_H

#include <pthread.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stddef.h>

#include "vr/flow.h"

/* Rays a worker gathers per cell before handing them to the cell's queue
 * in one locked step (fewer under a tight budget: flow.batch). */
#define VR_FLOW_BATCH 256
/* Generate more work only while a unit's rays fit with those waiting in the
 * queues below this (flow.c, queued_worker): it bounds memory whatever the
 * image size and the spp. */
#define VR_FLOW_LOW_WATER 65536
/* Under a memory budget, work is generated until this many rays wait
 * (in memory or spilled) when the loaded cells run dry: the more rays wait
 * for a cell, the more each load of it serves. */
#define VR_FLOW_BUDGET_PENDING (1L << 20)
/* Several ranks: a cell is hot on a rank once it took more than this many
 * of its rays and either an eighth of them or more than a load costs: the
 * rank loads it too when it has the room, instead of sending its rays to
 * a rank that holds it (ownership follows the work). */
#define VR_FLOW_ADOPT_RAYS 1024
/* Under a budget: anonymous resident memory the process may hold beyond
 * what the run counts before the cells give way (docs/ddm.md, "The memory
 * budget": resident memory <= memory at the start + budget + this). */
#define VR_FLOW_RSS_ALLOWANCE (16LL << 20)
/* Rays of in-flight count a worker reserves at a time. */
#define VR_FLOW_CREDIT 1024
#define VR_FLOW_LINE 64

/* Queues hold rays in blocks of f->batch rays from one pool shared by all
 * cells, so memory freed by one cell's queue serves the next (no queue
 * keeps a large array it no longer needs). */
typedef struct vr_flow_block {
  struct vr_flow_block *next;
  int n;
  _Alignas(8) vr_ray rays[]; /* f->batch */
} vr_flow_block;

typedef struct vr_flow_queue {
  _Alignas(VR_FLOW_LINE) pthread_mutex_t lock; /* one cache line per queue: no false sharing */
  vr_flow_block *top;   /* the newest block; a stack of blocks */
  /* Rays spilled to an unnamed file, used as a stack of records. */
  int spill_fd;
  size_t spilled;
  _Atomic long pending; /* n + spilled, readable without the lock to choose a cell */
} vr_flow_queue;

typedef struct vr_flow_net vr_flow_net;

typedef struct vr_flow {
  vr_domains *d;
  const vr_flow_ops *ops;
  void *ctx;
  int ncells, threads, batch;
  bool image_space;
  vr_flow_queue *q;
  /* The block pool: blocks made so far (never above max_blocks under a
   * budget) and those free for reuse. */
  pthread_mutex_t pool_lock;
  vr_flow_block *free_blocks;
  size_t nblocks, max_blocks, block_bytes;
  long units, max_pending;     /* units: this rank's share */
  long all_units;              /* of the whole run, over all ranks */
  const long *unit_list;
  int rank, nranks;
  vr_flow_net *net;            /* messages to and from other ranks, or NULL */
  /* Several ranks: which ranks hold each cell (ncells x nranks, as told;
   * this rank's own entries are its own), the rays this rank sent for each
   * cell, and how many it sends before it loads the cell itself. */
  _Atomic unsigned char *held_by;
  _Atomic long *routed;
  long adopt_rays;
  /* Budget: the process's anonymous resident memory before the render
   * (0: not watched), and the most found beyond it and the counted bytes
   * (under sched_lock). */
  long long rss_base;
  size_t peak_uncounted;
  size_t rss_extra;     /* the last reading of it */
  double rss_read_at;   /* when (monotonic seconds) */
  int *prefetch_left;          /* scratch of the scheduler: per rank, cells no rank holds */
  _Atomic long put_rays;       /* rays this rank handed to queues or other ranks in this run */
  _Atomic long outbox_rays;    /* rays in the outboxes, waiting to be sent */
  _Atomic long unit_rays;      /* the most rays one generated unit has made */
  _Atomic long generating;     /* rays reserved by the units being generated */
  /* Cells are loaded when rays need them, not all before the run (several
   * ranks without a budget: each loads what its rays need). */
  bool lazy;
  /* Rays that reach a loaded cell are traced on at once, not queued (no
   * budget: a loaded cell stays loaded all the run). */
  bool walk_loaded;
  vr_flow_profile *profile;   /* NULL: not recorded */
  _Atomic int terminated;      /* several ranks: the termination waves say so */
  /* Idle workers sleep here until rays are queued (or 1 ms passes). */
  pthread_mutex_t idle_lock;
  pthread_cond_t idle_cv;
  _Atomic int sleepers;
  _Atomic unsigned long long *cell_ns;
  long low_water;             /* budget: generate while loaded cells wait for fewer rays */
  pthread_mutex_t progress_lock;
  void (*progress)(void *, long, long);
  void *pctx;
  /* The memory budget (0: none, every cell loaded all along). */
  size_t budget, cells_cap, queue_cap, largest;
  size_t (*held)(void *);
  void *hctx;
  const char *spill_dir;
  pthread_mutex_t sched_lock; /* residency decisions, pins and reserved */
  int *pins;                  /* workers tracing in each cell */
  _Atomic unsigned long long *traced; /* rays taken from each cell's queue in this run */
  bool *loading;
  size_t reserved;            /* bytes of the loaded and loading cells */
  _Atomic long long queue_bytes, peak_queue_bytes, spill_bytes, peak_spill_bytes;
  /* The shared counters, each in its own cache line. */
  _Alignas(VR_FLOW_LINE) _Atomic long next_unit;
  _Alignas(VR_FLOW_LINE) _Atomic long done_units;
  _Alignas(VR_FLOW_LINE) _Atomic long queued;
  /* Rays in flight plus the workers' unused reservations: never below the
   * true number of rays in flight (see reserve in flow.c). */
  _Alignas(VR_FLOW_LINE) _Atomic long in_flight;
  _Alignas(VR_FLOW_LINE) _Atomic int failed;
  vr_error fail_err; /* the first failure's message (under sched_lock) */
} vr_flow;

struct vr_flow_worker {
  _Alignas(VR_FLOW_LINE) vr_flow *f; /* workers sit in separate cache lines */
  int index;
  bool oom;
  long credit;        /* reserved in f->in_flight and not yet used; >= 0 */
  vr_flow_stats st;   /* this worker's share of the statistics */
  double loads_since_idle; /* seconds of loads since it last had nothing to trace */
  int cur;            /* profile: the cell whose ray it traces, or -1 (generating) */
  /* Queued flow: f->batch rays per cell waiting to go to the cell's queue. */
  vr_ray *out;
  int *nout;
  /* Image space: the private depth-first stack. */
  vr_ray *stack;
  size_t top, cap;
};

/* flow_queue.c */
void vr_flow_queue_init(vr_flow_queue *q);
void vr_flow_queue_free(vr_flow *f, vr_flow_queue *q);
void vr_flow_pool_free(vr_flow *f);
/* Adds n rays to cell c's queue, spilling to disk when the queues' memory
 * would pass the budget's share; false (nothing added) when neither memory
 * nor disk can take them. */
bool vr_flow_queue_put(vr_flow *f, int c, const vr_ray *rays, int n, vr_flow_worker *w);
/* Takes up to f->batch rays of cell c (from memory, else from its spill). */
int vr_flow_queue_take(vr_flow *f, int c, vr_ray *batch, vr_flow_worker *w);
void vr_flow_note_bytes(_Atomic long long *now, _Atomic long long *peak, long long delta);
/* Wakes the idle workers (new rays, or the end). */
void vr_flow_wake(vr_flow *f);

/* flow_net.c: rays to and from other ranks, and termination over all of
 * them (only when there are several ranks). */
vr_status vr_flow_net_start(vr_flow *f, struct vr_comm *comm, int send_batch, int send_credit,
                            vr_error *err);
/* Puts n rays for cells rank dest holds in its outbox. */
bool vr_flow_net_put(vr_flow *f, int dest, const vr_ray *rays, int n);
/* The rank n rays for cell c go to: this one, or one that holds c. */
int vr_flow_route(vr_flow *f, int c, int n);
/* A rank other than this one that holds cell c (the one with the most
 * credit), or -1. */
int vr_flow_holder(vr_flow *f, int c);
/* The rank that loads cell c when no rank holds it and it is hot nowhere:
 * cold cells are shared out among the ranks, not loaded by all. */
int vr_flow_home(const vr_flow *f, int c);
/* Sends what this rank has to tell the others (credit, what it loads). */
void vr_flow_net_flush(vr_flow *f);
/* Whether cell c is hot here: it took more than VR_FLOW_ADOPT_RAYS of this
 * rank's rays (counting those waiting) and more than an eighth of them
 * (1/N of them on N > 8 ranks) or more than loading it costs. */
bool vr_flow_hot(vr_flow *f, int c);
/* Sends the rays waiting here for cell c to rank dest; whether any went. */
bool vr_flow_net_forward(vr_flow *f, int c, int dest);
/* Tells the other ranks that cell c is now loaded (or being loaded) here,
 * or not. */
void vr_flow_net_resident(vr_flow *f, int c, bool loaded);
/* One round of sending, receiving and termination waves, if no other
 * worker is doing one; whether anything happened. */
bool vr_flow_net_progress(vr_flow *f);
/* After the workers: runs the waves to their end (a failure here is told
 * to the others), waits for the sends, adds the statistics. */
void vr_flow_net_stop(vr_flow *f, vr_flow_stats *stats);

/* flow_sched.c */
/* Checks that the budget can hold the largest cell next to the queues and
 * what f->held reports, and splits it; the message names the smallest cell
 * that does not fit. */
vr_status vr_flow_budget_plan(vr_flow *f, vr_error *err);
/* A cell with pending rays for the worker to trace, loaded and pinned
 * (loading and unloading cells as the budget requires), or -1. */
int vr_flow_sched_pick(vr_flow *f, vr_flow_worker *w);
void vr_flow_sched_release(vr_flow *f, int c);
/* Whether cell c would fit beside what is loaded now, without unloading
 * anything (always without a budget). */
bool vr_flow_sched_room(vr_flow *f, int c);
/* Rays waiting for loaded cells.  Under a budget, new work is generated
 * only while these run low (and all waiting rays stay under max_pending):
 * rays the loaded cells can take are traced before more are made, so rays
 * pile up (and spill) only for cells that are not loaded. */
long vr_flow_loaded_pending(vr_flow *f);
void vr_flow_fail(vr_flow *f, const vr_error *e);

#endif
