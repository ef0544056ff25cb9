/* The optical model of an ellipsometry sample: ambient | layers | substrate,
 * each layer a dispersion model (or an effective-medium mixture of two) with
 * a thickness, the substrate optionally a thick incoherent slab whose back
 * face reflects; and the list of parameters a fit may adjust, with bounds.
 *
 * Model files are text, one statement per line ('#' comments):
 *
 *   ambient   MATERIAL
 *   layer     NAME MATERIAL thickness=NM [fit] [per-sample] [min=V] [max=V]
 *   layer     NAME ema=bruggeman|maxwell-garnett(A,B) fraction=F [fit] thickness=NM ...
 *   substrate MATERIAL [thickness=MM backside]
 *   param     NAME.PARAMETER = VALUE [fit] [per-sample] [min=V] [max=V]
 *   param     NAME.PARAMETER = COEF*OTHER.PARAMETER + OFFSET     (coupling)
 *
 * The measurement's own parameters are named sample.aoi_offset,
 * sample.delta_offset, sample.thickness_nonuniformity (percent) and
 * sample.bandwidth (nm).  "per-sample" marks a fitted parameter that takes
 * its own value in each data file of a multi-sample fit.
 *
 * MATERIAL is a dispersion model with its parameters at their defaults
 * (constant, cauchy, sellmeier:N, sellmeier2:N, genosc:TERM+TERM+...
 * with TERMs lorentz, drude, tauc_lorentz, cody_lorentz, gaussian,
 * bspline:E1,E2,...,En), or tabulated data: db:NAME (material database),
 * file:PATH (refractiveindex.info YAML, relative to the model file).  The
 * ambient and substrate are named "ambient" and "substrate" in param lines;
 * A and B of an EMA name earlier layers, or "void" (n = 1).  Layers are
 * listed from the ambient down.  docs/vr-ellipso.md has examples. */
#ifndef VR_ELLIPSO_MODEL_H
#define VR_ELLIPSO_MODEL_H

#include <stdbool.h>
#include <stddef.h>
#include "vr/dispersion.h"
#include "vr/error.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vr_matdb vr_matdb;

typedef enum vr_ema_kind { VR_EMA_NONE = 0, VR_EMA_BRUGGEMAN, VR_EMA_MAXWELL_GARNETT } vr_ema_kind;

/* Last value of a parameter-free (tabulated) dispersion: consecutive points
 * of a data set share a wavelength across angles, and interpolating the
 * table is the costly part of such a layer. */
typedef struct vr_eps_memo {
  double nm;
  vr_complex eps;
} vr_eps_memo;

typedef struct vr_model_layer {
  char *name;
  vr_eps_memo memo;
  vr_dispersion *disp;       /* NULL for an EMA layer */
  vr_ema_kind ema;
  long ema_a, ema_b;         /* layer indices, -1 = void */
  double fraction;           /* of component B, 0..1 */
  double thickness_nm;
} vr_model_layer;

/* Where a parameter lives: owner is a layer index, VR_OWNER_SUBSTRATE,
 * VR_OWNER_AMBIENT or VR_OWNER_SAMPLE (the measurement: "sample.aoi_offset"
 * and "sample.delta_offset"); slot is a dispersion parameter index, or
 * VR_SLOT_THICKNESS / VR_SLOT_FRACTION / VR_SLOT_AOI_OFFSET /
 * VR_SLOT_DELTA_OFFSET. */
enum { VR_OWNER_SUBSTRATE = -1, VR_OWNER_AMBIENT = -2, VR_OWNER_SAMPLE = -3 };
enum {
  VR_SLOT_THICKNESS = -1,
  VR_SLOT_FRACTION = -2,
  VR_SLOT_AOI_OFFSET = -3,
  VR_SLOT_DELTA_OFFSET = -4,
  VR_SLOT_NONUNIFORMITY = -5,
  VR_SLOT_BANDWIDTH = -6
};

typedef struct vr_model_param {
  char *name;                /* "oxide.thickness", "oxide.A", ... */
  long owner, slot;
  double lower, upper;
  bool free;
  long line;                 /* model-file line that set it, 0 if default */
  /* Coupling ("param film2.A = 2*film1.A + 0.1"): 1 + the index of the
   * parameter this one follows, 0 if none; value = coef * that + offset. */
  long coupled_to;
  double coef, offset;
  /* Multi-sample fits: a free parameter marked "per-sample" takes its own
   * value for every data file; the others are shared by all of them. */
  bool per_sample;
} vr_model_param;

