/* The CIE standard observers and tristimulus integration.
 *
 * Data: CIE 1931 2° and CIE 1964 10° colour-matching functions at 1 nm,
 * 360-830 nm (CIE 018:2019 / ISO 11664-1), embedded from core/data. */
#include "vr/colour.h"
#include "embedded.h"

#include <math.h>
#include <string.h>
#include <strings.h>

const double *vr_cmf_table(vr_observer obs, size_t *rows) {
  if (obs == VR_CIE1964_10DEG) {
    if (rows) *rows = vr_data_cie1964_10deg_rows;
    return vr_data_cie1964_10deg;
  }
  if (rows) *rows = vr_data_cie1931_2deg_rows;
  return vr_data_cie1931_2deg;
}

void vr_cmf_eval(vr_observer obs, double nm, double xyz[3]) {
  size_t rows;
  const double *t = vr_cmf_table(obs, &rows);
  double first = t[0], last = t[(rows - 1) * 4];
  if (!(nm >= first && nm <= last)) {
    xyz[0] = xyz[1] = xyz[2] = 0.0;
    return;
  }
  double pos = nm - first; /* the tables are on a 1 nm grid */
  size_t i = (size_t)pos;
  if (i >= rows - 1) i = rows - 2;
  double f = pos - (double)i;
  for (int k = 0; k < 3; k++) xyz[k] = (1.0 - f) * t[i * 4 + 1 + k] + f * t[(i + 1) * 4 + 1 + k];
}

vr_status vr_observer_parse(const char *s, vr_observer *obs, vr_error *err) {
  char buf[32];
  size_t n = 0;
  for (const char *p = s; *p && n + 1 < sizeof buf; p++)
    if (*p != ' ') buf[n++] = *p;
  buf[n] = '\0';
  const char *two[] = {"2", "2deg", "2°", "1931", "cie1931"};
  const char *ten[] = {"10", "10deg", "10°", "1964", "cie1964"};
  for (size_t i = 0; i < 5; i++) {
    if (!strcasecmp(buf, two[i])) { *obs = VR_CIE1931_2DEG; return VR_OK; }
    if (!strcasecmp(buf, ten[i])) { *obs = VR_CIE1964_10DEG; return VR_OK; }
  }
  return vr_error_set(err, VR_E_NOT_FOUND,
                      "unknown observer '%s' (use 2 for CIE 1931 2° or 10 for CIE 1964 10°)", s);
}

/* sum over the 1 nm CMF grid of w(nm) * cmf(nm); w = a(nm) * b(nm). */
static void weighted_sum(const vr_spectrum *a, const vr_spectrum *b, vr_observer obs,
                         double xyz[3]) {
  size_t rows;
  const double *t = vr_cmf_table(obs, &rows);
  double X = 0.0, Y = 0.0, Z = 0.0;
  for (size_t i = 0; i < rows; i++) {
    double nm = t[i * 4];
    double w = a ? vr_spectrum_eval(a, nm, VR_INTERP_LINEAR) : 1.0;
    if (b) w *= vr_spectrum_eval(b, nm, VR_INTERP_LINEAR);
    X += w * t[i * 4 + 1];
    Y += w * t[i * 4 + 2];
    Z += w * t[i * 4 + 3];
  }
  xyz[0] = X;
  xyz[1] = Y;
  xyz[2] = Z;
}

void vr_xyz_reflectance(const vr_spectrum *refl, const vr_spectrum *illum, vr_observer obs,
                        double xyz[3]) {
  double white[3];
  weighted_sum(NULL, illum, obs, white);
  weighted_sum(refl, illum, obs, xyz);
  double k = white[1] > 0.0 ? 1.0 / white[1] : 0.0;
  for (int i = 0; i < 3; i++) xyz[i] *= k;
}

void vr_xyz_white(const vr_spectrum *illum, vr_observer obs, double xyz[3]) {
  double white[3];
  weighted_sum(NULL, illum, obs, white);
  double k = white[1] > 0.0 ? 1.0 / white[1] : 0.0;
  for (int i = 0; i < 3; i++) xyz[i] = white[i] * k;
}

void vr_xyz_emitter(const vr_spectrum *radiance, vr_observer obs, double xyz[3]) {
  weighted_sum(radiance, NULL, obs, xyz);
  for (int i = 0; i < 3; i++) xyz[i] *= VR_KM; /* times the 1 nm step */
}
