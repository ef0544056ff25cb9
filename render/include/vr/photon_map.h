/* A spectral photon map (Jensen, "Global illumination using photon maps",
 * EGWR 1996, and "Realistic Image Synthesis Using Photon Mapping", 2001):
 * photons stored where they land on surfaces, a balanced kd-tree over them,
 * and the density estimate of reflected flux at a surface point.
 *
 * Each photon carries its power in nbins equal-width wavelength bins.  The
 * map is deterministic: every photon comes with a 64-bit key (typically the
 * counter of the random stream that made it), the build orders photons by
 * key, and ties in distance are broken by key, so the tree and every
 * estimate are bit-identical whatever order or thread the stores came from.
 *
 * Storage: positions are floats relative to the centre of the photons'
 * bounding box, so their resolution is 2^-25 of the scene's extent
 * (3 um for a 100 m scene) however far the scene sits from the origin;
 * doubles would add 12 bytes a photon for precision a gather radius of
 * millimetres never uses.  Directions and normals are octahedral-encoded in
 * 2 x 16 bits (Cigolle et al., JCGT 2014; error < 0.004 degrees).  Power:
 * a dense map (vr_photon_map_create) keeps all nbins floats, P = 4 nbins
 * bytes; a sparse map (vr_photon_map_create_sparse) keeps only the non-zero
 * bins, as max_nonzero (power float, bin index) pairs, P = max_nonzero
 * (4 + c) bytes with c = 1 for nbins <= 256, else 2 (when that is not less
 * than 4 nbins it keeps the dense form instead).  A built map costs 36 + P
 * bytes a photon (vr_photon_map_bytes_per_photon: 16 of tree node, 8 of
 * key, 8 of direction and normal, 4 of surface); before it, a staged
 * photon takes 44 + P bytes rounded up to 8, and the build briefly holds
 * both plus 32 bytes a photon for sorting.  For 10 nm bins over 400-700 or
 * 360-830 nm (30 or 47 bins) and photons of 4 or 8 hero wavelengths:
 *
 *                          built (B/photon)     staged (B/photon)
 *                          30 bins  47 bins     30 bins  47 bins
 *   dense                    156      224         168      232
 *   sparse, max_nonzero 4     56       56          64       64
 *   sparse, max_nonzero 8     76       76          88       88
 *
 * Both forms give the same photons back (vr_photon_map_get) and
 * bit-identical estimates: per bin, the same products are summed in the
 * same photon order; a dense map only adds zeros besides.
 *
 * Threads: vr_photon_map_store may be called from several threads at once;
 * vr_photon_map_build runs alone; after it, queries are read-only and may
 * run from any number of threads. */
#ifndef VR_PHOTON_MAP_H
#define VR_PHOTON_MAP_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include "vr/error.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Half-thickness of the gather disc as a fraction of its radius.  The
 * neighbourhood of radius r is the ball of radius r cut to the slab
 * |dot(p - x, n)| <= 0.1 r (Jensen 2001, ch. 7: compress the sphere into
 * a disc so photons on nearby surfaces of other orientation stay out).
 * 0.1 keeps every photon of a curved surface whose radius of curvature is at
 * least 5 r (its sag at distance r is r^2 / 2R <= 0.1 r) and is far above
 * the float resolution and ray-offset noise of stored positions. */
#define VR_PHOTON_MAP_DISC 0.1

/* Photons a map can hold (ranks are kept in 30 bits). */
#define VR_PHOTON_MAP_MAX ((size_t)1 << 30)

typedef struct vr_photon_map vr_photon_map;

/* nbins spectral bins (1 to 65536) of equal width over [lambda_min,
 * lambda_max] nm; each photon carries its power per bin (W).  Dense. */
vr_photon_map *vr_photon_map_create(int nbins, double lambda_min, double lambda_max,
                                    vr_error *err);

/* The same, sparse: each photon may have at most max_nonzero non-zero bins
 * (a photon of n hero wavelengths has at most n), and only those are kept.
 * max_nonzero >= 1 (VR_E_ARG otherwise); a value above nbins is taken as
 * nbins.  Stores of photons with more non-zero bins are refused (see
 * vr_photon_map_store).  Behaves as a dense map in every other way. */
vr_photon_map *vr_photon_map_create_sparse(int nbins, double lambda_min, double lambda_max,
                                           int max_nonzero, vr_error *err);
void vr_photon_map_destroy(vr_photon_map *m);

