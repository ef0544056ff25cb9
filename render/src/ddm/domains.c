/* Sub-domains (vr/domains.h): the geometry cache opened and checked (or
 * built), the kd-tree walk of a ray through the cells, and cells loaded
 * and unloaded on demand with exact accounting of what they hold.
 *
 * Memory.  A loaded cell holds its payload (the cache file's arrays, mapped
 * from the file and used in place) and its Embree scene.  Embree reports every allocation of the
 * device to on_memory, which keeps the device's running total; builds and
 * releases happen one at a time under build_lock, so the change of the
 * total across one build is that cell's, exactly.  The cache folder is
 * locked (flock) exclusively while it is checked or built and shared while
 * it is in use, so another process never rebuilds it under a render. */
#define _GNU_SOURCE /* mkdtemp */
#include "vr/domains.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include <embree3/rtcore.h>

#include "geometry/cache_build.h"
#include "geometry/cache_format.h"
#include "geometry/cache_key.h"
#include "geometry/cell_data.h"

#define DIRMAX 4000
#define PATHMAX 4200

typedef struct vr_dcell {
  const vr_cell_meta *meta;
  void *payload;
  vr_cell_view view;
  RTCScene scene;
  _Atomic bool loaded;
  bool loading;
  size_t embree;   /* what its scene holds (measured at the last load) */
  size_t peak;     /* Embree's most during that build */
  double load_seconds; /* the last load's */
} vr_dcell;

struct vr_domains {
  vr_cache_manifest *m;
  vr_dcell *cells;
  RTCDevice device;
  char dir[DIRMAX + 64];      /* the folder of this S's cells */
  char root[DIRMAX];          /* the cache folder */
  bool private_root;          /* made here; removed by destroy */
  int lock_fd;
  void (*log)(void *, const char *);
  void *user;
  /* Embree's running total and the most it reached during the current build. */
  _Atomic long long embree_now, build_peak;
  pthread_mutex_t build_lock; /* builds, releases and the counters below */
  pthread_cond_t loaded_cv;
  size_t geometry_now, peak_geometry, peak_embree, peak_cells;
  uint64_t loads, unloads, bytes_read;
  double load_seconds;
  bool cache_built;
  char cache_reason[1024];
  double cache_seconds;
};

