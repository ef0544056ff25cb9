/* Small 3-vector algebra, orthonormal frames and the direction samplers the
 * renderer draws from, in one place so that every module computes a dot
 * product, a frame or a cosine-weighted direction the same way, to the last
 * bit (a refactoring that moves a caller keeps its images bit for bit).
 *
 * Vectors are double[3] (the renderer's rays, hits and tables) or vr_vec3
 * (the BSDF and microfacet code, which passes them by value).  Everything is
 * inline and pure: no state, thread-safe.
 *
 * Samplers take uniform numbers u in [0, 1) and return unit directions:
 *   cosine hemisphere  p(w) = cos(theta) / pi about n (Malley's method);
 *   uniform cone       p(w) = 1 / (2 pi (1 - cos_max)) within cos_max of
 *                      the axis; cos_max = -1 is the whole sphere, 1 / (4 pi). */
#ifndef VR_VEC3_H
#define VR_VEC3_H

#include <math.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vr_vec3 {
  double x, y, z;
} vr_vec3;

static inline vr_vec3 vr_vec3_of(const double a[3]) { return (vr_vec3){a[0], a[1], a[2]}; }

static inline double vr_vec3_dot(vr_vec3 a, vr_vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

static inline double vr_dot3(const double a[3], const double b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* out may alias a or b. */
static inline void vr_cross3(const double a[3], const double b[3], double out[3]) {
  double r0 = a[1] * b[2] - a[2] * b[1], r1 = a[2] * b[0] - a[0] * b[2],
         r2 = a[0] * b[1] - a[1] * b[0];
  out[0] = r0, out[1] = r1, out[2] = r2;
}

/* Scales v to unit length; a zero (or non-finite length) vector is left as
 * it is.  Returns the length it had. */
static inline double vr_normalize3(double v[3]) {
  double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (l > 0)
    for (int a = 0; a < 3; a++) v[a] /= l;
  return l;
}

/* An orthonormal frame (t, b, n) about the unit vector n, branchless and
 * continuous but at n.z = 0 (Duff, Burgess, Christensen, Hery, Kensler,
 * Liani & Villemin, "Building an orthonormal basis, revisited", JCGT 6(1),
 * 2017, listing 3). */
static inline void vr_frame3(const double n[3], double t[3], double b[3]) {
  double s = copysign(1.0, n[2]);
  double a = -1.0 / (s + n[2]), c = n[0] * n[1] * a;
  t[0] = 1 + s * n[0] * n[0] * a, t[1] = s * c, t[2] = -s * n[0];
  b[0] = c, b[1] = s + n[1] * n[1] * a, b[2] = -n[1];
}

/* The direction z n + r (cos(phi) t + sin(phi) b) in the frame (t, b, n). */
static inline void vr_frame_dir(const double n[3], const double t[3], const double b[3], double z,
                                double r, double phi, double out[3]) {
  double c = cos(phi), s = sin(phi);
  for (int a = 0; a < 3; a++) out[a] = z * n[a] + r * (c * t[a] + s * b[a]);
}

/* A cosine-weighted direction about the unit normal n. */
static inline void vr_sample_cosine(const double n[3], double u1, double u2, double out[3]) {
  double t[3], b[3];
  vr_frame3(n, t, b);
  vr_frame_dir(n, t, b, sqrt(fmax(0, 1 - u1)), sqrt(u1), 2 * M_PI * u2, out);
}

/* A direction uniform in the cone of cos_max about the unit axis. */
static inline void vr_sample_cone(const double axis[3], double cos_max, double u1, double u2,
                                  double out[3]) {
  double t[3], b[3];
  vr_frame3(axis, t, b);
  double c = 1 - u1 * (1 - cos_max);
  vr_frame_dir(axis, t, b, c, sqrt(fmax(0, 1 - c * c)), 2 * M_PI * u2, out);
}

/* The density of vr_sample_cone (1 / (4 pi) for the whole sphere). */
static inline double vr_cone_pdf(double cos_max) { return 1.0 / (2 * M_PI * (1 - cos_max)); }

#ifdef __cplusplus
}
#endif
#endif
