/* Tensor trees (bsdf_xml_tree.h): parsing, lookup, and the mean over
 * Klems patch pairs. */
#include "bsdf_xml_tree.h"

#include <ctype.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define TT_MAX_DEPTH 24 /* branch levels: 2^-24 of the cube a side, far below any file's */

typedef struct node {
  int lg;       /* a leaf grid of 2^lg cells a side, or -1 for a branch */
  size_t at;    /* branch: its first child in kids; leaf: its first value in vals */
} node;

struct vr_tt_tree {
  int nd;
  node *nodes;
  size_t nnodes, capn;
  size_t *kids;
  size_t nkids, capk;
  float *vals;
  size_t nvals, capv;
};

typedef struct parser {
  const char *s;
  size_t pos;
  long line;
  char *msg;
  size_t cap;
  vr_tt_tree *t;
} parser;

static void skip(parser *p) {
  for (;;) {
    char c = p->s[p->pos];
    if (c == '\n') p->line++;
    if (c && (isspace((unsigned char)c) || c == ',')) p->pos++;
    else return;
  }
}

static int fail(parser *p, const char *what) {
  snprintf(p->msg, p->cap, "%s", what);
  return -1;
}

static int grow(void **a, size_t *cap, size_t want, size_t elem) {
  if (want <= *cap) return 0;
  size_t n = *cap ? *cap : 64;
  while (n < want) n *= 2;
  void *q = realloc(*a, n * elem);
  if (!q) return -1;
  *a = q;
  *cap = n;
  return 0;
}

/* One "{ ... }": its node's index in *out. */
static int parse_node(parser *p, int depth, size_t *out) {
  vr_tt_tree *t = p->t;
  skip(p);
  if (p->s[p->pos] != '{') return fail(p, "expected '{' (a tensor-tree node)");
  p->pos++;
  if (depth > TT_MAX_DEPTH) return fail(p, "the tree is nested more than 24 levels deep");
  if (grow((void **)&t->nodes, &t->capn, t->nnodes + 1, sizeof *t->nodes)) return fail(p, "out of memory");
  size_t me = t->nnodes++;
  *out = me;
  skip(p);
  if (p->s[p->pos] == '{') {
    size_t nk = (size_t)1 << t->nd, first = t->nkids;
    if (grow((void **)&t->kids, &t->capk, t->nkids + nk, sizeof *t->kids)) return fail(p, "out of memory");
    t->nkids += nk;
    t->nodes[me].lg = -1, t->nodes[me].at = first;
    for (size_t k = 0; k < nk; k++) {
      size_t c;
      if (parse_node(p, depth + 1, &c)) return -1;
      t->kids[first + k] = c;
      skip(p);
      if (k + 1 < nk && p->s[p->pos] != '{')
        return fail(p, "a branch holds fewer subtrees than 2^dimensions");
    }
  } else {
    size_t first = t->nvals;
    while (skip(p), p->s[p->pos] && p->s[p->pos] != '}' && p->s[p->pos] != '{') {
      char *end;
      double v = strtod(p->s + p->pos, &end);
      if (end == p->s + p->pos) return fail(p, "expected a number, '{' or '}'");
      if (!isfinite(v) || v < 0) return fail(p, "a value that is negative or not finite");
      if (grow((void **)&t->vals, &t->capv, t->nvals + 1, sizeof *t->vals)) return fail(p, "out of memory");
      t->vals[t->nvals++] = (float)v;
      p->pos = (size_t)(end - p->s);
    }
    size_t n = t->nvals - first;
    /* n = 2^(nd lg); lg kept so that the shift stays below 60 bits. */
    int lg = 0;
    while ((lg + 1) * t->nd < 60 && ((size_t)1 << (t->nd * lg)) < n) lg++;
    if (n == 0 || ((size_t)1 << (t->nd * lg)) != n) {
      char buf[160];
      snprintf(buf, sizeof buf, "a leaf of %zu values; a grid holds 2^(%d k) of them", n, t->nd);
      return fail(p, buf);
    }
    t->nodes[me].lg = lg, t->nodes[me].at = first;
  }
  skip(p);
  if (p->s[p->pos] != '}') return fail(p, "expected '}' closing a tensor-tree node");
  p->pos++;
  return 0;
}

