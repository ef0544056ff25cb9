/* BSDF XML, the file of LBNL WINDOW, the IGSDB, genBSDF and Radiance's
 * BSDF material (schema BSDF-v1.x of windows.lbl.gov), in its Klems form:
 * for each band (Visible, Solar, or one wavelength) and each of the four
 * sides (transmission and reflection, front and back), a square matrix of
 * BSDF values (1/sr) between the patches of an angle basis.
 *
 * The basis.  Rings of polar angle [theta_lo, theta_hi] (degrees from the
 * surface normal, on each side's own hemisphere), each cut into nphi equal
 * azimuth patches centred on phi = k 360/nphi.  Patch index runs ring by
 * ring from the normal outward, azimuth within a ring.  A patch's projected
 * solid angle is
 *     Lambda = pi (sin^2 theta_hi - sin^2 theta_lo) / nphi,
 * and the patches of a hemisphere sum to pi.  The Klems full basis has 145
 * patches in 9 rings (LBNL/Klems Full); files define their basis inline and
 * any ring structure that covers 0 to 90 degrees is read.
 *
 * Indexing.  Matrices are held as m[out * n + in] (out = exiting patch, in
 * = incident patch), the file's "Columns" layout (IncidentDataStructure:
 * each column one incident direction, so the text runs exiting row by
 * row); "Rows" files are transposed on reading.  An incident patch i
 * continues straight through (transmission) or mirrors (reflection) into
 * exiting patch i: the diagonal holds the specular part.
 *
 * Figures, as LBNL WINDOW and Windows-CalcEngine define them for one
 * incident patch i:
 *     direct-direct        m[i][i] Lambda_i
 *     direct-hemispherical sum_o m[o][i] Lambda_o
 *     direct-diffuse       the difference
 *     diffuse-diffuse      (1/pi) sum_i sum_o m[o][i] Lambda_o Lambda_i
 * (checked against WinCalc's published results for real files, tests/
 * matdb/test_bsdf_xml.c).
 *
 * Tensor-tree files (genBSDF's and Radiance's variable-resolution form:
 * AngleBasis LBNL/Shirley-Chiu, IncidentDataStructure TensorTree3 or
 * TensorTree4) are read and resampled onto the Klems full basis, each
 * matrix entry the tree's mean over the pair of patches (as Radiance's
 * bsdf2klems does; matdb/src/bsdf_xml_tree.h), so that they serve as a
 * Klems file would, at its resolution; a file's missing transmission
 * block is the other one read backwards, as Radiance reads it. */
#ifndef VR_BSDF_XML_H
#define VR_BSDF_XML_H

#include <stdbool.h>
#include <stddef.h>
#include "vr/error.h"

