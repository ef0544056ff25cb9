/* vr-render's overrides of the scene file (render_cli.h): one scene file
 * serves a study of resolutions, exposures, seeds and tint states.
 * --resolution and --exposure replace the camera line's values, --seed the
 * render line's, --set NAME.state=S a material's state; all are checked before the scene is read where they
 * can be (a usage error, exit 2), and against the scene and the database
 * before any work (exit 1). */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render_cli.h"
#include "vr/csv.h"
#include "vr/material.h"
#include "vr/matdb.h"


/* "ec.state=0.5": the material is everything before the last '.' ahead of
 * the '=' (scene names may hold dots), the parameter what follows it. */
static int parse_set(const char *text, render_set *out) {
  const char *eq = strchr(text, '=');
  const char *dot = NULL;
  for (const char *c = text; eq && c < eq; c++)
    if (*c == '.') dot = c;
  if (!eq || !dot || dot == text || dot + 1 == eq)
    return render_usage_error("--set '%s': expected NAME.state=S (a material of the scene and its tint state)",
                 text);
  size_t n = (size_t)(dot - text);
  if (n >= sizeof out->material) return render_usage_error("--set '%s': the material name is too long", text);
  if ((size_t)(eq - dot - 1) != 5 || strncmp(dot + 1, "state", 5))
    return render_usage_error("--set '%s': unknown parameter \"%.*s\" (a material takes state)", text,
                 (int)(eq - dot - 1), dot + 1);
  double v;
  if (vr_parse_double(eq + 1, &v) || !(v >= 0 && v <= 1))
    return render_usage_error("--set '%s': the state must be a number in [0, 1] (0 bleached, 1 fully "
                 "coloured)", text);
  memcpy(out->material, text, n);
  out->material[n] = '\0';
  out->state = v;
  out->text = text;
  return 0;
}

static const vr_option *find_long(const vr_option *opts, size_t nopts, const char *name,
                                  size_t len) {
  for (size_t k = 0; k < nopts; k++)
    if (strlen(opts[k].name) == len && !strncmp(opts[k].name, name, len)) return &opts[k];
  return NULL;
}

static const vr_option *find_short(const vr_option *opts, size_t nopts, char c) {
  for (size_t k = 0; c && k < nopts; k++)
    if (opts[k].short_name == c) return &opts[k];
  return NULL;
}

int render_overrides_parse(const vr_args *a, int argc, char **argv, const vr_option *opts,
                           size_t nopts, render_overrides *o) {
  memset(o, 0, sizeof *o);
  /* Every option once, but --set; vr_args has already refused unknown
   * options and missing values. */
  int seen[64] = {0};
  for (int i = 1; i < argc; i++) {
    const char *s = argv[i];
    if (!strcmp(s, "--")) break;
    if (s[0] != '-' || s[1] == '\0') continue;
    const vr_option *opt = NULL;
    const char *value = NULL;
    if (s[1] == '-') {
      const char *eq = strchr(s + 2, '=');
      opt = find_long(opts, nopts, s + 2, eq ? (size_t)(eq - s - 2) : strlen(s + 2));
      if (eq) value = eq + 1;
    } else if (s[2] == '\0') {
      opt = find_short(opts, nopts, s[1]);
    }
    if (!opt) continue; /* a negative number: an operand */
    if (opt->arg && !value && i + 1 < argc) value = argv[++i];
    size_t k = (size_t)(opt - opts);
    if (strcmp(opt->name, "set")) {
      if (k < 64 && seen[k]++)
        return render_usage_error("--%s is given twice: give it once", opt->name);
      continue;
    }
    if (o->nsets == RENDER_MAX_SETS) return render_usage_error("more than %d --set options", RENDER_MAX_SETS);
    render_set *set = &o->sets[o->nsets];
    if (parse_set(value ? value : "", set)) return 2;
    for (int j = 0; j < o->nsets; j++)
      if (!strcmp(o->sets[j].material, set->material))
        return render_usage_error("--set '%s': the state of \"%s\" is already set (--set '%s')", set->text,
                     set->material, o->sets[j].text);
    o->nsets++;
  }
  o->render = vr_args_get(a, "render");
  const char *res = vr_args_get(a, "resolution");
  if (res) {
    long w = 0, h = 0;
    char *end = NULL;
    w = strtol(res, &end, 10);
    if (end != res && *end == 'x') {
      const char *hs = end + 1;
      h = strtol(hs, &end, 10);
      if (end == hs) h = 0;
    }
    if (*res == '+' || *res == ' ' || *end || !(w >= 1 && w <= 16384) || !(h >= 1 && h <= 16384))
      return render_usage_error("--resolution '%s': expected WIDTHxHEIGHT, each 1 to 16384", res);
    o->width = (int)w, o->height = (int)h;
  }
  const char *seed = vr_args_get(a, "seed");
  if (seed) {
    /* The scene's seed= range, digits only: no sign, no exponent. */
    size_t n = strlen(seed);
    bool ok = n > 0 && n <= 20 && strspn(seed, "0123456789") == n;
    if (ok) {
      errno = 0;
      o->seed = strtoull(seed, NULL, 10);
      ok = errno == 0;
    }
    if (!ok)
      return render_usage_error("--seed '%s': expected an integer in [0, 18446744073709551615]",
                                seed);
    o->seed_given = true;
  }
  const char *ev = vr_args_get(a, "exposure");
  if (ev) {
    o->exposure_given = true;
    if (!strcmp(ev, "auto")) o->exposure_auto = true;
    else if (vr_parse_double(ev, &o->exposure_ev) || fabs(o->exposure_ev) > 1000)
      return render_usage_error("--exposure '%s': expected a number of EV (|EV| <= 1000) or auto", ev);
  }
  return 0;
}

