/* A discrete-event model of vr-render's ray flow over ranks and threads
 * (render/src/ddm/flow*.c), driven by a recorded flow profile
 * (sim_profile.h): what the paper's Table 1 would be on machines this one
 * cannot be.  It follows the scheduler as coded:
 *   - a rank generates a unit while its rays (at most half the cap) fit
 *     below max_pending with those waiting and being generated, else
 *     traces a batch of the loaded cell with the most waiting rays, else
 *     sends the rays of a cell it does not hold to a rank that holds it
 *     (or the cell's home rank) unless the cell is hot here, else loads
 *     the cell, else loads ahead a cell no rank holds, else waits;
 *   - a cell is hot on a rank past 1024 of its rays and an eighth of them,
 *     or past a load's cost (a byte of the cell per 64 rays);
 *   - one rank without a budget loads every cell before the passes;
 *   - under a budget, a load first unloads the loaded cells with the
 *     fewest waiting rays, none being traced;
 *   - outboxes leave at send_batch rays or after 200 us; a message costs
 *     latency + bytes / bandwidth (inside a node or between nodes), and
 *     its rays cost the sender and the receiver ray_overhead / 2 each;
 *   - a rank's news of what it loads reaches the others after a latency;
 *   - the workers of a node share its cores (more workers than cores run
 *     slower in proportion), and each busy core slows the others' loads and
 *     tracing by load_contention and trace_contention (the memory bus).
 * What a traced batch sends on is the profile's mean per ray, rounded at
 * random to whole rays (a seeded generator: the same run, the same time).
 * Left out: the credit between ranks (no sender waited for credit in the
 * runs it was checked against), spilling to disk, and the photon passes'
 * gathers (the profile's passes are run one after the other). */
#ifndef BENCH_SIM_FLOW_H
#define BENCH_SIM_FLOW_H

#include <stdbool.h>

#include "sim_profile.h"

typedef struct sim_config {
  int nodes, cores;        /* the machine */
  int ranks, threads;      /* ranks (dealt over the nodes in turn) and workers a rank */
  bool image_space;        /* every rank holds the whole scene (profile at S = 1) */
  double budget;           /* bytes of cells a rank may hold (0: no budget) */
  double latency, bandwidth;         /* between nodes: s, bytes/s */
  double node_latency, node_bandwidth; /* inside a node */
  double wire_bytes;       /* bytes a ray takes in a message */
  double ray_overhead;     /* CPU seconds per ray sent, sender and receiver together */
  double load_contention, trace_contention;
  /* A load on a rank of T threads runs min(T, cores)^load_scaling times as
   * fast (Embree builds on the rank's threads; threads beyond the node's
   * cores add nothing), using as many cores (at most the node's). */
  double load_scaling;
  double prepare_s;        /* seconds before the passes (reading the scene, the cache) */
  unsigned long long seed;
} sim_config;

void sim_config_default(sim_config *c);

typedef struct sim_result {
  double seconds;          /* the render: prepare, loads, passes */
  double loads;            /* cell loads over all ranks */
  double rays_sent;
  bool refused;            /* the scene does not fit (image space under a budget) */
} sim_result;

/* Runs the model; false if it cannot (out of memory). */
bool sim_run(const sim_profile *p, const sim_config *c, sim_result *r);

#endif
