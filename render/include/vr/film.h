/* The files a render leaves behind: what vr-render writes from a
 * vr_render_result, kept apart from the engine so that it can be tested
 * (and reused) on a result built by hand.
 *
 * vr_film_write(r, "out/room", ...) writes, all or nothing:
 *   out/room.exr           R, G, B float: linear sRGB (IEC 61966-2-1 primaries,
 *                          D65 white) of the film's XYZ, unscaled, so that
 *                          Y = 0.2126 R + 0.7152 G + 0.0722 B is the
 *                          luminance in cd/m²;
 *   out/room.spectral.exr  the film bins as S0.<λ>nm channels in the layout of
 *                          Fichet, Pacanowski and Wilkie (JCGT 2021), spectral
 *                          radiance in W.m^-2.sr^-1.nm^-1, with the same R, G, B;
 *   out/room.png           8-bit sRGB for the eye: linear sRGB times
 *                          2^exposure_ev / 100 (100 cd/m² maps to 1 at EV 0),
 *                          tone mapped (clip unless told: vr-render asks
 *                          for filmic), sRGB encoded;
 *   out/room.sensors.csv   one row per sensor point, when there are readings;
 *   out/room.falsecolour.png  with vr_film_write_with and a false-colour
 *                          scale: the luminance map of vr/falsecolour.h;
 *   out/room.manifest.json the run's id and each file's size and SHA-256.
 * The images are left out when the film is empty (width or height 0: a
 * sensors-only render), the spectral EXR when the film has no bins;
 * vr_film_write_with may leave out more (vr_film_options.outputs).
 *
 * All or nothing: every file is written into a staging folder beside its
 * target, and only when all have been written are they renamed into place
 * (then PREFIX.manifest.json, last; see vr_film_write_with).
 * If anything fails, no staging file is left, the files of this call that
 * were already renamed are removed, and earlier files of the same names that
 * were not reached keep their old contents.
 *
 * Both functions are thread-safe on distinct paths. */
#ifndef VR_FILM_H
#define VR_FILM_H

#include <stdio.h>
#include "vr/error.h"
#include "vr/render.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum vr_tonemap {
  VR_TONEMAP_CLIP = 0, /* channels clamped to [0, 1] */
  VR_TONEMAP_REINHARD, /* luminance L -> L / (1 + L), chromaticity kept, then clamped */
  VR_TONEMAP_FILMIC    /* each channel by Narkowicz's fit of the ACES film curve */
} vr_tonemap;

/* "clip", "reinhard" or "filmic" (case-insensitive); NULL gives clip (the
 * library's default; vr-render's is filmic).  VR_E_ARG
 * naming the text and the choices otherwise. */
vr_status vr_tonemap_parse(const char *text, vr_tonemap *out, vr_error *err);

/* The display value (linear, before the sRGB transfer curve, in [0, 1]) of
 * a film pixel of linear sRGB `rgb` and luminance `Y` (cd/m²) at
 * exposure_ev.  Shared by the PNG writer and its tests. */
void vr_film_display(const double rgb[3], double Y, double exposure_ev, vr_tonemap tm,
                     double out[3]);

/* Writes the files above for prefix (a path without extension; its folder
 * must exist).  tonemap: "clip", "reinhard", "filmic" or NULL (clip).  A NaN or
 * -infinity in the film's XYZ or spectral bins, or in the sensors' values,
 * is VR_E_RANGE naming the pixel (x, y from the top-left) or the sensor, and
 * nothing is written.  Errors on files name the path. */
vr_status vr_film_write(const vr_render_result *r, const char *prefix, const char *tonemap,
                        vr_error *err);

/* The files of the set, for vr_film_options.outputs. */
enum {
  VR_FILM_EXR = 1 << 0,      /* PREFIX.exr */
  VR_FILM_SPECTRAL = 1 << 1, /* PREFIX.spectral.exr */
  VR_FILM_PNG = 1 << 2,      /* PREFIX.png */
  VR_FILM_SENSORS = 1 << 3,  /* PREFIX.sensors.csv */
  VR_FILM_HDR = 1 << 4,      /* PREFIX.hdr, a Radiance picture: only when asked for */
  VR_FILM_ALL = (1 << 5) - 1
};

/* What vr_film_write_with writes besides the defaults. */
typedef struct vr_film_options {
  /* Which of the files above; 0: all that apply (the images when the film
   * has them, the table when there are readings).  A file asked for that
   * the result cannot give (an image of a film without one, the spectral
   * EXR of a film without bins, the table without readings) is VR_E_ARG
   * and nothing is written.  PNG, TIFF and JPEG load OpenCV (vr/image.h):
   * a set without them never does. */
  unsigned outputs;
  const char *tonemap;         /* "clip" (NULL), "reinhard", "filmic" */
  double falsecolour_lo_cd_m2; /* both > 0: PREFIX.falsecolour.png on that log scale; */
  double falsecolour_hi_cd_m2; /* 0: none */
  const char *stats_path;      /* non-NULL: the statistics (vr_stats_write_json), one of the set */
  const char *run_id;          /* the manifest's run id; NULL: a new one (vr_film_run_id) */
  /* The camera the film is from (the Radiance picture's VIEW line); NULL:
   * no VIEW line. */
  const vr_scene_camera *camera;
} vr_film_options;

