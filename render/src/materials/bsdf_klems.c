/* A Klems BSDF XML file as a material (vr/bsdf_xml.h for the file, the
 * basis and its conventions).
 *
 * Frame.  z is the surface normal n, the file's front (its "Front" blocks
 * are light arriving from the +n side); y is the settings' up direction
 * projected into the surface (default world +z, or +y for a horizontal
 * surface), x = y cross z.  Patches follow LBNL's convention as Radiance
 * reads it (src/common/bsdf_m.c): a direction v pointing away from the
 * surface has theta = acos |v.z| on its own side, and azimuth
 * atan2(-v.y, -v.x) when it is where light comes from (incident), atan2(v.y,
 * v.x) when it is where light goes (exiting), so that incident patch i
 * continues straight through, or mirrors, into exiting patch i.
 *
 * Value.  The Visible band, the same at every wavelength (a grey BSDF):
 * it is what the file says about light as the eye weighs it.  Radiance's
 * BSDF material uses the same band of a file without colour data.
 *
 * Sampling.  From the direction the path knows, a patch on either side is
 * drawn in proportion to the BSDF times the candidate patch's projected
 * solid angle (the row of the matrix for radiance, where the exiting
 * direction is known; its column for importance, where the incident one
 * is), then a direction uniformly in projected solid angle inside the
 * patch.  The weight f |cos| / pdf is then the row's or column's sum, the
 * same for every direction drawn. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "materials/bsdf_internal.h"
#include "vr/bsdf_xml.h"

struct vr_klems_bsdf {
  vr_klems_basis basis;
  double *m[VR_BSDF_SIDES]; /* Visible band, m[out * n + in], 1/sr */
  double *lambda;           /* projected solid angle of each patch */
  /* Sampling tables: [mode][side of the known direction][patch] -> the
   * cumulative weights of 2n candidates (n on the known direction's side,
   * reflection; n on the other, transmission) and their total. */
  double *cdf, *total;
  double up[3]; /* NAN: the default */
};

static size_t table_at(const vr_klems_bsdf *k, int mode, int side, int patch) {
  return ((size_t)mode * 2 + (size_t)side) * (size_t)k->basis.n + (size_t)patch;
}

/* The matrix for light arriving on side s_in (0 front) and leaving on s_out. */
static const double *side_matrix(const vr_klems_bsdf *k, int s_in, int s_out) {
  if (s_in == 0) return s_out == 0 ? k->m[VR_BSDF_RF] : k->m[VR_BSDF_TF];
  return s_out == 1 ? k->m[VR_BSDF_RB] : k->m[VR_BSDF_TB];
}

static void build_tables(vr_klems_bsdf *k) {
  int n = k->basis.n;
  for (int mode = 0; mode < 2; mode++)
    for (int side = 0; side < 2; side++)
      for (int p = 0; p < n; p++) {
        double *c = k->cdf + table_at(k, mode, side, p) * (size_t)(2 * n), sum = 0;
        for (int cand = 0; cand < 2 * n; cand++) {
          int j = cand % n, other = cand >= n ? 1 - side : side;
          double w;
          if (mode == VR_TRANSPORT_RADIANCE) /* known: exiting p on side; candidate: incident j */
            w = side_matrix(k, other, side)[(size_t)p * n + j] * k->lambda[j];
          else /* known: incident p on side; candidate: exiting j */
            w = side_matrix(k, side, other)[(size_t)j * n + p] * k->lambda[j];
          sum += w;
          c[cand] = sum;
        }
        k->total[table_at(k, mode, side, p)] = sum;
      }
}

