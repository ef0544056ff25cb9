/* Building a vr_bsdf: which kind a scene material becomes (the table in
 * vr/bsdf.h), the checks on its settings, and the per-wavelength tables
 * that keep the database's interpolators off the hot path. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "materials/bsdf_internal.h"
#include "vr/chromogenic.h"

/* Prefix naming the scene line and the material, for every error. */
static void locate(vr_error *err, const vr_scene_material *sm) {
  char where[64] = "";
  if (sm->loc.line > 0 && sm->loc.col > 0)
    snprintf(where, sizeof where, "%ld:%ld: ", sm->loc.line, sm->loc.col);
  else if (sm->loc.line > 0)
    snprintf(where, sizeof where, "%ld: ", sm->loc.line);
  if (sm->source == VR_MATSRC_DB)
    vr_error_prefix(err, "%smaterial '%s' (db:%s): ", where, sm->name ? sm->name : "?",
                    sm->db_name ? sm->db_name : "?");
  else
    vr_error_prefix(err, "%smaterial '%s': ", where, sm->name ? sm->name : "?");
}

static bool given(double x) { return !isnan(x); }

/* A "thickness" property in nm (mm unless another unit is stated); NAN if
 * absent. */
static double prop_thickness_nm(const vr_material *m) {
  const vr_property *p = m ? vr_material_property(m, "thickness") : NULL;
  if (!p || !isfinite(p->value)) return NAN;
  const char *u = p->unit ? p->unit : "mm";
  double scale = !strcmp(u, "nm") ? 1.0
                 : (!strcmp(u, "um") || !strcmp(u, "µm")) ? 1e3
                 : !strcmp(u, "m") ? 1e9
                 : !strcmp(u, "cm") ? 1e7
                                    : 1e6;
  return p->value * scale;
}

static double *grid_alloc(const vr_bsdf *b) { return calloc(b->nl, sizeof(double)); }

static double node_nm(const vr_bsdf *b, size_t i) { return b->lmin + (double)i; }

/* n, k of a dielectric or conductor on the grid. */
static vr_status fill_nk(vr_bsdf *b, const vr_material *m, vr_error *err) {
  b->n = grid_alloc(b);
  b->k = grid_alloc(b);
  if (!b->n || !b->k) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  for (size_t i = 0; i < b->nl; i++) {
    bool ext = false;
    vr_status st = vr_material_nk(m, node_nm(b, i), true, &b->n[i], &b->k[i], &ext, err);
    if (st) return st;
    if (ext) b->extrapolated = true;
    if (!(b->n[i] > 0.0) || !isfinite(b->n[i]) || !(b->k[i] >= 0.0) || !isfinite(b->k[i]))
      return vr_error_set(err, VR_E_RANGE, "n = %g, k = %g at %g nm is not a physical index",
                          b->n[i], b->k[i], node_nm(b, i));
  }
  return VR_OK;
}

/* A tabulated role on the grid, ends held; optional roles may be absent
 * (*out stays NULL). */
static vr_status fill_role(vr_bsdf *b, const vr_material *m, const char *role, bool optional,
                           double **out, vr_error *err) {
  *out = NULL;
  if (!vr_material_spectrum(m, role)) {
    if (optional) return VR_OK;
    return vr_error_set(err, VR_E_NOT_FOUND, "a %s material needs the spectrum '%s'",
                        vr_kind_name(m->kind), role);
  }
  double *v = grid_alloc(b);
  if (!v) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  *out = v;
  for (size_t i = 0; i < b->nl; i++) {
    bool ext = false;
    vr_status st = vr_material_eval(m, role, node_nm(b, i), true, &v[i], &ext, err);
    if (st) return st;
    if (ext) b->extrapolated = true;
    if (!isfinite(v[i])) return vr_error_set(err, VR_E_RANGE, "'%s' is not finite", role);
  }
  return VR_OK;
}

