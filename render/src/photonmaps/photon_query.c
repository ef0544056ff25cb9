/* Queries of a built photon map (vr/photon_map.h): the k nearest photons
 * in the disc around a point by a kd-tree walk, the density estimate over
 * them, and gathering them for callers that merge several maps (the
 * per-sub-domain maps of photon_set.c). */
#include "photonmaps/photon_map_internal.h"

#include <stdlib.h>

/* kNN heaps up to this size live on the stack. */
#define STACK_HEAP 256


/* One candidate: g2 is the squared "disc distance"
 * max(|p - x|, |dot(p - x, n)| / DISC)^2, the smallest squared radius whose
 * disc holds the photon. */
typedef struct vr_pm_candidate {
  double g2, d2;
  uint32_t rank, idx;
} vr_pm_candidate;

/* sum[b] += w power[b] for the bins of photon i. */
static void accumulate(const vr_photon_map *m, size_t i, double w, double *sum) {
  const unsigned char *spec = m->spec + i * m->spec_size;
  if (!m->slots) {
    const float *pw = (const float *)spec; /* spec_size is a multiple of 4 */
    for (int b = 0; b < m->nbins; b++) sum[b] += w * (double)pw[b];
  } else if (m->bin_bytes == 1) {
    const unsigned char *bins = spec + 4u * (size_t)m->slots;
    for (int s = 0; s < m->slots; s++) {
      float v = pm_slot_power(spec, s);
      if (v == 0.0f) break;
      sum[bins[s]] += w * (double)v;
    }
  } else {
    for (int s = 0; s < m->slots; s++) {
      float v = pm_slot_power(spec, s);
      if (v == 0.0f) break;
      sum[pm_slot_bin(m, spec, s)] += w * (double)v;
    }
  }
}

static bool cand_less(const vr_pm_candidate *a, const vr_pm_candidate *b) {
  return a->g2 < b->g2 || (a->g2 == b->g2 && a->rank < b->rank);
}

typedef struct vr_pm_query {
  const vr_photon_map *m;
  double x[3], n[3]; /* x relative to the centre; n unit */
  double rmax2;
  /* kNN: a max-heap of the best k so far (Jensen 2001, sec. 6.3). */
  int k, found;
  vr_pm_candidate *heap;
  /* fixed radius: running sums, or (gathering) the list to append to */
  double *sum, kcr; /* kcr = kc r, 0 for the box filter */
  vr_photon_list *list;
  uint32_t label;
  uint32_t surface; /* VR_PHOTON_ANY_SURFACE: every photon */
  bool nomem;
} vr_pm_query;

static void heap_sift_down(vr_pm_candidate *h, int n, int i) {
  for (;;) {
    int l = 2 * i + 1, r = l + 1, big = i;
    if (l < n && cand_less(&h[big], &h[l])) big = l;
    if (r < n && cand_less(&h[big], &h[r])) big = r;
    if (big == i) return;
    vr_pm_candidate t = h[i];
    h[i] = h[big];
    h[big] = t;
    i = big;
  }
}

static void consider(vr_pm_query *q, uint32_t i) {
  const vr_pm_node *p = &q->m->nodes[i];
  double dx = (double)p->p[0] - q->x[0], dy = (double)p->p[1] - q->x[1],
         dz = (double)p->p[2] - q->x[2];
  double d2 = dx * dx + dy * dy + dz * dz;
  bool full = q->heap && q->found == q->k;
  double bound = full ? q->heap[0].g2 : q->rmax2;
  if (d2 > bound) return;
  double t = (dx * q->n[0] + dy * q->n[1] + dz * q->n[2]) * (1.0 / VR_PHOTON_MAP_DISC);
  vr_pm_candidate c = {d2 > t * t ? d2 : t * t, d2, pm_rank(p), i};
  if (c.g2 > bound) return;
  if (full && !cand_less(&c, &q->heap[0])) return;
  double dir[3];
  pm_oct_decode_raw(q->m->dir[i], dir);
  if (!(dir[0] * q->n[0] + dir[1] * q->n[1] + dir[2] * q->n[2] < 0.0)) return;
  if (q->surface != VR_PHOTON_ANY_SURFACE && q->m->surf[i] != q->surface) return;

  if (!q->heap && q->list) { /* gathering every photon in the disc */
    vr_photon_list *l = q->list;
    if (l->n == l->cap && !vr_photon_list_reserve(l, l->cap ? 2 * l->cap : 256)) {
      q->nomem = true;
      return;
    }
    l->c[l->n++] = (vr_photon_cand){c.g2, c.d2, q->m->keys[i], i, q->label};
    q->found++;
  } else if (!q->heap) { /* fixed radius: add it now */
    double w = q->kcr > 0.0 ? 1.0 - sqrt(d2) / q->kcr : 1.0;
    accumulate(q->m, i, w, q->sum);
    q->found++;
  } else if (!full) {
    int j = q->found++;
    q->heap[j] = c;
    while (j > 0 && cand_less(&q->heap[(j - 1) / 2], &q->heap[j])) {
      vr_pm_candidate tmp = q->heap[j];
      q->heap[j] = q->heap[(j - 1) / 2];
      q->heap[(j - 1) / 2] = tmp;
      j = (j - 1) / 2;
    }
  } else {
    q->heap[0] = c;
    heap_sift_down(q->heap, q->k, 0);
  }
}

