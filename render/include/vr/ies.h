/* Goniometric lights: IES LM-63 photometric data files (LM-63-1986, -1991,
 * -1995 and -2002 layouts), photometric type C, TILT=NONE.
 *
 * File layout (ANSI/IESNA LM-63-2002 section 5): an optional "IESNA:..."
 * version line, keyword or free text lines, "TILT=NONE", then numbers
 * separated by blanks, commas or line breaks:
 *   lamps, lumens per lamp (-1: absolute photometry), candela multiplier,
 *   vertical angle count, horizontal angle count, photometric type
 *   (1 = C, 2 = B, 3 = A), units (1 feet, 2 metres), width, length, height,
 *   ballast factor, ballast-lamp photometric factor (LM-63-2002: "future
 *   use", 1), input watts,
 *   the vertical angles, the horizontal angles, and the candela values,
 *   one block of vertical values per horizontal angle.
 * The stored candela values are multiplied by candela multiplier x ballast
 * factor x ballast-lamp factor, as Radiance's ies2rad does.
 *
 * Type C angles, in the luminaire's own frame used here: z up, vertical
 * angle 0 at nadir (-z) and 180 at zenith (+z); horizontal angle 0 along +x
 * (the luminaire's length axis), 90 along +y, counter-clockwise seen from
 * above.  Horizontal angle sets and the symmetry they imply (LM-63-2002
 * section 5.10): a single 0 (rotational symmetry), 0..90 (symmetric in each
 * quadrant), 0..180 (symmetric about the 0-180 plane), 90..270 (symmetric
 * about the 90-270 plane), 0..360 (none).  Vertical sets start at 0 or 90
 * and end at 90 or 180; outside them the intensity is 0.
 *
 * Candela between the measured angles is bilinear in (horizontal, vertical)
 * angle.  A vr_ies is plain data: reading it from many threads is safe. */
#ifndef VR_IES_H
#define VR_IES_H

#include <stddef.h>
#include "vr/error.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum vr_ies_symmetry {
  VR_IES_ROTATIONAL = 0, /* one horizontal angle */
  VR_IES_QUADRANT,       /* 0..90 */
  VR_IES_BILATERAL,      /* 0..180 */
  VR_IES_BILATERAL_90,   /* 90..270 */
  VR_IES_NONE            /* 0..360 */
} vr_ies_symmetry;

typedef struct vr_ies {
  char version[32];          /* "LM-63-2002", "LM-63-1995", "LM-63-1991" or "LM-63-1986" */
  int lamps;
  double lumens_per_lamp;    /* -1: absolute photometry */
  double multiplier;         /* candela multiplier x ballast factor x ballast-lamp factor */
  int photometric_type;      /* 1 (type C) */
  double width_m, length_m, height_m; /* luminous opening, metres (negative: round, LM-63) */
  double input_watts;
  vr_ies_symmetry symmetry;
  size_t nv, nh;             /* vertical and horizontal angle counts */
  double *v_deg;             /* nv increasing vertical angles */
  double *h_deg;             /* nh increasing horizontal angles */
  double *cd;                /* nh x nv candela, row h: cd[h * nv + v], multiplier applied */
} vr_ies;

/* Reads a file; errors "path:line: message" (VR_E_PARSE), VR_E_IO when it
 * cannot be read.  Files over 16 MiB are refused. */
vr_status vr_ies_read(const char *path, vr_ies **out, vr_error *err);
/* The same from text in memory; name is used in messages. */
vr_status vr_ies_parse(const char *text, size_t len, const char *name, vr_ies **out,
                       vr_error *err);
void vr_ies_destroy(vr_ies *ies);

/* Candela at a vertical and horizontal angle (degrees; any horizontal angle,
 * folded by the file's symmetry). */
double vr_ies_candela(const vr_ies *ies, double vertical_deg, double horizontal_deg);
/* Candela towards a direction in the luminaire's frame (need not be unit). */
double vr_ies_candela_dir(const vr_ies *ies, const double dir[3]);
/* Largest candela value of the file. */
double vr_ies_max_candela(const vr_ies *ies);
/* Total luminous flux, lm: the integral of the bilinear candela over the
 * sphere, exact for that interpolant (each cell in closed form). */
double vr_ies_lumens(const vr_ies *ies);

#ifdef __cplusplus
}
#endif
#endif