static vr_status make_lambert(vr_bsdf *b, const vr_scene_material *sm, const vr_material *m,
                              vr_error *err) {
  b->kind = VR_BK_LAMBERT;
  b->lobes = VR_LOBE_DIFFUSE;
  if (m) {
    vr_status st = fill_role(b, m, "value", false, &b->refl, err);
    if (st) return st;
    for (size_t i = 0; i < b->nl; i++) b->refl[i] = vr_bsdfi_clamp01(b->refl[i]);
    snprintf(b->desc, sizeof b->desc, "Lambertian (reflectance spectrum)");
    return VR_OK;
  }
  if (sm->reflectance_spectrum) {
    /* An inline table: read as the database reads its reflectance spectra
     * (vr_material_eval), linear between points, ends held beyond them. */
    vr_spectrum *sp = vr_scene_inline_spectrum(sm->reflectance_spectrum, err);
    if (!sp) return err ? err->status : VR_E_PARSE;
    if (!(b->refl = grid_alloc(b))) {
      vr_spectrum_destroy(sp);
      return vr_error_set(err, VR_E_NOMEM, "out of memory");
    }
    for (size_t i = 0; i < b->nl; i++) {
      double nm = node_nm(b, i);
      if (!vr_spectrum_covers(sp, nm, nm)) b->extrapolated = true;
      b->refl[i] = vr_bsdfi_clamp01(vr_spectrum_eval(sp, nm, VR_INTERP_LINEAR));
    }
    vr_spectrum_destroy(sp);
    snprintf(b->desc, sizeof b->desc, "Lambertian (inline reflectance spectrum)");
    return VR_OK;
  }
  if (!(sm->reflectance >= 0.0 && sm->reflectance <= 1.0))
    return vr_error_set(err, VR_E_RANGE, "reflectance %g outside [0, 1]", sm->reflectance);
  if (!(b->refl = grid_alloc(b))) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  for (size_t i = 0; i < b->nl; i++) b->refl[i] = sm->reflectance;
  snprintf(b->desc, sizeof b->desc, "Lambertian (reflectance %g)", sm->reflectance);
  return VR_OK;
}

/* glTF metallic-roughness: the base colour as a Lambertian's reflectance
 * (constant, inline spectrum or colour), then its factors. */
static vr_status make_pbr(vr_bsdf *b, const vr_scene_material *sm, vr_error *err) {
  vr_status st = make_lambert(b, sm, NULL, err);
  if (st) return st;
  if (!(sm->metallic >= 0.0 && sm->metallic <= 1.0))
    return vr_error_set(err, VR_E_RANGE, "metallic %g outside [0, 1]", sm->metallic);
  if (!(sm->pbr_roughness >= 0.0 && sm->pbr_roughness <= 1.0))
    return vr_error_set(err, VR_E_RANGE, "roughness %g outside [0, 1]", sm->pbr_roughness);
  b->kind = VR_BK_PBR;
  b->metallic = sm->metallic;
  b->pbr_r = sm->pbr_roughness;
  double sum = 0.0;
  for (size_t i = 0; i < b->nl; i++) sum += b->refl[i];
  b->refl_mean = sum / (double)b->nl;
  /* A texture can lower both factors per point (it multiplies them). */
  bool mapped = sm->mr_map != NULL, mirror = vr_bsdfi_pbr_mirror(b->pbr_r * b->pbr_r);
  b->lobes = 0;
  if (b->metallic < 1.0 || mapped) b->lobes |= VR_LOBE_DIFFUSE;
  if (mirror || mapped) b->lobes |= VR_LOBE_SPECULAR_R;
  if (!mirror) b->lobes |= VR_LOBE_GLOSSY_R;
  snprintf(b->desc, sizeof b->desc, "glTF metallic-roughness (metallic %g, roughness %g%s)",
           b->metallic, b->pbr_r, mapped ? ", times a texture per point" : "");
  return VR_OK;
}

static vr_status make_conductor(vr_bsdf *b, const vr_scene_material *sm, const vr_material *m,
                                vr_error *err) {
  b->kind = VR_BK_CONDUCTOR;
  b->rough = given(sm->roughness) && sm->roughness > 0.0;
  b->alpha = b->rough ? sm->roughness : 0.0;
  b->lobes = b->rough ? VR_LOBE_GLOSSY_R : VR_LOBE_SPECULAR_R;
  if (b->rough)
    snprintf(b->desc, sizeof b->desc, "rough conductor (GGX, alpha %g)", b->alpha);
  else
    snprintf(b->desc, sizeof b->desc, "conductor mirror (Fresnel, complex N)");
  return fill_nk(b, m, err);
}

