/* Radiance materials as the renderer's (rad_read.h).  Radiance gives
 * colours as RGB in its own primaries, which are close to Rec. 709's; they
 * are read as linear sRGB, a grey as the constant it is and a colour as a
 * Jakob-Hanika sigmoid spectrum (vr/rgb_spectrum.h), as a model file's
 * colours are (models.c).  What each kind becomes:
 *   plastic R G B 0 rough   Lambertian, reflectance R G B (the specular
 *                           part is 0, so the roughness does nothing)
 *   plastic R G B spec r    glTF metallic-roughness, metallic 0, base R G B,
 *                           roughness sqrt(r) (GGX alpha = r, Radiance's
 *                           Ward alpha); its specular is the glTF coat's
 *                           (F0 0.04), not spec: said in the note
 *   metal R G B spec r      glTF metallic-roughness, metallic spec, base
 *                           R G B, roughness sqrt(r): a metal lobe of
 *                           colour R G B weighted spec and a diffuse one
 *                           weighted 1 - spec, as Radiance's metal
 *   mirror R G B            glTF metal, roughness 0: reflectance R G B at
 *                           normal incidence rising to 1 at grazing
 *                           (Schlick); Radiance's keeps R G B at every angle
 *   glass tr tg tb [n]      thin pane, n (1.52), internal transmittance
 *                           per pass t at normal incidence (Radiance's
 *                           transmissivity), both faces' Fresnel series
 *   dielectric t.. n 0      refracting interface, n, the medium
 *                           transmitting t per unit of the file's length
 *                           (t^(1/u) per metre, a unit u metres by the
 *                           mesh line's units= and scale=)
 *   light, glow R G B       black, emitting L = 179 (0.265 R + 0.670 G +
 *                           0.065 B) cd/m2 (Radiance's luminance of a
 *                           radiance in W/(sr m2)) from its front, the
 *                           colour as its spectrum's shape
 *   BSDF 0 F.xml ux uy uz . the BSDF XML file F, up the given vector
 *   trans R G B 0 r t 0     a translucent diffuser: Lambertian reflectance
 *                           R G B (1 - t) and transmittance R G B t (a
 *                           specular part, spec or tspec > 0, is refused) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "geometry/rad_read.h"
#include "scene/scene_parse.h"

static vr_status nomem(vr_error *err) { return vr_error_set(err, VR_E_NOMEM, "out of memory"); }

vr_status vr_rad_mesh_materials(const vr_rad_model *rm, vr_mesh_material **out, size_t *n,
                                vr_error *err) {
  *out = NULL, *n = 0;
  vr_mesh_material *m = calloc(rm->nmats ? rm->nmats : 1, sizeof *m);
  if (!m) return nomem(err);
  for (size_t i = 0; i < rm->nmats; i++) {
    const vr_rad_material *r = &rm->mats[i];
    snprintf(m[i].name, sizeof m[i].name, "%s", r->name);
    m[i].metallic = m[i].roughness = NAN;
    m[i].normal_scale = 1, m[i].alpha_cutoff = 0.5;
    m[i].triangles = r->triangles;
    m[i].rad_kind = (int)r->kind;
    memcpy(m[i].rad_arg, r->arg, sizeof r->arg);
    memcpy(m[i].rad_up, r->up, sizeof r->up);
    snprintf(m[i].rad_file, sizeof m[i].rad_file, "%s", r->file);
    snprintf(m[i].rad_where, sizeof m[i].rad_where, "%s", r->where);
  }
  *out = m;
  *n = rm->nmats;
  return VR_OK;
}

static const char *KIND[] = {"plastic", "metal", "mirror", "glass", "dielectric", "light",
                             "glow", "BSDF", "trans"};

static vr_status bad(const vr_mesh_material *mm, vr_error *err, const char *what) {
  return vr_error_set(err, VR_E_RANGE, "%s: %s '%s': %s", mm->rad_where, KIND[mm->rad_kind],
                      mm->name, what);
}

/* R G B as a spectrum: the constant of a grey (*constant, *spec NULL),
 * else an inline sigmoid spectrum of the colour over its largest
 * component (*spec, owned by the caller) and that component (*constant). */
static vr_status colour(const vr_mesh_material *mm, const double rgb[3], double *constant,
                        char **spec, vr_error *err) {
  *spec = NULL;
  double mx = fmax(rgb[0], fmax(rgb[1], rgb[2]));
  *constant = mx;
  if (rgb[0] == rgb[1] && rgb[1] == rgb[2]) return VR_OK;
  double shape[3] = {rgb[0] / mx, rgb[1] / mx, rgb[2] / mx};
  vr_error e = {0};
  if (!(*spec = vr_scene_colour_spectrum(shape, &e))) return bad(mm, err, e.message);
  return VR_OK;
}

