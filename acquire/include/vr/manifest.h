/* The capture manifest of vr-rgb2spec: which photos were taken under which
 * light, how their pixel values relate to light, the camera, and the
 * regions that name materials.  A text file next to the photos, one
 * statement per line, '#' comments; a word in double quotes (whole, or
 * after its key) keeps its spaces and '#', and the quotes are dropped:
 *
 *   camera  cie1931-srgb | db:NAME | file:PATH.csv
 *   grid    FROM TO STEP                  recovery wavelengths, nm (400 700 10)
 *   photo   FILE light=LIGHT [scale=S] [encoding=srgb|linear] [clip=C]
 *   labels  FILE.png                      a label image (grey level = id)
 *   region  NAME rect=X,Y,W,H [reference=REF]
 *   region  NAME label=ID [reference=REF]
 *   chart   auto | grid=X0,Y0,X1,Y1       a ColorChecker: 24 regions
 *                                         "patch-01".."patch-24" with the
 *                                         BabelColor reference spectra
 *
 * LIGHT is a CIE illuminant known to the core (D65, A, F2, LED-B3, D5000,
 * BB3000, ...; vr_illuminant), db:NAME (an illuminant in the material
 * database) or file:PATH (a CSV table, first spectrum column).  scale
 * multiplies the light (exposure; default 1: a white reflector under the
 * light gives Y = 1).  encoding: srgb (default for PNG/JPEG/TIFF: values are
 * sRGB-encoded and are decoded first) or linear (default for EXR).  clip:
 * values at or above it (before decoding) count as clipped (default 0.999).
 * REF: db:NAME or file:PATH, a reference reflectance for the report.
 * Camera file:PATH is a CSV with columns r, g, b (spectral sensitivities);
 * db:NAME a camera material (roles r, g, b).  A camera material made by
 * vr-rgb2spec calibrate also carries its tone curves (properties
 * linearisation_r/_g/_b, vr/calibrate.h): photos without encoding= whose
 * values would be taken as sRGB (integer files) are then decoded with those
 * curves instead (vr_capture_decode).  Paths are relative to the manifest's
 * folder, except for a manifest read from standard input ("-", /dev/stdin)
 * or from a pipe or other file that is not a regular one (a FIFO,
 * /dev/fd/N of a shell's <(...)), whose relative paths are taken from the
 * current working directory: such a stream has no folder of its own.
 * Errors are "manifest:line:col: message", the manifest named as given, or
 * "<stdin>" for "-".  A UTF-8 byte-order mark at the start is skipped. */
#ifndef VR_MANIFEST_H
#define VR_MANIFEST_H

#include <stdbool.h>
#include <stddef.h>
#include "vr/calibrate.h"
#include "vr/error.h"
#include "vr/spectrum.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vr_matdb vr_matdb;

typedef struct vr_capture_photo {
  char *path;            /* resolved against the manifest's folder (vr_capture.dir) */
  char *light_name;      /* as written */
  vr_spectrum *light;    /* the SPD */
  double scale;
  int encoding;          /* 0 default (by file type), 1 srgb, 2 linear */
  double clip;
  long line;
} vr_capture_photo;

typedef enum vr_region_kind { VR_REGION_RECT = 0, VR_REGION_LABEL, VR_REGION_CHART } vr_region_kind;

typedef struct vr_capture_region {
  char *name;
  vr_region_kind kind;
  int x, y, w, h;        /* rect; for a chart grid: x0, y0, x1, y1 */
  int label;
  bool chart_auto;
  char *reference_name;  /* as written, NULL if none */
  vr_spectrum *reference;
  long line;
} vr_capture_region;

typedef enum vr_capture_camera { VR_CAPTURE_CAMERA_SRGB = 0, VR_CAPTURE_CAMERA_MEASURED } vr_capture_camera;

typedef struct vr_capture {
  char *path;           /* as given; "<stdin>" for "-" */
  char *dir;            /* relative paths are resolved against it ("" = cwd) */
  bool stream;          /* read from standard input or a pipe: path names no file to reread */
  char sha256[65];      /* of the manifest's bytes as read (hex), for provenance */
  vr_capture_camera camera;
  char *camera_name;
  vr_spectrum *sens[3]; /* r, g, b sensitivities for VR_CAPTURE_CAMERA_MEASURED */
  bool has_tone;        /* a db: camera with stored tone curves */
  vr_tone tone[3];      /* ... per channel, with their exponents */
  double gamma[3];
  double grid[3];       /* from, to, step */
  size_t nphotos;
  vr_capture_photo *photos;
  size_t nregions;
  vr_capture_region *regions;
  char *labels_path;
} vr_capture;

/* db may be NULL (then db: names are an error naming the line).  path "-"
 * reads standard input.  The manifest is read once, at most 1 MiB. */
vr_status vr_capture_read(const char *path, vr_matdb *db, vr_capture **out, vr_error *err);
/* vr_capture_read for a tool that opens the material database only when it
 * needs one: reads the manifest once (a pipe cannot be read twice, so no
 * separate look for db: names such as vr_matdb_named_in), opens the
 * database at db_path (NULL: the default) with db_flags when need_db is true
 * or the manifest names a db: material outside comments, then parses.  *db
 * is NULL when none was opened; once opened it is the caller's to close,
 * also when an error follows. */
vr_status vr_capture_read_db(const char *path, const char *db_path, int db_flags, bool need_db,
                             vr_matdb **db, vr_capture **out, vr_error *err);
/* Parses manifest text; path names it in messages, its folder resolves
 * relative paths. */
vr_status vr_capture_parse(const char *text, size_t len, const char *path, vr_matdb *db,
                           vr_capture **out, vr_error *err);
void vr_capture_destroy(vr_capture *c);

/* A spectrum named as the manifest names lights and references: db:NAME
 * (the material's `role` spectrum, else its "value"), file:PATH (the first
 * spectrum column of a CSV, PATH relative to dir unless absolute) or, when
 * allow_cie, a CIE illuminant known to the core.  db may be NULL (then db:
 * is an error).  Messages carry no file:line prefix. */
vr_status vr_capture_spectrum(const char *ref, const char *dir, vr_matdb *db, const char *role,
                              bool allow_cie, vr_spectrum **out, vr_error *err);

/* The linear value of encoded v (channel 0-2) of photo p: the camera's
 * stored tone curve when it has one, the photo has no encoding= and srgb
 * (the default by file type) is true; otherwise the sRGB decoding when srgb,
 * else v itself.  vr_capture_encode is its inverse (for simulated photos). */
double vr_capture_decode(const vr_capture *c, const vr_capture_photo *p, int channel, double v,
                         bool srgb);
double vr_capture_encode(const vr_capture *c, const vr_capture_photo *p, int channel,
                         double linear, bool srgb);

/* The photo entry whose file name (or resolved path) matches, or NULL. */
const vr_capture_photo *vr_capture_find_photo(const vr_capture *c, const char *path);

#ifdef __cplusplus
}
#endif
#endif