static vr_status make_interface(vr_bsdf *b, const vr_scene_material *sm, vr_error *err) {
  b->kind = VR_BK_INTERFACE;
  b->rough = given(sm->roughness) && sm->roughness > 0.0;
  b->alpha = b->rough ? sm->roughness : 0.0;
  b->lobes = b->rough ? VR_LOBE_GLOSSY_R | VR_LOBE_GLOSSY_T
                      : VR_LOBE_SPECULAR_R | VR_LOBE_SPECULAR_T;
  if (!(b->sigma_a = grid_alloc(b))) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  double lo = INFINITY, hi = -INFINITY;
  for (size_t i = 0; i < b->nl; i++) {
    b->sigma_a[i] = 4.0 * M_PI * b->k[i] / (node_nm(b, i) * 1e-9);
    lo = fmin(lo, b->n[i]);
    hi = fmax(hi, b->n[i]);
  }
  /* Below a millionth the refracted directions differ by less than a
   * microradian: one direction serves all wavelengths. */
  b->dispersive = hi - lo > 1e-6;
  snprintf(b->desc, sizeof b->desc, "%s dielectric interface%s (n %.4f..%.4f)",
           b->rough ? "rough" : "smooth", b->dispersive ? ", dispersive" : "", lo, hi);
  return VR_OK;
}

static vr_status make_dielectric(vr_bsdf *b, const vr_scene_material *sm, const vr_material *m,
                                 const vr_material *coating, vr_error *err) {
  bool rough = given(sm->roughness) && sm->roughness > 0.0;
  double d = given(sm->thickness_m) ? sm->thickness_m * 1e9 : prop_thickness_nm(m);
  if (given(d) && !(d > 0.0 && isfinite(d)))
    return vr_error_set(err, VR_E_RANGE, "pane thickness must be positive (%g mm)", d * 1e-6);
  bool thin = coating || sm->pane == VR_PANE_THIN ||
              (sm->pane == VR_PANE_DEFAULT && given(d) && !rough);
  if (thin && rough)
    return vr_error_set(err, VR_E_ARG,
                        "roughness on a thin pane (model=thin) is not modelled; use model=interfaces for a "
                        "rough interface, or a btdf table (vr-spectro btdf) for frosted glass");
  if (thin && !given(d))
    return vr_error_set(err, VR_E_ARG, "a thin pane needs its thickness (thickness=)");
  if (coating && sm->pane == VR_PANE_INTERFACES)
    return vr_error_set(err, VR_E_ARG, "a coated pane is a thin element; model=interfaces "
                                       "cannot carry a coating");
  vr_status st = fill_nk(b, m, err);
  if (st) return st;
  if (!thin) return make_interface(b, sm, err);
  b->kind = VR_BK_PANE;
  b->lobes = VR_LOBE_SPECULAR_R | VR_LOBE_STRAIGHT;
  if (!coating) {
    snprintf(b->desc, sizeof b->desc, "thin pane (vr_slab, %g mm)", d * 1e-6);
    return vr_bsdfi_table_slab(b, d, err);
  }
  double film = prop_thickness_nm(coating);
  if (!given(film) || !(film > 0.0))
    return vr_error_set(err, VR_E_ARG,
                        "coating '%s' has no thickness: a coating is one film (a dielectric or "
                        "conductor with a thickness property) or a btdf table of the coated pane",
                        coating->name);
  snprintf(b->desc, sizeof b->desc, "coated pane (%s %g nm on %g mm, vr_stack_solve)",
           coating->name, film, d * 1e-6);
  return vr_bsdfi_table_coated(b, coating, film, d, err);
}

/* An inline non-dispersive dielectric (a Radiance glass or dielectric):
 * n constant, k from the transmission spectrum.  Glass: a thin pane whose
 * internal transmittance per pass at normal incidence is t; the pane is
 * given a nominal 6 mm, which only scales k (t^(1/cos theta_t) at other
 * angles whatever the thickness).  Dielectric: an interface whose medium
 * transmits t per metre, sigma_a = -ln t. */
