/* The Perez all-weather sky (Perez et al. 1990 and 1993): clearness,
 * brightness, luminous efficacies and the luminance coefficients.  See
 * vr/perez.h for the sources of the tables and the conventions. */
#include "vr/perez.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define PI 3.14159265358979323846

const double VR_PEREZ_BOUNDS[9] = {1.0, 1.065, 1.230, 1.500, 1.950, 2.800, 4.500, 6.200, 12.01};

#define EPS_MIN 1.0
#define EPS_MAX 12.01
#define DELTA_MIN 0.01
#define DELTA_MAX 0.6

/* Perez, Seals & Michalsky 1993, Table 1 (with the erratum), per clearness
 * bin: a1 a2 a3 a4, b1..b4, c1..c4, d1..d4, e1..e4 (gendaylit's
 * coeff_perez). */
static const double LUM[8][20] = {
    {1.3525, -0.2576, -0.2690, -1.4366, -0.7670, 0.0007, 1.2734, -0.1233, 2.8000, 0.6004,
     1.2375, 1.0000, 1.8734, 0.6297, 0.9738, 0.2809, 0.0356, -0.1246, -0.5718, 0.9938},
    {-1.2219, -0.7730, 1.4148, 1.1016, -0.2054, 0.0367, -3.9128, 0.9156, 6.9750, 0.1774,
     6.4477, -0.1239, -1.5798, -0.5081, -1.7812, 0.1080, 0.2624, 0.0672, -0.2190, -0.4285},
    {-1.1000, -0.2515, 0.8952, 0.0156, 0.2782, -0.1812, -4.5000, 1.1766, 24.7219, -13.0812,
     -37.7000, 34.8438, -5.0000, 1.5218, 3.9229, -2.6204, -0.0156, 0.1597, 0.4199, -0.5562},
    {-0.5484, -0.6654, -0.2672, 0.7117, 0.7234, -0.6219, -5.6812, 2.6297, 33.3389, -18.3000,
     -62.2500, 52.0781, -3.5000, 0.0016, 1.1477, 0.1062, 0.4659, -0.3296, -0.0876, -0.0329},
    {-0.6000, -0.3566, -2.5000, 2.3250, 0.2937, 0.0496, -5.6812, 1.8415, 21.0000, -4.7656,
     -21.5906, 7.2492, -3.5000, -0.1554, 1.4062, 0.3988, 0.0032, 0.0766, -0.0656, -0.1294},
    {-1.0156, -0.3670, 1.0078, 1.4051, 0.2875, -0.5328, -3.8500, 3.3750, 14.0000, -0.9999,
     -7.1406, 7.5469, -3.4000, -0.1078, -1.0750, 1.5702, -0.0672, 0.4016, 0.3017, -0.4844},
    {-1.0000, 0.0211, 0.5025, -0.5119, -0.3000, 0.1922, 0.7023, -1.6317, 19.0000, -5.0000,
     1.2438, -1.9094, -4.0000, 0.0250, 0.3844, 0.2656, 1.0468, -0.3788, -2.4517, 1.4656},
    {-1.0500, 0.0289, 0.4260, 0.3590, -0.3250, 0.1156, 0.7781, 0.0025, 31.0625, -14.5000,
     -46.1148, 55.3750, -7.2312, 0.4050, 13.3500, 0.6234, 1.5000, -0.6426, 1.8564, 0.5636},
};

/* Perez et al. 1990, Table 4: a, b, c, d of the diffuse efficacy (eq. 7,
 * a + b W + c cos Z + d ln Delta), the direct efficacy (eq. 8,
 * a + b W + c exp(5.73 Z - 5) + d Delta) and the zenith luminance (eq. 9,
 * a + c cos Z + c' exp(-3 Z) + d Delta, stored as a, c, c', d). */
