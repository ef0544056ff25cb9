/* vr/comm.h over MPI when the build has it (VR_HAVE_MPI), and for one
 * process either way. */
#include "vr/comm.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef VR_HAVE_MPI
#include <mpi.h>

struct vr_comm {
  int rank, size;
};

struct vr_comm_req {
  MPI_Request r;
};

enum { TAG_RAYS = 7 };

static bool launched_by_mpirun(void) {
  return getenv("OMPI_COMM_WORLD_SIZE") || getenv("PMI_SIZE") || getenv("PMIX_RANK");
}

bool vr_comm_built_with_mpi(void) { return true; }

vr_status vr_comm_init(int *argc, char ***argv, vr_comm **out, vr_error *err) {
  *out = NULL;
  if (!launched_by_mpirun()) return VR_OK;
  int provided = 0;
  if (MPI_Init_thread(argc, argv, MPI_THREAD_MULTIPLE, &provided) != MPI_SUCCESS)
    return vr_error_set(err, VR_E_IO, "MPI: cannot start");
  if (provided < MPI_THREAD_SERIALIZED) {
    MPI_Finalize();
    return vr_error_set(err, VR_E_IO, "MPI: this MPI library gives no thread support "
                        "(MPI_THREAD_SERIALIZED is needed)");
  }
  vr_comm *c = calloc(1, sizeof *c);
  if (!c) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  MPI_Comm_rank(MPI_COMM_WORLD, &c->rank);
  MPI_Comm_size(MPI_COMM_WORLD, &c->size);
  *out = c;
  return VR_OK;
}

void vr_comm_finalize(vr_comm *c) {
  if (!c) return;
  MPI_Finalize();
  free(c);
}

void vr_comm_abort(vr_comm *c, int status) {
  if (c) MPI_Abort(MPI_COMM_WORLD, status);
  exit(status);
}

int vr_comm_rank(const vr_comm *c) { return c ? c->rank : 0; }
int vr_comm_size(const vr_comm *c) { return c ? c->size : 1; }

/* MPI counts are ints: large arrays go in pieces. */
#define PIECE ((size_t)1 << 28)

static vr_status reduce(vr_comm *c, void *v, size_t n, MPI_Datatype t, size_t size, MPI_Op op,
                        vr_error *err) {
  if (!c || c->size == 1 || !n) return VR_OK;
  for (size_t at = 0; at < n; at += PIECE) {
    size_t k = n - at < PIECE ? n - at : PIECE;
    if (MPI_Allreduce(MPI_IN_PLACE, (char *)v + at * size, (int)k, t, op, MPI_COMM_WORLD) !=
        MPI_SUCCESS)
      return vr_error_set(err, VR_E_IO, "MPI: a reduction failed");
  }
  return VR_OK;
}

vr_status vr_comm_sum_doubles(vr_comm *c, double *v, size_t n, vr_error *err) {
  return reduce(c, v, n, MPI_DOUBLE, sizeof *v, MPI_SUM, err);
}
vr_status vr_comm_sum_u64(vr_comm *c, uint64_t *v, size_t n, vr_error *err) {
  return reduce(c, v, n, MPI_UINT64_T, sizeof *v, MPI_SUM, err);
}
vr_status vr_comm_max_u64(vr_comm *c, uint64_t *v, size_t n, vr_error *err) {
  return reduce(c, v, n, MPI_UINT64_T, sizeof *v, MPI_MAX, err);
}

