/* The scene file (docs/scene-format.md): one statement per line, split into
 * words, each statement's options checked against the ones it takes
 * (scene_parse_shapes.c and scene_parse_lights.c read them, with the value
 * readers of scene_parse_values.c).  Material names used by objects are
 * resolved once the whole file is read, so materials may be defined in any
 * order; the sky takes the sun's direction the same way.  Every error names
 * the file, line and column of the word at fault. */
#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scene/scene_parse.h"
#include "vr/sky.h"
#include "vr/file.h"

void vr_scene_destroy(vr_scene *s) {
  if (!s) return;
  for (size_t i = 0; i < s->nmaterials; i++) {
    free(s->materials[i].name);
    free(s->materials[i].db_name);
    free(s->materials[i].coating_db);
    free(s->materials[i].bsdf_file);
    free(s->materials[i].reflectance_spectrum);
    free(s->materials[i].transmission);
    free(s->materials[i].texture);
    free(s->materials[i].texture_bytes);
    free(s->materials[i].normal_map);
    free(s->materials[i].normal_bytes);
    free(s->materials[i].mr_map);
    free(s->materials[i].mr_bytes);
    free(s->materials[i].alpha_map);
    free(s->materials[i].alpha_map_bytes);
  }
  for (size_t i = 0; i < s->nobjects; i++) {
    free(s->objects[i].name);
    free(s->objects[i].mesh_path);
    free(s->objects[i].emission_spectrum);
  }
  for (size_t i = 0; i < s->nlights; i++) {
    free(s->lights[i].ies_path);
    free(s->lights[i].spectrum);
  }
  for (size_t i = 0; i < s->nsensors; i++) {
    free(s->sensors[i].name);
    free(s->sensors[i].pts);
    free(s->sensors[i].pts_path);
  }
  for (size_t i = 0; i < s->nmesh_maps; i++) free(s->mesh_maps[i].pattern), free(s->mesh_maps[i].file);
  free(s->mesh_maps);
  for (size_t i = 0; i < s->nnotes; i++) free(s->notes[i]);
  free(s->notes);
  free(s->sky.spectrum);
  free(s->sky.weather_path);
  free(s->annual.occupancy_path);
  free(s->portals);
  free(s->materials);
  free(s->objects);
  free(s->lights);
  free(s->sensors);
  free(s->path);
  free(s->dir);
  free(s);
}

bool scn_is_transform(const char *key, size_t n) {
  return (n == 9 && !strncmp(key, "translate", 9)) || (n == 6 && !strncmp(key, "rotate", 6)) ||
         (n == 5 && !strncmp(key, "scale", 5));
}

/* Checks the words from `first` on: key=value, a key in `allowed` (a NULL
 * terminated list), given once (transforms may repeat: they compose). */
vr_status scn_options(vr_scn_stmt *t, size_t first, const char *const *allowed) {
  const vr_scn_parser *p = t->p;
  for (size_t i = first; i < t->nw; i++) {
    const char *w = t->w[i], *eq = strchr(w, '=');
    if (!eq || eq == w)
      return scn_fail(p, w, "unexpected \"%s\" in %s (options are key=value)", w, t->what);
    size_t k = (size_t)(eq - w);
    bool known = false;
    for (size_t a = 0; allowed[a] && !known; a++) {
      size_t n = strlen(allowed[a]);
      /* "material.*" allows material.NAME= for any NAME. */
      if (n > 2 && !strcmp(allowed[a] + n - 2, ".*")) known = k > n - 1 && !strncmp(allowed[a], w, n - 1);
      else known = n == k && !strncmp(allowed[a], w, k);
    }
    if (!known) {
      char list[512];
      size_t used = 0;
      list[0] = '\0';
      for (size_t a = 0; allowed[a] && used < sizeof list - 1; a++) {
        size_t n = strlen(allowed[a]);
        if (used + n + 3 >= sizeof list) break;
        if (a) memcpy(list + used, ", ", 2), used += 2;
        memcpy(list + used, allowed[a], n + 1), used += n;
      }
      return scn_fail(p, w, "unknown option \"%.*s\" for %s (%s)", (int)k, w, t->what,
                      used ? list : "it takes none");
    }
    if (!eq[1]) return scn_fail(p, w, "%s has no value", w);
    if (!scn_is_transform(w, k))
      for (size_t j = 0; j < t->no; j++)
        if (t->o[j].klen == k && !strncmp(t->o[j].word, w, k))
          return scn_fail(p, w, "%.*s= is given twice (first at column %ld)", (int)k, w,
                          scn_loc(p, t->o[j].word).col);
    t->o[t->no++] = (vr_scn_opt){w, eq + 1, k};
  }
  return VR_OK;
}

