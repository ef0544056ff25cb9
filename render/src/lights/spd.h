/* Light spectra as the renderer holds them: on a 1 nm grid over the
 * sampled range and the UV band, resolved from the references a scene
 * writes (db:NAME, a CIE illuminant, bb:T, an inline table) and scaled to
 * the amount the scene gives, in photometric or radiometric units.
 *
 * Photometric to radiometric: an amount in photometric units Q_v with a
 * relative spectrum S(λ) is Q_e(λ) = Q_v S(λ) / (K_m ∫ V(λ) S(λ) dλ), with
 * K_m = 683.002 lm/W (VR_KM, CIE 015:2018) and V = ȳ of the CIE 1931
 * observer, integrated over 360-830 nm.  A radiometric amount (W, W/sr,
 * W/m², W/(m² sr)) is taken over the renderer's sampled range. */
#ifndef VR_LIGHTS_SPD_H
#define VR_LIGHTS_SPD_H

#include <stdbool.h>

#include "vr/error.h"
#include "vr/scene.h"

struct vr_matdb;

/* A spectrum on the resolved grid: value at lo + i nm, i = 0 .. n-1. */
typedef struct vr_rspd {
  double lo;
  int n;
  double *v;
} vr_rspd;

/* Linear between grid points, the end values held outside; 0 when empty. */
double vr_rspd_at(const vr_rspd *s, double nm);
void vr_rspd_free(vr_rspd *s);
/* The trapezoidal integral over [lo, hi] in 1 nm steps. */
double vr_rspd_integral(const vr_rspd *s, double lo, double hi);

/* Where spectra are resolved: the scene file (for messages), the database
 * (may be NULL) and the sampled range. */
typedef struct vr_spd_setup {
  const char *path;
  struct vr_matdb *db;
  double lmin, lmax;
} vr_spd_setup;

/* The relative spectrum named by ref (NULL: dflt) on the grid that covers
 * the UV band and the sampled range; zero outside the data. */
vr_status vr_spd_resolve(const vr_spd_setup *u, const char *ref, const char *dflt,
                         const vr_scene_loc *loc, vr_rspd *out, vr_error *err);
/* Scales s so that it carries the amount q (photometric or radiometric per
 * unit); `what` names the element in messages. */
vr_status vr_spd_normalise(const vr_spd_setup *u, vr_rspd *s, vr_quantity q, bool photometric,
                           const vr_scene_loc *loc, const char *what, vr_error *err);
bool vr_unit_is_photometric(vr_light_unit u);

#endif