vr_status vr_bsdfi_klems_create(vr_bsdf *b, const vr_scene_material *sm, vr_error *err) {
  vr_bsdf_xml *x = NULL;
  vr_status st = vr_bsdf_xml_read(sm->bsdf_file, &x, err);
  if (st) return st;
  const vr_bsdf_band *vis = vr_bsdf_xml_band(x, "Visible");
  if (!vis) {
    vr_bsdf_xml_destroy(x);
    return vr_error_set(err, VR_E_NOT_FOUND,
                        "%s has no Visible band: the renderer uses a file's Visible matrices "
                        "(spectral BSDF XML files are not rendered)", sm->bsdf_file);
  }
  for (int s = 0; s < VR_BSDF_SIDES; s++)
    if (!vis->m[s]) {
      vr_bsdf_xml_destroy(x);
      return vr_error_set(err, VR_E_NOT_FOUND,
                          "%s: the Visible band has no '%s' block; a window needs all four "
                          "(transmission and reflection, front and back)",
                          sm->bsdf_file, vr_bsdf_side_name((vr_bsdf_side)s));
    }
  vr_klems_bsdf *k = calloc(1, sizeof *k);
  int n = x->basis.n;
  if (k) {
    k->basis = x->basis;
    k->lambda = malloc((size_t)n * sizeof(double));
    k->cdf = malloc((size_t)4 * n * 2 * n * sizeof(double));
    k->total = malloc((size_t)4 * n * sizeof(double));
  }
  if (!k || !k->lambda || !k->cdf || !k->total) {
    vr_bsdf_xml_destroy(x);
    vr_bsdfi_klems_destroy(k);
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  for (int s = 0; s < VR_BSDF_SIDES; s++) {
    k->m[s] = vis->m[s];
    ((vr_bsdf_band *)vis)->m[s] = NULL; /* taken over */
  }
  for (int p = 0; p < n; p++) k->lambda[p] = vr_klems_lambda(&k->basis, p);
  memcpy(k->up, sm->bsdf_up, sizeof k->up);
  build_tables(k);
  b->klems = k;
  b->kind = VR_BK_KLEMS;
  b->lobes = VR_LOBE_GLOSSY_R | VR_LOBE_GLOSSY_T;
  const char *slash = strrchr(sm->bsdf_file, '/');
  snprintf(b->desc, sizeof b->desc, "BSDF XML %.60s (%.40s%s%.40s, %d Klems patches, Visible band as grey)",
           slash ? slash + 1 : sm->bsdf_file, x->name[0] ? x->name : "no name",
           x->manufacturer[0] ? ", " : "", x->manufacturer, n);
  vr_bsdf_xml_destroy(x);
  return VR_OK;
}

void vr_bsdfi_klems_destroy(vr_klems_bsdf *k) {
  if (!k) return;
  for (int s = 0; s < VR_BSDF_SIDES; s++) free(k->m[s]);
  free(k->lambda);
  free(k->cdf);
  free(k->total);
  free(k);
}

/* x = y cross z, y the up direction in the surface, z = n. */
static vr_shading_frame frame_of(const vr_klems_bsdf *k, vr_vec3 n) {
  double up[3] = {k->up[0], k->up[1], k->up[2]};
  if (isnan(up[0])) {
    up[0] = 0, up[1] = fabs(n.z) < 0.999 ? 0 : 1, up[2] = fabs(n.z) < 0.999 ? 1 : 0;
  }
  double nz[3] = {n.x, n.y, n.z}, d = vr_dot3(up, nz), y[3], x[3];
  for (int a = 0; a < 3; a++) y[a] = up[a] - d * nz[a];
  if (!(vr_normalize3(y) > 1e-9)) /* up along the normal: any frame */
    vr_frame3(nz, x, y);
  vr_cross3(y, nz, x);
  return (vr_shading_frame){{x[0], x[1], x[2]}, {y[0], y[1], y[2]}, n};
}

/* The patch of a local direction: incident (where light comes from) or
 * exiting (where it goes); -1 in the surface's plane. */
static int patch_of(const vr_klems_basis *b, vr_vec3 v, bool incident) {
  if (v.z == 0.0 || !isfinite(v.z)) return -1;
  double t = acos(fmin(1.0, fabs(v.z))) * 180.0 / M_PI;
  double phi = incident ? atan2(-v.y, -v.x) : atan2(v.y, v.x);
  return vr_klems_patch(b, t, phi * 180.0 / M_PI);
}

void vr_bsdfi_klems_eval(const vr_bsdf *b, vr_vec3 n, vr_vec3 wo, vr_vec3 wi, int nwl,
                         vr_transport mode, double *f, double *pdf) {
  const vr_klems_bsdf *k = b->klems;
  vr_shading_frame fr = frame_of(k, n);
  vr_vec3 o = vr_bsdfi_to_local(&fr, wo), i = vr_bsdfi_to_local(&fr, wi);
  /* Light goes from `from` to `to`: wi to wo for radiance, wo to wi for importance. */
  vr_vec3 from = mode == VR_TRANSPORT_RADIANCE ? i : o, to = mode == VR_TRANSPORT_RADIANCE ? o : i;
  int pin = patch_of(&k->basis, from, true), pout = patch_of(&k->basis, to, false);
  if (pin < 0 || pout < 0) return;
  int s_in = from.z > 0 ? 0 : 1, s_out = to.z > 0 ? 0 : 1;
  double v = side_matrix(k, s_in, s_out)[(size_t)pout * k->basis.n + pin];
  for (int w = 0; w < nwl; w++) f[w] = v;
  if (pdf) {
    /* The sampler knows wo (the exiting direction for radiance, the
     * incident one for importance) and draws wi. */
    int known = mode == VR_TRANSPORT_RADIANCE ? pout : pin;
    int side = (mode == VR_TRANSPORT_RADIANCE ? s_out : s_in);
    double tot = k->total[table_at(k, (int)mode, side, known)];
    *pdf = tot > 0 ? v * fabs(i.z) / tot : 0.0;
  }
}

bool vr_bsdfi_klems_sample(const vr_bsdf *b, vr_vec3 n, vr_vec3 wo, int nwl, vr_transport mode,
                           double u1, double u2, double u3, vr_bsdf_sample *out) {
  const vr_klems_bsdf *k = b->klems;
  int nb = k->basis.n;
  vr_shading_frame fr = frame_of(k, n);
  vr_vec3 o = vr_bsdfi_to_local(&fr, wo);
  bool radiance = mode == VR_TRANSPORT_RADIANCE;
  int known = patch_of(&k->basis, o, !radiance), side = o.z > 0 ? 0 : 1;
  if (known < 0) return false;
  size_t at = table_at(k, (int)mode, side, known);
  double tot = k->total[at];
  if (!(tot > 0)) return false;
  const double *c = k->cdf + at * (size_t)(2 * nb);
  double target = u3 * tot;
  int lo = 0, hi = 2 * nb - 1;
  while (lo < hi) { /* first candidate whose cumulative weight exceeds target */
    int mid = (lo + hi) / 2;
    if (c[mid] > target) hi = mid;
    else lo = mid + 1;
  }
  double prev = lo ? c[lo - 1] : 0.0, w = c[lo] - prev;
  if (!(w > 0)) return false;
  int j = lo % nb;
  bool transmit = lo >= nb;
  /* A direction uniform in projected solid angle inside patch j. */
  int r = k->basis.nrings - 1;
  while (r > 0 && k->basis.first[r] > j) r--;
  double s0 = sin(k->basis.theta_lo[r] * M_PI / 180), s1 = sin(k->basis.theta_hi[r] * M_PI / 180);
  double sin2 = s0 * s0 + u1 * (s1 * s1 - s0 * s0), st = sqrt(sin2), ct = sqrt(fmax(0.0, 1.0 - sin2));
  if (!(ct > 0)) return false;
  double width = 2 * M_PI / k->basis.nphi[r];
  double phi = (j - k->basis.first[r]) * width + (u2 - 0.5) * width;
  double sgn = radiance ? -1.0 : 1.0; /* wi is incident for radiance, exiting for importance */
  int wside = transmit ? 1 - side : side;
  vr_vec3 v = {sgn * st * cos(phi), sgn * st * sin(phi), wside == 0 ? ct : -ct};
  out->wi = vr_bsdfi_to_world(&fr, v);
  out->pdf = (w / tot) * ct / k->lambda[j];
  for (int q = 0; q < nwl; q++) out->weight[q] = tot;
  out->lobe = transmit ? VR_LOBE_GLOSSY_T : VR_LOBE_GLOSSY_R;
  out->eta = 1.0;
  out->terminate_secondary = false;
  return true;
}

void vr_bsdfi_klems_rt(const vr_bsdf *b, double cos_i, double *R, double *T) {
  const vr_klems_bsdf *k = b->klems;
  int in = vr_klems_patch(&k->basis, acos(fmin(1.0, fabs(cos_i))) * 180 / M_PI, 0), nb = k->basis.n;
  int s = cos_i > 0 ? 0 : 1;
  const double *mr = side_matrix(k, s, s), *mt = side_matrix(k, s, 1 - s);
  double r = 0, t = 0;
  for (int o = 0; o < nb; o++) {
    r += mr[(size_t)o * nb + in] * k->lambda[o];
    t += mt[(size_t)o * nb + in] * k->lambda[o];
  }
  *R = r;
  *T = t;
}
