/* Model files for vr-ellipso: the line grammar documented in
 * vr/ellipso_model.h and docs/vr-ellipso.md, turned into a vr_sample_model
 * with its parameter list.  Every complaint names the file and the line. */
#include "vr/file.h"
#include "model_internal.h"
#include "vr/csv.h"
#include "vr/matdb.h"
#include "vr/material_io.h"

#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* An effective-medium component named before its layer is defined (a
 * roughness layer above its film): resolved when the file has been read. */
typedef struct pending_component {
  long layer, line;
  int which; /* 0: A, 1: B */
  char name[64];
} pending_component;

typedef struct parser {
  const char *name, *base_dir;
  vr_matdb *db;
  vr_sample_model *m;
  vr_error *err;
  long line;
  pending_component pend[32];
  size_t npend;
} parser;

static vr_status fail(parser *p, vr_status st, const char *fmt, const char *a, const char *b) {
  char msg[512];
  snprintf(msg, sizeof msg, fmt, a ? a : "", b ? b : "");
  return vr_error_at(p->err, st, p->name, p->line, 0, "%s", msg);
}

static vr_status add_param(parser *p, const char *owner_name, const char *pname, long owner,
                           long slot, double lower, double upper) {
  vr_sample_model *m = p->m;
  vr_model_param *q = realloc(m->params, (m->nparams + 1) * sizeof *q);
  if (!q) return vr_error_set(p->err, VR_E_NOMEM, "out of memory");
  m->params = q;
  char full[160];
  snprintf(full, sizeof full, "%s.%s", owner_name, pname);
  vr_model_param np = {strdup(full), owner, slot, lower, upper, false, 0, 0, 1, 0, false};
  if (!np.name) return vr_error_set(p->err, VR_E_NOMEM, "out of memory");
  m->params[m->nparams++] = np;
  return VR_OK;
}

/* The measurement's own parameters, 0 unless a param line sets or frees
 * them: "sample.aoi_offset" (within ±10°), "sample.delta_offset" (within
 * ±180°), "sample.thickness_nonuniformity" (percent full width, 0..100)
 * and "sample.bandwidth" (nm FWHM, 0..100; naming it overrides the
 * bandwidth a data file gives). */
static vr_status add_sample_params(parser *p) {
  vr_status st = add_param(p, "sample", "aoi_offset", VR_OWNER_SAMPLE, VR_SLOT_AOI_OFFSET, -10, 10);
  if (!st) st = add_param(p, "sample", "delta_offset", VR_OWNER_SAMPLE, VR_SLOT_DELTA_OFFSET, -180, 180);
  if (!st)
    st = add_param(p, "sample", "thickness_nonuniformity", VR_OWNER_SAMPLE, VR_SLOT_NONUNIFORMITY, 0, 100);
  return st ? st : add_param(p, "sample", "bandwidth", VR_OWNER_SAMPLE, VR_SLOT_BANDWIDTH, 0, 100);
}

/* Registers every parameter of a dispersion under owner_name. */
static vr_status add_disp_params(parser *p, const char *owner_name, long owner, const vr_dispersion *d) {
  for (size_t i = 0; i < vr_dispersion_nparams(d); i++) {
    vr_status st = add_param(p, owner_name, vr_dispersion_param_name(d, i), owner, (long)i, -INFINITY, INFINITY);
    if (st) return st;
  }
  return VR_OK;
}

