/* Lights as the integrators see them: next-event samples of point, spot and
 * sun lights, emissive surfaces and the sky; the environment met by an
 * escaping ray (sky above the horizon, ground glow below); photon emission
 * from every kind of source; and the wavelengths a path carries.
 *
 * Every sample returns the incident spectral radiance times solid angle
 * over its pdf (for delta lights: the spectral irradiance at normal
 * incidence), so the caller multiplies by BSDF and cosine only. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bdpt.h"
#include "render_internal.h"
#include "vr/colour.h"
#include "vr/ies.h"

static void frame(const double n[3], double t[3], double b[3]) {
  /* Duff et al. 2017, "Building an orthonormal basis, revisited". */
  double s = copysign(1.0, n[2]);
  double a = -1.0 / (s + n[2]), c = n[0] * n[1] * a;
  t[0] = 1 + s * n[0] * n[0] * a;
  t[1] = s * c;
  t[2] = -s * n[0];
  b[0] = c;
  b[1] = s + n[1] * n[1] * a;
  b[2] = -n[1];
}

void vr_wavelengths(const rscene *rs, const vr_rng_key *key, uint32_t strata, double *wl) {
  double span = rs->lmax - rs->lmin, step = span / rs->nwl;
  if (rs->bins_mode) {
    for (int i = 0; i < rs->nwl; i++) wl[i] = rs->lmin + (i + 0.5) * step;
    return;
  }
  /* Hero wavelength sampling (Wilkie et al. 2014): one uniform wavelength,
   * the others spaced evenly from it and wrapped, so each is uniform. */
  /* Stratified over the samples of one pixel or sensor point: sample i of
   * n takes its hero from the i-th n-th of the range. */
  double u = vr_rng(key, VR_DIM_WAVELENGTH);
  if (strata > 1) u = ((key->sample % strata) + u) / strata;
  double h = u * span;
  for (int i = 0; i < rs->nwl; i++) {
    double x = h + i * step;
    if (x >= span) x -= span;
    wl[i] = rs->lmin + x;
  }
}

/* Intensity of a point or spot light towards unit direction d (from the
 * light), relative to the on-axis value. */
static double distribution(const rlight *l, const double d[3]) {
  double c = d[0] * l->axis[0] + d[1] * l->axis[1] + d[2] * l->axis[2];
  if (l->kind == VR_LIGHT_SPOT) {
    if (c >= l->cos_inner) return 1.0;
    if (c <= l->cos_outer) return 0.0;
    double x = (c - l->cos_outer) / (l->cos_inner - l->cos_outer);
    return x * x * (3 - 2 * x); /* smoothstep falloff */
  }
  switch (l->dist) {
  case VR_DIST_LAMBERTIAN: return c > 0 ? c : 0.0;
  case VR_DIST_GONIOMETRIC: return vr_ies_candela_dir(l->ies, d) / vr_ies_max_candela(l->ies);
  default: return 1.0;
  }
}

double vr_light_distribution(const rscene *rs, size_t i, const double d[3]) {
  return distribution(&rs->lights[i], d);
}

static void cone_dir(const double axis[3], double cos_max, double u1, double u2, double out[3]) {
  double t[3], b[3];
  frame(axis, t, b);
  double c = 1 - u1 * (1 - cos_max), s = sqrt(fmax(0, 1 - c * c)), ph = 2 * M_PI * u2;
  for (int a = 0; a < 3; a++) out[a] = c * axis[a] + s * (cos(ph) * t[a] + sin(ph) * b[a]);
}

int vr_light_sample_delta(const rscene *rs, size_t i, const double x[3], int nwl,
                          const double *wl, const vr_rng_key *key, light_sample *out) {
  const rlight *l = &rs->lights[i];
  out->delta = true;
  if (l->kind == VR_LIGHT_SUN) {
    /* Soft shadows: a direction within the solar disc, same irradiance. */
    cone_dir(l->axis, l->cos_sun, vr_rng(key, VR_DIM_LIGHT_U), vr_rng(key, VR_DIM_LIGHT_V),
             out->dir);
    out->dist = INFINITY;
    for (int k = 0; k < nwl; k++) out->L[k] = rspd_at(&l->spd, wl[k]);
    return 1;
  }
  double d[3], r2 = 0;
  for (int a = 0; a < 3; a++) {
    d[a] = l->pos[a] - x[a];
    r2 += d[a] * d[a];
  }
  if (!(r2 > 0)) return 0;
  double r = sqrt(r2);
  for (int a = 0; a < 3; a++) out->dir[a] = d[a] / r;
  out->dist = r;
  double from_light[3] = {-out->dir[0], -out->dir[1], -out->dir[2]};
  double f = distribution(l, from_light) / r2;
  if (!(f > 0)) return 0;
  for (int k = 0; k < nwl; k++) out->L[k] = rspd_at(&l->spd, wl[k]) * f;
  return 1;
}

