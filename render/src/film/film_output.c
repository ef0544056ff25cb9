/* The files of a render (vr/film.h): RGB and spectral OpenEXR, the PNG for
 * the eye, the sensor table and the statistics.  Nothing here knows how the
 * result was computed, so the tests build results by hand.
 *
 * All or nothing across files: each output is first written whole (by the
 * image library's own atomic writers) into a staging folder beside its
 * target, and the staged files are renamed into place only once every one
 * of them exists, then described by a manifest written last (film_set.c).
 * A failure before that point leaves the previous outputs untouched; a
 * failed rename (rare: the folder became unwritable) removes the outputs of
 * this call already renamed. */
#include "vr/film.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/resource.h>
#include <unistd.h>

#include "vr/atomic_file.h"
#include "vr/csv.h"
#include "vr/flow.h"
#include "vr/falsecolour.h"
#include "vr/colour.h"
#include "vr/image.h"
#include "vr/json.h"
#include "vr/spectral_exr.h"
#include "vr/version.h"

#include "film/film_set.h"

/* The unit the spectral EXR declares, spelt as the layout's reference
 * writer does (the channels hold W/(m2 sr nm)). */
static const char EMISSIVE_UNITS[] = VR_SPECTRAL_EMISSIVE_UNITS;

vr_status vr_tonemap_parse(const char *text, vr_tonemap *out, vr_error *err) {
  if (!text || !strcasecmp(text, "clip")) *out = VR_TONEMAP_CLIP;
  else if (!strcasecmp(text, "reinhard")) *out = VR_TONEMAP_REINHARD;
  else if (!strcasecmp(text, "filmic")) *out = VR_TONEMAP_FILMIC;
  else
    return vr_error_set(err, VR_E_ARG, "tone mapping '%s': expected clip, reinhard or filmic", text);
  return VR_OK;
}

static double clamp01(double v) { return v > 0.0 ? (v < 1.0 ? v : 1.0) : 0.0; }

/* Narkowicz's rational fit of the ACES film response (RRT and sRGB ODT;
 * K. Narkowicz, "ACES Filmic Tone Mapping Curve", 2016):
 * x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14).  A toe below 0.1, about
 * linear through the mid-tones, a shoulder that reaches 1 at x = 7.24. */
static double filmic(double x) {
  if (!(x > 0)) return 0.0;
  if (x > 1e6) return 1.0; /* above the shoulder, and x^2 would overflow near 1e154 */
  return clamp01(x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14));
}

void vr_film_display(const double rgb[3], double Y, double exposure_ev, vr_tonemap tm,
                     double out[3]) {
  /* At EV 0, 100 cd/m² (a white wall under a few hundred lux) is display
   * white: the convention of docs/vr-render.md. */
  double k = exp2(exposure_ev) / 100.0;
  double s = k;
  if (tm == VR_TONEMAP_REINHARD) {
    double L = Y * k;
    if (isinf(L) && L > 0) {
      out[0] = out[1] = out[2] = 1.0;
      return;
    }
    /* Scaling all three channels by L'/L keeps the chromaticity; channels
     * of saturated colours may still pass 1 and are clamped below. */
    if (L > 0) s = k / (1.0 + L);
  } else if (tm == VR_TONEMAP_FILMIC) {
    /* Per channel on linear sRGB, as the fit is commonly used (not ACES's
     * own transforms in AP1): a bright saturated colour goes towards white
     * instead of staying a clipped hue. */
    for (int c = 0; c < 3; c++) out[c] = filmic(rgb[c] * k);
    return;
  }
  for (int c = 0; c < 3; c++) out[c] = clamp01(rgb[c] * s);
}

/* ---- checks before anything is written ---- */

