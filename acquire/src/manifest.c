/* Capture manifests of vr-rgb2spec (vr/manifest.h has the grammar). */
#include "vr/manifest.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include "vr/calibrate.h"
#include "vr/colorchecker.h"
#include "vr/colour.h"
#include "vr/csv.h"
#include "vr/file.h"
#include "vr/matdb.h"
#include "vr/sha256.h"

typedef struct parser {
  vr_capture *c;
  vr_matdb *db;
  const char *file;
  long line;
  const char *text; /* the current line, for columns */
  vr_error *err;
} parser;

static long col_of(const parser *p, const char *tok) { return (long)(tok - p->text) + 1; }

#define FAIL(p, tok, status, ...) vr_error_at((p)->err, status, (p)->file, (p)->line, col_of(p, tok), __VA_ARGS__)

void vr_capture_destroy(vr_capture *c) {
  if (!c) return;
  for (size_t i = 0; i < c->nphotos; i++) {
    free(c->photos[i].path);
    free(c->photos[i].light_name);
    vr_spectrum_destroy(c->photos[i].light);
  }
  for (size_t i = 0; i < c->nregions; i++) {
    free(c->regions[i].name);
    free(c->regions[i].reference_name);
    vr_spectrum_destroy(c->regions[i].reference);
  }
  for (int i = 0; i < 3; i++) vr_spectrum_destroy(c->sens[i]);
  free(c->photos);
  free(c->regions);
  free(c->path);
  free(c->dir);
  free(c->camera_name);
  free(c->labels_path);
  free(c);
}

/* rel against the folder dir, unless rel is absolute or dir empty. */
static char *join(const char *dir, const char *rel) {
  if (rel[0] == '/' || !dir || !dir[0]) return strdup(rel);
  size_t n = strlen(dir) + strlen(rel) + 2;
  char *s = malloc(n);
  if (s) snprintf(s, n, "%s/%s", dir, rel);
  return s;
}

vr_status vr_capture_spectrum(const char *ref, const char *dir, vr_matdb *db, const char *role,
                              bool allow_cie, vr_spectrum **out, vr_error *err) {
  *out = NULL;
  if (!strncmp(ref, "db:", 3)) {
    if (!db) return vr_error_set(err, VR_E_ARG, "\"%s\" needs the material database (--db)", ref);
    vr_material *m;
    vr_status st = vr_matdb_load(db, ref + 3, 0, &m, err);
    if (st) return st;
    const vr_spectrum *s = vr_material_spectrum(m, role);
    if (!s) s = vr_material_spectrum(m, "value");
    *out = s ? vr_spectrum_copy(s, err) : NULL;
    vr_material_destroy(m);
    if (!*out)
      return vr_error_set(err, VR_E_NOT_FOUND, "material %s has no '%s' spectrum", ref + 3, role);
    return VR_OK;
  }
  if (!strncmp(ref, "file:", 5)) {
    char *path = join(dir, ref + 5);
    vr_spectrum_table t = {0};
    vr_status st = path ? vr_spectrum_table_read(path, &t, err)
                        : vr_error_set(err, VR_E_NOMEM, "out of memory");
    free(path);
    if (st) return st;
    *out = t.count ? vr_spectrum_copy(t.spectra[0], err) : NULL;
    vr_spectrum_table_free(&t);
    return *out ? VR_OK : vr_error_set(err, VR_E_PARSE, "%s holds no spectrum", ref + 5);
  }
  if (allow_cie) {
    *out = vr_illuminant(ref, NULL);
    if (*out) return VR_OK;
    return vr_error_set(err, VR_E_NOT_FOUND,
                        "unknown light \"%s\" (a CIE illuminant such as D65, A, F2, LED-B3, or "
                        "db:NAME, file:PATH)", ref);
  }
  return vr_error_set(err, VR_E_PARSE, "\"%s\": expected db:NAME or file:PATH", ref);
}

/* vr_capture_spectrum with the error placed at the token. */
static vr_status spectrum_ref(parser *p, const char *tok, const char *ref, const char *role,
                              bool allow_cie, vr_spectrum **out) {
  vr_error local = {0};
  vr_status st = vr_capture_spectrum(ref, p->c->dir, p->db, role, allow_cie, out, &local);
  return st ? FAIL(p, tok, st, "%s", local.message) : VR_OK;
}