vr_tt_tree *vr_tt_parse(const char *text, int nd, char *msg, size_t cap, long *line) {
  vr_tt_tree *t = calloc(1, sizeof *t);
  if (!t) {
    snprintf(msg, cap, "out of memory");
    return NULL;
  }
  t->nd = nd;
  parser p = {text, 0, 1, msg, cap, t};
  size_t root;
  int rc = parse_node(&p, 0, &root);
  if (!rc) {
    skip(&p);
    if (p.s[p.pos]) rc = fail(&p, "text after the tree's closing '}'");
  }
  *line = p.line;
  if (rc) {
    vr_tt_destroy(t);
    return NULL;
  }
  return t;
}

void vr_tt_destroy(vr_tt_tree *t) {
  if (!t) return;
  free(t->nodes), free(t->kids), free(t->vals);
  free(t);
}

double vr_tt_lookup(const vr_tt_tree *t, const double *pos) {
  double q[4];
  for (int i = 0; i < t->nd; i++) q[i] = fmin(fmax(pos[i], 0.0), 1.0);
  const node *n = &t->nodes[0];
  while (n->lg < 0) {
    size_t k = 0;
    for (int i = 0; i < t->nd; i++) {
      q[i] *= 2;
      if (q[i] >= 1) k |= (size_t)1 << i, q[i] -= 1;
    }
    n = &t->nodes[t->kids[n->at + k]];
  }
  size_t g = (size_t)1 << n->lg, idx = 0;
  for (int i = 0; i < t->nd; i++) {
    size_t c = (size_t)(q[i] * (double)g);
    idx = idx * g + (c < g ? c : g - 1);
  }
  return t->vals[n->at + idx];
}

/* Shirley and Chiu's map from [0, 1]^2 to the unit disk, the inverse of
 * vr_tt_disk_to_square. */
static void square_to_disk(double sx, double sy, double d[2]) {
  double a = 2 * sx - 1, b = 2 * sy - 1, r, phi;
  if (a > -b) {
    if (a > b) r = a, phi = (M_PI / 4) * (b / a);
    else r = b, phi = (M_PI / 4) * (2 - a / b);
  } else {
    if (a < b) r = -a, phi = (M_PI / 4) * (4 + b / a);
    else r = -b, phi = b != 0 ? (M_PI / 4) * (6 - a / b) : 0;
  }
  d[0] = r * cos(phi), d[1] = r * sin(phi);
}

void vr_tt_disk_to_square(double x, double y, double sq[2]) {
  /* The disk's four quarter sectors about the axes go to the square's
   * four triangles about its centre; the radius is the distance to the
   * centre along the axis, the angle runs linearly along the edge. */
  double r = sqrt(x * x + y * y), phi = atan2(y, x), a, b;
  if (phi < -M_PI / 4) phi += 2 * M_PI;
  if (phi < M_PI / 4) {
    a = r, b = phi * r / (M_PI / 4);
  } else if (phi < 3 * M_PI / 4) {
    b = r, a = -(phi - M_PI / 2) * r / (M_PI / 4);
  } else if (phi < 5 * M_PI / 4) {
    a = -r, b = -(phi - M_PI) * r / (M_PI / 4);
  } else {
    b = -r, a = (phi - 3 * M_PI / 2) * r / (M_PI / 4);
  }
  sq[0] = 0.5 + 0.5 * a, sq[1] = 0.5 + 0.5 * b;
}

enum { FREFL = VR_TT_FREFL, BREFL = VR_TT_BREFL, FXMIT = VR_TT_FXMIT, BXMIT = VR_TT_BXMIT };