const vr_scn_opt *scn_get(const vr_scn_stmt *t, const char *key) {
  size_t k = strlen(key);
  for (size_t i = 0; i < t->no; i++)
    if (t->o[i].klen == k && !strncmp(t->o[i].word, key, k)) return &t->o[i];
  return NULL;
}

vr_status scn_need(const vr_scn_stmt *t, const char *key, const vr_scn_opt **o) {
  *o = scn_get(t, key);
  return *o ? VR_OK : scn_fail(t->p, t->w[0], "%s needs %s=", t->what, key);
}

int scn_material_index(const vr_scene *s, const char *name) {
  for (size_t j = 0; j < s->nmaterials; j++)
    if (!strcmp(s->materials[j].name, name)) return (int)j;
  return -1;
}

/* The later of two words on the line, to blame when both are given. */
const char *scn_later(const vr_scn_opt *a, const vr_scn_opt *b) { return a->word > b->word ? a->word : b->word; }

/* The words 1..n before the options; `what` says what they should be. */
vr_status scn_positional(const vr_scn_stmt *t, size_t n, const char *what) {
  for (size_t i = 1; i <= n; i++)
    if (i >= t->nw || strchr(t->w[i], '='))
      return scn_fail(t->p, i < t->nw ? t->w[i] : t->w[0], "'%s' needs %s", t->w[0], what);
  return VR_OK;
}

/* Grows an array by one zeroed element; NULL when out of memory. */
void *scn_grow(void **arr, size_t *n, size_t size) {
  void *g = realloc(*arr, (*n + 1) * size);
  if (!g) return NULL;
  *arr = g;
  void *e = (char *)g + *n * size;
  memset(e, 0, size);
  (*n)++;
  return e;
}

/* Helpers reading an option when it is given. */
vr_status scn_range(const vr_scn_stmt *t, const char *key, double lo, double hi, bool open_lo,
                       bool open_hi, double *out) {
  const vr_scn_opt *o = scn_get(t, key);
  if (!o) return VR_OK;
  double x;
  vr_status st = scn_number(t->p, o->word, o->val, &x);
  if (st) return st;
  if (x < lo || x > hi || (open_lo && x == lo) || (open_hi && x == hi))
    return scn_fail(t->p, o->word, "\"%s\": must be in %c%g, %g%c", o->word, open_lo ? '(' : '[',
                    lo, hi, open_hi ? ')' : ']');
  *out = x;
  return VR_OK;
}

vr_status scn_positive_length(const vr_scn_stmt *t, const vr_scn_opt *o, double *out) {
  vr_status st = scn_length(t->p, o->word, o->val, out);
  if (!st && !(*out > 0)) st = scn_fail(t->p, o->word, "\"%s\": must be positive", o->word);
  return st;
}

vr_status scn_int_opt(const vr_scn_stmt *t, const char *key, long long lo, long long hi, long long *out) {
  const vr_scn_opt *o = scn_get(t, key);
  return o ? scn_ints(t->p, o->word, o->val, ',', 1, lo, hi, out) : VR_OK;
}

vr_status scn_point(const vr_scn_stmt *t, const vr_scn_opt *o, double out[3]) {
  return scn_numbers(t->p, o->word, o->val, true, 3, out);
}

vr_status scn_spectrum_opt(const vr_scn_stmt *t, const char *key, vr_spectrum_ref *out) {
  const vr_scn_opt *o = scn_get(t, key);
  return o ? scn_spectrum(t->p, o->word, o->val, out) : VR_OK;
}

