/* The channel names of spectral OpenEXR files in the layout of Fichet,
 * Pacanowski and Wilkie (JCGT 10(3), 2021), for the reader (spectral_exr.c)
 * and the writer (spectral_exr_write.c).  What a channel is called and how
 * a name is read follow their reference code,
 * github.com/afichet/spectral-exr, lib/EXRBiSpectralImage.cpp (commit
 * 1e4bc4714e144fec143251eb49f8631b0755f6a9): getEmissiveChannelName builds
 * "S" + stokes + "." + std::to_string(λ) with '.' turned into ',' + "nm",
 * getReflectiveChannelName the same with "T", and channelType accepts
 * ^((S([0-3]))|T)\.(\d*,?\d*([Ee][+-]?\d+)?)(Y|Z|E|P|T|G|M|k|h|da|d|c|m|u|n|p)?(m|Hz)$
 * (plus T.<λ>.<λ'> for re-radiation).  The attribute names are those of
 * lib/include/EXRBiSpectralImage.h (commit bf3f605149d5a3c9304e1c6e75c8684871798ea1):
 * spectralLayoutVersion, written "1.0", and emissiveUnits.
 *
 * Numbers are formatted and parsed here with integer arithmetic rather than
 * printf("%f") and strtod, which follow LC_NUMERIC: a program that set a
 * French locale would otherwise write "550,000000" through one path and fail
 * to read it back through the other. */
#include "spectral_exr_internal.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

static const char *kind_prefix(vr_spectral_kind kind) {
  return kind == VR_SPECTRAL_EMISSIVE ? "S0" : "T";
}

/* λ in micro-nanometres, the unit of the 6 decimals of a channel name. */
static long long wavelength_code(double nm) { return llround(nm * 1e6); }

/* std::to_string(double) in the reference code prints "%f": 6 decimals.
 * Integer printing has no locale-dependent decimal point. */
void vr_spectral_channel_name(char out[NAME_LEN], vr_spectral_kind kind, double nm) {
  long long code = wavelength_code(nm);
  snprintf(out, NAME_LEN, "%s.%lld,%06lldnm", kind_prefix(kind), code / 1000000, code % 1000000);
}

