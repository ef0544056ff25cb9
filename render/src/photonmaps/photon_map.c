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
#include "photonmaps/photon_map_internal.h"

#include <stdlib.h>

#define POS_MAX 1e18

/* --- octahedral unit vectors (Cigolle et al., JCGT 3(2), 2014) --------- */

static uint32_t oct_encode(const double v[3]) {
  double s = fabs(v[0]) + fabs(v[1]) + fabs(v[2]);
  double px = v[0] / s, py = v[1] / s;
  if (v[2] < 0.0) {
    double qx = (1.0 - fabs(py)) * pm_sign_nz(px), qy = (1.0 - fabs(px)) * pm_sign_nz(py);
    px = qx;
    py = qy;
  }
  /* rounding by hand: lrint would follow the caller's rounding mode */
  uint32_t ux = (uint32_t)((px * 0.5 + 0.5) * 65535.0 + 0.5);
  uint32_t uy = (uint32_t)((py * 0.5 + 0.5) * 65535.0 + 0.5);
  return ux | uy << 16;
}

static void oct_decode(uint32_t code, double v[3]) {
  pm_oct_decode_raw(code, v);
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
  free(m->surf);
  free(m->keys);
  free(m->spec);
  free(m);
}

static bool nonzero3(const double v[3]) { return v[0] != 0.0 || v[1] != 0.0 || v[2] != 0.0; }

vr_status vr_photon_map_store(vr_photon_map *m, uint64_t key, const double pos[3],
                              const double dir_in[3], const double normal[3],
                              const float *power, vr_error *err) {
  return vr_photon_map_store_on(m, key, pos, dir_in, normal, VR_PHOTON_ANY_SURFACE, power, err);
}