static void visit(vr_pm_query *q, size_t lo, size_t hi) {
  if (hi - lo <= LEAF) {
    for (size_t i = lo; i < hi; i++) consider(q, (uint32_t)i);
    return;
  }
  size_t mid = lo + (hi - lo) / 2;
  const vr_pm_node *s = &q->m->nodes[mid];
  int ax = pm_axis(s);
  double delta = q->x[ax] - (double)s->p[ax];
  /* Nearer side first, so the heap tightens early.  The lower side holds
   * coordinates <= the split, the upper side >= it; "<=" below keeps
   * photons tied in distance with the k-th in reach. */
  size_t nlo = delta < 0.0 ? lo : mid + 1, nhi = delta < 0.0 ? mid : hi;
  size_t flo = delta < 0.0 ? mid + 1 : lo, fhi = delta < 0.0 ? hi : mid;
  visit(q, nlo, nhi);
  consider(q, (uint32_t)mid);
  double bound = q->heap && q->found == q->k ? q->heap[0].g2 : q->rmax2;
  if (delta * delta <= bound) visit(q, flo, fhi);
}

/* Checks the arguments common to both queries and sets up q. */
static bool query_init(vr_pm_query *q, const vr_photon_map *m, const double x[3], const double n[3],
                       double radius_max) {
  if (!m || !m->built || !x || !n || !pm_finite3(x) || !pm_finite3(n)) return false;
  if (!isfinite(radius_max) || !(radius_max > 0.0)) return false;
  double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  if (!(l > 0.0) || !isfinite(l)) return false;
  memset(q, 0, sizeof *q);
  q->m = m;
  for (int a = 0; a < 3; a++) {
    q->x[a] = x[a] - m->centre[a];
    q->n[a] = n[a] / l;
  }
  q->rmax2 = radius_max * radius_max;
  q->surface = VR_PHOTON_ANY_SURFACE;
  return true;
}

/* The k nearest into q->heap[0 .. found): in heap order, which depends on
 * the tree alone, or sorted nearest first (ties by key). */
static void knn(vr_pm_query *q, bool sorted) {
  if (q->m->n) visit(q, 0, q->m->n);
  if (!sorted) return;
  for (int end = q->found - 1; end > 0; end--) { /* heap sort, in place */
    vr_pm_candidate t = q->heap[0];
    q->heap[0] = q->heap[end];
    q->heap[end] = t;
    heap_sift_down(q->heap, end, 0);
  }
}

int vr_photon_map_irradiance(const vr_photon_map *m, const double x[3], const double n[3],
                             int k, double radius_max, double kc, double *out,
                             double *r_used) {
  if (!out) return -1;
  if (m) memset(out, 0, sizeof *out * (size_t)m->nbins);
  if (r_used) *r_used = 0.0;
  vr_pm_query q;
  if (k < 0 || isnan(kc) || (kc > 0.0 && kc < 1.0) || !query_init(&q, m, x, n, radius_max))
    return -1;
  double norm = kc > 0.0 ? 1.0 - 2.0 / (3.0 * kc) : 1.0;
  double r = radius_max;

  if (k == 0) {
    q.sum = out;
    q.kcr = kc > 0.0 ? kc * r : 0.0;
    if (m->n) visit(&q, 0, m->n);
  } else {
    vr_pm_candidate stack_heap[STACK_HEAP];
    q.k = k;
    q.heap = k <= STACK_HEAP ? stack_heap : malloc((size_t)k * sizeof(vr_pm_candidate));
    if (!q.heap) return -1;
    knn(&q, false);
    if (q.found == k) r = sqrt(q.heap[0].g2);
    if (!(r > 0.0)) {
      if (q.heap != stack_heap) free(q.heap);
      return -1;
    }
    for (int j = 0; j < q.found; j++) {
      double w = kc > 0.0 ? 1.0 - sqrt(q.heap[j].d2) / (kc * r) : 1.0;
      accumulate(m, q.heap[j].idx, w, out);
    }
    if (q.heap != stack_heap) free(q.heap);
  }
  double scale = 1.0 / (norm * M_PI * r * r);
  for (int b = 0; b < m->nbins; b++) out[b] *= scale;
  if (r_used) *r_used = r;
  return q.found;
}

