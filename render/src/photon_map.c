/* The spectral photon map of vr/photon_map.h: photons are staged as they
 * are stored (under a lock, from any thread), then the build orders them by
 * key, packs them and arranges them as an implicit balanced kd-tree: the
 * median of each range sits at the range's middle index, the lower half
 * before it, the upper half after, so the tree needs no pointers.  Ranges of
 * LEAF photons or fewer are left unordered and scanned.
 *
 * A photon's power is a record of spec_size bytes, the same staged and
 * built: dense, nbins floats; sparse, `slots` floats (the non-zero powers in
 * increasing bin order, then +0 in unused slots) followed by their `slots`
 * bin indices (uint8 when nbins <= 256, else uint16; 0 in unused slots).
 * The record is not padded, so sparse floats are read with memcpy.  Both
 * forms add w * power to a bin for each non-zero bin of each photon in the
 * same photon order; the dense form also adds w * 0 = +-0 to the other bins,
 * which changes no sum (no sum is ever -0: each starts at +0, and
 * +0 + -0 = +0), so the two give bit-identical estimates. */
#include "vr/photon_map.h"

#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#define LEAF 8
#define POS_MAX 1e18
/* kNN heaps up to this size live on the stack. */
#define STACK_HEAP 256

/* One photon of the tree: 16 bytes, so four share a cache line.  The rank
 * is the photon's place in key order, which breaks ties in distance and in
 * the median splits; the split axis of an inner node sits in the low bits. */
typedef struct node {
  float p[3]; /* position - centre */
  uint32_t rank_axis;
} node;

struct vr_photon_map {
  int nbins;
  double lambda_min, lambda_max;
  int max_nz;    /* non-zero bins a photon may have (nbins for vr_photon_map_create) */
  int slots;     /* (power, bin) pairs a photon keeps; 0: dense */
  int bin_bytes; /* 1 or 2, sparse only */
  size_t spec_size; /* bytes of a photon's power record */

  /* Staging, before the build: records of rec_size bytes, each
   * key (u64) | pos (3 double) | dir (u32) | normal (u32) | power record | 0-padding. */
  pthread_mutex_t lock;
  unsigned char *stage;
  size_t nstage, capstage, rec_size;

  /* The built map. */
  bool built;
  size_t n;
  double centre[3];
  node *nodes;
  uint32_t *dir, *nrm; /* octahedral, 2 x 16 bits */
  unsigned char *spec; /* n power records of spec_size bytes */
};

enum { OFF_POS = 8, OFF_DIR = 32, OFF_NRM = 36, OFF_POW = 40 };

/* --- octahedral unit vectors (Cigolle et al., JCGT 3(2), 2014) --------- */

static double sign_nz(double v) { return v < 0.0 ? -1.0 : 1.0; }

static uint32_t oct_encode(const double v[3]) {
  double s = fabs(v[0]) + fabs(v[1]) + fabs(v[2]);
  double px = v[0] / s, py = v[1] / s;
  if (v[2] < 0.0) {
    double qx = (1.0 - fabs(py)) * sign_nz(px), qy = (1.0 - fabs(px)) * sign_nz(py);
    px = qx;
    py = qy;
  }
  /* rounding by hand: lrint would follow the caller's rounding mode */
  uint32_t ux = (uint32_t)((px * 0.5 + 0.5) * 65535.0 + 0.5);
  uint32_t uy = (uint32_t)((py * 0.5 + 0.5) * 65535.0 + 0.5);
  return ux | uy << 16;
}

/* The decoded vector before normalisation: enough for the sign of a dot
 * product, which is all the side rule asks. */
static void oct_decode_raw(uint32_t code, double v[3]) {
  double px = (double)(code & 0xffffu) * (2.0 / 65535.0) - 1.0;
  double py = (double)(code >> 16) * (2.0 / 65535.0) - 1.0;
  double pz = 1.0 - fabs(px) - fabs(py);
  if (pz < 0.0) {
    double qx = (1.0 - fabs(py)) * sign_nz(px), qy = (1.0 - fabs(px)) * sign_nz(py);
    px = qx;
    py = qy;
  }
  v[0] = px;
  v[1] = py;
  v[2] = pz;
}

