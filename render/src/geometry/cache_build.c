/* The geometry cache builder (cache_build.h).
 *
 * Pass 1 reads the scene one object at a time (vr_geometry_build_range, a
 * mesh read once however often it is placed), appends each object's arrays
 * to a spill file, keeps a sample of primitive bounds, and fills the
 * replicated tables (bounds, areas, rect frames, emitters).  The kd-tree
 * of cells is then chosen on the sample (cache_split.c).  Pass 2 deals the
 * spill file out: each primitive goes, with its vertices renumbered, to
 * every cell whose box it touches.  Pass 3 turns each cell's part into its
 * cache file and measures what Embree keeps for it. */
#include "geometry/cache_build.h"
#include "geometry/cache_tables.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "geometry/cache_dirs.h"
#include "geometry/cache_key.h"
#include "geometry/cache_split.h"
#include "geometry/mesh_cache.h"
#include "vr/hash64.h"

#define DIRMAX 4000  /* longest cache folder name */
#define PATHMAX 4200 /* a folder name and a file name in it */
#define SAMPLE_SEED 0x5CA1AB1Eull

typedef vr_cache_sample sample;

/* A cell's part while pass 2 fills it: bytes waiting to be appended to its
 * part file, the counts so far and the objects seen. */
typedef struct vr_build_part {
  unsigned char *buf;
  size_t len, cap;
  uint64_t nverts, ntris, nspheres;
  uint32_t flags;
  uint32_t *objects;
  size_t nobjects, capobjects;
  double glo[3], ghi[3]; /* bounds of the primitives dealt to it */
} vr_build_part;

typedef struct vr_mesh_builder {
  const vr_cache_build *b;
  vr_error *err;
  char tmp[DIRMAX + 64];
  FILE *soup;
  uint64_t nprims;
  sample *heap;
  size_t nheap;
  vr_scene_tables t;
  size_t emit_cap;
  bool any;
  double lo[3], hi[3];
  vr_cache_cells cells; /* the kd-tree */
  vr_build_part *parts;
  size_t flush_at;
} vr_mesh_builder;

