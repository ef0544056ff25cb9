/* Photon sources: every light line, every emitter, the sky and the ground
 * glow, chosen in proportion to their power, and with sky portals the far
 * sources (sun, sky, ground glow) once more through the portals, which get
 * VR_PORTAL_PHOTON_SHARE of the photons (portals.c).  Each source's photon
 * carries its power per wavelength sample: the spectral power over the
 * densities of its origin and direction. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lights/lights.h"
#include "vr/vec3.h"

/* A direction uniform over the lower hemisphere (density 1 / (2 pi)):
 * towards the ground glow, whose radiance is the same every way. */
static void ground_dir(double u3, double u4, double d[3]) {
  double z = -u3, rr = sqrt(fmax(0.0, 1.0 - z * z)), ph = 2 * M_PI * u4;
  d[0] = rr * cos(ph), d[1] = rr * sin(ph), d[2] = z;
}

bool vr_lights_emit_photon(const vr_lights *L, size_t source, int nwl, const double *wl,
                           const vr_rng_key *key, vr_photon_emit *out) {
  if (source < L->n) {
    const vr_light *l = &L->light[source];
    vr_light_emission e;
    if (!l->ops->sample_le(l, &L->setup, key, &e)) return false;
    memcpy(out->org, e.org, sizeof out->org);
    memcpy(out->dir, e.dir, sizeof out->dir);
    for (int k = 0; k < nwl; k++) out->power[k] = vr_rspd_at(&l->spd, wl[k]) * e.weight;
    return true;
  }
  source -= L->n;
  double u1 = vr_rng(key, VR_DIM_EMIT_U), u2 = vr_rng(key, VR_DIM_EMIT_V);
  double u3 = vr_rng(key, VR_DIM_EMIT_W), u4 = vr_rng(key, VR_DIM_EMIT_X);
  if (source < L->nemitters) {
    const vr_emitter *em = &L->emitter[source];
    uint32_t obj = em->object;
    double n[3];
    vr_scene_tables_sample_object(L->t, obj, u1, u2, vr_rng(key, VR_DIM_EMIT_Y), out->org, n);
    /* Cosine-weighted direction: L cos / (cos/pi) per unit area, times area. */
    vr_sample_cosine(n, u3, u4, out->dir);
    double f = M_PI * L->t->object_area[obj];
    double off = 1e-5 * (1 + fmax(fabs(out->org[0]), fmax(fabs(out->org[1]), fabs(out->org[2]))));
    for (int a = 0; a < 3; a++) out->org[a] += off * n[a];
    for (int k = 0; k < nwl; k++) out->power[k] = vr_rspd_at(&em->emission, wl[k]) * f;
    return true;
  }
  if (!L->has_sky) return false;
  double d[3], pdf;
  double area = M_PI * L->setup.radius * L->setup.radius;
  if (source > L->nemitters) {
    /* The ground glow: d (towards the source) uniform over the lower
     * hemisphere, radiance ground_radiance_scale times ground_spd whatever
     * the direction (a Lambertian ground). */
    ground_dir(u3, u4, d);
    for (int a = 0; a < 3; a++) out->dir[a] = -d[a];
    vr_light_disc_origin(&L->setup, out->dir, u1, u2, out->org);
    for (int k = 0; k < nwl; k++)
      out->power[k] = L->ground_radiance_scale * vr_rspd_at(&L->ground_spd, wl[k]) * area * 2 * M_PI;
    return L->ground_radiance_scale > 0;
  }
  vr_sky_sample(L->sky, u3, u4, d, &pdf);
  if (!(pdf > 0)) return false;
  double Ls[VR_MAX_WL];
  vr_lights_sky_radiance(L, d, nwl, wl, Ls);
  for (int a = 0; a < 3; a++) out->dir[a] = -d[a];
  vr_light_disc_origin(&L->setup, out->dir, u1, u2, out->org);
  for (int k = 0; k < nwl; k++) out->power[k] = Ls[k] * area / pdf;
  return true;
}

bool vr_lights_emit_portal_photon(const vr_lights *L, int kind, int nwl, const double *wl,
                                  const vr_rng_key *key, vr_photon_emit *out, double *to_portal) {
  if (!L->nportals) return false;
  double y[3], d[3], w[3], Ls[VR_MAX_WL], pdf = 1.0;
  size_t j;
  vr_portal_point(L, vr_rng(key, VR_DIM_EMIT_Y), vr_rng(key, VR_DIM_EMIT_U),
                  vr_rng(key, VR_DIM_EMIT_V), y, &j);
  /* w: from the portal towards the source; the photon travels along -w. */
  if (kind == VR_PORTAL_SRC_SUN) {
    if (L->sun >= L->n) return false;
    /* The sun's own sample towards it; its spectrum is its irradiance
     * normal to the beam: the flux through area A at incidence theta is
     * E A cos theta. */
    const vr_light *l = &L->light[L->sun];
    vr_light_sample ls;
    if (!l->ops->sample_li(l, y, key, (vr_light_dims){VR_DIM_EMIT_W, VR_DIM_EMIT_X}, nwl, wl, &ls))
      return false;
    memcpy(w, ls.dir, sizeof w);
    memcpy(Ls, ls.L, sizeof Ls);
  } else if (kind == VR_PORTAL_SRC_SKY) {
    if (!L->has_sky) return false;
    vr_sky_sample(L->sky, vr_rng(key, VR_DIM_EMIT_W), vr_rng(key, VR_DIM_EMIT_X), w, &pdf);
    if (!(pdf > 0)) return false;
    vr_lights_sky_radiance(L, w, nwl, wl, Ls);
  } else {
    if (!L->has_sky || !(L->ground_radiance_scale > 0)) return false;
    ground_dir(vr_rng(key, VR_DIM_EMIT_W), vr_rng(key, VR_DIM_EMIT_X), w);
    pdf = 1.0 / (2 * M_PI);
    for (int k = 0; k < nwl; k++) Ls[k] = L->ground_radiance_scale * vr_rspd_at(&L->ground_spd, wl[k]);
  }
  for (int a = 0; a < 3; a++) d[a] = -w[a];
  double c = vr_dot3(L->portals[j].n, d);
  if (!(c > 0)) return false; /* leaving the room: not light that enters by this portal */
  double R = L->setup.radius;
  for (int a = 0; a < 3; a++) {
    out->dir[a] = d[a];
    out->org[a] = y[a] - 2 * R * d[a];
  }
  *to_portal = 2 * R;
  bool any = false;
  for (int k = 0; k < nwl; k++) any |= (out->power[k] = Ls[k] * c * L->portal_area / pdf) > 0;
  return any;
}