double vr_capture_decode(const vr_capture *c, const vr_capture_photo *p, int channel, double v,
                         bool srgb) {
  if (p->encoding == 0 && srgb && c->has_tone)
    return vr_tone_decode(c->tone[channel], c->gamma[channel], v);
  return srgb ? vr_srgb_decode(v) : v;
}

double vr_capture_encode(const vr_capture *c, const vr_capture_photo *p, int channel,
                         double linear, bool srgb) {
  if (p->encoding == 0 && srgb && c->has_tone)
    return vr_tone_encode(c->tone[channel], c->gamma[channel], linear);
  return srgb ? vr_srgb_encode(linear) : linear;
}

static vr_status number(parser *p, const char *tok, const char *v, double *out, double lo,
                        double hi) {
  if (vr_parse_double(v, out) || !(*out >= lo && *out <= hi))
    return FAIL(p, tok, VR_E_PARSE, "\"%s\": expected a number in [%g, %g]", tok, lo, hi);
  return VR_OK;
}

static vr_status ints(parser *p, const char *tok, const char *v, int *out, int n) {
  char buf[128];
  snprintf(buf, sizeof buf, "%s", v);
  char *save = NULL, *t = strtok_r(buf, ",", &save);
  for (int i = 0; i < n; i++, t = strtok_r(NULL, ",", &save)) {
    double x;
    if (!t || vr_parse_double(t, &x) || x != floor(x) || x < 0 || x > 1e6)
      return FAIL(p, tok, VR_E_PARSE, "\"%s\": expected %d non-negative integers separated by commas",
                  tok, n);
    out[i] = (int)x;
  }
  if (t) return FAIL(p, tok, VR_E_PARSE, "\"%s\": more than %d numbers", tok, n);
  return VR_OK;
}

static vr_status photo(parser *p, char **tok, size_t n) {
  if (n < 2) return FAIL(p, tok[0], VR_E_PARSE, "'photo' needs a file and light=...");
  vr_capture *c = p->c;
  vr_capture_photo *grown = realloc(c->photos, (c->nphotos + 1) * sizeof *grown);
  if (!grown) return vr_error_set(p->err, VR_E_NOMEM, "out of memory");
  c->photos = grown;
  vr_capture_photo *ph = &c->photos[c->nphotos++];
  memset(ph, 0, sizeof *ph);
  ph->scale = 1;
  ph->clip = 0.999;
  ph->line = p->line;
  if (!(ph->path = join(p->c->dir, tok[1])))
    return vr_error_set(p->err, VR_E_NOMEM, "out of memory");
  for (size_t i = 2; i < n; i++) {
    char *eq = strchr(tok[i], '=');
    if (!eq) return FAIL(p, tok[i], VR_E_PARSE, "unexpected \"%s\" (key=value)", tok[i]);
    const char *v = eq + 1;
    vr_status st = VR_OK;
    if (!strncmp(tok[i], "light=", 6)) {
      if (ph->light_name) return FAIL(p, tok[i], VR_E_PARSE, "light= is given twice");
      if (!(ph->light_name = strdup(v))) return vr_error_set(p->err, VR_E_NOMEM, "out of memory");
      st = spectrum_ref(p, tok[i], v, "value", true, &ph->light);
    } else if (!strncmp(tok[i], "scale=", 6)) {
      st = number(p, tok[i], v, &ph->scale, 1e-9, 1e9);
    } else if (!strncmp(tok[i], "clip=", 5)) {
      st = number(p, tok[i], v, &ph->clip, 1e-3, 1.0);
    } else if (!strncmp(tok[i], "encoding=", 9)) {
      if (!strcasecmp(v, "srgb")) ph->encoding = 1;
      else if (!strcasecmp(v, "linear")) ph->encoding = 2;
      else st = FAIL(p, tok[i], VR_E_PARSE, "encoding must be srgb or linear");
    } else {
      st = FAIL(p, tok[i], VR_E_PARSE, "unknown photo key in \"%s\" (light, scale, encoding, clip)",
                tok[i]);
    }
    if (st) return st;
  }
  if (!ph->light) return FAIL(p, tok[1], VR_E_PARSE, "photo %s has no light=...", tok[1]);
  for (size_t i = 0; i + 1 < c->nphotos; i++)
    if (!strcmp(c->photos[i].path, ph->path))
      return FAIL(p, tok[1], VR_E_PARSE, "photo %s is listed twice (line %ld)", tok[1],
                  c->photos[i].line);
  return VR_OK;
}

