/* Reading and writing the geometry cache's files (cache_format.h).
 * Numbers are written in the host's byte order; the header carries a
 * marker, so a cache copied to a machine of the other order is refused
 * (and rebuilt) rather than misread. */
#include "geometry/cache_format.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>

#include "vr/hash64.h"

static const char CELL_MAGIC[8] = {'V', 'R', 'C', 'E', 'L', 'L', '\r', '\n'};
static const char MANIFEST_MAGIC[8] = {'V', 'R', 'M', 'A', 'N', 'I', 'F', '\n'};
static const uint32_t ENDIAN_MARK = 0x01020304u;
#define MANIFEST_HEADER 64
#define ALIGN 64

/* ---- a growable byte buffer and a bounded reader ---- */

typedef struct vr_wbuf {
  unsigned char *p;
  size_t n, cap;
  bool nomem;
} vr_wbuf;

static void put(vr_wbuf *b, const void *v, size_t n) {
  if (b->nomem) return;
  if (b->n + n > b->cap) {
    size_t cap = b->cap ? b->cap : 4096;
    while (cap < b->n + n) cap *= 2;
    unsigned char *p = realloc(b->p, cap);
    if (!p) {
      b->nomem = true;
      return;
    }
    b->p = p;
    b->cap = cap;
  }
  if (n) memcpy(b->p + b->n, v, n);
  b->n += n;
}
static void put_u32(vr_wbuf *b, uint32_t v) { put(b, &v, 4); }
static void put_i32(vr_wbuf *b, int32_t v) { put(b, &v, 4); }
static void put_u64(vr_wbuf *b, uint64_t v) { put(b, &v, 8); }
static void put_f64(vr_wbuf *b, double v) { put(b, &v, 8); }

typedef struct vr_rbuf {
  const unsigned char *p;
  size_t n, at;
  bool bad;
} vr_rbuf;

static bool take(vr_rbuf *r, void *v, size_t n) {
  if (r->bad || n > r->n - r->at) {
    r->bad = true;
    if (v && n) memset(v, 0, n);
    return false;
  }
  if (n) memcpy(v, r->p + r->at, n);
  r->at += n;
  return true;
}
static uint32_t get_u32(vr_rbuf *r) { uint32_t v = 0; take(r, &v, 4); return v; }
static int32_t get_i32(vr_rbuf *r) { int32_t v = 0; take(r, &v, 4); return v; }
static uint64_t get_u64(vr_rbuf *r) { uint64_t v = 0; take(r, &v, 8); return v; }
static double get_f64(vr_rbuf *r) { double v = 0; take(r, &v, 8); return v; }

/* An array of n elements of `size` bytes from r, or NULL (r->bad set) when
 * the rest of r is shorter or memory runs out. */
static void *get_array(vr_rbuf *r, uint64_t n, size_t size) {
  if (r->bad || (size && n > (r->n - r->at) / size)) {
    r->bad = true;
    return NULL;
  }
  size_t bytes = (size_t)n * size;
  void *v = malloc(bytes ? bytes : 1);
  if (!v) {
    r->bad = true;
    return NULL;
  }
  take(r, v, n * size);
  return v;
}

/* ---- whole-file writes: temporary name, fsync, rename ---- */