int vr_photon_map_locate(const vr_photon_map *m, const double x[3], const double n[3], int k,
                         double radius_max, vr_photon_hit *hits, double *r_used) {
  if (r_used) *r_used = 0.0;
  vr_pm_query q;
  if (!hits || k <= 0 || !query_init(&q, m, x, n, radius_max)) return -1;
  vr_pm_candidate stack_heap[STACK_HEAP];
  q.k = k;
  q.heap = k <= STACK_HEAP ? stack_heap : malloc((size_t)k * sizeof(vr_pm_candidate));
  if (!q.heap) return -1;
  knn(&q, true);
  double r = q.found == k ? sqrt(q.heap[k - 1].g2) : radius_max;
  for (int j = 0; j < q.found; j++) {
    hits[j].index = q.heap[j].idx;
    hits[j].dist = sqrt(q.heap[j].d2);
  }
  if (q.heap != stack_heap) free(q.heap);
  if (r_used) *r_used = r;
  return q.found;
}

/* --- gathering, for several maps answering as one --------------------- */

bool vr_photon_list_reserve(vr_photon_list *l, size_t cap) {
  if (cap <= l->cap) return true;
  vr_photon_cand *c;
  if (l->borrowed) {
    c = malloc(cap * sizeof *c);
    if (c && l->n) memcpy(c, l->c, l->n * sizeof *c);
  } else {
    c = realloc(l->c, cap * sizeof *c);
  }
  if (!c) return false;
  l->c = c;
  l->cap = cap;
  l->borrowed = false;
  return true;
}

void vr_photon_list_free(vr_photon_list *l) {
  if (!l->borrowed) free(l->c);
  l->c = NULL;
  l->n = l->cap = 0;
  l->borrowed = false;
}

long vr_photon_map_gather(const vr_photon_map *m, uint32_t label, const double x[3],
                          const double n[3], int k, double bound2, vr_photon_list *out) {
  return vr_photon_map_gather_on(m, label, x, n, VR_PHOTON_ANY_SURFACE, k, bound2, out);
}

long vr_photon_map_gather_on(const vr_photon_map *m, uint32_t label, const double x[3],
                             const double n[3], uint32_t surface, int k, double bound2,
                             vr_photon_list *out) {
  vr_pm_query q;
  if (!out || k < 0 || !(bound2 > 0.0) || !isfinite(bound2) ||
      !query_init(&q, m, x, n, 1.0))
    return -1;
  q.rmax2 = bound2;
  q.surface = surface;
  q.label = label;
  if (k == 0) {
    q.list = out;
    if (m->n) visit(&q, 0, m->n);
    return q.nomem ? -1 : q.found;
  }
  if (!vr_photon_list_reserve(out, out->n + (size_t)k)) return -1;
  vr_pm_candidate stack_heap[STACK_HEAP];
  q.k = k;
  q.heap = k <= STACK_HEAP ? stack_heap : malloc((size_t)k * sizeof(vr_pm_candidate));
  if (!q.heap) return -1;
  knn(&q, false); /* heap order: the farthest first when k were found */
  for (int j = 0; j < q.found; j++) {
    const vr_pm_candidate *c = &q.heap[j];
    out->c[out->n++] = (vr_photon_cand){c->g2, c->d2, m->keys[c->idx], c->idx, label};
  }
  if (q.heap != stack_heap) free(q.heap);
  return q.found;
}

double vr_photon_map_box_d2(const vr_photon_map *m, const double x[3]) {
  if (!m || !m->built || !m->n || !x || !pm_finite3(x)) return INFINITY;
  /* In the coordinates and the arithmetic of consider(): the rounded
   * differences are monotone in the photon's coordinate, so this is never
   * above a stored photon's own d2. */
  double d2 = 0.0;
  double d[3];
  for (int a = 0; a < 3; a++) {
    double xr = x[a] - m->centre[a];
    d[a] = (double)m->lo[a] > xr ? (double)m->lo[a] - xr
           : xr > (double)m->hi[a] ? xr - (double)m->hi[a]
                                   : 0.0;
  }
  d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
  return d2;
}

void vr_photon_map_add(const vr_photon_map *m, uint32_t index, double w, double *sum) {
  if (m && m->built && index < m->n) accumulate(m, index, w, sum);
}