/* Stores one photon.  Thread-safe.  key orders photons deterministically.
 * dir_in: the direction the photon travelled (any length > 0); normal: the
 * geometric normal of the surface hit (any length > 0, either side); power:
 * nbins values >= 0 (a -0 is kept as +0).  Non-finite or negative values,
 * coordinates beyond 1e18 m, and (sparse maps) more non-zero power bins
 * than the map's max_nonzero are refused with VR_E_RANGE; NULL pointers,
 * and stores after the build, with VR_E_ARG.  A refused photon is not kept
 * (the map is unchanged; the error message says why).  The
 * normal is kept for callers (vr_photon_map_get), e.g. to precompute
 * irradiance at photon positions (Christensen 1999); the estimates below
 * use only the direction. */
vr_status vr_photon_map_store(vr_photon_map *m, uint64_t key, const double pos[3],
                              const double dir_in[3], const double normal[3],
                              const float *power, vr_error *err);

/* The surface a photon landed on, for estimates that must not mix
 * surfaces: a floor and the ground outside its wall lie in one plane and
 * face the same way, so neither the disc nor the side rule keeps the
 * ground's photons out of the floor's estimate (light leaking under the
 * wall).  The renderer passes its object index.  VR_PHOTON_ANY_SURFACE:
 * no surface (vr_photon_map_store); as a query's surface: every photon. */
#define VR_PHOTON_ANY_SURFACE UINT32_MAX
vr_status vr_photon_map_store_on(vr_photon_map *m, uint64_t key, const double pos[3],
                                 const double dir_in[3], const double normal[3],
                                 uint32_t surface, const float *power, vr_error *err);
/* Photon index's surface (VR_PHOTON_ANY_SURFACE for a bad index). */
uint32_t vr_photon_map_surface(const vr_photon_map *m, size_t index);

/* Staged photons as raw records, for moving them between processes before
 * the build: *records points at vr_photon_map_staged() records of
 * vr_photon_map_record_size() bytes each, valid until the next store or
 * the build.  vr_photon_map_add_records stores records another map of the
 * same nbins, range and sparsity staged (VR_E_ARG after the build).  A map
 * built from its own photons plus another's records is the map that would
 * have been built had every photon been stored in it: the build orders by
 * key whatever the order of arrival. */
size_t vr_photon_map_record_size(const vr_photon_map *m);
size_t vr_photon_map_staged(const vr_photon_map *m, const unsigned char **records);
vr_status vr_photon_map_add_records(vr_photon_map *m, const unsigned char *records, size_t n,
                                    vr_error *err);

/* Orders the photons by key (then by content, for equal keys) and builds a
 * balanced kd-tree: median splits along the longest axis of each subset's
 * bounding box.  A second call does nothing.  Not concurrent with stores. */
vr_status vr_photon_map_build(vr_photon_map *m, vr_error *err);

/* Photons stored so far (before the build) or in the map (after). */
size_t vr_photon_map_count(const vr_photon_map *m);
int vr_photon_map_nbins(const vr_photon_map *m);
bool vr_photon_map_built(const vr_photon_map *m);
/* What a photon of the built map costs: 32 + P bytes (see the top). */
size_t vr_photon_map_bytes_per_photon(const vr_photon_map *m);
/* Bytes the map holds now: its photons (built) or its staging buffer. */
size_t vr_photon_map_bytes(const vr_photon_map *m);

/* Positions are stored as floats relative to this point instead of the
 * middle of the photons' bounding box.  Maps that are to answer as one
 * (vr/photon_set.h) share a centre, so that a photon's distance to a query
 * point comes out bit for bit the same whichever map holds it.  Before the
 * first store only (VR_E_ARG after); VR_E_RANGE for a non-finite centre. */
vr_status vr_photon_map_set_centre(vr_photon_map *m, const double centre[3], vr_error *err);

/* Flux density (irradiance) estimate at x on a surface of normal n (any
 * length > 0).  Only photons arriving from the side n points to count
 * (dot(dir_in, n) < 0), and only inside the disc: |p - x| <= r and
 * |dot(p - x, n)| <= VR_PHOTON_MAP_DISC r.
 *   k > 0: the k nearest such photons within radius_max, ties broken by key;
 *          r is the smallest radius whose disc holds them (the k-th smallest
 *          max(|p - x|, |dot(p - x, n)| / VR_PHOTON_MAP_DISC)), or
 *          radius_max when fewer than k are found;
 *   k == 0: every such photon within r = radius_max.
 * kc >= 1: cone filter (Jensen 2001 eq. 7.6), w = 1 - |p - x| / (kc r),
 * normalised by 1 - 2 / (3 kc); kc <= 0: box filter (w = 1).
 *   out[b] = sum_p w_p power_p[b] / ((1 - 2/(3 kc)) pi r^2)   (W/m^2 per bin)
 * Sums run in an order that depends on the built tree alone, which the keys
 * fix, so estimates are bit-reproducible.
 * *r_used (may be NULL) gets r.  Returns the number of photons used, or -1
 * with out zeroed on a bad argument (NULL pointer, k < 0, radius_max not
 * finite and > 0, 0 < kc < 1, non-finite x, zero n), on a map not yet
 * built, on memory exhaustion, or when the k nearest photons all lie at x
 * itself (r = 0: no density can be formed; use a fixed radius there). */
