/* A density estimate's disc on the surface it estimates (surface_disc.h). */
#include "integrators/surface_disc.h"

#include <math.h>
#include <stdlib.h>

#include "vr/bsdf.h"
#include "vr/geometry.h"
#include "vr/scene.h"
#include "vr/vec3.h"

/* Coplanar: unit normals within 2.6 degrees, and a point of one within
 * 1 cm of the other's plane (a rug on a floor, a wall cut in pieces). */
#define COPLANAR_COS 0.999
#define COPLANAR_DIST 0.01
/* One sheet at a density estimate: normals within 25.8 degrees (the facets
 * of a smooth mesh about one point), the plane within r/4 or 1 cm. */
#define SHEET_COS 0.9
#define SHEET_DIST 0.01

static void unit_normal(const double f[9], double n[3]) {
  vr_cross3(f + 3, f + 6, n);
  double l = sqrt(vr_dot3(n, n));
  for (int a = 0; a < 3; a++) n[a] = l > 0 ? n[a] / l : 0;
}

/* x's coordinates (u, v) in the parallelogram of frame f and its distance
 * to the plane; false for a degenerate frame. */
static bool frame_coords(const double f[9], const double x[3], double *u, double *v,
                         double *dist) {
  double d[3] = {x[0] - f[0], x[1] - f[1], x[2] - f[2]};
  double a = vr_dot3(f + 3, f + 3), b = vr_dot3(f + 3, f + 6), c = vr_dot3(f + 6, f + 6);
  double det = a * c - b * b;
  if (!(det > 1e-18 * a * c)) return false;
  double p = vr_dot3(d, f + 3), q = vr_dot3(d, f + 6);
  *u = (c * p - b * q) / det;
  *v = (a * q - b * p) / det;
  double n[3];
  unit_normal(f, n);
  *dist = fabs(vr_dot3(d, n));
  return true;
}

static bool photons_land_on(const vr_rscene *rs, size_t o) {
  int m = rs->obj[o].material;
  return m >= 0 && (size_t)m < rs->nmat && (vr_bsdf_lobes(rs->mat[m].bsdf) & VR_LOBE_DIFFUSE);
}

/* Each rect's bounds, 1 cm larger: the cheap test before the plane's. */
typedef struct rect_box {
  double lo[3], hi[3];
} rect_box;

static rect_box box_of(const double f[9]) {
  rect_box b;
  for (int a = 0; a < 3; a++) {
    double c[4] = {f[a], f[a] + f[3 + a], f[a] + f[6 + a], f[a] + f[3 + a] + f[6 + a]};
    b.lo[a] = fmin(fmin(c[0], c[1]), fmin(c[2], c[3])) - COPLANAR_DIST;
    b.hi[a] = fmax(fmax(c[0], c[1]), fmax(c[2], c[3])) + COPLANAR_DIST;
  }
  return b;
}

static bool in_box(const rect_box *b, const double x[3]) {
  return x[0] >= b->lo[0] && x[0] <= b->hi[0] && x[1] >= b->lo[1] && x[1] <= b->hi[1] &&
         x[2] >= b->lo[2] && x[2] <= b->hi[2];
}

/* Whether point x (just past an edge of rect o) lies on another rect,
 * coplanar with o, of o's material, that photons land on.  A floor and
 * the ground outside share a plane; they are not one sheet. */
static bool covered(const vr_rscene *rs, const rect_box *boxes, size_t o, const double x[3]) {
  const vr_scene_tables *t = rs->t;
  double n[3];
  unit_normal(t->rect_frame[o], n);
  for (size_t j = 0; j < t->nobjects; j++) {
    if (j == o || !t->is_rect[j] || !in_box(&boxes[j], x) || !photons_land_on(rs, j)) continue;
    if (rs->obj[j].material != rs->obj[o].material) continue;
    double m[3], u, v, dist;
    unit_normal(t->rect_frame[j], m);
    if (fabs(vr_dot3(n, m)) < COPLANAR_COS) continue;
    if (!frame_coords(t->rect_frame[j], x, &u, &v, &dist) || dist > COPLANAR_DIST) continue;
    if (u >= 0 && u <= 1 && v >= 0 && v <= 1) return true;
  }
  return false;
}

