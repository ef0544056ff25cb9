/* vr-rgb2spec simulate: the photos a manifest describes, rendered from the
 * regions' reference spectra through the manifest's camera and lights, with
 * Gaussian noise on the linear values, then encoded and quantised as the
 * photo's file says (8-bit sRGB PNG by default; a calibrated db: camera's
 * own tone curves, vr_capture_encode).  Used to make
 * samples/photos and the tests' captures. */
#include "rgb2spec.h"
#include "rgb2spec_inputs.h"

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vr/colour.h"

/* Background: a flat grey of reflectance 0.2; chart card: 0.03. */
#define BACKGROUND 0.20
#define CARD 0.03

static void fill(vr_image *img, int x0, int y0, int x1, int y1, const double rgb[3]) {
  for (int y = y0 < 0 ? 0 : y0; y < y1 && y < img->height; y++)
    for (int x = x0 < 0 ? 0 : x0; x < x1 && x < img->width; x++)
      for (int ch = 0; ch < 3; ch++) img->data[((size_t)y * img->width + x) * 3 + ch] = (float)rgb[ch];
}

/* Linear responses of a spectrum under light l (flat if s is NULL). */
static void respond(const vr_recovery_system *sys, size_t l, const vr_spectrum *s, double flat,
                    double out[3]) {
  size_t n = vr_recovery_system_samples(sys);
  const double *grid = vr_recovery_system_grid(sys);
  double r[1024], c[3 * RGB2SPEC_MAX_LIGHTS];
  for (size_t j = 0; j < n && j < 1024; j++) r[j] = s ? vr_spectrum_eval(s, grid[j], VR_INTERP_LINEAR) : flat;
  vr_render_rgb(sys, r, c);
  memcpy(out, &c[3 * l], 3 * sizeof *out);
}