/* Emitter i's share at x before normalising: its power over the squared
 * distance to its bounding sphere's centre, at least its radius. */
static double emitter_weight(const rscene *rs, size_t i, const double x[3]) {
  const double *s = rs->emitter_sphere[i];
  double d2 = 0;
  for (int a = 0; a < 3; a++) d2 += (x[a] - s[a]) * (x[a] - s[a]);
  double r2 = s[3] * s[3];
  double p = rs->emitter_cdf[i] - (i ? rs->emitter_cdf[i - 1] : 0.0);
  return p / (d2 > r2 ? d2 : (r2 > 0 ? r2 : 1e-30));
}

bool vr_light_sample_emitter(const rscene *rs, const double x[3], int nwl, const double *wl,
                             const vr_rng_key *key, light_sample *out) {
  if (!rs->nemitters) return false;
  /* Choose an emitter by power over squared distance (never closer than
   * its bounding radius): a lamp across the building is rarely chosen
   * from inside a room, and its shadow ray rarely leaves the room.  Any
   * choice with p > 0 wherever light can arrive is unbiased; this one
   * tracks the unoccluded 1/d² falloff.  Two passes, no storage. */
  double sum = 0;
  for (size_t i = 0; i < rs->nemitters; i++) sum += emitter_weight(rs, i, x);
  if (!(sum > 0)) return false;
  double u = vr_rng(key, VR_DIM_LIGHT_PICK) * sum, acc = 0, w = 0;
  size_t e = 0;
  for (; e < rs->nemitters; e++) {
    w = emitter_weight(rs, e, x);
    acc += w;
    if (u < acc) break;
  }
  if (e == rs->nemitters) { /* rounding at the top end */
    e = rs->nemitters - 1;
    while (e > 0 && !(emitter_weight(rs, e, x) > 0)) e--;
    w = emitter_weight(rs, e, x);
  }
  double p_pick = w / sum;
  if (!(p_pick > 0)) return false;
  uint32_t obj = rs->emitters[e];
  double y[3], ny[3];
  vr_scene_tables_sample_object(rs->t, obj, vr_rng(key, VR_DIM_LIGHT_U), vr_rng(key, VR_DIM_LIGHT_V),
                            vr_rng(key, VR_DIM_LIGHT_W), y, ny);
  if (key->seed.sampler != VR_SAMPLER_INDEPENDENT && rs->t->is_rect && rs->t->is_rect[obj]) {
    /* A low-discrepancy sampler's 2D point (LIGHT_V, LIGHT_W) placed on
     * the whole rect (uniform by area, as its two triangles are), so its
     * stratification covers the light instead of a triangle picked apart
     * by LIGHT_U.  Independent numbers keep the triangles' way, bit for
     * bit as before samplers existed. */
    const double *f = rs->t->rect_frame[obj];
    double s = vr_rng(key, VR_DIM_LIGHT_V), t = vr_rng(key, VR_DIM_LIGHT_W);
    for (int a = 0; a < 3; a++) y[a] = f[a] + s * f[3 + a] + t * f[6 + a];
  }
  double d[3], r2 = 0;
  for (int a = 0; a < 3; a++) {
    d[a] = y[a] - x[a];
    r2 += d[a] * d[a];
  }
  if (!(r2 > 0)) return false;
  double r = sqrt(r2);
  for (int a = 0; a < 3; a++) out->dir[a] = d[a] / r;
  double cos_y = -(out->dir[0] * ny[0] + out->dir[1] * ny[1] + out->dir[2] * ny[2]);
  if (!(cos_y > 0)) return false; /* emitters emit from their front side */
  double area = rs->t->object_area[obj];
  double g = cos_y * area / (r2 * p_pick);
  const robject *o = &rs->obj[obj];
  for (int k = 0; k < nwl; k++) out->L[k] = rspd_at(&o->emission, wl[k]) * g;
  out->dist = r;
  out->delta = false;
  return true;
}

