/* CIE skies: the ISO 15469:2004 / CIE S 011/E:2003 general sky and the
 * traditional CIE overcast sky, the ratio of diffuse horizontal illuminance
 * to zenith luminance, and a tabulated importance sampler.
 *
 * The parameter table is Table 1 of ISO 15469:2004 (= CIE S 011/E:2003),
 * also printed in Darula & Kittler, "CIE general sky standard defining
 * luminance distributions", Proc. eSim 2002, Table 1.  It was checked entry
 * by entry against two independent copies: DigitalRune's
 * CieSkyParameters.cs (DigitalRune/DigitalRune) and rcaiman's
 * inst/external/15_CIE_standard_skies.csv (GastonMauroDiaz/rcaiman). */
#include "vr/sky.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "vr/perez.h"
#include "vr/photometry.h"

#define PI 3.14159265358979323846

/* Gradation groups I..VI and indicatrix groups 1..6 combined as in
 * ISO 15469:2004 Table 1 (types 1..15). */
static const vr_sky_params TABLE[15] = {
    {4.0, -0.70, 0.0, -1.0, 0.00},   /* 1  I.1  overcast, steep gradation, azimuthal uniformity */
    {4.0, -0.70, 2.0, -1.5, 0.15},   /* 2  I.2  overcast, steep, slight brightening to the sun */
    {1.1, -0.80, 0.0, -1.0, 0.00},   /* 3  II.1 overcast, moderate gradation, uniform azimuth */
    {1.1, -0.80, 2.0, -1.5, 0.15},   /* 4  II.2 overcast, moderate, slight brightening */
    {0.0, -1.00, 0.0, -1.0, 0.00},   /* 5  III.1 sky of uniform luminance */
    {0.0, -1.00, 2.0, -1.5, 0.15},   /* 6  III.2 partly cloudy, slight brightening */
    {0.0, -1.00, 5.0, -2.5, 0.30},   /* 7  III.3 partly cloudy, brighter circumsolar region */
    {0.0, -1.00, 10.0, -3.0, 0.45},  /* 8  III.4 partly cloudy, distinct solar corona */
    {-1.0, -0.55, 2.0, -1.5, 0.15},  /* 9  IV.2 partly cloudy, obscured sun */
    {-1.0, -0.55, 5.0, -2.5, 0.30},  /* 10 IV.3 partly cloudy, brighter circumsolar region */
    {-1.0, -0.55, 10.0, -3.0, 0.45}, /* 11 IV.4 white-blue sky, distinct solar corona */
    {-1.0, -0.32, 10.0, -3.0, 0.45}, /* 12 V.4  CIE standard clear sky, low turbidity */
    {-1.0, -0.32, 16.0, -3.0, 0.30}, /* 13 V.5  CIE standard clear sky, polluted atmosphere */
    {-1.0, -0.15, 16.0, -3.0, 0.30}, /* 14 VI.5 cloudless turbid sky, broad solar corona */
    {-1.0, -0.15, 24.0, -2.8, 0.15}, /* 15 VI.6 white-blue turbid sky, broad solar corona */
};

enum { NU = VR_SKY_SAMPLER_NU, NPHI = VR_SKY_SAMPLER_NPHI };

struct vr_sky {
  int type;            /* 0..15, or VR_SKY_PEREZ */
  vr_sky_params p;
  double sun[3];       /* unit, towards the sun */
  double sun_zenith;   /* Zs, radians */
  double inv_norm;     /* 1 / (f(Zs) phi(0)) */
  double ratio;        /* E_h / Lz, sr */
  /* Sampler: cell probabilities, the marginal CDF over cos Z rows and one
   * conditional CDF over azimuth per row. */
  double prob[NU * NPHI];
  double row_cdf[NU + 1];
  double col_cdf[NU * (NPHI + 1)];
};

vr_status vr_sky_params_of(int cie_type, vr_sky_params *out, vr_error *err) {
  if (cie_type < 1 || cie_type > 15)
    return vr_error_set(err, VR_E_ARG,
                        "CIE standard general sky type %d does not exist (types are 1..15)",
                        cie_type);
  *out = TABLE[cie_type - 1];
  return VR_OK;
}

double vr_sky_gradation(const vr_sky_params *p, double cos_z) {
  /* exp(b / cos Z) -> 0 as Z -> 90 deg for b < 0 (every type has b < 0),
   * so phi(90 deg) = 1; the limit is taken explicitly at and below the
   * horizon rather than dividing by zero. */
  if (!(cos_z > 0.0)) return 1.0;
  return 1.0 + p->a * exp(p->b / cos_z);
}