static void oct_decode(uint32_t code, double v[3]) {
  oct_decode_raw(code, v);
  double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  v[0] /= l;
  v[1] /= l;
  v[2] /= l;
}

/* --- creation and staging ---------------------------------------------- */

/* sparse: keep (power, bin) pairs, if they cost less than the dense bins. */
static vr_photon_map *create(int nbins, double lambda_min, double lambda_max, int max_nz,
                             bool sparse, vr_error *err) {
  if (nbins < 1 || nbins > 65536) {
    vr_error_set(err, VR_E_ARG, "photon map: nbins = %d, expected 1 to 65536", nbins);
    return NULL;
  }
  if (!isfinite(lambda_min) || !isfinite(lambda_max) || !(lambda_min > 0.0) ||
      !(lambda_max > lambda_min)) {
    vr_error_set(err, VR_E_ARG,
                 "photon map: wavelength range [%g, %g] nm, expected 0 < lambda_min < lambda_max",
                 lambda_min, lambda_max);
    return NULL;
  }
  if (max_nz < 1) {
    vr_error_set(err, VR_E_ARG, "photon map: max_nonzero = %d, expected at least 1", max_nz);
    return NULL;
  }
  vr_photon_map *m = calloc(1, sizeof *m);
  if (!m) {
    vr_error_set(err, VR_E_NOMEM, "photon map: out of memory");
    return NULL;
  }
  if (pthread_mutex_init(&m->lock, NULL) != 0) {
    free(m);
    vr_error_set(err, VR_E_NOMEM, "photon map: cannot create a mutex");
    return NULL;
  }
  m->nbins = nbins;
  m->lambda_min = lambda_min;
  m->lambda_max = lambda_max;
  m->max_nz = max_nz < nbins ? max_nz : nbins;
  m->bin_bytes = nbins <= 256 ? 1 : 2;
  /* Pairs only when they are smaller than the bins they stand for. */
  size_t pairs = (size_t)m->max_nz * (4u + (size_t)m->bin_bytes), dense = 4u * (size_t)nbins;
  m->slots = sparse && pairs < dense ? m->max_nz : 0;
  m->spec_size = m->slots ? pairs : dense;
  m->rec_size = ((size_t)OFF_POW + m->spec_size + 7u) & ~(size_t)7u;
  return m;
}

vr_photon_map *vr_photon_map_create(int nbins, double lambda_min, double lambda_max,
                                    vr_error *err) {
  return create(nbins, lambda_min, lambda_max, nbins, false, err);
}

vr_photon_map *vr_photon_map_create_sparse(int nbins, double lambda_min, double lambda_max,
                                           int max_nonzero, vr_error *err) {
  return create(nbins, lambda_min, lambda_max, max_nonzero, true, err);
}

void vr_photon_map_destroy(vr_photon_map *m) {
  if (!m) return;
  pthread_mutex_destroy(&m->lock);
  free(m->stage);
  free(m->nodes);
  free(m->dir);
  free(m->nrm);
  free(m->spec);
  free(m);
}

