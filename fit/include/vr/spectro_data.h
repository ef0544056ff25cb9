/* Spectrophotometer data of glazing: transmittance T and front and back
 * reflectance Rf, Rb against wavelength, optionally per angle of incidence
 * and per tint state.
 *
 * CSV (the vr_csv rules: any separator, '#' comments): a header line naming
 * the columns, found by name, case-insensitive:
 *   wavelength   "wavelength_nm", "lambda (um)", "nm", ... (unit from the
 *                header: nm, um, A, eV; nm if none)
 *   T            "T", "Tnorm", "transmittance", "%T"; or absorbance "Abs",
 *                "absorbance", "OD" (decadic: T = 10^-A)
 *   Rf           "Rf", "R", "R_front", "reflectance" (optional)
 *   Rb           "Rb", "R_back" (optional)
 *   angle        "angle", "aoi", "theta" in degrees (optional, default 0)
 *   state        "state", "tint", "charge", "voltage", ... (optional):
 *                rows with the same state label form one spectrum
 * A "%" in the T/R headers means percent ("T (%)", "%T", "%R").  A comment
 * line "# thickness: 3.048 mm" (or nm, um) gives the pane's thickness; a
 * value that is not a positive number is refused, naming the line.
 *
 * Spectrophotometer exports (Agilent Cary WinUV, PerkinElmer UV WinLab
 * .csv): title lines (sample names) before the "Wavelength (nm),%T" header
 * are skipped, and so is the metadata block after the first blank line that
 * follows the data.  In column pairs (wavelength, value, wavelength, value,
 * ...) each value goes with the wavelength column on its left; one pane per
 * file (one %T column, and %R on T's wavelengths).
 *
 * LBNL Optics files, known by their content (a first line in braces),
 * whatever the extension (IGDB ".DAT", Optics 5 ".LOF"): "{ Thickness } mm",
 * "{ Units, Wavelength Units } SI Microns|Nanometers", then rows
 * "wavelength T Rf Rb".
 *
 * Checks, each naming file:line and the field: numbers must be finite,
 * 0 <= T, R <= 1, T + R <= 1 + 0.005 (the photometric tolerance LBNL
 * Optics applies), wavelengths strictly increasing inside each (state,
 * angle) spectrum, or strictly decreasing throughout it (then turned
 * round), every spectrum at least VR_SPECTRO_MIN_ROWS rows. */
#ifndef VR_SPECTRO_DATA_H
#define VR_SPECTRO_DATA_H

#include <stdbool.h>
#include <stddef.h>
#include "vr/error.h"
#include "vr/material.h"

#ifdef __cplusplus
extern "C" {
#endif

#define VR_SPECTRO_TR_TOLERANCE 0.005
/* Rows a spectrum needs: fewer cannot say how the pane varies with
 * wavelength (one row would make a flat, grey pane). */
#define VR_SPECTRO_MIN_ROWS 3

typedef struct vr_spectro_point {
  double nm, T, Rf, Rb;      /* Rf, Rb NAN when not measured */
  long line;                 /* in the source file, 0 if none */
} vr_spectro_point;

typedef struct vr_spectro_curve {
  char *state;               /* state label as written, NULL without a state column */
  double angle_deg;
  size_t n;
  vr_spectro_point *p;
} vr_spectro_curve;

/* Which faces carry a coating (the hemispherical-emissivity polynomial of
 * NFRC 301 differs for coated faces; vr/glazing_layers.h). */
typedef enum vr_coated_side {
  VR_COATED_UNKNOWN = 0, VR_COATED_NEITHER, VR_COATED_FRONT, VR_COATED_BACK, VR_COATED_BOTH
} vr_coated_side;

/* Thermal data written beside the spectra, for the heat balance of a
 * glazing (vr/glazing_thermal.h):
 *   CSV comments   "# emissivity: 0.84 0.068" (front back; one value for
 *                  both), "# conductivity: 1.0" (W/(m K)), "# coated side:
 *                  back" (front, back, both, neither), "# ir transmittance:
 *                  0" (of a film or plastic pane; glass: 0);
 *   LBNL Optics    "{ Emissivity, front back } Emis= 0.84 0.84",
 *                  "{ Conductivity } 1", "{ IR Transmittance } TIR=0",
 *                  "{ Coated Side: Back }".
 * NAN / VR_COATED_UNKNOWN when not given. */
typedef struct vr_spectro_thermal {
  double emissivity[2];      /* hemispherical, front and back */
  double conductivity;       /* W/(m K) */
  double tir;                /* thermal-infrared transmittance */
  vr_coated_side coated;
  long line;                 /* of the emissivity, 0 if none */
} vr_spectro_thermal;

typedef struct vr_spectro_data {
  char *source;              /* path */
  double thickness_nm;       /* NAN when the file does not say */
  vr_spectro_thermal thermal;
  bool has_Rf, has_Rb, has_state, has_angle;
  size_t ncurves;            /* in order of first appearance */
  vr_spectro_curve *curves;
} vr_spectro_data;

vr_status vr_spectro_read(const char *path, vr_spectro_data **out, vr_error *err);
/* A pane's thickness (nm) that a glazing tool can stand behind: 0.01-200
 * mm; VR_E_RANGE naming file and line (0: none) otherwise, with the likely
 * unit slip. */
vr_status vr_spectro_pane_plausible(double nm, const char *file, long line, vr_error *err);
vr_status vr_spectro_parse_csv(const char *text, size_t len, const char *name,
                               vr_spectro_data **out, vr_error *err);
/* An LBNL Optics file (IGDB .DAT, Optics 5 .LOF) already in memory. */
vr_status vr_spectro_parse_optics(const char *text, size_t len, const char *name,
                                  vr_spectro_data **out, vr_error *err);
/* From a glazing material (roles T, Rf, Rb; property "thickness" in mm). */
vr_status vr_spectro_from_material(const vr_material *m, vr_spectro_data **out, vr_error *err);
void vr_spectro_destroy(vr_spectro_data *d);

void vr_spectro_thermal_init(vr_spectro_thermal *t);
/* One CSV comment line: an emissivity, conductivity or coated-side line
 * fills t (others are ignored); a malformed value is VR_E_RANGE/VR_E_PARSE
 * naming file, line and field. */
vr_status vr_spectro_thermal_line(const char *comment, const char *file, long line,
                                  vr_spectro_thermal *t, vr_error *err);
/* A material's thermal properties (emissivity_front/back, conductivity,
 * coated_side, as the IGDB importer stores them). */
void vr_spectro_thermal_from_material(const vr_material *m, vr_spectro_thermal *t);
/* "front", "back", "both", "neither"/"none" (case-insensitive). */
vr_status vr_spectro_coated_parse(const char *s, vr_coated_side *out);

/* The curve's column as a spectrum (which: 'T', 'f' front, 'b' back);
 * NULL with VR_E_NOT_FOUND when that column was not measured. */
vr_spectrum *vr_spectro_spectrum(const vr_spectro_curve *c, char which, vr_error *err);

#ifdef __cplusplus
}
#endif
#endif