static vr_scene_material *material_named(vr_scene *s, const char *name) {
  for (size_t i = 0; i < s->nmaterials; i++)
    if (!strcmp(s->materials[i].name, name)) return &s->materials[i];
  return NULL;
}

vr_status render_overrides_apply(const render_overrides *o, vr_scene *s, vr_error *err) {
  if (o->width) s->camera.width = o->width, s->camera.height = o->height;
  if (o->exposure_given && !o->exposure_auto) s->camera.exposure_ev = o->exposure_ev;
  if (o->seed_given) s->settings.seed = o->seed;
  for (int i = 0; i < o->nsets; i++) {
    const render_set *set = &o->sets[i];
    vr_scene_material *m = material_named(s, set->material);
    if (!m) {
      char names[1024] = "";
      for (size_t j = 0; j < s->nmaterials; j++) {
        strncat(names, j ? ", " : "", sizeof names - strlen(names) - 1);
        strncat(names, s->materials[j].name, sizeof names - strlen(names) - 1);
      }
      return vr_error_set(err, VR_E_NOT_FOUND, "--set '%s': no material \"%s\" in %s (%s%s)",
                          set->text, set->material, s->path,
                          s->nmaterials ? "its materials: " : "it has no material", names);
    }
    if (m->source != VR_MATSRC_DB)
      return vr_error_set(err, VR_E_ARG,
                          "--set '%s': material \"%s\" (%s:%ld) is %s: it has no tint state",
                          set->text, m->name, s->path, m->loc.line,
                          m->source == VR_MATSRC_BLACK      ? "black"
                          : m->source == VR_MATSRC_GLASS    ? "an inline glass"
                          : m->source == VR_MATSRC_TRANSLUCENT ? "a translucent diffuser"
                          : m->source == VR_MATSRC_BSDF_XML ? "a BSDF XML file"
                                                            : "lambert");
    m->state = set->state;
    m->charge_mC_cm2 = NAN;
  }
  return VR_OK;
}

vr_status render_overrides_check_db(const render_overrides *o, const vr_scene *s, vr_matdb *db,
                                    vr_error *err) {
  for (int i = 0; i < o->nsets; i++) {
    const vr_scene_material *m = NULL;
    for (size_t j = 0; j < s->nmaterials && !m; j++)
      if (!strcmp(s->materials[j].name, o->sets[i].material)) m = &s->materials[j];
    if (!m || !db) continue; /* a missing database is reported when the scene is resolved */
    vr_material *dm = NULL;
    if (vr_matdb_load(db, m->db_name, 0, &dm, NULL)) continue; /* idem: named there */
    bool chromo = dm->kind == VR_KIND_CHROMOGENIC;
    vr_material_destroy(dm);
    if (!chromo)
      return vr_error_set(err, VR_E_ARG,
                          "--set '%s': material \"%s\" (db:%s) is not chromogenic glass: it has no "
                          "tint state",
                          o->sets[i].text, m->name, m->db_name);
  }
  return VR_OK;
}

void render_overrides_text(const render_overrides *o, char *out, size_t cap) {
  size_t used = (size_t)snprintf(out, cap, "res=%dx%d ev=%s%.17g seed=%d:%llu", o->width,
                                 o->height, o->exposure_auto ? "auto" : "", o->exposure_ev,
                                 o->seed_given, o->seed);
  for (int i = 0; i < o->nsets && used < cap; i++)
    used += (size_t)snprintf(out + used, cap - used, " set=%s:%.17g", o->sets[i].material,
                             o->sets[i].state);
}

/* ---- options that need the scene ---- */

/* Why a render has no image, or NULL when it has one. */
static const char *no_image_reason(const vr_scene *s, bool sensors_only) {
  return !s->camera.given ? "the scene has no camera"
         : s->sky.annual  ? "an annual study renders no image"
         : sensors_only   ? "--sensors-only renders none"
                          : NULL;
}

vr_status render_options_check(const vr_args *a, const vr_scene *s, vr_error *err) {
  const char *why = no_image_reason(s, vr_args_flag(a, "sensors-only"));
  if (why && vr_args_get(a, "falsecolour"))
    return vr_error_set(err, VR_E_ARG, "%s: --falsecolour maps a camera's image: %s", s->path, why);
  static const char *const IMAGE_ONLY[] = {"resolution", "spp",        "exposure",
                                           "tonemap",    "time-limit", "max-spp"};
  for (size_t i = 0; why && i < sizeof IMAGE_ONLY / sizeof *IMAGE_ONLY; i++)
    if (vr_args_get(a, IMAGE_ONLY[i]))
      return vr_error_set(err, VR_E_ARG, "%s: --%s applies to the camera's image: %s", s->path,
                          IMAGE_ONLY[i], why);
  if (s->sky.annual && vr_args_flag(a, "denoise"))
    return vr_error_set(err, VR_E_ARG,
                        "%s: --denoise filters one render's image; an annual study makes none",
                        s->path);
  if (why && vr_args_flag(a, "denoise"))
    return vr_error_set(err, VR_E_ARG, "%s: --denoise filters the camera's image: %s", s->path, why);
  if (s->sky.annual && vr_args_get(a, "target-error"))
    return vr_error_set(err, VR_E_ARG,
                        "%s: --target-error applies to one render's pixels and path sensors; an "
                        "annual study's daylight coefficients take the scene's sensor_samples",
                        s->path);
  if (s->sky.annual && (vr_args_get(a, "stats") || vr_args_flag(a, "json")))
    return vr_error_set(err, VR_E_ARG,
                        "%s: --%s reports one render; an annual study's results are "
                        "PREFIX.annual.csv and PREFIX.annual-hourly.csv",
                        s->path, vr_args_get(a, "stats") ? "stats" : "json");
  return VR_OK;
}