static const double DIFFUSE[8][4] = {
    {97.24, -0.46, 12.00, -8.91},   {107.22, 1.15, 0.59, -3.95},   {104.97, 2.96, -5.53, -8.77},
    {102.39, 5.59, -13.95, -13.90}, {100.71, 5.94, -22.75, -23.74}, {106.42, 3.83, -36.15, -28.83},
    {141.88, 1.90, -53.24, -14.03}, {152.23, 0.35, -45.27, -7.98},
};
static const double DIRECT[8][4] = {
    {57.20, -4.55, -2.98, 117.12},  {98.99, -3.46, -1.21, 12.38},  {109.83, -4.90, -1.71, -8.81},
    {110.34, -5.84, -1.99, -4.56},  {106.36, -3.97, -1.75, -6.16}, {107.19, -1.25, -1.51, -26.73},
    {105.75, 0.77, -1.26, -34.44},  {101.18, 1.58, -1.10, -8.29},
};
static const double ZENITH[8][4] = {
    {40.86, 26.77, -29.59, -45.75}, {26.58, 14.73, 58.46, -21.25}, {19.34, 2.28, 100.00, 0.25},
    {13.25, -1.39, 124.79, 15.66},  {14.47, -5.09, 160.09, 9.13},  {19.76, -3.88, 154.61, -19.21},
    {28.39, -9.67, 151.58, -69.39}, {42.91, -19.62, 130.80, -164.08},
};

double vr_perez_water_cm(double dew_point_c) { return exp(0.07 * dew_point_c - 0.075); }

double vr_perez_air_mass(double z_deg) {
  return 1.0 / (cos(z_deg * PI / 180.0) + 0.15 * pow(93.885 - z_deg, -1.253));
}

double vr_perez_extraterrestrial(int day) {
  double g = 2.0 * PI * (day - 1) / 365.0;
  return 1367.0 * (1.00011 + 0.034221 * cos(g) + 0.00128 * sin(g) + 0.000719 * cos(2 * g) +
                   0.000077 * sin(2 * g));
}

double vr_perez_gradation(const vr_sky_params *p, double cos_z) {
  double g = 1.0 + p->a * exp(p->b / fmax(cos_z, 0.01));
  return g > 0.0 ? g : 0.0;
}

double vr_perez_indicatrix(const vr_sky_params *p, double gamma) {
  double cc = cos(gamma);
  double f = 1.0 + p->c * exp(p->d * gamma) + p->e * cc * cc;
  return f > 0.0 ? f : 0.0;
}

double vr_perez_relative(const vr_sky_params *p, const double sun[3], const double dir[3]) {
  if (dir[2] < 0) return 0;
  double cg = sun[0] * dir[0] + sun[1] * dir[1] + sun[2] * dir[2];
  cg = cg > 1 ? 1 : cg < -1 ? -1 : cg;
  return vr_perez_gradation(p, dir[2]) * vr_perez_indicatrix(p, acos(cg));
}

int vr_perez_bin(double eps) {
  int bin = 1;
  while (bin < 8 && eps >= VR_PEREZ_BOUNDS[bin]) bin++;
  return bin;
}

void vr_perez_luminance_params(double z, double eps, double delta, vr_sky_params *out) {
  int bin = vr_perez_bin(eps);
  const double *x = LUM[bin - 1];
  double v[5];
  for (int i = 0; i < 5; i++)
    v[i] = x[4 * i] + x[4 * i + 1] * z + delta * (x[4 * i + 2] + x[4 * i + 3] * z);
  if (bin == 1) {
    /* The overcast bin's own forms of c and d (1993, eqs. for bin 1). */
    v[2] = exp(pow(delta * (x[8] + x[9] * z), x[10])) - x[11];
    v[3] = -exp(delta * (x[12] + x[13] * z)) + x[14] + delta * x[15];
  }
  out->a = v[0], out->b = v[1], out->c = v[2], out->d = v[3], out->e = v[4];
}

double vr_perez_diffuse_efficacy(int bin, double z, double delta, double w) {
  const double *k = DIFFUSE[bin - 1];
  return k[0] + k[1] * w + k[2] * cos(z) + k[3] * log(delta);
}

double vr_perez_direct_efficacy(int bin, double z, double delta, double w) {
  const double *k = DIRECT[bin - 1];
  double v = k[0] + k[1] * w + k[2] * exp(5.73 * z - 5.0) + k[3] * delta;
  return v > 0.0 ? v : 0.0; /* the fit goes negative near the horizon in bin 1 */
}

double vr_perez_zenith_ratio(int bin, double z, double delta) {
  const double *k = ZENITH[bin - 1];
  return k[0] + k[1] * cos(z) + k[2] * exp(-3.0 * z) + k[3] * delta;
}