double vr_tt_query(const vr_tt_tree *t, int side, const double in[3], const double out[3]) {
  const double *v;
  switch (side) {
  case FREFL:
    if (out[2] < 0 || in[2] < 0) return 0;
    break;
  case BREFL:
    if (out[2] > 0 || in[2] > 0) return 0;
    break;
  case FXMIT:
    if (out[2] > 0) {
      if (in[2] > 0) return 0;
      v = out, out = in, in = v;
    } else if (in[2] < 0) return 0;
    break;
  default: /* BXMIT */
    if (in[2] > 0) {
      if (out[2] > 0) return 0;
      v = out, out = in, in = v;
    } else if (out[2] < 0) return 0;
    break;
  }
  double g[4];
  if (t->nd == 3) {
    /* The exiting direction turned by minus the incident azimuth (of -in). */
    double a = -atan2(-in[1], -in[0]), c = cos(a), s = sin(a);
    g[0] = 0.5 - 1e-6 - 0.5 * sqrt(in[0] * in[0] + in[1] * in[1]);
    vr_tt_disk_to_square(c * out[0] - s * out[1], s * out[0] + c * out[1], g + 1);
  } else {
    vr_tt_disk_to_square(-in[0], -in[1], g);
    vr_tt_disk_to_square(out[0], out[1], g + 2);
  }
  return vr_tt_lookup(t, g);
}

/* A direction in Klems patch p of basis b, at (u, v) of the patch: uniform
 * in projected solid angle (cos^2 theta linear in u), azimuth across the
 * patch's width (v); on the front hemisphere (z > 0). */
static void patch_dir(const vr_klems_basis *b, int p, double u, double v, double d[3]) {
  int r = 0;
  while (r + 1 < b->nrings && p >= b->first[r + 1]) r++;
  double c0 = cos(b->theta_lo[r] * M_PI / 180), c1 = cos(b->theta_hi[r] * M_PI / 180);
  double ct = sqrt((1 - u) * c0 * c0 + u * c1 * c1), st = sqrt(fmax(0, 1 - ct * ct));
  double az = 2 * M_PI * ((p - b->first[r]) + v - 0.5) / b->nphi[r];
  d[0] = cos(az) * st, d[1] = sin(az) * st, d[2] = ct;
}

/* Radical inverse of k in a prime base (a Halton coordinate). */
static double radical(unsigned k, unsigned base) {
  double f = 1, r = 0;
  for (; k; k /= base) f /= base, r += f * (k % base);
  return r;
}

/* The exiting points shared by every incident direction: for each of the
 * nin incident samples k, the whole hemisphere on a side x side grid of
 * the unit square (shifted by a Halton offset for k) taken to the disk by
 * Shirley and Chiu's map, so uniform in projected solid angle, each point
 * pi / side^2 of it: its square point, its direction (z >= 0) and its
 * Klems patch. */
typedef struct grid {
  int nin, side;
  double *sq;  /* 2 per point */
  double *dir; /* 3 per point */
  int *patch;
} grid;

static int grid_make(grid *g, const vr_klems_basis *b, int nin, int side) {
  size_t n = (size_t)nin * side * side;
  g->nin = nin, g->side = side;
  g->sq = malloc(2 * n * sizeof *g->sq);
  g->dir = malloc(3 * n * sizeof *g->dir);
  g->patch = malloc(n * sizeof *g->patch);
  if (!g->sq || !g->dir || !g->patch) return -1;
  size_t at = 0;
  for (int k = 0; k < nin; k++) {
    unsigned q = (unsigned)k + 1;
    double ox = radical(q, 5), oy = radical(q, 7);
    for (int gy = 0; gy < side; gy++)
      for (int gx = 0; gx < side; gx++, at++) {
        double sx = (gx + ox) / side, sy = (gy + oy) / side, d[2];
        square_to_disk(sx, sy, d);
        double r2 = d[0] * d[0] + d[1] * d[1], z = sqrt(fmax(0, 1 - r2));
        g->sq[2 * at] = sx, g->sq[2 * at + 1] = sy;
        g->dir[3 * at] = d[0], g->dir[3 * at + 1] = d[1], g->dir[3 * at + 2] = z;
        g->patch[at] = vr_klems_patch(b, acos(fmin(1, z)) * 180 / M_PI, atan2(d[1], d[0]) * 180 / M_PI);
      }
  }
  return 0;
}

static void grid_free(grid *g) { free(g->sq), free(g->dir), free(g->patch); }

/* Matrix m of WINDOW's label s from tree t (Radiance's side rs): for each
 * incident patch, g->nin incident directions (2-D Halton points in it),
 * each with the whole exiting hemisphere of g, every exiting point adding
 * to the patch it falls in.  The straight-through peak of a clear layer
 * (a few degrees wide) is then met wherever it lies, which sampling each
 * patch pair apart misses or overweights at random. */