static vr_capture_region *new_region(parser *p, const char *name) {
  vr_capture *c = p->c;
  vr_capture_region *grown = realloc(c->regions, (c->nregions + 1) * sizeof *grown);
  if (!grown) return NULL;
  c->regions = grown;
  vr_capture_region *r = &c->regions[c->nregions++];
  memset(r, 0, sizeof *r);
  r->name = strdup(name);
  r->line = p->line;
  return r->name ? r : NULL;
}

static vr_status region(parser *p, char **tok, size_t n) {
  if (n < 3) return FAIL(p, tok[0], VR_E_PARSE, "'region' needs a name and rect=... or label=...");
  for (const char *c = tok[1]; *c; c++)
    if (isspace((unsigned char)*c) || strchr("#=\"", *c))
      return FAIL(p, tok[1], VR_E_PARSE, "region \"%s\": a region's name is one word without '#', '=' "
                  "or '\"' (it names the material saved, which a scene's db:NAME must be able to "
                  "write)", tok[1]);
  for (size_t i = 0; i < p->c->nregions; i++)
    if (!strcmp(p->c->regions[i].name, tok[1]))
      return FAIL(p, tok[1], VR_E_PARSE, "region %s is defined twice (line %ld)", tok[1],
                  p->c->regions[i].line);
  vr_capture_region *r = new_region(p, tok[1]);
  if (!r) return vr_error_set(p->err, VR_E_NOMEM, "out of memory");
  bool placed = false;
  for (size_t i = 2; i < n; i++) {
    vr_status st = VR_OK;
    if (!strncmp(tok[i], "rect=", 5)) {
      int v[4];
      st = ints(p, tok[i], tok[i] + 5, v, 4);
      if (!st && (v[2] == 0 || v[3] == 0)) st = FAIL(p, tok[i], VR_E_PARSE, "empty rectangle");
      r->kind = VR_REGION_RECT, r->x = v[0], r->y = v[1], r->w = v[2], r->h = v[3];
      placed = true;
    } else if (!strncmp(tok[i], "label=", 6)) {
      st = ints(p, tok[i], tok[i] + 6, &r->label, 1);
      if (!st && r->label == 0) st = FAIL(p, tok[i], VR_E_PARSE, "label 0 is the background");
      r->kind = VR_REGION_LABEL;
      placed = true;
    } else if (!strncmp(tok[i], "reference=", 10)) {
      if (r->reference_name) return FAIL(p, tok[i], VR_E_PARSE, "reference= is given twice");
      r->reference_name = strdup(tok[i] + 10);
      st = spectrum_ref(p, tok[i], tok[i] + 10, "value", false, &r->reference);
    } else {
      st = FAIL(p, tok[i], VR_E_PARSE, "unexpected \"%s\" (rect=, label=, reference=)", tok[i]);
    }
    if (st) return st;
  }
  if (!placed) return FAIL(p, tok[1], VR_E_PARSE, "region %s needs rect=X,Y,W,H or label=ID", tok[1]);
  if (r->kind == VR_REGION_LABEL && !p->c->labels_path)
    return FAIL(p, tok[1], VR_E_PARSE, "label regions need a 'labels FILE' line before them");
  return VR_OK;
}

