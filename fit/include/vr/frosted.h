/* The roughness of frosted glass from angle-resolved scattered
 * transmittance.
 *
 * The sample: a pane of index n whose front face is rough (GGX, roughness
 * alpha) and whose back face is smooth.  Light from direction (theta_i,
 * azimuth 0) is refracted into the glass by the rough face (Walter et al.
 * 2007 BTDF, vr/microfacet.h) and leaves through the smooth face, where
 * Snell's law maps the internal direction t to the outgoing one o
 * (n sin theta_t = sin theta_o, same azimuth) and radiance is multiplied by
 * the Fresnel transmittance T(theta_t) and 1/n².  So the BTDF seen in air is
 *     f(i, o) = s · f_GGX(i, t) · T(theta_t) / n²,
 * s a scale for what the single-scattering model leaves out (absorption,
 * the back face's reflections, the detector's calibration).  alpha and s
 * are fitted by least squares on relative residuals (f_model - f) /
 * (sigma_rel f), n held at the glass's index.
 *
 * Data: CSV with columns theta_i, theta_o (degrees from the normal, the
 * outgoing one on the transmitted side), optional phi_o (degrees, 0 = in the
 * plane of incidence, forward) and btdf (1/sr). */
#ifndef VR_FROSTED_H
#define VR_FROSTED_H

#include <stddef.h>
#include "vr/error.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vr_btdf_sample {
  double theta_i, theta_o, phi_o, f;
  long line;
} vr_btdf_sample;

vr_status vr_btdf_samples_read(const char *path, vr_btdf_sample **out, size_t *count,
                               vr_error *err);

/* The model above at one geometry. */
double vr_frosted_btdf(double alpha, double n, double scale, double theta_i, double theta_o,
                       double phi_o);

typedef struct vr_frosted_fit {
  double alpha, alpha_err, scale, scale_err;
  double rms_rel;       /* RMS of the relative residuals */
} vr_frosted_fit;

/* sigma_rel: the relative noise of the data (e.g. 0.02). */
vr_status vr_frosted_fit_alpha(const vr_btdf_sample *s, size_t count, double n, double sigma_rel,
                               vr_frosted_fit *out, vr_error *err);

#ifdef __cplusplus
}
#endif
#endif
