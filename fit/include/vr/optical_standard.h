/* Optical standards for glazing: how a spectral transmittance or reflectance
 * becomes one figure (visible, solar, UV), in the file format of LBNL's
 * Optics/WINDOW/Windows-CalcEngine ("*.std" naming a source spectrum, a
 * detector spectrum, a wavelength set, an integration rule and a range per
 * method; "*.ssp", "*.dsp" and "*.wvl" files holding the tables).
 *
 * A figure is the weighted mean
 *      P = sum_w  data(l) S(l) D(l)  /  sum_w  S(l) D(l)
 * over the method's wavelength set, restricted to [min, max], where S is the
 * source, D the detector (1 when "None"), data, S and D are interpolated
 * linearly onto the set, and sum_w is the integration rule:
 *   Trapezoidal   each interval [l_i, l_i+1] of the set inside the range
 *                 contributes (f_i + f_i+1)/2 (l_i+1 - l_i);
 *   Rectangular   each point l_i inside the range contributes f_i times the
 *                 width of its interval (l_i+1 - l_i; the last point the
 *                 previous width).
 *   Pre-weighted  each point contributes f_i alone: the tables of EN 410
 *                 and ISO 9050 already hold S D dl, so
 *                 P = sum data(l_i) w_i / sum w_i exactly as those
 *                 standards write it.
 * Data outside its own grid hold their end values (a sample measured from
 * 300 to 2500 nm under a source set reaching further only matters where the
 * range does).
 *
 * Standards are found by name: the built-in ones ("nfrc" = W5_NFRC_2003.std,
 * "en410" = prEN_410.std (the EN 410 tables: D65 V dl, the CIE 85 air
 * mass 1.0 global solar table, the UV table), "iso9050" = ISO_9050.std (the
 * 1990 edition's tables as LBNL ships them); list with
 * vr_standard_builtin_names) ship inside the
 * library with their sources named in their description lines, or a path to
 * an .std file whose tables sit next to it.  docs/vr-spectro.md lists them. */
#ifndef VR_OPTICAL_STANDARD_H
#define VR_OPTICAL_STANDARD_H

#include <stdbool.h>
#include <stddef.h>
#include "vr/error.h"
#include "vr/spectrum.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum vr_wlset { VR_WLSET_SOURCE, VR_WLSET_DATA, VR_WLSET_DETECTOR, VR_WLSET_LIST } vr_wlset;
typedef enum vr_integration { VR_INTEG_TRAPEZOIDAL, VR_INTEG_RECTANGULAR, VR_INTEG_PREWEIGHTED } vr_integration;

typedef struct vr_std_method {
  char *name;          /* "SOLAR", "PHOTOPIC", "TUV", "COLOR_TRISTIMX", ... */
  char *description;
  vr_spectrum *source; /* NULL: flat (None) or blackbody */
  double blackbody_K;  /* > 0: Planck source at this temperature */
  vr_spectrum *detector; /* NULL: none (or the UV action below) */
  bool uv_action;      /* detector exp(a - b l[um]), CIE 89/3 damage weighting */
  double uv_a, uv_b;
  vr_wlset wlset;
  size_t nlist;        /* VR_WLSET_LIST: the listed wavelengths, nm */
  double *list_nm;
  vr_integration rule;
  double norm_k;       /* "(Normalized, k=..)": colour methods, else 0 */
  double min_nm, max_nm; /* max_nm = INFINITY: "Wavelength set" */
  char *unsupported;   /* non-NULL: why this method cannot be evaluated */
} vr_std_method;

typedef struct vr_standard {
  char *name;          /* built-in name or path */
  char *description;
  size_t count;
  vr_std_method *methods;
} vr_standard;

/* "nfrc", "en410", "iso9050", ... or a path.  Errors name the file and line
 * (an unknown key, a missing table file, a malformed number). */
vr_status vr_standard_open(const char *name_or_path, vr_standard **out, vr_error *err);
void vr_standard_destroy(vr_standard *s);
/* Space-separated names of the built-in standards. */
const char *vr_standard_builtin_names(void);

/* The method of that name (case-insensitive), or NULL. */
const vr_std_method *vr_standard_method(const vr_standard *s, const char *name);

/* Share of a method's weight (source x detector over its range) that data
 * must cover: beyond it, the nearest measured value would stand in for a
 * real measurement.  1 %: IGDB files start at 300 nm, and a measurement
 * from 310 nm leaves 0.02 % of the NFRC solar weight uncovered; one that
 * stops at 900 nm leaves 45 %. */
#define VR_STD_MAX_UNCOVERED 0.01

/* Weighted mean of data under the method (see the top).  VR_E_RANGE when the
 * data leave more than VR_STD_MAX_UNCOVERED of the method's weight
 * unmeasured (the message gives the share) or the weights sum to 0;
 * VR_E_ARG for an unsupported method. */
vr_status vr_std_average(const vr_std_method *m, const vr_spectrum *data, double *out,
                         vr_error *err);
/* The two sums themselves: num = sum_w data S D (data NULL: 1) and den =
 * sum_w S D, for colour (X = k num_X / den_Y).  data must still be given for
 * VR_WLSET_DATA methods; given data must cover the method as for
 * vr_std_average. */
vr_status vr_std_sums(const vr_std_method *m, const vr_spectrum *data, double *num, double *den,
                      vr_error *err);

#ifdef __cplusplus
}
#endif
#endif
