/* The photon maps of the sub-domains answering as one map.
 *
 * Each sub-domain (cell) keeps the photons that landed in it, in its own
 * vr_photon_map, so that photon memory is held by the cell that owns it.
 * A density estimate at a point near a cell face needs photons on both
 * sides, so a query walks the maps in order of the distance from the point
 * to each map's bounding box, gathers from each the k best photons within
 * the current bound, and tightens the bound as soon as k are known.
 *
 * Why the answer is the single map's (a proof sketch, checked bit for bit by
 * tests/render/test_photon_set.c).  Let U be the union of the maps and K
 * the k first photons of U in the order (g2, key) with g2 <= rmax^2 (g2 the
 * squared disc distance of vr/photon_map.h).  All maps share one centre
 * (vr_photon_map_set_centre), so each photon's g2 and d2 are the same bits
 * whichever map holds it, and keys are distinct, so (g2, key) is a total
 * order.  Take any photon p of K, in map j.  (1) Map j is visited: its box
 * distance is at most p's d2 <= g2(p) <= the bound at any time, because
 * the bound is rmax^2 or the k-th g2 of a set of k photons of U, which is
 * at least the k-th g2 of U, which is at least g2(p).  (2) The gather of
 * map j returns p: the photons of map j that precede p in (g2, key) order
 * all belong to K (K is a prefix of U's order), so fewer than k precede it,
 * and g2(p) is within the bound.  So every photon of K is gathered, and
 * the k first of the gathered photons are K.  The radius r follows from K
 * alone (sqrt of the k-th g2, or rmax when fewer than k), and the sum over
 * K runs in key order, so the estimate is the same number for any split of
 * the photons into maps: the same as one map holding them all.
 *
 * Threads: stores from any number of threads; build alone; queries from
 * any number of threads after it. */
#ifndef VR_PHOTON_SET_H
#define VR_PHOTON_SET_H

#include <stddef.h>
#include <stdint.h>
#include "vr/error.h"
#include "vr/photon_map.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vr_photon_set vr_photon_set;

/* nmaps sparse maps (vr_photon_map_create_sparse arguments) sharing the
 * position centre `centre` (e.g. the middle of the scene). */
vr_photon_set *vr_photon_set_create(int nmaps, int nbins, double lambda_min, double lambda_max,
                                    int max_nonzero, const double centre[3], vr_error *err);
void vr_photon_set_destroy(vr_photon_set *s);

/* Stores a photon in map `map` (see vr_photon_map_store). */
vr_status vr_photon_set_store(vr_photon_set *s, int map, uint64_t key, const double pos[3],
                              const double dir_in[3], const double normal[3],
                              const float *power, vr_error *err);
/* The same with the surface it landed on (vr_photon_map_store_on). */
vr_status vr_photon_set_store_on(vr_photon_set *s, int map, uint64_t key, const double pos[3],
                                 const double dir_in[3], const double normal[3],
                                 uint32_t surface, const float *power, vr_error *err);
/* Builds every map. */
vr_status vr_photon_set_build(vr_photon_set *s, vr_error *err);

int vr_photon_set_count_maps(const vr_photon_set *s);
const vr_photon_map *vr_photon_set_map(const vr_photon_set *s, int map);
/* Photons in all maps, and the bytes the maps hold. */
size_t vr_photon_set_count(const vr_photon_set *s);
size_t vr_photon_set_bytes(const vr_photon_set *s);

/* The estimate of vr_photon_map_irradiance (same arguments and result)
 * over the union of the maps, its sum taken in key order.  Returns the
 * photons used, or -1 with out zeroed as vr_photon_map_irradiance does. */
int vr_photon_set_irradiance(const vr_photon_set *s, const double x[3], const double n[3], int k,
                             double radius_max, double kc, double *out, double *r_used);
/* The same among the photons of one surface (VR_PHOTON_ANY_SURFACE: all):
 * the k nearest of that surface, the union's answer restricted to it. */
int vr_photon_set_irradiance_on(const vr_photon_set *s, const double x[3], const double n[3],
                                uint32_t surface, int k, double radius_max, double kc,
                                double *out, double *r_used);

#ifdef __cplusplus
}
#endif
#endif