/* The film's XYZ, and its bins when spectral: what the files to write hold. */
static vr_status check_film(const vr_render_result *r, bool spectral, vr_error *err) {
  static const char XYZ[] = "XYZ";
  size_t npix = (size_t)r->width * (size_t)r->height;
  for (size_t p = 0; p < npix; p++)
    for (int c = 0; c < 3; c++) {
      double v = r->xyz[3 * p + (size_t)c];
      if (isnan(v) || (isinf(v) && v < 0))
        return vr_error_set(err, VR_E_RANGE, "film pixel (%zu, %zu): %c is %s", p % (size_t)r->width,
                            p / (size_t)r->width, XYZ[c], isnan(v) ? "NaN" : "-infinity");
    }
  if (spectral && r->spectral)
    for (size_t p = 0; p < npix; p++)
      for (size_t b = 0; b < r->nbins; b++) {
        double v = r->spectral[p * r->nbins + b];
        if (isnan(v) || (isinf(v) && v < 0))
          return vr_error_set(err, VR_E_RANGE, "film pixel (%zu, %zu): the %g nm bin is %s",
                              p % (size_t)r->width, p / (size_t)r->width, r->bin_nm[b],
                              isnan(v) ? "NaN" : "-infinity");
      }
  return VR_OK;
}

static const char *sensor_name(const vr_sensor_reading *s) { return s->sensor ? s->sensor : ""; }

static vr_status check_sensors(const vr_render_result *r, vr_error *err) {
  for (size_t k = 0; k < r->nreadings; k++) {
    const vr_sensor_reading *s = &r->readings[k];
    const char *bad = isnan(s->illuminance_lx) ? "illuminance" : isnan(s->stderr_lx) ? "standard error" : NULL;
    for (size_t b = 0; !bad && r->sensor_spectral && b < r->nbins; b++)
      if (isnan(r->sensor_spectral[k * r->nbins + b])) bad = "spectral irradiance";
    if (bad)
      return vr_error_set(err, VR_E_RANGE, "sensor %s (%d, %d): the %s is NaN", sensor_name(s), s->i,
                          s->j, bad);
  }
  return VR_OK;
}

static vr_status check_result(const vr_render_result *r, vr_error *err) {
  if (!r) return vr_error_set(err, VR_E_ARG, "film: no render result");
  if (r->width < 0 || r->height < 0 || (r->width > 0 && r->height > 0 && !r->xyz))
    return vr_error_set(err, VR_E_ARG, "film: a %dx%d film without pixels", r->width, r->height);
  if (r->nbins && !r->bin_nm && (r->spectral || r->sensor_spectral))
    return vr_error_set(err, VR_E_ARG, "film: %zu bins without their wavelengths", r->nbins);
  if (r->nreadings && !r->readings)
    return vr_error_set(err, VR_E_ARG, "film: %zu sensor readings missing", r->nreadings);
  return VR_OK;
}

/* ---- the sensor table ---- */

static vr_status write_csv_to(const vr_render_result *r, const char *path, vr_error *err) {
  vr_atomic_file af;
  vr_status st = vr_atomic_file_open(&af, path, err);
  if (st) return st;
  FILE *f = af.fp;
  bool spectral = r->sensor_spectral && r->nbins;
  fputs("sensor,i,j,x,y,z,illuminance_lx,stderr_lx", f);
  for (size_t b = 0; spectral && b < r->nbins; b++) fprintf(f, ",E_%g", r->bin_nm[b]);
  fputs(",sky_component_lx,sun_direct_lx,externally_reflected_sky_lx,externally_reflected_sun_lx,"
        "internally_reflected_sky_lx,internally_reflected_sun_lx,electric_lx,"
        "daylight_factor_pct,df_sky_component_pct,df_externally_reflected_pct,"
        "df_internally_reflected_pct\n",
        f);
  for (size_t k = 0; k < r->nreadings; k++) {
    const vr_sensor_reading *s = &r->readings[k];
    vr_csv_write_field(f, sensor_name(s));
    fprintf(f, ",%d,%d,%.9g,%.9g,%.9g,%.9g,%.9g", s->i, s->j, s->position[0], s->position[1],
            s->position[2], s->illuminance_lx, s->stderr_lx);
    for (size_t b = 0; spectral && b < r->nbins; b++)
      fprintf(f, ",%.9g", r->sensor_spectral[k * r->nbins + b]);
    /* The parts and the daylight factor; an empty field where they do not
     * apply (photon sensors, no sky). */
    const double more[] = {s->part_lx[0], s->part_lx[1], s->part_lx[2], s->part_lx[3],
                           s->part_lx[4], s->part_lx[5], s->part_lx[6], s->df_pct,
                           s->df_sc_pct,  s->df_erc_pct, s->df_irc_pct};
    for (size_t q = 0; q < sizeof more / sizeof more[0]; q++)
      if (isnan(more[q]))
        fputc(',', f);
      else
        fprintf(f, ",%.9g", more[q]);
    fputc('\n', f);
  }
  return vr_atomic_file_commit(&af, err);
}