static vr_status write_whole(const char *path, const void *head, size_t nhead, const void *body,
                             size_t nbody, vr_error *err) {
  char tmp[4200];
  snprintf(tmp, sizeof tmp, "%s.tmp-%ld", path, (long)getpid());
  int fd = open(tmp, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return vr_error_set(err, VR_E_IO, "%s: cannot create: %s", tmp, strerror(errno));
  const unsigned char *parts[2] = {head, body};
  size_t sizes[2] = {nhead, nbody};
  for (int i = 0; i < 2; i++) {
    size_t done = 0;
    while (done < sizes[i]) {
      ssize_t w = write(fd, parts[i] + done, sizes[i] - done);
      if (w < 0 && errno == EINTR) continue;
      if (w <= 0) {
        int e = w < 0 ? errno : ENOSPC;
        close(fd);
        unlink(tmp);
        return vr_error_set(err, VR_E_IO, "%s: cannot write: %s", tmp, strerror(e));
      }
      done += (size_t)w;
    }
  }
  if (fsync(fd) != 0 || close(fd) != 0) {
    int e = errno;
    unlink(tmp);
    return vr_error_set(err, VR_E_IO, "%s: cannot write: %s", tmp, strerror(e));
  }
  if (rename(tmp, path) != 0) {
    int e = errno;
    unlink(tmp);
    return vr_error_set(err, VR_E_IO, "%s: cannot rename to %s: %s", tmp, path, strerror(e));
  }
  return VR_OK;
}

/* ---- the manifest ---- */

void vr_cache_manifest_free(vr_cache_manifest *m) {
  if (!m) return;
  for (int32_t c = 0; m->cells && c < m->ncells; c++) free(m->cells[c].objects);
  free(m->cells);
  free(m->nodes);
  vr_scene_tables_free(&m->tables);
  free(m);
}

static void put_tables(vr_wbuf *b, const vr_scene_tables *t) {
  for (int a = 0; a < 3; a++) put_f64(b, t->bmin[a]);
  for (int a = 0; a < 3; a++) put_f64(b, t->bmax[a]);
  put_u64(b, t->ntris);
  put_u64(b, t->nspheres);
  put_u64(b, t->degenerate_dropped);
  size_t n = t->nobjects;
  put_u64(b, n);
  put(b, t->object_area, n * sizeof *t->object_area);
  put(b, t->object_box, n * sizeof *t->object_box);
  put(b, t->object_prims, n * sizeof *t->object_prims);
  put(b, t->is_rect, n);
  put(b, t->rect_frame, n * sizeof *t->rect_frame);
  put(b, t->emit_begin, n * sizeof *t->emit_begin);
  put(b, t->emit_end, n * sizeof *t->emit_end);
  put(b, t->sphere, n * sizeof *t->sphere);
  put_u64(b, t->nemit);
  put(b, t->emit_verts, t->nemit * 9 * sizeof *t->emit_verts);
  put(b, t->emit_cdf, t->nemit * sizeof *t->emit_cdf);
}

static void get_tables(vr_rbuf *r, vr_scene_tables *t) {
  for (int a = 0; a < 3; a++) t->bmin[a] = get_f64(r);
  for (int a = 0; a < 3; a++) t->bmax[a] = get_f64(r);
  t->ntris = get_u64(r);
  t->nspheres = get_u64(r);
  t->degenerate_dropped = get_u64(r);
  uint64_t n = get_u64(r);
  t->nobjects = (size_t)n;
  t->object_area = get_array(r, n, sizeof *t->object_area);
  t->object_box = get_array(r, n, sizeof *t->object_box);
  t->object_prims = get_array(r, n, sizeof *t->object_prims);
  t->is_rect = get_array(r, n, 1);
  t->rect_frame = get_array(r, n, sizeof *t->rect_frame);
  t->emit_begin = get_array(r, n, sizeof *t->emit_begin);
  t->emit_end = get_array(r, n, sizeof *t->emit_end);
  t->sphere = get_array(r, n, sizeof *t->sphere);
  t->nemit = get_u64(r);
  t->emit_verts = get_array(r, t->nemit, 9 * sizeof *t->emit_verts);
  t->emit_cdf = get_array(r, t->nemit, sizeof *t->emit_cdf);
  for (uint64_t i = 0; !r->bad && i < n; i++)
    if (t->emit_begin[i] > t->emit_end[i] || t->emit_end[i] > t->nemit) r->bad = true;
}

vr_status vr_cache_manifest_write(const char *path, const vr_cache_manifest *m, vr_error *err) {
  vr_wbuf b = {0};
  put(&b, m->key, 32);
  put_i32(&b, m->ncells);
  put_i32(&b, m->nnodes);
  for (int32_t i = 0; i < m->nnodes; i++) {
    const vr_kd_node *k = &m->nodes[i];
    put_i32(&b, k->axis);
    put_i32(&b, k->child[0]);
    put_i32(&b, k->child[1]);
    put_i32(&b, k->cell);
    put_f64(&b, k->split);
  }
  for (int32_t c = 0; c < m->ncells; c++) {
    const vr_cell_meta *e = &m->cells[c];
    for (int a = 0; a < 3; a++) put_f64(&b, e->lo[a]);
    for (int a = 0; a < 3; a++) put_f64(&b, e->hi[a]);
    for (int a = 0; a < 3; a++) put_f64(&b, e->glo[a]);
    for (int a = 0; a < 3; a++) put_f64(&b, e->ghi[a]);
    put_u64(&b, e->nverts);
    put_u64(&b, e->ntris);
    put_u64(&b, e->nspheres);
    put_u32(&b, e->flags);
    put_u64(&b, e->payload_bytes);
    put_u64(&b, e->payload_hash);
    put_u64(&b, e->embree_bytes);
    put_u64(&b, e->embree_peak);
    put_u32(&b, e->nobjects);
    put(&b, e->objects, (size_t)e->nobjects * sizeof *e->objects);
  }
  put_tables(&b, &m->tables);
  if (b.nomem) {
    free(b.p);
    return vr_error_set(err, VR_E_NOMEM, "%s: out of memory", path);
  }
  unsigned char head[MANIFEST_HEADER] = {0};
  uint32_t version = VR_CACHE_VERSION;
  uint64_t nbytes = b.n, hash = vr_hash64_buffer(b.p, b.n, 0);
  memcpy(head, MANIFEST_MAGIC, 8);
  memcpy(head + 8, &version, 4);
  memcpy(head + 12, &ENDIAN_MARK, 4);
  memcpy(head + 16, &nbytes, 8);
  memcpy(head + 24, &hash, 8);
  uint64_t hh = vr_hash64_buffer(head, 32, 0);
  memcpy(head + 32, &hh, 8);
  vr_status st = write_whole(path, head, sizeof head, b.p, b.n, err);
  free(b.p);
  return st;
}

/* Checks a header's magic, version and byte order. */
static const char *check_magic(const unsigned char *h, const char magic[8]) {
  uint32_t version, mark;
  memcpy(&version, h + 8, 4);
  memcpy(&mark, h + 12, 4);
  if (memcmp(h, magic, 8)) return "not a file of the geometry cache (bad magic)";
  if (mark != ENDIAN_MARK) return "written on a machine of the other byte order";
  if (version != VR_CACHE_VERSION) return "written by another version of the cache format";
  return NULL;
}

static bool tree_ok(const vr_cache_manifest *m) {
  if (m->ncells < 1 || m->nnodes != 2 * m->ncells - 1) return false;
  int seen = 0;
  for (int32_t i = 0; i < m->nnodes; i++) {
    const vr_kd_node *k = &m->nodes[i];
    if (k->axis < 0) {
      if (k->cell < 0 || k->cell >= m->ncells) return false;
      seen++;
    } else if (k->axis > 2 || k->child[0] <= i || k->child[1] <= i ||
               k->child[0] >= m->nnodes || k->child[1] >= m->nnodes) {
      return false; /* children after their parent: the walk cannot loop */
    }
  }
  return seen == m->ncells;
}

vr_status vr_cache_manifest_read(const char *path, vr_cache_manifest **out, vr_error *err) {
  *out = NULL;
  FILE *f = fopen(path, "rb");
  if (!f) return vr_error_set(err, VR_E_IO, "%s: %s", path, strerror(errno));
  unsigned char head[MANIFEST_HEADER];
  if (fread(head, 1, sizeof head, f) != sizeof head) {
    fclose(f);
    return vr_error_set(err, VR_E_PARSE, "%s: cut short (no header)", path);
  }
  const char *why = check_magic(head, MANIFEST_MAGIC);
  uint64_t nbytes, hash, hh;
  memcpy(&nbytes, head + 16, 8);
  memcpy(&hash, head + 24, 8);
  memcpy(&hh, head + 32, 8);
  if (!why && hh != vr_hash64_buffer(head, 32, 0)) why = "damaged header (checksum)";
  if (!why && nbytes > ((uint64_t)1 << 40)) why = "implausible size";
  if (why) {
    fclose(f);
    return vr_error_set(err, VR_E_PARSE, "%s: %s", path, why);
  }
  unsigned char *p = malloc(nbytes ? nbytes : 1);
  if (!p) {
    fclose(f);
    return vr_error_set(err, VR_E_NOMEM, "%s: out of memory", path);
  }
  size_t got = fread(p, 1, nbytes, f);
  int extra = fgetc(f);
  fclose(f);
  if (got != nbytes || extra != EOF) {
    free(p);
    return vr_error_set(err, VR_E_PARSE, "%s: %s (%zu bytes of %llu)", path,
                        got != nbytes ? "cut short" : "longer than its header says", got,
                        (unsigned long long)nbytes);
  }
  if (vr_hash64_buffer(p, nbytes, 0) != hash) {
    free(p);
    return vr_error_set(err, VR_E_PARSE, "%s: damaged (checksum)", path);
  }
  vr_cache_manifest *m = calloc(1, sizeof *m);
  if (!m) {
    free(p);
    return vr_error_set(err, VR_E_NOMEM, "%s: out of memory", path);
  }
  vr_rbuf r = {p, nbytes, 0, false};
  take(&r, m->key, 32);
  m->ncells = get_i32(&r);
  m->nnodes = get_i32(&r);
  if (m->ncells < 1 || m->ncells > (1 << 20) || m->nnodes < 1 || m->nnodes > (1 << 21)) r.bad = true;
  if (!r.bad) {
    m->nodes = calloc((size_t)m->nnodes, sizeof *m->nodes);
    m->cells = calloc((size_t)m->ncells, sizeof *m->cells);
    if (!m->nodes || !m->cells) r.bad = true;
  }
  for (int32_t i = 0; !r.bad && i < m->nnodes; i++) {
    vr_kd_node *k = &m->nodes[i];
    k->axis = get_i32(&r);
    k->child[0] = get_i32(&r);
    k->child[1] = get_i32(&r);
    k->cell = get_i32(&r);
    k->split = get_f64(&r);
  }
  for (int32_t c = 0; !r.bad && c < m->ncells; c++) {
    vr_cell_meta *e = &m->cells[c];
    for (int a = 0; a < 3; a++) e->lo[a] = get_f64(&r);
    for (int a = 0; a < 3; a++) e->hi[a] = get_f64(&r);
    for (int a = 0; a < 3; a++) e->glo[a] = get_f64(&r);
    for (int a = 0; a < 3; a++) e->ghi[a] = get_f64(&r);
    e->nverts = get_u64(&r);
    e->ntris = get_u64(&r);
    e->nspheres = get_u64(&r);
    e->flags = get_u32(&r);
    e->payload_bytes = get_u64(&r);
    e->payload_hash = get_u64(&r);
    e->embree_bytes = get_u64(&r);
    e->embree_peak = get_u64(&r);
    e->nobjects = get_u32(&r);
    e->objects = get_array(&r, e->nobjects, sizeof *e->objects);
    vr_cell_layout L;
    if ((e->flags & ~(VR_CELL_NORMALS | VR_CELL_COLOURS)) ||
        !vr_cell_layout_of(e->nverts, e->ntris, e->nspheres, e->flags, &L) ||
        L.total != e->payload_bytes)
      r.bad = true;
  }
  if (!r.bad) get_tables(&r, &m->tables);
  bool trailing = !r.bad && r.at != r.n;
  free(p);
  if (r.bad || trailing || !tree_ok(m)) {
    vr_cache_manifest_free(m);
    return vr_error_set(err, VR_E_PARSE, "%s: inconsistent contents", path);
  }
  *out = m;
  return VR_OK;
}

/* ---- cell files ---- */

static size_t up(size_t v) { return (v + ALIGN - 1) / ALIGN * ALIGN; }

bool vr_cell_layout_of(uint64_t nverts, uint64_t ntris, uint64_t nspheres, uint32_t flags,
                       vr_cell_layout *L) {
  /* Limits that keep every size below far from overflow. */
  if (nverts >= UINT32_MAX || ntris >= UINT32_MAX || nspheres >= UINT32_MAX) return false;
  size_t at = 0;
  L->verts = at;
  at = up(at + (size_t)nverts * 12 + 16);
  L->normals = at;
  if (flags & VR_CELL_NORMALS) at = up(at + (size_t)nverts * 12);
  L->tris = at;
  at = up(at + (size_t)ntris * 12);
  L->objects = at;
  at = up(at + (size_t)ntris * 4);
  L->uv = at;
  at = up(at + (size_t)ntris * 24);
  L->colours = at;
  if (flags & VR_CELL_COLOURS) at = up(at + (size_t)ntris * 9);
  L->spheres = at;
  at = up(at + (size_t)nspheres * 32);
  L->sphere_objects = at;
  at = up(at + (size_t)nspheres * 4);
  L->total = at;
  return true;
}

static void cell_header(unsigned char h[VR_CELL_HEADER], uint32_t cell, const uint8_t key[32],
                        const vr_cell_meta *meta, uint64_t hash) {
  memset(h, 0, VR_CELL_HEADER);
  uint32_t version = VR_CACHE_VERSION;
  memcpy(h, CELL_MAGIC, 8);
  memcpy(h + 8, &version, 4);
  memcpy(h + 12, &ENDIAN_MARK, 4);
  memcpy(h + 16, &cell, 4);
  memcpy(h + 20, &meta->flags, 4);
  memcpy(h + 24, &meta->nverts, 8);
  memcpy(h + 32, &meta->ntris, 8);
  memcpy(h + 40, &meta->nspheres, 8);
  memcpy(h + 48, &meta->payload_bytes, 8);
  memcpy(h + 56, &hash, 8);
  memcpy(h + 64, key, 32);
  uint64_t hh = vr_hash64_buffer(h, 96, 0);
  memcpy(h + 96, &hh, 8);
}

vr_status vr_cell_file_write(const char *path, uint32_t cell, const uint8_t key[32],
                             const vr_cell_meta *meta, const void *payload, uint64_t *hash,
                             vr_error *err) {
  *hash = vr_hash64_buffer(payload, meta->payload_bytes, 0);
  unsigned char h[VR_CELL_HEADER];
  cell_header(h, cell, key, meta, *hash);
  return write_whole(path, h, sizeof h, payload, meta->payload_bytes, err);
}

/* The header read from fd against what the manifest expects. */
static vr_status check_header(int fd, const char *path, uint32_t cell, const uint8_t key[32],
                              const vr_cell_meta *meta, vr_error *err) {
  unsigned char h[VR_CELL_HEADER], want[VR_CELL_HEADER];
  ssize_t got = read(fd, h, sizeof h);
  if (got != (ssize_t)sizeof h)
    return vr_error_set(err, VR_E_PARSE, "%s: cut short (no header)", path);
  const char *why = check_magic(h, CELL_MAGIC);
  if (why) return vr_error_set(err, VR_E_PARSE, "%s: %s", path, why);
  cell_header(want, cell, key, meta, meta->payload_hash);
  if (memcmp(h, want, 104)) {
    uint64_t hh = vr_hash64_buffer(h, 96, 0);
    if (memcmp(&hh, h + 96, 8)) return vr_error_set(err, VR_E_PARSE, "%s: damaged header (checksum)", path);
    return vr_error_set(err, VR_E_PARSE, "%s: belongs to another scene or cut (key, cell or counts differ from the manifest)", path);
  }
  off_t size = lseek(fd, 0, SEEK_END);
  if (size != (off_t)(VR_CELL_HEADER + meta->payload_bytes))
    return vr_error_set(err, VR_E_PARSE, "%s: %lld bytes, expected %llu (truncated or extended)",
                        path, (long long)size,
                        (unsigned long long)(VR_CELL_HEADER + meta->payload_bytes));
  lseek(fd, VR_CELL_HEADER, SEEK_SET);
  return VR_OK;
}

static bool read_all(int fd, unsigned char *p, size_t n) {
  size_t done = 0;
  while (done < n) {
    ssize_t r = read(fd, p + done, n - done);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) return false;
    done += (size_t)r;
  }
  return true;
}