static vr_status chart(parser *p, char **tok, size_t n) {
  if (n != 2) return FAIL(p, tok[0], VR_E_PARSE, "'chart' takes auto or grid=X0,Y0,X1,Y1");
  int v[4] = {0, 0, 0, 0};
  bool automatic = !strcmp(tok[1], "auto");
  if (!automatic) {
    if (strncmp(tok[1], "grid=", 5)) return FAIL(p, tok[1], VR_E_PARSE, "expected auto or grid=X0,Y0,X1,Y1");
    vr_status st = ints(p, tok[1], tok[1] + 5, v, 4);
    if (st) return st;
    if (!(v[2] > v[0] && v[3] > v[1]))
      return FAIL(p, tok[1], VR_E_PARSE, "the chart's corners must satisfy X1 > X0 and Y1 > Y0");
  }
  for (size_t i = 0; i < 24; i++) {
    char name[16];
    snprintf(name, sizeof name, "patch-%02zu", i + 1);
    vr_capture_region *r = new_region(p, name);
    if (!r) return vr_error_set(p->err, VR_E_NOMEM, "out of memory");
    r->kind = VR_REGION_CHART;
    r->chart_auto = automatic;
    r->x = v[0], r->y = v[1], r->w = v[2], r->h = v[3];
    r->label = (int)i; /* the patch index */
    r->reference_name = strdup(vr_colorchecker_name(i));
    vr_error local;
    r->reference = vr_colorchecker_patch(i, &local);
    if (!r->reference) return vr_error_set(p->err, local.status, "%s", local.message);
  }
  return VR_OK;
}

static vr_status camera(parser *p, char **tok, size_t n) {
  vr_capture *c = p->c;
  if (n != 2) return FAIL(p, tok[0], VR_E_PARSE, "'camera' takes one name");
  if (c->camera_name) return FAIL(p, tok[0], VR_E_PARSE, "a second 'camera' line");
  c->camera_name = strdup(tok[1]);
  if (!strcasecmp(tok[1], "cie1931-srgb")) {
    c->camera = VR_CAPTURE_CAMERA_SRGB;
    return VR_OK;
  }
  c->camera = VR_CAPTURE_CAMERA_MEASURED;
  static const char *const ROLES[3] = {"r", "g", "b"};
  if (!strncmp(tok[1], "file:", 5)) {
    char *path = join(c->dir, tok[1] + 5);
    vr_spectrum_table t = {0};
    vr_error local = {0};
    vr_status st = path ? vr_spectrum_table_read(path, &t, &local) : VR_E_NOMEM;
    free(path);
    if (st) return FAIL(p, tok[1], st, "%s", local.message);
    for (int k = 0; k < 3 && !st; k++) {
      for (size_t j = 0; j < t.count; j++)
        if (!strcasecmp(t.names[j], ROLES[k])) c->sens[k] = vr_spectrum_copy(t.spectra[j], NULL);
      if (!c->sens[k]) st = FAIL(p, tok[1], VR_E_PARSE, "camera file has no column '%s'", ROLES[k]);
    }
    vr_spectrum_table_free(&t);
    return st;
  }
  if (!strncmp(tok[1], "db:", 3)) {
    for (int k = 0; k < 3; k++) {
      vr_status st = spectrum_ref(p, tok[1], tok[1], ROLES[k], false, &c->sens[k]);
      if (st) return st;
    }
    /* A calibrated camera (vr-rgb2spec calibrate) carries its tone curves. */
    vr_material *m = NULL;
    vr_error local = {0};
    vr_status st = vr_matdb_load(p->db, tok[1] + 3, 0, &m, &local);
    if (!st) {
      st = vr_calibration_tone_of(m, c->tone, c->gamma, &c->has_tone, &local);
      vr_material_destroy(m);
    }
    return st ? FAIL(p, tok[1], st, "%s", local.message) : VR_OK;
  }
  return FAIL(p, tok[1], VR_E_PARSE, "unknown camera \"%s\" (cie1931-srgb, db:NAME, file:PATH)", tok[1]);
}