vr_status vr_sensors_write_csv(const vr_render_result *r, const char *path, vr_error *err) {
  vr_status st = check_result(r, err);
  if (!st) st = check_sensors(r, err);
  if (!st) st = write_csv_to(r, path, err);
  return st;
}

/* ---- staging: film_set.c ---- */

/* An error from a writer names the staging file: name the target instead. */
static void rename_in_message(vr_error *err, const vr_film_staged *g) {
  if (!err) return;
  char *at = strstr(err->message, g->stage);
  if (!at) return;
  char buf[VR_ERROR_MESSAGE_MAX];
  snprintf(buf, sizeof buf, "%.*s%s%s", (int)(at - err->message), err->message, g->target,
           at + strlen(g->stage));
  strcpy(err->message, buf);
}

/* ---- the images ---- */

/* The RGB EXR; after adaptive sampling with two more layers: each pixel's
 * samples (samples.N, uint) and the variance of its mean luminance
 * (variance.Y, (cd/m2)^2, float), a denoised render of fixed spp with the
 * variance alone; with the denoiser's features, the layers albedo (R, G,
 * B), normal (X, Y, Z) and nearness (V). */
static const char *const FEATURE_CHANNELS[VR_RESULT_FEATURES] = {
    "albedo.R", "albedo.G", "albedo.B", "normal.X", "normal.Y", "normal.Z", "nearness.V"};

static vr_status write_exr(const vr_render_result *r, const char *path, const vr_image *rgb,
                           const vr_exr_colour *colour, vr_error *err) {
  bool variance = r->pixel_variance != NULL;
  if (!variance && !r->features) return vr_image_write_exr_with(path, rgb, colour, err);
  size_t px = (size_t)r->width * (size_t)r->height, n = 0;
  size_t planes = (variance ? 1 : 0) + (r->features ? VR_RESULT_FEATURES : 0);
  float *buf = malloc((px ? px : 1) * planes * sizeof *buf);
  if (!buf) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  vr_exr_channel extra[2 + VR_RESULT_FEATURES];
  float *plane = buf;
  if (r->pixel_samples) extra[n++] = (vr_exr_channel){"samples.N", 1, r->pixel_samples};
  if (variance) {
    for (size_t p = 0; p < px; p++) plane[p] = (float)r->pixel_variance[p];
    extra[n++] = (vr_exr_channel){"variance.Y", 0, plane};
    plane += px;
  }
  for (int k = 0; r->features && k < VR_RESULT_FEATURES; k++, plane += px) {
    for (size_t p = 0; p < px; p++) plane[p] = r->features[p * VR_RESULT_FEATURES + (size_t)k];
    extra[n++] = (vr_exr_channel){FEATURE_CHANNELS[k], 0, plane};
  }
  vr_status st = vr_image_write_exr_channels(path, rgb, colour, extra, n, err);
  free(buf);
  return st;
}

/* The linear sRGB of the EXRs (rgb) and the display values of the PNG
 * (png); either may be NULL when its files are not asked for. */