/* A spectrum reference (inline table) of R G B scaled to peak: for an
 * emitter's shape, a glass's transmission. */
static vr_status table(const vr_mesh_material *mm, const double rgb[3], bool scaled, char **out,
                       vr_error *err) {
  double c;
  char *spec;
  vr_status st = colour(mm, rgb, &c, &spec, err);
  if (st) return st;
  char buf[64];
  if (!spec) {
    snprintf(buf, sizeof buf, "[360:%.17g,830:%.17g]", scaled ? c : 1.0, scaled ? c : 1.0);
    return (*out = strdup(buf)) ? VR_OK : nomem(err);
  }
  if (!scaled || c == 1) {
    *out = spec;
    return VR_OK;
  }
  /* Scale every value of "[W:V,...]" by c. */
  size_t cap = strlen(spec) * 2 + 64, n = 0;
  char *o = malloc(cap);
  if (!o) {
    free(spec);
    return nomem(err);
  }
  o[n++] = '[';
  char *save = NULL;
  for (char *tok = strtok_r(spec + 1, ",]", &save); tok; tok = strtok_r(NULL, ",]", &save)) {
    double w, v;
    if (sscanf(tok, "%lf:%lf", &w, &v) != 2) continue;
    n += (size_t)snprintf(o + n, cap - n, "%s%g:%.9g", n > 1 ? "," : "", w, v * c);
  }
  snprintf(o + n, cap - n, "]");
  free(spec);
  *out = o;
  return VR_OK;
}

static double lum(const double rgb[3]) {
  return 179.0 * (0.265 * rgb[0] + 0.670 * rgb[1] + 0.065 * rgb[2]);
}

vr_status vr_rad_emission(const vr_mesh_material *mm, vr_quantity *emission, char **spectrum,
                          vr_error *err) {
  emission->value = 0, emission->unit = VR_UNIT_NONE;
  *spectrum = NULL;
  if (mm->rad_kind != VR_RAD_LIGHT && mm->rad_kind != VR_RAD_GLOW) return VR_OK;
  vr_status st = table(mm, mm->rad_arg, false, spectrum, err);
  if (st) return st;
  emission->value = lum(mm->rad_arg);
  emission->unit = VR_UNIT_CD_M2;
  return VR_OK;
}