/* A model is used by one thread at a time (it keeps small caches). */
typedef struct vr_sample_model {
  vr_dispersion *ambient;
  vr_eps_memo ambient_memo, substrate_memo;
  size_t nlayers;
  vr_model_layer *layers;
  vr_dispersion *substrate;
  double substrate_thickness_nm; /* > 0 with backside: incoherent slab */
  /* The instrument's errors (degrees): the true angle of incidence is the
   * nominal one + aoi_offset, and the measured Δ is the sample's +
   * delta_offset (a retarder or window offset).  0 unless fitted or set. */
  double aoi_offset_deg, delta_offset_deg;
  /* Thickness non-uniformity over the light spot: every layer thickness
   * scaled by 1 + u, u uniform over [-w/2, +w/2], w = this / 100 (percent
   * full width).  The detected intensities add over u (vr_model_measure). */
  double nonuniformity_pct;
  /* The instrument's spectral bandwidth: full width at half maximum (nm) of
   * a triangular slit function, over which intensities add.  Used when
   * bandwidth_set (a "param sample.bandwidth" line); otherwise each data
   * point's own bandwidth is used when its file gives one, else none. */
  double bandwidth_nm;
  bool bandwidth_set;
  bool backside;
  size_t nparams;
  vr_model_param *params;
  char *source;
} vr_sample_model;

/* Parses a model file.  db may be NULL (then db: materials are an error). */
vr_status vr_model_read(const char *path, vr_matdb *db, vr_sample_model **out, vr_error *err);
vr_status vr_model_parse(const char *text, size_t len, const char *name, const char *base_dir,
                         vr_matdb *db, vr_sample_model **out, vr_error *err);
/* A bulk sample: ambient n = 1 over the given substrate dispersion (taken). */
vr_sample_model *vr_model_bulk(vr_dispersion *substrate, vr_error *err);
void vr_model_destroy(vr_sample_model *m);
vr_sample_model *vr_model_copy(const vr_sample_model *m, vr_error *err);

/* Index of a parameter by name, or -1. */
long vr_model_param_index(const vr_sample_model *m, const char *name);
/* The storage of parameter i inside the model (valid until the model is
 * destroyed). */
double *vr_model_param_value(vr_sample_model *m, size_t i);
double vr_model_param_get(const vr_sample_model *m, size_t i);
/* Checks every free parameter's value against its bounds and the model's
 * domain (thickness >= 0, 0 <= fraction <= 1). */
vr_status vr_model_check(const vr_sample_model *m, vr_error *err);

/* Sets every coupled parameter from the one it follows; VR_E_RANGE if that
 * makes a thickness negative or a fraction leave [0, 1].  Model evaluation
 * calls it. */
vr_status vr_model_apply_couplings(vr_sample_model *m, vr_error *err);

/* What an ellipsometer reports at one point.  Ψ, Δ in degrees (Woollam's
 * convention: tan Ψ = sqrt(I_pp / I_ss), Δ = -arg of the p-s cross term);
 * the normalised Stokes-like values N = cos 2Ψ, C, S with
 * C² + S² = (1 - depol)² - N²; depolarisation as Woollam's instruments
 * report it, 1 - sqrt(N² + C² + S²), in 0..1. */
typedef struct vr_model_response {
  double psi, delta;
  double N, C, S;
  double depolarisation;
} vr_model_response;

/* The response at a wavelength and angle: the coherent stack, plus the
 * incoherent beams of a reflecting back side, averaged in intensity over
 * the thickness non-uniformity and the spectral bandwidth (the model's
 * sample.bandwidth when set, else bandwidth_nm: the data point's, 0 or NAN
 * for none).  Averages are composite Gauss-Legendre sums, 8 nodes per
 * panel of at most π/2 of interference phase (ellipso_response.c). */
vr_status vr_model_measure(const vr_sample_model *m, double nm, double aoi_deg, double bandwidth_nm,
                           vr_model_response *r, vr_error *err);

/* Ψ and Δ (degrees) and depolarisation (0..1; may be NULL) of
 * vr_model_measure with no bandwidth beyond the model's own. */
vr_status vr_model_psi_delta(const vr_sample_model *m, double nm, double aoi_deg, double *psi,
                             double *delta, double *depolarisation, vr_error *err);
/* n, k of layer i (or of the substrate with i = -1) at a wavelength. */
vr_status vr_model_layer_index(const vr_sample_model *m, long i, double nm, vr_complex *N,
                               vr_error *err);

#ifdef __cplusplus
}
#endif
#endif
