/* Per-cell photon maps answering as one (vr/photon_set.h, which holds the
 * proof that the answer is the single map's). */
#include "vr/photon_set.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Candidates a query keeps on its own stack before it needs the heap. */
#define STACK_CANDS 1024
/* Maps a query orders on its own stack. */
#define STACK_MAPS 64

struct vr_photon_set {
  int nmaps;
  vr_photon_map **maps;
};

vr_photon_set *vr_photon_set_create(int nmaps, int nbins, double lambda_min, double lambda_max,
                                    int max_nonzero, const double centre[3], vr_error *err) {
  if (nmaps < 1) {
    vr_error_set(err, VR_E_ARG, "photon set: %d maps, expected at least 1", nmaps);
    return NULL;
  }
  vr_photon_set *s = calloc(1, sizeof *s);
  if (!s || !(s->maps = calloc((size_t)nmaps, sizeof *s->maps))) {
    free(s);
    vr_error_set(err, VR_E_NOMEM, "photon set: out of memory");
    return NULL;
  }
  s->nmaps = nmaps;
  for (int i = 0; i < nmaps; i++) {
    s->maps[i] = vr_photon_map_create_sparse(nbins, lambda_min, lambda_max, max_nonzero, err);
    if (!s->maps[i] || vr_photon_map_set_centre(s->maps[i], centre, err)) {
      vr_photon_set_destroy(s);
      return NULL;
    }
  }
  return s;
}

void vr_photon_set_destroy(vr_photon_set *s) {
  if (!s) return;
  for (int i = 0; s->maps && i < s->nmaps; i++) vr_photon_map_destroy(s->maps[i]);
  free(s->maps);
  free(s);
}

vr_status vr_photon_set_store(vr_photon_set *s, int map, uint64_t key, const double pos[3],
                              const double dir_in[3], const double normal[3],
                              const float *power, vr_error *err) {
  return vr_photon_set_store_on(s, map, key, pos, dir_in, normal, VR_PHOTON_ANY_SURFACE, power,
                                err);
}

vr_status vr_photon_set_store_on(vr_photon_set *s, int map, uint64_t key, const double pos[3],
                                 const double dir_in[3], const double normal[3],
                                 uint32_t surface, const float *power, vr_error *err) {
  if (!s || map < 0 || map >= s->nmaps)
    return vr_error_set(err, VR_E_ARG, "photon set store: map %d out of range", map);
  return vr_photon_map_store_on(s->maps[map], key, pos, dir_in, normal, surface, power, err);
}

vr_status vr_photon_set_build(vr_photon_set *s, vr_error *err) {
  for (int i = 0; i < s->nmaps; i++) {
    vr_status st = vr_photon_map_build(s->maps[i], err);
    if (st) return st;
  }
  return VR_OK;
}

int vr_photon_set_count_maps(const vr_photon_set *s) { return s ? s->nmaps : 0; }

const vr_photon_map *vr_photon_set_map(const vr_photon_set *s, int map) {
  return s && map >= 0 && map < s->nmaps ? s->maps[map] : NULL;
}

size_t vr_photon_set_count(const vr_photon_set *s) {
  size_t n = 0;
  for (int i = 0; s && i < s->nmaps; i++) n += vr_photon_map_count(s->maps[i]);
  return n;
}

size_t vr_photon_set_bytes(const vr_photon_set *s) {
  size_t n = s ? sizeof *s + (size_t)s->nmaps * sizeof *s->maps : 0;
  for (int i = 0; s && i < s->nmaps; i++) n += vr_photon_map_bytes(s->maps[i]);
  return n;
}

/* The order in which the k nearest are chosen: (g2, key), then the map for
 * equal keys, which only a caller storing one key twice can make. */
static inline bool before(const vr_photon_cand *x, const vr_photon_cand *y) {
  if (x->g2 != y->g2) return x->g2 < y->g2;
  if (x->key != y->key) return x->key < y->key;
  return x->map < y->map;
}

static inline void swap(vr_photon_cand *a, vr_photon_cand *b) {
  vr_photon_cand t = *a;
  *a = *b;
  *b = t;
}

/* Puts the k first of v[0..n) in `before` order into v[0..k), the k-th at
 * v[k-1] (quickselect, median-of-three pivots; no two candidates compare
 * equal). */
static void select_k(vr_photon_cand *v, size_t n, size_t k) {
  size_t lo = 0, hi = n, want = k - 1;
  while (hi - lo > 8) {
    size_t a = lo, b = lo + (hi - lo) / 2, c = hi - 1, m;
    if (before(&v[a], &v[b]))
      m = before(&v[b], &v[c]) ? b : (before(&v[a], &v[c]) ? c : a);
    else
      m = before(&v[a], &v[c]) ? a : (before(&v[b], &v[c]) ? c : b);
    swap(&v[m], &v[hi - 1]);
    size_t store = lo;
    for (size_t i = lo; i + 1 < hi; i++)
      if (before(&v[i], &v[hi - 1])) swap(&v[i], &v[store++]);
    swap(&v[store], &v[hi - 1]);
    if (store == want) return;
    if (want < store)
      hi = store;
    else
      lo = store + 1;
  }
  for (size_t i = lo + 1; i < hi; i++)
    for (size_t j = i; j > lo && before(&v[j], &v[j - 1]); j--) swap(&v[j], &v[j - 1]);
}

/* Sorts v[0..n) by key (stable), by bytes from the lowest, skipping the
 * bytes all keys share (photon keys differ in a few low bytes only).  tmp
 * has room for n. */
