/* vr-render's outputs (render_cli.h): which files the user wants
 * (--outputs), and their checks before any work: none may replace a file
 * the run reads (the scene, its meshes, IES and weather files, the material
 * database), two may not be the same file, and each folder must exist and
 * be writable, so that a typo costs a second, not a render. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "render_cli.h"
#include "vr/out_guard.h"

/* ---- which files: --outputs ---- */

static const struct {
  const char *name, *suffix;
  unsigned bit;
} FILES[] = {{"exr", ".exr", VR_FILM_EXR},
             {"spectral", ".spectral.exr", VR_FILM_SPECTRAL},
             {"png", ".png", VR_FILM_PNG},
             {"hdr", ".hdr", VR_FILM_HDR},
             {"sensors", ".sensors.csv", VR_FILM_SENSORS}};
#define NFILES (sizeof FILES / sizeof FILES[0])
#define IMAGES (VR_FILM_EXR | VR_FILM_SPECTRAL | VR_FILM_PNG | VR_FILM_HDR)

int render_outputs_parse(const vr_args *a, unsigned *out) {
  *out = 0;
  const char *list = vr_args_get(a, "outputs");
  bool sensors_only = vr_args_flag(a, "sensors-only");
  if (!list) return 0;
  for (const char *at = list;; at++) {
    size_t n = strcspn(at, ",");
    if (n == 0)
      return render_usage_error("--outputs '%s': an empty name in the list (names are "
                                "separated by single commas)", list);
    unsigned bit = 0;
    for (size_t k = 0; k < NFILES && !bit; k++)
      if (strlen(FILES[k].name) == n && !strncasecmp(at, FILES[k].name, n)) bit = FILES[k].bit;
    if (!bit)
      return render_usage_error("--outputs '%s': unknown output \"%.*s\" (choose among exr, "
                                "spectral, png, hdr, sensors)", list, (int)n, at);
    if (*out & bit)
      return render_usage_error("--outputs '%s': \"%.*s\" is named twice", list, (int)n, at);
    if (sensors_only && (bit & IMAGES))
      return render_usage_error("--outputs '%s': \"%.*s\" is an image, and --sensors-only "
                                "renders none", list, (int)n, at);
    *out |= bit;
    at += n;
    if (!*at) break;
  }
  /* Options that change only files left out are refused, not ignored. */
  if (!(*out & VR_FILM_PNG) && vr_args_get(a, "tonemap"))
    return render_usage_error("--tonemap maps the PNG, which --outputs '%s' leaves out", list);
  if (!(*out & IMAGES) && vr_args_get(a, "exposure"))
    return render_usage_error("--exposure sets the images' exposure, and --outputs '%s' writes "
                              "no image", list);
  return 0;
}

vr_status render_outputs_choose(unsigned asked, const vr_scene *s, bool no_camera,
                                unsigned *out, vr_error *err) {
  unsigned can = (no_camera ? 0u : IMAGES) | (s->nsensors ? VR_FILM_SENSORS : 0u);
  *out = asked ? asked : can & ~(unsigned)VR_FILM_HDR; /* the Radiance picture when asked */
  if (asked && s->sky.annual)
    return vr_error_set(err, VR_E_ARG, "%s: --outputs chooses among the files of one render; "
                        "an annual study writes PREFIX.annual.csv and PREFIX.annual-hourly.csv",
                        s->path);
  for (size_t k = 0; k < NFILES; k++)
    if (asked & FILES[k].bit & ~can)
      return vr_error_set(err, VR_E_ARG, "%s: --outputs names \"%s\", but %s", s->path,
                          FILES[k].name, FILES[k].bit == VR_FILM_SENSORS
                                             ? "the scene has no sensor line"
                                             : "the scene has no camera: there is no image");
  return VR_OK;
}

/* ---- the files and their checks ---- */

static vr_status add(render_outputs *o, const char *a, const char *b, const char *option,
                     vr_error *err) {
  if (o->n == RENDER_MAX_OUTPUTS) return vr_error_set(err, VR_E_ARG, "too many outputs");
  size_t n = strlen(a) + strlen(b) + 1;
  char *p = malloc(n);
  if (!p) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  snprintf(p, n, "%s%s", a, b);
  o->path[o->n] = p;
  o->option[o->n++] = option;
  return VR_OK;
}