vr_status vr_perez_sky_from(const vr_perez_input *in, vr_perez_sky *o, vr_error *err) {
  memset(o, 0, sizeof *o);
  double zd = in->sun_zenith_deg, dn = in->direct_normal_w_m2, dh = in->diffuse_horizontal_w_m2;
  if (!(zd >= 0.0 && zd < 90.0))
    return vr_error_set(err, VR_E_RANGE,
                        "Perez sky: the sun's zenith angle %g deg is outside [0, 90): the model "
                        "needs the sun above the horizon",
                        zd);
  if (!(dh > 0.0) || !isfinite(dh))
    return vr_error_set(err, VR_E_RANGE,
                        "Perez sky: diffuse horizontal irradiance %g W/m2 must be finite and > 0 "
                        "(the model is defined by the diffuse light)",
                        dh);
  if (!(dn >= 0.0) || !isfinite(dn))
    return vr_error_set(err, VR_E_RANGE,
                        "Perez sky: direct normal irradiance %g W/m2 must be finite and >= 0", dn);
  if (in->day_of_year < 0 || in->day_of_year > 366)
    return vr_error_set(err, VR_E_RANGE,
                        "Perez sky: day of the year %d is outside 1..366 (0: mean distance)",
                        in->day_of_year);
  double z = zd * PI / 180.0, kz3 = 1.041 * z * z * z;
  o->air_mass = vr_perez_air_mass(zd);
  o->extraterrestrial_w_m2 = in->day_of_year ? vr_perez_extraterrestrial(in->day_of_year) : 1367.0;
  o->water_cm = isnan(in->dew_point_c) ? 2.0 : vr_perez_water_cm(in->dew_point_c);
  o->epsilon_raw = ((dh + dn) / dh + kz3) / (1.0 + kz3); /* 1990 eq. 1 */
  o->delta_raw = dh * o->air_mass / o->extraterrestrial_w_m2; /* 1990 eq. 2 */
  double eps = o->epsilon_raw, delta = o->delta_raw;
  if (eps < EPS_MIN) eps = EPS_MIN, o->limited |= VR_PEREZ_LIMIT_EPSILON_LOW;
  if (eps > EPS_MAX) eps = EPS_MAX, o->limited |= VR_PEREZ_LIMIT_EPSILON_HIGH;
  if (delta < DELTA_MIN) delta = DELTA_MIN, o->limited |= VR_PEREZ_LIMIT_DELTA_LOW;
  if (delta > DELTA_MAX) delta = DELTA_MAX, o->limited |= VR_PEREZ_LIMIT_DELTA_HIGH;
  o->epsilon = eps, o->delta = delta;
  o->bin = vr_perez_bin(eps);
  double delta_lum = delta;
  if (eps > 1.065 && eps < 2.8 && delta_lum < 0.2) {
    delta_lum = 0.2;
    o->limited |= VR_PEREZ_LIMIT_DELTA_BIN;
  }
  vr_perez_luminance_params(z, eps, delta_lum, &o->lum);
  o->diffuse_efficacy = vr_perez_diffuse_efficacy(o->bin, z, delta, o->water_cm);
  o->direct_efficacy = vr_perez_direct_efficacy(o->bin, z, delta, o->water_cm);
  o->diffuse_horizontal_lx = dh * o->diffuse_efficacy;
  o->direct_normal_lx = dn * o->direct_efficacy;
  o->zenith_cd_m2 = dh * vr_perez_zenith_ratio(o->bin, z, delta);
  if (!(o->diffuse_horizontal_lx > 0.0))
    return vr_error_set(err, VR_E_NUMERIC,
                        "Perez sky: the diffuse efficacy is %g lm/W (bin %d, epsilon %.3f, Delta "
                        "%.3f, W %.2f cm): no diffuse illuminance",
                        o->diffuse_efficacy, o->bin, eps, delta, o->water_cm);
  return VR_OK;
}

const char *vr_perez_limits_text(int limited, char *buf, size_t size) {
  static const char *const WHAT[5] = {
      "clearness below 1 raised to 1", "clearness above 12.01 lowered to 12.01",
      "brightness below 0.01 raised to 0.01", "brightness above 0.6 lowered to 0.6",
      "brightness below 0.2 raised to 0.2 for the luminance distribution (1.065 < clearness < 2.8)"};
  if (size == 0) return buf;
  buf[0] = '\0';
  size_t n = 0;
  for (int i = 0; i < 5; i++) {
    if (!(limited & (1 << i))) continue;
    int k = snprintf(buf + n, size - n, "%s%s", n ? "; " : "", WHAT[i]);
    if (k < 0 || (size_t)k >= size - n) break;
    n += (size_t)k;
  }
  return buf;
}