static void fill(const vr_tt_tree *t, int rs, const vr_klems_basis *b, int s, const grid *g,
                 double *m) {
  static const int IN_Z[VR_BSDF_SIDES] = {[VR_BSDF_TF] = -1, [VR_BSDF_TB] = 1, [VR_BSDF_RF] = -1,
                                          [VR_BSDF_RB] = 1};
  static const int OUT_Z[VR_BSDF_SIDES] = {[VR_BSDF_TF] = 1, [VR_BSDF_TB] = -1, [VR_BSDF_RF] = -1,
                                           [VR_BSDF_RB] = 1};
  int n = b->n, per = g->side * g->side;
  double w = M_PI / per / g->nin;
  /* The query's rule (vr_tt_query): a transmission read backwards swaps
   * the two directions. */
  bool swap = (rs == FXMIT && OUT_Z[s] > 0) || (rs == BXMIT && IN_Z[s] > 0);
  for (int i = 0; i < n; i++) {
    for (int k = 0; k < g->nin; k++) {
      unsigned q = (unsigned)k + 1;
      double pd[3], vi[3], pin[2];
      patch_dir(b, i, radical(q, 2), radical(q, 3), pd);
      /* Radiance's fi/bi: the incident vector points back at the source,
       * its plane components negated; below z = 0 for bi. */
      vi[0] = -pd[0], vi[1] = -pd[1], vi[2] = pd[2] * IN_Z[s];
      vr_tt_disk_to_square(pd[0], pd[1], pin); /* the square point of -vi */
      for (int j = 0; j < per; j++) {
        size_t at = (size_t)k * per + j;
        int o = g->patch[at];
        if (o < 0) continue;
        double v;
        if (t->nd == 4) {
          /* Straight to the tree's coordinates: the exiting point is its
           * own square point; the concentric map turns with the disk, so
           * a negated direction's point is 1 - the point. */
          const double *sq = g->sq + 2 * at;
          double gp[4];
          if (!swap) gp[0] = pin[0], gp[1] = pin[1], gp[2] = sq[0], gp[3] = sq[1];
          else gp[0] = 1 - sq[0], gp[1] = 1 - sq[1], gp[2] = 1 - pin[0], gp[3] = 1 - pin[1];
          v = vr_tt_lookup(t, gp);
        } else {
          const double *d = g->dir + 3 * at;
          double vo[3] = {d[0], d[1], d[2] * OUT_Z[s]};
          v = vr_tt_query(t, rs, vi, vo);
        }
        m[(size_t)o * n + i] += v * w;
      }
    }
  }
  for (int o = 0; o < n; o++) {
    double lam = vr_klems_lambda(b, o);
    for (int i = 0; i < n; i++) m[(size_t)o * n + i] /= lam;
  }
}

int vr_tt_to_klems(vr_tt_tree *const trees[VR_BSDF_SIDES], const vr_klems_basis *b, int samples,
                   double *m[VR_BSDF_SIDES]) {
  /* WINDOW's label -> Radiance's side of its own tree, or the other
   * transmission's (read backwards) when the label has none. */
  static const struct {
    int own, other_label, other;
  } S[VR_BSDF_SIDES] = {[VR_BSDF_TF] = {BXMIT, VR_BSDF_TB, FXMIT},
                        [VR_BSDF_TB] = {FXMIT, VR_BSDF_TF, BXMIT},
                        [VR_BSDF_RF] = {BREFL, -1, 0},
                        [VR_BSDF_RB] = {FREFL, -1, 0}};
  grid g;
  if (grid_make(&g, b, samples < 1 ? 1 : samples, 16)) {
    grid_free(&g);
    return -1;
  }
  for (int s = 0; s < VR_BSDF_SIDES; s++) {
    const vr_tt_tree *t = trees[s];
    int rs = S[s].own;
    if (!t && S[s].other_label >= 0) t = trees[S[s].other_label], rs = S[s].other;
    if (!t || !m[s]) continue;
    fill(t, rs, b, s, &g, m[s]);
  }
  grid_free(&g);
  return 0;
}
