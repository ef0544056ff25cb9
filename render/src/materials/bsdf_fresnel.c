/* Fresnel reflectance of one smooth interface between air and a medium, the
 * one place the interface dielectrics and the conductors get it from, so
 * that the renderer agrees with core's vr_fresnel_interface (to rounding:
 * lossless dielectrics take the real form of the same equations). */
#include <complex.h>
#include <math.h>

#include "materials/bsdf_internal.h"
#include "vr/optics.h"

double vr_bsdfi_fresnel(double n, double k, bool inside, double cos_i, double *cos_t) {
  double c = fmin(fabs(cos_i), 1.0);
  double s2 = 1.0 - c * c;
  /* Snell with the real index: sin_t = sin_i n_i / n_t. */
  double st2 = inside ? s2 * n * n : s2 / (n * n);
  double ct = st2 < 1.0 ? sqrt(1.0 - st2) : 0.0;
  if (cos_t) *cos_t = ct;
  if (inside && !(ct > 0.0)) return 1.0; /* total internal reflection, exactly */
  if (k < 1e-7 * n) {
    /* A (nearly) lossless dielectric: the real Fresnel equations (Born &
     * Wolf 1999, eq. 1.5.21a), with n_i cos_i and n_t cos_t of each side.
     * The complex form below gives the same to rounding at k = 0, and
     * differs by O((k/n)^2) < 1e-14 below this bound (glass catalogues'
     * k is 1e-9 to 1e-7), at several times the cost (a complex square
     * root and an arccosine a call). */
    double ni = inside ? n : 1.0, nt = inside ? 1.0 : n;
    if (!(ni * c + nt * ct > 0.0)) return 1.0; /* grazing with no transmitted wave */
    double rs = (ni * c - nt * ct) / (ni * c + nt * ct);
    double rp = (nt * c - ni * ct) / (nt * c + ni * ct);
    double F = 0.5 * (rs * rs + rp * rp);
    return F < 0.0 ? 0.0 : (F > 1.0 ? 1.0 : F);
  }
  vr_fresnel f;
  if (inside) vr_fresnel_interface(n, 1.0, acos(c), &f);
  else vr_fresnel_interface(1.0, n + I * k, acos(c), &f);
  double F = 0.5 * (f.Rs + f.Rp);
  return F < 0.0 ? 0.0 : (F > 1.0 ? 1.0 : F);
}