vr_status vr_comm_gather_bytes(vr_comm *c, const void *mine, size_t n, unsigned char **all,
                               size_t **counts, vr_error *err) {
  int R = vr_comm_size(c);
  *all = NULL;
  if (counts) *counts = NULL;
  size_t *cnt = calloc((size_t)R, sizeof *cnt);
  if (!cnt) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  cnt[vr_comm_rank(c)] = n;
  vr_status st = vr_comm_max_u64(c, (uint64_t *)cnt, (size_t)R, err);
  size_t total = 0;
  for (int r = 0; r < R; r++) total += cnt[r];
  unsigned char *buf = st ? NULL : malloc(total ? total : 1);
  if (!st && !buf) st = vr_error_set(err, VR_E_NOMEM, "out of memory for %zu bytes", total);
  if (!st && R == 1 && n) memcpy(buf, mine, n);
  /* Each rank's bytes broadcast from it, in pieces of at most PIECE. */
  size_t at = 0;
  for (int r = 0; !st && R > 1 && r < R; r++) {
    if (r == c->rank && cnt[r]) memcpy(buf + at, mine, cnt[r]);
    for (size_t off = 0; off < cnt[r]; off += PIECE) {
      size_t k = cnt[r] - off < PIECE ? cnt[r] - off : PIECE;
      if (MPI_Bcast(buf + at + off, (int)k, MPI_BYTE, r, MPI_COMM_WORLD) != MPI_SUCCESS) {
        st = vr_error_set(err, VR_E_IO, "MPI: a broadcast failed");
        break;
      }
    }
    at += cnt[r];
  }
  if (st) {
    free(buf);
    free(cnt);
    return st;
  }
  *all = buf;
  if (counts)
    *counts = cnt;
  else
    free(cnt);
  return VR_OK;
}