double vr_sky_indicatrix(const vr_sky_params *p, double chi) {
  double cc = cos(chi);
  return 1.0 + p->c * (exp(p->d * chi) - exp(p->d * PI / 2.0)) + p->e * cc * cc;
}

static double gradation_of(const vr_sky *s, double cos_z) {
  return s->type == VR_SKY_PEREZ ? vr_perez_gradation(&s->p, cos_z) : vr_sky_gradation(&s->p, cos_z);
}

static double indicatrix_of(const vr_sky *s, double chi) {
  if (s->type == 0) return 1.0;
  return s->type == VR_SKY_PEREZ ? vr_perez_indicatrix(&s->p, chi) : vr_sky_indicatrix(&s->p, chi);
}

/* Relative luminance (before normalisation) from cos Z and cos chi. */
static double shape(const vr_sky *s, double cos_z, double cos_chi) {
  if (s->type == 0) return (1.0 + 2.0 * cos_z) / 3.0; /* Moon & Spencer 1942 */
  if (cos_chi > 1.0) cos_chi = 1.0;
  if (cos_chi < -1.0) cos_chi = -1.0;
  return indicatrix_of(s, acos(cos_chi)) * gradation_of(s, cos_z);
}

double vr_sky_relative_luminance(const vr_sky *s, const double d[3]) {
  if (d[2] < 0.0) return 0.0;
  double cos_chi = d[0] * s->sun[0] + d[1] * s->sun[1] + d[2] * s->sun[2];
  return shape(s, d[2], cos_chi) * s->inv_norm;
}

int vr_sky_type(const vr_sky *s) { return s->type; }
double vr_sky_horizontal_ratio(const vr_sky *s) { return s->ratio; }

/* ---- E_h / Lz ------------------------------------------------------------ */

/* Gauss-Legendre nodes and weights on [-1, 1] by Newton's iteration on the
 * Legendre recurrence (Press et al., Numerical Recipes 3rd ed., section 4.6,
 * routine gauleg).  n is small and the rule is rebuilt per call, which keeps
 * the module free of shared tables. */
#define GL_N 16
static void gauss_legendre(double x[GL_N], double w[GL_N]) {
  const int n = GL_N;
  for (int i = 0; i < (n + 1) / 2; i++) {
    double z = cos(PI * (i + 0.75) / (n + 0.5)), pp = 1.0;
    for (int it = 0; it < 100; it++) {
      double p1 = 1.0, p2 = 0.0;
      for (int j = 0; j < n; j++) {
        double p3 = p2;
        p2 = p1;
        p1 = ((2.0 * j + 1.0) * z * p2 - j * p3) / (j + 1);
      }
      pp = n * (z * p1 - p2) / (z * z - 1.0);
      double z1 = z;
      z = z1 - p1 / pp;
      if (fabs(z - z1) < 1e-15) break;
    }
    x[i] = -z;
    x[n - 1 - i] = z;
    w[i] = w[n - 1 - i] = 2.0 / ((1.0 - z * z) * pp * pp);
  }
}

typedef struct vr_sky_quad {
  double x[GL_N], w[GL_N];
} vr_sky_quad;

/* Gradation part times cos Z, the integrand of E_h along a ring. */
static double radial(const vr_sky *s, double u) {
  if (u <= 0.0) return 0.0;
  if (s->type == 0) return (1.0 + 2.0 * u) / 3.0 * u;
  return gradation_of(s, u) * u;
}

/* Over the ring at angular distance chi from the sun: the integral of
 * phi(Z) cos Z dpsi over the part above the horizon, psi the position angle
 * around the sun.  cos Z = cos Zs cos chi + sin Zs sin chi cos psi
 * (spherical law of cosines), so the ring is above the horizon for
 * |psi| <= psi_max = acos(-cot Zs cot chi). */
