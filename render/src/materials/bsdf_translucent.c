/* A translucent diffuser (a Radiance trans with no specular parts): light
 * arriving on either side is reflected to that side with the Lambertian
 * reflectance refl and transmitted to the other with the Lambertian
 * transmittance trans, f = refl / pi and trans / pi.  Sampling picks
 * reflection with probability refl_share (the albedos' means, fixed per
 * material so that it does not depend on the wavelengths a call carries),
 * then a cosine-weighted direction on that side. */
#include <math.h>

#include "materials/bsdf_internal.h"

void vr_bsdfi_translucent_eval(const vr_bsdf *b, unsigned only, vr_vec3 o, vr_vec3 i, int nwl,
                               const double *nm, double *f, double *pdf) {
  bool same = o.z * i.z > 0.0;
  if (!(o.z * i.z != 0.0)) return;
  unsigned lobe = same ? VR_LOBE_DIFFUSE : VR_LOBE_GLOSSY_T;
  if (only && !(only & lobe)) return;
  const double *v = same ? b->refl : b->trans;
  for (int w = 0; w < nwl; w++) f[w] = vr_bsdfi_lerp(v, vr_bsdfi_at(b, nm[w])) / M_PI;
  if (pdf) *pdf = (same ? b->refl_share : 1.0 - b->refl_share) * fabs(i.z) / M_PI;
}

bool vr_bsdfi_translucent_sample(const vr_bsdf *b, vr_vec3 o, int nwl, const double *nm, double u1,
                                 double u2, double u3, vr_bsdf_sample *out) {
  if (o.z == 0.0 || !isfinite(o.z)) return false;
  bool reflect = u3 < b->refl_share;
  double p = reflect ? b->refl_share : 1.0 - b->refl_share;
  if (!(p > 0.0)) return false;
  double r = sqrt(u1), phi = 2.0 * M_PI * u2, z = sqrt(fmax(0.0, 1.0 - u1));
  if (!(z > 0.0)) return false;
  bool up = (o.z > 0.0) == reflect;
  out->wi = (vr_vec3){r * cos(phi), r * sin(phi), up ? z : -z};
  out->pdf = p * z / M_PI;
  out->lobe = reflect ? VR_LOBE_DIFFUSE : VR_LOBE_GLOSSY_T;
  out->eta = 1.0;
  out->terminate_secondary = false;
  const double *v = reflect ? b->refl : b->trans;
  for (int w = 0; w < nwl; w++) out->weight[w] = vr_bsdfi_lerp(v, vr_bsdfi_at(b, nm[w])) / p;
  return true;
}
