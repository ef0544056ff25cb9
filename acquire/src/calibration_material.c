/* A camera calibration as a material of the database and back: the three
 * sensitivities as roles r, g, b, and the tone curves, fit figures and
 * provenance as properties, so that a capture manifest can name the camera
 * with "camera db:NAME" and vr-rgb2spec can linearise its photos. */
#include "vr/calibrate.h"

#include <math.h>
#include <stdbool.h>
#include <stdio.h>

static const char *const ROLE[3] = {"r", "g", "b"};

vr_status vr_calibration_to_material(const vr_calibration *cal, const char *name,
                                     vr_material **out, vr_error *err) {
  if (!cal || !name || !out || !cal->grid_nm)
    return vr_error_set(err, VR_E_ARG, "camera material: NULL argument");
  *out = NULL;
  vr_material *m = vr_material_create(name, VR_KIND_CAMERA, err);
  if (!m) return err ? err->status : VR_E_NOMEM;
  vr_status st = VR_OK;
  double worst = 0.0;
  char key[64], text[64];
  for (int c = 0; c < 3 && !st; c++) {
    vr_spectrum *s = vr_spectrum_create(cal->n, cal->grid_nm, cal->sens[c], err);
    st = s ? vr_material_add_spectrum(m, ROLE[c], s, err) : VR_E_NOMEM;
    if (st) break;
    vr_tone_format(cal->tone[c], cal->gamma[c], text, sizeof text);
    snprintf(key, sizeof key, "linearisation_%s", ROLE[c]);
    st = vr_material_add_property(m, key, text, cal->tone[c] == VR_TONE_GAMMA ? cal->gamma[c] : NAN,
                                  NULL, err);
    snprintf(key, sizeof key, "tone_rms_%s", ROLE[c]);
    if (!st) st = vr_material_add_property(m, key, NULL, cal->tone_rms[c], NULL, err);
    snprintf(key, sizeof key, "lambda_%s", ROLE[c]);
    if (!st) st = vr_material_add_parameter(m, key, cal->lambda[c], NAN, NULL, err);
    snprintf(key, sizeof key, "dof_%s", ROLE[c]);
    if (!st) st = vr_material_add_parameter(m, key, cal->dof[c], NAN, NULL, err);
    worst = fmax(worst, cal->rms[c]);
  }
  if (!st) st = vr_material_add_property(m, "condition_number", NULL, cal->cond, NULL, err);
  if (!st) st = vr_material_add_property(m, "used_patches", NULL, cal->used_patches, NULL, err);
  if (!st)
    st = vr_material_add_property(m, "clipped_patches", NULL, cal->clipped_patches, NULL, err);
  char model[320], t[3][32], how[64];
  for (int c = 0; c < 3; c++) vr_tone_format(cal->tone[c], cal->gamma[c], t[c], sizeof t[c]);
  if (cal->options.lambda < 0.0)
    snprintf(how, sizeof how, "GCV (Kim-Gu rho %.3g)", cal->options.gcv_rho);
  else
    snprintf(how, sizeof how, "fixed lambda %.3g", cal->options.lambda);
  snprintf(model, sizeof model, "smooth NNLS, %s, second-difference prior; tone r %s, g %s, b %s",
           how, t[0], t[1], t[2]);
  if (!st) st = vr_material_set_text(&m->prov.model, model, err);
  if (!st)
    st = vr_material_set_text(&m->description,
                              "camera sensitivities from a ColorChecker photo (green peak 1)", err);
  if (st) {
    vr_material_destroy(m);
    return st;
  }
  m->prov.residual = worst;
  *out = m;
  return VR_OK;
}

vr_status vr_calibration_tone_of(const vr_material *m, vr_tone tone[3], double gamma[3],
                                 bool *present, vr_error *err) {
  *present = false;
  int found = 0;
  for (int c = 0; c < 3; c++) {
    char key[64];
    snprintf(key, sizeof key, "linearisation_%s", ROLE[c]);
    const vr_property *p = vr_material_property(m, key);
    tone[c] = VR_TONE_LINEAR;
    gamma[c] = 1.0;
    if (!p) continue;
    found++;
    if (!p->text || vr_tone_parse(p->text, false, &tone[c], &gamma[c], NULL) != VR_OK)
      return vr_error_set(err, VR_E_PARSE, "material %s: property %s \"%s\" is not linear, srgb "
                                           "or gamma G", m->name, key, p->text ? p->text : "");
  }
  if (found == 0) return VR_OK;
  if (found < 3)
    return vr_error_set(err, VR_E_PARSE, "material %s: linearisation is given for %d of the "
                                         "three channels", m->name, found);
  *present = true;
  return VR_OK;
}