static vr_dispersion *material_disp(parser *p, const char *spec) {
  vr_error *err = p->err;
  vr_dispersion *d = NULL;
  /* db:NAME and file:PATH: a stored material, tabulated. */
  int from_db = !strncasecmp(spec, "db:", 3), from_file = !strncasecmp(spec, "file:", 5);
  if (from_db || from_file) {
    vr_material *mat = NULL;
    vr_status st;
    if (from_db) {
      if (!p->db) {
        fail(p, VR_E_ARG, "material '%s' needs the material database (--db)", spec, NULL);
        return NULL;
      }
      st = vr_matdb_load(p->db, spec + 3, 0, &mat, err);
    } else {
      char path[PATH_MAX];
      const char *f = spec + 5;
      if (f[0] == '/' || !p->base_dir) snprintf(path, sizeof path, "%s", f);
      else snprintf(path, sizeof path, "%s/%s", p->base_dir, f);
      st = vr_import_file(path, NULL, NULL, "vr-ellipso", &mat, err);
    }
    if (!st) {
      d = vr_dispersion_from_material(mat, err);
      vr_material_destroy(mat);
    }
    if (!d) vr_error_prefix(err, "%s:%ld: ", p->name, p->line);
    return d;
  }
  char kind[64];
  const char *colon = strchr(spec, ':');
  size_t kl = colon ? (size_t)(colon - spec) : strlen(spec);
  if (kl >= sizeof kind) kl = sizeof kind - 1;
  memcpy(kind, spec, kl);
  kind[kl] = '\0';
  const char *arg = colon ? colon + 1 : NULL;
  if (!strcasecmp(kind, "constant")) d = vr_dispersion_create(VR_DISP_CONSTANT, err);
  else if (!strcasecmp(kind, "cauchy")) d = vr_dispersion_create(VR_DISP_CAUCHY, err);
  else if (!strcasecmp(kind, "sellmeier") || !strcasecmp(kind, "sellmeier2")) {
    d = vr_dispersion_create(strlen(kind) == 9 ? VR_DISP_SELLMEIER : VR_DISP_SELLMEIER2, err);
    long terms = arg ? strtol(arg, NULL, 10) : 1;
    if (d && (terms < 1 || terms > 8)) {
      vr_dispersion_destroy(d);
      fail(p, VR_E_PARSE, "'%s': the number of Sellmeier terms must be 1 to 8", spec, NULL);
      return NULL;
    }
    for (long t = 0; d && t < terms; t++)
      if (vr_dispersion_add_term(d, VR_OSC_LORENTZ, err)) {
        vr_dispersion_destroy(d);
        d = NULL;
      }
  } else if (!strcasecmp(kind, "genosc")) {
    if (!arg || !*arg) {
      fail(p, VR_E_PARSE, "'%s': genosc needs its terms, e.g. genosc:tauc_lorentz+gaussian", spec, NULL);
      return NULL;
    }
    d = vr_dispersion_create(VR_DISP_GENOSC, err);
    char terms[256];
    snprintf(terms, sizeof terms, "%s", arg);
    char *save = NULL;
    for (char *t = strtok_r(terms, "+", &save); d && t; t = strtok_r(NULL, "+", &save)) {
      static const struct { const char *name; vr_osc_kind kind; } OSC[] = {
          {"lorentz", VR_OSC_LORENTZ}, {"drude", VR_OSC_DRUDE}, {"tauc_lorentz", VR_OSC_TAUC_LORENTZ},
          {"cody_lorentz", VR_OSC_CODY_LORENTZ}, {"gaussian", VR_OSC_GAUSSIAN}};
      size_t k = 0;
      while (k < 5 && strcasecmp(t, OSC[k].name)) k++;
      if (k == 5) {
        vr_dispersion_destroy(d);
        fail(p, VR_E_PARSE, "unknown oscillator '%s' (lorentz, drude, tauc_lorentz, cody_lorentz, gaussian)", t, NULL);
        return NULL;
      }
      if (vr_dispersion_add_term(d, OSC[k].kind, err)) {
        vr_dispersion_destroy(d);
        d = NULL;
      }
    }
  } else if (!strcasecmp(kind, "bspline")) {
    double e[64];
    size_t n = 0;
    char list[512];
    snprintf(list, sizeof list, "%s", arg ? arg : "");
    char *save = NULL;
    for (char *t = strtok_r(list, ",", &save); t && n < 64; t = strtok_r(NULL, ",", &save))
      if (vr_parse_double(t, &e[n++])) {
        fail(p, VR_E_PARSE, "'%s': knot '%s' is not a number", spec, t);
        return NULL;
      }
    d = vr_dispersion_create(VR_DISP_BSPLINE, err);
    if (d && vr_dispersion_set_knots(d, n, e, err)) {
      vr_dispersion_destroy(d);
      d = NULL;
    }
  } else {
    fail(p, VR_E_PARSE,
         "unknown material '%s' (constant, cauchy, sellmeier:N, sellmeier2:N, genosc:TERMS, "
         "bspline:E1,...,En, db:NAME, file:PATH)%s", spec, NULL);
    return NULL;
  }
  if (!d) vr_error_prefix(err, "%s:%ld: ", p->name, p->line);
  return d;
}

