/* What the files of vr-render share (render/tools/): the command line's
 * overrides of the scene (render_overrides.c), the choice of its outputs
 * and their checks against its inputs (render_outputs.c) and its results on stdout as text
 * or JSON (render_report.c), an annual study's summary (render_annual.c).
 * vr_render.c holds main. */
#ifndef VR_RENDER_CLI_H
#define VR_RENDER_CLI_H

#include <stdbool.h>
#include <stddef.h>

#include "vr/args.h"
#include "vr/error.h"
#include "vr/film.h"
#include "vr/render.h"
#include "vr/scene.h"

typedef struct vr_matdb vr_matdb;
struct vr_annual_result;

/* ---- render_annual.c ---- */

/* The summary of an annual study on stdout: its renders, the glass or
 * shade, sDA, ASE, UDI over the work plane, EN 17037's levels, each point
 * and the files written under prefix. */
void render_annual_report(const vr_scene *scene, const struct vr_annual_result *res,
                          const char *prefix);

/* Prints "vr-render: MESSAGE" and the --help hint; returns 2, the exit
 * status of a usage error (vr_render.c). */
int render_usage_error(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

/* ---- render_overrides.c ---- */

#define RENDER_MAX_SETS 64

typedef struct render_set {
  const char *text;   /* as given: "ec.state=0.5" */
  char material[256];
  double state;
} render_set;

/* What the command line changes in the scene after it is parsed. */
typedef struct render_overrides {
  int width, height;    /* --resolution; 0: the scene's */
  bool exposure_given;  /* --exposure EV */
  bool exposure_auto;   /* --exposure auto */
  double exposure_ev;
  const char *render;   /* --render OPTIONS: the render line instead of the file's, or NULL */
  bool seed_given;      /* --seed N, instead of the render line's seed= */
  unsigned long long seed;
  int nsets;            /* --set NAME.state=S, repeated */
  render_set sets[RENDER_MAX_SETS];
} render_overrides;

/* Reads --render, --resolution, --exposure, --seed and every --set from the command line
 * (vr_args keeps one value per option, so --set, which may repeat, is read
 * from argv), and refuses any other option given twice.  0, or 2 after a
 * usage error was printed. */
int render_overrides_parse(const vr_args *a, int argc, char **argv, const vr_option *opts,
                           size_t nopts, render_overrides *o);

/* Applies them to the parsed scene: the camera's resolution and exposure,
 * the render line's seed, the materials' states (charge= then no longer
 * counts).  VR_E_NOT_FOUND
 * naming a material the scene lacks, VR_E_ARG for one without a state. */
vr_status render_overrides_apply(const render_overrides *o, vr_scene *s, vr_error *err);

/* Every --set material is chromogenic glass in the database. */
vr_status render_overrides_check_db(const render_overrides *o, const vr_scene *s, vr_matdb *db,
                                    vr_error *err);

/* Options that only change the image, refused when there is none (no
 * camera, --sensors-only, an annual study) rather than ignored; --stats and
 * --json refused for an annual study, which writes its own tables. */
vr_status render_options_check(const vr_args *a, const vr_scene *s, vr_error *err);

/* A text of the overrides for the ranks' checksum. */
void render_overrides_text(const render_overrides *o, char *out, size_t cap);

/* ---- render_outputs.c ---- */

/* --outputs LIST: the film's files (VR_FILM_EXR, ... of vr/film.h) named
 * in a comma-separated list of exr, spectral, png, sensors, into *out (0
 * without --outputs: all that apply).  An empty list or name, an unknown
 * name, a name given twice, an image with --sensors-only, and --tonemap
 * without png or --exposure without an image are usage errors: 2 after the
 * message was printed, else 0. */
int render_outputs_parse(const vr_args *a, unsigned *out);

/* The files of the set for the scene: those asked for (0: all that apply,
 * the images when there is a camera pass, the table when the scene has
 * sensors).  VR_E_ARG naming the scene for a file it cannot give (an image
 * without a camera, the table without sensors) and for any --outputs in an
 * annual study. */
vr_status render_outputs_choose(unsigned asked, const vr_scene *s, bool no_camera,
                                unsigned *out, vr_error *err);

/* The files one run writes, all known before any work. */
#define RENDER_MAX_OUTPUTS 10
typedef struct render_outputs {
  int n;
  char *path[RENDER_MAX_OUTPUTS];
  const char *option[RENDER_MAX_OUTPUTS]; /* "-o" or "--stats", for messages */
} render_outputs;

/* Lists the outputs (the prefix's files of `outputs`, a mask of
 * render_outputs_choose, and the false-colour map, the manifest, the
 * statistics), and checks each with vr/out_guard.h against the run's inputs
 * (the scene, its meshes, IES and weather files, the database and its
 * journals) and against each other: none may be an input or a folder, each
 * folder must exist and be writable. */
vr_status render_outputs_check(const vr_scene *s, const char *prefix, const char *stats,
                               const char *db_path, unsigned outputs, bool falsecolour,
                               render_outputs *out, vr_error *err);
void render_outputs_free(render_outputs *o);

/* --verify PREFIX: the set against its manifest, a line per file on stdout
 * unless quiet; the exit status (0 whole, 1 not). */
int render_verify(const char *prefix, bool quiet);

/* Removes what killed runs left of the prefix's and the statistics' sets,
 * with a line through log for each name that had any. */
void render_clean_stale(const char *prefix, const char *stats,
                        void (*log)(void *user, const char *line), void *user);

/* ---- render_report.c ---- */

/* One sensor grid's readings summed up (EN 12464-1 uniformity). */
typedef struct render_grid {
  const char *name;
  size_t points;
  double min_lx, mean_lx, max_lx;
  double u0;          /* Emin / Eavg (NaN when Eavg is 0) */
  double min_max;     /* Emin / Emax (NaN when Emax is 0) */
} render_grid;

/* The grids of the scene's grid sensors, from the result's readings;
 * returns how many (at most cap). */
size_t render_grids(const vr_scene *s, const vr_render_result *r, render_grid *g, size_t cap);

typedef struct render_report {
  const char *scene, *prefix, *stats, *run_id;
  const render_outputs *outputs;
  bool falsecolour, exposure_auto;
  double film_seconds;
} render_report;

void render_summary_text(const vr_scene *s, const vr_render_result *r, const render_report *rep);
void render_summary_json(const vr_scene *s, const vr_render_result *r, const render_report *rep);

#endif