/* vr_film_write with options: the same files, all or nothing, and the
 * false-colour map and the statistics when asked for (VR_E_ARG for a scale
 * without 0 < lo < hi, or for a map asked of a film without an image).
 *
 * The set is written into a staging folder PREFIX.partial.<pid> beside the
 * outputs (the statistics, when they go to another folder, beside their
 * target as FILE.partial.<pid>), each file is then moved into place, and
 * PREFIX.manifest.json is written last, atomically: {"run_id": ...,
 * "files": [{"name", "bytes", "sha256"}, ...]}, names relative to the
 * manifest's folder (absolute for a file elsewhere).  A process killed
 * while the files are moved leaves new files beside the old manifest, and
 * vr_film_verify finds them. */
vr_status vr_film_write_with(const vr_render_result *r, const char *prefix,
                             const vr_film_options *o, vr_error *err);

/* The Radiance picture (film_hdr.c): the film's XYZ in Radiance's RGB
 * (its standard primaries, equal-energy white) and units (radiance of
 * 179 lm/W white: luminance = 179 (0.265 R + 0.670 G + 0.065 B)), times
 * 2^exposure_ev with EXPOSURE= that factor, PRIMARIES= and the camera's
 * VIEW= (vr_film_radiance_view) when it has one. */
vr_status vr_film_write_hdr(const vr_render_result *r, const vr_scene_camera *camera,
                            const char *path, vr_error *err);
/* The camera as Radiance's view options (" -vtv -vp ... -vv V"), for a
 * W x H picture: -vtv for pinhole and thin-lens cameras, -vta for an
 * angular fisheye; false (nothing written) for an equisolid fisheye, which
 * Radiance has no view type for, and for an angular one wider than 360
 * degrees across the picture, which Radiance refuses. */
bool vr_film_radiance_view(const vr_scene_camera *c, int W, int H, char *buf, size_t n);
/* Radiance's RGB to XYZ (row-major), Y at 1 for white: the Y row is
 * Radiance's CIE_rf, CIE_gf, CIE_bf. */
void vr_film_radiance_rgb_matrix(double rgb_to_xyz[9]);

/* A new run id: "20261128T013000Z-<pid>-<8 random hex digits>". */
#define VR_FILM_RUN_ID_MAX 64
void vr_film_run_id(char out[VR_FILM_RUN_ID_MAX]);

/* Removes what killed runs left of a set named `name` (a prefix, or the
 * statistics' path): NAME.partial.<pid> folders or files in its folder
 * whose process no longer exists on this machine (a live run's are kept).
 * Returns how many were removed; their paths, space-separated, in removed
 * (may be NULL). */
size_t vr_film_clean_stale(const char *name, char *removed, size_t cap);

/* Checks the files PREFIX.manifest.json lists against their size and
 * SHA-256.  `line` (may be NULL) receives one line per file ("ok       F",
 * "differs  F: ...", "missing  F ..."); out has the counts and the run id.
 * VR_E_RANGE "PREFIX: N of M files do not match ...: a mixed or altered
 * set" when any differs or is missing; VR_E_IO without a manifest;
 * VR_E_PARSE for a damaged one. */
typedef struct vr_film_check {
  char run_id[VR_FILM_RUN_ID_MAX];
  int files, bad;
} vr_film_check;
typedef void (*vr_film_verify_line)(void *user, const char *line);
vr_status vr_film_verify(const char *prefix, vr_film_verify_line line, void *user,
                         vr_film_check *out, vr_error *err);

/* The exposure (EV) that maps the film's log-average luminance
 * exp(mean ln Y), over its pixels with 0 < Y < infinity, to mid grey
 * (display value 0.18, PNG 118): EV = log2(18 / Y_log), Y in cd/m2.  false
 * (and *ev unchanged) when no pixel has light. */
bool vr_film_auto_exposure(const vr_render_result *r, double *ev);

/* The sensor table alone (what vr_film_write writes as PREFIX.sensors.csv),
 * atomically: header "sensor,i,j,x,y,z,illuminance_lx,stderr_lx,E_<nm>..."
 * with one E column per film bin (spectral irradiance in W/(m² nm)). */
vr_status vr_sensors_write_csv(const vr_render_result *r, const char *path, vr_error *err);

/* Statistics as JSON, atomically (see docs/vr-render.md for the keys):
 * passes with their decisions and times, ray and photon counts, sensor
 * readings, the photochromic state range, the peak resident memory of the
 * process so far (getrusage) and the total time. */
vr_status vr_stats_write_json(const vr_render_result *r, const char *path, vr_error *err);
/* The passes of a render as a JSON array (name, ran, reason, seconds; null
 * seconds for a pass that did not run), for the statistics and --json. */
void vr_passes_write_json(FILE *f, const vr_render_result *r);
/* The adaptive sampling summary as a JSON object (null without it). */
void vr_adaptive_write_json(FILE *f, const vr_render_result *r);

/* The render's flow profiles (vr_render_options.flow_profile) as the
 * statistics' "flow_profile" member and a comma, or nothing. */
void vr_flow_profile_write_json(FILE *f, const vr_render_result *r);

/* Peak resident set size of this process so far, in bytes (0 if unknown). */
long long vr_peak_rss_bytes(void);

#ifdef __cplusplus
}
#endif
#endif
