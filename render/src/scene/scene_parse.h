/* Shared by the scene parser's files: the parser's state, a statement and
 * its checked options (scene_parse.c), the statements themselves
 * (scene_parse_shapes.c, scene_parse_lights.c) and the readers of numbers,
 * lengths, vectors, light quantities, spectrum references and transforms
 * (scene_parse_values.c).  Every reader takes the whole word ("radius=5cm")
 * for the column and the message, and the value part to read. */
#ifndef VR_SCENE_PARSE_H
#define VR_SCENE_PARSE_H

#include <stdbool.h>
#include <stddef.h>
#include <string.h>

#include "vr/vec3.h"
#include "vr/scene.h"

typedef struct vr_scn_parser {
  vr_scene *s;
  const char *file;  /* for messages */
  long line;
  const char *text;  /* the current line, for columns */
  vr_error *err;
  char **alias;      /* per object: its material= name until resolved (NULL: a mesh
                        without one, whose materials come from its file) */
  vr_scene_loc *alias_loc;
  size_t nalias;     /* objects with an alias slot (the parser's objects) */
  struct vr_scn_mesh_map *maps; /* mesh lines' material.NAME=ALIAS, in order */
  size_t nmaps;
  size_t sun;        /* index + 1 of the sun light, 0 if none */
  char *annual_glass, *annual_sensor; /* annual glass= and control_sensor= until resolved */
  char *annual_shade, *annual_window;  /* annual shade= and window= until resolved */
  vr_scene_loc annual_shade_loc, annual_window_loc;
  vr_scene_loc annual_glass_loc, annual_sensor_loc;
  char *annual_workplane;             /* annual workplane= until resolved */
  char *annual_views;                 /* annual glare_views= until resolved */
  vr_scene_loc annual_views_loc;
  vr_scene_loc annual_workplane_loc;
  bool have_render;
} vr_scn_parser;

#define SCN_MAX_WORDS 64

/* One statement: its words, and its key=value options once checked. */
typedef struct vr_scn_opt {
  const char *word, *val;
  size_t klen;
} vr_scn_opt;

typedef struct vr_scn_stmt {
  vr_scn_parser *p;
  char **w;
  size_t nw;
  vr_scn_opt o[SCN_MAX_WORDS];
  size_t no;
  const char *what; /* "a sphere", for messages */
} vr_scn_stmt;

/* The statements (w[0] is the keyword). */
vr_status scn_camera(vr_scn_stmt *t);
vr_status scn_material(vr_scn_stmt *t);
vr_status scn_object(vr_scn_stmt *t, vr_shape_kind kind);
vr_status scn_light(vr_scn_stmt *t);
/* The kinds of light and the integrators a scene may name are units
 * registered above the grammar; the grammar reaches them through these two
 * functions, which their registries define (lights/light.c,
 * integrators/registry.c), so adding a kind touches no file here. */
typedef struct vr_scn_light_syntax {
  const char *name; /* the word after 'light' */
  /* Reads the line's options into l (its kind, loc and defaults set). */
  vr_status (*parse)(vr_scn_stmt *t, vr_scene_light *l);
  bool unique;      /* at most one in a scene */
  bool sun;         /* the sun a weather sky places (scn_sky_finish) */
} vr_scn_light_syntax;
/* Light kind `kind` (vr_scene_light.kind); false past the last. */
bool vr_scn_light_kind(size_t kind, vr_scn_light_syntax *out);
/* The name of integrator i (vr_scene_settings.integrator), NULL past the
 * last; and its own rules for the render line once the common options are
 * read (NULL: none): *spp and *wavelengths may be changed. */
typedef vr_status (*vr_scn_settings_rule)(const vr_scn_stmt *t, vr_scene_settings *g,
                                          long long *spp, long long *wavelengths);
