/* vr-render's outputs, all checked before any work (render_cli.h): none may
 * replace a file the run reads (the scene, its meshes, IES and weather
 * files, the material database), two may not be the same file, and each
 * folder must exist and be writable, so that a typo costs a second, not a
 * render. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render_cli.h"
#include "vr/out_guard.h"

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
                               const char *db_path, bool image, bool falsecolour,
                               render_outputs *out, vr_error *err) {
  memset(out, 0, sizeof *out);
  vr_out_guard *g = malloc(sizeof *g);
  if (!g) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  vr_out_guard_init(g);
  vr_out_guard_input(g, s->path, "the scene");
  if (s->sky.weather_path) vr_out_guard_input(g, s->sky.weather_path, "the weather file");
  for (size_t i = 0; i < s->nlights; i++)
    if (s->lights[i].ies_path) vr_out_guard_input(g, s->lights[i].ies_path, "an IES file");
  for (size_t i = 0; i < s->nobjects; i++)
    if (s->objects[i].mesh_path) vr_out_guard_input(g, s->objects[i].mesh_path, "a mesh");
  vr_out_guard_database(g, db_path);

  vr_status st = VR_OK;
  static const char *const IMAGE[] = {".exr", ".spectral.exr", ".png"};
  if (s->sky.annual) {
    if (!(st = add(out, prefix, ".annual.csv", "-o", err)))
      st = add(out, prefix, ".annual-hourly.csv", "-o", err);
  } else {
    for (int i = 0; image && !st && i < 3; i++) st = add(out, prefix, IMAGE[i], "-o", err);
    if (!st && image && falsecolour) st = add(out, prefix, ".falsecolour.png", "-o", err);
    if (!st && s->nsensors) st = add(out, prefix, ".sensors.csv", "-o", err);
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