/* Applies "key=value" settings (n=1, A=1.45) to a dispersion's parameters. */
static vr_status set_inline(parser *p, const char *owner, char **tok, size_t ntok) {
  for (size_t i = 0; i < ntok; i++) {
    char *eq = strchr(tok[i], '=');
    if (!eq) return fail(p, VR_E_PARSE, "unexpected '%s'", tok[i], NULL);
    *eq = '\0';
    char full[160];
    snprintf(full, sizeof full, "%s.%s", owner, tok[i]);
    long k = vr_model_param_index(p->m, full);
    double v;
    if (k < 0) return fail(p, VR_E_PARSE, "'%s' has no parameter '%s'", owner, tok[i]);
    if (vr_parse_double(eq + 1, &v)) return fail(p, VR_E_PARSE, "parameter %s: '%s' is not a number", full, eq + 1);
    *vr_model_param_value(p->m, (size_t)k) = v;
    p->m->params[k].line = p->line;
  }
  return VR_OK;
}

/* "[a*]NAME[*a][+b|-b]" into parameter k's coupling (NAME another
 * parameter that follows none). */
static vr_status couple(parser *p, long k, const char *expr) {
  vr_sample_model *m = p->m;
  double coef = 1, offset = 0;
  char name[160] = "";
  const char *s = expr;
  char *end;
  double a = strtod(s, &end);
  if (end != s && *end == '*') { /* a*NAME */
    coef = a;
    s = end + 1;
  }
  size_t n = 0;
  if (!(isalpha((unsigned char)*s) || *s == '_'))
    return fail(p, VR_E_PARSE,
                "parameter %s: '%s' is neither a number nor a coupling such as "
                "2*film1.A + 0.1",
                m->params[k].name, expr);
  while ((isalnum((unsigned char)*s) || *s == '_' || *s == '.') && n + 1 < sizeof name) name[n++] = *s++;
  name[n] = '\0';
  if (*s == '*') { /* NAME*a */
    coef = strtod(s + 1, &end);
    if (end == s + 1) return fail(p, VR_E_PARSE, "parameter %s: no number after '*' in '%s'", m->params[k].name, expr);
    s = end;
  }
  if (*s == '+' || *s == '-') {
    offset = strtod(s, &end);
    if (end == s || end == s + 1) return fail(p, VR_E_PARSE, "parameter %s: no number after the sign in '%s'", m->params[k].name, expr);
    s = end;
  }
  if (*s) return fail(p, VR_E_PARSE, "parameter %s: cannot read '%s' as [a*]NAME[*a][+b]", m->params[k].name, expr);
  if (!isfinite(coef) || !isfinite(offset))
    return fail(p, VR_E_RANGE, "parameter %s: '%s' is not finite", m->params[k].name, expr);
  long r = vr_model_param_index(m, name);
  if (r < 0) return fail(p, VR_E_PARSE, "parameter %s follows an unknown parameter '%s'", m->params[k].name, name);
  if (r == k) return fail(p, VR_E_PARSE, "parameter %s cannot follow itself", name, NULL);
  if (m->params[r].coupled_to)
    return fail(p, VR_E_PARSE, "parameter %s follows %s, which itself follows another: couple both to the first",
                m->params[k].name, name);
  for (size_t i = 0; i < m->nparams; i++)
    if (m->params[i].coupled_to == k + 1)
      return fail(p, VR_E_PARSE, "parameter %s is followed by others and cannot follow %s", m->params[k].name, name);
  m->params[k].coupled_to = r + 1;
  m->params[k].coef = coef;
  m->params[k].offset = offset;
  m->params[k].line = p->line;
  vr_status st = vr_model_apply_couplings(m, p->err);
  if (st) vr_error_prefix(p->err, "%s:%ld: ", p->name, p->line);
  return st;
}

