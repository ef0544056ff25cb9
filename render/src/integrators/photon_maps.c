/* Reading the photon maps (photon_maps.h): irradiance estimates from the
 * k nearest photons of the hit's own object, and the radiance of a diffuse
 * surface lit by them. */
#include <math.h>
#include <string.h>

#include "integrators/photon_maps.h"
#include "integrators/surface_disc.h"
#include "vr/vec3.h"

/* From the photons of object `surface` only: a floor's estimate never
 * takes the ground's photons from beyond the wall, which share its plane
 * and side (vr_photon_map_store_on).  A rect's estimate divides by its
 * disc's share on the rect, every edge of it taken as one that ends.
 * SPPM also takes a coplanar rect's photons past an edge that carries on
 * (surface_disc.h); the maps do not, which is as unbiased and a little
 * noisier at a wall's seams. */
int vr_photon_maps_irradiance(const vr_photon_maps *c, const vr_scene_tables *t,
                              const vr_photon_set *ps, const double x[3], const double n[3],
                              uint32_t surface, int k, double radius, int nwl, const double *wl,
                              double *E) {
  /* Edge shares: in photon sensors' gathers they remove a 2 % low bias
   * (tests/render/test_photon_sensors.c); in the camera pass 7 % at the
   * furnace's junctions (tests/render/test_junctions.c). */
  const bool edge_share = c->edge_share;
  for (int j = 0; j < nwl; j++) E[j] = 0;
  if (!ps || !vr_photon_set_count(ps)) return 0;
  const vr_photon_map *m = vr_photon_set_map(ps, 0); /* for its bins: all maps share them */
  int nb = vr_photon_map_nbins(m);
  double bins[512], r;
  if (nb > 512) return 0;
  bool rect = edge_share && surface != VR_PHOTON_ANY_SURFACE && surface < t->nobjects &&
              t->is_rect[surface];
  int got = vr_photon_set_irradiance_on(ps, x, n, surface, c->fixed_radius ? 0 : k, radius, 1.1,
                                        bins, &r);
  if (got <= 0) return 0;
  /* On a rect, the disc's part beyond its edges held none of its photons. */
  double share = rect ? vr_rect_disc_share(t->rect_frame[surface], VR_EDGE_ALL, x, r, 1.1) : 1.0;
  for (int j = 0; j < nwl; j++) {
    int b = vr_photon_map_bin(m, wl[j]);
    double lo, hi;
    if (b < 0 || !vr_photon_map_bin_range(m, b, &lo, &hi)) continue;
    E[j] = bins[b] * c->scale / (hi - lo) / share;
  }
  return got;
}

void vr_photon_maps_radiance(const vr_photon_maps *c, const vr_rscene *rs, const vr_hit *hit,
                             const double wo[3], const vr_surface *se, const vr_payload *p,
                             int maps, int k, double radius, double *L, int *got_global) {
  double n[3];
  memcpy(n, hit->ng, sizeof n);
  if (vr_dot3(n, wo) < 0)
    for (int a = 0; a < 3; a++) n[a] = -n[a];
  double E[VR_MAX_WL], Et[VR_MAX_WL] = {0}, fc[VR_MAX_WL];
  const vr_photon_set *set[3] = {c->direct, c->caustic, c->global};
  for (int i = 0; i < 3; i++) {
    if (!(maps >> i & 1)) continue;
    int got = vr_photon_maps_irradiance(c, rs->t, set[i], hit->p, n, (uint32_t)hit->object, k,
                                        radius, p->nwl, p->wl, E);
    if (i == 2 && got_global) *got_global = got;
    for (int j = 0; j < p->nwl; j++) Et[j] += E[j];
  }
  /* rho/pi at wo's mirror about the shading normal, turned towards wo. */
  double sn[3] = {se->ns.x, se->ns.y, se->ns.z};
  if (vr_dot3(sn, wo) < 0)
    for (int a = 0; a < 3; a++) sn[a] = -sn[a];
  double refl[3] = {2 * vr_dot3(sn, wo) * sn[0] - wo[0], 2 * vr_dot3(sn, wo) * sn[1] - wo[1],
                    2 * vr_dot3(sn, wo) * sn[2] - wo[2]};
  vr_surface sd = *se; /* the diffuse part (a pbr surface's specular part goes on) */
  sd.pt.only = VR_LOBE_DIFFUSE;
  vr_surface_f(&sd, refl, fc);
  double cs = fabs(vr_dot3(sn, refl));
  for (int j = 0; j < p->nwl; j++) L[j] = p->beta[j] * (cs > 0 ? fc[j] / cs : 0) * Et[j];
}