static vr_status make_images(const vr_render_result *r, vr_tonemap tm, vr_image *rgb,
                             vr_image *png, vr_error *err) {
  vr_status st = rgb ? vr_image_alloc(rgb, r->width, r->height, err) : VR_OK;
  if (!st && png) st = vr_image_alloc(png, r->width, r->height, err);
  if (st) return st;
  size_t npix = (size_t)r->width * (size_t)r->height;
  for (size_t p = 0; p < npix; p++) {
    const double *xyz = &r->xyz[3 * p];
    double lin[3], disp[3];
    vr_xyz_to_srgb_linear(xyz, lin);
    if (png && r->xyz_display) {
      /* The PNG shows the denoised image, the EXRs the film. */
      const double *d = &r->xyz_display[3 * p];
      double dl[3];
      vr_xyz_to_srgb_linear(d, dl);
      vr_film_display(dl, d[1], r->exposure_ev, tm, disp);
    } else if (png) {
      vr_film_display(lin, xyz[1], r->exposure_ev, tm, disp);
    }
    for (int c = 0; c < 3; c++) {
      if (rgb) rgb->data[3 * p + (size_t)c] = (float)lin[c];
      if (png) png->data[3 * p + (size_t)c] = (float)vr_srgb_encode(disp[c]);
    }
  }
  return VR_OK;
}

/* The files asked for (0: all the result can give), or VR_E_ARG naming
 * one it cannot give. */
static vr_status chosen_outputs(const vr_render_result *r, unsigned asked, unsigned *out,
                                vr_error *err) {
  bool image = r->width > 0 && r->height > 0;
  unsigned can = (image ? VR_FILM_EXR | VR_FILM_PNG | VR_FILM_HDR : 0u) |
                 (image && r->nbins > 0 && r->spectral ? VR_FILM_SPECTRAL : 0u) |
                 (r->nreadings ? VR_FILM_SENSORS : 0u);
  *out = asked ? asked : can & ~(unsigned)VR_FILM_HDR; /* the Radiance picture when asked */
  if (asked & ~(unsigned)VR_FILM_ALL)
    return vr_error_set(err, VR_E_ARG, "film: unknown outputs 0x%x", asked & ~(unsigned)VR_FILM_ALL);
  unsigned cannot = asked & ~can;
  if (cannot & (VR_FILM_EXR | VR_FILM_PNG | VR_FILM_HDR))
    return vr_error_set(err, VR_E_ARG, "film: the %s was asked for, but the render has no image "
                        "(no camera pass)",
                        cannot & VR_FILM_EXR ? "EXR" : cannot & VR_FILM_PNG ? "PNG" : "Radiance picture");
  if (cannot & VR_FILM_SPECTRAL)
    return vr_error_set(err, VR_E_ARG, "film: the spectral EXR was asked for, but the %s",
                        image ? "film has no spectral bins" : "render has no image (no camera pass)");
  if (cannot & VR_FILM_SENSORS)
    return vr_error_set(err, VR_E_ARG, "film: the sensor table was asked for, but the render has "
                        "no sensor readings");
  return VR_OK;
}

/* The spectral EXR's rows, made from the film's doubles a chunk of lines
 * at a time (vr_spectral_exr_write_rows): no float copy of the whole
 * spectral film (4 bytes a pixel a bin, 950 MiB at 4K with 30 bins). */
typedef struct spectral_rows {
  const vr_render_result *r;
  const vr_image *rgb;
} spectral_rows;

static vr_status fill_spectral_rows(void *user, int thread, int y0, int y1, float *spectra,
                                    float *rgb, uint32_t *flags, vr_error *err) {
  (void)thread;
  (void)flags;
  (void)err;
  const spectral_rows *s = user;
  size_t w = (size_t)s->r->width, nb = s->r->nbins, n = (size_t)(y1 - y0) * w;
  const double *from = s->r->spectral + (size_t)y0 * w * nb;
  for (size_t i = 0; i < n * nb; i++) spectra[i] = (float)from[i];
  if (rgb) memcpy(rgb, s->rgb->data + (size_t)y0 * w * 3, n * 3 * sizeof(float));
  return VR_OK;
}