/* Whether point x (on an edge of rect o) lies on a rect that is not
 * coplanar with o, within 1 cm: a wall standing on a floor's edge, which
 * the floor's sheet does not cross whatever lies in its plane beyond. */
static bool met(const vr_rscene *rs, const rect_box *boxes, size_t o, const double x[3]) {
  const vr_scene_tables *t = rs->t;
  double n[3];
  unit_normal(t->rect_frame[o], n);
  for (size_t j = 0; j < t->nobjects; j++) {
    if (j == o || !t->is_rect[j] || !in_box(&boxes[j], x)) continue;
    const double *f = t->rect_frame[j];
    double m[3], u, v, dist;
    unit_normal(f, m);
    if (fabs(vr_dot3(n, m)) >= COPLANAR_COS) continue;
    if (!frame_coords(f, x, &u, &v, &dist) || dist > COPLANAR_DIST) continue;
    double tu = COPLANAR_DIST / sqrt(vr_dot3(f + 3, f + 3));
    double tv = COPLANAR_DIST / sqrt(vr_dot3(f + 6, f + 6));
    if (u >= -tu && u <= 1 + tu && v >= -tv && v <= 1 + tv) return true;
  }
  return false;
}

uint8_t *vr_rect_edges_ending(const vr_rscene *rs) {
  const vr_scene_tables *t = rs->t;
  uint8_t *ends = calloc(t->nobjects ? t->nobjects : 1, 1);
  rect_box *boxes = malloc((t->nobjects ? t->nobjects : 1) * sizeof *boxes);
  if (!ends || !boxes) {
    free(ends);
    free(boxes);
    return NULL;
  }
  for (size_t o = 0; o < t->nobjects; o++)
    if (t->is_rect[o]) boxes[o] = box_of(t->rect_frame[o]);
  for (size_t o = 0; o < t->nobjects; o++) {
    if (rs->s && o < rs->s->nobjects && rs->s->objects[o].shape == VR_SHAPE_BOX)
      ends[o] = VR_SHEET_BOX;
    if (!t->is_rect[o]) continue;
    const double *f = t->rect_frame[o];
    double Lu = sqrt(vr_dot3(f + 3, f + 3)), Lv = sqrt(vr_dot3(f + 6, f + 6));
    if (!(Lu > 0) || !(Lv > 0)) continue;
    /* Each edge: its start, its direction along, and outwards (unit). */
    for (int e = 0; e < 4; e++) {
      const double *along = e < 2 ? f + 6 : f + 3, *across = e < 2 ? f + 3 : f + 6;
      double La = e < 2 ? Lu : Lv, sg = e % 2 ? 1.0 : -1.0;
      double start[3], out[3];
      for (int a = 0; a < 3; a++) {
        start[a] = f[a] + (e % 2 ? across[a] : 0);
        out[a] = sg * across[a] / La;
      }
      /* A millimetre past the edge at a quarter, half and three quarters
       * of its length: it carries on where two of three are covered and no
       * other surface stands on the edge there. */
      int hits = 0;
      bool walled = false;
      for (int k = 1; k <= 3; k++) {
        double x[3], on[3];
        for (int a = 0; a < 3; a++) {
          on[a] = start[a] + 0.25 * k * along[a];
          x[a] = on[a] + 1e-3 * out[a];
        }
        hits += covered(rs, boxes, o, x);
        walled |= met(rs, boxes, o, on);
      }
      if (hits < 2 || walled) ends[o] |= (uint8_t)(1u << e);
    }
  }
  free(boxes);
  return ends;
}