/* fit / fixed / min=V / max=V for parameter k. */
static vr_status flags(parser *p, long k, char **tok, size_t ntok) {
  vr_model_param *q = &p->m->params[k];
  for (size_t i = 0; i < ntok; i++) {
    double v;
    if (!strcasecmp(tok[i], "fit") || !strcasecmp(tok[i], "free")) q->free = true;
    else if (!strcasecmp(tok[i], "fixed")) q->free = false;
    else if (!strcasecmp(tok[i], "per-sample")) q->per_sample = true;
    else if (!strncasecmp(tok[i], "min=", 4) && !vr_parse_double(tok[i] + 4, &v)) q->lower = v;
    else if (!strncasecmp(tok[i], "max=", 4) && !vr_parse_double(tok[i] + 4, &v)) q->upper = v;
    else return fail(p, VR_E_PARSE, "'%s': expected fit, fixed, per-sample, min=V or max=V", tok[i], NULL);
  }
  if (q->per_sample && !q->free)
    return fail(p, VR_E_PARSE, "parameter %s: per-sample applies to a fitted parameter (add fit)", q->name, NULL);
  if (q->slot == VR_SLOT_BANDWIDTH && q->owner == VR_OWNER_SAMPLE) p->m->bandwidth_set = true;
  if (!(q->lower <= q->upper)) return fail(p, VR_E_PARSE, "parameter %s: min exceeds max", q->name, NULL);
  double v = vr_model_param_get(p->m, (size_t)k);
  if (v < q->lower || v > q->upper) {
    char range[96];
    snprintf(range, sizeof range, "%g is outside [%g, %g]", v, q->lower, q->upper);
    return fail(p, VR_E_RANGE, "parameter %s: start value %s", q->name, range);
  }
  q->line = p->line;
  return VR_OK;
}

static long layer_index(const vr_sample_model *m, const char *name) {
  if (!strcasecmp(name, "void")) return -1;
  for (size_t i = 0; i < m->nlayers; i++)
    if (!strcmp(m->layers[i].name, name)) return (long)i;
  return -2;
}