/* One of the words in `names` (NULL terminated); *out its index. */
vr_status scn_choice(const vr_scn_stmt *t, const char *key, const char *const *names, int *out) {
  const vr_scn_opt *o = scn_get(t, key);
  if (!o) return VR_OK;
  for (int i = 0; names[i]; i++)
    if (!strcmp(o->val, names[i])) return *out = i, VR_OK;
  char list[256] = "";
  for (int i = 0; names[i]; i++) {
    strncat(list, i ? ", " : "", sizeof list - strlen(list) - 1);
    strncat(list, names[i], sizeof list - strlen(list) - 1);
  }
  return scn_fail(t->p, o->word, "\"%s\": expected %s", o->word, list);
}

static vr_status statement(vr_scn_parser *p, char **w, size_t nw) {
  vr_scn_stmt t = {.p = p, .w = w, .nw = nw, .what = w[0]};
  const char *kw = w[0];
  if (!strcmp(kw, "camera")) return scn_camera(&t);
  if (!strcmp(kw, "material")) return scn_material(&t);
  if (!strcmp(kw, "sphere")) return scn_object(&t, VR_SHAPE_SPHERE);
  if (!strcmp(kw, "rect") || !strcmp(kw, "plane")) return scn_object(&t, VR_SHAPE_RECT);
  if (!strcmp(kw, "box")) return scn_object(&t, VR_SHAPE_BOX);
  if (!strcmp(kw, "mesh")) return scn_object(&t, VR_SHAPE_MESH);
  if (!strcmp(kw, "light")) return scn_light(&t);
  if (!strcmp(kw, "sky")) return scn_sky(&t);
  if (!strcmp(kw, "portal")) return scn_portal(&t);
  if (!strcmp(kw, "sensor")) return scn_sensor(&t);
  if (!strcmp(kw, "render")) return scn_render(&t);
  if (!strcmp(kw, "annual")) return scn_annual(&t);
  return scn_fail(p, kw,
                  "unknown statement \"%s\" (camera, material, sphere, rect, box, mesh, light, sky, "
                  "portal, sensor, render, annual)",
                  kw);
}

/* What needs the whole file: material names, the sky's sun, something to render. */
static vr_status finish(vr_scn_parser *p) {
  vr_scene *s = p->s;
  for (size_t i = 0; i < p->nalias; i++) {
    if (!p->alias[i]) continue; /* a mesh that takes its materials from its file */
    int m = scn_material_index(s, p->alias[i]);
    if (m < 0)
      return vr_error_at(p->err, VR_E_PARSE, p->file, p->alias_loc[i].line, p->alias_loc[i].col,
                         "unknown material \"%s\" (no 'material %s ...' line)", p->alias[i], p->alias[i]);
    s->objects[i].material = m;
  }
  /* material.PATTERN=NAME: the names resolved, the patterns kept for
   * vr_scene_load_models, which reads the files. */
  if (p->nmaps && !(s->mesh_maps = calloc(p->nmaps, sizeof *s->mesh_maps))) return scn_nomem(p);
  for (size_t k = 0; k < p->nmaps; k++) {
    vr_scn_mesh_map *m = &p->maps[k];
    int idx = scn_material_index(s, m->alias);
    if (idx < 0)
      return vr_error_at(p->err, VR_E_PARSE, m->file ? m->file : p->file, m->loc.line, m->loc.col,
                         "unknown material \"%s\" (no 'material %s ...' line in %s)", m->alias,
                         m->alias, p->file);
    s->mesh_maps[k] = (vr_scene_mesh_map){m->object, m->pattern, idx, m->loc, m->file};
    m->pattern = NULL, m->file = NULL; /* the scene's now */
    s->nmesh_maps = k + 1;
  }
  vr_status st = scn_sky_finish(p);
  if (st) return st;
  if ((st = scn_annual_finish(p))) return st;
  if (!s->camera.given && s->nsensors == 0)
    return vr_error_at(p->err, VR_E_PARSE, p->file, 0, 0, "no camera and no sensor: nothing to render");
  return VR_OK;
}

/* The integrator a render line without integrator= gets. */
#define DEFAULT_INTEGRATOR "photon"

static vr_integrator default_integrator(void) {
  vr_scn_settings_rule rule;
  const char *name;
  size_t i = 0;
  while ((name = vr_scn_integrator(i, &rule)) && strcmp(name, DEFAULT_INTEGRATOR)) i++;
  return (vr_integrator)i;
}

