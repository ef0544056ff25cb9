/* Reading the photon maps (photon_maps.h): irradiance estimates from the
 * k nearest photons of the hit's own object, and the radiance of a diffuse
 * surface lit by them. */
#include <math.h>
#include <string.h>

#include "integrators/photon_maps.h"
#include "vr/vec3.h"

/* The share of a density estimate's disc (radius r about x, weighted by the
 * cone filter of constant kc, or uniformly for kc <= 0) that lies on the
 * rectangle of frame f (p = corner + u eu + v ev, u and v in [0, 1]).  A
 * disc reaching past the rectangle's edge holds that surface's photons
 * over only this share of its area, so the estimate, which divides by the
 * whole disc, reads low by this factor near walls' and floors' edges and
 * corners.  In polar coordinates about x: along each of 128 directions the
 * rectangle ends at distance t, and the filter's integral out to s =
 * min(t, r) is s^2/2 - s^3/(3 kc r) (s^2/2 for the box).  Returns 1 for a
 * parallelogram that is not a rectangle. */
static double rect_disc_share(const double f[9], const double x[3], double r, double kc) {
  double Lu = sqrt(vr_dot3(f + 3, f + 3)), Lv = sqrt(vr_dot3(f + 6, f + 6));
  if (!(Lu > 0) || !(Lv > 0) || !(r > 0) || fabs(vr_dot3(f + 3, f + 6)) > 1e-9 * Lu * Lv) return 1.0;
  double d[3] = {x[0] - f[0], x[1] - f[1], x[2] - f[2]};
  double cx = vr_dot3(d, f + 3) / Lu, cy = vr_dot3(d, f + 6) / Lv;
  cx = cx < 0 ? 0 : cx > Lu ? Lu : cx;
  cy = cy < 0 ? 0 : cy > Lv ? Lv : cy;
  enum { DIRS = 128 };
  double full = kc > 0 ? r * r / 2 - r * r / (3 * kc) : r * r / 2, sum = 0;
  for (int i = 0; i < DIRS; i++) {
    double ph = (i + 0.5) * (2 * M_PI / DIRS), cu = cos(ph), sv = sin(ph), t = r;
    if (cu > 0 && (Lu - cx) / cu < t) t = (Lu - cx) / cu;
    if (cu < 0 && -cx / cu < t) t = -cx / cu;
    if (sv > 0 && (Lv - cy) / sv < t) t = (Lv - cy) / sv;
    if (sv < 0 && -cy / sv < t) t = -cy / sv;
    sum += kc > 0 ? t * t / 2 - t * t * t / (3 * kc * r) : t * t / 2;
  }
  double share = sum / DIRS / full;
  return share < 0.05 ? 0.05 : share > 1 ? 1 : share;
}

/* From the photons of object `surface` only: a floor's estimate never
 * takes the ground's photons from beyond the wall, which share its plane
 * and side (vr_photon_map_store_on). */
int vr_photon_maps_irradiance(const vr_photon_maps *c, const vr_scene_tables *t,
                              const vr_photon_set *ps, const double x[3], const double n[3],
                              uint32_t surface, int k, double radius, int nwl, const double *wl,
                              double *E) {
  /* Edge shares only for photon sensors' gathers: there they remove a 2 %
   * low bias (tests/render/test_photon_sensors.c), but in the camera
   * pass's direct reading of the maps they made the walls by the sample
   * room's east window read far brighter than the path tracer shows, for a
   * reason not yet found (see docs/vr-render.md, "Photon sensors"). */
  const bool edge_share = c->edge_share;
  for (int j = 0; j < nwl; j++) E[j] = 0;
  if (!ps || !vr_photon_set_count(ps)) return 0;
  const vr_photon_map *m = vr_photon_set_map(ps, 0); /* for its bins: all maps share them */
  int nb = vr_photon_map_nbins(m);
  double bins[512], r;
  if (nb > 512) return 0;
  int got = vr_photon_set_irradiance_on(ps, x, n, surface, c->fixed_radius ? 0 : k, radius, 1.1,
                                        bins, &r);
  if (got <= 0) return 0;
  /* On a rect, the disc's part beyond its edges held none of its photons. */
  double share = edge_share && surface != VR_PHOTON_ANY_SURFACE && t->is_rect[surface]
                     ? rect_disc_share(t->rect_frame[surface], x, r, 1.1)
                     : 1.0;
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