vr_status vr_cell_file_read(const char *path, uint32_t cell, const uint8_t key[32],
                            const vr_cell_meta *meta, void **payload, vr_error *err) {
  *payload = NULL;
  int fd = open(path, O_RDONLY | O_CLOEXEC);
  if (fd < 0) return vr_error_set(err, VR_E_IO, "%s: %s", path, strerror(errno));
  /* The header, and the size the mapping needs: a file shorter than the
   * manifest says is refused here, before it is mapped. */
  vr_status st = check_header(fd, path, cell, key, meta, err);
  size_t len = VR_CELL_HEADER + (size_t)meta->payload_bytes;
  void *base = MAP_FAILED;
  if (!st) {
    base = mmap(NULL, len, PROT_READ, MAP_PRIVATE, fd, 0);
    if (base == MAP_FAILED && errno != ENOMEM) {
      /* A file system that cannot map files: the file read into anonymous
       * memory instead, released the same way. */
      base = mmap(NULL, len, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
      if (base != MAP_FAILED) {
        bool ok = lseek(fd, 0, SEEK_SET) == 0 && read_all(fd, base, len);
        if (!ok || mprotect(base, len, PROT_READ) != 0) {
          munmap(base, len);
          base = MAP_FAILED;
          st = vr_error_set(err, VR_E_PARSE, "%s: cut short while reading", path);
        }
      }
    }
    if (base == MAP_FAILED && !st)
      st = vr_error_set(err, VR_E_NOMEM, "%s: out of memory for %llu bytes", path,
                        (unsigned long long)len);
  }
  close(fd);
  if (st) return st;
  unsigned char *p = (unsigned char *)base + VR_CELL_HEADER;
  if (vr_hash64_buffer(p, meta->payload_bytes, 0) != meta->payload_hash) {
    munmap(base, len);
    return vr_error_set(err, VR_E_PARSE, "%s: damaged (checksum of its contents)", path);
  }
  *payload = p;
  return VR_OK;
}

void vr_cell_file_release(void *payload, const vr_cell_meta *meta) {
  if (!payload) return;
  munmap((unsigned char *)payload - VR_CELL_HEADER, VR_CELL_HEADER + (size_t)meta->payload_bytes);
}

vr_status vr_cell_file_check(const char *path, uint32_t cell, const uint8_t key[32],
                             const vr_cell_meta *meta, vr_error *err) {
  int fd = open(path, O_RDONLY | O_CLOEXEC);
  if (fd < 0) return vr_error_set(err, VR_E_IO, "%s: %s", path, strerror(errno));
  vr_status st = check_header(fd, path, cell, key, meta, err);
  enum { PIECE = 1 << 20 };
  unsigned char *buf = st ? NULL : malloc(PIECE);
  if (!st && !buf) st = vr_error_set(err, VR_E_NOMEM, "%s: out of memory", path);
  vr_hash64 h;
  vr_hash64_init(&h, 0);
  for (uint64_t left = meta->payload_bytes; !st && left;) {
    size_t n = left < PIECE ? (size_t)left : PIECE;
    if (!read_all(fd, buf, n)) st = vr_error_set(err, VR_E_PARSE, "%s: cut short while reading", path);
    else vr_hash64_update(&h, buf, n);
    left -= n;
  }
  close(fd);
  free(buf);
  if (!st && vr_hash64_final(&h) != meta->payload_hash)
    st = vr_error_set(err, VR_E_PARSE, "%s: damaged (checksum of its contents)", path);
  return st;
}