static vr_status write_spectral(const vr_render_result *r, const char *path, const vr_image *rgb,
                                const vr_exr_colour *colour, vr_error *err) {
  vr_spectral_exr_layout layout = {.width = r->width,
                                   .height = r->height,
                                   .nbands = r->nbins,
                                   .wavelengths_nm = r->bin_nm,
                                   .kind = VR_SPECTRAL_EMISSIVE,
                                   .rgb = 1,
                                   .emissive_units = EMISSIVE_UNITS,
                                   .compression = VR_EXR_COMPRESSION_ZIP,
                                   .threads = 1,
                                   .colour = colour};
  spectral_rows rows = {r, rgb};
  return vr_spectral_exr_write_rows(path, &layout, fill_spectral_rows, &rows, err);
}

/* The luminance map on the options' scale, the film's Y. */
static vr_status make_falsecolour(const vr_render_result *r, const vr_film_options *o,
                                  vr_image *fc, vr_error *err) {
  size_t npix = (size_t)r->width * (size_t)r->height;
  double *Y = malloc((npix + 1) * sizeof *Y);
  if (!Y) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  for (size_t p = 0; p < npix; p++) Y[p] = r->xyz[3 * p + 1];
  vr_status st = vr_falsecolour_image(Y, r->width, r->height, o->falsecolour_lo_cd_m2,
                                      o->falsecolour_hi_cd_m2, fc, err);
  free(Y);
  return st;
}

vr_status vr_film_write(const vr_render_result *r, const char *prefix, const char *tonemap,
                        vr_error *err) {
  vr_film_options o = {.tonemap = tonemap};
  return vr_film_write_with(r, prefix, &o, err);
}

vr_status vr_film_write_with(const vr_render_result *r, const char *prefix,
                             const vr_film_options *o, vr_error *err) {
  vr_tonemap tm = VR_TONEMAP_CLIP;
  vr_status st = vr_tonemap_parse(o->tonemap, &tm, err);
  if (st) return st;
  bool falsecolour = o->falsecolour_lo_cd_m2 != 0 || o->falsecolour_hi_cd_m2 != 0;
  if (!prefix || !*prefix) return vr_error_set(err, VR_E_ARG, "film: no output prefix");
  if ((st = check_result(r, err)) || (st = check_sensors(r, err))) return st;
  bool image = r->width > 0 && r->height > 0;
  unsigned want;
  if ((st = chosen_outputs(r, o->outputs, &want, err))) return st;
  bool exr = want & VR_FILM_EXR, spectral = want & VR_FILM_SPECTRAL, png_file = want & VR_FILM_PNG;
  bool hdr = want & VR_FILM_HDR;
  if ((exr || spectral || png_file || hdr || falsecolour) && image &&
      (st = check_film(r, spectral, err)))
    return st;
  if (falsecolour && !image)
    return vr_error_set(err, VR_E_ARG, "false colour: the render has no image (no camera pass)");

  vr_image rgb = {0}, png = {0}, fc = {0};
  vr_film_set set = {0};
  vr_film_staged *g = NULL;
  char run_id[VR_FILM_RUN_ID_MAX];
  if (!o->run_id) vr_film_run_id(run_id);
  if ((st = film_set_begin(&set, prefix, err))) goto out;
  if (image) {
    /* The EXRs' linear RGB (12 bytes a pixel, 95 MiB at 4K), freed before
     * the PNG's image is made; the spectral EXR is converted a chunk of
     * lines at a time (write_spectral). */
    if ((exr || spectral) && (st = make_images(r, tm, &rgb, NULL, err))) goto out;
    /* For viewers: linear sRGB, pixels in cd/m2 (RGB (1,1,1) is 1 cd/m2),
     * and the exposure that makes the PNG's white (100 cd/m2 at EV 0) 1.0. */
    vr_exr_colour colour = vr_exr_colour_srgb(1.0, r->exposure_ev - log2(100.0));
    if (exr) {
      if ((st = film_set_add(&set, ".exr", &g, err))) goto out;
      if ((st = write_exr(r, g->stage, &rgb, &colour, err))) goto fail;
    }
    if (spectral) {
      if ((st = film_set_add(&set, ".spectral.exr", &g, err))) goto out;
      if ((st = write_spectral(r, g->stage, &rgb, &colour, err))) goto fail;
    }
    vr_image_free(&rgb);
    if (hdr) {
      if ((st = film_set_add(&set, ".hdr", &g, err))) goto out;
      if ((st = vr_film_write_hdr(r, o->camera, g->stage, err))) goto fail;
    }
    if (png_file) {
      if ((st = make_images(r, tm, NULL, &png, err))) goto out;
      if ((st = film_set_add(&set, ".png", &g, err))) goto out;
      if ((st = vr_image_write_png(g->stage, &png, 8, err))) goto fail;
      vr_image_free(&png);
    }
    if (falsecolour) {
      if ((st = make_falsecolour(r, o, &fc, err))) goto out;
      if ((st = film_set_add(&set, ".falsecolour.png", &g, err))) goto out;
      if ((st = vr_image_write_png(g->stage, &fc, 8, err))) goto fail;
    }
  }
  if (want & VR_FILM_SENSORS) {
    if ((st = film_set_add(&set, ".sensors.csv", &g, err))) goto out;
    if ((st = write_csv_to(r, g->stage, err))) goto fail;
  }
  if (o->stats_path) {
    if ((st = film_set_add_path(&set, o->stats_path, &g, err))) goto out;
    if ((st = vr_stats_write_json(r, g->stage, err))) goto fail;
  }
  st = film_set_commit(&set, o->run_id ? o->run_id : run_id, err);
  goto out;
fail:
  rename_in_message(err, g);
out:
  if (st && set.dir) film_set_abort(&set);
  vr_image_free(&rgb);
  vr_image_free(&png);
  vr_image_free(&fc);
  return st;
}