/* Rough powers of the portal sources, only to share the photons. */
static double portal_power(const vr_lights *L, int kind) {
  double e = 0;
  if (kind == VR_PORTAL_SRC_SUN) {
    if (L->sun >= L->n) return 0;
    const vr_light *l = &L->light[L->sun];
    double a = 0;
    for (size_t j = 0; j < L->nportals; j++) {
      const vr_portal *q = &L->portals[j];
      double c = -vr_dot3(q->n, l->axis);
      if (c > 0) a += q->area * c;
    }
    for (double nm = L->setup.spd.lmin; nm <= L->setup.spd.lmax; nm += 1.0) e += vr_rspd_at(&l->spd, nm);
    return e * a;
  }
  if (!L->has_sky) return 0;
  const vr_rspd *spd = kind == VR_PORTAL_SRC_SKY ? &L->sky_spd : &L->ground_spd;
  double scale = kind == VR_PORTAL_SRC_SKY ? vr_sky_horizontal_ratio(L->sky) : L->ground_radiance_scale * M_PI;
  for (double nm = L->setup.spd.lmin; nm <= L->setup.spd.lmax; nm += 1.0) e += vr_rspd_at(spd, nm);
  return 0.5 * e * scale * L->portal_area;
}

vr_status vr_lights_sources_create(vr_lights *L, bool photon_portals, vr_error *err) {
  /* The sky is two photon sources: the sky above the horizon and the
   * ground glow below it (the light an escaping path meets there,
   * vr_lights_environment), so photon maps hold ground-reflected light too.
   * With portals, the far sources (sun, sky, ground glow) also emit through
   * them (portals.c): those sources get VR_PORTAL_PHOTON_SHARE of the
   * photons, shared by power, the usual ones the rest. */
  L->nportal_sources = 0;
  double pp[3], portal_total = 0;
  if (L->nportals && photon_portals) {
    static const int KINDS[3] = {VR_PORTAL_SRC_SUN, VR_PORTAL_SRC_SKY, VR_PORTAL_SRC_GROUND};
    for (int i = 0; i < 3; i++) {
      double w = portal_power(L, KINDS[i]);
      if (!(w > 0)) continue;
      L->portal_source[L->nportal_sources] = KINDS[i];
      pp[L->nportal_sources++] = w;
      portal_total += w;
    }
  }
  size_t base = L->n + L->nemitters + (L->has_sky ? 2 : 0);
  size_t n = base + L->nportal_sources;
  L->nsources = n;
  L->source_cdf = calloc(n + 1, sizeof *L->source_cdf);
  if (!L->source_cdf) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  double acc = 0;
  size_t k = 0;
  for (size_t i = 0; i < L->n; i++) L->source_cdf[k++] = (acc += L->light[i].power);
  for (size_t i = 0; i < L->nemitters; i++) L->source_cdf[k++] = (acc += L->emitter[i].power);
  if (L->has_sky) {
    L->source_cdf[k++] = (acc += vr_lights_sky_power(L));
    L->source_cdf[k++] = (acc += vr_lights_ground_power(L));
  }
  L->total_power = acc;
  double q = L->nportal_sources && acc > 0 ? VR_PORTAL_PHOTON_SHARE : 0.0;
  if (L->nportal_sources && !(acc > 0)) q = 1.0;
  for (size_t i = 0; i < base; i++) L->source_cdf[i] = acc > 0 ? (1 - q) * L->source_cdf[i] / acc : 0;
  double pacc = 0;
  for (size_t i = 0; i < L->nportal_sources; i++)
    L->source_cdf[base + i] = (1 - q) + q * (pacc += pp[i]) / portal_total;
  if (L->nportal_sources) L->source_cdf[n - 1] = 1.0;
  if (L->nportal_sources) L->total_power += portal_total;
  L->portal_photon_power = L->nportal_sources && q > 0 ? portal_total / q : 0.0;
  return VR_OK;
}

bool vr_lights_source_is_far(const vr_lights *L, size_t s) {
  return s == L->sun || (L->has_sky && s >= L->n + L->nemitters);
}

bool vr_lights_source_is_ground(const vr_lights *L, size_t s) {
  return L->has_sky && s == L->n + L->nemitters + 1;
}
