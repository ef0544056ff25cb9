/* Tensor-tree BSDF data (IncidentDataStructure TensorTree3 or TensorTree4,
 * AngleBasis LBNL/Shirley-Chiu: genBSDF's and Radiance's variable
 * resolution form) and their resampling onto a Klems basis.  Private to
 * matdb/ (bsdf_xml_read.c).
 *
 * The data.  A ScatteringData text is a tree over the unit hypercube of
 * nd = 3 or 4 dimensions: "{" then either 2^nd subtrees (a branch, child
 * k the half-cube whose coordinate i is in the upper half where bit i of
 * k is set) or 2^(nd lg) values (a leaf grid of 2^lg cells a side,
 * coordinate 0 the slowest), then "}"; values are separated by blanks or
 * commas.  TensorTree4's coordinates are the incident and the exiting
 * directions, each a point of the unit disk (x, y of the unit vector)
 * taken to the unit square by Shirley and Chiu's concentric map ("A
 * Low Distortion Map Between Disk and Square", JGT 2(3), 1997);
 * TensorTree3 (an isotropic layer) keeps of the incident direction only
 * 1/2 - sin(theta)/2 and gives the exiting one relative to the incident
 * azimuth.  The vector conventions (which side each direction lies on,
 * the incident one negated in the plane) are Radiance's (bsdf_t.c), as
 * are the four blocks' sides, front and back reversed from WINDOW's.
 *
 * The resampling.  A Klems matrix entry is the mean of the tree over the
 * pair of patches, uniformly in projected solid angle on both (what
 * Radiance's bsdf2klems estimates with random samples a pair; here Halton
 * incident directions in each patch, each with a stratified grid over the
 * whole exiting hemisphere), so the result reads as a Klems file would. */
#ifndef VR_BSDF_XML_TREE_H
#define VR_BSDF_XML_TREE_H

#include <stddef.h>
#include <stdint.h>

#include "vr/bsdf_xml.h"

typedef struct vr_tt_tree vr_tt_tree;

/* Parses text (a ScatteringData element's content) as a tree of nd
 * dimensions.  NULL on failure with msg (cap bytes) saying why and *line
 * the line within text (1-based) where. */
vr_tt_tree *vr_tt_parse(const char *text, int nd, char *msg, size_t cap, long *line);
void vr_tt_destroy(vr_tt_tree *t);

/* The tree's value at a point of the unit hypercube (no interpolation). */
double vr_tt_lookup(const vr_tt_tree *t, const double *pos);

/* Radiance's sides of a tree (its front and back are WINDOW's back and
 * front: a block labelled "Transmission Front" is VR_TT_BXMIT). */
enum { VR_TT_FREFL, VR_TT_BREFL, VR_TT_FXMIT, VR_TT_BXMIT };

/* The tree's BSDF (1/sr) for light arriving from in (a unit vector towards
 * where it comes from) and leaving along out, in the layer's frame (z the
 * normal of Radiance's front), for a tree of Radiance's side `side`
 * (read backwards when the pair is the other transmission's, as Radiance
 * does); 0 when the pair is on neither of the side's hemispheres. */
double vr_tt_query(const vr_tt_tree *t, int side, const double in[3], const double out[3]);

/* Fills the n x n Klems matrices m[side] (m[out * n + in], allocated by
 * the caller) of the sides whose tree is given (trees[side] non-NULL):
 * a side without its tree stays untouched, except that a missing
 * transmission is the other transmission's tree read backwards (as
 * Radiance reads such a file).  samples: incident directions a patch,
 * each with a 16 x 16 grid of the exiting hemisphere.  -1: out of memory. */
int vr_tt_to_klems(vr_tt_tree *const trees[VR_BSDF_SIDES], const vr_klems_basis *b, int samples,
                   double *m[VR_BSDF_SIDES]);

/* Shirley and Chiu's concentric map from the unit disk to [0, 1]^2. */
void vr_tt_disk_to_square(double x, double y, double sq[2]);

#endif