static void defaults(vr_scene *s) {
  vr_scene_camera *c = &s->camera;
  c->to[1] = 1, c->up[2] = 1;
  c->fov_deg = 60, c->width = 320, c->height = 240, c->focus_m = 1;
  vr_filter_init(&c->filter, VR_FILTER_BOX, 0.5, 0);
  s->sky.sun_direction[2] = 1;
  s->sky.ground_reflectance = 0.2;
  s->sky.dew_point_c = NAN;
  vr_scene_settings *g = &s->settings;
  g->integrator = default_integrator(), g->spp = 16, g->max_depth = 8, g->spectral = VR_SPECTRAL_HERO;
  g->wavelengths = 4, g->lambda_min = 360, g->lambda_max = 830;
  g->photons = g->caustic_photons = 200000, g->knn = 50, g->sensor_knn = 50, g->radius_m = NAN;
  g->final_gather = false, g->gather_rays = 32, g->passes = 16, g->alpha = 2.0 / 3.0;
  g->sensor_samples = 4096, g->seed = 1, g->sampler = VR_SAMPLER_SOBOL;
  g->film_min_nm = 400, g->film_max_nm = 700, g->film_step_nm = 10;
  vr_scene_annual *a = &s->annual;
  a->from_h = 8, a->to_h = 18, a->da_lx = 300, a->sda_share = 0.5;
  a->udi_lo = 100, a->udi_hi = 3000, a->ase_lx = 1000, a->ase_hours = 250;
  a->glass = -1, a->control_sensor = -1, a->workplane = -1, a->max = NAN;
  a->view_resolution = 64;
  a->edmed_lx = NAN, a->shade = a->shade_window = -1;
}

bool vr_scene_has_grid(const vr_scene *s) {
  for (size_t i = 0; i < s->nsensors; i++)
    if (s->sensors[i].grid) return true;
  return false;
}

bool vr_scene_photon_portals(const vr_scene *s) {
  if (s->settings.photon_portals_given) return s->settings.photon_portals;
  return s->settings.sensors == VR_SENSORS_PHOTON && s->nsensors > 0 && s->nportals > 0;
}

/* Splits a line into words in place; the rest of the line after '#' is a
 * comment, unless the '#' opens a value ("color=#c8b49a").  A value that
 * opens with '[' ("spectrum=[400 0.1 700 0.5]") runs to its ']', spaces
 * and all: pbrt-v4's inline spectra have spaces. */
static vr_status words(vr_scn_parser *p, char *line, char **w, size_t *nw) {
  char *hash = strchr(line, '#');
  while (hash && hash > line && hash[-1] == '=') hash = strchr(hash + 1, '#');
  if (hash) *hash = '\0';
  *nw = 0;
  for (char *q = line; *q;) {
    while (*q && isspace((unsigned char)*q)) *q++ = '\0';
    if (!*q) break;
    if (*nw == SCN_MAX_WORDS) return scn_fail(p, q, "more than %d words on a line", SCN_MAX_WORDS);
    w[(*nw)++] = q;
    bool bracket = false;
    for (; *q && (bracket || !isspace((unsigned char)*q)); q++) {
      if (*q == '[' && q > w[*nw - 1] && q[-1] == '=') bracket = true;
      else if (*q == ']') bracket = false;
    }
  }
  return VR_OK;
}

/* The render line given on the command line (vr_scene_parse_with): parsed
 * by the file's own grammar once the file is read, over the defaults, its
 * messages naming "--render" and the column in that text. */
static vr_status render_line(vr_scn_parser *p, const vr_scene_settings *dflt, const char *text) {
  static const char WHERE[] = "--render";
  size_t n = strlen(text);
  char *line = malloc(n + 8);
  if (!line) return scn_nomem(p);
  memcpy(line, "render ", 7);
  memcpy(line + 7, text, n + 1);
  p->s->settings = *dflt;
  p->have_render = false;
  p->file = WHERE, p->line = 1, p->text = line + 7; /* columns counted in the option text */
  char *w[SCN_MAX_WORDS];
  size_t nw;
  vr_status st = VR_OK;
  if (memchr(text, '\n', n) || strchr(text, '#'))
    st = scn_fail(p, line + 7 + strcspn(text, "\n#"), "one render line's options: no line break or comment");
  if (!st) st = words(p, line, w, &nw);
  if (!st) {
    vr_scn_stmt t = {.p = p, .w = w, .nw = nw, .what = "render"};
    st = scn_render(&t);
  }
  if (!st) p->s->settings.source = WHERE, p->s->settings.loc = (vr_scene_loc){1, 1};
  free(line);
  return st;
}