static void sort_by_key(vr_photon_cand *v, size_t n, vr_photon_cand *tmp) {
  uint64_t all_or = 0, all_and = ~(uint64_t)0;
  for (size_t i = 0; i < n; i++) {
    all_or |= v[i].key;
    all_and &= v[i].key;
  }
  uint64_t differ = all_or ^ all_and;
  vr_photon_cand *src = v, *dst = tmp;
  for (int shift = 0; shift < 64; shift += 8) {
    if (!((differ >> shift) & 0xff)) continue;
    size_t count[257] = {0};
    for (size_t i = 0; i < n; i++) count[((src[i].key >> shift) & 0xff) + 1]++;
    for (int d = 0; d < 256; d++) count[d + 1] += count[d];
    for (size_t i = 0; i < n; i++) dst[count[(src[i].key >> shift) & 0xff]++] = src[i];
    vr_photon_cand *t = src;
    src = dst;
    dst = t;
  }
  if (src != v) memcpy(v, src, n * sizeof *v);
}

typedef struct vr_near_map {
  double d2;
  int map;
} vr_near_map;

static int by_box(const void *a, const void *b) {
  const vr_near_map *x = a, *y = b;
  if (x->d2 != y->d2) return x->d2 < y->d2 ? -1 : 1;
  return (x->map > y->map) - (x->map < y->map);
}

int vr_photon_set_irradiance(const vr_photon_set *s, const double x[3], const double n[3], int k,
                             double radius_max, double kc, double *out, double *r_used) {
  return vr_photon_set_irradiance_on(s, x, n, VR_PHOTON_ANY_SURFACE, k, radius_max, kc, out,
                                     r_used);
}

int vr_photon_set_irradiance_on(const vr_photon_set *s, const double x[3], const double n[3],
                                uint32_t surface, int k, double radius_max, double kc,
                                double *out, double *r_used) {
  if (!out) return -1;
  if (r_used) *r_used = 0.0;
  if (!s) return -1;
  int nbins = vr_photon_map_nbins(s->maps[0]);
  memset(out, 0, sizeof *out * (size_t)nbins);
  if (k < 0 || isnan(kc) || (kc > 0.0 && kc < 1.0) || !x || !n || !isfinite(radius_max) ||
      !(radius_max > 0.0))
    return -1;
  for (int i = 0; i < s->nmaps; i++)
    if (!vr_photon_map_built(s->maps[i])) return -1;
  double rmax2 = radius_max * radius_max, bound2 = rmax2;

  /* The maps by distance from x to their photons' boxes; those beyond
   * rmax can hold nothing. */
  vr_near_map stack_maps[STACK_MAPS], *order = stack_maps;
  if (s->nmaps > STACK_MAPS && !(order = malloc((size_t)s->nmaps * sizeof *order))) return -1;
  int nm = 0;
  for (int i = 0; i < s->nmaps; i++) {
    double d2 = vr_photon_map_box_d2(s->maps[i], x);
    if (d2 <= rmax2) order[nm++] = (vr_near_map){d2, i};
  }
  qsort(order, (size_t)nm, sizeof *order, by_box);

  /* L gathers each map's candidates; with k > 0 it is cut back to the k
   * best of the union whenever it holds more, and the bound follows. */
  vr_photon_cand stack_cands[STACK_CANDS];
  vr_photon_list L = {stack_cands, 0, STACK_CANDS, true};
  vr_photon_cand *tmp = NULL;
  int rc = -1;
  for (int j = 0; j < nm; j++) {
    if (order[j].d2 > bound2) break; /* sorted: the rest are farther still */
    long got = vr_photon_map_gather_on(s->maps[order[j].map], (uint32_t)order[j].map, x, n,
                                       surface, k, bound2, &L);
    if (got < 0) goto done;
    if (k > 0 && got > 0 && L.n >= (size_t)k) {
      if (L.n > (size_t)k) {
        select_k(L.c, L.n, (size_t)k);
        L.n = (size_t)k;
      }
      double far = L.c[0].g2;
      for (size_t i = 1; i < L.n; i++)
        if (L.c[i].g2 > far) far = L.c[i].g2;
      bound2 = far;
    }
  }
  double r = radius_max;
  if (k > 0 && L.n == (size_t)k) r = sqrt(bound2);
  if (!(r > 0.0)) goto done; /* the k nearest all at x: no density */
  /* The sum runs in key order, which depends on the photons alone. */
  if (L.n > 1) {
    if (!(tmp = malloc(L.n * sizeof *tmp))) goto done;
    sort_by_key(L.c, L.n, tmp);
  }
  double norm = kc > 0.0 ? 1.0 - 2.0 / (3.0 * kc) : 1.0;
  for (size_t i = 0; i < L.n; i++) {
    double w = kc > 0.0 ? 1.0 - sqrt(L.c[i].d2) / (kc * r) : 1.0;
    vr_photon_map_add(s->maps[L.c[i].map], L.c[i].index, w, out);
  }
  double scale = 1.0 / (norm * M_PI * r * r);
  for (int b = 0; b < nbins; b++) out[b] *= scale;
  if (r_used) *r_used = r;
  rc = (int)L.n;
done:
  if (rc < 0) memset(out, 0, sizeof *out * (size_t)nbins);
  free(tmp);
  vr_photon_list_free(&L);
  if (order != stack_maps) free(order);
  return rc;
}