static vr_status statement(parser *p, char **tok, size_t n) {
  const char *kw = tok[0];
  if (!strcmp(kw, "photo")) return photo(p, tok, n);
  if (!strcmp(kw, "region")) return region(p, tok, n);
  if (!strcmp(kw, "chart")) return chart(p, tok, n);
  if (!strcmp(kw, "camera")) return camera(p, tok, n);
  if (!strcmp(kw, "labels")) {
    if (n != 2) return FAIL(p, tok[0], VR_E_PARSE, "'labels' takes one file");
    if (p->c->labels_path) return FAIL(p, tok[0], VR_E_PARSE, "a second 'labels' line");
    p->c->labels_path = join(p->c->dir, tok[1]);
    return VR_OK;
  }
  if (!strcmp(kw, "grid")) {
    if (n != 4) return FAIL(p, tok[0], VR_E_PARSE, "'grid' takes FROM TO STEP (nm)");
    double *g = p->c->grid;
    for (int i = 0; i < 3; i++) {
      vr_status st = number(p, tok[1 + i], tok[1 + i], &g[i], 0.1, 1e5);
      if (st) return st;
    }
    if (!(g[1] > g[0]) || g[2] > g[1] - g[0])
      return FAIL(p, tok[1], VR_E_PARSE, "grid: need FROM < TO and STEP <= TO - FROM");
    return VR_OK;
  }
  return FAIL(p, kw, VR_E_PARSE, "unknown statement \"%s\" (camera, grid, photo, labels, region, chart)", kw);
}

/* Parses text, named path in messages; relative paths are resolved against
 * dir ("" for the working directory). */