static bool finite3(const double v[3]) {
  return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

static bool nonzero3(const double v[3]) { return v[0] != 0.0 || v[1] != 0.0 || v[2] != 0.0; }

vr_status vr_photon_map_store(vr_photon_map *m, uint64_t key, const double pos[3],
                              const double dir_in[3], const double normal[3],
                              const float *power, vr_error *err) {
  if (!m || !pos || !dir_in || !normal || !power)
    return vr_error_set(err, VR_E_ARG, "photon map store: NULL argument");
  /* Positions become floats about the centre: keep them far inside float range. */
  if (!finite3(pos) || fabs(pos[0]) > POS_MAX || fabs(pos[1]) > POS_MAX || fabs(pos[2]) > POS_MAX)
    return vr_error_set(err, VR_E_RANGE,
                        "photon map store: position (%g, %g, %g) is not finite or beyond 1e18 m",
                        pos[0], pos[1], pos[2]);
  if (!finite3(dir_in) || !nonzero3(dir_in))
    return vr_error_set(err, VR_E_RANGE,
                        "photon map store: direction (%g, %g, %g) is not a finite non-zero vector",
                        dir_in[0], dir_in[1], dir_in[2]);
  if (!finite3(normal) || !nonzero3(normal))
    return vr_error_set(err, VR_E_RANGE,
                        "photon map store: normal (%g, %g, %g) is not a finite non-zero vector",
                        normal[0], normal[1], normal[2]);
  int nz = 0;
  for (int b = 0; b < m->nbins; b++) {
    if (!isfinite(power[b]) || power[b] < 0.0f)
      return vr_error_set(err, VR_E_RANGE,
                          "photon map store: power[%d] = %g, expected finite and >= 0", b,
                          (double)power[b]);
    nz += power[b] != 0.0f;
  }
  if (nz > m->max_nz)
    return vr_error_set(err, VR_E_RANGE,
                        "photon map store: %d non-zero power bins, but this map keeps at most %d "
                        "a photon (max_nonzero of vr_photon_map_create_sparse)",
                        nz, m->max_nz);

  /* Everything but the copy happens outside the lock. */
  uint32_t d = oct_encode(dir_in), nr = oct_encode(normal);
  vr_status st = VR_OK;
  pthread_mutex_lock(&m->lock);
  if (m->built) {
    st = vr_error_set(err, VR_E_ARG, "photon map store: the map is already built");
  } else if (m->nstage >= VR_PHOTON_MAP_MAX) {
    st = vr_error_set(err, VR_E_RANGE, "photon map store: the map is full (%zu photons)",
                      m->nstage);
  } else {
    if (m->nstage == m->capstage) {
      size_t cap = m->capstage ? 2 * m->capstage : 1024;
      unsigned char *s = cap <= SIZE_MAX / m->rec_size ? realloc(m->stage, cap * m->rec_size)
                                                        : NULL;
      if (!s)
        st = vr_error_set(err, VR_E_NOMEM, "photon map store: out of memory at %zu photons",
                          m->nstage);
      else {
        m->stage = s;
        m->capstage = cap;
      }
    }
    if (st == VR_OK) {
      unsigned char *r = m->stage + m->nstage * m->rec_size;
      memset(r, 0, m->rec_size); /* padding takes part in the ordering */
      memcpy(r, &key, 8);
      memcpy(r + OFF_POS, pos, 24);
      memcpy(r + OFF_DIR, &d, 4);
      memcpy(r + OFF_NRM, &nr, 4);
      float *pw = (float *)(r + OFF_POW); /* 8-aligned: rec_size and OFF_POW are */
      if (!m->slots) {
        /* -0 is kept as +0, as in a sparse map: it adds nothing anyway */
        for (int b = 0; b < m->nbins; b++) pw[b] = power[b] != 0.0f ? power[b] : 0.0f;
      } else {
        unsigned char *bins = r + OFF_POW + 4u * (size_t)m->slots;
        int s = 0;
        for (int b = 0; b < m->nbins; b++)
          if (power[b] != 0.0f) {
            pw[s] = power[b];
            if (m->bin_bytes == 1)
              bins[s] = (unsigned char)b;
            else {
              uint16_t b16 = (uint16_t)b;
              memcpy(bins + 2 * s, &b16, 2);
            }
            s++;
          }
      }
      m->nstage++;
    }
  }
  pthread_mutex_unlock(&m->lock);
  return st;
}

/* --- the build ----------------------------------------------------------- */

/* Key order, then the record's bytes: photons with equal keys are ordered
 * by content, and identical ones are interchangeable, so the order never
 * depends on the order of stores.  The keys travel with the indices, so
 * only equal keys send the comparison to the records. */
typedef struct keyed {
  uint64_t key;
  uint64_t idx;
} keyed;

/* Bin and power of slot s of a sparse power record. */
static int slot_bin(const vr_photon_map *m, const unsigned char *spec, int s) {
  const unsigned char *bins = spec + 4u * (size_t)m->slots;
  if (m->bin_bytes == 1) return bins[s];
  uint16_t b;
  memcpy(&b, bins + 2 * s, 2);
  return b;
}

static float slot_power(const unsigned char *spec, int s) {
  float v;
  memcpy(&v, spec + 4 * s, 4);
  return v;
}

/* A sparse record against another in the order memcmp gives their dense
 * forms (bins in turn, the bytes of each float in memory order), so a
 * sparse map orders photons of equal keys as a dense map does. */
static int sparse_cmp(const vr_photon_map *m, const unsigned char *a, const unsigned char *b) {
  int i = 0, j = 0;
  for (;;) {
    int ba = i < m->slots && slot_power(a, i) != 0.0f ? slot_bin(m, a, i) : m->nbins;
    int bb = j < m->slots && slot_power(b, j) != 0.0f ? slot_bin(m, b, j) : m->nbins;
    if (ba == m->nbins && bb == m->nbins) return 0;
    int bin = ba < bb ? ba : bb;
    float fa = ba == bin ? slot_power(a, i++) : 0.0f, fb = bb == bin ? slot_power(b, j++) : 0.0f;
    int c = memcmp(&fa, &fb, 4);
    if (c) return c;
  }
}

static bool keyed_less(const vr_photon_map *m, const keyed *a, const keyed *b) {
  if (a->key != b->key) return a->key < b->key;
  const unsigned char *ra = m->stage + a->idx * m->rec_size, *rb = m->stage + b->idx * m->rec_size;
  if (!m->slots) return memcmp(ra + 8, rb + 8, m->rec_size - 8) < 0;
  int c = memcmp(ra + 8, rb + 8, OFF_POW - 8);
  return (c ? c : sparse_cmp(m, ra + OFF_POW, rb + OFF_POW)) < 0;
}

/* Bottom-up merge sort, stable (qsort has no context argument in C17). */
static bool sort_records(const vr_photon_map *m, keyed *v, size_t n) {
  keyed *tmp = malloc((n ? n : 1) * sizeof *tmp);
  if (!tmp) return false;
  keyed *src = v, *dst = tmp;
  for (size_t w = 1; w < n; w *= 2) {
    for (size_t lo = 0; lo < n; lo += 2 * w) {
      size_t mid = lo + w < n ? lo + w : n, hi = lo + 2 * w < n ? lo + 2 * w : n;
      size_t i = lo, j = mid, o = lo;
      while (i < mid && j < hi) dst[o++] = keyed_less(m, &src[j], &src[i]) ? src[j++] : src[i++];
      while (i < mid) dst[o++] = src[i++];
      while (j < hi) dst[o++] = src[j++];
    }
    keyed *t = src;
    src = dst;
    dst = t;
  }
  if (src != v) memcpy(v, src, n * sizeof *v);
  free(tmp);
  return true;
}

static uint32_t rank_of(const node *a) { return a->rank_axis >> 2; }
static int axis_of(const node *a) { return (int)(a->rank_axis & 3u); }

/* A strict total order along an axis: coordinate, then rank. */
static bool node_less(const node *a, const node *b, int ax) {
  return a->p[ax] < b->p[ax] || (a->p[ax] == b->p[ax] && rank_of(a) < rank_of(b));
}

static void swap_nodes(node *a, node *b) {
  node t = *a;
  *a = *b;
  *b = t;
}

/* Puts the element of order kth of [lo, hi) at kth, smaller ones before it
 * and larger ones after (quickselect, median-of-three pivots).  No two
 * elements compare equal, so there is no degenerate case of equal keys. */
static void select_nth(node *v, size_t lo, size_t hi, size_t kth, int ax) {
  while (hi - lo > 16) {
    size_t a = lo, b = lo + (hi - lo) / 2, c = hi - 1, piv;
    if (node_less(&v[a], &v[b], ax))
      piv = node_less(&v[b], &v[c], ax) ? b : (node_less(&v[a], &v[c], ax) ? c : a);
    else
      piv = node_less(&v[a], &v[c], ax) ? a : (node_less(&v[b], &v[c], ax) ? c : b);
    swap_nodes(&v[piv], &v[hi - 1]);
    size_t store = lo;
    for (size_t i = lo; i < hi - 1; i++)
      if (node_less(&v[i], &v[hi - 1], ax)) swap_nodes(&v[i], &v[store++]);
    swap_nodes(&v[store], &v[hi - 1]);
    if (store == kth) return;
    if (kth < store)
      hi = store;
    else
      lo = store + 1;
  }
  for (size_t i = lo + 1; i < hi; i++)
    for (size_t j = i; j > lo && node_less(&v[j], &v[j - 1], ax); j--) swap_nodes(&v[j], &v[j - 1]);
}

/* Depth is log2(n / LEAF) whatever the positions: splits are by count, so
 * coincident photons cannot make the recursion run away. */
static void build_tree(node *v, size_t lo, size_t hi) {
  if (hi - lo <= LEAF) return;
  float mn[3], mx[3];
  for (int a = 0; a < 3; a++) mn[a] = mx[a] = v[lo].p[a];
  for (size_t i = lo + 1; i < hi; i++)
    for (int a = 0; a < 3; a++) {
      if (v[i].p[a] < mn[a]) mn[a] = v[i].p[a];
      if (v[i].p[a] > mx[a]) mx[a] = v[i].p[a];
    }
  int ax = 0;
  for (int a = 1; a < 3; a++)
    if (mx[a] - mn[a] > mx[ax] - mn[ax]) ax = a;
  size_t mid = lo + (hi - lo) / 2;
  select_nth(v, lo, hi, mid, ax);
  v[mid].rank_axis = (v[mid].rank_axis & ~3u) | (uint32_t)ax;
  build_tree(v, lo, mid);
  build_tree(v, mid + 1, hi);
}

vr_status vr_photon_map_build(vr_photon_map *m, vr_error *err) {
  if (!m) return vr_error_set(err, VR_E_ARG, "photon map build: NULL map");
  if (m->built) return VR_OK;
  size_t n = m->nstage, sz = m->spec_size;
  keyed *order = malloc((n ? n : 1) * sizeof *order);
  node *nodes = malloc((n ? n : 1) * sizeof *nodes);
  uint32_t *dir = malloc((n ? n : 1) * sizeof *dir);
  uint32_t *nrm = malloc((n ? n : 1) * sizeof *nrm);
  unsigned char *spec = n <= SIZE_MAX / sz ? malloc((n ? n : 1) * sz) : NULL;
  if (!order || !nodes || !dir || !nrm || !spec) goto nomem;
  for (size_t i = 0; i < n; i++) {
    memcpy(&order[i].key, m->stage + i * m->rec_size, 8);
    order[i].idx = i;
  }
  if (!sort_records(m, order, n)) goto nomem;

  /* The centre of the bounding box: min and max do not depend on order. */
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  for (size_t i = 0; i < n; i++) {
    double p[3];
    memcpy(p, m->stage + i * m->rec_size + OFF_POS, 24);
    for (int a = 0; a < 3; a++) {
      if (i == 0 || p[a] < lo[a]) lo[a] = p[a];
      if (i == 0 || p[a] > hi[a]) hi[a] = p[a];
    }
  }
  for (int a = 0; a < 3; a++) m->centre[a] = 0.5 * lo[a] + 0.5 * hi[a];

  for (size_t r = 0; r < n; r++) {
    double p[3];
    memcpy(p, m->stage + order[r].idx * m->rec_size + OFF_POS, 24);
    for (int a = 0; a < 3; a++) nodes[r].p[a] = (float)(p[a] - m->centre[a]);
    nodes[r].rank_axis = (uint32_t)r << 2;
  }
  build_tree(nodes, 0, n);
  for (size_t i = 0; i < n; i++) {
    const unsigned char *rec = m->stage + order[rank_of(&nodes[i])].idx * m->rec_size;
    memcpy(&dir[i], rec + OFF_DIR, 4);
    memcpy(&nrm[i], rec + OFF_NRM, 4);
    memcpy(spec + i * sz, rec + OFF_POW, sz);
  }
  free(order);
  free(m->stage);
  m->stage = NULL;
  m->capstage = 0;
  m->nodes = nodes;
  m->dir = dir;
  m->nrm = nrm;
  m->spec = spec;
  m->n = n;
  m->built = true;
  return VR_OK;

nomem:
  free(order);
  free(nodes);
  free(dir);
  free(nrm);
  free(spec);
  return vr_error_set(err, VR_E_NOMEM, "photon map build: out of memory for %zu photons", n);
}

/* --- small accessors ------------------------------------------------------ */

size_t vr_photon_map_count(const vr_photon_map *m) {
  if (!m) return 0;
  if (m->built) return m->n;
  vr_photon_map *w = (vr_photon_map *)m; /* the lock is not part of the value */
  pthread_mutex_lock(&w->lock);
  size_t n = w->built ? w->n : w->nstage;
  pthread_mutex_unlock(&w->lock);
  return n;
}

int vr_photon_map_nbins(const vr_photon_map *m) { return m ? m->nbins : 0; }
bool vr_photon_map_built(const vr_photon_map *m) { return m && m->built; }

size_t vr_photon_map_bytes_per_photon(const vr_photon_map *m) {
  return m ? sizeof(node) + 2 * sizeof(uint32_t) + m->spec_size : 0;
}

vr_status vr_photon_map_get(const vr_photon_map *m, size_t index, double pos[3],
                            double dir_in[3], double normal[3], float *power) {
  if (!m || !m->built || index >= m->n) return VR_E_ARG;
  if (pos)
    for (int a = 0; a < 3; a++) pos[a] = m->centre[a] + (double)m->nodes[index].p[a];
  if (dir_in) oct_decode(m->dir[index], dir_in);
  if (normal) oct_decode(m->nrm[index], normal);
  if (power) {
    const unsigned char *spec = m->spec + index * m->spec_size;
    if (!m->slots) {
      memcpy(power, spec, m->spec_size);
    } else {
      memset(power, 0, sizeof(float) * (size_t)m->nbins);
      for (int s = 0; s < m->slots && slot_power(spec, s) != 0.0f; s++)
        power[slot_bin(m, spec, s)] = slot_power(spec, s);
    }
  }
  return VR_OK;
}

int vr_photon_map_bin(const vr_photon_map *m, double nm) {
  if (!m || !(nm >= m->lambda_min && nm <= m->lambda_max)) return -1;
  int b = (int)floor((nm - m->lambda_min) * m->nbins / (m->lambda_max - m->lambda_min));
  return b < m->nbins ? b : m->nbins - 1;
}

bool vr_photon_map_bin_range(const vr_photon_map *m, int bin, double *lo_nm, double *hi_nm) {
  if (!m || bin < 0 || bin >= m->nbins) return false;
  double span = m->lambda_max - m->lambda_min;
  if (lo_nm) *lo_nm = m->lambda_min + span * bin / m->nbins;
  if (hi_nm) *hi_nm = bin + 1 == m->nbins ? m->lambda_max : m->lambda_min + span * (bin + 1) / m->nbins;
  return true;
}

/* --- queries ------------------------------------------------------------- */

/* One candidate: g2 is the squared "disc distance"
 * max(|p - x|, |dot(p - x, n)| / DISC)^2, the smallest squared radius whose
 * disc holds the photon. */
typedef struct cand {
  double g2, d2;
  uint32_t rank, idx;
} cand;

/* sum[b] += w power[b] for the bins of photon i. */
static void accumulate(const vr_photon_map *m, size_t i, double w, double *sum) {
  const unsigned char *spec = m->spec + i * m->spec_size;
  if (!m->slots) {
    const float *pw = (const float *)spec; /* spec_size is a multiple of 4 */
    for (int b = 0; b < m->nbins; b++) sum[b] += w * (double)pw[b];
  } else if (m->bin_bytes == 1) {
    const unsigned char *bins = spec + 4u * (size_t)m->slots;
    for (int s = 0; s < m->slots; s++) {
      float v = slot_power(spec, s);
      if (v == 0.0f) break;
      sum[bins[s]] += w * (double)v;
    }
  } else {
    for (int s = 0; s < m->slots; s++) {
      float v = slot_power(spec, s);
      if (v == 0.0f) break;
      sum[slot_bin(m, spec, s)] += w * (double)v;
    }
  }
}

static bool cand_less(const cand *a, const cand *b) {
  return a->g2 < b->g2 || (a->g2 == b->g2 && a->rank < b->rank);
}

typedef struct query {
  const vr_photon_map *m;
  double x[3], n[3]; /* x relative to the centre; n unit */
  double rmax2;
  /* kNN: a max-heap of the best k so far (Jensen 2001, sec. 6.3). */
  int k, found;
  cand *heap;
  /* fixed radius: running sums */
  double *sum, kcr; /* kcr = kc r, 0 for the box filter */
} query;

static void heap_sift_down(cand *h, int n, int i) {
  for (;;) {
    int l = 2 * i + 1, r = l + 1, big = i;
    if (l < n && cand_less(&h[big], &h[l])) big = l;
    if (r < n && cand_less(&h[big], &h[r])) big = r;
    if (big == i) return;
    cand t = h[i];
    h[i] = h[big];
    h[big] = t;
    i = big;
  }
}

static void consider(query *q, uint32_t i) {
  const node *p = &q->m->nodes[i];
  double dx = (double)p->p[0] - q->x[0], dy = (double)p->p[1] - q->x[1],
         dz = (double)p->p[2] - q->x[2];
  double d2 = dx * dx + dy * dy + dz * dz;
  bool full = q->heap && q->found == q->k;
  double bound = full ? q->heap[0].g2 : q->rmax2;
  if (d2 > bound) return;
  double t = (dx * q->n[0] + dy * q->n[1] + dz * q->n[2]) * (1.0 / VR_PHOTON_MAP_DISC);
  cand c = {d2 > t * t ? d2 : t * t, d2, rank_of(p), i};
  if (c.g2 > bound) return;
  if (full && !cand_less(&c, &q->heap[0])) return;
  double dir[3];
  oct_decode_raw(q->m->dir[i], dir);
  if (!(dir[0] * q->n[0] + dir[1] * q->n[1] + dir[2] * q->n[2] < 0.0)) return;

  if (!q->heap) { /* fixed radius: add it now */
    double w = q->kcr > 0.0 ? 1.0 - sqrt(d2) / q->kcr : 1.0;
    accumulate(q->m, i, w, q->sum);
    q->found++;
  } else if (!full) {
    int j = q->found++;
    q->heap[j] = c;
    while (j > 0 && cand_less(&q->heap[(j - 1) / 2], &q->heap[j])) {
      cand tmp = q->heap[j];
      q->heap[j] = q->heap[(j - 1) / 2];
      q->heap[(j - 1) / 2] = tmp;
      j = (j - 1) / 2;
    }
  } else {
    q->heap[0] = c;
    heap_sift_down(q->heap, q->k, 0);
  }
}

static void visit(query *q, size_t lo, size_t hi) {
  if (hi - lo <= LEAF) {
    for (size_t i = lo; i < hi; i++) consider(q, (uint32_t)i);
    return;
  }
  size_t mid = lo + (hi - lo) / 2;
  const node *s = &q->m->nodes[mid];
  int ax = axis_of(s);
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
static bool query_init(query *q, const vr_photon_map *m, const double x[3], const double n[3],
                       double radius_max) {
  if (!m || !m->built || !x || !n || !finite3(x) || !finite3(n)) return false;
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
  return true;
}

/* The k nearest into q->heap[0 .. found): in heap order, which depends on
 * the tree alone, or sorted nearest first (ties by key). */
static void knn(query *q, bool sorted) {
  if (q->m->n) visit(q, 0, q->m->n);
  if (!sorted) return;
  for (int end = q->found - 1; end > 0; end--) { /* heap sort, in place */
    cand t = q->heap[0];
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
  query q;
  if (k < 0 || isnan(kc) || (kc > 0.0 && kc < 1.0) || !query_init(&q, m, x, n, radius_max))
    return -1;
  double norm = kc > 0.0 ? 1.0 - 2.0 / (3.0 * kc) : 1.0;
  double r = radius_max;

  if (k == 0) {
    q.sum = out;
    q.kcr = kc > 0.0 ? kc * r : 0.0;
    if (m->n) visit(&q, 0, m->n);
  } else {
    cand stack_heap[STACK_HEAP];
    q.k = k;
    q.heap = k <= STACK_HEAP ? stack_heap : malloc((size_t)k * sizeof(cand));
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
  query q;
  if (!hits || k <= 0 || !query_init(&q, m, x, n, radius_max)) return -1;
  cand stack_heap[STACK_HEAP];
  q.k = k;
  q.heap = k <= STACK_HEAP ? stack_heap : malloc((size_t)k * sizeof(cand));
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
