/* vr-rgb2spec's pieces: what one run measures and recovers, shared by the
 * recovery, the outputs and the simulator. */
#ifndef VR_RGB2SPEC_H
#define VR_RGB2SPEC_H

#include <stdbool.h>
#include "vr/args.h"
#include "vr/image.h"
#include "vr/manifest.h"
#include "vr/matdb.h"
#include "vr/recover.h"
#include "vr/spectral_exr.h"
#include <stdio.h>

#define RGB2SPEC_MAX_LIGHTS 16

/* One region seen in every photo, and what was recovered for it. */
typedef struct rg_region {
  const vr_capture_region *def;
  double encoded[RGB2SPEC_MAX_LIGHTS][3]; /* mean pixel value as stored */
  double c[3 * RGB2SPEC_MAX_LIGHTS];       /* linear responses */
  double rendered[3 * RGB2SPEC_MAX_LIGHTS];
  unsigned char clipped[3 * RGB2SPEC_MAX_LIGHTS];
  int box[4];                                /* x0, y0, x1, y1 of pixels inside it; x1 = 0: none */
  double sigma[3 * RGB2SPEC_MAX_LIGHTS];       /* noise of the mean response (linear) */
  double sigma_pixel[3 * RGB2SPEC_MAX_LIGHTS]; /* noise of one pixel (linear) */
  long pixels[RGB2SPEC_MAX_LIGHTS];            /* pixels averaged in each photo */
  /* CIEDE2000 photo vs re-rendered per light; NAN for a light with a
   * clipped channel (the photo's value there is a bound, not a colour). */
  double de[RGB2SPEC_MAX_LIGHTS];
  double de_mean, de_max; /* over the lights without clipped channels (NAN: none) */
  size_t nclipped_lights; /* lights left out of de_mean for clipping */
  bool misfit;            /* misses its photos by more than their noise explains */
  double *r;                                 /* recovered spectrum on the grid */
  vr_recover_info info;
  double rmse;                               /* vs the reference, NAN without one */
  double heldout_de[8];                      /* under lights left out of the fit */
  size_t nheldout;
} rg_region;

typedef struct rg_run {
  const vr_capture *cap;
  const vr_camera *cam;
  size_t nphotos;
  const vr_capture_photo *photo[RGB2SPEC_MAX_LIGHTS];
  vr_recovery_system *sys;
  vr_recover_method method;
  const char *method_name;
  size_t n;                   /* grid samples */
  const double *grid;
  double condition;
  size_t nregions;
  rg_region *regions;
  const char *heldout_name[8];
  size_t nheldout;
  size_t nmisfit; /* regions flagged misfit */
  /* Consistency of each photo with its light: the regions recovered from
   * the other photos, re-rendered under this light, against this photo
   * (median CIEDE2000 over the regions; NAN with fewer than 3 photos). */
  double loo_de[RGB2SPEC_MAX_LIGHTS];
  bool light_suspect[RGB2SPEC_MAX_LIGHTS];
} rg_run;

/* Median leave-one-photo-out CIEDE2000 above which a photo's light is
 * reported as inconsistent with it (rgb2spec_checks.c). */
#define RG_LOO_LIMIT 6.0
vr_status rg_check_lights(rg_run *run, vr_error *err);
/* The median of v[0..k), k >= 1 (sorts v; rgb2spec_checks.c). */
double rg_median(double *v, size_t k);
/* true when the spectra of the two lights agree in shape (rgb2spec_checks.c). */
bool rg_same_light(const vr_spectrum *a, const vr_spectrum *b);

/* The run's photos decoded into img[0..nphotos) on up to `threads`
 * threads, and every region measured in each (rgb2spec_measure.c). */
vr_status rg_read_photos(rg_run *run, vr_image *img, int threads, vr_error *err);
vr_status rg_measure_photos(rg_run *run, const vr_image *img, int threads, vr_error *err);

/* Outputs (rgb2spec_output.c). */
void rg_print_text(const rg_run *run);
void rg_print_json(const rg_run *run);
vr_status rg_write_report(const char *path, const rg_run *run, vr_error *err);
/* Saves each region's spectrum as P<region>; forced: saved with --force
 * although some region misses its photos or a light disagrees with its
 * photo (said in the provenance note, with the region's own flags). */
vr_status rg_save(vr_matdb *db, const char *prefix, const rg_run *run, bool forced, vr_error *err);

/* CIEDE2000 between two linear camera responses under light l of the run
 * (through XYZ with the light's white). */
double rg_delta_e(const rg_run *run, size_t light, const double a[3], const double b[3]);

/* Per-pixel recovery into a spectral OpenEXR (rgb2spec_pixels.c). */
typedef struct rg_pixel_options {
  int threads;
  vr_exr_compression compression;
  bool half; /* 16-bit half bands (default) */
} rg_pixel_options;

typedef struct rg_pixels {
  long pixels;
  double lambda;                 /* per-pixel smoothing, weighted units */
  double sigma[3 * RGB2SPEC_MAX_LIGHTS]; /* per-pixel noise used (linear) */
  long bounded, clipped, misfit, no_data, fallback; /* pixels with each flag */
  double chi2_per_channel;       /* mean over pixels of chi2 / unclipped channels */
  double *mean;                  /* mean spectrum over the pixels (n), malloc'ed */
  /* Texture against the regions, over the pixels of rect and chart regions:
   * RMSE of the pixels' spectra against the region's own (patch) recovery
   * and against its reference (NAN without one). */
  long *region_pixels;           /* nregions, malloc'ed */
  double *region_rmse_patch, *region_rmse_ref;
  double rmse_patch, rmse_ref;   /* over every counted pixel */
  double seconds;                /* recovery and writing */
} rg_pixels;
vr_status rg_per_pixel(const rg_run *run, const vr_image *img, const char *path,
                       const rg_pixel_options *opt, rg_pixels *res, vr_error *err);
void rg_pixels_free(rg_pixels *px);
void rg_print_pixels(FILE *out, const rg_run *run, const rg_pixels *px, const char *path);
/* Saves material `name` for the texture: its hash is of the file as
 * written at `written`, its 'texture' property the absolute path of
 * `final` (where the caller then puts it; the same name when written in
 * place). */
vr_status rg_save_texture(vr_matdb *db, const char *name, const char *written, const char *final,
                          const rg_run *run, const rg_pixels *px, bool forced, vr_error *err);

/* vr-rgb2spec simulate (rgb2spec_simulate.c). */
int rg_cmd_simulate(vr_args *a);

/* vr-rgb2spec calibrate (rgb2spec_calibrate.c): parses its own options;
 * argv[0] is "calibrate". */
int rg_cmd_calibrate(int argc, char **argv);

#endif