vr_status vr_rad_scene_material(const vr_mesh_material *mm, const vr_scene_object *ob,
                                vr_scene_material *m, char *note, size_t cap, vr_error *err) {
  const double *a = mm->rad_arg;
  const char *kind = KIND[mm->rad_kind];
  bool rgb_kind = mm->rad_kind != VR_RAD_BSDF;
  for (int k = 0; rgb_kind && k < 3; k++)
    if (!(a[k] >= 0)) return bad(mm, err, "a negative colour component");
  vr_status st = VR_OK;
  double c;
  char *spec = NULL;
  switch ((vr_rad_kind)mm->rad_kind) {
  case VR_RAD_PLASTIC:
  case VR_RAD_METAL:
  case VR_RAD_MIRROR: {
    bool mirror = mm->rad_kind == VR_RAD_MIRROR;
    double specular = mirror ? 1 : a[3], rough = mirror ? 0 : a[4];
    if (a[0] > 1 || a[1] > 1 || a[2] > 1)
      return bad(mm, err, "a reflectance above 1 (not physical)");
    if (!(specular >= 0 && specular <= 1)) return bad(mm, err, "its specularity is outside [0, 1]");
    if (!(rough >= 0)) return bad(mm, err, "a negative roughness");
    if ((st = colour(mm, a, &c, &spec, err))) return st;
    m->source = VR_MATSRC_LAMBERT_CONST;
    m->reflectance = spec ? 1 : c;
    m->reflectance_spectrum = spec;
    if (spec && c != 1) {
      /* The sigmoid spectrum is of the colour over its peak: the peak
       * goes back in through a scaled table. */
      free(spec);
      m->reflectance_spectrum = NULL;
      if ((st = table(mm, a, true, &m->reflectance_spectrum, err))) return st;
    }
    if (mm->rad_kind == VR_RAD_PLASTIC && specular == 0) {
      snprintf(note, cap, "%s %g %g %g 0: Lambertian", kind, a[0], a[1], a[2]);
      return VR_OK;
    }
    m->pbr = true;
    m->metallic = mm->rad_kind == VR_RAD_PLASTIC ? 0 : specular;
    m->pbr_roughness = fmin(sqrt(rough), 1.0);
    if (mm->rad_kind == VR_RAD_PLASTIC)
      snprintf(note, cap,
               "%s %g %g %g %g %g: glTF metallic-roughness (metallic 0, roughness %g); its "
               "specularity %g is drawn as glTF's dielectric coat (F0 0.04)",
               kind, a[0], a[1], a[2], a[3], a[4], m->pbr_roughness, a[3]);
    else if (mirror)
      snprintf(note, cap,
               "%s %g %g %g: a glTF metal of roughness 0 (Schlick: R G B at normal incidence "
               "rising to 1 at grazing; Radiance's mirror keeps R G B at every angle)",
               kind, a[0], a[1], a[2]);
    else
      snprintf(note, cap, "%s %g %g %g %g %g: glTF metallic-roughness (metallic %g, roughness %g)",
               kind, a[0], a[1], a[2], a[3], a[4], m->metallic, m->pbr_roughness);
    return VR_OK;
  }
  case VR_RAD_GLASS:
  case VR_RAD_DIELECTRIC: {
    bool glass = mm->rad_kind == VR_RAD_GLASS;
    if (glass && (a[0] > 1 || a[1] > 1 || a[2] > 1))
      return bad(mm, err, "a transmissivity above 1 (not physical)");
    if (!(a[3] >= 1 && a[3] < 10)) return bad(mm, err, "its index of refraction is outside [1, 10)");
    if (!glass && a[4] != 0)
      return bad(mm, err, "a Hartmann constant other than 0 (dispersion) is not read; map it to "
                          "a database dielectric with material.NAME=");
    if (!glass && (a[0] > 1 || a[1] > 1 || a[2] > 1))
      return bad(mm, err, "a transmission per unit length above 1 (not physical)");
    m->source = VR_MATSRC_GLASS;
    m->ior = a[3];
    m->pane = glass ? VR_PANE_THIN : VR_PANE_INTERFACES;
    /* A dielectric's transmission is per unit of the file's length; the
     * mesh line's units= (and scale=) make a unit u metres, the cube root
     * of its transform's volume scale: per metre it is t^(1/u). */
    double t[3] = {a[0], a[1], a[2]}, u = 1;
    if (!glass) {
      const double(*x)[4] = ob->xform.m;
      double det = x[0][0] * (x[1][1] * x[2][2] - x[1][2] * x[2][1]) -
                   x[0][1] * (x[1][0] * x[2][2] - x[1][2] * x[2][0]) +
                   x[0][2] * (x[1][0] * x[2][1] - x[1][1] * x[2][0]);
      u = cbrt(fabs(det));
      if (u > 0 && u != 1)
        for (int k = 0; k < 3; k++) t[k] = pow(a[k], 1 / u);
    }
    if ((st = table(mm, t, true, &m->transmission, err))) return st;
    if (glass)
      snprintf(note, cap, "%s %g %g %g, n %g: a thin pane (internal transmittance per pass)", kind,
               a[0], a[1], a[2], a[3]);
    else
      snprintf(note, cap,
               "%s %g %g %g, n %g: a refracting interface, its medium transmitting %.6g %.6g %.6g "
               "per metre (the file's unit %g m)",
               kind, a[0], a[1], a[2], a[3], t[0], t[1], t[2], u);
    return VR_OK;
  }
  case VR_RAD_LIGHT:
  case VR_RAD_GLOW: {
    m->source = VR_MATSRC_BLACK;
    double L = lum(a);
    if (!(L > 0)) return bad(mm, err, "it emits nothing (R G B all 0)");
    snprintf(note, cap, "%s %g %g %g: black, emitting %g cd/m2 from its front%s", kind, a[0], a[1],
             a[2], L,
             mm->rad_kind == VR_RAD_GLOW ? " (a glow's radius of influence changes nothing in a "
                                           "path tracer: every emitter lights everything)"
                                         : "");
    return VR_OK;
  }
  case VR_RAD_TRANS: {
    /* Radiance's trans: of the light not reflected specularly (spec), the
     * fraction trans is transmitted, tspec of it specularly; the rest of
     * the colour's share is diffuse.  Without specular parts, a diffuse
     * reflectance R G B (1 - trans) and transmittance R G B trans. */
    if (a[0] > 1 || a[1] > 1 || a[2] > 1) return bad(mm, err, "a colour above 1 (not physical)");
    if (a[3] != 0 || a[6] != 0)
      return bad(mm, err, "a specular part (spec or tspec other than 0) is not modelled; map it "
                          "with material.NAME= (a database glass, a BSDF XML file)");
    if (!(a[5] >= 0 && a[5] <= 1)) return bad(mm, err, "its transmissivity is outside [0, 1]");
    double rr[3] = {a[0] * (1 - a[5]), a[1] * (1 - a[5]), a[2] * (1 - a[5])};
    double tt[3] = {a[0] * a[5], a[1] * a[5], a[2] * a[5]};
    m->source = VR_MATSRC_TRANSLUCENT;
    if (rr[0] == rr[1] && rr[1] == rr[2]) m->reflectance = rr[0];
    else if ((st = table(mm, rr, true, &m->reflectance_spectrum, err))) return st;
    if (tt[0] == 0 && tt[1] == 0 && tt[2] == 0) m->transmission = strdup("[360:0,830:0]");
    else if ((st = table(mm, tt, true, &m->transmission, err))) return st;
    if (!m->transmission) return nomem(err);
    snprintf(note, cap,
             "trans %g %g %g 0 %g %g 0: a translucent diffuser, reflectance %.3g %.3g %.3g and "
             "transmittance %.3g %.3g %.3g, both Lambertian",
             a[0], a[1], a[2], a[4], a[5], rr[0], rr[1], rr[2], tt[0], tt[1], tt[2]);
    return VR_OK;
  }
  case VR_RAD_BSDF: {
    m->source = VR_MATSRC_BSDF_XML;
    if (!(m->bsdf_file = strdup(mm->rad_file))) return nomem(err);
    double up[3];
    vr_xform_vector(&ob->xform, mm->rad_up, up);
    double l = sqrt(up[0] * up[0] + up[1] * up[1] + up[2] * up[2]);
    if (!(l > 0)) return bad(mm, err, "its up vector is 0");
    for (int k = 0; k < 3; k++) m->bsdf_up[k] = up[k] / l;
    snprintf(note, cap, "BSDF '%s', up (%g, %g, %g)", mm->rad_file, m->bsdf_up[0], m->bsdf_up[1],
             m->bsdf_up[2]);
    return VR_OK;
  }
  }
  return bad(mm, err, "unknown kind");
}