const char *vr_scn_integrator(size_t i, vr_scn_settings_rule *rule);
vr_status scn_sky(vr_scn_stmt *t);
vr_status scn_portal(vr_scn_stmt *t);
/* The sky's last pass, once the whole file is read: the sun it follows,
 * a Perez sky's model and the sun's illuminance from it. */
vr_status scn_sky_finish(vr_scn_parser *p);

/* Calendar and clock helpers shared by the sun and the weather sky. */
int scn_month_days(int y, int m);
int scn_day_of_year(int y, int m, int d);
/* time=HH:MM[:SS] as minutes of the day. */
vr_status scn_clock_time(vr_scn_parser *p, const vr_scn_opt *o, double *minutes);
/* The sun's direction at a site and local civil time (minutes of the day
 * in a zone tz hours east of UTC); below the horizon is an error at word,
 * "when" naming the instant in the message. */
vr_status scn_sun_at(vr_scn_parser *p, const char *word, const char *when, double lat, double lon,
                     double tz, int y, int m, int d, double minutes, double dir[3]);
vr_status scn_sensor(vr_scn_stmt *t);
vr_status scn_render(vr_scn_stmt *t);
/* The 'annual' line (scene_parse_annual.c) and its checks once the whole
 * file is read (the glass, the control sensor, the weather sky). */
vr_status scn_annual(vr_scn_stmt *t);
vr_status scn_annual_finish(vr_scn_parser *p);

/* Checks the words from `first` on: key=value, a key in `allowed` (NULL
 * terminated), given once (translate/rotate/scale may repeat: they compose). */
vr_status scn_options(vr_scn_stmt *t, size_t first, const char *const *allowed);
bool scn_is_transform(const char *key, size_t n);
/* The option `key`, or NULL when not given. */
const vr_scn_opt *scn_get(const vr_scn_stmt *t, const char *key);
/* The same, an error naming the statement when it is missing. */
vr_status scn_need(const vr_scn_stmt *t, const char *key, const vr_scn_opt **o);
/* The later of two words on the line, to blame when both are given. */
const char *scn_later(const vr_scn_opt *a, const vr_scn_opt *b);
/* The words 1..n before the options; `what` says what they should be. */
vr_status scn_positional(const vr_scn_stmt *t, size_t n, const char *what);
/* Grows an array by one zeroed element; NULL when out of memory. */
void *scn_grow(void **arr, size_t *n, size_t size);
/* Readers of an option when it is given (*out untouched otherwise). */
vr_status scn_range(const vr_scn_stmt *t, const char *key, double lo, double hi, bool open_lo,
                    bool open_hi, double *out);
vr_status scn_int_opt(const vr_scn_stmt *t, const char *key, long long lo, long long hi, long long *out);
vr_status scn_spectrum_opt(const vr_scn_stmt *t, const char *key, vr_spectrum_ref *out);
/* One of the words in `names` (NULL terminated); *out its index. */
vr_status scn_choice(const vr_scn_stmt *t, const char *key, const char *const *names, int *out);
/* Readers of a given option. */
vr_status scn_positive_length(const vr_scn_stmt *t, const vr_scn_opt *o, double *out);
vr_status scn_point(const vr_scn_stmt *t, const vr_scn_opt *o, double out[3]);