static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void say(const vr_domains *d, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void say(const vr_domains *d, const char *fmt, ...) {
  if (!d->log) return;
  char line[1024];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(line, sizeof line, fmt, ap);
  va_end(ap);
  d->log(d->user, line);
}

void vr_domains_options_default(vr_domains_options *o) {
  memset(o, 0, sizeof *o);
  o->subdomains = 1;
  o->threads = 1;
  o->mesh_cache_bytes = (size_t)256 << 20;
}

/* ---- Embree's memory ---- */

static bool on_memory(void *user, ssize_t bytes, bool post) {
  (void)post;
  vr_domains *d = user;
  long long v = atomic_fetch_add(&d->embree_now, (long long)bytes) + (long long)bytes;
  long long p = atomic_load(&d->build_peak);
  while (v > p && !atomic_compare_exchange_weak(&d->build_peak, &p, v)) {
  }
  return true;
}

/* Builds v's scene under build_lock (held by the caller) and measures it. */
static vr_status build_measured(vr_domains *d, const vr_cell_view *v, RTCScene *scene,
                                size_t *retained, size_t *peak, vr_error *err) {
  long long before = atomic_load(&d->embree_now);
  atomic_store(&d->build_peak, before);
  vr_status st = vr_cell_scene_build(d->device, v, scene, err);
  long long after = atomic_load(&d->embree_now), top = atomic_load(&d->build_peak);
  *retained = after > before ? (size_t)(after - before) : 0;
  *peak = top > before ? (size_t)(top - before) : 0;
  return st;
}

static vr_status measure(void *ctx, const void *payload, const vr_cell_meta *meta,
                         uint64_t *retained, uint64_t *peak, vr_error *err) {
  vr_domains *d = ctx;
  vr_cell_view v;
  vr_cell_view_of(payload, meta, &v);
  RTCScene scene = NULL;
  size_t r = 0, p = 0;
  pthread_mutex_lock(&d->build_lock);
  vr_status st = build_measured(d, &v, &scene, &r, &p, err);
  if (scene) rtcReleaseScene(scene);
  pthread_mutex_unlock(&d->build_lock);
  *retained = r;
  *peak = p;
  return st;
}

/* ---- the cache folder ---- */

static vr_status make_dirs(const char *path, vr_error *err) {
  char p[DIRMAX];
  snprintf(p, sizeof p, "%s", path);
  for (char *s = p + 1; *s; s++)
    if (*s == '/') {
      *s = '\0';
      if (mkdir(p, 0755) != 0 && errno != EEXIST)
        return vr_error_set(err, VR_E_IO, "cache folder %s: cannot create %s: %s", path, p,
                            strerror(errno));
      *s = '/';
    }
  if (mkdir(p, 0755) != 0 && errno != EEXIST)
    return vr_error_set(err, VR_E_IO, "cache folder %s: cannot create: %s", path, strerror(errno));
  return VR_OK;
}

/* Removes a private cache: its S folders' files, the folders, lock files. */
static void remove_private(const char *root) {
  DIR *d = opendir(root);
  if (!d) return;
  struct dirent *e;
  char p[PATHMAX];
  while ((e = readdir(d))) {
    if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
    snprintf(p, sizeof p, "%s/%s", root, e->d_name);
    DIR *sub = opendir(p);
    if (sub) {
      struct dirent *f;
      char q[PATHMAX + 256];
      while ((f = readdir(sub)))
        if (strcmp(f->d_name, ".") && strcmp(f->d_name, "..")) {
          snprintf(q, sizeof q, "%s/%s", p, f->d_name);
          unlink(q);
        }
      closedir(sub);
      rmdir(p);
    } else {
      unlink(p);
    }
  }
  closedir(d);
  rmdir(root);
}

/* Checks the cache in d->dir against key; NULL manifest and a reason when
 * it must be built. */
static vr_cache_manifest *check_cache(vr_domains *d, const uint8_t key[32], int S, char *why,
                                      size_t nwhy) {
  char path[PATHMAX];
  snprintf(path, sizeof path, "%s/manifest.vrm", d->dir);
  vr_cache_manifest *m = NULL;
  vr_error e = {0};
  vr_status st = vr_cache_manifest_read(path, &m, &e);
  if (st == VR_E_IO) {
    snprintf(why, nwhy, "no cache yet");
    return NULL;
  }
  if (st) {
    snprintf(why, nwhy, "%s", e.message);
    return NULL;
  }
  if (memcmp(m->key, key, 32) || m->ncells != S) {
    snprintf(why, nwhy, "the geometry changed since the cache was built");
    vr_cache_manifest_free(m);
    return NULL;
  }
  for (int c = 0; c < m->ncells; c++) {
    snprintf(path, sizeof path, "%s/cell-%05d.vrc", d->dir, c);
    if (vr_cell_file_check(path, (uint32_t)c, key, &m->cells[c], &e)) {
      snprintf(why, nwhy, "%s", e.message);
      vr_cache_manifest_free(m);
      return NULL;
    }
  }
  return m;
}

static vr_status open_common(vr_domains *d, const vr_domains_options *o, const vr_scene *scene,
                             const vr_geometry *g, const uint8_t key[32], vr_error *err) {
  int S = o->subdomains;
  d->log = o->log;
  d->user = o->user;
  d->lock_fd = -1;
  pthread_mutex_init(&d->build_lock, NULL);
  pthread_cond_init(&d->loaded_cv, NULL);
  char cfg[64];
  snprintf(cfg, sizeof cfg, "threads=%d,verbose=0", o->threads > 0 ? o->threads : 1);
  d->device = rtcNewDevice(cfg);
  if (!d->device)
    return vr_error_set(err, VR_E_NUMERIC, "Embree: cannot create a device (error %d)",
                        (int)rtcGetDeviceError(NULL));
  rtcSetDeviceMemoryMonitorFunction(d->device, on_memory, d);
  /* The folder. */
  if (o->cache_dir) {
    if (strlen(o->cache_dir) + 16 >= DIRMAX)
      return vr_error_set(err, VR_E_ARG, "cache folder %s: name too long", o->cache_dir);
    snprintf(d->root, sizeof d->root, "%s", o->cache_dir);
    vr_status st = make_dirs(d->root, err);
    if (st) return st;
  } else {
    const char *tmp = getenv("TMPDIR");
    snprintf(d->root, sizeof d->root, "%s/vr-cache-XXXXXX", tmp && *tmp ? tmp : "/tmp");
    if (!mkdtemp(d->root))
      return vr_error_set(err, VR_E_IO, "cannot create a temporary cache folder %s: %s", d->root,
                          strerror(errno));
    d->private_root = true;
  }
  snprintf(d->dir, sizeof d->dir, "%s/S%d", d->root, S);
  char lock[PATHMAX];
  snprintf(lock, sizeof lock, "%s/S%d.lock", d->root, S);
  d->lock_fd = open(lock, O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (d->lock_fd < 0)
    return vr_error_set(err, VR_E_IO, "cache folder %s: cannot write in it (%s): give a writable "
                        "one with --cache", d->root, strerror(errno));
  /* Check under a shared lock, so that renders of the same geometry (MPI
   * ranks on one machine among them) never wait for each other.  Only a
   * build takes the lock exclusively, and it never waits for it while the
   * cache may be valid: a render holding the shared lock keeps it until it
   * ends, and a rank waiting for it would wait for the others forever. */
  double t0 = now();
  char why[1024];
  bool said = false;
  for (;;) {
    while (flock(d->lock_fd, LOCK_SH) != 0)
      if (errno != EINTR)
        return vr_error_set(err, VR_E_IO, "cache %s: cannot lock: %s", lock, strerror(errno));
    d->m = check_cache(d, key, S, why, sizeof why);
    if (d->m) break;
    flock(d->lock_fd, LOCK_UN);
    if (flock(d->lock_fd, LOCK_EX | LOCK_NB) == 0) {
      /* Ours: check again (another render may have just built it). */
      d->m = check_cache(d, key, S, why, sizeof why);
      if (!d->m) {
        snprintf(d->cache_reason, sizeof d->cache_reason, "%s", why);
        if (!d->private_root) say(d, "cache: building %s (%s)", d->dir, why);
        vr_cache_build b = {.dir = d->dir, .key = key, .subdomains = S, .scene = scene,
                            .geometry = g, .mesh_cache_bytes = o->mesh_cache_bytes,
                            .measure = measure, .measure_ctx = d, .log = o->log, .user = o->user};
        vr_status st = vr_cache_build_run(&b, &d->m, err);
        if (st) return st;
        d->cache_built = true;
      }
      /* Shared from now on: other renders may use it, nobody may rebuild it. */
      flock(d->lock_fd, LOCK_SH);
      break;
    }
    if (errno != EWOULDBLOCK && errno != EINTR)
      return vr_error_set(err, VR_E_IO, "cache %s: cannot lock: %s", lock, strerror(errno));
    /* Someone builds it, or renders with another geometry: wait and look again. */
    if (!said && !d->private_root) {
      say(d, "cache: %s is being built or used by another render; waiting", d->dir);
      said = true;
    }
    nanosleep(&(struct timespec){0, 50000000}, NULL);
  }
  if (!d->cache_built) {
    snprintf(d->cache_reason, sizeof d->cache_reason, "reused");
    say(d, "cache: %s holds the %d sub-domain%s of this geometry, checked in %.2f s", d->dir, S,
        S == 1 ? "" : "s", now() - t0);
  }
  d->cache_seconds = now() - t0;
  d->cells = calloc((size_t)d->m->ncells, sizeof *d->cells);
  if (!d->cells) return vr_error_set(err, VR_E_NOMEM, "sub-domains: out of memory");
  for (int c = 0; c < d->m->ncells; c++) {
    d->cells[c].meta = &d->m->cells[c];
    d->cells[c].embree = (size_t)d->m->cells[c].embree_bytes;
    d->cells[c].peak = (size_t)d->m->cells[c].embree_peak;
  }
  return VR_OK;
}

vr_status vr_domains_open(const vr_scene *scene, const vr_domains_options *o, vr_domains **out,
                          vr_error *err) {
  *out = NULL;
  if (!scene || !o) return vr_error_set(err, VR_E_ARG, "vr_domains_open: NULL argument");
  if (o->subdomains < 1 || o->subdomains > VR_MAX_SUBDOMAINS)
    return vr_error_set(err, VR_E_ARG, "sub-domains: S = %d, expected 1 to %d", o->subdomains,
                        VR_MAX_SUBDOMAINS);
  uint8_t key[32];
  vr_status st = vr_cache_key_scene(scene, o->subdomains, key, err);
  if (st) return st;
  vr_domains *d = calloc(1, sizeof *d);
  if (!d) return vr_error_set(err, VR_E_NOMEM, "sub-domains: out of memory");
  st = open_common(d, o, scene, NULL, key, err);
  if (st) {
    vr_domains_destroy(d);
    return st;
  }
  *out = d;
  return VR_OK;
}

vr_status vr_domains_build(const vr_geometry *g, int S, vr_domains **out, vr_error *err) {
  *out = NULL;
  if (S < 1 || S > VR_MAX_SUBDOMAINS)
    return vr_error_set(err, VR_E_ARG, "sub-domains: S = %d, expected 1 to %d", S, VR_MAX_SUBDOMAINS);
  uint8_t key[32];
  vr_cache_key_geometry(g, S, key);
  vr_domains_options o;
  vr_domains_options_default(&o);
  o.subdomains = S;
  vr_domains *d = calloc(1, sizeof *d);
  if (!d) return vr_error_set(err, VR_E_NOMEM, "sub-domains: out of memory");
  vr_status st = open_common(d, &o, NULL, g, key, err);
  if (!st) st = vr_domains_load_all(d, err);
  if (st) {
    vr_domains_destroy(d);
    return st;
  }
  *out = d;
  return VR_OK;
}

void vr_domains_destroy(vr_domains *d) {
  if (!d) return;
  for (int c = 0; d->cells && c < d->m->ncells; c++) {
    if (d->cells[c].scene) rtcReleaseScene(d->cells[c].scene);
    vr_cell_file_release(d->cells[c].payload, d->cells[c].meta);
  }
  free(d->cells);
  if (d->device) rtcReleaseDevice(d->device);
  vr_cache_manifest_free(d->m);
  if (d->lock_fd >= 0) close(d->lock_fd); /* releases the lock */
  if (d->private_root) remove_private(d->root);
  pthread_mutex_destroy(&d->build_lock);
  pthread_cond_destroy(&d->loaded_cv);
  free(d);
}

/* ---- what the manifest knows ---- */

int vr_domains_count(const vr_domains *d) { return d->m->ncells; }

size_t vr_domains_cell_primitives(const vr_domains *d, int cell) {
  const vr_cell_meta *m = &d->m->cells[cell];
  return (size_t)(m->ntris + m->nspheres);
}

void vr_domains_cell_bounds(const vr_domains *d, int cell, double lo[3], double hi[3]) {
  memcpy(lo, d->m->cells[cell].lo, 3 * sizeof *lo);
  memcpy(hi, d->m->cells[cell].hi, 3 * sizeof *hi);
}

const uint32_t *vr_domains_cell_objects(const vr_domains *d, int cell, size_t *n) {
  *n = d->m->cells[cell].nobjects;
  return d->m->cells[cell].objects;
}

const vr_scene_tables *vr_domains_tables(const vr_domains *d) { return &d->m->tables; }

void vr_domains_key(const vr_domains *d, uint8_t key[32]) { memcpy(key, d->m->key, 32); }

int vr_domains_locate(const vr_domains *d, const double org[3], const double dir[3], double t,
                      double *t_exit) {
  const vr_kd_node *nodes = d->m->nodes;
  double te = INFINITY;
  int n = 0;
  while (nodes[n].axis >= 0) {
    const vr_kd_node *k = &nodes[n];
    int a = k->axis, side;
    if (dir[a] == 0.0) {
      side = org[a] >= k->split; /* in the plane: the upper side, always */
    } else {
      double ts = (k->split - org[a]) / dir[a];
      if (ts > t) {
        side = dir[a] < 0; /* not yet crossed: on the side it comes from */
        if (ts < te) te = ts;
      } else {
        side = dir[a] > 0; /* crossed at or before t */
      }
    }
    n = k->child[side];
  }
  *t_exit = te;
  return nodes[n].cell;
}

bool vr_domains_may_hit(const vr_domains *d, int cell, const double org[3], const double dir[3],
                        double t0, double t1) {
  const vr_cell_meta *m = &d->m->cells[cell];
  if (!(m->glo[0] <= m->ghi[0])) return false; /* no primitive */
  /* Widen the box by more than Embree's float rounding of the ray and of
   * the vertices can move a hit: 1e-5 of the largest coordinate involved. */
  double big = 1.0;
  for (int a = 0; a < 3; a++)
    big = fmax(big, fmax(fabs(org[a]), fmax(fabs(m->glo[a]), fabs(m->ghi[a]))));
  double pad = 1e-5 * big;
  double lo = t0 - 1e-6 * fabs(t0), hi = t1 + 1e-6 * fabs(t1);
  for (int a = 0; a < 3; a++) {
    double bl = m->glo[a] - pad, bh = m->ghi[a] + pad;
    if (dir[a] == 0.0) {
      if (org[a] < bl || org[a] > bh) return false;
      continue;
    }
    double ta = (bl - org[a]) / dir[a], tb = (bh - org[a]) / dir[a];
    if (ta > tb) {
      double t = ta;
      ta = tb;
      tb = t;
    }
    if (ta > lo) lo = ta;
    if (tb < hi) hi = tb;
    if (lo > hi) return false;
  }
  return true;
}

bool vr_domains_intersect(const vr_domains *d, int cell, const double org[3], const double dir[3],
                          double tnear, double tfar, vr_hit *hit) {
  const vr_dcell *c = &d->cells[cell];
  if (!vr_cell_intersect(c->scene, &c->view, org, dir, tnear, tfar, hit)) return false;
  hit->cell = cell;
  return true;
}

/* ---- loading ---- */

size_t vr_domains_cell_bytes(const vr_domains *d, int cell) {
  return (size_t)d->cells[cell].meta->payload_bytes + d->cells[cell].embree;
}

size_t vr_domains_cell_load_peak(const vr_domains *d, int cell) {
  return (size_t)d->cells[cell].meta->payload_bytes + d->cells[cell].peak;
}

bool vr_domains_loaded(const vr_domains *d, int cell) {
  return atomic_load(&((vr_domains *)d)->cells[cell].loaded);
}

static void note_peaks(vr_domains *d) {
  size_t e = (size_t)(atomic_load(&d->embree_now) > 0 ? atomic_load(&d->embree_now) : 0);
  if (d->geometry_now > d->peak_geometry) d->peak_geometry = d->geometry_now;
  if (e > d->peak_embree) d->peak_embree = e;
  if (d->geometry_now + e > d->peak_cells) d->peak_cells = d->geometry_now + e;
}

vr_status vr_domains_load(vr_domains *d, int cell, vr_error *err) {
  if (cell < 0 || cell >= d->m->ncells)
    return vr_error_set(err, VR_E_ARG, "sub-domain %d out of range", cell);
  vr_dcell *c = &d->cells[cell];
  pthread_mutex_lock(&d->build_lock);
  while (c->loading) pthread_cond_wait(&d->loaded_cv, &d->build_lock);
  if (atomic_load(&c->loaded)) {
    pthread_mutex_unlock(&d->build_lock);
    return VR_OK;
  }
  c->loading = true;
  pthread_mutex_unlock(&d->build_lock);

  /* Reading and checking run outside the lock: other loads go on. */
  double t0 = now();
  char path[PATHMAX];
  snprintf(path, sizeof path, "%s/cell-%05d.vrc", d->dir, cell);
  void *payload = NULL;
  vr_status st = vr_cell_file_read(path, (uint32_t)cell, d->m->key, c->meta, &payload, err);
  if (st == VR_E_PARSE || st == VR_E_IO)
    vr_error_prefix(err, "sub-domain %d changed on disk during the render: ", cell);

  pthread_mutex_lock(&d->build_lock);
  if (!st) {
    vr_cell_view_of(payload, c->meta, &c->view);
    size_t retained = 0, peak = 0;
    st = build_measured(d, &c->view, &c->scene, &retained, &peak, err);
    if (!st) {
      c->payload = payload;
      c->embree = retained;
      if (peak > c->peak) c->peak = peak;
      d->geometry_now += (size_t)c->meta->payload_bytes;
      d->loads++;
      d->bytes_read += VR_CELL_HEADER + c->meta->payload_bytes;
      c->load_seconds = now() - t0;
      atomic_store(&c->loaded, true);
    } else {
      vr_error_prefix(err, "sub-domain %d: ", cell);
      memset(&c->view, 0, sizeof c->view); /* it pointed into the payload */
      vr_cell_file_release(payload, c->meta);
    }
  }
  d->load_seconds += now() - t0;
  note_peaks(d);
  c->loading = false;
  pthread_cond_broadcast(&d->loaded_cv);
  pthread_mutex_unlock(&d->build_lock);
  return st;
}

double vr_domains_cell_load_seconds(const vr_domains *d, int cell) {
  return d->cells[cell].load_seconds;
}

void vr_domains_unload(vr_domains *d, int cell) {
  vr_dcell *c = &d->cells[cell];
  pthread_mutex_lock(&d->build_lock);
  while (c->loading) pthread_cond_wait(&d->loaded_cv, &d->build_lock);
  if (atomic_load(&c->loaded)) {
    atomic_store(&c->loaded, false);
    if (c->scene) rtcReleaseScene(c->scene);
    c->scene = NULL;
    vr_cell_file_release(c->payload, c->meta);
    c->payload = NULL;
    memset(&c->view, 0, sizeof c->view);
    d->geometry_now -= (size_t)c->meta->payload_bytes;
    d->unloads++;
  }
  pthread_mutex_unlock(&d->build_lock);
}

vr_status vr_domains_load_all(vr_domains *d, vr_error *err) {
  for (int c = 0; c < d->m->ncells; c++) {
    vr_status st = vr_domains_load(d, c, err);
    if (st) return st;
  }
  return VR_OK;
}

void vr_domains_get_stats(const vr_domains *d, vr_domains_stats *out) {
  vr_domains *w = (vr_domains *)d; /* the lock is not part of the value */
  memset(out, 0, sizeof *out);
  pthread_mutex_lock(&w->build_lock);
  out->loads = d->loads;
  out->unloads = d->unloads;
  out->bytes_read = d->bytes_read;
  out->load_seconds = d->load_seconds;
  out->geometry_bytes = d->geometry_now;
  long long e = atomic_load(&w->embree_now);
  out->embree_bytes = e > 0 ? (size_t)e : 0;
  out->peak_geometry = d->peak_geometry;
  out->peak_embree = d->peak_embree;
  out->peak_cells = d->peak_cells;
  pthread_mutex_unlock(&w->build_lock);
  out->cache_built = d->cache_built;
  snprintf(out->cache_reason, sizeof out->cache_reason, "%s", d->cache_reason);
  out->cache_seconds = d->cache_seconds;
  for (int c = 0; c < d->m->ncells; c++) out->cache_bytes += d->m->cells[c].payload_bytes;
}
