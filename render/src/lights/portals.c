/* Sky portals: next-event estimation of the sky aimed through the windows.
 *
 * A room lit through its windows sees the sky in a small solid angle; the
 * sky's own importance sampler (by luminance over the whole hemisphere)
 * then sends most shadow rays into walls.  With portals declared, a sky
 * sample is drawn from a mixture: with probability VR_PORTAL_SHARE a point
 * uniform on one portal's part above the shading point's horizontal plane
 * (the sky gives nothing below the horizon; above_part), the portal chosen
 * in proportion to the solid angle it roughly subtends from the shading
 * point times that part's share, otherwise the sky's sampler.  The sample
 * is weighted by the mixture's density
 *   p(w) = q sum_j P_j [ray hits portal j] t_j^2 / (a_j A_j |n_j . w|) + (1 - q) p_sky(w)
 * for a rising w (a_j the share of portal j above the point),
 * the one-sample balance heuristic of the two strategies (Veach 1997,
 * section 9.2.4), so the estimate stays unbiased whatever the portals
 * cover: light that enters another way is still found by the sky share.
 * Portals are only a sampling hint, not geometry.
 *
 * Photons: the far sources (sun, sky, ground glow) also emit through the
 * portals (sources.c, vr_lights_emit_portal_photon), from points uniform over
 * their total area, travelling into the room (along the portal's normal),
 * starting outside the scene on the line through that point and killed if
 * anything but a straight pane stops them before the portal (an overhang
 * shades it).  So that no light is counted twice, the far sources' usual
 * photons are killed where they cross a portal inwards before any
 * scattering (vr_portal_crossed_inward): their light in the room is the
 * portal photons', and only what the outside reflected enters with them.
 * That light is aimed at the portals too: a photon scattered by a diffuse
 * outdoor surface (outside=yes) draws its direction half the time towards
 * a portal (vr_portal_sample from its point), weighted by the mixture's
 * density, after being split into copies by the share of its light the
 * portals would take (vr_portal_form_factor; integrators/photon_trace.c). */
#include <math.h>
#include <stdlib.h>

#include "vr/vec3.h"
#include "lights/lights.h"

vr_status vr_lights_portals_create(vr_lights *L, const vr_scene *s, vr_error *err) {
  L->nportals = 0;
  if (!s->nportals) return VR_OK;
  L->portals = calloc(s->nportals, sizeof *L->portals);
  if (!L->portals) return vr_error_set(err, VR_E_NOMEM, "out of memory for portals");
  for (size_t i = 0; i < s->nportals; i++) {
    const vr_scene_portal *p = &s->portals[i];
    vr_portal *q = &L->portals[i];
    for (int k = 0; k < 3; k++) q->corner[k] = p->corner[k], q->u[k] = p->u[k], q->v[k] = p->v[k];
    double c[3];
    vr_cross3(p->u, p->v, c);
    q->area = sqrt(vr_dot3(c, c));
    for (int k = 0; k < 3; k++) q->n[k] = c[k] / q->area;
    q->uu = vr_dot3(p->u, p->u), q->vv = vr_dot3(p->v, p->v);
  }
  L->nportals = s->nportals;
  L->portal_area_cdf = calloc(s->nportals, sizeof *L->portal_area_cdf);
  if (!L->portal_area_cdf) return vr_error_set(err, VR_E_NOMEM, "out of memory for portals");
  double acc = 0;
  for (size_t i = 0; i < s->nportals; i++) L->portal_area_cdf[i] = (acc += L->portals[i].area);
  L->portal_area = acc;
  return VR_OK;
}

void vr_portal_point(const vr_lights *L, double u0, double u1, double u2, double y[3], size_t *which) {
  double t = u0 * L->portal_area;
  size_t j = 0;
  while (j + 1 < L->nportals && L->portal_area_cdf[j] <= t) j++;
  const vr_portal *q = &L->portals[j];
  for (int k = 0; k < 3; k++) y[k] = q->corner[k] + u1 * q->u[k] + u2 * q->v[k];
  *which = j;
}

/* Where the segment org + t dir, t in (0, tmax], crosses portal q (its
 * plane within its rectangle): the t, or -1. */