static vr_status parse_in(const char *text, size_t len, const char *path, char *dir, bool stream,
                          vr_matdb *db, vr_capture **out, vr_error *err) {
  *out = NULL;
  vr_capture *c = calloc(1, sizeof *c);
  if (!c) {
    free(dir);
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  c->path = strdup(path);
  c->dir = dir;
  c->stream = stream;
  vr_sha256_buffer(text, len, c->sha256);
  /* A UTF-8 byte-order mark, as Windows editors write one, is not a
   * statement (the hash above is still of the bytes as read). */
  if (len >= 3 && !memcmp(text, "\xEF\xBB\xBF", 3)) text += 3, len -= 3;
  c->grid[0] = 400, c->grid[1] = 700, c->grid[2] = 10;
  parser p = {c, db, path, 0, NULL, err};
  vr_status st = (c->path && c->dir) ? VR_OK : vr_error_set(err, VR_E_NOMEM, "out of memory");
  const char *s = text, *end = text + len;
  while (!st && s < end) {
    const char *e = memchr(s, '\n', (size_t)(end - s));
    if (!e) e = end;
    size_t n = (size_t)(e - s);
    char line[2048];
    p.line++;
    if (n >= sizeof line) {
      st = vr_error_at(err, VR_E_PARSE, path, p.line, 0, "line longer than %zu characters", sizeof line - 1);
      break;
    }
    memcpy(line, s, n);
    line[n] = '\0';
    s = e < end ? e + 1 : end;
    p.text = line;
    char *tok[32];
    size_t nt = 0;
    /* Tokens are pointers into line (for columns): split in place.  A
     * double-quoted part keeps its spaces and '#' ("my photo.png",
     * reference="file:a b.csv"); the quotes are dropped.  '#' outside
     * quotes starts a comment. */
    for (char *q = line; *q && *q != '#' && !st;) {
      while (*q && isspace((unsigned char)*q)) *q++ = '\0';
      if (!*q || *q == '#') break;
      if (nt == 32) {
        st = vr_error_at(err, VR_E_PARSE, path, p.line, 0, "more than 32 words on a line");
        break;
      }
      tok[nt++] = q;
      char *w = q;
      bool quoted = false;
      long open_col = 0;
      while (*q && (quoted || (!isspace((unsigned char)*q) && *q != '#'))) {
        if (*q == '"') {
          if (!quoted) open_col = (long)(q - line) + 1;
          quoted = !quoted;
          q++;
          continue;
        }
        *w++ = *q++;
      }
      if (quoted) {
        st = vr_error_at(err, VR_E_PARSE, path, p.line, open_col,
                         "a double quote opened here is not closed on this line");
        break;
      }
      bool comment = *q == '#';
      if (*q) q++;
      *w = '\0';
      if (!*tok[nt - 1]) {
        st = vr_error_at(err, VR_E_PARSE, path, p.line, (long)(tok[nt - 1] - line) + 1,
                         "an empty \"\" names nothing");
        break;
      }
      if (comment) break;
    }
    if (!st && nt) st = statement(&p, tok, nt);
  }
  if (!st && c->nphotos == 0) st = vr_error_at(err, VR_E_PARSE, path, 0, 0, "no 'photo' lines");
  if (st) {
    vr_capture_destroy(c);
    return st;
  }
  *out = c;
  return VR_OK;
}

/* The folder of path ("" when it has none): where its relative paths go. */
static char *folder_of(const char *path) {
  const char *slash = strrchr(path, '/');
  return slash ? strndup(path, (size_t)(slash - path)) : strdup("");
}

vr_status vr_capture_parse(const char *text, size_t len, const char *path, vr_matdb *db,
                           vr_capture **out, vr_error *err) {
  return parse_in(text, len, path, folder_of(path), false, db, out, err);
}

enum { MANIFEST_MAX_BYTES = 1 << 20 };

/* A manifest read whole, once: from standard input for "-", else from the
 * file named, which is a stream when it is not a regular file (a pipe, a
 * FIFO, a terminal) or lies under /dev or /proc (/dev/stdin, /dev/fd/N):
 * a name there says nothing of where the photos are. */
typedef struct loaded {
  char *text;
  size_t len;
  const char *name; /* for messages */
  bool stream;
} loaded;

static vr_status load(const char *path, loaded *m, vr_error *err) {
  memset(m, 0, sizeof *m);
  if (!strcmp(path, "-")) {
    m->name = "<stdin>";
    m->stream = true;
    return vr_read_stream(stdin, m->name, MANIFEST_MAX_BYTES, &m->text, &m->len, err);
  }
  m->name = path;
  FILE *f = fopen(path, "rb");
  if (!f) return vr_error_set(err, VR_E_IO, "%s: cannot open: %s", path, strerror(errno));
  struct stat sb;
  m->stream = fstat(fileno(f), &sb) != 0 || !S_ISREG(sb.st_mode) || !strncmp(path, "/dev/", 5) ||
              !strncmp(path, "/proc/", 6);
  vr_status st = vr_read_stream(f, path, MANIFEST_MAX_BYTES, &m->text, &m->len, err);
  fclose(f);
  return st;
}

static vr_status parse_loaded(const loaded *m, vr_matdb *db, vr_capture **out, vr_error *err) {
  return parse_in(m->text, m->len, m->name, m->stream ? strdup("") : folder_of(m->name),
                  m->stream, db, out, err);
}

vr_status vr_capture_read(const char *path, vr_matdb *db, vr_capture **out, vr_error *err) {
  *out = NULL;
  loaded m;
  vr_status st = load(path, &m, err);
  if (!st) st = parse_loaded(&m, db, out, err);
  free(m.text);
  return st;
}

/* Does the text name a db: material outside '#' comments?  The same test
 * as vr_matdb_named_in, on text already read. */
static bool names_db(const char *text, size_t len) {
  bool comment = false;
  for (size_t i = 0; i < len; i++) {
    if (text[i] == '\n') comment = false;
    else if (text[i] == '#') comment = true;
    else if (!comment && i + 3 <= len && !memcmp(text + i, "db:", 3)) return true;
  }
  return false;
}

vr_status vr_capture_read_db(const char *path, const char *db_path, int db_flags, bool need_db,
                             vr_matdb **db, vr_capture **out, vr_error *err) {
  *db = NULL;
  *out = NULL;
  loaded m;
  vr_status st = load(path, &m, err);
  if (!st && (need_db || names_db(m.text, m.len))) st = vr_matdb_open(db_path, db_flags, db, err);
  if (!st) st = parse_loaded(&m, *db, out, err);
  free(m.text);
  return st;
}

const vr_capture_photo *vr_capture_find_photo(const vr_capture *c, const char *path) {
  const char *base = strrchr(path, '/');
  base = base ? base + 1 : path;
  for (size_t i = 0; i < c->nphotos; i++) {
    const char *pb = strrchr(c->photos[i].path, '/');
    pb = pb ? pb + 1 : c->photos[i].path;
    if (!strcmp(c->photos[i].path, path) || !strcmp(pb, base)) return &c->photos[i];
  }
  return NULL;
}
