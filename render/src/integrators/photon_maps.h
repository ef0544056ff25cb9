/* Jensen's photon maps (Jensen 2001) as the photon integrator and the
 * photon sensors use them: tracing photons into them (photon_trace.c) and
 * reading radiance from them at a diffuse hit (photon_maps.c).
 *
 * Three maps by the path a photon took before it met a diffuse surface:
 *   direct   light, then thin elements only (panes) -> diffuse: what
 *            next-event estimation already computes; used only by final
 *            gathering, whose gather points need all the light;
 *   caustic  light, then at least one specular or glossy bounce or
 *            refraction, no diffuse one -> diffuse;
 *   global   at least one diffuse bounce before.
 * Each map is a vr_photon_set: a photon is stored in the map of the cell
 * where it landed, and estimates gather across cells as one map would. */
#ifndef VR_INTEGRATORS_PHOTON_MAPS_H
#define VR_INTEGRATORS_PHOTON_MAPS_H

#include "integrators/pass.h"
#include "vr/photon_set.h"

typedef struct vr_photon_maps {
  vr_photon_set *global, *direct, *caustic;
  double scale;      /* 1 / photons emitted */
  int knn;           /* photons per estimate */
  double radius;     /* the largest (k nearest) or the fixed radius, m */
  bool fixed_radius;
  /* An estimate on a rect is divided by the share of its disc that lies on
   * the rect (edges and corners read low otherwise; surface_disc.h). */
  bool edge_share;
} vr_photon_maps;

enum { VR_MAP_DIRECT = 1, VR_MAP_CAUSTIC = 2, VR_MAP_GLOBAL = 4 };

/* Traces `photons` photons into the maps asked for (the global one, with
 * direct the direct one, and/or the caustic one), with base's depth and
 * sample offset, then builds them and counts their photons; the run counts
 * their memory until vr_photon_maps_free. */
vr_status vr_photon_maps_trace(vr_run *r, const vr_pass *base, vr_photon_maps *m, long photons,
                               bool caustic, bool global, bool direct, vr_error *err);
void vr_photon_maps_free(vr_run *r, vr_photon_maps *m);

/* Irradiance at x (normal n) on object `surface` from set ps: k nearest
 * photons within radius (or all within it when the radius is fixed), per
 * wavelength, of that object; returns the photons used. */
int vr_photon_maps_irradiance(const vr_photon_maps *m, const vr_scene_tables *t,
                              const vr_photon_set *ps, const double x[3], const double n[3],
                              uint32_t surface, int k, double radius, int nwl, const double *wl,
                              double *E);
/* Radiance towards wo of a diffuse hit from the maps in `maps` (VR_MAP_*;
 * restricted to the hit's object), times p->beta: rho/pi E.  *got_global
 * (may be NULL) gets the photons the global map's estimate used. */
void vr_photon_maps_radiance(const vr_photon_maps *m, const vr_rscene *rs, const vr_hit *hit,
                             const double wo[3], const vr_surface *se, const vr_payload *p,
                             int maps, int k, double radius, double *L, int *got_global);

/* The photon pass's flow (photon_trace.c): photons from the lights'
 * sources, landing through the pass's land(). */
extern const vr_flow_ops vr_photon_ops;

#endif