static double crossing(const vr_portal *q, const double org[3], const double dir[3], double tmax) {
  double cn = vr_dot3(q->n, dir);
  if (fabs(cn) <= 1e-12) return -1;
  double t = (vr_dot3(q->n, q->corner) - vr_dot3(q->n, org)) / cn;
  if (!(t > 0) || t > tmax) return -1;
  double h[3];
  for (int k = 0; k < 3; k++) h[k] = org[k] + t * dir[k] - q->corner[k];
  double s = vr_dot3(h, q->u) / q->uu, r = vr_dot3(h, q->v) / q->vv;
  return s < 0 || s > 1 || r < 0 || r > 1 ? -1 : t;
}

bool vr_portal_crossed_inward(const vr_lights *L, const double org[3], const double dir[3],
                              double tmax) {
  /* A pane in the portal's plane ends the segment at the crossing itself:
   * count it (the next segment starts just beyond). */
  tmax = tmax * (1 + 1e-6) + 1e-7;
  for (size_t j = 0; j < L->nportals; j++)
    if (vr_dot3(L->portals[j].n, dir) > 0 && crossing(&L->portals[j], org, dir, tmax) > 0) return true;
  return false;
}

/* How much portal j is worth sampling from x: its area over the squared
 * distance to its centre, times the cosine there (a solid-angle estimate,
 * capped at 2 pi), 0 when x lies in its plane. */
/* d = portal q's centre - x; returns |d|^2. */
static double to_centre(const vr_portal *q, const double x[3], double d[3]) {
  for (int k = 0; k < 3; k++) d[k] = q->corner[k] + 0.5 * (q->u[k] + q->v[k]) - x[k];
  return vr_dot3(d, d);
}

static double weight(const vr_portal *q, const double x[3]) {
  double d[3], h = 0;
  double d2 = to_centre(q, x, d);
  double plane = vr_dot3(q->n, q->corner) - vr_dot3(q->n, x);
  if (fabs(plane) <= 1e-9 * (1 + sqrt(d2))) return 0;
  h = fabs(vr_dot3(q->n, d)) / sqrt(d2);
  double w = q->area * h / d2;
  return w < 2 * M_PI ? w : 2 * M_PI;
}

/* The area of triangle (poly[0], poly[k], poly[k + 1]). */
static double fan_triangle(const double poly[5][2], int k) {
  return 0.5 * fabs((poly[k][0] - poly[0][0]) * (poly[k + 1][1] - poly[0][1]) -
                    (poly[k + 1][0] - poly[0][0]) * (poly[k][1] - poly[0][1]));
}

/* The part of portal q above the horizontal plane through x, as a convex
 * polygon in its (s, t) square (the point corner + s u + t v): the square
 * clipped by z(s, t) >= x_z (Sutherland-Hodgman, one plane), at most 5
 * vertices.  Returns its area, a share of the square's 1.  The sky gives
 * nothing below the horizon, so a window seen from above its sill is only
 * worth sampling above x's level: from a point 2 m up a wall facing a
 * window 4 m away whose head is 0.1 m higher, 15 in 16 of the window's
 * directions point down. */
