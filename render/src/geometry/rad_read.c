/* Reading a Radiance scene description (rad_read.h): the words of a file,
 * its primitives (modifier type identifier, then string, integer and
 * real arguments, each list led by its count), the identifiers they
 * define and the !xform lines that place other files.  Radiance reads
 * identifiers in file order, a later definition replacing an earlier one
 * for the primitives after it; so does this reader. */
#include <ctype.h>
#include <stdarg.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include "geometry/rad_parse.h"
#include "vr/scene.h"
#include "vr/sha256.h"

#define RAD_MAX_DEPTH 32
#define RAD_MAX_ARGS 1000000

vr_status rad_nomem(vr_error *err) { return vr_error_set(err, VR_E_NOMEM, "out of memory"); }

bool vr_rad_is(const char *path) {
  size_t n = strlen(path);
  return n > 4 && !strcasecmp(path + n - 4, ".rad");
}

/* The next word and its line; false at the end of the file.  Double
 * quotes keep spaces in a word, as Radiance's reader does. */
static bool word(src *f, char *out, size_t cap, long *line) {
  while (f->pos < f->len && isspace((unsigned char)f->text[f->pos]))
    if (f->text[f->pos++] == '\n') f->line++;
  if (f->pos >= f->len) return false;
  *line = f->line;
  size_t n = 0;
  bool quoted = f->text[f->pos] == '"';
  if (quoted) f->pos++;
  while (f->pos < f->len) {
    char c = f->text[f->pos];
    if (quoted ? c == '"' : isspace((unsigned char)c)) break;
    if (c == '\n') f->line++;
    if (n + 1 < cap) out[n++] = c;
    f->pos++;
  }
  if (quoted && f->pos < f->len) f->pos++;
  out[n] = '\0';
  return true;
}

/* The rest of the line (a comment, a command), with backslash-newline
 * continuations joined. */
static void rest_of_line(src *f, char *out, size_t cap) {
  size_t n = 0;
  while (f->pos < f->len && f->text[f->pos] != '\n') {
    char c = f->text[f->pos++];
    if (c == '\\' && f->pos < f->len && f->text[f->pos] == '\n') {
      f->pos++, f->line++;
      c = ' ';
    }
    if (n + 1 < cap) out[n++] = c;
  }
  out[n] = '\0';
}

vr_status rad_fail(reader *r, const src *f, long line, const char *fmt, ...) {
  char msg[900];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(msg, sizeof msg, fmt, ap);
  va_end(ap);
  return vr_error_at(r->err, VR_E_PARSE, f->path, line, 0, "%s", msg);
}

/* A count, a real, a whole word. */
static bool to_long(const char *w, long *out) {
  char *end;
  errno = 0;
  long v = strtol(w, &end, 10);
  if (!*w || *end || errno || v < 0 || v > RAD_MAX_ARGS) return false;
  *out = v;
  return true;
}

bool rad_to_real(const char *w, double *out) {
  char *end;
  errno = 0;
  double v = strtod(w, &end);
  if (!*w || *end || !isfinite(v)) return false;
  *out = v;
  return true;
}

static void prim_free(prim *p) {
  for (long i = 0; i < p->nstr; i++) free(p->str[i]);
  free(p->str);
  free(p->real);
  p->str = NULL, p->real = NULL, p->nstr = p->nreal = 0;
}

/* The count that leads a list of arguments (what: their kind). */
static vr_status count(reader *r, src *f, const prim *p, const char *what, long *n) {
  char w[64];
  long line;
  if (!word(f, w, sizeof w, &line) || !to_long(w, n))
    return rad_fail(r, f, p->line, "%s '%s': the count of %s arguments is missing or not a count",
                    p->type, p->id, what);
  return VR_OK;
}