static vr_status make_glass(vr_bsdf *b, const vr_scene_material *sm, vr_error *err) {
  if (!(sm->ior >= 1.0 && sm->ior < 10.0))
    return vr_error_set(err, VR_E_RANGE, "index of refraction %g outside [1, 10)", sm->ior);
  vr_spectrum *sp = vr_scene_inline_spectrum(sm->transmission ? sm->transmission : "", err);
  if (!sp) return err ? err->status : VR_E_PARSE;
  b->n = grid_alloc(b);
  b->k = grid_alloc(b);
  if (!b->n || !b->k) {
    vr_spectrum_destroy(sp);
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  bool thin = sm->pane != VR_PANE_INTERFACES;
  const double d_nm = 6e6;
  for (size_t i = 0; i < b->nl; i++) {
    double nm = node_nm(b, i);
    if (!vr_spectrum_covers(sp, nm, nm)) b->extrapolated = true;
    double t = vr_spectrum_eval(sp, nm, VR_INTERP_LINEAR);
    t = fmax(t, 1e-30);
    if (thin && t > 1) t = 1;
    b->n[i] = sm->ior;
    /* alpha = 4 pi k / lambda: per pass over d, or per metre. */
    b->k[i] = thin ? -nm * log(t) / (4.0 * M_PI * d_nm) : -(nm * 1e-9) * log(t) / (4.0 * M_PI);
    if (b->k[i] < 0) b->k[i] = 0;
  }
  vr_spectrum_destroy(sp);
  if (!thin) return make_interface(b, sm, err);
  b->kind = VR_BK_PANE;
  b->lobes = VR_LOBE_SPECULAR_R | VR_LOBE_STRAIGHT;
  snprintf(b->desc, sizeof b->desc, "thin glass (n %g, inline transmissivity)", sm->ior);
  return vr_bsdfi_table_slab(b, d_nm, err);
}

/* A translucent diffuser: the reflectance as a lambert's, the Lambertian
 * transmittance from its inline spectrum; reflectance plus transmittance
 * at most 1 at every wavelength. */
static vr_status make_translucent(vr_bsdf *b, const vr_scene_material *sm, vr_error *err) {
  vr_status st = make_lambert(b, sm, NULL, err);
  if (st) return st;
  vr_spectrum *sp = vr_scene_inline_spectrum(sm->transmission ? sm->transmission : "", err);
  if (!sp) return err ? err->status : VR_E_PARSE;
  if (!(b->trans = grid_alloc(b))) {
    vr_spectrum_destroy(sp);
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  double sr = 0, stt = 0;
  for (size_t i = 0; i < b->nl; i++) {
    double nm = node_nm(b, i);
    if (!vr_spectrum_covers(sp, nm, nm)) b->extrapolated = true;
    b->trans[i] = vr_bsdfi_clamp01(vr_spectrum_eval(sp, nm, VR_INTERP_LINEAR));
    if (b->refl[i] + b->trans[i] > 1.0 + 1e-9) {
      vr_spectrum_destroy(sp);
      return vr_error_set(err, VR_E_RANGE,
                          "reflectance %g plus transmittance %g at %g nm is above 1", b->refl[i],
                          b->trans[i], nm);
    }
    sr += b->refl[i], stt += b->trans[i];
  }
  vr_spectrum_destroy(sp);
  b->kind = VR_BK_TRANSLUCENT;
  b->lobes = VR_LOBE_DIFFUSE | VR_LOBE_GLOSSY_T;
  b->refl_share = sr + stt > 0 ? sr / (sr + stt) : 1.0;
  snprintf(b->desc, sizeof b->desc, "translucent diffuser (mean reflectance %.3g, transmittance %.3g)",
           sr / (double)b->nl, stt / (double)b->nl);
  return VR_OK;
}

static vr_status make_glazing(vr_bsdf *b, const vr_scene_material *sm, const vr_material *m,
                              vr_error *err) {
  /* The measured pane's own thickness first: T and R belong to it. */
  double d = prop_thickness_nm(m);
  if (!given(d) && given(sm->thickness_m)) d = sm->thickness_m * 1e9;
  if (!given(d)) d = 4e6; /* nominal; the angular result hardly depends on it */
  if (!(d > 0.0 && isfinite(d)))
    return vr_error_set(err, VR_E_RANGE, "pane thickness must be positive");
  b->kind = VR_BK_PANE;
  b->lobes = VR_LOBE_SPECULAR_R | VR_LOBE_STRAIGHT;
  snprintf(b->desc, sizeof b->desc, "measured pane (equivalent uncoated slab, %g mm)", d * 1e-6);
  return vr_bsdfi_table_glazing(b, m, d, err);
}

static vr_status make_chromo(vr_bsdf *b, const vr_scene_material *sm, const vr_material *m,
                             vr_error *err) {
  vr_chromo_type type;
  vr_status st = vr_chromo_type_of(m, &type, err);
  if (st) return st;
  b->kind = VR_BK_CHROMO;
  b->lobes = VR_LOBE_SPECULAR_R | VR_LOBE_STRAIGHT;
  b->photochromic = type == VR_CHROMO_PHOTO;
  if ((st = fill_role(b, m, "T0", false, &b->T0, err)) ||
      (st = fill_role(b, m, "dOD", false, &b->dOD, err)) ||
      (st = fill_role(b, m, "Rf0", true, &b->Rf0, err)) ||
      (st = fill_role(b, m, "dRf", true, &b->dRf, err)) ||
      (st = fill_role(b, m, "Rb0", true, &b->Rb0, err)) ||
      (st = fill_role(b, m, "dRb", true, &b->dRb, err)))
    return st;
  if (given(sm->state) && !(sm->state >= 0.0 && sm->state <= 1.0))
    return vr_error_set(err, VR_E_RANGE, "state %g outside [0, 1]", sm->state);
  if (given(sm->charge_mC_cm2) && b->photochromic)
    return vr_error_set(err, VR_E_ARG, "charge= applies to electrochromic glass; a photochromic "
                                       "pane's state comes from its UV exposure");
  if (given(sm->state) && given(sm->charge_mC_cm2))
    return vr_error_set(err, VR_E_ARG, "give state= or charge=, not both");
  b->default_state = 0.0;
  if (given(sm->state)) b->default_state = sm->state;
  else if (given(sm->charge_mC_cm2) &&
           (st = vr_chromo_state_of_charge(m, sm->charge_mC_cm2, &b->default_state, err)))
    return st;
  snprintf(b->desc, sizeof b->desc, "%s glass (state %g%s)",
           b->photochromic ? "photochromic" : "electrochromic", b->default_state,
           b->photochromic && !given(sm->state) ? " until its UV exposure sets it" : "");
  return VR_OK;
}

/* Settings that only some kinds take, refused elsewhere rather than
 * silently ignored. */
static vr_status check_settings(const vr_scene_material *sm, vr_material_kind kind,
                                vr_error *err) {
  bool chromo = kind == VR_KIND_CHROMOGENIC, dielectric = kind == VR_KIND_DIELECTRIC;
  if ((given(sm->state) || given(sm->charge_mC_cm2)) && !chromo)
    return vr_error_set(err, VR_E_ARG, "state= and charge= apply to chromogenic glass only");
  if (given(sm->roughness) && !(sm->roughness >= 0.0 && isfinite(sm->roughness)))
    return vr_error_set(err, VR_E_RANGE, "roughness %g must be >= 0", sm->roughness);
  if (given(sm->roughness) && sm->roughness > 0.0 && !dielectric && kind != VR_KIND_CONDUCTOR)
    return vr_error_set(err, VR_E_ARG, "roughness= is for dielectrics and conductors, not a %s",
                        vr_kind_name(kind));
  if (sm->pane == VR_PANE_INTERFACES && !dielectric)
    return vr_error_set(err, VR_E_ARG, "model=interfaces needs a dielectric with n and k, not a %s",
                        vr_kind_name(kind));
  if (sm->coating_db && !dielectric)
    return vr_error_set(err, VR_E_ARG, "a coating goes on a dielectric pane, not on a %s",
                        vr_kind_name(kind));
  return VR_OK;
}

static vr_status build(vr_bsdf *b, const vr_scene_material *sm, const vr_material *m,
                       const vr_material *coating, vr_error *err) {
  if (sm->source == VR_MATSRC_BLACK) {
    b->kind = VR_BK_BLACK;
    snprintf(b->desc, sizeof b->desc, "black");
    return VR_OK;
  }
  if (sm->source == VR_MATSRC_LAMBERT_CONST)
    return sm->pbr ? make_pbr(b, sm, err) : make_lambert(b, sm, NULL, err);
  if (sm->source == VR_MATSRC_BSDF_XML) return vr_bsdfi_klems_create(b, sm, err);
  if (sm->source == VR_MATSRC_GLASS) return make_glass(b, sm, err);
  if (sm->source == VR_MATSRC_TRANSLUCENT) return make_translucent(b, sm, err);
  if (!m) return vr_error_set(err, VR_E_ARG, "the database material was not resolved");
  vr_status st = check_settings(sm, m->kind, err);
  if (st) return st;
  if (sm->coating_db && !coating)
    return vr_error_set(err, VR_E_ARG, "the coating db:%s was not resolved", sm->coating_db);
  if (coating && coating->kind == VR_KIND_BTDF) {
    /* A btdf table of the coated pane stands for the whole pane. */
    b->kind = VR_BK_PANE;
    b->lobes = VR_LOBE_SPECULAR_R | VR_LOBE_STRAIGHT;
    snprintf(b->desc, sizeof b->desc, "coated pane (btdf table %s)", coating->name);
    return vr_bsdfi_table_btdf(b, coating, err);
  }
  if (coating && coating->kind != VR_KIND_DIELECTRIC && coating->kind != VR_KIND_CONDUCTOR)
    return vr_error_set(err, VR_E_ARG,
                        "coating '%s' is a %s; the database stores no layer stacks, so a coating "
                        "is one film (dielectric or conductor with a thickness) or the btdf table "
                        "of the coated pane (vr-spectro btdf --model)",
                        coating->name, vr_kind_name(coating->kind));
  switch (m->kind) {
  case VR_KIND_REFLECTANCE: return make_lambert(b, sm, m, err);
  case VR_KIND_CONDUCTOR: return make_conductor(b, sm, m, err);
  case VR_KIND_DIELECTRIC: return make_dielectric(b, sm, m, coating, err);
  case VR_KIND_GLAZING: return make_glazing(b, sm, m, err);
  case VR_KIND_CHROMOGENIC: return make_chromo(b, sm, m, err);
  case VR_KIND_BTDF:
    b->kind = VR_BK_PANE;
    b->lobes = VR_LOBE_SPECULAR_R | VR_LOBE_STRAIGHT;
    snprintf(b->desc, sizeof b->desc, "tabulated pane (btdf)");
    return vr_bsdfi_table_btdf(b, m, err);
  case VR_KIND_LAYERED:
    return vr_error_set(err, VR_E_ARG,
                        "layered materials have no stored stack yet; save the coated pane as a "
                        "btdf table (vr-spectro btdf --model) and use that");
  default:
    return vr_error_set(err, VR_E_ARG, "a %s is not a surface material",
                        vr_kind_name(m->kind));
  }
}

vr_status vr_bsdf_create(const vr_scene_material *sm, const vr_material *m,
                         const vr_material *coating, double lambda_min, double lambda_max,
                         vr_bsdf **out, vr_error *err) {
  *out = NULL;
  if (!sm) return vr_error_set(err, VR_E_ARG, "vr_bsdf_create: no scene material");
  vr_status st = VR_OK;
  if (!(lambda_min > 0.0) || !(lambda_max >= lambda_min) || !isfinite(lambda_max) ||
      lambda_max - lambda_min > 1e5) {
    st = vr_error_set(err, VR_E_ARG, "wavelength range %g-%g nm is not valid", lambda_min,
                      lambda_max);
    locate(err, sm);
    return st;
  }
  vr_bsdf *b = calloc(1, sizeof *b);
  if (!b) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  b->lmin = lambda_min;
  b->nl = (size_t)ceil(lambda_max - lambda_min - 1e-9) + 1;
  if (b->nl < 2) b->nl = 2;
  st = build(b, sm, m, coating, err);
  if (st) {
    locate(err, sm);
    vr_bsdf_destroy(b);
    return st;
  }
  /* The scratch n, k of panes are not needed once the tables exist. */
  if (b->kind == VR_BK_PANE) {
    free(b->n);
    free(b->k);
    b->n = b->k = NULL;
  }
  *out = b;
  return VR_OK;
}

void vr_bsdf_destroy(vr_bsdf *b) {
  if (!b) return;
  double *arrays[] = {b->refl, b->n,   b->k,   b->sigma_a, b->T,   b->Rf,  b->Rb,
                      b->T0,   b->dOD, b->Rf0, b->dRf,     b->Rb0, b->dRb, b->trans};
  for (size_t i = 0; i < sizeof arrays / sizeof *arrays; i++) free(arrays[i]);
  vr_bsdfi_klems_destroy(b->klems);
  free(b);
}

unsigned vr_bsdf_lobes(const vr_bsdf *b) { return b->lobes; }
bool vr_bsdf_dispersive(const vr_bsdf *b) { return b->dispersive; }
bool vr_bsdf_is_chromogenic(const vr_bsdf *b) { return b->kind == VR_BK_CHROMO; }
bool vr_bsdf_is_photochromic(const vr_bsdf *b) {
  return b->kind == VR_BK_CHROMO && b->photochromic;
}
bool vr_bsdf_is_pbr(const vr_bsdf *b) { return b->kind == VR_BK_PBR; }
bool vr_bsdf_is_klems(const vr_bsdf *b) { return b->kind == VR_BK_KLEMS; }
bool vr_bsdf_is_thin(const vr_bsdf *b) { return b->kind == VR_BK_PANE || b->kind == VR_BK_CHROMO; }
double vr_bsdf_default_state(const vr_bsdf *b) { return b->default_state; }
bool vr_bsdf_extrapolated(const vr_bsdf *b) { return b->extrapolated; }
const char *vr_bsdf_describe(const vr_bsdf *b) { return b->desc; }