#ifdef __cplusplus
extern "C" {
#endif

#define VR_KLEMS_MAX_RINGS 32
#define VR_KLEMS_MAX_PATCHES 1024

typedef struct vr_klems_basis {
  char name[64];
  int nrings;
  double theta_lo[VR_KLEMS_MAX_RINGS], theta_hi[VR_KLEMS_MAX_RINGS]; /* degrees */
  double theta_c[VR_KLEMS_MAX_RINGS];  /* the ring's nominal direction */
  int nphi[VR_KLEMS_MAX_RINGS];
  int first[VR_KLEMS_MAX_RINGS];       /* index of the ring's first patch */
  int n;                               /* patches */
} vr_klems_basis;

/* LBNL/Klems Full: 145 patches (WINDOW's and Radiance's definition). */
void vr_klems_full(vr_klems_basis *b);
/* LBNL/Klems Full, Half (77 patches) or Quarter (41) by name (any case);
 * false for another name. */
bool vr_klems_named(const char *name, vr_klems_basis *b);
/* Checks a basis read from a file (rings contiguous from 0 to 90 degrees,
 * nphi >= 1, at most VR_KLEMS_MAX_RINGS rings and VR_KLEMS_MAX_PATCHES
 * patches) and fills first[] and n. */
vr_status vr_klems_finish(vr_klems_basis *b, vr_error *err);
/* Projected solid angle of a patch (sr). */
double vr_klems_lambda(const vr_klems_basis *b, int patch);
/* The patch holding direction (theta, phi) in degrees: theta in [0, 90]
 * (a ring holds (theta_lo, theta_hi], the first ring also 0), phi any
 * value (taken modulo 360).  -1 when theta is outside [0, 90]. */
int vr_klems_patch(const vr_klems_basis *b, double theta_deg, double phi_deg);
/* A patch's nominal direction (ring's theta, azimuth centre), degrees. */
void vr_klems_direction(const vr_klems_basis *b, int patch, double *theta_deg, double *phi_deg);

typedef struct vr_klems_figures {
  double direct_direct, direct_diffuse, direct_hemispherical, diffuse_diffuse;
} vr_klems_figures;

/* The figures above for incident patch `in` of the matrix m (n x n). */
void vr_klems_figures_of(const vr_klems_basis *b, const double *m, int in, vr_klems_figures *f);

typedef enum vr_bsdf_side {
  VR_BSDF_TF = 0, /* transmission, light incident on the front */
  VR_BSDF_TB,     /* transmission, light incident on the back */
  VR_BSDF_RF,     /* reflection on the front */
  VR_BSDF_RB,     /* reflection on the back */
  VR_BSDF_SIDES
} vr_bsdf_side;

/* "Transmission Front", ... as the files write them. */
const char *vr_bsdf_side_name(vr_bsdf_side s);

typedef struct vr_bsdf_band {
  char name[64];  /* "Visible", "Solar", "NIR", ... or the wavelength as written */
  double nm;      /* a spectral band's wavelength (nm), else NAN */
  char detector[64]; /* DetectorSpectrum when given ("ASTM E308 1931 Y.dsp"), else "" */
  double *m[VR_BSDF_SIDES]; /* m[out * n + in], 1/sr; NULL where the file has no such block */
} vr_bsdf_band;

typedef struct vr_bsdf_xml {
  vr_klems_basis basis;
  size_t nbands;
  vr_bsdf_band *bands;
  char name[128], manufacturer[128], device_type[64];
  double thickness_mm; /* NAN when not given */
  int tensor_tree;     /* 3 or 4: read from a TensorTree3 or 4 file and resampled onto the
                          Klems full basis; 0: the file's own Klems matrices */
} vr_bsdf_xml;

/* Reads a Klems BSDF XML file (gzip-compressed files too).  Refused, with
 * the file, line and element: malformed XML, a missing or inconsistent
 * basis, a block whose ScatteringData does not hold n x n finite,
 * non-negative numbers, an unknown direction or data type, a block given
 * twice, different incident and exiting bases, a tensor tree that is not one
 * (unbalanced braces, a leaf whose count is not 2^(d k), negative values). */
vr_status vr_bsdf_xml_read(const char *path, vr_bsdf_xml **out, vr_error *err);
/* The same from text in memory (name: what messages call it). */
vr_status vr_bsdf_xml_parse(const char *text, size_t size, const char *name, vr_bsdf_xml **out,
                            vr_error *err);
/* An empty description on basis b with nbands bands (names set by the
 * caller, matrices allocated zeroed on all four sides). */
vr_status vr_bsdf_xml_create(const vr_klems_basis *b, size_t nbands, vr_bsdf_xml **out,
                             vr_error *err);
/* Writes a WINDOW-style file (namespace windows.lbl.gov, Columns, BTDF for
 * transmission and BRDF for reflection), whole or not at all; sides whose
 * matrix is NULL are left out. */
vr_status vr_bsdf_xml_write(const char *path, const vr_bsdf_xml *x, vr_error *err);
void vr_bsdf_xml_destroy(vr_bsdf_xml *x);
/* The band named `name` (case-insensitive), or NULL. */
const vr_bsdf_band *vr_bsdf_xml_band(const vr_bsdf_xml *x, const char *name);

#ifdef __cplusplus
}
#endif
#endif