static vr_status statement(parser *p, char **tok, size_t ntok) {
  vr_sample_model *m = p->m;
  vr_status st;
  const char *kw = tok[0];
  if (!strcasecmp(kw, "ambient") || !strcasecmp(kw, "substrate")) {
    int amb = !strcasecmp(kw, "ambient");
    if (ntok < 2) return fail(p, VR_E_PARSE, "'%s' needs a material", kw, NULL);
    if (amb ? m->ambient != NULL : m->substrate != NULL) return fail(p, VR_E_PARSE, "a second '%s' line", kw, NULL);
    vr_dispersion *d = material_disp(p, tok[1]);
    if (!d) return p->err ? p->err->status : VR_E_PARSE;
    long owner = amb ? VR_OWNER_AMBIENT : VR_OWNER_SUBSTRATE;
    if (amb) m->ambient = d;
    else m->substrate = d;
    if ((st = add_disp_params(p, kw, owner, d))) return st;
    size_t rest = 2;
    if (!amb) {
      if ((st = add_param(p, "substrate", "thickness", owner, VR_SLOT_THICKNESS, 0, INFINITY))) return st;
      /* thickness= and backside may stand anywhere among the material's
       * inline parameters; the others are kept in order for set_inline. */
      size_t kept = rest;
      for (size_t i = rest; i < ntok; i++) {
        double mm;
        if (!strcasecmp(tok[i], "backside")) m->backside = true;
        else if (!strncasecmp(tok[i], "thickness=", 10)) {
          if (vr_parse_double(tok[i] + 10, &mm) || !(mm > 0))
            return fail(p, VR_E_RANGE, "substrate thickness '%s' must be a positive number of mm", tok[i] + 10, NULL);
          m->substrate_thickness_nm = mm * 1e6;
        } else tok[kept++] = tok[i];
      }
      ntok = kept;
      if (m->backside && !(m->substrate_thickness_nm > 0))
        return fail(p, VR_E_PARSE, "backside needs the substrate thickness (thickness=MM)", NULL, NULL);
    }
    return set_inline(p, kw, tok + rest, ntok - rest);
  }
  if (!strcasecmp(kw, "layer")) {
    if (ntok < 3) return fail(p, VR_E_PARSE, "'layer' needs a name and a material", NULL, NULL);
    const char *name = tok[1];
    if (!strcmp(name, "ambient") || !strcmp(name, "substrate") || !strcasecmp(name, "void") ||
        layer_index(m, name) >= 0 || strchr(name, '.'))
      return fail(p, VR_E_PARSE, "layer name '%s' is reserved, repeated or contains '.'", name, NULL);
    vr_model_layer L = {0};
    L.ema_a = L.ema_b = -1;
    L.fraction = 0.5;
    if (!strncasecmp(tok[2], "ema=", 4)) {
      char *open = strchr(tok[2], '('), *comma = open ? strchr(open, ',') : NULL,
           *close = comma ? strchr(comma, ')') : NULL;
      if (!close) return fail(p, VR_E_PARSE, "'%s': expected ema=bruggeman(A,B) or ema=maxwell-garnett(A,B)", tok[2], NULL);
      *open = *comma = *close = '\0';
      const char *kind = tok[2] + 4;
      if (!strcasecmp(kind, "bruggeman")) L.ema = VR_EMA_BRUGGEMAN;
      else if (!strcasecmp(kind, "maxwell-garnett") || !strcasecmp(kind, "mg")) L.ema = VR_EMA_MAXWELL_GARNETT;
      else return fail(p, VR_E_PARSE, "unknown effective medium '%s'", kind, NULL);
      L.ema_a = layer_index(m, open + 1);
      L.ema_b = layer_index(m, comma + 1);
      /* A component not defined yet is looked up when the file is read:
       * it must then be a layer below with a material of its own. */
      const char *cname[2] = {open + 1, comma + 1};
      long *cidx[2] = {&L.ema_a, &L.ema_b};
      for (int c = 0; c < 2; c++) {
        if (*cidx[c] >= -1) continue;
        if (p->npend == sizeof p->pend / sizeof *p->pend || strlen(cname[c]) >= sizeof p->pend[0].name)
          return fail(p, VR_E_PARSE, "effective medium component '%s': too many or too long a name", cname[c], NULL);
        pending_component *q = &p->pend[p->npend++];
        q->layer = (long)m->nlayers, q->line = p->line, q->which = c;
        snprintf(q->name, sizeof q->name, "%s", cname[c]);
        *cidx[c] = -1;
      }
    } else if (!(L.disp = material_disp(p, tok[2]))) {
      return p->err ? p->err->status : VR_E_PARSE;
    }
    if (!(L.name = strdup(name))) {
      vr_dispersion_destroy(L.disp);
      return vr_error_set(p->err, VR_E_NOMEM, "out of memory");
    }
    vr_model_layer *nl = realloc(m->layers, (m->nlayers + 1) * sizeof *nl);
    if (!nl) {
      free(L.name);
      vr_dispersion_destroy(L.disp);
      return vr_error_set(p->err, VR_E_NOMEM, "out of memory");
    }
    m->layers = nl;
    long idx = (long)m->nlayers;
    m->layers[m->nlayers++] = L;
    if ((st = add_param(p, name, "thickness", idx, VR_SLOT_THICKNESS, 0, 1e6))) return st;
    long tk = (long)m->nparams - 1;
    if (L.ema && (st = add_param(p, name, "fraction", idx, VR_SLOT_FRACTION, 0, 1))) return st;
    if (L.disp && (st = add_disp_params(p, name, idx, L.disp))) return st;
    /* key=value settings (thickness=, fraction=, dispersion parameters) and
     * the flags fit / fixed / min= / max=, which apply to the thickness. */
    char *flagtok[32];
    size_t nflags = 0;
    int have_thickness = 0;
    for (size_t i = 3; i < ntok; i++) {
      char *eq = strchr(tok[i], '=');
      if (!eq || !strncasecmp(tok[i], "min=", 4) || !strncasecmp(tok[i], "max=", 4)) {
        flagtok[nflags++] = tok[i];
        continue;
      }
      double v;
      *eq = '\0';
      if (!strcasecmp(tok[i], "thickness") || (!strcasecmp(tok[i], "fraction") && L.ema)) {
        if (vr_parse_double(eq + 1, &v)) return fail(p, VR_E_PARSE, "'%s': '%s' is not a number", tok[i], eq + 1);
        if (!strcasecmp(tok[i], "thickness")) {
          if (v < 0) return fail(p, VR_E_RANGE, "layer '%s': negative thickness %s nm", name, eq + 1);
          m->layers[idx].thickness_nm = v;
          have_thickness = 1;
        } else {
          if (v < 0 || v > 1) return fail(p, VR_E_RANGE, "layer '%s': fraction %s outside [0, 1]", name, eq + 1);
          m->layers[idx].fraction = v;
        }
      } else {
        *eq = '=';
        if ((st = set_inline(p, name, &tok[i], 1))) return st;
      }
    }
    if (!have_thickness) return fail(p, VR_E_PARSE, "layer '%s' needs thickness=NM", name, NULL);
    return flags(p, tk, flagtok, nflags);
  }
  if (!strcasecmp(kw, "param")) {
    /* param NAME.P = V flags...   or   param NAME.P=V flags... */
    if (ntok < 2) return fail(p, VR_E_PARSE, "'param' needs NAME.PARAMETER = VALUE", NULL, NULL);
    char *name = tok[1], *value = NULL;
    size_t i = 2;
    char *eq = strchr(name, '=');
    if (eq) {
      *eq = '\0';
      value = eq + 1;
    } else if (i < ntok && !strcmp(tok[i], "=")) {
      i++;
      if (i < ntok) value = tok[i++];
    } else if (i < ntok && tok[i][0] == '=') {
      value = tok[i++] + 1;
    }
    long k = vr_model_param_index(m, name);
    if (k < 0) return fail(p, VR_E_PARSE, "unknown parameter '%s'", name, NULL);
    double v;
    /* The value's words up to the first flag, joined: a number, or a
     * coupling (a linear expression of another parameter). */
    char expr[256] = "";
    if (value) {
      snprintf(expr, sizeof expr, "%s", value);
      while (i < ntok && strcasecmp(tok[i], "fit") && strcasecmp(tok[i], "free") &&
             strcasecmp(tok[i], "fixed") && strcasecmp(tok[i], "per-sample") && strncasecmp(tok[i], "min=", 4) &&
             strncasecmp(tok[i], "max=", 4)) {
        size_t l = strlen(expr);
        snprintf(expr + l, sizeof expr - l, "%s", tok[i++]);
      }
      value = expr;
    }
    if (value && vr_parse_double(value, &v)) {
      vr_status st = couple(p, k, expr);
      if (st) return st;
      st = flags(p, k, tok + i, ntok - i);
      if (!st && m->params[k].free)
        return fail(p, VR_E_PARSE, "parameter %s follows another: it cannot also be fitted", name, NULL);
      return st;
    }
    if (value) {
      if (m->params[k].slot == VR_SLOT_THICKNESS && v < 0)
        return fail(p, VR_E_RANGE, "parameter %s: negative thickness %s", name, value);
      *vr_model_param_value(m, (size_t)k) = v;
    }
    return flags(p, k, tok + i, ntok - i);
  }
  return fail(p, VR_E_PARSE, "unknown statement '%s' (ambient, layer, substrate, param)", kw, NULL);
}