void render_outputs_free(render_outputs *o) {
  for (int i = 0; i < o->n; i++) free(o->path[i]);
  o->n = 0;
}

vr_status render_outputs_check(const vr_scene *s, const char *prefix, const char *stats,
                               const char *db_path, unsigned outputs, bool falsecolour,
                               render_outputs *out, vr_error *err) {
  memset(out, 0, sizeof *out);
  vr_out_guard *g = malloc(sizeof *g);
  if (!g) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  vr_out_guard_init(g);
  vr_out_guard_input(g, s->path, "the scene");
  if (s->sky.weather_path) vr_out_guard_input(g, s->sky.weather_path, "the weather file");
  if (s->annual.occupancy_path)
    vr_out_guard_input(g, s->annual.occupancy_path, "the occupancy schedule");
  for (size_t i = 0; i < s->nsensors; i++)
    if (s->sensors[i].pts_path) vr_out_guard_input(g, s->sensors[i].pts_path, "a sensor points file");
  for (size_t i = 0; i < s->nlights; i++)
    if (s->lights[i].ies_path) vr_out_guard_input(g, s->lights[i].ies_path, "an IES file");
  for (size_t i = 0; i < s->nobjects; i++)
    if (s->objects[i].mesh_path) vr_out_guard_input(g, s->objects[i].mesh_path, "a mesh");
  vr_out_guard_database(g, db_path);

  vr_status st = VR_OK;
  if (s->sky.annual) {
    if (!(st = add(out, prefix, ".annual.csv", "-o", err)))
      st = add(out, prefix, ".annual-hourly.csv", "-o", err);
    if (!st && s->annual.nviews) st = add(out, prefix, ".annual-glare.csv", "-o", err);
    if (!st) st = add(out, prefix, ".manifest.json", "-o", err);
  } else {
    /* In the order the film writes them. */
    for (size_t k = 0; !st && k < NFILES; k++) {
      if (outputs & FILES[k].bit) st = add(out, prefix, FILES[k].suffix, "-o", err);
      if (!st && FILES[k].bit == VR_FILM_PNG && falsecolour)
        st = add(out, prefix, ".falsecolour.png", "-o", err);
    }
    if (!st) st = add(out, prefix, ".manifest.json", "-o", err);
    if (!st && stats) st = add(out, stats, "", "--stats", err);
  }
  for (int i = 0; !st && i < out->n; i++) {
    char option[64];
    snprintf(option, sizeof option, "%s", out->option[i]);
    st = vr_out_guard_check(g, out->path[i], option, err);
  }
  for (int i = 0; !st && stats && i + 1 < out->n; i++)
    st = vr_out_guard_distinct(stats, "--stats", out->path[i], "-o", err);
  free(g);
  if (st) render_outputs_free(out);
  return st;
}

/* ---- the set afterwards ---- */

static void verify_line(void *user, const char *line) {
  (void)user;
  printf("%s\n", line);
}

int render_verify(const char *prefix, bool quiet) {
  vr_film_check c;
  vr_error err = {0};
  if (vr_film_verify(prefix, quiet ? NULL : verify_line, NULL, &c, &err)) {
    fprintf(stderr, "vr-render: %s\n", err.message);
    return 1;
  }
  if (!quiet)
    printf("verified %s: the %d files of run %s match %s.manifest.json\n", prefix, c.files,
           c.run_id, prefix);
  return 0;
}

void render_clean_stale(const char *prefix, const char *stats,
                        void (*log)(void *user, const char *line), void *user) {
  const char *names[2] = {prefix, stats};
  for (int i = 0; i < 2; i++) {
    char removed[4096], line[4400];
    if (names[i] && vr_film_clean_stale(names[i], removed, sizeof removed)) {
      snprintf(line, sizeof line, "removed what a killed run left: %s", removed);
      log(user, line);
    }
  }
}