static vr_status read_prim(reader *r, src *f, prim *p) {
  char w[1024];
  long line;
  const char *what[] = {"a type", "an identifier"};
  char *slots[] = {p->type, p->id};
  size_t caps[] = {sizeof p->type, sizeof p->id};
  for (int k = 0; k < 2; k++) {
    if (!word(f, w, sizeof w, &line))
      return rad_fail(r, f, p->line, "'%s': the file ends before %s", p->mod, what[k]);
    if (strlen(w) >= caps[k])
      return rad_fail(r, f, line, "'%.40s...': longer than %zu characters", w, caps[k] - 1);
    memcpy(slots[k], w, strlen(w) + 1);
  }
  long n;
  vr_status st = count(r, f, p, "string", &n);
  if (st) return st;
  if (!(p->str = calloc((size_t)n + 1, sizeof *p->str))) return rad_nomem(r->err);
  for (long i = 0; i < n; i++) {
    if (!word(f, w, sizeof w, &line))
      return rad_fail(r, f, p->line, "%s '%s': the file ends inside its %ld string arguments", p->type,
                  p->id, n);
    if (!(p->str[i] = strdup(w))) return rad_nomem(r->err);
    p->nstr = i + 1;
  }
  if ((st = count(r, f, p, "integer", &n))) return st;
  if (n)
    return rad_fail(r, f, p->line, "%s '%s': %ld integer arguments (no primitive read here takes any)",
                p->type, p->id, n);
  if ((st = count(r, f, p, "real", &n))) return st;
  if (!(p->real = calloc((size_t)n + 1, sizeof *p->real))) return rad_nomem(r->err);
  for (long i = 0; i < n; i++) {
    if (!word(f, w, sizeof w, &line))
      return rad_fail(r, f, p->line, "%s '%s': the file ends inside its %ld real arguments", p->type,
                  p->id, n);
    if (!rad_to_real(w, &p->real[i]))
      return rad_fail(r, f, line, "%s '%s': real argument %ld '%s' is not a finite number", p->type,
                  p->id, i + 1, w);
  }
  p->nreal = n;
  return VR_OK;
}

int rad_lookup(const reader *r, const char *name, bool *found) {
  for (size_t i = r->ndefs; i-- > 0;)
    if (!strcmp(r->defs[i].name, name)) {
      *found = true;
      return r->defs[i].mat;
    }
  *found = false;
  return -1;
}

vr_status rad_define(reader *r, const char *name, int mat) {
  def *d = realloc(r->defs, (r->ndefs + 1) * sizeof *d);
  if (!d) return rad_nomem(r->err);
  r->defs = d;
  snprintf(d[r->ndefs].name, sizeof d->name, "%s", name);
  d[r->ndefs++].mat = mat;
  return VR_OK;
}

static const char *const PATTERNS[] = {
    "texfunc", "texdata", "colorfunc", "brightfunc", "colordata", "brightdata", "colorpict",
    "colortext", "brighttext", "mixfunc", "mixdata", "mixpict", "mixtext", "specfunc", "specdata",
    "specfile", "specpict", NULL};
static const char *const UNREAD_MATERIALS[] = {
    "trans2", "plastic2", "metal2", "ashik2", "plasfunc", "metfunc", "transfunc",
    "plasdata", "metdata", "transdata", "BRTDfunc", "aBSDF", "antimatter", "prism1", "prism2",
    "mist", "interface", "spotlight", "WGMDfunc", NULL};

static bool in(const char *const *list, const char *w) {
  for (; *list; list++)
    if (!strcmp(*list, w)) return true;
  return false;
}

static vr_status read_file(reader *r, const char *path, const vr_xform *x, const char *mod,
                           int depth, const src *from, long from_line);