vr_status vr_model_parse(const char *text, size_t len, const char *name, const char *base_dir,
                         vr_matdb *db, vr_sample_model **out, vr_error *err) {
  *out = NULL;
  vr_sample_model *m = calloc(1, sizeof *m);
  char *buf = malloc(len + 1);
  if (!m || !buf || !(m->source = strdup(name))) {
    free(buf);
    vr_model_destroy(m);
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  memcpy(buf, text, len);
  buf[len] = '\0';
  parser p = {.name = name, .base_dir = base_dir, .db = db, .m = m, .err = err};
  vr_status st = add_sample_params(&p);
  for (char *s = buf, *next; s && *s && !st; s = next) {
    p.line++;
    next = strchr(s, '\n');
    if (next) *next++ = '\0';
    char *hash = strchr(s, '#');
    if (hash) *hash = '\0';
    char *tok[32];
    size_t ntok = 0;
    char *save = NULL;
    for (char *t = strtok_r(s, " \t\r", &save); t; t = strtok_r(NULL, " \t\r", &save)) {
      if (ntok == 32) {
        st = fail(&p, VR_E_PARSE, "too many words on one line%s", "", NULL);
        break;
      }
      tok[ntok++] = t;
    }
    if (!st && ntok) st = statement(&p, tok, ntok);
  }
  free(buf);
  for (size_t i = 0; !st && i < p.npend; i++) {
    const pending_component *q = &p.pend[i];
    long k = layer_index(m, q->name);
    if (k < -1)
      st = vr_error_at(err, VR_E_PARSE, name, q->line, 0,
                       "effective medium of layer '%s': no layer '%s' (name a layer of this model or void)",
                       m->layers[q->layer].name, q->name);
    else if (k >= 0 && !m->layers[k].disp)
      st = vr_error_at(err, VR_E_PARSE, name, q->line, 0,
                       "effective medium of layer '%s': '%s' comes later and is itself an effective "
                       "medium; a component named before its layer must have a material of its own",
                       m->layers[q->layer].name, q->name);
    else if (q->which) m->layers[q->layer].ema_b = k;
    else m->layers[q->layer].ema_a = k;
  }
  if (!st && !m->substrate) st = vr_error_at(err, VR_E_PARSE, name, 0, 0, "no 'substrate' line");
  if (!st && !m->ambient) {
    /* Air by default. */
    if (!(m->ambient = vr_dispersion_create(VR_DISP_CONSTANT, err))) st = VR_E_NOMEM;
    else st = add_disp_params(&p, "ambient", VR_OWNER_AMBIENT, m->ambient);
  }
  if (st) {
    vr_model_destroy(m);
    return st;
  }
  *out = m;
  return VR_OK;
}

vr_status vr_model_read(const char *path, vr_matdb *db, vr_sample_model **out, vr_error *err) {
  vr_status rs = vr_file_check_regular(path, err);
  if (rs) return rs;
  FILE *f = fopen(path, "rb");
  if (!f) return vr_error_at(err, VR_E_IO, path, 0, 0, "cannot open: %s", strerror(errno));
  char buf[1 << 16];
  size_t n = fread(buf, 1, sizeof buf, f);
  int big = !feof(f);
  fclose(f);
  if (big) return vr_error_at(err, VR_E_PARSE, path, 0, 0, "model file larger than 64 KiB");
  char dir[PATH_MAX];
  snprintf(dir, sizeof dir, "%s", path);
  char *slash = strrchr(dir, '/');
  if (slash) *slash = '\0';
  else snprintf(dir, sizeof dir, ".");
  return vr_model_parse(buf, n, path, dir, db, out, err);
}

vr_sample_model *vr_model_bulk(vr_dispersion *substrate, vr_error *err) {
  vr_sample_model *m = calloc(1, sizeof *m);
  if (!m || !(m->source = strdup("bulk"))) {
    free(m);
    vr_dispersion_destroy(substrate);
    vr_error_set(err, VR_E_NOMEM, "out of memory");
    return NULL;
  }
  m->substrate = substrate;
  /* The bulk analysis inverts the measured values as they are: a bare
   * substrate's Ψ, Δ vary slowly with wavelength, so an instrument's
   * bandwidth changes them only to second order in b / λ. */
  m->bandwidth_set = true;
  parser p = {.name = "bulk", .m = m, .err = err};
  if (add_sample_params(&p) || !(m->ambient = vr_dispersion_create(VR_DISP_CONSTANT, err)) ||
      add_disp_params(&p, "ambient", VR_OWNER_AMBIENT, m->ambient) ||
      add_disp_params(&p, "substrate", VR_OWNER_SUBSTRATE, substrate)) {
    vr_model_destroy(m);
    return NULL;
  }
  return m;
}