/* Sky radiance along dir (towards the sky), per wavelength. */
static void sky_radiance(const rscene *rs, const double dir[3], int nwl, const double *wl,
                         double *L) {
  double rel = vr_sky_relative_luminance(rs->sky, dir);
  for (int k = 0; k < nwl; k++) L[k] = rel * rspd_at(&rs->sky_spd, wl[k]);
}

bool vr_light_sample_sky(const rscene *rs, const double x[3], const double n[3], int nwl,
                         const double *wl, const vr_rng_key *key, light_sample *out) {
  if (!rs->has_sky) return false;
  double pdf, u = vr_rng(key, VR_DIM_SKY_U), v = vr_rng(key, VR_DIM_SKY_V);
  if (rs->nportals) {
    /* The portal / sky mixture of portals.c, weighted by its density. */
    double q = VR_PORTAL_SHARE;
    if (vr_rng(key, VR_DIM_SKY_PICK) < q) {
      if (!vr_portal_sample(rs, x, vr_rng(key, VR_DIM_SKY_W), u, v, out->dir)) return false;
    } else {
      vr_sky_sample(rs->sky, u, v, out->dir, &pdf);
    }
    if (out->dir[2] < 0) return false; /* the sky gives nothing below the horizon */
    pdf = q * vr_portal_pdf(rs, x, out->dir) + (1 - q) * vr_sky_pdf(rs->sky, out->dir);
  } else {
    vr_sky_sample(rs->sky, u, v, out->dir, &pdf);
  }
  if (!(pdf > 0)) return false;
  if (n && out->dir[0] * n[0] + out->dir[1] * n[1] + out->dir[2] * n[2] <= 0) return false;
  sky_radiance(rs, out->dir, nwl, wl, out->L);
  for (int k = 0; k < nwl; k++) out->L[k] /= pdf;
  out->dist = INFINITY;
  out->delta = false;
  return true;
}

void vr_light_environment(const rscene *rs, const double dir[3], bool include_sky, int nwl,
                          const double *wl, double *L) {
  for (int k = 0; k < nwl; k++) L[k] = 0;
  if (!rs->has_sky) return;
  if (dir[2] >= 0) {
    if (include_sky) sky_radiance(rs, dir, nwl, wl, L);
    return;
  }
  for (int k = 0; k < nwl; k++) L[k] = rs->ground_radiance_scale * rspd_at(&rs->ground_spd, wl[k]);
}

vr_status vr_light_sky_create(rscene *rs, struct vr_matdb *db, vr_error *err) {
  (void)db;
  const vr_scene_sky *sk = &rs->s->sky;
  if (!sk->present) return VR_OK;
  if (sk->annual)
    return vr_error_set(err, VR_E_ARG,
                        "%s:%ld:%ld: sky: a whole weather file (weather= with no date= and time=) "
                        "is a year of skies, for an annual study (vr-render runs one for such a "
                        "scene), not one render",
                        rs->s->path, sk->loc.line, sk->loc.col);
  vr_status st = sk->cie_type == VR_SKY_PEREZ
                     ? vr_sky_create_perez(&sk->perez.lum, sk->sun_direction, &rs->sky, err)
                     : vr_sky_create(sk->cie_type, sk->sun_direction, &rs->sky, err);
  if (st) {
    vr_error_prefix(err, "%s:%ld:%ld: sky: ", rs->s->path, sk->loc.line, sk->loc.col);
    return st;
  }
  vr_quantity z;
  st = vr_sky_zenith_level(rs->sky, sk->level, &z, err);
  if (st) {
    vr_error_prefix(err, "%s:%ld:%ld: sky: ", rs->s->path, sk->loc.line, sk->loc.col);
    return st;
  }
  st = vr_rscene_spectrum(rs, db, sk->spectrum, "D65", &sk->loc, &rs->sky_spd, err);
  if (st) return st;
  /* sky_spd becomes the spectral radiance at the zenith. */
  bool photometric = z.unit == VR_UNIT_CD_M2;
  st = vr_rscene_normalise(rs, &rs->sky_spd, z, photometric, &sk->loc, "sky", err);
  if (st) return st;
  rs->has_sky = true;
  /* Ground glow: a Lambertian ground of reflectance rho under the sky
   * and the sun, L = rho (E_sky + E_sun,h) / pi, with the sky's spectrum
   * for the sky part and the sun's for the sun part. */
  double eh = vr_sky_horizontal_ratio(rs->sky); /* E_h / L_z */
  int n = rs->sky_spd.n;
  rs->ground_spd.lo = rs->sky_spd.lo;
  rs->ground_spd.n = n;
  rs->ground_spd.v = malloc((size_t)n * sizeof *rs->ground_spd.v);
  if (!rs->ground_spd.v) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  for (int i = 0; i < n; i++) rs->ground_spd.v[i] = rs->sky_spd.v[i] * eh;
  for (size_t l = 0; l < rs->nlights; l++) {
    const rlight *li = &rs->lights[l];
    if (li->kind != VR_LIGHT_SUN || li->axis[2] <= 0) continue;
    for (int i = 0; i < n; i++) rs->ground_spd.v[i] += rspd_at(&li->spd, rs->ground_spd.lo + i) * li->axis[2];
  }
  rs->ground_radiance_scale = sk->ground_reflectance / M_PI;
  return VR_OK;
}