/* A !command: !xform is parsed and its files read; any other is refused. */
static vr_status command(reader *r, src *f, long line) {
  char buf[4096];
  rest_of_line(f, buf, sizeof buf);
  char *save = NULL, *w = strtok_r(buf, " \t\r", &save);
  if (!w || strcmp(w, "xform"))
    return rad_fail(r, f, line,
                "'!%s': a command; .rad files are read here, never run through a shell (write "
                "its output into the file)", w ? w : "");
  vr_xform t;
  vr_xform_identity(&t);
  char mod[128] = "";
  snprintf(mod, sizeof mod, "%s", f->mod);
  int files = 0;
  vr_status st = VR_OK;
  while (!st && (w = strtok_r(NULL, " \t\r", &save))) {
    vr_xform op;
    vr_xform_identity(&op);
    double v[3];
    int need = 0;
    const char *opt = w;
    if (!strcmp(w, "-t")) need = 3;
    else if (!strcmp(w, "-rx") || !strcmp(w, "-ry") || !strcmp(w, "-rz") || !strcmp(w, "-s"))
      need = 1;
    else if (!strcmp(w, "-n") || !strcmp(w, "-m")) {
      const char *arg = strtok_r(NULL, " \t\r", &save);
      if (!arg) return rad_fail(r, f, line, "!xform: %s needs an argument", w);
      if (!strcmp(w, "-m")) snprintf(mod, sizeof mod, "%s", arg);
      continue;
    } else if (!strcmp(w, "-mx") || !strcmp(w, "-my") || !strcmp(w, "-mz")) {
      int ax = w[2] - 'x';
      op.m[ax][ax] = -1;
    } else if (w[0] == '-') {
      return rad_fail(r, f, line,
                  "!xform option '%s' is not read (read: -t -rx -ry -rz -s -mx -my -mz -n -m)", w);
    } else {
      if (files == 0 && !strcmp(w, "-"))
        return rad_fail(r, f, line, "!xform reading its standard input is not read");
      char path[1100];
      const char *slash = strrchr(f->path, '/');
      int dir = w[0] == '/' || !slash ? 0 : (int)(slash - f->path + 1);
      snprintf(path, sizeof path, "%.*s%s", dir, f->path, w);
      vr_xform all;
      vr_xform_then(&t, &f->x, &all);
      st = read_file(r, path, &all, mod, f->depth + 1, f, line);
      files++;
      continue;
    }
    for (int k = 0; k < need; k++) {
      const char *arg = strtok_r(NULL, " \t\r", &save);
      if (!arg || !rad_to_real(arg, &v[k]))
        return rad_fail(r, f, line, "!xform %s: argument %d is missing or not a number", opt, k + 1);
    }
    if (!strcmp(opt, "-t"))
      for (int k = 0; k < 3; k++) op.m[k][3] = v[k];
    else if (!strcmp(opt, "-s")) {
      if (!(v[0] > 0)) return rad_fail(r, f, line, "!xform -s %g: the scale must be positive", v[0]);
      for (int k = 0; k < 3; k++) op.m[k][k] = v[0];
    } else if (opt[1] == 'r') {
      int ax = opt[2] - 'x', i = (ax + 1) % 3, j = (ax + 2) % 3;
      double c = cos(v[0] * M_PI / 180), s = sin(v[0] * M_PI / 180);
      op.m[i][i] = c, op.m[i][j] = -s, op.m[j][i] = s, op.m[j][j] = c;
    }
    if (files)
      return rad_fail(r, f, line, "!xform: transform '%s' after its files (options come first)", opt);
    vr_xform_then(&t, &op, &t);
  }
  if (!st && !files) return rad_fail(r, f, line, "!xform names no file");
  return st;
}

