/* Fresnel reflectance of one smooth interface between air and a medium, the
 * one place the interface dielectrics and the conductors get it from, so
 * that the renderer agrees with core's vr_fresnel_interface to the last
 * digit. */
#include <complex.h>
#include <math.h>

#include "bsdf_internal.h"
#include "vr/optics.h"

double vr_bsdfi_fresnel(double n, double k, bool inside, double cos_i, double *cos_t) {
  double c = fmin(fabs(cos_i), 1.0);
  double s2 = 1.0 - c * c;
  /* Snell with the real index: sin_t = sin_i n_i / n_t. */
  double st2 = inside ? s2 * n * n : s2 / (n * n);
  double ct = st2 < 1.0 ? sqrt(1.0 - st2) : 0.0;
  if (cos_t) *cos_t = ct;
  if (inside && !(ct > 0.0)) return 1.0; /* total internal reflection, exactly */
  vr_fresnel f;
  if (inside) vr_fresnel_interface(n, 1.0, acos(c), &f);
  else vr_fresnel_interface(1.0, n + I * k, acos(c), &f);
  double F = 0.5 * (f.Rs + f.Rp);
  return F < 0.0 ? 0.0 : (F > 1.0 ? 1.0 : F);
}