/* VR_E_PARSE "file:line:col: message", the column of `at` in the line. */
vr_status scn_fail(const vr_scn_parser *p, const char *at, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
vr_status scn_nomem(const vr_scn_parser *p);
vr_scene_loc scn_loc(const vr_scn_parser *p, const char *at);

/* A finite decimal number, nothing after it. */
vr_status scn_number(const vr_scn_parser *p, const char *word, const char *v, double *out);
/* A length in metres: a number with an optional unit m, cm or mm. */
vr_status scn_length(const vr_scn_parser *p, const char *word, const char *v, double *out);
/* n comma-separated numbers (lengths with units when `length`). */
vr_status scn_numbers(const vr_scn_parser *p, const char *word, const char *v, bool length, int n,
                      double *out);
/* X,Y,Z normalised to unit length; a zero vector is an error. */
vr_status scn_direction(const vr_scn_parser *p, const char *word, const char *v, double out[3]);
/* n integers in [lo, hi] separated by sep ("640x480", "16,16"); a number in
 * exponent notation is accepted when it is a whole number ("1e6"). */
vr_status scn_ints(const vr_scn_parser *p, const char *word, const char *v, char sep, int n, long long lo,
                   long long hi, long long *out);
vr_status scn_u64(const vr_scn_parser *p, const char *word, const char *v, unsigned long long *out);
/* A number followed by a light unit among `allowed` (VR_UNIT_NONE ends the
 * list); no unit gives `dflt`, or an error when dflt is VR_UNIT_NONE.  The
 * value must not be negative.  `what` names the quantity for messages. */
vr_status scn_quantity(const vr_scn_parser *p, const char *word, const char *v,
                       const vr_light_unit *allowed, vr_light_unit dflt, const char *what,
                       vr_quantity *out);
/* db:NAME, bb:KELVIN, a CIE illuminant name or an inline table "[...]";
 * *out receives a copy. */
vr_status scn_spectrum(const vr_scn_parser *p, const char *word, const char *v, vr_spectrum_ref *out);
/* An inline spectrum "[W:V,...]" or "[W V ...]" (scene_spectrum.c): its
 * points, values in [0, vmax]; false with the offset in text of the entry
 * at fault and a message. */
typedef struct vr_scn_inline {
  size_t n;
  double *nm, *v;
  size_t at;
  char msg[256];
} vr_scn_inline;
bool scn_inline_read(const char *text, double vmax, vr_scn_inline *out);
void scn_inline_free(vr_scn_inline *s);
/* The same checks on the value v of word ("reflectance=[...]"), an error
 * at the entry at fault that names the option. */
vr_status scn_inline_check(const vr_scn_parser *p, const char *word, const char *v, double vmax);
/* A mesh line's material.PATTERN=ALIAS until the aliases are resolved. */
typedef struct vr_scn_mesh_map {
  size_t object;
  char *pattern, *alias;
  vr_scene_loc loc;
  char *file;      /* from materials=FILE (loc: its line there), else NULL */
} vr_scn_mesh_map;
/* scene_mapfile.c: a mesh line's materials=FILE (option o) as maps of the
 * line's object, after its material.PATTERN= options; errors name the file
 * and its line. */
vr_status scn_map_file(vr_scn_stmt *t, const vr_scn_opt *o, size_t object);

/* The index of the material named name, or -1. */
int scn_material_index(const vr_scene *s, const char *name);

/* scene_colour.c: a lambert line's color=#RRGGBB or rgb=R,G,B [space=srgb|linear]
 * as an inline reflectance spectrum (new string in *spectrum). */
vr_status scn_colour(vr_scn_stmt *t, char **spectrum);
/* A lambert line's texture=FILE [colorspace=srgb|linear] [alpha=off|mask|blend]
 * [alpha_cutoff=A], normal_map=FILE [normal_scale=S] and tile=N|NU,NV (for
 * both) into m; the files must be readable regular files.  Options without
 * the file they go with are refused. */
vr_status scn_texture(vr_scn_stmt *t, vr_scene_material *m);
/* A pbr line's metallic=, roughness= (required) and metallic_roughness=FILE. */
vr_status scn_pbr(vr_scn_stmt *t, vr_scene_material *m);
/* Applies translate=, rotate= or scale= (key) after *x. */
vr_status scn_transform(const vr_scn_parser *p, const char *word, const char *key, const char *v,
                        vr_xform *x);
/* A path relative to the scene's folder; absolute paths are kept.  NULL when
 * out of memory. */
char *scn_resolve(const vr_scene *s, const char *rel);
/* A Radiance sensor points file (sensor_pts.c): *n points of 6 doubles. */
vr_status scn_read_pts(const char *path, double **out, int *n, vr_error *err);

#endif