vr_status vr_scene_parse(const char *text, size_t len, const char *name, vr_scene **out, vr_error *err) {
  return vr_scene_parse_with(text, len, name, NULL, out, err);
}

vr_status vr_scene_parse_with(const char *text, size_t len, const char *name, const char *render,
                              vr_scene **out, vr_error *err) {
  if (!out) return vr_error_set(err, VR_E_ARG, "vr_scene_parse: no place for the result");
  *out = NULL;
  if (!text && len) return vr_error_set(err, VR_E_ARG, "vr_scene_parse: no text");
  if (!text) text = "";
  if (!name) name = "<scene>";
  vr_scene *s = calloc(1, sizeof *s);
  if (!s) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  defaults(s);
  const vr_scene_settings dflt = s->settings;
  s->path = strdup(name);
  const char *slash = strrchr(name, '/');
  s->dir = !slash ? strdup(".") : slash == name ? strdup("/") : strndup(name, (size_t)(slash - name));
  vr_scn_parser p = {.s = s, .file = name, .err = err};
  vr_status st = (s->path && s->dir) ? VR_OK : scn_nomem(&p);
  char *line = NULL, *w[SCN_MAX_WORDS];
  size_t cap = 0, nw;
  const char *c = text, *end = text + len;
  /* A UTF-8 byte order mark, as some Windows editors write it: not text. */
  if (len >= 3 && !memcmp(text, "\xEF\xBB\xBF", 3)) c += 3;
  while (!st && c < end) {
    const char *start = c, *e = memchr(c, '\n', (size_t)(end - c));
    if (!e) e = end;
    size_t n = (size_t)(e - start);
    c = e < end ? e + 1 : end;
    p.line++;
    if (n && start[n - 1] == '\r') n--; /* CRLF */
    if (n + 1 > cap) {
      char *g = realloc(line, n + 1);
      if (!g) {
        st = scn_nomem(&p);
        break;
      }
      line = g, cap = n + 1;
    }
    memcpy(line, start, n);
    line[n] = '\0';
    p.text = line;
    const char *nul = memchr(line, '\0', n);
    if (nul) st = scn_fail(&p, nul, "a NUL byte in the text");
    else if (!(st = words(&p, line, w, &nw)) && nw) st = statement(&p, w, nw);
  }
  free(line);
  /* The command line's render line replaces the file's, which was read
   * (and checked) like any other line. */
  if (!st && render) {
    const char *file = p.file;
    st = render_line(&p, &dflt, render);
    p.file = file, p.line = 0;
  }
  if (!st) st = finish(&p);
  for (size_t i = 0; i < p.nalias; i++) free(p.alias[i]);
  free(p.alias);
  for (size_t i = 0; i < p.nmaps; i++)
    free(p.maps[i].pattern), free(p.maps[i].alias), free(p.maps[i].file);
  free(p.maps);
  free(p.alias_loc);
  free(p.annual_glass);
  free(p.annual_sensor);
  free(p.annual_workplane);
  free(p.annual_views);
  free(p.annual_shade);
  free(p.annual_window);
  if (st) {
    vr_scene_destroy(s);
    return st;
  }
  *out = s;
  return VR_OK;
}

vr_status vr_scene_read(const char *path, vr_scene **out, vr_error *err) {
  return vr_scene_read_with(path, NULL, out, err);
}

vr_status vr_scene_read_with(const char *path, const char *render, vr_scene **out, vr_error *err) {
  if (!out) return vr_error_set(err, VR_E_ARG, "vr_scene_read: no place for the result");
  *out = NULL;
  char *text;
  size_t n;
  vr_status st = vr_read_file(path, 64u << 20, &text, &n, err);
  if (st) return st;
  if ((st = vr_text_check_encoding(text, n, path, err))) {
    free(text);
    return st;
  }
  st = vr_scene_parse_with(text, n, path, render, out, err);
  free(text);
  return st;
}