double vr_light_ground_sun_share(const rscene *rs, double nm) {
  if (!rs->has_sky) return 0.0;
  double g = rspd_at(&rs->ground_spd, nm);
  if (!(g > 0)) return 0.0;
  double share = 1.0 - rspd_at(&rs->sky_spd, nm) * vr_sky_horizontal_ratio(rs->sky) / g;
  return share < 0 ? 0 : share > 1 ? 1 : share;
}

double vr_light_sky_horizontal_lx(const rscene *rs) {
  if (!rs->has_sky) return 0.0;
  double eh = vr_sky_horizontal_ratio(rs->sky), lx = 0;
  for (double nm = rs->lmin; nm <= rs->lmax; nm += 1.0) {
    double xyz[3];
    vr_cmf_eval(VR_CIE1931_2DEG, nm, xyz);
    lx += xyz[1] * rspd_at(&rs->sky_spd, nm) * eh;
  }
  return VR_KM * lx;
}

void vr_light_sky_destroy(rscene *rs) {
  vr_sky_destroy(rs->sky);
  rs->sky = NULL;
  free(rs->sky_spd.v);
  free(rs->ground_spd.v);
  rs->sky_spd.v = rs->ground_spd.v = NULL;
}

double vr_light_sky_power(const rscene *rs) {
  if (!rs->has_sky) return 0.0;
  /* Power through a disc of the scene's radius from the whole sky, taken
   * as horizontal irradiance times the disc's area: only for sharing the
   * photons among sources, never in an estimate. */
  double e = 0;
  for (double nm = rs->lmin; nm <= rs->lmax; nm += 1.0) e += rspd_at(&rs->sky_spd, nm);
  return e * vr_sky_horizontal_ratio(rs->sky) * M_PI * rs->scene_radius * rs->scene_radius;
}

double vr_light_ground_power(const rscene *rs) {
  if (!rs->has_sky) return 0.0;
  /* The ground glow's upward flux through a horizontal disc of the
   * scene's radius: pi L A for a uniform radiance L over the lower
   * hemisphere.  Only for sharing the photons among sources. */
  double e = 0;
  for (double nm = rs->lmin; nm <= rs->lmax; nm += 1.0) e += rspd_at(&rs->ground_spd, nm);
  return rs->ground_radiance_scale * e * M_PI * M_PI * rs->scene_radius * rs->scene_radius;
}

/* A point on the disc of radius R perpendicular to d, centred on the
 * scene's centre moved 2R back along d: photons from far sources start
 * there and cross the whole scene. */
static void disc_origin(const rscene *rs, const double d[3], double u1, double u2, double o[3]) {
  double t[3], b[3];
  frame(d, t, b);
  double R = rs->scene_radius, r = R * sqrt(u1), ph = 2 * M_PI * u2;
  for (int a = 0; a < 3; a++)
    o[a] = rs->scene_centre[a] - 2 * R * d[a] + r * (cos(ph) * t[a] + sin(ph) * b[a]);
}

