/* The sky and the ground glow as lights: the sky's radiance (a CIE or
 * Perez sky's relative luminance times its spectrum at the stated level),
 * its next-event samples (through the portals' mixture when there are
 * portals, portals.c), the environment an escaping ray meets, and the
 * ground glow: a Lambertian ground of reflectance rho below the horizon
 * lit by the sky and the sun, L = rho (E_sky + E_sun,h) / pi, with the
 * sky's spectrum for the sky's part and the sun's for the sun's.  The
 * powers here only share the photons among sources, never an estimate. */
#include <math.h>
#include <stdlib.h>

#include "lights/lights.h"
#include "vr/colour.h"
#include "vr/vec3.h"

void vr_lights_sky_radiance(const vr_lights *Ls, const double dir[3], int nwl, const double *wl,
                         double *L) {
  double rel = vr_sky_relative_luminance(Ls->sky, dir);
  for (int k = 0; k < nwl; k++) L[k] = rel * vr_rspd_at(&Ls->sky_spd, wl[k]);
}

bool vr_lights_sample_sky(const vr_lights *L, const double x[3], const double n[3], int nwl,
                         const double *wl, const vr_rng_key *key, vr_light_sample *out) {
  if (!L->has_sky) return false;
  double pdf, u = vr_rng(key, VR_DIM_SKY_U), v = vr_rng(key, VR_DIM_SKY_V);
  vr_portal_weights pw = {0};
  if (L->nportals) vr_portal_weights_at(L, x, true, &pw);
  if (pw.sum > 0) {
    /* The portal / sky mixture of portals.c, weighted by its density.
     * Where no portal has a part above x (a ceiling, a point above every
     * window's head) the sky's own sampler takes every sample. */
    double q = VR_PORTAL_SHARE;
    if (vr_rng(key, VR_DIM_SKY_PICK) < q) {
      if (!vr_portal_sample(L, x, &pw, vr_rng(key, VR_DIM_SKY_W), u, v, out->dir)) return false;
    } else {
      vr_sky_sample(L->sky, u, v, out->dir, &pdf);
    }
    if (out->dir[2] < 0) return false; /* the sky gives nothing below the horizon */
    pdf = q * vr_portal_pdf(L, x, &pw, out->dir) + (1 - q) * vr_sky_pdf(L->sky, out->dir);
  } else {
    vr_sky_sample(L->sky, u, v, out->dir, &pdf);
  }
  if (!(pdf > 0)) return false;
  if (n && vr_dot3(out->dir, n) <= 0) return false;
  vr_lights_sky_radiance(L, out->dir, nwl, wl, out->L);
  for (int k = 0; k < nwl; k++) out->L[k] /= pdf;
  out->dist = INFINITY;
  out->delta = false;
  return true;
}

void vr_lights_environment(const vr_lights *Ls, const double dir[3], bool include_sky, int nwl,
                           const double *wl, double *L) {
  for (int k = 0; k < nwl; k++) L[k] = 0;
  if (!Ls->has_sky) return;
  if (dir[2] >= 0) {
    if (include_sky) vr_lights_sky_radiance(Ls, dir, nwl, wl, L);
    return;
  }
  for (int k = 0; k < nwl; k++) L[k] = Ls->ground_radiance_scale * vr_rspd_at(&Ls->ground_spd, wl[k]);
}