/* ---- statistics ---- */

long long vr_peak_rss_bytes(void) {
  struct rusage ru;
  if (getrusage(RUSAGE_SELF, &ru) != 0) return 0;
  return (long long)ru.ru_maxrss * 1024; /* Linux reports KiB */
}

static void json_key(FILE *f, const char *indent, const char *key) {
  fprintf(f, "%s", indent);
  vr_json_string(f, key);
  fputs(": ", f);
}

void vr_adaptive_write_json(FILE *f, const vr_render_result *r) {
  if (!r->pixel_samples) {
    fputs("null", f);
    return;
  }
  const struct vr_adaptive_summary *a = &r->adaptive;
  fprintf(f, "{\"rounds\": %d, \"spp_first\": %u, \"spp_min\": %u, \"spp_max\": %u, \"spp_mean\": ",
          a->rounds, a->spp_first, a->spp_min, a->spp_max);
  vr_json_number(f, a->spp_mean);
  fputs(", \"converged_share\": ", f);
  vr_json_number(f, a->converged_share);
  fputs(", \"error_p95\": ", f);
  vr_json_number(f, a->error_p95);
  fputs(", \"stop\": ", f);
  vr_json_string(f, a->stop);
  fputc('}', f);
}

void vr_passes_write_json(FILE *f, const vr_render_result *r) {
  fputc('[', f);
  size_t np = r->npasses < VR_MAX_PASSES ? r->npasses : VR_MAX_PASSES;
  for (size_t i = 0; i < np; i++) {
    const vr_pass_record *p = &r->passes[i];
    fprintf(f, "%s\n    {\"name\": ", i ? "," : "");
    vr_json_string(f, p->name);
    fprintf(f, ", \"ran\": %s, \"reason\": ", p->ran ? "true" : "false");
    vr_json_string(f, p->reason);
    fputs(", \"seconds\": ", f);
    vr_json_number(f, p->ran ? p->seconds : NAN);
    fputc('}', f);
  }
  fputs(np ? "\n  ]" : "]", f);
}