vr_status vr_photon_map_store_on(vr_photon_map *m, uint64_t key, const double pos[3],
                                 const double dir_in[3], const double normal[3],
                                 uint32_t surface, const float *power, vr_error *err) {
  if (!m || !pos || !dir_in || !normal || !power)
    return vr_error_set(err, VR_E_ARG, "photon map store: NULL argument");
  /* Positions become floats about the centre: keep them far inside float range. */
  if (!pm_finite3(pos) || fabs(pos[0]) > POS_MAX || fabs(pos[1]) > POS_MAX || fabs(pos[2]) > POS_MAX)
    return vr_error_set(err, VR_E_RANGE,
                        "photon map store: position (%g, %g, %g) is not finite or beyond 1e18 m",
                        pos[0], pos[1], pos[2]);
  if (!pm_finite3(dir_in) || !nonzero3(dir_in))
    return vr_error_set(err, VR_E_RANGE,
                        "photon map store: direction (%g, %g, %g) is not a finite non-zero vector",
                        dir_in[0], dir_in[1], dir_in[2]);
  if (!pm_finite3(normal) || !nonzero3(normal))
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
      memcpy(r + OFF_SURF, &surface, 4);
      float *pw = (float *)(r + OFF_POW); /* 4-aligned: rec_size is a multiple of 8, OFF_POW of 4 */
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
typedef struct vr_keyed_photon {
  uint64_t key;
  uint64_t idx;
} vr_keyed_photon;

/* A sparse record against another in the order memcmp gives their dense
 * forms (bins in turn, the bytes of each float in memory order), so a
 * sparse map orders photons of equal keys as a dense map does. */
static int sparse_cmp(const vr_photon_map *m, const unsigned char *a, const unsigned char *b) {
  int i = 0, j = 0;
  for (;;) {
    int ba = i < m->slots && pm_slot_power(a, i) != 0.0f ? pm_slot_bin(m, a, i) : m->nbins;
    int bb = j < m->slots && pm_slot_power(b, j) != 0.0f ? pm_slot_bin(m, b, j) : m->nbins;
    if (ba == m->nbins && bb == m->nbins) return 0;
    int bin = ba < bb ? ba : bb;
    float fa = ba == bin ? pm_slot_power(a, i++) : 0.0f, fb = bb == bin ? pm_slot_power(b, j++) : 0.0f;
    int c = memcmp(&fa, &fb, 4);
    if (c) return c;
  }
}

static bool keyed_less(const vr_photon_map *m, const vr_keyed_photon *a, const vr_keyed_photon *b) {
  if (a->key != b->key) return a->key < b->key;
  const unsigned char *ra = m->stage + a->idx * m->rec_size, *rb = m->stage + b->idx * m->rec_size;
  if (!m->slots) return memcmp(ra + 8, rb + 8, m->rec_size - 8) < 0;
  int c = memcmp(ra + 8, rb + 8, OFF_POW - 8);
  return (c ? c : sparse_cmp(m, ra + OFF_POW, rb + OFF_POW)) < 0;
}

/* Bottom-up merge sort, stable (qsort has no context argument in C17). */
static bool sort_records(const vr_photon_map *m, vr_keyed_photon *v, size_t n) {
  vr_keyed_photon *tmp = malloc((n ? n : 1) * sizeof *tmp);
  if (!tmp) return false;
  vr_keyed_photon *src = v, *dst = tmp;
  for (size_t w = 1; w < n; w *= 2) {
    for (size_t lo = 0; lo < n; lo += 2 * w) {
      size_t mid = lo + w < n ? lo + w : n, hi = lo + 2 * w < n ? lo + 2 * w : n;
      size_t i = lo, j = mid, o = lo;
      while (i < mid && j < hi) dst[o++] = keyed_less(m, &src[j], &src[i]) ? src[j++] : src[i++];
      while (i < mid) dst[o++] = src[i++];
      while (j < hi) dst[o++] = src[j++];
    }
    vr_keyed_photon *t = src;
    src = dst;
    dst = t;
  }
  if (src != v) memcpy(v, src, n * sizeof *v);
  free(tmp);
  return true;
}


/* A strict total order along an axis: coordinate, then rank. */
static bool node_less(const vr_pm_node *a, const vr_pm_node *b, int ax) {
  return a->p[ax] < b->p[ax] || (a->p[ax] == b->p[ax] && pm_rank(a) < pm_rank(b));
}

static void swap_nodes(vr_pm_node *a, vr_pm_node *b) {
  vr_pm_node t = *a;
  *a = *b;
  *b = t;
}

/* Puts the element of order kth of [lo, hi) at kth, smaller ones before it
 * and larger ones after (quickselect, median-of-three pivots).  No two
 * elements compare equal, so there is no degenerate case of equal keys. */
static void select_nth(vr_pm_node *v, size_t lo, size_t hi, size_t kth, int ax) {
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
static void build_tree(vr_pm_node *v, size_t lo, size_t hi) {
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
  vr_keyed_photon *order = malloc((n ? n : 1) * sizeof *order);
  vr_pm_node *nodes = malloc((n ? n : 1) * sizeof *nodes);
  uint32_t *dir = malloc((n ? n : 1) * sizeof *dir);
  uint32_t *nrm = malloc((n ? n : 1) * sizeof *nrm);
  uint32_t *surf = malloc((n ? n : 1) * sizeof *surf);
  uint64_t *keys = malloc((n ? n : 1) * sizeof *keys);
  unsigned char *spec = n <= SIZE_MAX / sz ? malloc((n ? n : 1) * sz) : NULL;
  if (!order || !nodes || !dir || !nrm || !surf || !keys || !spec) goto nomem;
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
  if (!m->centre_given)
    for (int a = 0; a < 3; a++) m->centre[a] = 0.5 * lo[a] + 0.5 * hi[a];

  for (int a = 0; a < 3; a++) {
    m->lo[a] = INFINITY;
    m->hi[a] = -INFINITY;
  }
  for (size_t r = 0; r < n; r++) {
    double p[3];
    memcpy(p, m->stage + order[r].idx * m->rec_size + OFF_POS, 24);
    for (int a = 0; a < 3; a++) {
      nodes[r].p[a] = (float)(p[a] - m->centre[a]);
      if (nodes[r].p[a] < m->lo[a]) m->lo[a] = nodes[r].p[a];
      if (nodes[r].p[a] > m->hi[a]) m->hi[a] = nodes[r].p[a];
    }
    nodes[r].rank_axis = (uint32_t)r << 2;
  }
  build_tree(nodes, 0, n);
  for (size_t i = 0; i < n; i++) {
    const unsigned char *rec = m->stage + order[pm_rank(&nodes[i])].idx * m->rec_size;
    keys[i] = order[pm_rank(&nodes[i])].key;
    memcpy(&dir[i], rec + OFF_DIR, 4);
    memcpy(&nrm[i], rec + OFF_NRM, 4);
    memcpy(&surf[i], rec + OFF_SURF, 4);
    memcpy(spec + i * sz, rec + OFF_POW, sz);
  }
  free(order);
  free(m->stage);
  m->stage = NULL;
  m->capstage = 0;
  m->nodes = nodes;
  m->dir = dir;
  m->nrm = nrm;
  m->surf = surf;
  m->keys = keys;
  m->spec = spec;
  m->n = n;
  m->built = true;
  return VR_OK;

nomem:
  free(order);
  free(nodes);
  free(dir);
  free(nrm);
  free(surf);
  free(keys);
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
  return m ? sizeof(vr_pm_node) + sizeof(uint64_t) + 3 * sizeof(uint32_t) + m->spec_size : 0;
}

size_t vr_photon_map_bytes(const vr_photon_map *m) {
  if (!m) return 0;
  if (m->built) return sizeof *m + m->n * vr_photon_map_bytes_per_photon(m);
  vr_photon_map *w = (vr_photon_map *)m; /* the lock is not part of the value */
  pthread_mutex_lock(&w->lock);
  size_t b = sizeof *m + w->capstage * w->rec_size;
  pthread_mutex_unlock(&w->lock);
  return b;
}

vr_status vr_photon_map_set_centre(vr_photon_map *m, const double centre[3], vr_error *err) {
  if (!m || !centre) return vr_error_set(err, VR_E_ARG, "photon map: NULL argument");
  if (!pm_finite3(centre))
    return vr_error_set(err, VR_E_RANGE, "photon map: centre (%g, %g, %g) is not finite",
                        centre[0], centre[1], centre[2]);
  pthread_mutex_lock(&m->lock);
  vr_status st = VR_OK;
  if (m->built || m->nstage)
    st = vr_error_set(err, VR_E_ARG, "photon map: the centre is set before the first store");
  else {
    memcpy(m->centre, centre, sizeof m->centre);
    m->centre_given = true;
  }
  pthread_mutex_unlock(&m->lock);
  return st;
}

uint32_t vr_photon_map_surface(const vr_photon_map *m, size_t index) {
  return m && m->built && index < m->n ? m->surf[index] : VR_PHOTON_ANY_SURFACE;
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
      for (int s = 0; s < m->slots && pm_slot_power(spec, s) != 0.0f; s++)
        power[pm_slot_bin(m, spec, s)] = pm_slot_power(spec, s);
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


size_t vr_photon_map_record_size(const vr_photon_map *m) { return m ? m->rec_size : 0; }

size_t vr_photon_map_staged(const vr_photon_map *m, const unsigned char **records) {
  *records = m && !m->built ? m->stage : NULL;
  return m && !m->built ? m->nstage : 0;
}

vr_status vr_photon_map_add_records(vr_photon_map *m, const unsigned char *records, size_t n,
                                    vr_error *err) {
  if (!m || (n && !records)) return vr_error_set(err, VR_E_ARG, "photon map: NULL argument");
  pthread_mutex_lock(&m->lock);
  vr_status st = VR_OK;
  if (m->built) {
    st = vr_error_set(err, VR_E_ARG, "photon map: records added after the build");
  } else if (m->nstage + n > VR_PHOTON_MAP_MAX) {
    st = vr_error_set(err, VR_E_RANGE, "photon map: more than %zu photons", VR_PHOTON_MAP_MAX);
  } else if (m->nstage + n > m->capstage) {
    size_t cap = m->capstage ? m->capstage : 1024;
    while (cap < m->nstage + n) cap *= 2;
    unsigned char *s = realloc(m->stage, cap * m->rec_size);
    if (!s)
      st = vr_error_set(err, VR_E_NOMEM, "photon map: out of memory at %zu photons", m->nstage);
    else
      m->stage = s, m->capstage = cap;
  }
  if (!st && n) {
    memcpy(m->stage + m->nstage * m->rec_size, records, n * m->rec_size);
    m->nstage += n;
  }
  pthread_mutex_unlock(&m->lock);
  return st;
}
