/* The Klems angle basis and the figures of a Klems BSDF matrix (vr/bsdf_xml.h). */
#include "vr/bsdf_xml.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>

/* LBNL/Klems Full as WINDOW writes it in every file's AngleBasis (ring
 * centres, bounds and azimuth counts); 145 patches. */
/* The three Klems bases LBNL defines, ring bounds and azimuth counts (as
 * WINDOW writes them, and Radiance's src/common/bsdf_m.c tabulates them);
 * a ring's nominal angle is the middle of its bounds, 0 for the first. */
static const struct {
  const char *name;
  int nrings;
  double bound[10];
  int nphi[9];
} NAMED[] = {
    {"LBNL/Klems Full", 9, {0, 5, 15, 25, 35, 45, 55, 65, 75, 90}, {1, 8, 16, 20, 24, 24, 24, 16, 12}},
    {"LBNL/Klems Half", 7, {0, 6.5, 19.5, 32.5, 45.5, 58.5, 71.5, 90}, {1, 8, 12, 16, 20, 12, 8}},
    {"LBNL/Klems Quarter", 5, {0, 9, 27, 45, 63, 90}, {1, 8, 12, 12, 8}},
};

static void named(vr_klems_basis *b, int k) {
  memset(b, 0, sizeof *b);
  snprintf(b->name, sizeof b->name, "%s", NAMED[k].name);
  b->nrings = NAMED[k].nrings;
  for (int r = 0; r < b->nrings; r++) {
    b->theta_lo[r] = NAMED[k].bound[r];
    b->theta_hi[r] = NAMED[k].bound[r + 1];
    b->theta_c[r] = r ? 0.5 * (b->theta_lo[r] + b->theta_hi[r]) : 0;
    b->nphi[r] = NAMED[k].nphi[r];
  }
  vr_klems_finish(b, NULL);
}

void vr_klems_full(vr_klems_basis *b) { named(b, 0); }

bool vr_klems_named(const char *name, vr_klems_basis *b) {
  for (int k = 0; k < (int)(sizeof NAMED / sizeof NAMED[0]); k++)
    if (!strcasecmp(name, NAMED[k].name)) {
      named(b, k);
      return true;
    }
  return false;
}

vr_status vr_klems_finish(vr_klems_basis *b, vr_error *err) {
  if (b->nrings < 1 || b->nrings > VR_KLEMS_MAX_RINGS)
    return vr_error_set(err, VR_E_RANGE, "angle basis '%s': %d rings (expected 1 to %d)",
                        b->name, b->nrings, VR_KLEMS_MAX_RINGS);
  int n = 0;
  for (int r = 0; r < b->nrings; r++) {
    double lo = b->theta_lo[r], hi = b->theta_hi[r];
    double expect_lo = r ? b->theta_hi[r - 1] : 0;
    if (!(fabs(lo - expect_lo) < 1e-9) || !(hi > lo) || !(hi <= 90))
      return vr_error_set(err, VR_E_RANGE,
                          "angle basis '%s': ring %d spans [%g, %g] degrees; rings must follow "
                          "one another from 0 to 90",
                          b->name, r + 1, lo, hi);
    if (b->nphi[r] < 1 || b->nphi[r] > 100000)
      return vr_error_set(err, VR_E_RANGE, "angle basis '%s': ring %d has %d azimuths",
                          b->name, r + 1, b->nphi[r]);
    if (r == 0 && b->nphi[0] != 1)
      return vr_error_set(err, VR_E_RANGE,
                          "angle basis '%s': the first ring (around the normal) has %d azimuths; "
                          "a Klems basis has one patch there",
                          b->name, b->nphi[0]);
    b->first[r] = n;
    n += b->nphi[r];
  }
  if (n > VR_KLEMS_MAX_PATCHES)
    return vr_error_set(err, VR_E_RANGE,
                        "angle basis '%s': %d patches; at most %d are read (a Klems full basis "
                        "has 145), so that a file cannot ask for gigabytes",
                        b->name, n, VR_KLEMS_MAX_PATCHES);
  if (!(fabs(b->theta_hi[b->nrings - 1] - 90) < 1e-9))
    return vr_error_set(err, VR_E_RANGE, "angle basis '%s': the rings end at %g degrees, not 90",
                        b->name, b->theta_hi[b->nrings - 1]);
  b->n = n;
  return VR_OK;
}

static int ring_of(const vr_klems_basis *b, int patch) {
  int r = b->nrings - 1;
  while (r > 0 && b->first[r] > patch) r--;
  return r;
}

double vr_klems_lambda(const vr_klems_basis *b, int patch) {
  int r = ring_of(b, patch);
  double s1 = sin(b->theta_hi[r] * M_PI / 180), s0 = sin(b->theta_lo[r] * M_PI / 180);
  return M_PI * (s1 * s1 - s0 * s0) / b->nphi[r];
}

int vr_klems_patch(const vr_klems_basis *b, double theta_deg, double phi_deg) {
  if (!(theta_deg >= 0 && theta_deg <= 90)) return -1;
  int r = 0;
  while (r < b->nrings - 1 && theta_deg > b->theta_hi[r]) r++;
  double w = 360.0 / b->nphi[r];
  double p = fmod(phi_deg, 360);
  if (p < 0) p += 360;
  int k = (int)floor(p / w + 0.5) % b->nphi[r];
  return b->first[r] + k;
}

void vr_klems_direction(const vr_klems_basis *b, int patch, double *theta_deg, double *phi_deg) {
  int r = ring_of(b, patch);
  *theta_deg = b->theta_c[r];
  *phi_deg = (patch - b->first[r]) * 360.0 / b->nphi[r];
}

void vr_klems_figures_of(const vr_klems_basis *b, const double *m, int in, vr_klems_figures *f) {
  int n = b->n;
  double lam[VR_KLEMS_MAX_PATCHES], hemi = 0, dd = 0; /* each patch's Lambda, once */
  for (int p = 0; p < n; p++) lam[p] = vr_klems_lambda(b, p);
  for (int o = 0; o < n; o++) hemi += m[(size_t)o * n + in] * lam[o];
  for (int i = 0; i < n; i++) {
    double s = 0;
    for (int o = 0; o < n; o++) s += m[(size_t)o * n + i] * lam[o];
    dd += s * lam[i];
  }
  f->direct_direct = m[(size_t)in * n + in] * lam[in];
  f->direct_hemispherical = hemi;
  f->direct_diffuse = hemi - f->direct_direct;
  f->diffuse_diffuse = dd / M_PI;
}