static double ring(const vr_sky *s, const vr_sky_quad *q, double chi) {
  double A = cos(s->sun_zenith) * cos(chi), B = sin(s->sun_zenith) * sin(chi);
  double psi_max;
  if (B < 1e-300) {
    psi_max = A >= 0.0 ? PI : 0.0;
  } else {
    double x = -A / B;
    psi_max = x <= -1.0 ? PI : x >= 1.0 ? 0.0 : acos(x);
  }
  if (psi_max <= 0.0) return 0.0;
  /* The integrand is smooth on [0, psi_max] (it falls to 0 at psi_max), so
   * a few panels of Gauss-Legendre converge quickly. */
  const int panels = 4;
  double h = psi_max / panels, sum = 0.0;
  for (int k = 0; k < panels; k++) {
    double mid = (k + 0.5) * h;
    for (int i = 0; i < GL_N; i++) {
      double psi = mid + 0.5 * h * q->x[i];
      sum += q->w[i] * radial(s, A + B * cos(psi));
    }
  }
  return 2.0 * sum * 0.5 * h; /* both halves of the ring */
}

/* E_h / Lz = norm * int_0^pi f(chi) sin chi ring(chi) dchi.  The ring is
 * entirely above the horizon for chi <= pi/2 - Zs and entirely below for
 * chi >= pi/2 + Zs; in between psi_max has square-root ends, which the
 * substitution chi = chi1 + (chi2 - chi1)(1 - cos(pi t))/2 smooths out.
 * Working around the sun rather than the zenith keeps the circumsolar peak
 * of f (exp(d chi), a cusp in any other coordinates) smooth. */
static double horizontal_ratio(const vr_sky *s) {
  vr_sky_quad q;
  gauss_legendre(q.x, q.w);
  double chi1 = PI / 2.0 - s->sun_zenith, chi2 = PI / 2.0 + s->sun_zenith;
  double total = 0.0;
  if (chi1 > 0.0) {
    const int panels = 16;
    double h = chi1 / panels;
    for (int k = 0; k < panels; k++) {
      double mid = (k + 0.5) * h, part = 0.0;
      for (int i = 0; i < GL_N; i++) {
        double chi = mid + 0.5 * h * q.x[i];
        part += q.w[i] * indicatrix_of(s, chi) * sin(chi) * ring(s, &q, chi);
      }
      total += part * 0.5 * h;
    }
  }
  if (chi2 > chi1) {
    const int panels = 32;
    double span = chi2 - chi1, h = 1.0 / panels;
    for (int k = 0; k < panels; k++) {
      double mid = (k + 0.5) * h, part = 0.0;
      for (int i = 0; i < GL_N; i++) {
        double t = mid + 0.5 * h * q.x[i];
        double chi = chi1 + span * 0.5 * (1.0 - cos(PI * t));
        double jac = span * 0.5 * PI * sin(PI * t);
        part += q.w[i] * jac * indicatrix_of(s, chi) * sin(chi) * ring(s, &q, chi);
      }
      total += part * 0.5 * h;
    }
  }
  return total * s->inv_norm;
}

/* ---- sampler ------------------------------------------------------------- */

static double lum_at(const vr_sky *s, double u, double az) {
  double sz = sqrt(fmax(0.0, 1.0 - u * u));
  double d[3] = {sz * sin(az), sz * cos(az), u};
  return vr_sky_relative_luminance(s, d);
}

static vr_status build_sampler(vr_sky *s, vr_error *err) {
  /* Cell means by the 3-point Gauss-Legendre rule in each coordinate
   * (nodes 0, +-sqrt(3/5), weights 8/9, 5/9): cells are equal in solid
   * angle (du dphi), so the mean is the cell's share of the integral. */
  const double gx[3] = {-sqrt(0.6), 0.0, sqrt(0.6)}, gw[3] = {5.0 / 9, 8.0 / 9, 5.0 / 9};
  const double du = 1.0 / NU, dphi = 2.0 * PI / NPHI;
  double total = 0.0;
  for (int i = 0; i < NU; i++) {
    double row = 0.0;
    for (int j = 0; j < NPHI; j++) {
      double m = 0.0;
      for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) {
          double u = (i + 0.5 + 0.5 * gx[a]) * du;
          double az = (j + 0.5 + 0.5 * gx[b]) * dphi;
          m += gw[a] * gw[b] * lum_at(s, u, az);
        }
      m *= 0.25;
      s->prob[i * NPHI + j] = m;
      row += m;
    }
    s->row_cdf[i + 1] = row;
    total += row;
  }
  if (!(total > 0.0) || !isfinite(total))
    return vr_error_set(err, VR_E_NUMERIC, "CIE sky type %d: luminance integral is %g", s->type,
                        total);
  s->row_cdf[0] = 0.0;
  double acc = 0.0;
  for (int i = 0; i < NU; i++) {
    double row = s->row_cdf[i + 1];
    double *c = s->col_cdf + (size_t)i * (NPHI + 1);
    c[0] = 0.0;
    double racc = 0.0;
    for (int j = 0; j < NPHI; j++) {
      racc += s->prob[i * NPHI + j];
      c[j + 1] = row > 0.0 ? racc / row : (j + 1.0) / NPHI;
      s->prob[i * NPHI + j] /= total;
    }
    c[NPHI] = 1.0;
    acc += row;
    s->row_cdf[i + 1] = acc / total;
  }
  s->row_cdf[NU] = 1.0;
  return VR_OK;
}