static const double exact_powers_of_ten[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                               1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                               1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

/* mant * 10^e.  Up to 10^22 the power is exact, so a mantissa below 2^53
 * (every name we write) gets one correctly rounded operation. */
static double decimal_value(uint64_t mant, long e) {
  double m = (double)mant;
  if (mant == 0) return 0.0;
  if (e >= 0) return e <= 22 ? m * exact_powers_of_ten[e] : m * pow(10.0, (double)e);
  return -e <= 22 ? m / exact_powers_of_ten[-e] : m / pow(10.0, (double)-e);
}

/* SI prefixes of the reference regular expression, as powers of ten. */
static int si_prefix_exponent(const char *p, size_t n, int *e) {
  static const struct {
    const char *p;
    int e;
  } table[] = {{"", 0},   {"Y", 24}, {"Z", 21}, {"E", 18},  {"P", 15}, {"T", 12},
               {"G", 9},  {"M", 6},  {"k", 3},  {"h", 2},   {"da", 1}, {"d", -1},
               {"c", -2}, {"m", -3}, {"u", -6}, {"n", -9},  {"p", -12}};
  for (size_t i = 0; i < sizeof table / sizeof table[0]; i++)
    if (strlen(table[i].p) == n && memcmp(table[i].p, p, n) == 0) {
      *e = table[i].e;
      return 1;
    }
  return 0;
}

/* Parses "<number>[<prefix>](m|Hz)" that fills all of s[0..n) into a
 * wavelength in nm.  The number is \d*,?\d*([Ee][+-]?\d+)? with at least
 * one digit; an exponent is taken only when digits follow the E, so "5Em"
 * is 5 exametres, as the regular expression decides. */
static int parse_wavelength(const char *s, size_t n, double *nm) {
  const char *end = s + n;
  uint64_t mant = 0;
  long e10 = 0;
  int digits = 0;
  for (; s < end && *s >= '0' && *s <= '9'; s++, digits++) {
    if (mant < 100000000000000000ULL)
      mant = mant * 10 + (uint64_t)(*s - '0');
    else
      e10++; /* digits beyond 17 are below a double's precision */
  }
  if (s < end && *s == ',') {
    for (s++; s < end && *s >= '0' && *s <= '9'; s++, digits++)
      if (mant < 100000000000000000ULL) {
        mant = mant * 10 + (uint64_t)(*s - '0');
        e10--;
      }
  }
  if (digits == 0) return 0;
  if (s < end && (*s == 'E' || *s == 'e')) {
    const char *q = s + 1;
    int sign = 1;
    if (q < end && (*q == '+' || *q == '-')) sign = *q++ == '-' ? -1 : 1;
    if (q < end && *q >= '0' && *q <= '9') {
      long ev = 0;
      for (; q < end && *q >= '0' && *q <= '9'; q++)
        if (ev < 100000) ev = ev * 10 + (*q - '0');
      e10 += sign * ev;
      s = q;
    }
  }
  size_t rest = (size_t)(end - s);
  int hz = rest >= 2 && memcmp(end - 2, "Hz", 2) == 0;
  int metres = !hz && rest >= 1 && end[-1] == 'm';
  int pe;
  if (!hz && !metres) return 0;
  if (!si_prefix_exponent(s, rest - (hz ? 2 : 1), &pe)) return 0;
  double v;
  if (metres) {
    v = decimal_value(mant, e10 + pe + 9);
  } else {
    /* The reference converts with c = 299792458 m/s, a wavelength in vacuum. */
    double f = decimal_value(mant, e10 + pe);
    v = f > 0 ? 299792458.0e9 / f : 0.0;
  }
  if (!isfinite(v) || v <= 0) return 0;
  *nm = v;
  return 1;
}

/* A name is taken as the layout's when it starts S0. to S3. or T. followed
 * by a digit or a comma, the only ways its number can begin: "T.R" or
 * "S1.Z" are ordinary channels of layers that happen to be called T or S1,
 * and stay out of the way.  Returns where the number starts, or NULL. */
static const char *spectral_number(const char *name) {
  const char *rest;
  if (name[0] == 'S' && name[1] >= '0' && name[1] <= '3' && name[2] == '.')
    rest = name + 3;
  else if (name[0] == 'T' && name[1] == '.')
    rest = name + 2;
  else
    return NULL;
  return (rest[0] >= '0' && rest[0] <= '9') || rest[0] == ',' ? rest : NULL;
}

int vr_spectral_name_is_spectral(const char *name) { return spectral_number(name) != NULL; }

channel_class vr_spectral_classify(const char *name, double *nm) {
  const char *rest = spectral_number(name);
  if (!rest) return CH_OTHER;
  const int emissive = name[0] == 'S';
  const char *dot = strchr(rest, '.');
  if (!dot) {
    if (!parse_wavelength(rest, strlen(rest), nm)) return CH_MALFORMED;
    if (!emissive) return CH_REFLECTIVE;
    return name[1] == '0' ? CH_EMISSIVE : CH_POLARISED;
  }
  double out;
  if (emissive || !parse_wavelength(rest, (size_t)(dot - rest), nm) ||
      !parse_wavelength(dot + 1, strlen(dot + 1), &out))
    return CH_MALFORMED;
  return CH_RERADIATION;
}

vr_status vr_spectral_check_wavelengths(const double *wl, size_t n, vr_error *err) {
  if (!wl) return vr_error_set(err, VR_E_ARG, "spectral image: wavelengths_nm is NULL");
  for (size_t i = 0; i < n; i++) {
    if (!isfinite(wl[i]) || wl[i] <= 0)
      return vr_error_set(err, VR_E_ARG,
                          "spectral image: wavelengths_nm[%zu] = %g nm: must be finite and > 0",
                          i, wl[i]);
    if (i > 0 && !(wl[i] > wl[i - 1]))
      return vr_error_set(err, VR_E_ARG,
                          "spectral image: wavelengths_nm[%zu] = %g nm does not follow "
                          "wavelengths_nm[%zu] = %g nm: they must increase strictly",
                          i, wl[i], i - 1, wl[i - 1]);
  }
  return VR_OK;
}

/* Checked by the writers (spectral_exr_write.c) before anything is
 * written: the 6 decimals of a name must tell the bands apart. */
vr_status vr_spectral_check_names(const char *path, const double *wl, size_t n,
                                  vr_spectral_kind kind, vr_error *err) {
  for (size_t b = 0; b < n; b++) {
    double nm = wl[b];
    if (nm > MAX_WAVELENGTH_NM || wavelength_code(nm) < 1)
      return vr_error_at(err, VR_E_ARG, path, 0, 0,
                         "wavelength %g nm (band %zu) is outside (0, 1e9] nm once written with "
                         "6 decimals", nm, b);
    if (b > 0 && wavelength_code(nm) == wavelength_code(wl[b - 1])) {
      char name[NAME_LEN];
      vr_spectral_channel_name(name, kind, nm);
      return vr_error_at(err, VR_E_ARG, path, 0, 0,
                         "bands %zu and %zu (%.12g and %.12g nm) would both be channel %s: the "
                         "layout keeps 6 decimals of a nanometre", b - 1, b, wl[b - 1], nm, name);
    }
  }
  return VR_OK;
}