bool vr_light_emit_photon(const rscene *rs, size_t source, int nwl, const double *wl,
                          const vr_rng_key *key, photon_emit *out) {
  double u1 = vr_rng(key, VR_DIM_EMIT_U), u2 = vr_rng(key, VR_DIM_EMIT_V);
  double u3 = vr_rng(key, VR_DIM_EMIT_W), u4 = vr_rng(key, VR_DIM_EMIT_X);
  if (source < rs->nlights) {
    const rlight *l = &rs->lights[source];
    if (l->kind == VR_LIGHT_SUN) {
      double toward[3];
      cone_dir(l->axis, l->cos_sun, u3, u4, toward);
      for (int a = 0; a < 3; a++) out->dir[a] = -toward[a];
      disc_origin(rs, out->dir, u1, u2, out->org);
      double area = M_PI * rs->scene_radius * rs->scene_radius;
      for (int k = 0; k < nwl; k++) out->power[k] = rspd_at(&l->spd, wl[k]) * area;
      return true;
    }
    /* Directions uniform on the sphere (or within the spot's outer cone),
     * weighted by the distribution. */
    double pdf;
    if (l->kind == VR_LIGHT_SPOT) {
      cone_dir(l->axis, l->cos_outer, u1, u2, out->dir);
      pdf = 1.0 / (2 * M_PI * (1 - l->cos_outer));
    } else {
      cone_dir((double[3]){0, 0, 1}, -1.0, u1, u2, out->dir);
      pdf = 1.0 / (4 * M_PI);
    }
    double f = distribution(l, out->dir) / pdf;
    memcpy(out->org, l->pos, sizeof out->org);
    for (int k = 0; k < nwl; k++) out->power[k] = rspd_at(&l->spd, wl[k]) * f;
    return f > 0;
  }
  source -= rs->nlights;
  if (source < rs->nemitters) {
    uint32_t obj = rs->emitters[source];
    double n[3];
    vr_scene_tables_sample_object(rs->t, obj, u1, u2, vr_rng(key, VR_DIM_EMIT_Y), out->org, n);
    /* Cosine-weighted direction: L cos / (cos/pi) per unit area, times area. */
    double t[3], b[3];
    frame(n, t, b);
    double r = sqrt(u3), ph = 2 * M_PI * u4, z = sqrt(fmax(0, 1 - u3));
    for (int a = 0; a < 3; a++)
      out->dir[a] = z * n[a] + r * (cos(ph) * t[a] + sin(ph) * b[a]);
    double f = M_PI * rs->t->object_area[obj];
    double off = 1e-5 * (1 + fmax(fabs(out->org[0]), fmax(fabs(out->org[1]), fabs(out->org[2]))));
    for (int a = 0; a < 3; a++) out->org[a] += off * n[a];
    for (int k = 0; k < nwl; k++) out->power[k] = rspd_at(&rs->obj[obj].emission, wl[k]) * f;
    return true;
  }
  if (!rs->has_sky) return false;
  double d[3], pdf;
  if (source > rs->nemitters) {
    /* The ground glow: d (towards the source) uniform over the lower
     * hemisphere, pdf 1 / (2 pi), radiance ground_radiance_scale times
     * ground_spd whatever the direction (a Lambertian ground). */
    double z = -u3, rr = sqrt(fmax(0.0, 1.0 - z * z)), ph = 2 * M_PI * u4;
    d[0] = rr * cos(ph), d[1] = rr * sin(ph), d[2] = z;
    for (int a = 0; a < 3; a++) out->dir[a] = -d[a];
    disc_origin(rs, out->dir, u1, u2, out->org);
    double area = M_PI * rs->scene_radius * rs->scene_radius;
    for (int k = 0; k < nwl; k++)
      out->power[k] = rs->ground_radiance_scale * rspd_at(&rs->ground_spd, wl[k]) * area * 2 * M_PI;
    return rs->ground_radiance_scale > 0;
  }
  vr_sky_sample(rs->sky, u3, u4, d, &pdf);
  if (!(pdf > 0)) return false;
  double L[VR_MAX_WL];
  sky_radiance(rs, d, nwl, wl, L);
  for (int a = 0; a < 3; a++) out->dir[a] = -d[a];
  disc_origin(rs, out->dir, u1, u2, out->org);
  double area = M_PI * rs->scene_radius * rs->scene_radius;
  for (int k = 0; k < nwl; k++) out->power[k] = L[k] * area / pdf;
  return true;
}