/* Largest k in [0, n) with cdf[k] <= u (cdf[0] = 0 <= u < 1 = cdf[n]),
 * skipping empty intervals so the returned one has positive width. */
static int find_interval(const double *cdf, int n, double u) {
  int lo = 0, hi = n; /* cdf[lo] <= u < cdf[hi] */
  while (hi - lo > 1) {
    int mid = (lo + hi) / 2;
    if (cdf[mid] <= u)
      lo = mid;
    else
      hi = mid;
  }
  return lo;
}

static double clamp01(double u) {
  if (!(u >= 0.0)) return 0.0; /* also NaN */
  if (u >= 1.0) return nextafter(1.0, 0.0);
  return u;
}

void vr_sky_sample(const vr_sky *s, double u1, double u2, double dir[3], double *pdf) {
  u1 = clamp01(u1);
  u2 = clamp01(u2);
  int i = find_interval(s->row_cdf, NU, u1);
  double w = s->row_cdf[i + 1] - s->row_cdf[i];
  double fu = w > 0.0 ? (u1 - s->row_cdf[i]) / w : 0.5;
  const double *c = s->col_cdf + (size_t)i * (NPHI + 1);
  int j = find_interval(c, NPHI, u2);
  double wc = c[j + 1] - c[j];
  double fv = wc > 0.0 ? (u2 - c[j]) / wc : 0.5;
  if (fu >= 1.0) fu = nextafter(1.0, 0.0);
  if (fv >= 1.0) fv = nextafter(1.0, 0.0);
  double u = (i + fu) / NU;
  double az = (j + fv) * (2.0 * PI / NPHI);
  double sz = sqrt(fmax(0.0, 1.0 - u * u));
  dir[0] = sz * sin(az);
  dir[1] = sz * cos(az);
  dir[2] = u;
  /* Cell probability over its solid angle (1/NU) (2 pi/NPHI). */
  if (pdf) *pdf = s->prob[i * NPHI + j] * NU * NPHI / (2.0 * PI);
}

double vr_sky_pdf(const vr_sky *s, const double d[3]) {
  if (!(d[2] >= 0.0)) return 0.0;
  int i = (int)(d[2] * NU);
  if (i >= NU) i = NU - 1;
  double az = atan2(d[0], d[1]);
  if (az < 0.0) az += 2.0 * PI;
  int j = (int)(az / (2.0 * PI) * NPHI);
  if (j >= NPHI) j = NPHI - 1;
  if (j < 0) j = 0;
  return s->prob[i * NPHI + j] * NU * NPHI / (2.0 * PI);
}

/* ---- creation and level --------------------------------------------------- */

/* A unit sun direction on or above the horizon (a rounding error below it
 * is taken as on it); what names the sky in messages. */
static vr_status sun_of(const double sun_dir[3], const char *what, double sun[3], vr_error *err) {
  if (!sun_dir) return vr_error_set(err, VR_E_ARG, "%s needs a sun direction", what);
  double len = sqrt(sun_dir[0] * sun_dir[0] + sun_dir[1] * sun_dir[1] + sun_dir[2] * sun_dir[2]);
  if (!(len > 0.0) || !isfinite(len))
    return vr_error_set(err, VR_E_ARG, "%s: the sun direction is not a direction", what);
  for (int k = 0; k < 3; k++) sun[k] = sun_dir[k] / len;
  if (sun[2] < -1e-9)
    return vr_error_set(err, VR_E_RANGE,
                        "%s: the sun is %.3f deg below the horizon; the sky is defined for a sun "
                        "on or above it",
                        what, -asin(sun[2]) * 180.0 / PI);
  if (sun[2] < 0.0) {
    sun[2] = 0.0;
    double h = hypot(sun[0], sun[1]);
    sun[0] /= h;
    sun[1] /= h;
  }
  return VR_OK;
}