vr_status vr_lights_sky_create(vr_lights *L, const vr_scene *s, vr_error *err) {
  const vr_scene_sky *sk = &s->sky;
  if (!sk->present) return VR_OK;
  if (sk->annual)
    return vr_error_set(err, VR_E_ARG,
                        "%s:%ld:%ld: sky: a whole weather file (weather= with no date= and time=) "
                        "is a year of skies, for an annual study (vr-render runs one for such a "
                        "scene), not one render",
                        s->path, sk->loc.line, sk->loc.col);
  vr_status st = sk->cie_type == VR_SKY_PEREZ
                     ? vr_sky_create_perez(&sk->perez.lum, sk->sun_direction, &L->sky, err)
                     : vr_sky_create(sk->cie_type, sk->sun_direction, &L->sky, err);
  if (st) {
    vr_error_prefix(err, "%s:%ld:%ld: sky: ", s->path, sk->loc.line, sk->loc.col);
    return st;
  }
  vr_quantity z;
  st = vr_sky_zenith_level(L->sky, sk->level, &z, err);
  if (st) {
    vr_error_prefix(err, "%s:%ld:%ld: sky: ", s->path, sk->loc.line, sk->loc.col);
    return st;
  }
  st = vr_spd_resolve(&L->setup.spd, sk->spectrum, "D65", &sk->loc, &L->sky_spd, err);
  if (st) return st;
  /* sky_spd becomes the spectral radiance at the zenith. */
  bool photometric = z.unit == VR_UNIT_CD_M2;
  st = vr_spd_normalise(&L->setup.spd, &L->sky_spd, z, photometric, &sk->loc, "sky", err);
  if (st) return st;
  L->has_sky = true;
  /* Ground glow: a Lambertian ground of reflectance rho under the sky
   * and the sun, L = rho (E_sky + E_sun,h) / pi, with the sky's spectrum
   * for the sky part and the sun's for the sun part. */
  double eh = vr_sky_horizontal_ratio(L->sky); /* E_h / L_z */
  int n = L->sky_spd.n;
  L->ground_spd.lo = L->sky_spd.lo;
  L->ground_spd.n = n;
  L->ground_spd.v = malloc((size_t)n * sizeof *L->ground_spd.v);
  if (!L->ground_spd.v) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  for (int i = 0; i < n; i++) L->ground_spd.v[i] = L->sky_spd.v[i] * eh;
  for (size_t l = 0; l < L->n; l++) {
    const vr_light *li = &L->light[l];
    if (!(li->ops->flags & VR_LF_SUN) || li->axis[2] <= 0) continue;
    for (int i = 0; i < n; i++) L->ground_spd.v[i] += vr_rspd_at(&li->spd, L->ground_spd.lo + i) * li->axis[2];
  }
  L->ground_radiance_scale = sk->ground_reflectance / M_PI;
  return VR_OK;
}

double vr_lights_ground_sun_share(const vr_lights *L, double nm) {
  if (!L->has_sky) return 0.0;
  double g = vr_rspd_at(&L->ground_spd, nm);
  if (!(g > 0)) return 0.0;
  double share = 1.0 - vr_rspd_at(&L->sky_spd, nm) * vr_sky_horizontal_ratio(L->sky) / g;
  return share < 0 ? 0 : share > 1 ? 1 : share;
}

double vr_lights_sky_horizontal_lx(const vr_lights *L) {
  if (!L->has_sky) return 0.0;
  double eh = vr_sky_horizontal_ratio(L->sky), lx = 0;
  for (double nm = L->setup.spd.lmin; nm <= L->setup.spd.lmax; nm += 1.0) {
    double xyz[3];
    vr_cmf_eval(VR_CIE1931_2DEG, nm, xyz);
    lx += xyz[1] * vr_rspd_at(&L->sky_spd, nm) * eh;
  }
  return VR_KM * lx;
}

double vr_lights_sky_power(const vr_lights *L) {
  if (!L->has_sky) return 0.0;
  /* Power through a disc of the scene's radius from the whole sky, taken
   * as horizontal irradiance times the disc's area: only for sharing the
   * photons among sources, never in an estimate. */
  double e = 0;
  for (double nm = L->setup.spd.lmin; nm <= L->setup.spd.lmax; nm += 1.0) e += vr_rspd_at(&L->sky_spd, nm);
  return e * vr_sky_horizontal_ratio(L->sky) * M_PI * L->setup.radius * L->setup.radius;
}

double vr_lights_ground_power(const vr_lights *L) {
  if (!L->has_sky) return 0.0;
  /* The ground glow's upward flux through a horizontal disc of the
   * scene's radius: pi L A for a uniform radiance L over the lower
   * hemisphere.  Only for sharing the photons among sources. */
  double e = 0;
  for (double nm = L->setup.spd.lmin; nm <= L->setup.spd.lmax; nm += 1.0) e += vr_rspd_at(&L->ground_spd, nm);
  return L->ground_radiance_scale * e * M_PI * M_PI * L->setup.radius * L->setup.radius;
}