vr_status vr_stats_write_json(const vr_render_result *r, const char *path, vr_error *err) {
  vr_status st = check_result(r, err);
  if (st) return st;
  if (!path) return vr_error_set(err, VR_E_ARG, "stats: no path");
  vr_atomic_file af;
  if ((st = vr_atomic_file_open(&af, path, err))) return st;
  FILE *f = af.fp;
  fputs("{\n", f);
  json_key(f, "  ", "version");
  vr_json_string(f, vr_version());
  fputs(",\n", f);

  json_key(f, "  ", "image");
  fprintf(f, "{\"width\": %d, \"height\": %d, \"bins\": %zu, \"bin_first_nm\": ", r->width,
          r->height, r->nbins);
  vr_json_number(f, r->nbins && r->bin_nm ? r->bin_nm[0] : NAN);
  fputs(", \"bin_last_nm\": ", f);
  vr_json_number(f, r->nbins && r->bin_nm ? r->bin_nm[r->nbins - 1] : NAN);
  fputs(", \"bin_width_nm\": ", f);
  vr_json_number(f, r->nbins ? r->bin_width_nm : NAN);
  fputs(", \"exposure_ev\": ", f);
  vr_json_number(f, r->exposure_ev);
  fputs(", \"adaptive\": ", f);
  vr_adaptive_write_json(f, r);
  fputs("},\n", f);

  json_key(f, "  ", "passes");
  vr_passes_write_json(f, r);
  fputs(",\n", f);

  json_key(f, "  ", "rays");
  fprintf(f,
          "{\"camera\": %" PRIu64 ", \"shadow\": %" PRIu64 ", \"photon\": %" PRIu64
          ", \"other\": %" PRIu64 ", \"crossings\": %" PRIu64 ", \"created\": %" PRIu64
          ", \"finished\": %" PRIu64 "},\n",
          r->rays_camera, r->rays_shadow, r->rays_photon, r->rays_other, r->crossings,
          r->rays_created, r->rays_finished);
  json_key(f, "  ", "photons");
  fprintf(f, "{\"global\": %zu, \"caustic\": %zu, \"direct\": %zu},\n", r->photons_global,
          r->photons_caustic, r->photons_direct);

  json_key(f, "  ", "sensors");
  fputs("[", f);
  for (size_t k = 0; k < r->nreadings; k++) {
    const vr_sensor_reading *s = &r->readings[k];
    fprintf(f, "%s\n    {\"name\": ", k ? "," : "");
    vr_json_string(f, sensor_name(s));
    fprintf(f, ", \"i\": %d, \"j\": %d, \"position\": [", s->i, s->j);
    for (int c = 0; c < 3; c++) {
      if (c) fputs(", ", f);
      vr_json_number(f, s->position[c]);
    }
    fputs("], \"illuminance_lx\": ", f);
    vr_json_number(f, s->illuminance_lx);
    fputs(", \"stderr_lx\": ", f);
    vr_json_number(f, s->stderr_lx);
    fprintf(f, ", \"paths\": %llu", (unsigned long long)s->paths);
    fputs(", \"daylight_factor_pct\": ", f);
    vr_json_number(f, s->df_pct);
    fputs("}", f);
  }
  fputs(r->nreadings ? "\n  ],\n" : "],\n", f);

  json_key(f, "  ", "photochromic");
  fprintf(f, "{\"texels\": %zu, \"state_min\": ", r->photochromic_texels);
  vr_json_number(f, r->photochromic_texels ? r->photochromic_state_min : NAN);
  fputs(", \"state_max\": ", f);
  vr_json_number(f, r->photochromic_texels ? r->photochromic_state_max : NAN);
  fputs("},\n", f);

  json_key(f, "  ", "degenerate_triangles");
  fprintf(f, "%zu,\n", r->degenerate_triangles);
  /* Sub-domains, the geometry cache and what was held against the budget
   * (docs/ddm.md). */
  json_key(f, "  ", "subdomains");
  fprintf(f,
          "{\"count\": %d, \"loads\": %" PRIu64 ", \"unloads\": %" PRIu64
          ", \"bytes_read\": %" PRIu64 ", \"load_seconds\": ",
          r->subdomains, r->cell_loads, r->cell_unloads, r->cell_bytes_read);
  vr_json_number(f, r->cell_load_seconds);
  fprintf(f, ", \"rays_spilled\": %" PRIu64 "},\n", r->rays_spilled);
  json_key(f, "  ", "cache");
  fprintf(f, "{\"built\": %s, \"reason\": ", r->cache_built ? "true" : "false");
  vr_json_string(f, r->cache_reason);
  fputs(", \"seconds\": ", f);
  vr_json_number(f, r->cache_seconds);
  fprintf(f, ", \"bytes\": %" PRIu64 "},\n", r->cache_bytes);
  json_key(f, "  ", "cells");
  fputs("[", f);
  for (size_t c = 0; r->cell_seconds && c < r->ncells; c++) {
    fprintf(f, "%s{\"seconds\": ", c ? ", " : "");
    vr_json_number(f, r->cell_seconds[c]);
    fprintf(f, ", \"ranks\": %d}", r->cell_ranks ? r->cell_ranks[c] : 1);
  }
  fputs("],\n", f);
  json_key(f, "  ", "ranks");
  fputs("[", f);
  for (int k = 0; r->rank_stats && k < r->ranks; k++) {
    const vr_rank_stats *q = &r->rank_stats[k];
    fprintf(f,
            "%s\n    {\"rank\": %d, \"cells_loaded\": %d, \"rays_traced\": %" PRIu64
            ", \"rays_sent\": %" PRIu64 ", \"rays_received\": %" PRIu64 ", \"messages\": %" PRIu64
            ", \"bytes_sent\": %" PRIu64 ", \"waves\": %" PRIu64 ", \"idle_seconds\": ",
            k ? "," : "", k, q->cells_loaded, q->rays_traced, q->rays_sent, q->rays_received,
            q->messages, q->bytes_sent, q->waves);
    vr_json_number(f, q->idle_seconds);
    fputs(", \"load_seconds\": ", f);
    vr_json_number(f, q->load_seconds);
    fprintf(f,
            ", \"cell_loads\": %" PRIu64 ", \"credit_waits\": %" PRIu64
            ", \"ray_messages\": %" PRIu64 ", \"ray_bytes_sent\": %" PRIu64 ", \"ray_wire_bytes\": ",
            q->cell_loads, q->credit_waits, q->ray_messages, q->ray_bytes_sent);
    /* A ray's mean size on the wire: its messages' bytes but their 8-byte
     * headers, over the rays they carried. */
    vr_json_number(f, q->rays_sent ? (double)(q->ray_bytes_sent - 8 * q->ray_messages) /
                                         (double)q->rays_sent
                                   : 0.0);
    fprintf(f,
            ", \"peak_uncredited\": %" PRIu64
            ", \"peak_queue_bytes\": %zu, \"peak_cells_bytes\": %zu, \"peak_rss_bytes\": %lld"
            ", \"rss_start_bytes\": %lld, \"rss_base_bytes\": %lld}",
            q->peak_uncredited, q->peak_queue_bytes, q->peak_cells_bytes, q->peak_rss_bytes,
            q->rss_start_bytes, q->rss_base_bytes);
  }
  fputs(r->rank_stats && r->ranks ? "\n  ],\n" : "],\n", f);
  json_key(f, "  ", "memory");
  fprintf(f,
          "{\"budget_bytes\": %zu, \"peak_cells_bytes\": %zu, \"peak_geometry_bytes\": %zu, "
          "\"peak_embree_bytes\": %zu, \"peak_queue_bytes\": %zu, \"peak_map_bytes\": %zu, "
          "\"peak_spill_bytes\": %zu, \"rss_start_bytes\": %lld, \"rss_base_bytes\": %lld, "
          "\"peak_uncounted_bytes\": %zu, \"film_bytes\": %zu},\n",
          r->memory_budget, r->peak_cells_bytes, r->peak_geometry_bytes, r->peak_embree_bytes,
          r->peak_queue_bytes, r->peak_map_bytes, r->peak_spill_bytes, r->rss_start_bytes,
          r->rss_base_bytes, r->peak_uncounted_bytes, r->film_bytes);
  vr_flow_profile_write_json(f, r);
  json_key(f, "  ", "peak_rss_bytes");
  fprintf(f, "%lld,\n", vr_peak_rss_bytes());
  json_key(f, "  ", "seconds_total");
  vr_json_number(f, r->seconds_total);
  fputs("\n}\n", f);
  return vr_atomic_file_commit(&af, err);
}