/* Normalisation, E_h / Lz and the sampler of a sky whose type, parameters
 * and sun are set. */
static vr_status finish_sky(vr_sky *s, vr_sky **out, vr_error *err) {
  s->sun_zenith = acos(fmin(1.0, fmax(-1.0, s->sun[2])));
  if (s->type == 0) {
    s->inv_norm = 1.0;
  } else {
    double zen = indicatrix_of(s, s->sun_zenith) * gradation_of(s, 1.0);
    if (!(zen > 0.0) || !isfinite(zen)) {
      vr_status st = vr_error_set(err, VR_E_NUMERIC,
                                  "sky: the luminance is %g at the zenith (a=%g b=%g c=%g d=%g "
                                  "e=%g): it cannot be normalised%s",
                                  zen, s->p.a, s->p.b, s->p.c, s->p.d, s->p.e,
                                  s->type == VR_SKY_PEREZ
                                      ? " (the Perez model is outside the brightness and "
                                        "clearness it was fitted on)"
                                      : "");
      free(s);
      return st;
    }
    s->inv_norm = 1.0 / zen;
  }
  s->ratio = horizontal_ratio(s);
  vr_status st = build_sampler(s, err);
  if (st != VR_OK) {
    free(s);
    return st;
  }
  *out = s;
  return VR_OK;
}

vr_status vr_sky_create(int cie_type, const double sun_dir[3], vr_sky **out, vr_error *err) {
  *out = NULL;
  if (cie_type < 0 || cie_type > 15)
    return vr_error_set(err, VR_E_ARG,
                        "sky type %d does not exist (0 = traditional CIE overcast, 1..15 = CIE "
                        "standard general sky)",
                        cie_type);
  double sun[3] = {0.0, 0.0, 1.0};
  if (cie_type != 0) {
    char what[48];
    snprintf(what, sizeof what, "CIE sky type %d", cie_type);
    vr_status st = sun_of(sun_dir, what, sun, err);
    if (st) return st;
  }
  vr_sky *s = calloc(1, sizeof *s);
  if (!s) return vr_error_set(err, VR_E_NOMEM, "out of memory for a sky");
  s->type = cie_type;
  for (int k = 0; k < 3; k++) s->sun[k] = sun[k];
  if (cie_type != 0) s->p = TABLE[cie_type - 1];
  return finish_sky(s, out, err);
}

vr_status vr_sky_create_perez(const vr_sky_params *p, const double sun_dir[3], vr_sky **out,
                              vr_error *err) {
  *out = NULL;
  double sun[3];
  vr_status st = sun_of(sun_dir, "Perez sky", sun, err);
  if (st) return st;
  if (!isfinite(p->a) || !isfinite(p->b) || !isfinite(p->c) || !isfinite(p->d) || !isfinite(p->e))
    return vr_error_set(err, VR_E_ARG, "Perez sky: a coefficient is not finite");
  vr_sky *s = calloc(1, sizeof *s);
  if (!s) return vr_error_set(err, VR_E_NOMEM, "out of memory for a sky");
  s->type = VR_SKY_PEREZ;
  s->p = *p;
  for (int k = 0; k < 3; k++) s->sun[k] = sun[k];
  return finish_sky(s, out, err);
}

void vr_sky_destroy(vr_sky *s) { free(s); }

vr_status vr_sky_zenith_level(const vr_sky *s, vr_quantity level, vr_quantity *zenith,
                              vr_error *err) {
  if (!(level.value >= 0.0) || !isfinite(level.value))
    return vr_error_set(err, VR_E_ARG, "sky level %g %s: must be a finite value >= 0",
                        level.value, vr_photometry_unit_name(level.unit));
  switch (level.unit) {
  case VR_UNIT_CD_M2:
  case VR_UNIT_W_M2_SR:
    *zenith = level;
    return VR_OK;
  case VR_UNIT_LX:
    zenith->value = level.value / s->ratio;
    zenith->unit = VR_UNIT_CD_M2;
    return VR_OK;
  case VR_UNIT_W_M2:
    zenith->value = level.value / s->ratio;
    zenith->unit = VR_UNIT_W_M2_SR;
    return VR_OK;
  default:
    return vr_error_set(err, VR_E_ARG,
                        "sky level %g %s: expected a diffuse horizontal illuminance (lx, W/m2) "
                        "or a zenith luminance (cd/m2, W/(m2 sr))",
                        level.value, vr_photometry_unit_name(level.unit));
  }
}
