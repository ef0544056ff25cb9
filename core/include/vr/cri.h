/* Correlated colour temperature and the CIE colour rendering index.
 *
 * CCT: the temperature of the Planckian radiator whose chromaticity is
 * nearest in the CIE 1960 UCS (u, v) diagram (CIE 015:2018 section 9.5),
 * found by minimising that distance over reciprocal temperature; the locus
 * is computed from Planck's law and the CIE 1931 2° observer at 1 nm,
 * 360-830 nm.  Domain: 1000-100000 K; a chromaticity farther than 0.05
 * from the locus has no CCT (CIE 015: the concept loses its meaning well
 * before; 0.05 is the range of the usual tables).
 *
 * Colour rendering: CIE 13.3-1995.  The 14 test colour samples are lit by
 * the test source and by a reference source of the same CCT (a Planckian
 * radiator below 5000 K, CIE daylight from 5000 K up), with sums at 5 nm
 * from 380 to 780 nm under the CIE 1931 2° observer, the source's Y at
 * 100; the test samples are adapted by the von Kries transform of the
 * standard (its c, d coordinates) and compared in CIE 1964 U*V*W*:
 * R_i = 100 - 4.6 dE_i, and Ra is the mean of R_1..R_8.  EN 410 (4.9)
 * takes D65 as the reference of the light D65 transmits through a glazing:
 * vr_cri_against. */
#ifndef VR_CRI_H
#define VR_CRI_H

#include <stdbool.h>
#include "vr/error.h"
#include "vr/spectrum.h"

#ifdef __cplusplus
extern "C" {
#endif

#define VR_CRI_SAMPLES 14

/* CIE 13.3's limit on the distance between the test and reference
 * chromaticities, DC, in the 1960 UCS diagram: beyond it the index is
 * not meaningful (the standard says so; we report, not refuse). */
#define VR_CRI_DC_LIMIT 5.4e-3

typedef struct vr_cri {
  double cct;     /* K, of the test source; NAN from vr_cri_against */
  double dc;      /* distance of test and reference in (u, v), CIE 13.3 DC */
  bool dc_ok;     /* dc < VR_CRI_DC_LIMIT */
  bool planckian; /* the reference was a Planckian radiator (else daylight or given) */
  double R[VR_CRI_SAMPLES]; /* special indices R_1..R_14 */
  double Ra;                /* general index: mean of R_1..R_8 */
} vr_cri;

/* CIE 1960 u, v of tristimulus values (X + 15Y + 3Z > 0). */
void vr_xyz_to_uv1960(const double xyz[3], double uv[2]);

/* CCT of a chromaticity (CIE 1960 u, v) and its signed distance from the
 * Planckian locus (positive above it, towards green).  VR_E_RANGE when the
 * distance exceeds 0.05 or the nearest temperature lies outside
 * 1000-100000 K. */
vr_status vr_cct_from_uv(const double uv[2], double *cct, double *duv, vr_error *err);

/* CIE 13.3 colour rendering of a light source (relative spectral power;
 * it must cover 380-780 nm). */
vr_status vr_cri_compute(const vr_spectrum *source, vr_cri *out, vr_error *err);

/* The same against a given reference source (both must cover 380-780 nm;
 * a source or reference of zero luminance is VR_E_RANGE). */
vr_status vr_cri_against(const vr_spectrum *source, const vr_spectrum *reference, vr_cri *out,
                         vr_error *err);

#ifdef __cplusplus
}
#endif
#endif