vr_status vr_comm_agree(vr_comm *c, vr_status mine, vr_error *err) {
  if (!c || c->size == 1) return mine;
  /* The lowest failing rank, then its message from it. */
  int me = mine ? c->rank : c->size, first = c->size;
  MPI_Allreduce(&me, &first, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  if (first == c->size) return VR_OK;
  int code = mine;
  char msg[VR_ERROR_MESSAGE_MAX];
  if (c->rank == first) snprintf(msg, sizeof msg, "%s", err ? err->message : "");
  MPI_Bcast(&code, 1, MPI_INT, first, MPI_COMM_WORLD);
  MPI_Bcast(msg, (int)sizeof msg, MPI_CHAR, first, MPI_COMM_WORLD);
  msg[sizeof msg - 1] = '\0';
  return vr_error_set(err, (vr_status)code, "rank %d: %s", first, msg);
}

vr_status vr_comm_isend(vr_comm *c, int dest, const void *buf, size_t bytes, vr_comm_req **req,
                        vr_error *err) {
  vr_comm_req *q = malloc(sizeof *q);
  if (!q) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  if (bytes > (size_t)0x7fffffff ||
      MPI_Isend(buf, (int)bytes, MPI_BYTE, dest, TAG_RAYS, MPI_COMM_WORLD, &q->r) != MPI_SUCCESS) {
    free(q);
    return vr_error_set(err, VR_E_IO, "MPI: cannot send %zu bytes to rank %d", bytes, dest);
  }
  (void)c;
  *req = q;
  return VR_OK;
}

bool vr_comm_test(vr_comm_req *req) {
  if (!req) return true;
  int done = 0;
  MPI_Test(&req->r, &done, MPI_STATUS_IGNORE);
  if (done) free(req);
  return done != 0;
}

bool vr_comm_poll(vr_comm *c, int *src, size_t *bytes) {
  (void)c;
  int flag = 0, count = 0;
  MPI_Status s;
  MPI_Iprobe(MPI_ANY_SOURCE, TAG_RAYS, MPI_COMM_WORLD, &flag, &s);
  if (!flag) return false;
  MPI_Get_count(&s, MPI_BYTE, &count);
  *src = s.MPI_SOURCE;
  *bytes = (size_t)count;
  return true;
}

vr_status vr_comm_recv(vr_comm *c, int src, void *buf, size_t bytes, vr_error *err) {
  (void)c;
  if (MPI_Recv(buf, (int)bytes, MPI_BYTE, src, TAG_RAYS, MPI_COMM_WORLD, MPI_STATUS_IGNORE) !=
      MPI_SUCCESS)
    return vr_error_set(err, VR_E_IO, "MPI: cannot receive %zu bytes from rank %d", bytes, src);
  return VR_OK;
}

vr_status vr_comm_isum_i64(vr_comm *c, const int64_t *in, int64_t *out, int n,
                           vr_comm_req **req, vr_error *err) {
  (void)c;
  vr_comm_req *q = malloc(sizeof *q);
  if (!q) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  if (MPI_Iallreduce(in, out, n, MPI_INT64_T, MPI_SUM, MPI_COMM_WORLD, &q->r) != MPI_SUCCESS) {
    free(q);
    return vr_error_set(err, VR_E_IO, "MPI: a termination wave failed to start");
  }
  *req = q;
  return VR_OK;
}

#else /* one process */

struct vr_comm {
  int unused;
};
struct vr_comm_req {
  int unused;
};

bool vr_comm_built_with_mpi(void) { return false; }

vr_status vr_comm_init(int *argc, char ***argv, vr_comm **out, vr_error *err) {
  (void)argc, (void)argv;
  *out = NULL;
  /* Launched as one of several ranks by mpirun: every copy would render
   * the whole scene and write the same files; say so instead. */
  const char *n = getenv("OMPI_COMM_WORLD_SIZE");
  if (!n) n = getenv("PMI_SIZE");
  if (n && atoi(n) > 1)
    return vr_error_set(err, VR_E_ARG, "this vr-render was built without MPI (cmake -DVR_MPI=OFF, "
                        "or no MPI found): run it without mpirun, or build it with MPI");
  return VR_OK;
}
void vr_comm_finalize(vr_comm *c) { (void)c; }
void vr_comm_abort(vr_comm *c, int status) {
  (void)c;
  exit(status);
}
int vr_comm_rank(const vr_comm *c) { return (void)c, 0; }
int vr_comm_size(const vr_comm *c) { return (void)c, 1; }
vr_status vr_comm_sum_doubles(vr_comm *c, double *v, size_t n, vr_error *err) {
  return (void)c, (void)v, (void)n, (void)err, VR_OK;
}
vr_status vr_comm_sum_u64(vr_comm *c, uint64_t *v, size_t n, vr_error *err) {
  return (void)c, (void)v, (void)n, (void)err, VR_OK;
}
vr_status vr_comm_max_u64(vr_comm *c, uint64_t *v, size_t n, vr_error *err) {
  return (void)c, (void)v, (void)n, (void)err, VR_OK;
}
vr_status vr_comm_gather_bytes(vr_comm *c, const void *mine, size_t n, unsigned char **all,
                               size_t **counts, vr_error *err) {
  (void)c;
  *all = malloc(n ? n : 1);
  if (counts) *counts = malloc(sizeof **counts);
  if (!*all || (counts && !*counts)) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  if (n) memcpy(*all, mine, n);
  if (counts) **counts = n;
  return VR_OK;
}
vr_status vr_comm_agree(vr_comm *c, vr_status mine, vr_error *err) {
  return (void)c, (void)err, mine;
}
/* With one rank the flow never sends: these are not reached. */
vr_status vr_comm_isend(vr_comm *c, int dest, const void *buf, size_t bytes, vr_comm_req **req,
                        vr_error *err) {
  (void)c, (void)dest, (void)buf, (void)bytes, (void)req;
  return vr_error_set(err, VR_E_ARG, "one process: there is no rank %d to send to", dest);
}
bool vr_comm_test(vr_comm_req *req) { return (void)req, true; }
bool vr_comm_poll(vr_comm *c, int *src, size_t *bytes) {
  return (void)c, (void)src, (void)bytes, false;
}
vr_status vr_comm_recv(vr_comm *c, int src, void *buf, size_t bytes, vr_error *err) {
  (void)c, (void)buf, (void)bytes;
  return vr_error_set(err, VR_E_ARG, "one process: there is no rank %d to receive from", src);
}
vr_status vr_comm_isum_i64(vr_comm *c, const int64_t *in, int64_t *out, int n,
                           vr_comm_req **req, vr_error *err) {
  (void)c, (void)err;
  memcpy(out, in, (size_t)n * sizeof *out);
  *req = NULL; /* done already */
  return VR_OK;
}
#endif
