/* Spectral OpenEXR in the layout of Fichet, Pacanowski and Wilkie (JCGT
 * 10(3), 2021), through the OpenEXR 3 core C API like image_exr.c.  What a
 * channel is called and how a name is read follow their reference code,
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
#include "vr/spectral_exr.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <openexr.h>

#include "exr_stream.h"

#include "vr/atomic_file.h"
#include "vr/file.h"

/* Longest name we write: "S0." + 10 digits + ",000000nm" + NUL, with room. */
#define NAME_LEN 40
/* Wavelengths above 1 m make no optical sense, and the bound keeps
 * round(λ * 1e6) exact in a double and an int64. */
#define MAX_WAVELENGTH_NM 1e9
#define LAYOUT_VERSION "1.0"

/* ---------------------------------------------------------------- names */

static const char *kind_prefix(vr_spectral_kind kind) {
  return kind == VR_SPECTRAL_EMISSIVE ? "S0" : "T";
}

/* λ in micro-nanometres, the unit of the 6 decimals of a channel name. */
static long long wavelength_code(double nm) { return llround(nm * 1e6); }

/* std::to_string(double) in the reference code prints "%f": 6 decimals.
 * Integer printing has no locale-dependent decimal point. */
static void channel_name(char out[NAME_LEN], vr_spectral_kind kind, double nm) {
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

typedef enum {
  CH_OTHER,       /* not part of the layout: R, G, B, A, Y, layer.channel ... */
  CH_EMISSIVE,    /* S0.<λ> */
  CH_POLARISED,   /* S1..S3.<λ>: checked, skipped */
  CH_REFLECTIVE,  /* T.<λ> */
  CH_RERADIATION, /* T.<λ>.<λ'>: checked, skipped */
  CH_MALFORMED
} channel_class;

/* A name is taken as the layout's when it starts S0. to S3. or T. followed
 * by a digit or a comma, the only ways its number can begin: "T.R" or
 * "S1.Z" are ordinary channels of layers that happen to be called T or S1,
 * and stay out of the way. */
static channel_class classify(const char *name, double *nm) {
  const char *rest;
  int emissive;
  if (name[0] == 'S' && name[1] >= '0' && name[1] <= '3' && name[2] == '.') {
    emissive = 1;
    rest = name + 3;
  } else if (name[0] == 'T' && name[1] == '.') {
    emissive = 0;
    rest = name + 2;
  } else {
    return CH_OTHER;
  }
  if (!((rest[0] >= '0' && rest[0] <= '9') || rest[0] == ',')) return CH_OTHER;
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

/* ---------------------------------------------------------------- image */

static vr_status check_wavelengths(const double *wl, size_t n, vr_error *err) {
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

vr_status vr_spectral_image_alloc(vr_spectral_image *img, int w, int h, size_t nbands,
                                  const double *wavelengths_nm, vr_spectral_kind kind,
                                  vr_error *err) {
  if (!img) return vr_error_set(err, VR_E_ARG, "vr_spectral_image_alloc: image is NULL");
  memset(img, 0, sizeof *img);
  if (w < 1 || h < 1)
    return vr_error_set(err, VR_E_ARG, "spectral image size %d x %d: both sides must be at least 1",
                        w, h);
  if (nbands < 1) return vr_error_set(err, VR_E_ARG, "spectral image: nbands is 0");
  if (kind != VR_SPECTRAL_EMISSIVE && kind != VR_SPECTRAL_REFLECTIVE)
    return vr_error_set(err, VR_E_ARG, "spectral image: kind %d is neither emissive nor reflective",
                        (int)kind);
  vr_status st = check_wavelengths(wavelengths_nm, nbands, err);
  if (st != VR_OK) return st;
  size_t pixels = (size_t)w * (size_t)h;
  if (nbands > SIZE_MAX / sizeof(double) || pixels > SIZE_MAX / sizeof(float) / nbands)
    return vr_error_set(err, VR_E_NOMEM, "spectral image %d x %d x %zu bands is too large", w, h,
                        nbands);
  img->wavelengths_nm = malloc(nbands * sizeof(double));
  img->data = calloc(pixels * nbands, sizeof(float));
  if (!img->wavelengths_nm || !img->data) {
    vr_spectral_image_free(img);
    return vr_error_set(err, VR_E_NOMEM, "out of memory for a %d x %d x %zu-band spectral image",
                        w, h, nbands);
  }
  memcpy(img->wavelengths_nm, wavelengths_nm, nbands * sizeof(double));
  img->width = w;
  img->height = h;
  img->nbands = nbands;
  img->kind = kind;
  return VR_OK;
}

void vr_spectral_image_free(vr_spectral_image *img) {
  if (!img) return;
  free(img->wavelengths_nm);
  free(img->data);
  memset(img, 0, sizeof *img);
}

/* ------------------------------------------------------------- writing */

static vr_status check_writable(const char *path, const vr_spectral_image *img,
                                const vr_image *rgb, const char *units, vr_error *err) {
  if (!path) return vr_error_set(err, VR_E_ARG, "vr_spectral_exr_write: path is NULL");
  if (!img || !img->data)
    return vr_error_at(err, VR_E_ARG, path, 0, 0, "no spectral image (NULL or without pixels)");
  if (img->width < 1 || img->height < 1 || img->nbands < 1)
    return vr_error_at(err, VR_E_ARG, path, 0, 0, "bad spectral image shape %d x %d x %zu bands",
                       img->width, img->height, img->nbands);
  if (img->kind != VR_SPECTRAL_EMISSIVE && img->kind != VR_SPECTRAL_REFLECTIVE)
    return vr_error_at(err, VR_E_ARG, path, 0, 0, "spectral kind %d is neither emissive nor "
                       "reflective", (int)img->kind);
  vr_status st = check_wavelengths(img->wavelengths_nm, img->nbands, err);
  if (st != VR_OK) {
    vr_error_prefix(err, "%s: ", path);
    return st;
  }
  for (size_t b = 0; b < img->nbands; b++) {
    double nm = img->wavelengths_nm[b];
    if (nm > MAX_WAVELENGTH_NM || wavelength_code(nm) < 1)
      return vr_error_at(err, VR_E_ARG, path, 0, 0,
                         "wavelength %g nm (band %zu) is outside (0, 1e9] nm once written with "
                         "6 decimals", nm, b);
    if (b > 0 && wavelength_code(nm) == wavelength_code(img->wavelengths_nm[b - 1])) {
      char name[NAME_LEN];
      channel_name(name, img->kind, nm);
      return vr_error_at(err, VR_E_ARG, path, 0, 0,
                         "bands %zu and %zu (%.12g and %.12g nm) would both be channel %s: the "
                         "layout keeps 6 decimals of a nanometre", b - 1, b,
                         img->wavelengths_nm[b - 1], nm, name);
    }
  }
  /* The core API takes strides as int32: a line of all bands must fit. */
  if ((size_t)img->width * img->nbands > INT32_MAX / sizeof(float))
    return vr_error_at(err, VR_E_ARG, path, 0, 0,
                       "%d pixels x %zu bands per line is more than OpenEXR's strides hold",
                       img->width, img->nbands);
  if (rgb) {
    st = vr_image_check(rgb, "RGB preview", err);
    if (st != VR_OK) {
      vr_error_prefix(err, "%s: ", path);
      return st;
    }
    if (rgb->width != img->width || rgb->height != img->height)
      return vr_error_at(err, VR_E_ARG, path, 0, 0,
                         "RGB preview is %d x %d, the spectral image %d x %d", rgb->width,
                         rgb->height, img->width, img->height);
  }
  if (units && img->kind != VR_SPECTRAL_EMISSIVE)
    return vr_error_at(err, VR_E_ARG, path, 0, 0,
                       "emissive units '%s' given for a reflective image (T channels hold "
                       "ratios without units)", units);
  if (units && !units[0])
    return vr_error_at(err, VR_E_ARG, path, 0, 0,
                       "emissive units are an empty string; pass NULL to write none");
  return VR_OK;
}

/* A NaN says nothing a reader could use and -inf no physical quantity: the
 * first one found is reported by pixel and band rather than written. */
static vr_status check_values(const char *path, const vr_spectral_image *img, const vr_image *rgb,
                              vr_error *err) {
  const size_t nb = img->nbands;
  for (int y = 0; y < img->height; y++)
    for (int x = 0; x < img->width; x++) {
      const float *p = img->data + ((size_t)y * (size_t)img->width + (size_t)x) * nb;
      for (size_t b = 0; b < nb; b++)
        if (isnan(p[b]) || (isinf(p[b]) && p[b] < 0)) {
          char name[NAME_LEN];
          channel_name(name, img->kind, img->wavelengths_nm[b]);
          return vr_error_at(err, VR_E_RANGE, path, 0, 0,
                             "pixel (%d, %d), band %zu (%g nm, channel %s) is %s; nothing "
                             "written", x, y, b, img->wavelengths_nm[b], name,
                             isnan(p[b]) ? "NaN" : "-infinity");
        }
      if (rgb) {
        const float *q = rgb->data + ((size_t)y * (size_t)img->width + (size_t)x) * 3;
        for (int c = 0; c < 3; c++)
          if (isnan(q[c]) || (isinf(q[c]) && q[c] < 0))
            return vr_error_at(err, VR_E_RANGE, path, 0, 0,
                               "RGB preview pixel (%d, %d), channel %c is %s; nothing written",
                               x, y, "RGB"[c], isnan(q[c]) ? "NaN" : "-infinity");
      }
    }
  return VR_OK;
}

/* Where each channel of the pipeline comes from or goes to: band index
 * >= 0, -1 - c for R, G, B (c = 0, 1, 2), or SKIP. */
#define SKIP INT32_MIN

static exr_result_t encode_pixels(exr_context_t ctxt, int part, const vr_spectral_image *img,
                                  const vr_image *rgb, char (*names)[NAME_LEN]) {
  int32_t lines = 0;
  exr_result_t rv = exr_get_scanlines_per_chunk(ctxt, part, &lines);
  if (rv != EXR_ERR_SUCCESS) return rv;
  exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
  int started = 0;
  int32_t *map = NULL;
  const size_t nb = img->nbands, w = (size_t)img->width;
  for (int y = 0; y < img->height && rv == EXR_ERR_SUCCESS; y += lines) {
    exr_chunk_info_t cinfo;
    rv = exr_write_scanline_chunk_info(ctxt, part, y, &cinfo);
    if (rv == EXR_ERR_SUCCESS)
      rv = started ? exr_encoding_update(ctxt, part, &cinfo, &enc)
                   : exr_encoding_initialize(ctxt, part, &cinfo, &enc);
    if (rv != EXR_ERR_SUCCESS) break;
    if (!map) {
      /* The library keeps channels sorted by name ("S0.1000,..." before
       * "S0.380,..."), so each one is looked up once by its name. */
      map = malloc((size_t)enc.channel_count * sizeof *map);
      if (!map) {
        rv = EXR_ERR_OUT_OF_MEMORY;
        break;
      }
      for (int c = 0; c < enc.channel_count; c++) {
        const char *n = enc.channels[c].channel_name;
        map[c] = SKIP;
        if (rgb && n[0] && !n[1] && strchr("RGB", n[0]))
          map[c] = -1 - (int32_t)(strchr("RGB", n[0]) - "RGB");
        for (size_t b = 0; b < nb && map[c] == SKIP; b++)
          if (strcmp(n, names[b]) == 0) map[c] = (int32_t)b;
        if (map[c] == SKIP) rv = EXR_ERR_INVALID_ARGUMENT; /* cannot happen: we added them */
      }
      if (rv != EXR_ERR_SUCCESS) break;
    }
    for (int c = 0; c < enc.channel_count; c++) {
      exr_coding_channel_info_t *ci = &enc.channels[c];
      if (map[c] >= 0) {
        ci->encode_from_ptr = (const uint8_t *)(img->data + (size_t)y * w * nb + (size_t)map[c]);
        ci->user_pixel_stride = (int32_t)(nb * sizeof(float));
        ci->user_line_stride = (int32_t)(w * nb * sizeof(float));
      } else {
        const size_t k = (size_t)(-1 - map[c]);
        ci->encode_from_ptr = (const uint8_t *)(rgb->data + (size_t)y * w * 3 + k);
        ci->user_pixel_stride = 3 * (int32_t)sizeof(float);
        ci->user_line_stride = (int32_t)(w * 3 * sizeof(float));
      }
      ci->user_bytes_per_element = (int16_t)sizeof(float);
      ci->user_data_type = EXR_PIXEL_FLOAT;
    }
    if (!started) {
      started = 1;
      rv = exr_encoding_choose_default_routines(ctxt, part, &enc);
    }
    if (rv == EXR_ERR_SUCCESS) rv = exr_encoding_run(ctxt, part, &enc);
  }
  if (started) exr_encoding_destroy(ctxt, &enc);
  free(map);
  return rv;
}

vr_status vr_spectral_exr_write(const char *path, const vr_spectral_image *img,
                                const vr_image *rgb, const char *emissive_units, vr_error *err) {
  vr_status st = check_writable(path, img, rgb, emissive_units, err);
  if (st == VR_OK) st = check_values(path, img, rgb, err);
  if (st != VR_OK) return st;
  char (*names)[NAME_LEN] = malloc(img->nbands * sizeof *names);
  if (!names) return vr_error_at(err, VR_E_NOMEM, path, 0, 0, "out of memory for channel names");
  for (size_t b = 0; b < img->nbands; b++)
    channel_name(names[b], img->kind, img->wavelengths_nm[b]);

  vr_atomic_file af;
  st = vr_atomic_file_open(&af, path, err);
  if (st != VR_OK) {
    free(names);
    return st;
  }
  exr_stream s = {.fp = af.fp};
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.user_data = &s;
  init.write_fn = vr_exr_stream_write;
  init.error_handler_fn = vr_exr_on_write_error;
  exr_context_t ctxt = NULL;
  int part = 0;
  exr_result_t rv = exr_start_write(&ctxt, path, EXR_WRITE_FILE_DIRECTLY, &init);
  if (rv == EXR_ERR_SUCCESS) rv = exr_add_part(ctxt, NULL, EXR_STORAGE_SCANLINE, &part);
  if (rv == EXR_ERR_SUCCESS)
    rv = exr_initialize_required_attr_simple(ctxt, part, img->width, img->height,
                                             EXR_COMPRESSION_ZIP);
  /* The reference writer adds R, G, B first and always; here they are the
   * caller's choice, since only the caller knows the observer and white. */
  static const char *const rgb_names[3] = {"R", "G", "B"};
  for (int k = 0; rgb && k < 3 && rv == EXR_ERR_SUCCESS; k++)
    rv = exr_add_channel(ctxt, part, rgb_names[k], EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LINEAR, 1, 1);
  /* Spectral values are radiometric, not perceptual: linear for lossy codecs. */
  for (size_t b = 0; b < img->nbands && rv == EXR_ERR_SUCCESS; b++)
    rv = exr_add_channel(ctxt, part, names[b], EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LINEAR, 1, 1);
  if (rv == EXR_ERR_SUCCESS)
    rv = exr_attr_set_string(ctxt, part, "spectralLayoutVersion", LAYOUT_VERSION);
  if (rv == EXR_ERR_SUCCESS && emissive_units)
    rv = exr_attr_set_string(ctxt, part, "emissiveUnits", emissive_units);
  if (rv == EXR_ERR_SUCCESS) rv = exr_write_header(ctxt);
  if (rv == EXR_ERR_SUCCESS) rv = encode_pixels(ctxt, part, img, rgb, names);
  if (ctxt) {
    /* exr_finish writes the chunk offset table: its result counts too. */
    exr_result_t fin = exr_finish(&ctxt);
    if (rv == EXR_ERR_SUCCESS) rv = fin;
  }
  free(names);
  if (rv != EXR_ERR_SUCCESS || s.write_errno) {
    vr_atomic_file_abort(&af);
    if (s.write_errno)
      return vr_error_at(err, VR_E_IO, path, 0, 0, "write failed: %s", strerror(s.write_errno));
    return vr_error_at(err, VR_E_IO, path, 0, 0, "OpenEXR could not write the spectral image: %s",
                       exr_get_default_error_message(rv));
  }
  return vr_atomic_file_commit(&af, err);
}

/* ------------------------------------------------------------- reading */

typedef struct band {
  double nm;
  int channel; /* index in the channel list */
} band;

static int band_cmp(const void *a, const void *b) {
  double x = ((const band *)a)->nm, y = ((const band *)b)->nm;
  return (x > y) - (x < y);
}



/* Only half and full-resolution float can hold what the layout stores. */
static vr_status check_channel(const exr_attr_chlist_entry_t *e, const char *name, vr_error *err) {
  if (e->pixel_type != EXR_PIXEL_HALF && e->pixel_type != EXR_PIXEL_FLOAT)
    return vr_error_at(err, VR_E_PARSE, name, 0, 0,
                       "channel %s holds unsigned integers; half or float needed", e->name.str);
  if (e->x_sampling != 1 || e->y_sampling != 1)
    return vr_error_at(err, VR_E_PARSE, name, 0, 0,
                       "channel %s is subsampled (%d x %d); full resolution needed", e->name.str,
                       e->x_sampling, e->y_sampling);
  return VR_OK;
}

/* The reference reader only warns about another version; a later major
 * version may name things differently, so here it stops. */
static vr_status check_version(exr_context_t ctxt, const char *name, vr_error *err) {
  const exr_attribute_t *a = NULL;
  if (exr_get_attribute_by_name(ctxt, 0, "spectralLayoutVersion", &a) != EXR_ERR_SUCCESS || !a)
    return VR_OK; /* absent: files of other writers may leave it out */
  if (a->type != EXR_ATTR_STRING || !a->string || !a->string->str)
    return vr_error_at(err, VR_E_PARSE, name, 0, 0,
                       "attribute spectralLayoutVersion is not a string");
  const char *v = a->string->str;
  int n = a->string->length;
  if (n >= 1 && v[0] == '1' && (n == 1 || v[1] == '.')) return VR_OK;
  return vr_error_at(err, VR_E_PARSE, name, 0, 0,
                     "spectralLayoutVersion is '%.*s'; only version 1 of the layout is read",
                     n > 64 ? 64 : (n < 0 ? 0 : n), v);
}

typedef struct layout {
  band *bands;
  size_t nbands;
  vr_spectral_kind kind;
  int rgb[3]; /* channel indices of R, G, B, or -1 when not read */
} layout;

static vr_status find_layout(const exr_attr_chlist_t *ch, const char *name, int want_rgb,
                             layout *lay, vr_error *err) {
  lay->bands = malloc((size_t)(ch->num_channels > 0 ? ch->num_channels : 1) * sizeof(band));
  if (!lay->bands) return vr_error_at(err, VR_E_NOMEM, name, 0, 0, "out of memory");
  lay->nbands = 0;
  int first_s0 = -1, first_t = -1;
  for (int i = 0; i < ch->num_channels; i++) {
    const exr_attr_chlist_entry_t *e = &ch->entries[i];
    double nm = 0;
    channel_class k = classify(e->name.str, &nm);
    if (k == CH_MALFORMED)
      return vr_error_at(err, VR_E_PARSE, name, 0, 0,
                         "channel '%s' is not a spectral channel name of the layout (S0..S3 or "
                         "T, a dot, a number with a decimal comma, a unit: S0.550,000000nm, "
                         "T.550,000000nm)", e->name.str);
    if (k != CH_EMISSIVE && k != CH_REFLECTIVE) continue;
    int *first = k == CH_EMISSIVE ? &first_s0 : &first_t;
    if (*first < 0) *first = i;
    vr_status st = check_channel(e, name, err);
    if (st != VR_OK) return st;
    lay->bands[lay->nbands].nm = nm;
    lay->bands[lay->nbands].channel = i;
    lay->nbands++;
  }
  if (first_s0 >= 0 && first_t >= 0)
    return vr_error_at(err, VR_E_PARSE, name, 0, 0,
                       "both emissive (%s) and reflective (%s) spectral channels; one image holds "
                       "one kind", ch->entries[first_s0].name.str, ch->entries[first_t].name.str);
  if (lay->nbands == 0)
    return vr_error_at(err, VR_E_PARSE, name, 0, 0,
                       "no spectral channels (named like S0.550,000000nm or T.550,000000nm) among "
                       "its %d channels", ch->num_channels);
  lay->kind = first_s0 >= 0 ? VR_SPECTRAL_EMISSIVE : VR_SPECTRAL_REFLECTIVE;
  qsort(lay->bands, lay->nbands, sizeof(band), band_cmp);
  for (size_t b = 1; b < lay->nbands; b++)
    if (lay->bands[b].nm == lay->bands[b - 1].nm)
      return vr_error_at(err, VR_E_PARSE, name, 0, 0,
                         "channels '%s' and '%s' have the same wavelength (%.9g nm)",
                         ch->entries[lay->bands[b - 1].channel].name.str,
                         ch->entries[lay->bands[b].channel].name.str, lay->bands[b].nm);
  lay->rgb[0] = lay->rgb[1] = lay->rgb[2] = -1;
  if (want_rgb) {
    int idx[3] = {vr_exr_find_channel(ch, "R"), vr_exr_find_channel(ch, "G"), vr_exr_find_channel(ch, "B")};
    if (idx[0] >= 0 && idx[1] >= 0 && idx[2] >= 0)
      for (int c = 0; c < 3; c++) {
        vr_status st = check_channel(&ch->entries[idx[c]], name, err);
        if (st != VR_OK) return st;
        lay->rgb[c] = idx[c];
      }
  }
  return VR_OK;
}

/* Every chunk is located before any pixel memory is taken: a cut file
 * fails here, with OpenEXR's own words, whatever its header claims. */
static vr_status check_chunks(exr_context_t ctxt, const char *name, const exr_stream *s,
                              exr_attr_box2i_t dw, int32_t lines, vr_error *err) {
  for (int64_t y = dw.min.y; y <= dw.max.y; y += lines) {
    exr_chunk_info_t cinfo;
    exr_result_t rv = exr_read_scanline_chunk_info(ctxt, 0, (int)y, &cinfo);
    if (rv != EXR_ERR_SUCCESS) {
      char doing[64];
      snprintf(doing, sizeof doing, "truncated or corrupt at the chunk of line %" PRId64, y);
      return vr_exr_read_failed(err, name, s, rv, doing);
    }
  }
  return VR_OK;
}

static vr_status decode_pixels(exr_context_t ctxt, const char *name, const exr_stream *s,
                               exr_attr_box2i_t dw, int32_t lines, const layout *lay,
                               const exr_attr_chlist_t *ch, vr_spectral_image *out, vr_image *rgb,
                               vr_error *err) {
  /* Channel list index -> destination, built once; the decoder's channels
   * follow the channel list. */
  int32_t *dest = malloc((size_t)ch->num_channels * sizeof *dest);
  if (!dest) return vr_error_at(err, VR_E_NOMEM, name, 0, 0, "out of memory");
  for (int i = 0; i < ch->num_channels; i++) dest[i] = SKIP;
  for (size_t b = 0; b < lay->nbands; b++) dest[lay->bands[b].channel] = (int32_t)b;
  for (int c = 0; c < 3; c++)
    if (lay->rgb[c] >= 0) dest[lay->rgb[c]] = -1 - c;

  exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
  int started = 0;
  vr_status st = VR_OK;
  const size_t nb = out->nbands, w = (size_t)out->width;
  for (int64_t y = dw.min.y; y <= dw.max.y && st == VR_OK; y += lines) {
    exr_chunk_info_t cinfo;
    exr_result_t rv = exr_read_scanline_chunk_info(ctxt, 0, (int)y, &cinfo);
    if (rv == EXR_ERR_SUCCESS)
      rv = started ? exr_decoding_update(ctxt, 0, &cinfo, &dec)
                   : exr_decoding_initialize(ctxt, 0, &cinfo, &dec);
    if (rv != EXR_ERR_SUCCESS) {
      st = vr_exr_read_failed(err, name, s, rv, "reading the scanlines");
      break;
    }
    const size_t row = (size_t)(cinfo.start_y - dw.min.y);
    for (int c = 0; c < dec.channel_count; c++) {
      exr_coding_channel_info_t *ci = &dec.channels[c];
      int i = c < ch->num_channels && strcmp(ch->entries[c].name.str, ci->channel_name) == 0
                  ? c
                  : vr_exr_find_channel(ch, ci->channel_name);
      int32_t d = i < 0 ? SKIP : dest[i];
      if (d == SKIP) {
        ci->decode_to_ptr = NULL;
      } else if (d >= 0) {
        ci->decode_to_ptr = (uint8_t *)(out->data + row * w * nb + (size_t)d);
        ci->user_pixel_stride = (int32_t)(nb * sizeof(float));
        ci->user_line_stride = (int32_t)(w * nb * sizeof(float));
      } else {
        ci->decode_to_ptr = (uint8_t *)(rgb->data + row * w * 3 + (size_t)(-1 - d));
        ci->user_pixel_stride = 3 * (int32_t)sizeof(float);
        ci->user_line_stride = (int32_t)(w * 3 * sizeof(float));
      }
      ci->user_bytes_per_element = (int16_t)sizeof(float);
      ci->user_data_type = EXR_PIXEL_FLOAT;
    }
    if (!started) {
      started = 1;
      rv = exr_decoding_choose_default_routines(ctxt, 0, &dec);
    }
    if (rv == EXR_ERR_SUCCESS) rv = exr_decoding_run(ctxt, 0, &dec);
    if (rv != EXR_ERR_SUCCESS) st = vr_exr_read_failed(err, name, s, rv, "decoding the scanlines");
  }
  if (started) exr_decoding_destroy(ctxt, &dec);
  free(dest);
  return st;
}

static vr_status read_context(exr_context_t ctxt, const char *name, const exr_stream *s,
                              vr_spectral_image *out, vr_image *rgb, vr_error *err) {
  exr_storage_t storage;
  exr_result_t rv = exr_get_storage(ctxt, 0, &storage);
  if (rv != EXR_ERR_SUCCESS) return vr_exr_read_failed(err, name, s, rv, "storage type");
  if (storage != EXR_STORAGE_SCANLINE)
    return vr_error_at(err, VR_E_PARSE, name, 0, 0,
                       "OpenEXR: only scanline images are read, this one is %s",
                       storage == EXR_STORAGE_TILED ? "tiled" : "deep");
  exr_attr_box2i_t dw;
  const exr_attr_chlist_t *ch = NULL;
  int32_t lines = 0;
  if ((rv = exr_get_data_window(ctxt, 0, &dw)) != EXR_ERR_SUCCESS)
    return vr_exr_read_failed(err, name, s, rv, "data window");
  if ((rv = exr_get_channels(ctxt, 0, &ch)) != EXR_ERR_SUCCESS || !ch)
    return vr_exr_read_failed(err, name, s, rv, "channel list");
  if ((rv = exr_get_scanlines_per_chunk(ctxt, 0, &lines)) != EXR_ERR_SUCCESS || lines < 1)
    return vr_exr_read_failed(err, name, s, rv, "chunk layout");
  vr_status st = check_version(ctxt, name, err);
  if (st != VR_OK) return st;
  layout lay = {0};
  st = find_layout(ch, name, rgb != NULL, &lay, err);
  if (st != VR_OK) {
    free(lay.bands);
    return st;
  }
  /* As image_exr.c: no more than 2^30 pixels, whatever the header says.
   * And no more pixel memory than the file could decompress to: zlib's
   * ratio tops out near 1032:1, the other codecs' below, so 4096 times the
   * file's size (with 64 MiB always allowed) is only ever passed by a
   * header that lies, which must not cost gigabytes of memory to find. */
  int64_t w = (int64_t)dw.max.x - dw.min.x + 1, h = (int64_t)dw.max.y - dw.min.y + 1;
  uint64_t floats = 0;
  if (w >= 1 && h >= 1 && w <= INT32_MAX && h <= INT32_MAX && w * h <= ((int64_t)1 << 30))
    floats = (uint64_t)(w * h) * (lay.nbands + (lay.rgb[0] >= 0 ? 3 : 0));
  if (floats == 0)
    st = vr_error_at(err, VR_E_PARSE, name, 0, 0,
                     "OpenEXR: data window (%d,%d)-(%d,%d) is empty or larger than 2^30 pixels",
                     dw.min.x, dw.min.y, dw.max.x, dw.max.y);
  else if (floats * sizeof(float) > ((uint64_t)64 << 20) &&
           floats * sizeof(float) / 4096 > (uint64_t)s->len)
    st = vr_error_at(err, VR_E_PARSE, name, 0, 0,
                     "OpenEXR: a %" PRId64 " x %" PRId64 " x %zu-band image cannot come from "
                     "%zu bytes; the header is corrupt", w, h, lay.nbands, s->len);
  else if ((uint64_t)w * lay.nbands > INT32_MAX / sizeof(float))
    st = vr_error_at(err, VR_E_PARSE, name, 0, 0,
                     "%" PRId64 " pixels x %zu bands per line is more than OpenEXR's strides hold",
                     w, lay.nbands);
  if (st == VR_OK) st = check_chunks(ctxt, name, s, dw, lines, err);
  if (st == VR_OK) {
    double *wl = malloc(lay.nbands * sizeof *wl);
    if (!wl) {
      st = vr_error_at(err, VR_E_NOMEM, name, 0, 0, "out of memory");
    } else {
      for (size_t b = 0; b < lay.nbands; b++) wl[b] = lay.bands[b].nm;
      st = vr_spectral_image_alloc(out, (int)w, (int)h, lay.nbands, wl, lay.kind, err);
      free(wl);
      if (st == VR_OK && lay.rgb[0] >= 0) st = vr_image_alloc(rgb, (int)w, (int)h, err);
      if (st != VR_OK) vr_error_prefix(err, "%s: ", name);
    }
  }
  if (st == VR_OK) st = decode_pixels(ctxt, name, s, dw, lines, &lay, ch, out, rgb, err);
  free(lay.bands);
  return st;
}

vr_status vr_spectral_exr_read_memory(const void *buf, size_t len, const char *name,
                                      vr_spectral_image *out, vr_image *rgb_or_null,
                                      vr_error *err) {
  if (!out) return vr_error_set(err, VR_E_ARG, "vr_spectral_exr_read: output image is NULL");
  memset(out, 0, sizeof *out);
  if (rgb_or_null) memset(rgb_or_null, 0, sizeof *rgb_or_null);
  if (!name) name = "memory";
  if (!buf && len > 0) return vr_error_set(err, VR_E_ARG, "%s: buffer is NULL", name);
  static const unsigned char magic[4] = {0x76, 0x2F, 0x31, 0x01};
  if (len < 4 || memcmp(buf, magic, 4) != 0)
    return vr_error_at(err, VR_E_PARSE, name, 0, 0, "not an OpenEXR file (no magic number)");
  exr_stream s = {.buf = buf, .len = len};
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.user_data = &s;
  init.read_fn = vr_exr_stream_read;
  init.size_fn = vr_exr_stream_size;
  init.error_handler_fn = vr_exr_on_read_error;
  /* A cut file should fail, not be half-rebuilt from whatever chunks remain. */
  init.flags = EXR_CONTEXT_FLAG_DISABLE_CHUNK_RECONSTRUCTION;
  exr_context_t ctxt = NULL;
  exr_result_t rv = exr_start_read(&ctxt, name, &init);
  vr_status st = rv == EXR_ERR_SUCCESS ? read_context(ctxt, name, &s, out, rgb_or_null, err)
                                       : vr_exr_read_failed(err, name, &s, rv, "header");
  if (ctxt) exr_finish(&ctxt);
  if (st != VR_OK) {
    vr_spectral_image_free(out);
    vr_image_free(rgb_or_null);
  }
  return st;
}

vr_status vr_spectral_exr_read(const char *path, vr_spectral_image *out, vr_image *rgb_or_null,
                               vr_error *err) {
  if (!out) return vr_error_set(err, VR_E_ARG, "vr_spectral_exr_read: output image is NULL");
  memset(out, 0, sizeof *out);
  if (rgb_or_null) memset(rgb_or_null, 0, sizeof *rgb_or_null);
  if (!path) return vr_error_set(err, VR_E_ARG, "vr_spectral_exr_read: path is NULL");
  char *buf = NULL;
  size_t len = 0;
  vr_status st = vr_read_file(path, 0, &buf, &len, err);
  if (st != VR_OK) return st;
  st = vr_spectral_exr_read_memory(buf, len, path, out, rgb_or_null, err);
  free(buf);
  return st;
}
