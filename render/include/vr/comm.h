/* The processes (MPI ranks) that render one scene together, behind a small
 * interface so that the renderer builds and runs without MPI.
 *
 * vr_comm_init starts MPI when the program was launched by mpirun (Open MPI
 * or any launcher that sets PMI/PMIx variables) and the build has MPI;
 * otherwise, and for a NULL communicator, there is one rank and every
 * collective below leaves its data as it is.
 *
 * Collectives must be called by every rank, in the same order.  The point
 * to point calls and vr_comm_isum_i64 are for the ray flow's communication
 * thread (flow_mpi.c): MPI is initialised with at least
 * MPI_THREAD_SERIALIZED, and the renderer never calls MPI from two threads
 * at once. */
#ifndef VR_COMM_H
#define VR_COMM_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include "vr/error.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vr_comm vr_comm;

/* *out is NULL (one process) unless MPI was started. */
vr_status vr_comm_init(int *argc, char ***argv, vr_comm **out, vr_error *err);
void vr_comm_finalize(vr_comm *c);
/* Ends every rank of the job at once, with a non-zero status. */
void vr_comm_abort(vr_comm *c, int status);
bool vr_comm_built_with_mpi(void);

int vr_comm_rank(const vr_comm *c); /* 0 for NULL */
int vr_comm_size(const vr_comm *c); /* 1 for NULL */

/* In place, every rank gets the element-wise sum (or maximum). */
vr_status vr_comm_sum_doubles(vr_comm *c, double *v, size_t n, vr_error *err);
vr_status vr_comm_sum_u64(vr_comm *c, uint64_t *v, size_t n, vr_error *err);
vr_status vr_comm_max_u64(vr_comm *c, uint64_t *v, size_t n, vr_error *err);
/* Every rank's n bytes, concatenated in rank order, to every rank: *all
 * (malloc'd) and, when counts is not NULL, *counts (malloc'd, size ranks). */
vr_status vr_comm_gather_bytes(vr_comm *c, const void *mine, size_t n, unsigned char **all,
                               size_t **counts, vr_error *err);
/* Every rank passes its own status and error; every rank returns VR_OK if
 * all were VR_OK, else the status and the message of the lowest failing
 * rank (prefixed "rank K: " when there are several ranks). */
vr_status vr_comm_agree(vr_comm *c, vr_status mine, vr_error *err);

/* --- For the ray flow's communication thread ------------------------- */

typedef struct vr_comm_req vr_comm_req;
/* Starts sending bytes to rank dest; buf must stay untouched until
 * vr_comm_test says the request is done. */
vr_status vr_comm_isend(vr_comm *c, int dest, const void *buf, size_t bytes, vr_comm_req **req,
                        vr_error *err);
/* Whether the request is done (then freed). */
bool vr_comm_test(vr_comm_req *req);
/* A message waiting to be received: its source and size; false if none. */
bool vr_comm_poll(vr_comm *c, int *src, size_t *bytes);
vr_status vr_comm_recv(vr_comm *c, int src, void *buf, size_t bytes, vr_error *err);
/* Starts an element-wise sum of n int64 over all ranks into out (in and out
 * must stay untouched until the request is done). */
vr_status vr_comm_isum_i64(vr_comm *c, const int64_t *in, int64_t *out, int n,
                           vr_comm_req **req, vr_error *err);

#ifdef __cplusplus
}
#endif
#endif