static vr_status parse(reader *r, src *f) {
  char w[1024];
  long line;
  vr_status st = VR_OK;
  while (!st) {
    while (f->pos < f->len && isspace((unsigned char)f->text[f->pos]))
      if (f->text[f->pos++] == '\n') f->line++;
    if (f->pos >= f->len) break;
    if (f->text[f->pos] == '#') {
      rest_of_line(f, w, sizeof w);
      continue;
    }
    if (f->text[f->pos] == '!') {
      line = f->line;
      f->pos++;
      st = command(r, f, line);
      continue;
    }
    prim p;
    memset(&p, 0, sizeof p);
    word(f, w, sizeof w, &p.line);
    if (strlen(w) >= sizeof p.mod)
      st = rad_fail(r, f, p.line, "'%.40s...': longer than %zu characters", w, sizeof p.mod - 1);
    else {
      memcpy(p.mod, w, strlen(w) + 1);
      st = read_prim(r, f, &p);
    }
    const char *t = p.type;
    if (st) {
    } else if (in(PATTERNS, t)) {
      st = rad_fail(r, f, p.line,
                "%s '%s': patterns, textures and mixtures are not read (a sky is given by the "
                "scene's sky line; map a textured material with material.NAME= in the scene)",
                t, p.id);
    } else if (in(UNREAD_MATERIALS, t)) {
      st = rad_fail(r, f, p.line,
                "%s '%s': this material is not modelled here; map it to a database or scene "
                "material with material.%s=NAME on the mesh line",
                t, p.id, p.id);
    } else if (!strcmp(t, "instance") || !strcmp(t, "mesh")) {
      st = rad_fail(r, f, p.line,
                "%s '%s': octree instances and Radiance meshes are not read (give the model "
                "file itself on a mesh line)", t, p.id);
    } else if (!strcmp(t, "alias")) {
      bool found;
      int mat = p.nstr == 1 ? rad_lookup(r, p.str[0], &found) : (found = false, -1);
      if (p.nstr != 1 || p.nreal)
        st = rad_fail(r, f, p.line, "alias '%s': it takes one string argument, the identifier it copies",
                  p.id);
      else if (strcmp(p.mod, "void"))
        st = rad_fail(r, f, p.line, "alias '%s': a modifier other than void ('%s') is not read", p.id,
                  p.mod);
      else if (!found && !r->walk_only)
        st = rad_fail(r, f, p.line, "alias '%s': '%s' is not defined before it", p.id, p.str[0]);
      else
        st = rad_define(r, p.id, mat);
    } else if (!strcmp(t, "illum")) {
      /* A secondary source: invisible unless it names an alternate
       * material, which its surfaces then are. */
      bool found = true;
      int mat = -1;
      if (p.nstr > 1 || p.nreal != 3)
        st = rad_fail(r, f, p.line, "illum '%s': it takes 0 or 1 string argument and 3 reals", p.id);
      else if (p.nstr == 1 && strcmp(p.str[0], "void"))
        mat = rad_lookup(r, p.str[0], &found);
      if (!st && !found && !r->walk_only)
        st = rad_fail(r, f, p.line, "illum '%s': its alternate material '%s' is not defined before it",
                  p.id, p.str[0]);
      if (!st) st = rad_define(r, p.id, mat);
    } else {
      static const struct {
        const char *type;
        vr_rad_kind kind;
      } M[] = {{"plastic", VR_RAD_PLASTIC}, {"metal", VR_RAD_METAL},
               {"mirror", VR_RAD_MIRROR},   {"glass", VR_RAD_GLASS},
               {"dielectric", VR_RAD_DIELECTRIC}, {"light", VR_RAD_LIGHT},
               {"glow", VR_RAD_GLOW},       {"BSDF", VR_RAD_BSDF},
               {"trans", VR_RAD_TRANS}};
      static const char *const S[] = {"polygon", "sphere", "bubble", "cone", "cup",
                                      "cylinder", "tube", "ring", "source", NULL};
      size_t k = 0;
      while (k < sizeof M / sizeof *M && strcmp(M[k].type, t)) k++;
      if (k < sizeof M / sizeof *M) st = rad_material(r, f, &p, M[k].kind);
      else if (in(S, t)) st = rad_surface(r, f, &p);
      else st = rad_fail(r, f, p.line, "'%s' (identifier '%s') is not a Radiance primitive type", t, p.id);
    }
    prim_free(&p);
  }
  return st;
}