/* ---- photons through the portals (portals.c) ---- */

bool vr_light_emit_portal_photon(const rscene *rs, int kind, int nwl, const double *wl,
                                 const vr_rng_key *key, photon_emit *out, double *to_portal) {
  if (!rs->nportals) return false;
  double y[3], d[3], w[3], L[VR_MAX_WL], pdf = 1.0;
  size_t j;
  vr_portal_point(rs, vr_rng(key, VR_DIM_EMIT_Y), vr_rng(key, VR_DIM_EMIT_U),
                  vr_rng(key, VR_DIM_EMIT_V), y, &j);
  double u3 = vr_rng(key, VR_DIM_EMIT_W), u4 = vr_rng(key, VR_DIM_EMIT_X);
  /* w: from the portal towards the source; the photon travels along -w. */
  if (kind == PORTAL_SRC_SUN) {
    if (rs->sun_light >= rs->nlights) return false;
    const rlight *l = &rs->lights[rs->sun_light];
    cone_dir(l->axis, l->cos_sun, u3, u4, w);
    /* The sun's spectrum is its irradiance normal to the beam: the flux
     * through area A at incidence theta is E A cos theta. */
    for (int k = 0; k < nwl; k++) L[k] = rspd_at(&l->spd, wl[k]);
  } else if (kind == PORTAL_SRC_SKY) {
    if (!rs->has_sky) return false;
    vr_sky_sample(rs->sky, u3, u4, w, &pdf);
    if (!(pdf > 0)) return false;
    sky_radiance(rs, w, nwl, wl, L);
  } else {
    if (!rs->has_sky || !(rs->ground_radiance_scale > 0)) return false;
    double z = -u3, rr = sqrt(fmax(0.0, 1.0 - z * z)), ph = 2 * M_PI * u4;
    w[0] = rr * cos(ph), w[1] = rr * sin(ph), w[2] = z;
    pdf = 1.0 / (2 * M_PI);
    for (int k = 0; k < nwl; k++) L[k] = rs->ground_radiance_scale * rspd_at(&rs->ground_spd, wl[k]);
  }
  for (int a = 0; a < 3; a++) d[a] = -w[a];
  double c = rs->portals[j].n[0] * d[0] + rs->portals[j].n[1] * d[1] + rs->portals[j].n[2] * d[2];
  if (!(c > 0)) return false; /* leaving the room: not light that enters by this portal */
  double R = rs->scene_radius;
  for (int a = 0; a < 3; a++) {
    out->dir[a] = d[a];
    out->org[a] = y[a] - 2 * R * d[a];
  }
  *to_portal = 2 * R;
  bool any = false;
  for (int k = 0; k < nwl; k++) any |= (out->power[k] = L[k] * c * rs->portal_area / pdf) > 0;
  return any;
}

double vr_light_portal_power(const rscene *rs, int kind) {
  double e = 0;
  if (kind == PORTAL_SRC_SUN) {
    if (rs->sun_light >= rs->nlights) return 0;
    const rlight *l = &rs->lights[rs->sun_light];
    double a = 0;
    for (size_t j = 0; j < rs->nportals; j++) {
      const rportal *q = &rs->portals[j];
      double c = -(q->n[0] * l->axis[0] + q->n[1] * l->axis[1] + q->n[2] * l->axis[2]);
      if (c > 0) a += q->area * c;
    }
    for (double nm = rs->lmin; nm <= rs->lmax; nm += 1.0) e += rspd_at(&l->spd, nm);
    return e * a;
  }
  if (!rs->has_sky) return 0;
  const rspd *spd = kind == PORTAL_SRC_SKY ? &rs->sky_spd : &rs->ground_spd;
  double scale = kind == PORTAL_SRC_SKY ? vr_sky_horizontal_ratio(rs->sky) : rs->ground_radiance_scale * M_PI;
  for (double nm = rs->lmin; nm <= rs->lmax; nm += 1.0) e += rspd_at(spd, nm);
  return 0.5 * e * scale * rs->portal_area;
}
