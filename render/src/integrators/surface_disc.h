/* A density estimate's disc on the surface it estimates: which photons
 * belong to that surface, and what share of the disc the surface covers.
 *
 * A disc of radius r about a point of a floor reaches past the floor's edge
 * into the wall it meets.  Counting the wall's photons there adds the
 * wall's light to the floor (bright lines along every junction where the
 * wall is the brighter); dropping them without more leaves the floor's
 * photons over only part of the disc (dark lines).  The estimate is right
 * when it keeps the photons of the point's own sheet of surface and divides
 * by the disc's area on that sheet:
 *
 *   - a photon belongs to the point's sheet when its surface faces the same
 *     way (geometric normals within 25.8 degrees, |cos| >= 0.9) and lies
 *     on the point's plane (within a quarter of the radius, or 1 cm);
 *   - on a rect, the sheet's extent is known: the rect itself, continued
 *     across an edge only where a coplanar rect of the same material that
 *     photons land on (a diffuse one) carries on past it and no other
 *     surface stands on the edge (a wall cut around a window carries on
 *     across its seams; a floor does not carry on into the ground outside,
 *     under its wall).  Another object's photon inside the rect counts (a
 *     rug on a floor).  Photons of other objects beyond an edge that ends
 *     are not the sheet's, and the estimate divides by the share of the
 *     disc inside the edges that end;
 *   - on a box, each face is a rect whose four edges end: the point's
 *     object's photons count only on the point's face (the normals tell
 *     the faces apart), and the estimate divides by the disc's share on
 *     that face;
 *   - elsewhere (meshes, spheres) the sheet is taken to cover the disc,
 *     and all of the point's own object's photons count (its faces are not
 *     told apart): a junction between two objects that are not rects reads
 *     low within r of it (by half at the junction, a fifth on average over
 *     the strip), one inside a mesh keeps the other face's photons; both
 *     biases shrink with the radius as SPPM's does. */
#ifndef VR_INTEGRATORS_SURFACE_DISC_H
#define VR_INTEGRATORS_SURFACE_DISC_H

#include <stdbool.h>
#include <stdint.h>

#include "world/rscene.h"

/* The edges of a rect (frame f: p = corner + u eu + v ev, u and v in
 * [0, 1]) where its sheet ends; VR_SHEET_BOX marks a box, each of whose
 * six faces is a sheet of its own, every edge of it ending (its
 * neighbours stand on it at right angles). */
enum { VR_EDGE_U0 = 1, VR_EDGE_U1 = 2, VR_EDGE_V0 = 4, VR_EDGE_V1 = 8, VR_EDGE_ALL = 15,
       VR_SHEET_BOX = 16 };

/* Per object: the VR_EDGE_* bits of a rect's edges where no coplanar rect
 * of a diffuse material carries on (VR_EDGE_ALL for a lone rect),
 * VR_SHEET_BOX for a box, 0 for any other object.  NULL when out of
 * memory. */
uint8_t *vr_rect_edges_ending(const vr_rscene *rs);

/* The face of box object o (shape box) whose plane point x lies nearest:
 * its frame (corner, eu, ev in world space, as the geometry builds it). */
void vr_box_face_frame(const vr_scene_object *o, const double x[3], double f[9]);

/* Whether a photon on a face of geometric normal n lies on the same face
 * of a box as a point of geometric normal np: the faces meet at right
 * angles or face away, so the normals agree on one face only. */
bool vr_box_same_face(const double np[3], const double n[3]);

/* The share of a disc (radius r about x, on the rect's plane, weighted by
 * the cone filter of constant kc, or uniformly for kc <= 0) that lies
 * inside the edges `ends` of the rect of frame f; in [0.05, 1].  Returns 1
 * for a parallelogram that is not a rectangle. */
double vr_rect_disc_share(const double f[9], unsigned ends, const double x[3], double r, double kc);

/* Whether point x, projected on the rect's plane, lies on the rect or past
 * only edges that do not end. */
bool vr_rect_sheet_holds(const double f[9], unsigned ends, const double x[3]);

/* Whether a photon at x on a surface of geometric normal n belongs to the
 * sheet of the point at p with geometric normal np, for a disc of radius r
 * (the normals need not be unit). */
bool vr_same_sheet(const double p[3], const double np[3], const double x[3], const double n[3],
                   double r);

#endif
