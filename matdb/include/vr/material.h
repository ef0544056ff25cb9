/* A material as the tools exchange it: what it is (kind), how its optical
 * data are given (a dispersion formula and/or tabulated spectra), named
 * properties (thickness, emissivity, ...), fitted parameters with their
 * uncertainties, and where it all came from (provenance).
 *
 * The struct is plain data owned by whoever created it; vr_material_destroy
 * frees it and everything it points to.  The material database (matdb.h)
 * stores and loads exactly this. */
#ifndef VR_MATERIAL_H
#define VR_MATERIAL_H

#include <stdbool.h>
#include <stddef.h>
#include "vr/error.h"
#include "vr/spectrum.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum vr_material_kind {
  VR_KIND_DIELECTRIC = 0, /* n, k from a formula or tables (glass, films, Si) */
  VR_KIND_CONDUCTOR,      /* n, k tables of a metal */
  VR_KIND_LAYERED,        /* coating stack on a substrate */
  VR_KIND_REFLECTANCE,    /* diffuse reflectance spectrum (role "value") */
  VR_KIND_BTDF,           /* angle x wavelength table */
  VR_KIND_CHROMOGENIC,    /* spectra per tint state plus kinetics */
  VR_KIND_ILLUMINANT,     /* spectral power distribution (role "value") */
  VR_KIND_CAMERA,         /* camera sensitivities (roles "r", "g", "b") */
  VR_KIND_GLAZING,        /* a measured pane at normal incidence: roles "T", "Rf", "Rb" */
  VR_KIND_COUNT
} vr_material_kind;

const char *vr_kind_name(vr_material_kind kind);           /* "dielectric", ... */
vr_status vr_kind_parse(const char *text, vr_material_kind *kind, vr_error *err);

/* A refractiveindex.info dispersion formula (types 1-9 of "Dispersion
 * formulas", refractiveindex.info database documentation), in micrometres
 * as published, valid on [min_nm, max_nm].  type 0 means "no formula". */
#define VR_FORMULA_MAX_COEFFS 17
typedef struct vr_formula {
  int type;
  size_t ncoeffs;
  double c[VR_FORMULA_MAX_COEFFS];
  double min_nm, max_nm;
} vr_formula;

/* n of a formula at a wavelength in nm (no range check here). */
vr_status vr_formula_eval(const vr_formula *f, double nm, double *n, vr_error *err);

/* A tabulated spectrum with a role: "n", "k", "value", "T", "Rf", "Rb", ... */
typedef struct vr_role_spectrum {
  char *role;
  vr_spectrum *s;
} vr_role_spectrum;

/* A named property: text, a number with a unit, or both. */
typedef struct vr_property {
  char *key;
  char *text;     /* NULL if purely numeric */
  double value;   /* NAN if purely text */
  char *unit;     /* NULL if none */
} vr_property;

/* A fitted parameter with its standard error (NAN when unknown). */
typedef struct vr_parameter {
  char *name;
  double value, stderr_;
  char *unit;
} vr_parameter;

typedef struct vr_provenance {
  char *source_path;   /* file the data came from, or "built-in:..." */
  char sha256[65];     /* of that file's bytes, hex (several files: of their hex digests in order); "" if none */
  char *tool;          /* "vr-matdb import", "vr-ellipso fit", ... */
  char *tool_version;
  char *model;         /* "rii formula 2 + tabulated k", "Cauchy", ... */
  char *reference;     /* published source, as text */
  char *note;
  double residual;     /* fit residual, NAN if not a fit */
  char created_at[32]; /* ISO 8601 UTC, set when saved */
} vr_provenance;

typedef struct vr_material {
  char *name;
  int version;                 /* set by the database; 0 before saving */
  vr_material_kind kind;
  char *description;
  vr_formula n_formula;        /* type 0 when n is tabulated or absent */
  size_t nspectra;
  vr_role_spectrum *spectra;
  size_t nprops;
  vr_property *props;
  size_t nparams;
  vr_parameter *params;
  vr_provenance prov;
} vr_material;

vr_material *vr_material_create(const char *name, vr_material_kind kind, vr_error *err);
void vr_material_destroy(vr_material *m);

/* Builders: each copies its arguments; the spectrum is taken over (owned). */
vr_status vr_material_set_text(char **field, const char *text, vr_error *err);
vr_status vr_material_add_spectrum(vr_material *m, const char *role, vr_spectrum *s, vr_error *err);
vr_status vr_material_add_property(vr_material *m, const char *key, const char *text, double value,
                                   const char *unit, vr_error *err);
vr_status vr_material_add_parameter(vr_material *m, const char *name, double value, double stderr_,
                                    const char *unit, vr_error *err);

const vr_spectrum *vr_material_spectrum(const vr_material *m, const char *role);
const vr_property *vr_material_property(const vr_material *m, const char *key);

/* Wavelength range over which n and k are both defined. */
vr_status vr_material_nk_range(const vr_material *m, double *min_nm, double *max_nm,
                               vr_error *err);
/* n and k at nm.  Outside the stated range this is VR_E_RANGE (naming the
 * material, the wavelength and the range) unless allow_extrapolation, in
 * which case the end values are held and *extrapolated (if not NULL) is set.
 * A material with n but no k has k = 0 over n's range. */
vr_status vr_material_nk(const vr_material *m, double nm, bool allow_extrapolation, double *n,
                         double *k, bool *extrapolated, vr_error *err);
/* Value of a tabulated role (linear interpolation), same range rules. */
vr_status vr_material_eval(const vr_material *m, const char *role, double nm,
                           bool allow_extrapolation, double *value, bool *extrapolated,
                           vr_error *err);

#ifdef __cplusplus
}
#endif
#endif