int vr_photon_map_irradiance(const vr_photon_map *m, const double x[3], const double n[3],
                             int k, double radius_max, double kc, double *out,
                             double *r_used);

/* The neighbourhood an estimate with the same arguments (k > 0) uses, for
 * callers weighting photons by a BRDF: up to k photons, nearest first (ties
 * by key).  hits has room for k.  Returns the number found, or -1 as above. */
typedef struct vr_photon_hit {
  size_t index; /* for vr_photon_map_get */
  double dist;  /* |p - x| */
} vr_photon_hit;
int vr_photon_map_locate(const vr_photon_map *m, const double x[3], const double n[3], int k,
                         double radius_max, vr_photon_hit *hits, double *r_used);

/* Photon index (0 <= index < count, in the built map's order, which is the
 * same for any order of stores) as stored: position (float-rounded), unit
 * direction and normal (as decoded), power (nbins, dense for sparse maps
 * too).  Any output may be NULL.
 * VR_E_ARG before the build or for an index out of range. */
vr_status vr_photon_map_get(const vr_photon_map *m, size_t index, double pos[3],
                            double dir_in[3], double normal[3], float *power);

/* --- Gathering, for several maps answering as one ------------------------
 *
 * A candidate photon of a query at x with normal n: its squared disc
 * distance g2 = max(|p - x|, |dot(p - x, n)| / VR_PHOTON_MAP_DISC)^2 (the
 * smallest squared radius whose disc holds it), its squared distance d2,
 * its key, its index in its map and the caller's label for the map.  The
 * k nearest of a map are the k first in the order (g2, key), which is the
 * order vr_photon_map_irradiance breaks ties in when keys are distinct. */
typedef struct vr_photon_cand {
  double g2, d2;
  uint64_t key;
  uint32_t index, map;
} vr_photon_cand;

/* A growable list of candidates.  It may start on a caller's buffer
 * (borrowed = true: never freed here, copied out when it must grow). */
typedef struct vr_photon_list {
  vr_photon_cand *c;
  size_t n, cap;
  bool borrowed;
} vr_photon_list;
bool vr_photon_list_reserve(vr_photon_list *l, size_t cap);
void vr_photon_list_free(vr_photon_list *l);

/* Appends the photons of m that arrive from n's side and lie in the disc
 * of squared radius bound2 around x (g2 <= bound2): all of them when
 * k == 0, else the k first in (g2, key) order (in heap order: the first
 * appended is the farthest of them).  Returns how many were
 * appended, or -1 (nothing appended) on a bad argument, a map not built,
 * or memory exhaustion. */
long vr_photon_map_gather(const vr_photon_map *m, uint32_t label, const double x[3],
                          const double n[3], int k, double bound2, vr_photon_list *out);
/* The same among the photons of one surface only (VR_PHOTON_ANY_SURFACE:
 * all, as vr_photon_map_gather). */
long vr_photon_map_gather_on(const vr_photon_map *m, uint32_t label, const double x[3],
                             const double n[3], uint32_t surface, int k, double bound2,
                             vr_photon_list *out);
/* Squared distance from x to the bounding box of m's photons, INFINITY
 * for an empty or unbuilt map.  It is never above the d2 that a gather at
 * x computes for any photon of m, so a map whose box_d2 exceeds a bound
 * has no photon within it. */
double vr_photon_map_box_d2(const vr_photon_map *m, const double x[3]);
/* sum[b] += w power[b] over the bins of photon `index`. */
void vr_photon_map_add(const vr_photon_map *m, uint32_t index, double w, double *sum);

/* Bin of a wavelength (lambda_max falls in the last bin), -1 outside
 * [lambda_min, lambda_max] or NaN; and the wavelength range of a bin, for
 * callers converting W per bin to W/nm (false for a bin out of range). */
int vr_photon_map_bin(const vr_photon_map *m, double nm);
bool vr_photon_map_bin_range(const vr_photon_map *m, int bin, double *lo_nm, double *hi_nm);

#ifdef __cplusplus
}
#endif
#endif
