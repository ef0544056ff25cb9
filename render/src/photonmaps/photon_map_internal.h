/* What the two halves of the photon map share (photon_map.c: creation,
 * staging, the build, accessors; photon_query.c: the density estimates and
 * gathering): the packed layout of a built map and its small decoders.
 * Private to render/. */
#ifndef VR_PHOTON_MAP_INTERNAL_H
#define VR_PHOTON_MAP_INTERNAL_H

#include <math.h>
#include <pthread.h>
#include <stdbool.h>
#include <string.h>

#include "vr/photon_map.h"

#define LEAF 8

/* One photon of the tree: 16 bytes, so four share a cache line.  The rank
 * is the photon's place in key order, which breaks ties in distance and in
 * the median splits; the split axis of an inner node sits in the low bits. */
typedef struct vr_pm_node {
  float p[3]; /* position - centre */
  uint32_t rank_axis;
} vr_pm_node;

struct vr_photon_map {
  int nbins;
  double lambda_min, lambda_max;
  int max_nz;    /* non-zero bins a photon may have (nbins for vr_photon_map_create) */
  int slots;     /* (power, bin) pairs a photon keeps; 0: dense */
  int bin_bytes; /* 1 or 2, sparse only */
  size_t spec_size; /* bytes of a photon's power record */

  /* Staging, before the build: records of rec_size bytes, each
   * key (u64) | pos (3 double) | dir (u32) | normal (u32) | surface (u32) |
   * power record | 0-padding. */
  pthread_mutex_t lock;
  unsigned char *stage;
  size_t nstage, capstage, rec_size;

  /* A centre given by vr_photon_map_set_centre, else the build takes the
   * middle of the photons' bounding box. */
  bool centre_given;

  /* The built map. */
  bool built;
  size_t n;
  double centre[3];
  float lo[3], hi[3];  /* bounds of the stored positions (relative to centre) */
  vr_pm_node *nodes;
  uint64_t *keys;      /* each photon's key, in node order */
  uint32_t *dir, *nrm; /* octahedral, 2 x 16 bits */
  uint32_t *surf;      /* the surface each photon landed on (vr_photon_map_store_on) */
  unsigned char *spec; /* n power records of spec_size bytes */
};

enum { OFF_POS = 8, OFF_DIR = 32, OFF_NRM = 36, OFF_SURF = 40, OFF_POW = 44 };

static inline uint32_t pm_rank(const vr_pm_node *a) { return a->rank_axis >> 2; }
static inline int pm_axis(const vr_pm_node *a) { return (int)(a->rank_axis & 3u); }

/* Bin and power of slot s of a sparse power record. */
static inline int pm_slot_bin(const vr_photon_map *m, const unsigned char *spec, int s) {
  const unsigned char *bins = spec + 4u * (size_t)m->slots;
  if (m->bin_bytes == 1) return bins[s];
  uint16_t b;
  memcpy(&b, bins + 2 * s, 2);
  return b;
}

static inline float pm_slot_power(const unsigned char *spec, int s) {
  float v;
  memcpy(&v, spec + 4 * s, 4);
  return v;
}

static inline double pm_sign_nz(double v) { return v < 0.0 ? -1.0 : 1.0; }

/* The decoded octahedral vector (Cigolle et al., JCGT 3(2), 2014) before
 * normalisation: enough for the sign of a dot product, which is all the
 * side rule asks. */
static inline void pm_oct_decode_raw(uint32_t code, double v[3]) {
  double px = (double)(code & 0xffffu) * (2.0 / 65535.0) - 1.0;
  double py = (double)(code >> 16) * (2.0 / 65535.0) - 1.0;
  double pz = 1.0 - fabs(px) - fabs(py);
  if (pz < 0.0) {
    double qx = (1.0 - fabs(py)) * pm_sign_nz(px), qy = (1.0 - fabs(px)) * pm_sign_nz(py);
    px = qx;
    py = qy;
  }
  v[0] = px;
  v[1] = py;
  v[2] = pz;
}

static inline bool pm_finite3(const double v[3]) {
  return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

#endif
