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

#define RGB2SPEC_MAX_LIGHTS 16

/* One region seen in every photo, and what was recovered for it. */
typedef struct rg_region {
  const vr_capture_region *def;
  double encoded[RGB2SPEC_MAX_LIGHTS][3]; /* mean pixel value as stored */
  double c[3 * RGB2SPEC_MAX_LIGHTS];       /* linear responses */
  double rendered[3 * RGB2SPEC_MAX_LIGHTS];
  unsigned char clipped[3 * RGB2SPEC_MAX_LIGHTS];
  double de[RGB2SPEC_MAX_LIGHTS];           /* CIEDE2000 photo vs re-rendered, per light */
  double de_mean, de_max;
  double *r;                                 /* recovered spectrum on the grid */
  vr_recover_info info;
  double rmse;                               /* vs the reference, NAN without one */
  double heldout_de[8];                      /* under lights left out of the fit */
  size_t nheldout;
} rg_region;

typedef struct rg_run {
  const vr_capture *cap;
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
} rg_run;

/* Outputs (rgb2spec_output.c). */
void rg_print_text(const rg_run *run);
void rg_print_json(const rg_run *run);
vr_status rg_write_report(const char *path, const rg_run *run, vr_error *err);
vr_status rg_save(vr_matdb *db, const char *prefix, const rg_run *run, vr_error *err);

/* CIEDE2000 between two linear camera responses under light l of the run
 * (through XYZ with the light's white). */
double rg_delta_e(const rg_run *run, size_t light, const double a[3], const double b[3]);

/* Per-pixel recovery into a spectral OpenEXR (rgb2spec_pixels.c). */
typedef struct rg_pixels {
  long pixels;
  double clamped_fraction; /* of all spectral samples, clamped into [0, 1] */
  double rgb_rms;          /* RMS of re-rendered minus photo linear responses, after clamping */
  double *mean;            /* mean spectrum over the pixels (n), malloc'ed */
} rg_pixels;
vr_status rg_per_pixel(const rg_run *run, const vr_image *img, const char *path, int threads,
                       rg_pixels *res, vr_error *err);
vr_status rg_save_texture(vr_matdb *db, const char *name, const char *path, const rg_run *run,
                          const rg_pixels *px, vr_error *err);

/* vr-rgb2spec simulate (rgb2spec_simulate.c). */
int rg_cmd_simulate(vr_args *a);

/* vr-rgb2spec calibrate (rgb2spec_calibrate.c): parses its own options;
 * argv[0] is "calibrate". */
int rg_cmd_calibrate(int argc, char **argv);

#endif