double vr_rect_disc_share(const double f[9], unsigned ends, const double x[3], double r, double kc) {
  double Lu = sqrt(vr_dot3(f + 3, f + 3)), Lv = sqrt(vr_dot3(f + 6, f + 6));
  if (!(Lu > 0) || !(Lv > 0) || !(r > 0) || fabs(vr_dot3(f + 3, f + 6)) > 1e-9 * Lu * Lv) return 1.0;
  double d[3] = {x[0] - f[0], x[1] - f[1], x[2] - f[2]};
  double cx = vr_dot3(d, f + 3) / Lu, cy = vr_dot3(d, f + 6) / Lv;
  cx = cx < 0 ? 0 : cx > Lu ? Lu : cx;
  cy = cy < 0 ? 0 : cy > Lv ? Lv : cy;
  /* Most discs reach no edge that ends. */
  if (!(ends & VR_EDGE_U0 && cx < r) && !(ends & VR_EDGE_U1 && Lu - cx < r) &&
      !(ends & VR_EDGE_V0 && cy < r) && !(ends & VR_EDGE_V1 && Lv - cy < r))
    return 1.0;
  /* In polar coordinates about x: along each of 128 directions the sheet
   * ends at distance t (an edge that ends, or r), and the filter's integral
   * out to t is t^2/2 - t^3/(3 kc r) (t^2/2 for the box).  The directions
   * turn by a rotation, not a cosine and sine each. */
  enum { DIRS = 128 };
  double full = kc > 0 ? r * r / 2 - r * r / (3 * kc) : r * r / 2, sum = 0;
  const double step = 2 * M_PI / DIRS, cs = cos(step), sn = sin(step);
  double cu = cos(0.5 * step), sv = sin(0.5 * step);
  for (int i = 0; i < DIRS; i++) {
    if (i) {
      double c2 = cu * cs - sv * sn;
      sv = sv * cs + cu * sn;
      cu = c2;
    }
    double t = r;
    if (ends & VR_EDGE_U1 && cu > 0 && (Lu - cx) / cu < t) t = (Lu - cx) / cu;
    if (ends & VR_EDGE_U0 && cu < 0 && -cx / cu < t) t = -cx / cu;
    if (ends & VR_EDGE_V1 && sv > 0 && (Lv - cy) / sv < t) t = (Lv - cy) / sv;
    if (ends & VR_EDGE_V0 && sv < 0 && -cy / sv < t) t = -cy / sv;
    sum += kc > 0 ? t * t / 2 - t * t * t / (3 * kc * r) : t * t / 2;
  }
  double share = sum / DIRS / full;
  return share < 0.05 ? 0.05 : share > 1 ? 1 : share;
}

bool vr_rect_sheet_holds(const double f[9], unsigned ends, const double x[3]) {
  double u, v, dist;
  if (!frame_coords(f, x, &u, &v, &dist)) return true;
  return !((u < 0 && ends & VR_EDGE_U0) || (u > 1 && ends & VR_EDGE_U1) ||
           (v < 0 && ends & VR_EDGE_V0) || (v > 1 && ends & VR_EDGE_V1));
}

void vr_box_face_frame(const vr_scene_object *o, const double x[3], double f[9]) {
  double face[6][9], best = INFINITY;
  vr_box_faces(o->bmin, o->bmax, face);
  for (int k = 0; k < 6; k++) {
    double g[9], n[3];
    vr_xform_point(&o->xform, face[k], g);
    vr_xform_vector(&o->xform, face[k] + 3, g + 3);
    vr_xform_vector(&o->xform, face[k] + 6, g + 6);
    unit_normal(g, n);
    double d = fabs((x[0] - g[0]) * n[0] + (x[1] - g[1]) * n[1] + (x[2] - g[2]) * n[2]);
    if (d < best) {
      best = d;
      for (int a = 0; a < 9; a++) f[a] = g[a];
    }
  }
}

bool vr_box_same_face(const double np[3], const double n[3]) {
  double c = vr_dot3(np, n);
  return c > 0 && c * c >= SHEET_COS * SHEET_COS * vr_dot3(np, np) * vr_dot3(n, n);
}

bool vr_same_sheet(const double p[3], const double np[3], const double x[3], const double n[3],
                   double r) {
  double ll = vr_dot3(np, np) * vr_dot3(n, n), c = vr_dot3(np, n);
  if (!(c * c >= SHEET_COS * SHEET_COS * ll)) return false;
  double d[3] = {x[0] - p[0], x[1] - p[1], x[2] - p[2]}, h = vr_dot3(d, np);
  double tol = fmax(0.25 * r, SHEET_DIST);
  return h * h <= tol * tol * vr_dot3(np, np);
}