/* The light kind that is the sun, from the registry of light kinds. */
static vr_light_kind sun_kind(void) {
  vr_scn_light_syntax k;
  size_t i = 0;
  while (vr_scn_light_kind(i, &k) && !k.sun) i++;
  return (vr_light_kind)i;
}

vr_status vr_rad_add_sources(vr_scene *s, const vr_scene_object *ob, const vr_rad_model *rm,
                             vr_error *err) {
  for (size_t i = 0; i < rm->nsrc; i++) {
    const vr_rad_source *src = &rm->src[i];
    if (i > 0)
      return vr_error_set(err, VR_E_PARSE, "%s: a second distant source (the first is at %s)",
                          src->where, rm->src[0].where);
    if (s->sky.present)
      return vr_error_set(err, VR_E_PARSE,
                          "%s: a distant source in a scene with a sky (line %ld): write the sun "
                          "in the scene (light sun) so that the sky is placed with it",
                          src->where, s->sky.loc.line);
    for (size_t j = 0; j < s->nlights; j++)
      if (s->lights[j].kind == sun_kind())
        return vr_error_set(err, VR_E_PARSE,
                            "%s: a distant source, and the scene has a sun already (line %ld)",
                            src->where, s->lights[j].loc.line);
    const vr_rad_material *lm = &rm->mats[src->material];
    vr_scene_light *l = realloc(s->lights, (s->nlights + 1) * sizeof *l);
    if (!l) return nomem(err);
    s->lights = l;
    l = &l[s->nlights];
    memset(l, 0, sizeof *l);
    l->kind = sun_kind();
    l->normal[2] = -1;
    double d[3];
    vr_xform_vector(&ob->xform, src->dir, d);
    double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int k = 0; k < 3; k++) l->direction[k] = d[k] / len;
    l->sun_radius_deg = src->angle_deg / 2;
    double omega = 2 * M_PI * (1 - cos(src->angle_deg / 2 * M_PI / 180));
    l->amount.value = lum(lm->arg) * omega;
    l->amount.unit = VR_UNIT_LX;
    vr_mesh_material mm;
    memset(&mm, 0, sizeof mm);
    mm.rad_kind = VR_RAD_LIGHT;
    snprintf(mm.name, sizeof mm.name, "%s", lm->name);
    snprintf(mm.rad_where, sizeof mm.rad_where, "%s", lm->where);
    vr_status st = table(&mm, lm->arg, false, &l->spectrum, err);
    if (st) return st;
    if (!(l->amount.value > 0))
      return vr_error_set(err, VR_E_RANGE, "%s: the distant source's light '%s' emits nothing",
                          src->where, lm->name);
    l->loc = ob->loc;
    s->nlights++;
  }
  return VR_OK;
}