static void say(const vr_mesh_builder *B, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void say(const vr_mesh_builder *B, const char *fmt, ...) {
  if (!B->b->log) return;
  char line[512];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(line, sizeof line, fmt, ap);
  va_end(ap);
  B->b->log(B->b->user, line);
}

static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static vr_status nomem(vr_mesh_builder *B) {
  return vr_error_set(B->err, VR_E_NOMEM, "geometry cache: out of memory");
}

static vr_status io_fail(vr_mesh_builder *B, const char *what, const char *path) {
  return vr_error_set(B->err, VR_E_IO, "geometry cache: cannot %s %s: %s", what, path,
                      strerror(errno));
}

/* ---- pass 1: objects to the spill file, the sample, the tables ---- */

static bool wr(vr_mesh_builder *B, const void *p, size_t n) {
  return n == 0 || fwrite(p, 1, n, B->soup) == n;
}

typedef struct vr_build_chunk_head {
  uint64_t nverts, ntris, nspheres;
  uint32_t flags, pad;
} vr_build_chunk_head;

static void sample_add(vr_mesh_builder *B, const double lo[3], const double hi[3]) {
  uint64_t i = B->nprims++;
  uint64_t h = vr_hash64_buffer(&i, sizeof i, SAMPLE_SEED);
  sample s = {h, {(float)lo[0], (float)lo[1], (float)lo[2]}, {(float)hi[0], (float)hi[1], (float)hi[2]}};
  /* The VR_CACHE_SAMPLE smallest hashes, in a max-heap. */
  sample *v = B->heap;
  size_t j;
  if (B->nheap < VR_CACHE_SAMPLE) {
    j = B->nheap++;
    v[j] = s;
    while (j > 0 && v[(j - 1) / 2].h < v[j].h) {
      sample t = v[j];
      v[j] = v[(j - 1) / 2];
      v[(j - 1) / 2] = t;
      j = (j - 1) / 2;
    }
    return;
  }
  if (h >= v[0].h) return;
  v[0] = s;
  size_t n = B->nheap;
  j = 0;
  for (;;) {
    size_t l = 2 * j + 1, r = l + 1, big = j;
    if (l < n && v[l].h > v[big].h) big = l;
    if (r < n && v[r].h > v[big].h) big = r;
    if (big == j) break;
    sample t = v[j];
    v[j] = v[big];
    v[big] = t;
    j = big;
  }
}

/* One chunk (objects [first, last) of g) into the spill file, the sample
 * and the tables. */
static vr_status take_chunk(vr_mesh_builder *B, const vr_geometry *g, size_t first, size_t last) {
  uint32_t flags = (g->vnormals ? VR_CELL_NORMALS : 0u) | (g->tri_rgb ? VR_CELL_COLOURS : 0u);
  vr_build_chunk_head h = {g->nverts, g->ntris, g->nspheres, flags, 0};
  bool ok = wr(B, &h, sizeof h) && wr(B, g->verts, g->nverts * 12) &&
            (!g->vnormals || wr(B, g->vnormals, g->nverts * 12)) && wr(B, g->tris, g->ntris * 12) &&
            wr(B, g->tri_object, g->ntris * 4) && wr(B, g->tri_uv, g->ntris * 24) &&
            (!g->tri_rgb || wr(B, g->tri_rgb, g->ntris * 9)) &&
            wr(B, g->spheres, g->nspheres * 32) && wr(B, g->sphere_object, g->nspheres * 4);
  if (!ok) return io_fail(B, "write", B->tmp);
  double lo[3], hi[3];
  for (size_t i = 0; i < g->ntris; i++) {
    vr_cache_tri_box(g->verts, g->tris + 3 * i, lo, hi);
    sample_add(B, lo, hi);
  }
  for (size_t i = 0; i < g->nspheres; i++) {
    vr_cache_sphere_box(g->spheres + 4 * i, lo, hi);
    sample_add(B, lo, hi);
  }
  if (g->ntris || g->nspheres) {
    for (int a = 0; a < 3; a++) {
      if (!B->any || g->bmin[a] < B->lo[a]) B->lo[a] = g->bmin[a];
      if (!B->any || g->bmax[a] > B->hi[a]) B->hi[a] = g->bmax[a];
    }
    B->any = true;
  }
  return vr_cache_tables_take(&B->t, &B->emit_cap, g, B->b->scene, first, last, B->err);
}

static vr_status pass1(vr_mesh_builder *B) {
  const vr_cache_build *b = B->b;
  size_t nobj = b->scene ? b->scene->nobjects : b->geometry->nobjects;
  B->heap = malloc(VR_CACHE_SAMPLE * sizeof *B->heap);
  if (!vr_cache_tables_alloc(&B->t, nobj) || !B->heap) return nomem(B);
  char path[PATHMAX];
  snprintf(path, sizeof path, "%s/spill", B->tmp);
  if (!(B->soup = fopen(path, "wb"))) return io_fail(B, "create", path);
  vr_status st = VR_OK;
  if (!b->scene) {
    st = take_chunk(B, b->geometry, 0, nobj);
  } else {
    vr_mesh_cache *mc = vr_mesh_cache_create(b->mesh_cache_bytes);
    if (!mc) st = nomem(B);
    double t0 = now(), last_say = t0;
    for (size_t o = 0; !st && o < nobj; o++) {
      vr_geometry *g = NULL;
      st = vr_geometry_build_range(b->scene, o, o + 1, mc, &g, B->err);
      if (!st) st = take_chunk(B, g, o, o + 1);
      vr_geometry_destroy(g);
      if (now() - last_say > 5.0) {
        last_say = now();
        say(B, "cache: read %zu of %zu objects, %llu primitives so far", o + 1, nobj,
            (unsigned long long)B->nprims);
      }
    }
    vr_mesh_cache_destroy(mc);
  }
  if (fclose(B->soup) != 0 && !st) st = io_fail(B, "write", path);
  B->soup = NULL;
  if (st) return st;
  if (B->any) {
    memcpy(B->t.bmin, B->lo, sizeof B->t.bmin);
    memcpy(B->t.bmax, B->hi, sizeof B->t.bmax);
  }
  return VR_OK;
}

/* ---- pass 2: the spill file dealt out to the cells ---- */

static vr_status flush_part(vr_mesh_builder *B, int c) {
  vr_build_part *p = &B->parts[c];
  if (!p->len) return VR_OK;
  char path[PATHMAX];
  snprintf(path, sizeof path, "%s/part-%05d", B->tmp, c);
  int fd = open(path, O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (fd < 0) return io_fail(B, "create", path);
  size_t done = 0;
  while (done < p->len) {
    ssize_t w = write(fd, p->buf + done, p->len - done);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) {
      if (w == 0) errno = ENOSPC;
      close(fd);
      return io_fail(B, "write", path);
    }
    done += (size_t)w;
  }
  if (close(fd) != 0) return io_fail(B, "write", path);
  p->len = 0;
  return VR_OK;
}

static bool part_put(vr_build_part *p, const void *v, size_t n) {
  if (p->len + n > p->cap) {
    size_t cap = p->cap ? p->cap : 65536;
    while (cap < p->len + n) cap *= 2;
    unsigned char *b = realloc(p->buf, cap);
    if (!b) return false;
    p->buf = b;
    p->cap = cap;
  }
  if (n) memcpy(p->buf + p->len, v, n);
  p->len += n;
  return true;
}

static bool part_object(vr_build_part *p, uint32_t o) {
  if (p->nobjects && p->objects[p->nobjects - 1] == o) return true;
  if (p->nobjects == p->capobjects) {
    size_t cap = p->capobjects ? 2 * p->capobjects : 16;
    uint32_t *v = realloc(p->objects, cap * sizeof *v);
    if (!v) return false;
    p->objects = v;
    p->capobjects = cap;
  }
  p->objects[p->nobjects++] = o;
  return true;
}

/* The cells whose boxes a primitive's box touches, by the kd-tree: below a
 * split if it reaches down to it, above if it reaches up to it. */
static int cells_of(const vr_mesh_builder *B, const double lo[3], const double hi[3], int *out) {
  int stack[64], top = 0, n = 0;
  stack[top++] = 0;
  while (top) {
    const vr_kd_node *k = &B->cells.nodes[stack[--top]];
    if (k->axis < 0) {
      out[n++] = k->cell;
      continue;
    }
    if (lo[k->axis] <= k->split) stack[top++] = k->child[0];
    if (hi[k->axis] >= k->split) stack[top++] = k->child[1];
  }
  return n;
}

typedef struct vr_build_chunk {
  vr_build_chunk_head h;
  float *verts, *normals, *uv;
  uint8_t *rgb;
  uint32_t *tris, *objects, *sphere_objects;
  double *spheres;
} vr_build_chunk;

static void chunk_free(vr_build_chunk *k) {
  free(k->verts);
  free(k->normals);
  free(k->uv);
  free(k->rgb);
  free(k->tris);
  free(k->objects);
  free(k->sphere_objects);
  free(k->spheres);
  memset(k, 0, sizeof *k);
}

static bool rd(FILE *f, void *p, size_t n) { return n == 0 || fread(p, 1, n, f) == n; }

/* Reads one chunk; *eof when the file ends cleanly before it. */
static vr_status chunk_read(vr_mesh_builder *B, FILE *f, const char *path, vr_build_chunk *k, bool *eof) {
  memset(k, 0, sizeof *k);
  size_t got = fread(&k->h, 1, sizeof k->h, f);
  *eof = got == 0 && feof(f);
  if (*eof) return VR_OK;
  const vr_build_chunk_head *h = &k->h;
  size_t nv = h->nverts, nt = h->ntris, ns = h->nspheres;
  k->verts = malloc(nv * 12 + 16);
  k->normals = (h->flags & VR_CELL_NORMALS) ? malloc(nv * 12 + 1) : NULL;
  k->tris = malloc(nt * 12 + 1);
  k->objects = malloc(nt * 4 + 1);
  k->uv = malloc(nt * 24 + 1);
  k->rgb = (h->flags & VR_CELL_COLOURS) ? malloc(nt * 9 + 1) : NULL;
  k->spheres = malloc(ns * 32 + 1);
  k->sphere_objects = malloc(ns * 4 + 1);
  if (!k->verts || ((h->flags & VR_CELL_NORMALS) && !k->normals) || !k->tris || !k->objects ||
      !k->uv || ((h->flags & VR_CELL_COLOURS) && !k->rgb) || !k->spheres || !k->sphere_objects)
    return nomem(B);
  bool ok = got == sizeof k->h && rd(f, k->verts, nv * 12) &&
            (!k->normals || rd(f, k->normals, nv * 12)) && rd(f, k->tris, nt * 12) &&
            rd(f, k->objects, nt * 4) && rd(f, k->uv, nt * 24) &&
            (!k->rgb || rd(f, k->rgb, nt * 9)) && rd(f, k->spheres, ns * 32) &&
            rd(f, k->sphere_objects, ns * 4);
  if (!ok) return vr_error_set(B->err, VR_E_IO, "geometry cache: %s: cut short", path);
  return VR_OK;
}

/* One chunk's primitives to the parts of the cells they touch. */
static vr_status deal(vr_mesh_builder *B, const vr_build_chunk *k, uint32_t *mark, uint32_t *local,
                      uint32_t *gen) {
  const vr_build_chunk_head *h = &k->h;
  int S = B->cells.ncells;
  /* (cell, primitive) pairs grouped by cell with a counting sort. */
  size_t cap = h->ntris + h->nspheres + 16, npairs = 0;
  uint32_t *pc = malloc(cap * sizeof *pc), *pp = malloc(cap * sizeof *pp);
  size_t *count = calloc((size_t)S + 1, sizeof *count);
  int *cells = malloc((size_t)S * sizeof *cells);
  vr_status st = VR_OK;
  if (!pc || !pp || !count || !cells) st = nomem(B);
  double lo[3], hi[3];
  for (size_t i = 0; !st && i < h->ntris + h->nspheres; i++) {
    if (i < h->ntris)
      vr_cache_tri_box(k->verts, k->tris + 3 * i, lo, hi);
    else
      vr_cache_sphere_box(k->spheres + 4 * (i - h->ntris), lo, hi);
    int n = cells_of(B, lo, hi, cells);
    for (int j = 0; j < n; j++) {
      vr_build_part *p = &B->parts[cells[j]];
      for (int a = 0; a < 3; a++) {
        if (lo[a] < p->glo[a]) p->glo[a] = lo[a];
        if (hi[a] > p->ghi[a]) p->ghi[a] = hi[a];
      }
    }
    if (npairs + (size_t)n > cap) {
      while (npairs + (size_t)n > cap) cap *= 2;
      uint32_t *a = realloc(pc, cap * sizeof *a);
      if (a) pc = a;
      uint32_t *b = a ? realloc(pp, cap * sizeof *b) : NULL;
      if (b) pp = b;
      if (!a || !b) {
        st = nomem(B);
        break;
      }
    }
    for (int j = 0; j < n; j++) {
      pc[npairs] = (uint32_t)cells[j];
      pp[npairs++] = (uint32_t)i;
      count[cells[j] + 1]++;
    }
  }
  uint32_t *sorted = st ? NULL : malloc((npairs + 1) * sizeof *sorted);
  if (!st && !sorted) st = nomem(B);
  if (!st) {
    for (int c = 0; c < S; c++) count[c + 1] += count[c];
    size_t *at = malloc(((size_t)S + 1) * sizeof *at);
    if (!at) st = nomem(B);
    else {
      memcpy(at, count, ((size_t)S + 1) * sizeof *at);
      /* Stable: each cell's primitives stay in the order of the file. */
      for (size_t i = 0; i < npairs; i++) sorted[at[pc[i]]++] = pp[i];
      free(at);
    }
  }
  bool normals = (h->flags & VR_CELL_NORMALS) != 0;
  uint32_t colours = h->flags & VR_CELL_COLOURS;
  for (int c = 0; !st && c < S; c++) {
    size_t a = count[c], z = count[c + 1];
    if (a == z) continue;
    vr_build_part *p = &B->parts[c];
    /* Vertices renumbered in the order the cell's triangles first use them. */
    uint32_t g = ++*gen, nnew = 0;
    size_t ntri = 0, nsph = 0;
    for (size_t i = a; i < z; i++) {
      uint32_t q = sorted[i];
      if (q >= h->ntris) {
        nsph++;
        continue;
      }
      ntri++;
      for (int j = 0; j < 3; j++) {
        uint32_t v = k->tris[3 * (size_t)q + j];
        if (mark[v] != g) {
          mark[v] = g;
          local[v] = nnew++;
        }
      }
    }
    vr_build_chunk_head ph = {nnew, ntri, nsph, (normals ? VR_CELL_NORMALS : 0u) | colours, 0};
    bool ok = part_put(p, &ph, sizeof ph);
    /* New vertices in their local order: walk the triangles again. */
    uint32_t written = 0;
    for (size_t i = a; ok && i < z && written < nnew; i++) {
      uint32_t q = sorted[i];
      if (q >= h->ntris) continue;
      for (int j = 0; ok && j < 3; j++) {
        uint32_t v = k->tris[3 * (size_t)q + j];
        if (local[v] == written) {
          ok = part_put(p, k->verts + 3 * (size_t)v, 12);
          written++;
        }
      }
    }
    if (normals) {
      written = 0;
      for (size_t i = a; ok && i < z && written < nnew; i++) {
        uint32_t q = sorted[i];
        if (q >= h->ntris) continue;
        for (int j = 0; ok && j < 3; j++) {
          uint32_t v = k->tris[3 * (size_t)q + j];
          if (local[v] == written) {
            ok = part_put(p, k->normals + 3 * (size_t)v, 12);
            written++;
          }
        }
      }
    }
    for (size_t i = a; ok && i < z; i++) {
      uint32_t q = sorted[i];
      if (q >= h->ntris) continue;
      uint32_t t[3];
      for (int j = 0; j < 3; j++) t[j] = local[k->tris[3 * (size_t)q + j]];
      ok = part_put(p, t, sizeof t);
    }
    for (size_t i = a; ok && i < z; i++)
      if (sorted[i] < h->ntris) ok = part_put(p, &k->objects[sorted[i]], 4) && part_object(p, k->objects[sorted[i]]);
    for (size_t i = a; ok && i < z; i++)
      if (sorted[i] < h->ntris) ok = part_put(p, k->uv + 6 * (size_t)sorted[i], 24);
    for (size_t i = a; ok && colours && i < z; i++)
      if (sorted[i] < h->ntris) ok = part_put(p, k->rgb + 9 * (size_t)sorted[i], 9);
    for (size_t i = a; ok && i < z; i++)
      if (sorted[i] >= h->ntris) ok = part_put(p, k->spheres + 4 * (size_t)(sorted[i] - h->ntris), 32);
    for (size_t i = a; ok && i < z; i++)
      if (sorted[i] >= h->ntris) {
        uint32_t o = k->sphere_objects[sorted[i] - h->ntris];
        ok = part_put(p, &o, 4) && part_object(p, o);
      }
    if (!ok) {
      st = nomem(B);
      break;
    }
    p->nverts += nnew;
    p->ntris += ntri;
    p->nspheres += nsph;
    if (normals) p->flags |= VR_CELL_NORMALS;
    p->flags |= colours;
    if (p->len >= B->flush_at) st = flush_part(B, c);
  }
  free(pc);
  free(pp);
  free(count);
  free(cells);
  free(sorted);
  return st;
}

static vr_status pass2(vr_mesh_builder *B) {
  char path[PATHMAX];
  snprintf(path, sizeof path, "%s/spill", B->tmp);
  FILE *f = fopen(path, "rb");
  if (!f) return io_fail(B, "read", path);
  B->parts = calloc((size_t)B->cells.ncells, sizeof *B->parts);
  for (int c = 0; B->parts && c < B->cells.ncells; c++)
    for (int a = 0; a < 3; a++) {
      B->parts[c].glo[a] = INFINITY;
      B->parts[c].ghi[a] = -INFINITY;
    }
  /* Part buffers share about 64 MiB, at least 64 KiB each. */
  B->flush_at = ((size_t)64 << 20) / (size_t)B->cells.ncells;
  if (B->flush_at < 65536) B->flush_at = 65536;
  vr_status st = B->parts ? VR_OK : nomem(B);
  uint32_t *mark = NULL, *local = NULL, gen = 0;
  size_t vcap = 0;
  for (;;) {
    if (st) break;
    vr_build_chunk k;
    bool eof;
    st = chunk_read(B, f, path, &k, &eof);
    if (!st && !eof && k.h.nverts > vcap) {
      free(mark);
      free(local);
      vcap = k.h.nverts;
      mark = calloc(vcap, sizeof *mark);
      local = malloc(vcap * sizeof *local);
      gen = 0;
      if (!mark || !local) st = nomem(B);
    }
    if (!st && !eof) st = deal(B, &k, mark, local, &gen);
    chunk_free(&k);
    if (eof) break;
  }
  fclose(f);
  unlink(path);
  free(mark);
  free(local);
  for (int c = 0; !st && c < B->cells.ncells; c++) {
    st = flush_part(B, c);
    free(B->parts[c].buf); /* on disk now: pass 3 reads it back cell by cell */
    B->parts[c].buf = NULL;
    B->parts[c].cap = 0;
  }
  return st;
}

/* ---- pass 3: each part to its cell file ---- */

static int cmp_u32(const void *a, const void *b) {
  uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
  return (x > y) - (x < y);
}

static vr_status assemble(vr_mesh_builder *B, int c, vr_cell_meta *meta) {
  vr_build_part *p = &B->parts[c];
  meta->nverts = p->nverts;
  meta->ntris = p->ntris;
  meta->nspheres = p->nspheres;
  meta->flags = p->flags;
  memcpy(meta->lo, B->cells.lo[c], sizeof meta->lo);
  memcpy(meta->hi, B->cells.hi[c], sizeof meta->hi);
  /* What a ray in the cell can meet: its primitives' bounds, within its
   * box (a primitive shared with a neighbour reaches past it). */
  for (int a = 0; a < 3; a++) {
    meta->glo[a] = fmax(p->glo[a], meta->lo[a]);
    meta->ghi[a] = fmin(p->ghi[a], meta->hi[a]);
  }
  if (p->nobjects) qsort(p->objects, p->nobjects, sizeof *p->objects, cmp_u32);
  size_t u = 0;
  for (size_t i = 0; i < p->nobjects; i++)
    if (!u || p->objects[i] != p->objects[u - 1]) p->objects[u++] = p->objects[i];
  meta->nobjects = (uint32_t)u;
  meta->objects = malloc((u + 1) * sizeof *meta->objects);
  if (!meta->objects) return nomem(B);
  if (u) memcpy(meta->objects, p->objects, u * sizeof *meta->objects);
  vr_cell_layout L;
  if (!vr_cell_layout_of(p->nverts, p->ntris, p->nspheres, p->flags, &L))
    return vr_error_set(B->err, VR_E_RANGE,
                        "geometry cache: sub-domain %d holds more than 2^32 vertices or "
                        "triangles; use more sub-domains",
                        c);
  meta->payload_bytes = L.total;
  unsigned char *pay = NULL;
  if (posix_memalign((void **)&pay, 64, L.total ? L.total : 64)) return nomem(B);
  memset(pay, 0, L.total); /* padding too: the checksum sees every byte */
  char path[PATHMAX];
  snprintf(path, sizeof path, "%s/part-%05d", B->tmp, c);
  FILE *f = (p->ntris || p->nspheres) ? fopen(path, "rb") : NULL;
  vr_status st = VR_OK;
  if ((p->ntris || p->nspheres) && !f) st = io_fail(B, "read", path);
  uint64_t vb = 0, tb = 0, sb = 0;
  while (!st && f) {
    vr_build_chunk_head h;
    size_t got = fread(&h, 1, sizeof h, f);
    if (got == 0 && feof(f)) break;
    size_t nv = h.nverts, nt = h.ntris, ns = h.nspheres;
    uint32_t *tri = (uint32_t *)(pay + L.tris) + 3 * tb;
    bool ok = got == sizeof h && rd(f, pay + L.verts + 12 * vb, nv * 12) &&
              (!(h.flags & VR_CELL_NORMALS) || rd(f, pay + L.normals + 12 * vb, nv * 12)) &&
              rd(f, tri, nt * 12) && rd(f, pay + L.objects + 4 * tb, nt * 4) &&
              rd(f, pay + L.uv + 24 * tb, nt * 24) &&
              (!(h.flags & VR_CELL_COLOURS) || rd(f, pay + L.colours + 9 * tb, nt * 9)) &&
              rd(f, pay + L.spheres + 32 * sb, ns * 32) &&
              rd(f, pay + L.sphere_objects + 4 * sb, ns * 4);
    if (!ok) {
      st = vr_error_set(B->err, VR_E_IO, "geometry cache: %s: cut short", path);
      break;
    }
    for (size_t i = 0; i < 3 * nt; i++) tri[i] += (uint32_t)vb;
    /* A chunk without colours in a cell with some: white (a factor of 1). */
    if ((p->flags & VR_CELL_COLOURS) && !(h.flags & VR_CELL_COLOURS))
      memset(pay + L.colours + 9 * tb, 255, nt * 9);
    vb += nv;
    tb += nt;
    sb += ns;
  }
  if (f) fclose(f);
  unlink(path);
  if (!st) {
    snprintf(path, sizeof path, "%s/cell-%05d.vrc", B->tmp, c);
    st = vr_cell_file_write(path, (uint32_t)c, B->b->key, meta, pay, &meta->payload_hash, B->err);
  }
  if (!st && B->b->measure)
    st = B->b->measure(B->b->measure_ctx, pay, meta, &meta->embree_bytes, &meta->embree_peak,
                       B->err);
  free(pay);
  return st;
}

static void builder_free(vr_mesh_builder *B) {
  if (B->soup) fclose(B->soup);
  free(B->heap);
  vr_scene_tables_free(&B->t);
  for (int c = 0; B->parts && c < B->cells.ncells; c++) {
    free(B->parts[c].buf);
    free(B->parts[c].objects);
  }
  free(B->parts);
  vr_cache_cells_free(&B->cells); /* last: the parts are counted by it */
}

vr_status vr_cache_build_run(const vr_cache_build *b, vr_cache_manifest **out, vr_error *err) {
  *out = NULL;
  vr_mesh_builder B = {.b = b, .err = err};
  if (strlen(b->dir) >= DIRMAX)
    return vr_error_set(err, VR_E_ARG, "geometry cache: folder name longer than %d bytes", DIRMAX);
  snprintf(B.tmp, sizeof B.tmp, "%s.tmp-%ld", b->dir, (long)getpid());
  vr_cache_remove_leftovers(b->dir);
  if (mkdir(B.tmp, 0755) != 0) return io_fail(&B, "create", B.tmp);
  double t0 = now();
  vr_cache_manifest *m = calloc(1, sizeof *m);
  vr_status st = m ? pass1(&B) : nomem(&B);
  double t1 = now();
  if (!st) {
    st = vr_cache_choose_cells(B.heap, B.nheap, B.t.bmin, B.t.bmax, b->subdomains, &B.cells, err);
    free(B.heap); /* the sample has served */
    B.heap = NULL;
  }
  if (!st) st = pass2(&B);
  double t2 = now();
  if (!st) {
    m->ncells = B.cells.ncells;
    m->nnodes = B.cells.nnodes;
    m->cells = calloc((size_t)B.cells.ncells, sizeof *m->cells);
    if (!m->cells) st = nomem(&B);
  }
  uint64_t bytes = 0;
  for (int c = 0; !st && c < B.cells.ncells; c++) {
    st = assemble(&B, c, &m->cells[c]);
    bytes += m->cells[c].payload_bytes;
  }
  if (!st) {
    memcpy(m->key, b->key, 32);
    m->nodes = B.cells.nodes;
    B.cells.nodes = NULL;
    m->tables = B.t;
    memset(&B.t, 0, sizeof B.t);
    char path[PATHMAX];
    snprintf(path, sizeof path, "%s/manifest.vrm", B.tmp);
    st = vr_cache_manifest_write(path, m, err);
  }
  if (!st) {
    /* The new folder takes the old one's place; the old one goes. */
    char old[PATHMAX];
    snprintf(old, sizeof old, "%s.old-%ld", b->dir, (long)getpid());
    vr_cache_remove_flat(old);
    bool had = rename(b->dir, old) == 0;
    if (rename(B.tmp, b->dir) != 0) {
      st = io_fail(&B, "rename to", b->dir);
      if (had) rename(old, b->dir);
    } else if (had) {
      vr_cache_remove_flat(old);
    }
  }
  builder_free(&B);
  if (st) {
    vr_cache_remove_flat(B.tmp);
    vr_cache_manifest_free(m);
    return st;
  }
  say(&B, "cache: %llu triangles and %llu spheres into %d sub-domain%s, %.1f MiB on disk, in "
      "%.2f s (reading %.2f s, dealing %.2f s, cells %.2f s)",
      (unsigned long long)m->tables.ntris, (unsigned long long)m->tables.nspheres, m->ncells,
      m->ncells == 1 ? "" : "s", (double)bytes / 1048576.0, now() - t0, t1 - t0, t2 - t1,
      now() - t2);
  *out = m;
  return VR_OK;
}
