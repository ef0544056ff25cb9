/* Affine transforms of scene objects: composition and the mapping of points,
 * vectors and normals.  Normals go through the inverse transpose of the
 * linear part, so a non-uniform scale keeps them perpendicular to the
 * transformed surface. */
#include <math.h>
#include <string.h>

#include "vr/scene.h"

void vr_xform_identity(vr_xform *x) {
  memset(x, 0, sizeof *x);
  x->m[0][0] = x->m[1][1] = x->m[2][2] = 1.0;
}

void vr_xform_then(const vr_xform *a, const vr_xform *b, vr_xform *out) {
  vr_xform r;
  for (int i = 0; i < 3; i++) {
    for (int j = 0; j < 4; j++) {
      double v = j == 3 ? b->m[i][3] : 0.0;
      for (int k = 0; k < 3; k++) v += b->m[i][k] * a->m[k][j];
      r.m[i][j] = v;
    }
  }
  *out = r;
}

void vr_xform_point(const vr_xform *x, const double p[3], double out[3]) {
  double r[3];
  for (int i = 0; i < 3; i++)
    r[i] = x->m[i][0] * p[0] + x->m[i][1] * p[1] + x->m[i][2] * p[2] + x->m[i][3];
  memcpy(out, r, sizeof r);
}

void vr_xform_vector(const vr_xform *x, const double v[3], double out[3]) {
  double r[3];
  for (int i = 0; i < 3; i++) r[i] = x->m[i][0] * v[0] + x->m[i][1] * v[1] + x->m[i][2] * v[2];
  memcpy(out, r, sizeof r);
}

bool vr_xform_normal(const vr_xform *x, const double n[3], double out[3]) {
  /* The cofactor matrix is det * inverse transpose; its direction is all a
   * normal needs, and it avoids dividing by a tiny determinant. */
  const double(*m)[4] = x->m;
  double c[3][3] = {
      {m[1][1] * m[2][2] - m[1][2] * m[2][1], m[1][2] * m[2][0] - m[1][0] * m[2][2],
       m[1][0] * m[2][1] - m[1][1] * m[2][0]},
      {m[0][2] * m[2][1] - m[0][1] * m[2][2], m[0][0] * m[2][2] - m[0][2] * m[2][0],
       m[0][1] * m[2][0] - m[0][0] * m[2][1]},
      {m[0][1] * m[1][2] - m[0][2] * m[1][1], m[0][2] * m[1][0] - m[0][0] * m[1][2],
       m[0][0] * m[1][1] - m[0][1] * m[1][0]}};
  double det = m[0][0] * c[0][0] + m[0][1] * c[0][1] + m[0][2] * c[0][2];
  if (!(fabs(det) > 0.0) || !isfinite(det)) return false;
  double r[3];
  for (int i = 0; i < 3; i++) r[i] = c[i][0] * n[0] + c[i][1] * n[1] + c[i][2] * n[2];
  double len = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
  if (!(len > 0.0)) return false;
  if (det < 0) len = -len; /* a mirroring transform keeps the outward side */
  for (int i = 0; i < 3; i++) out[i] = r[i] / len;
  return true;
}