static vr_status read_file(reader *r, const char *path, const vr_xform *x, const char *mod,
                           int depth, const src *from, long from_line) {
  if (depth > RAD_MAX_DEPTH)
    return vr_error_at(r->err, VR_E_PARSE, from->path, from_line, 0,
                       "!xform: files nested more than %d deep (a file that includes itself?)",
                       RAD_MAX_DEPTH);
  FILE *fp = fopen(path, "rb");
  if (!fp) {
    if (from)
      return vr_error_at(r->err, VR_E_IO, from->path, from_line, 0, "!xform: cannot open '%s': %s",
                         path, strerror(errno));
    return vr_error_set(r->err, VR_E_IO, "mesh '%s': %s", path, strerror(errno));
  }
  /* A device or a pipe could be endless (!xform /dev/zero). */
  struct stat sb;
  if (fstat(fileno(fp), &sb) || !S_ISREG(sb.st_mode)) {
    fclose(fp);
    if (from)
      return vr_error_at(r->err, VR_E_IO, from->path, from_line, 0,
                         "!xform: '%s' is not a regular file", path);
    return vr_error_set(r->err, VR_E_IO, "mesh '%s': not a regular file", path);
  }
  src f;
  memset(&f, 0, sizeof f);
  f.path = path;
  f.line = 1;
  f.x = *x;
  f.depth = depth;
  snprintf(f.mod, sizeof f.mod, "%s", mod);
  double det = x->m[0][0] * (x->m[1][1] * x->m[2][2] - x->m[1][2] * x->m[2][1]) -
               x->m[0][1] * (x->m[1][0] * x->m[2][2] - x->m[1][2] * x->m[2][0]) +
               x->m[0][2] * (x->m[1][0] * x->m[2][1] - x->m[1][1] * x->m[2][0]);
  f.flip = det < 0;
  size_t cap = 0;
  vr_status st = VR_OK;
  for (;;) {
    if (f.len + 65536 > cap) {
      cap = cap ? 2 * cap : 65536;
      char *t = realloc(f.text, cap + 1);
      if (!t) {
        st = rad_nomem(r->err);
        break;
      }
      f.text = t;
    }
    size_t got = fread(f.text + f.len, 1, cap - f.len, fp);
    f.len += got;
    if (got == 0) break;
  }
  if (!st && ferror(fp)) st = vr_error_set(r->err, VR_E_IO, "mesh '%s': read error", path);
  fclose(fp);
  char **files = st ? NULL : realloc(r->files, (r->nfiles + 1) * sizeof *files);
  if (!st && !files) st = rad_nomem(r->err);
  if (!st) {
    r->files = files;
    if (!(files[r->nfiles] = strdup(path))) st = rad_nomem(r->err);
    else r->nfiles++;
  }
  if (!st) {
    f.text[f.len] = '\0';
    if (memchr(f.text, '\0', f.len))
      st = vr_error_set(r->err, VR_E_PARSE, "%s: holds NUL bytes: not a Radiance scene text", path);
  }
  if (!st) st = parse(r, &f);
  free(f.text);
  return st;
}

static vr_status run(const char *path, reader *r) {
  vr_xform id;
  vr_xform_identity(&id);
  return read_file(r, path, &id, "", 0, NULL, 0);
}

static void reader_free(reader *r) {
  for (size_t i = 0; i < r->nfiles; i++) free(r->files[i]);
  free(r->files);
  free(r->defs);
}

vr_status vr_rad_read(const char *path, vr_rad_model *out, vr_error *err) {
  memset(out, 0, sizeof *out);
  reader r = {.m = out, .err = err};
  vr_status st = run(path, &r);
  out->files = r.nfiles;
  reader_free(&r);
  if (!st && out->mesh.ntris == 0)
    st = vr_error_set(err, VR_E_PARSE, "mesh '%s': no surfaces (no triangles)", path);
  if (st) vr_rad_free(out);
  return st;
}

void vr_rad_free(vr_rad_model *m) {
  vr_mesh_data_free(&m->mesh);
  free(m->mats);
  free(m->src);
  free(m->polys);
  memset(m, 0, sizeof *m);
}

vr_status vr_rad_digest(const char *path, char hex[65], vr_error *err) {
  vr_rad_model m;
  memset(&m, 0, sizeof m);
  reader r = {.m = &m, .err = err, .walk_only = true};
  vr_status st = run(path, &r);
  vr_sha256 c;
  vr_sha256_init(&c);
  for (size_t i = 0; !st && i < r.nfiles; i++) {
    char h[65];
    if (!(st = vr_sha256_file(r.files[i], h, err))) vr_sha256_update(&c, h, 64);
  }
  if (!st) vr_sha256_final(&c, hex);
  reader_free(&r);
  vr_rad_free(&m);
  return st;
}