int rg_cmd_simulate(vr_args *a) {
  vr_error err = {0};
  const char *manifest = vr_args_get(a, "manifest"), *size = vr_args_get(a, "size");
  if (!manifest) {
    fprintf(stderr, "vr-rgb2spec: simulate needs --manifest FILE\n");
    return 2;
  }
  int W = 640, H = 480;
  if (size && (sscanf(size, "%dx%d", &W, &H) != 2 || W < 8 || H < 8 || W > 20000 || H > 20000)) {
    fprintf(stderr, "vr-rgb2spec: --size '%s': expected WxH, e.g. 640x480\n", size);
    return 2;
  }
  double sigma, seed;
  if (vr_args_double(a, "noise", 0.002, &sigma, &err) || vr_args_double(a, "seed", 1, &seed, &err)) {
    fprintf(stderr, "vr-rgb2spec: %s\n", err.message);
    return 2;
  }
  /* Noise on linear values in [0, 1]; a seed is a whole number. */
  if (!(sigma >= 0 && sigma < 1)) {
    fprintf(stderr, "vr-rgb2spec: --noise %g: expected a standard deviation in [0, 1) of linear "
                    "pixel values\n", sigma);
    return 2;
  }
  if (!(seed >= 0 && seed <= 4294967295.0 && seed == floor(seed))) {
    fprintf(stderr, "vr-rgb2spec: --seed %g: expected a whole number in [0, 4294967295]\n", seed);
    return 2;
  }
  vr_matdb *db = NULL;
  vr_capture *cap = NULL;
  vr_camera *cam = NULL;
  vr_recovery_system *sys = NULL;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  vr_image img = {0};
  int rc = 1;
  if (!rng) goto out;
  gsl_rng_set(rng, (unsigned long)seed);
  /* The database only when the manifest names db: materials. */
  if (vr_capture_read_db(manifest, vr_args_get(a, "db"), VR_MATDB_READONLY, false, &db, &cap, &err))
    goto out;
  if (cap->nphotos > RGB2SPEC_MAX_LIGHTS) {
    vr_error_set(&err, VR_E_ARG, "at most %d photos", RGB2SPEC_MAX_LIGHTS);
    goto out;
  }
  /* The photos are this command's outputs: none may replace a file the
   * capture reads, and every one must be writable before the first is
   * rendered (no half-made set). */
  {
    vr_out_guard *g = calloc(1, sizeof *g);
    if (!g) {
      vr_error_set(&err, VR_E_NOMEM, "out of memory");
      goto out;
    }
    vr_out_guard_init(g);
    rg_guard_capture(g, cap, false);
    vr_out_guard_database(g, vr_args_get(a, "db") ? vr_args_get(a, "db") : vr_matdb_default_path());
    vr_status gst = VR_OK;
    for (size_t l = 0; l < cap->nphotos && !gst; l++) {
      gst = vr_out_guard_check(g, cap->photos[l].path, "photo", &err);
      if (gst) vr_error_prefix(&err, "%s:%ld: ", cap->path, cap->photos[l].line);
    }
    free(g);
    if (gst) goto out;
  }
  double grid[1024];
  size_t n;
  if (vr_camera_grid_uniform(cap->grid[0], cap->grid[1], cap->grid[2], grid, 1024, &n, &err)) goto out;
  cam = cap->camera == VR_CAPTURE_CAMERA_SRGB
            ? vr_camera_create_srgb(n, grid, &err)
            : vr_camera_create_measured((const vr_spectrum *const *)cap->sens, n, grid, &err);
  if (!cam) goto out;
  const vr_spectrum *lights[RGB2SPEC_MAX_LIGHTS];
  double scale[RGB2SPEC_MAX_LIGHTS];
  for (size_t l = 0; l < cap->nphotos; l++) lights[l] = cap->photos[l].light, scale[l] = cap->photos[l].scale;
  if (!(sys = vr_recovery_system_create(cam, cap->nphotos, lights, scale, NULL, &err))) goto out;
  for (size_t i = 0; i < cap->nregions; i++) {
    const vr_capture_region *r = &cap->regions[i];
    if (r->kind == VR_REGION_LABEL || (r->kind == VR_REGION_CHART && r->chart_auto)) {
      vr_error_at(&err, VR_E_ARG, cap->path, r->line, 0,
                  "simulate places rectangles and charts with grid=...; region %s is not one", r->name);
      goto out;
    }
    if (!r->reference) {
      vr_error_at(&err, VR_E_ARG, cap->path, r->line, 0,
                  "region %s has no reference=...: simulate renders reference spectra", r->name);
      goto out;
    }
  }
  if (vr_image_alloc(&img, W, H, &err)) goto out;
  for (size_t l = 0; l < cap->nphotos; l++) {
    const vr_capture_photo *p = &cap->photos[l];
    double rgb[3];
    respond(sys, l, NULL, BACKGROUND, rgb);
    fill(&img, 0, 0, W, H, rgb);
    for (size_t i = 0; i < cap->nregions; i++) {
      const vr_capture_region *r = &cap->regions[i];
      if (r->kind == VR_REGION_RECT) {
        respond(sys, l, r->reference, 0, rgb);
        fill(&img, r->x, r->y, r->x + r->w, r->y + r->h, rgb);
        continue;
      }
      /* Chart layout of vr/chart.h: 6 x 4 patches of side s, gaps s/10,
       * patch area 6.5 s by 4.3 s from (x0, y0) on a dark card. */
      double s = (r->w - r->x) / 6.5;
      if (r->label == 0) {
        respond(sys, l, NULL, CARD, rgb);
        fill(&img, r->x - (int)(s / 5), r->y - (int)(s / 5), r->w + (int)(s / 5), r->h + (int)(s / 5), rgb);
      }
      int row = r->label / 6, col = r->label % 6;
      double px = r->x + col * 1.1 * s, py = r->y + row * 1.1 * s;
      respond(sys, l, r->reference, 0, rgb);
      fill(&img, (int)lround(px), (int)lround(py), (int)lround(px + s), (int)lround(py + s), rgb);
    }
    /* Noise on linear values, then the file's encoding. */
    bool srgb = p->encoding != 2;
    for (size_t k = 0; k < (size_t)W * H * 3; k++) {
      double v = img.data[k] + (sigma > 0 ? gsl_ran_gaussian(rng, sigma) : 0);
      v = fmin(fmax(v, 0), 1);
      img.data[k] = (float)vr_capture_encode(cap, p, (int)(k % 3), v, srgb);
    }
    /* Linear photos as 16-bit files, as a raw converter writes them. */
    if (vr_image_write(p->path, &img, srgb ? 8 : 16, &err)) goto out;
    fprintf(stderr, "vr-rgb2spec: wrote %s (%s)\n", p->path, p->light_name);
  }
  rc = 0;
out:
  if (rc) fprintf(stderr, "vr-rgb2spec: %s\n", err.message);
  vr_image_free(&img);
  vr_recovery_system_destroy(sys);
  vr_camera_destroy(cam);
  vr_capture_destroy(cap);
  vr_matdb_close(db);
  gsl_rng_free(rng);
  return rc;
}