static double above_part(const vr_portal *q, const double x[3], double poly[5][2], int *n) {
  static const double SQ[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  double a = q->corner[2] - x[2], b = q->u[2], c = q->v[2];
  int m = 0;
  for (int i = 0; i < 4; i++) {
    const double *P = SQ[i], *Q = SQ[(i + 1) % 4];
    double fp = a + b * P[0] + c * P[1], fq = a + b * Q[0] + c * Q[1];
    if (fp >= 0) poly[m][0] = P[0], poly[m][1] = P[1], m++;
    if ((fp >= 0) != (fq >= 0)) {
      double t = fp / (fp - fq);
      poly[m][0] = P[0] + t * (Q[0] - P[0]), poly[m][1] = P[1] + t * (Q[1] - P[1]), m++;
    }
  }
  *n = m;
  /* The area as the sum of the fan's triangles about poly[0], the same
   * sum vr_portal_sample walks, so the share the density divides by is the
   * area sampled even for a sliver (a shoelace about the origin would
   * cancel its terms there). */
  double area = 0;
  for (int k = 1; k + 1 < m; k++) area += fan_triangle(poly, k);
  return m >= 3 ? area : 0;
}

/* The share of portal q a sky sample from x may use: 1 for a portal
 * wholly above x (then the square is sampled as it is), its part above
 * x's horizontal plane otherwise. */
static double sky_share(const vr_portal *q, const double x[3]) {
  double lo = q->corner[2] + fmin(0, q->u[2]) + fmin(0, q->v[2]);
  if (lo >= x[2]) return 1;
  double poly[5][2];
  int n;
  return above_part(q, x, poly, &n);
}

void vr_portal_weights_at(const vr_lights *L, const double x[3], bool sky, vr_portal_weights *pw) {
  pw->sky = sky;
  pw->sum = 0;
  for (size_t j = 0; j < L->nportals; j++) {
    pw->share[j] = sky ? sky_share(&L->portals[j], x) : 1;
    pw->sum += pw->w[j] = pw->share[j] > 0 ? weight(&L->portals[j], x) * pw->share[j] : 0;
  }
}

bool vr_portal_sample(const vr_lights *L, const double x[3], const vr_portal_weights *pw,
                      double u0, double u1, double u2, double dir[3]) {
  const double *w = pw->w, *share = pw->share, sum = pw->sum;
  if (!(sum > 0)) return false;
  double t = u0 * sum;
  size_t j = 0;
  while (j + 1 < L->nportals && t >= w[j]) t -= w[j++];
  /* Rounding can carry t past the last usable portal onto one of weight 0
   * (a window wholly below x): nothing to sample there. */
  if (!(w[j] > 0)) return false;
  const vr_portal *q = &L->portals[j];
  double s = u1, r = u2;
  if (share[j] < 1) {
    /* Uniform over the part above x: a triangle of its fan, chosen by
     * area with u1 (reused within it), then a point uniform in it. */
    double poly[5][2];
    int n;
    double total = above_part(q, x, poly, &n), pick = u1 * total, acc = 0;
    if (n < 3) return false;
    int k = 1;
    double tri = 0;
    for (; k + 1 < n; k++) {
      tri = fan_triangle(poly, k);
      if (pick < acc + tri || k + 2 >= n) break;
      acc += tri;
    }
    double f = tri > 0 ? fmin(fmax((pick - acc) / tri, 0), 1) : 0, sf = sqrt(f);
    double b0 = 1 - sf, b1 = u2 * sf, b2 = 1 - b0 - b1;
    s = b0 * poly[0][0] + b1 * poly[k][0] + b2 * poly[k + 1][0];
    r = b0 * poly[0][1] + b1 * poly[k][1] + b2 * poly[k + 1][1];
  }
  double y[3], len2 = 0;
  for (int k = 0; k < 3; k++) {
    y[k] = q->corner[k] + s * q->u[k] + r * q->v[k] - x[k];
    len2 += y[k] * y[k];
  }
  if (!(len2 > 0)) return false;
  double len = sqrt(len2);
  for (int k = 0; k < 3; k++) dir[k] = y[k] / len;
  return fabs(vr_dot3(q->n, dir)) > 1e-12;
}

double vr_portal_pdf(const vr_lights *L, const double x[3], const vr_portal_weights *pw,
                     const double dir[3]) {
  const double *w = pw->w, *share = pw->share, sum = pw->sum;
  double pdf = 0;
  if (!(sum > 0)) return 0;
  /* For the sky, only directions that rise: the part sampled is above x. */
  if (pw->sky && dir[2] < 0) return 0;
  for (size_t j = 0; j < L->nportals; j++) {
    if (!(w[j] > 0)) continue;
    const vr_portal *q = &L->portals[j];
    double cn = vr_dot3(q->n, dir);
    double t = crossing(q, x, dir, INFINITY);
    if (!(t > 0)) continue;
    pdf += w[j] / sum * t * t / (q->area * share[j] * fabs(cn));
  }
  return pdf;
}

double vr_portal_form_factor(const vr_lights *L, const double x[3], const double n[3]) {
  double F = 0;
  for (size_t j = 0; j < L->nportals; j++) {
    const vr_portal *q = &L->portals[j];
    double d[3], d2 = to_centre(q, x, d);
    if (!(d2 > 0)) continue;
    double len = sqrt(d2), cx = vr_dot3(n, d) / len, cq = fabs(vr_dot3(q->n, d)) / len;
    if (cx > 0) F += q->area * cx * cq / (M_PI * d2);
  }
  return F < 1 ? F : 1;
}
