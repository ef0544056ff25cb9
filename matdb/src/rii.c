/* refractiveindex.info YAML input: the database's own format
 * (polyanskiy/refractiveindex.info-database), with a REFERENCES text,
 * COMMENTS, a DATA list of blocks (a dispersion formula, or rows of
 * tabulated n, k or n k, wavelengths in micrometres) and CONDITIONS / SPECS /
 * PROPERTIES mappings.  libyaml reads the YAML; this file maps its nodes onto
 * a vr_material (µm become nm) and keeps every node's position, so that a
 * complaint names the file, the line and the field. */
#include "rii.h"

#include "vr/csv.h"

#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <yaml.h>

/* Bounds on what the property mappings may expand to.  YAML aliases let a
 * small file name the same subtree many times (or inside itself), so the
 * walk is limited in depth and in the number of nodes it visits. */
#define RII_MAX_DEPTH 16
#define RII_MAX_VISITS 100000

typedef struct rii_ctx {
  const char *name; /* file name for messages */
  const char *text; /* the raw text, to find a data field's column */
  size_t len;
  yaml_document_t *doc;
  vr_material *t; /* scratch material, moved into the caller's on success */
  vr_error *err;
  size_t visits;
  /* raw_line() cursor: offset of the start of line cur_line (1-based). */
  size_t cur_off;
  long cur_line;
} rii_ctx;

/* ---------------------------------------------------------------------- */
/* Nodes */

static bool is_scalar(const yaml_node_t *n) { return n && n->type == YAML_SCALAR_NODE; }
static const char *sval(const yaml_node_t *n) { return (const char *)n->data.scalar.value; }
static size_t slen(const yaml_node_t *n) { return n->data.scalar.length; }

static bool scalar_eq(const yaml_node_t *n, const char *s) {
  size_t l = strlen(s);
  return is_scalar(n) && slen(n) == l && memcmp(sval(n), s, l) == 0;
}

/* An empty plain scalar, "~" or "null": YAML's null, a key given no value. */
static bool is_null(const yaml_node_t *n) {
  return is_scalar(n) && n->data.scalar.style == YAML_PLAIN_SCALAR_STYLE &&
         (slen(n) == 0 || scalar_eq(n, "~") || !strcasecmp(sval(n), "null"));
}

static yaml_node_t *node(const rii_ctx *c, int id) { return yaml_document_get_node(c->doc, id); }

static yaml_node_t *map_get(const rii_ctx *c, const yaml_node_t *map, const char *key) {
  for (yaml_node_pair_t *p = map->data.mapping.pairs.start; p < map->data.mapping.pairs.top; p++)
    if (scalar_eq(node(c, p->key), key)) return node(c, p->value);
  return NULL;
}

static vr_status fail_at(const rii_ctx *c, long line, long col, vr_status st, const char *fmt, ...)
    __attribute__((format(printf, 5, 6)));
static vr_status fail_at(const rii_ctx *c, long line, long col, vr_status st, const char *fmt,
                         ...) {
  char msg[VR_ERROR_MESSAGE_MAX];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(msg, sizeof msg, fmt, ap);
  va_end(ap);
  return vr_error_at(c->err, st, c->name, line, col, "%s", msg);
}

/* An error at a node's position (libyaml counts lines and columns from 0). */
#define fail(c, n, st, ...) \
  fail_at((c), (long)(n)->start_mark.line + 1, (long)(n)->start_mark.column + 1, (st), __VA_ARGS__)

/* ---------------------------------------------------------------------- */
/* Numbers */

static bool next_token(const char **p, const char *end, const char **tok, size_t *tlen) {
  const char *s = *p;
  while (s < end && (*s == ' ' || *s == '\t' || *s == '\n' || *s == '\r')) s++;
  if (s == end) {
    *p = s;
    return false;
  }
  const char *e = s;
  while (e < end && !(*e == ' ' || *e == '\t' || *e == '\n' || *e == '\r')) e++;
  *tok = s;
  *tlen = (size_t)(e - s);
  *p = e;
  return true;
}

/* 0, or vr_parse_double's -1 (not a number) / -2 (not finite). */
static int token_number(const char *tok, size_t len, double *out) {
  char buf[64];
  if (len == 0 || len >= sizeof buf || memchr(tok, '\0', len)) return -1;
  memcpy(buf, tok, len);
  buf[len] = '\0';
  return vr_parse_double(buf, out);
}

/* A wavelength in µm, as nm.  The decimal point moves three places in the
 * text ("2.5000e-01" is read as "2.5000e2"), so the result is the double
 * nearest the decimal value in nm: 0.5875618 µm gives the double nearest
 * 587.5618, where strtod("0.5875618") * 1000 can be one ulp off.  It also
 * makes writing exact: any nm double has a µm text that reads back to it
 * (fmt_um).  Hexadecimal floats, whose exponent is binary, are scaled. */
int vr_rii_um_to_nm(const char *tok, size_t len, double *nm) {
  double um;
  int rc = token_number(tok, len, &um);
  if (rc) return rc;
  char buf[96];
  memcpy(buf, tok, len);
  buf[len] = '\0';
  long ex = 0;
  char *e = strpbrk(buf, "eE");
  if (!strpbrk(buf, "xX") && (!e || (ex = strtol(e + 1, NULL, 10), labs(ex) < 100000))) {
    if (e) *e = '\0';
    snprintf(buf + strlen(buf), sizeof buf - strlen(buf), "e%ld", ex + 3);
    *nm = strtod(buf, NULL);
  } else {
    *nm = um * 1000.0;
  }
  return isfinite(*nm) ? 0 : -2;
}

/* The whitespace-separated numbers of a scalar ("0.21 6.7"): the first max
 * go to out (as nm if they are wavelengths in µm), *count says how many
 * there were. */
static vr_status numbers(const rii_ctx *c, const yaml_node_t *n, const char *field, bool um,
                         double *out, size_t max, size_t *count) {
  if (!is_scalar(n))
    return fail(c, n, VR_E_PARSE, "field '%s': expected numbers separated by spaces", field);
  const char *p = sval(n), *end = p + slen(n), *tok;
  size_t len, i = 0;
  while (next_token(&p, end, &tok, &len)) {
    double v;
    int rc = um ? vr_rii_um_to_nm(tok, len, &v) : token_number(tok, len, &v);
    if (rc)
      return fail(c, n, rc == -2 ? VR_E_RANGE : VR_E_PARSE, "field '%s': item %zu, '%.*s', is %s",
                  field, i + 1, (int)(len > 40 ? 40 : len), tok,
                  rc == -2 ? "not a finite number" : "not a number");
    if (i < max) out[i] = v;
    i++;
  }
  *count = i;
  return VR_OK;
}

/* ---------------------------------------------------------------------- */
/* Tabulated rows */

typedef struct rii_rows {
  size_t n, cap;
  double *nm, *a, *b;
} rii_rows;

static void rows_free(rii_rows *r) {
  free(r->nm);
  free(r->a);
  free(r->b);
  memset(r, 0, sizeof *r);
}

static bool rows_push(rii_rows *r, double nm, double a, double b) {
  if (r->n == r->cap) {
    size_t cap = r->cap ? 2 * r->cap : 64;
    if (cap > SIZE_MAX / sizeof(double)) return false;
    double *p;
    if (!(p = realloc(r->nm, cap * sizeof *p))) return false;
    r->nm = p;
    if (!(p = realloc(r->a, cap * sizeof *p))) return false;
    r->a = p;
    if (!(p = realloc(r->b, cap * sizeof *p))) return false;
    r->b = p;
    r->cap = cap;
  }
  r->nm[r->n] = nm;
  r->a[r->n] = a;
  r->b[r->n] = b;
  r->n++;
  return true;
}

/* Line `line` (1-based) of the raw text, without its line break.  Rows are
 * looked up in increasing order, so a cursor makes the walk linear.  Line
 * breaks are counted as libyaml counts them: LF, CR LF and a lone CR. */
static bool raw_line(rii_ctx *c, long line, const char **start, size_t *len) {
  if (line < c->cur_line || c->cur_line == 0) {
    c->cur_line = 1;
    c->cur_off = 0;
  }
  size_t i = c->cur_off;
  while (c->cur_line < line) {
    while (i < c->len && c->text[i] != '\n' && c->text[i] != '\r') i++;
    if (i == c->len) return false;
    if (c->text[i] == '\r' && i + 1 < c->len && c->text[i + 1] == '\n') i++;
    i++;
    c->cur_line++;
    c->cur_off = i;
  }
  size_t e = i;
  while (e < c->len && c->text[e] != '\n' && c->text[e] != '\r') e++;
  *start = c->text + i;
  *len = e - i;
  return true;
}

/* Column of a field on a row of a literal block.  The block's lines lose
 * their indentation in the scalar, so the row is found again as the tail
 * of its line in the raw text; if it is not there (tabs, odd breaks), the
 * message names the line only. */
static long field_col(rii_ctx *c, long line, const char *row, size_t rowlen, const char *tok) {
  const char *raw;
  size_t rawlen;
  if (line <= 0 || !raw_line(c, line, &raw, &rawlen)) return 0;
  if (rawlen < rowlen || memcmp(raw + rawlen - rowlen, row, rowlen) != 0) return 0;
  return (long)(rawlen - rowlen + (size_t)(tok - row)) + 1;
}

/* Reads the rows of a `data:` scalar: ncols numbers per non-blank line,
 * the first a wavelength in µm, strictly increasing. */
static vr_status parse_rows(rii_ctx *c, const yaml_node_t *data, int ncols,
                            const char *const fields[3], rii_rows *r) {
  if (!is_scalar(data))
    return fail(c, data, VR_E_PARSE, "field 'data': expected rows of numbers as text (data: |)");
  /* In a literal block (data: |) the first row is on the line after the
   * indicator and every row keeps its own line; in any other style the
   * rows cannot be placed, and the scalar's own line is named. */
  const bool literal = data->data.scalar.style == YAML_LITERAL_SCALAR_STYLE;
  const long first = (long)data->start_mark.line + (literal ? 2 : 1);
  const char *s = sval(data), *end = s + slen(data);
  size_t row = 0;
  for (long j = 0;; j++) {
    const char *eol = memchr(s, '\n', (size_t)(end - s));
    if (!eol) eol = end;
    const long line = literal ? first + j : first;
    const char *p = s, *tok;
    size_t len;
    double v[3] = {0, 0, 0};
    int k = 0;
    while (next_token(&p, eol, &tok, &len)) {
      if (k == 0) row++;
      long col = literal ? field_col(c, line, s, (size_t)(eol - s), tok) : 0;
      if (k == ncols)
        return fail_at(c, line, col, VR_E_PARSE,
                       "data row %zu: an extra field '%.*s' after '%s' (tabulated rows here have "
                       "%d fields)",
                       row, (int)(len > 40 ? 40 : len), tok, fields[ncols - 1], ncols);
      int rc = k == 0 ? vr_rii_um_to_nm(tok, len, &v[k]) : token_number(tok, len, &v[k]);
      if (rc)
        return fail_at(c, line, col, rc == -2 ? VR_E_RANGE : VR_E_PARSE,
                       "data row %zu: field '%s': %s, got '%.*s'", row, fields[k],
                       rc == -2 ? "not a finite number" : "expected a number",
                       (int)(len > 40 ? 40 : len), tok);
      if (k == 0) {
        if (!(v[0] > 0.0))
          return fail_at(c, line, col, VR_E_RANGE,
                         "data row %zu: field '%s': %g µm is not a positive wavelength", row,
                         fields[0], v[0] / 1000.0);
        if (r->n && !(v[0] > r->nm[r->n - 1]))
          return fail_at(c, line, col, VR_E_PARSE,
                         "data row %zu: field '%s': %.9g µm does not follow the previous row's "
                         "%.9g µm (wavelengths must increase strictly; a repeated wavelength "
                         "is ambiguous)",
                         row, fields[0], v[0] / 1000.0, r->nm[r->n - 1] / 1000.0);
      }
      k++;
    }
    if (k > 0 && k < ncols) {
      long col = literal ? field_col(c, line, s, (size_t)(eol - s), eol) : 0;
      return fail_at(c, line, col, VR_E_PARSE, "data row %zu: field '%s' is missing", row,
                     fields[k]);
    }
    if (k > 0 && !rows_push(r, v[0], v[1], v[2]))
      return vr_error_set(c->err, VR_E_NOMEM, "out of memory");
    if (eol == end) break;
    s = eol + 1;
  }
  if (r->n == 0) return fail(c, data, VR_E_PARSE, "field 'data': no rows");
  return VR_OK;
}

/* ---------------------------------------------------------------------- */
/* DATA blocks */

typedef enum rii_kind { RII_FORMULA, RII_TAB_N, RII_TAB_K, RII_TAB_NK } rii_kind;

/* "formula 1".."formula 9", "tabulated n", "tabulated k", "tabulated nk",
 * words separated and surrounded by any blanks. */
static bool parse_type(const yaml_node_t *n, rii_kind *kind, int *formula) {
  if (!is_scalar(n)) return false;
  const char *p = sval(n), *end = p + slen(n), *w1, *w2, *w3;
  size_t l1, l2, l3;
  if (!next_token(&p, end, &w1, &l1) || !next_token(&p, end, &w2, &l2) ||
      next_token(&p, end, &w3, &l3))
    return false;
  if (l1 == 7 && !strncasecmp(w1, "formula", 7) && l2 == 1 && w2[0] >= '1' && w2[0] <= '9') {
    *kind = RII_FORMULA;
    *formula = w2[0] - '0';
    return true;
  }
  if (l1 != 9 || strncasecmp(w1, "tabulated", 9)) return false;
  if (l2 == 1 && (w2[0] == 'n' || w2[0] == 'N')) *kind = RII_TAB_N;
  else if (l2 == 1 && (w2[0] == 'k' || w2[0] == 'K')) *kind = RII_TAB_K;
  else if (l2 == 2 && !strncasecmp(w2, "nk", 2)) *kind = RII_TAB_NK;
  else return false;
  return true;
}

static vr_status parse_formula(rii_ctx *c, const yaml_node_t *blk, size_t b, int type) {
  const yaml_node_t *rn = map_get(c, blk, "wavelength_range");
  if (!rn) rn = map_get(c, blk, "range"); /* the name in older database files */
  if (!rn)
    return fail(c, blk, VR_E_PARSE,
                "DATA block %zu (formula %d): field 'wavelength_range' is missing (the formula "
                "is only valid on a stated range)",
                b, type);
  double r[2];
  size_t nr;
  vr_status st = numbers(c, rn, "wavelength_range", true, r, 2, &nr);
  if (st) return st;
  if (nr != 2)
    return fail(c, rn, VR_E_PARSE,
                "field 'wavelength_range': expected two wavelengths in µm, found %zu number%s",
                nr, nr == 1 ? "" : "s");
  if (!(r[0] > 0.0 && r[1] > r[0]))
    return fail(c, rn, VR_E_RANGE,
                "field 'wavelength_range': %g to %g µm is not an increasing range of positive "
                "wavelengths",
                r[0] / 1000.0, r[1] / 1000.0);

  const yaml_node_t *cn = map_get(c, blk, "coefficients");
  if (!cn)
    return fail(c, blk, VR_E_PARSE, "DATA block %zu (formula %d): field 'coefficients' is missing",
                b, type);
  vr_formula f = {.type = type, .min_nm = r[0], .max_nm = r[1]};
  st = numbers(c, cn, "coefficients", false, f.c, VR_FORMULA_MAX_COEFFS, &f.ncoeffs);
  if (st) return st;
  if (f.ncoeffs == 0) return fail(c, cn, VR_E_PARSE, "field 'coefficients': no coefficients");
  if (f.ncoeffs > VR_FORMULA_MAX_COEFFS)
    return fail(c, cn, VR_E_PARSE,
                "field 'coefficients': %zu coefficients, but a refractiveindex.info formula has "
                "at most %d",
                f.ncoeffs, VR_FORMULA_MAX_COEFFS);
  /* A formula that cannot be evaluated at the ends of its own range (a pole,
   * n² < 0) is a broken file: say so now rather than in the middle of a
   * render. */
  const double probe[3] = {f.min_nm, 0.5 * (f.min_nm + f.max_nm), f.max_nm};
  for (int i = 0; i < 3; i++) {
    double n;
    vr_error e;
    if (vr_formula_eval(&f, probe[i], &n, &e))
      return fail(c, cn, VR_E_NUMERIC, "field 'coefficients': %s", e.message);
  }
  c->t->n_formula = f;
  return VR_OK;
}

static vr_status add_spectrum(rii_ctx *c, const char *role, size_t n, const double *nm,
                              const double *v) {
  vr_spectrum *s = vr_spectrum_create(n, nm, v, c->err);
  if (!s) return c->err ? c->err->status : VR_E_ARG;
  return vr_material_add_spectrum(c->t, role, s, c->err);
}

static vr_status parse_tabulated(rii_ctx *c, const yaml_node_t *blk, size_t b, rii_kind kind) {
  static const char *const FIELDS[3][3] = {
      {"wavelength", "n", NULL}, {"wavelength", "k", NULL}, {"wavelength", "n", "k"}};
  const char *const *fields = FIELDS[kind == RII_TAB_N ? 0 : kind == RII_TAB_K ? 1 : 2];
  const char *what = kind == RII_TAB_N ? "n" : kind == RII_TAB_K ? "k" : "nk";
  const yaml_node_t *dn = map_get(c, blk, "data");
  if (!dn)
    return fail(c, blk, VR_E_PARSE, "DATA block %zu (tabulated %s): field 'data' is missing", b,
                what);
  rii_rows r = {0};
  vr_status st = parse_rows(c, dn, kind == RII_TAB_NK ? 3 : 2, fields, &r);
  if (!st) {
    if (kind == RII_TAB_NK) {
      st = add_spectrum(c, "n", r.n, r.nm, r.a);
      if (!st) st = add_spectrum(c, "k", r.n, r.nm, r.b);
    } else {
      st = add_spectrum(c, what, r.n, r.nm, r.a);
    }
  }
  rows_free(&r);
  return st;
}

static vr_status parse_data(rii_ctx *c, const yaml_node_t *data, char *model, size_t msize) {
  if (data->type != YAML_SEQUENCE_NODE)
    return fail(c, data, VR_E_PARSE, "DATA: expected a list of blocks ('- type: ...')");
  if (data->data.sequence.items.start == data->data.sequence.items.top)
    return fail(c, data, VR_E_PARSE, "DATA is empty: nothing gives n or k");
  size_t n_from = 0, k_from = 0, b = 0;
  snprintf(model, msize, "rii");
  for (yaml_node_item_t *it = data->data.sequence.items.start; it < data->data.sequence.items.top;
       it++) {
    const yaml_node_t *blk = node(c, *it);
    b++;
    if (!blk || blk->type != YAML_MAPPING_NODE)
      return fail(c, blk ? blk : data, VR_E_PARSE,
                  "DATA block %zu: expected a mapping with 'type' and its data", b);
    const yaml_node_t *tn = map_get(c, blk, "type");
    if (!tn)
      return fail(c, blk, VR_E_PARSE,
                  "DATA block %zu: no 'type' (formula 1 to formula 9, tabulated n, tabulated k "
                  "or tabulated nk)",
                  b);
    rii_kind kind;
    int type = 0;
    if (!parse_type(tn, &kind, &type))
      return fail(c, tn, VR_E_PARSE,
                  "DATA block %zu: field 'type': unknown type '%.60s' (formula 1 to formula 9, "
                  "tabulated n, tabulated k or tabulated nk)",
                  b, is_scalar(tn) ? sval(tn) : "(not text)");
    bool gives_n = kind != RII_TAB_K, gives_k = kind == RII_TAB_K || kind == RII_TAB_NK;
    if (gives_n && n_from)
      return fail(c, blk, VR_E_PARSE,
                  "DATA block %zu: a second definition of n (block %zu already gives n)", b,
                  n_from);
    if (gives_k && k_from)
      return fail(c, blk, VR_E_PARSE,
                  "DATA block %zu: a second definition of k (block %zu already gives k)", b,
                  k_from);
    vr_status st = kind == RII_FORMULA ? parse_formula(c, blk, b, type)
                                       : parse_tabulated(c, blk, b, kind);
    if (st) return st;
    if (gives_n) n_from = b;
    if (gives_k) k_from = b;
    size_t used = strlen(model);
    if (kind == RII_FORMULA)
      snprintf(model + used, msize - used, "%s formula %d", b > 1 ? " +" : "", type);
    else
      snprintf(model + used, msize - used, "%s tabulated %s", b > 1 ? " +" : "",
               kind == RII_TAB_N ? "n" : kind == RII_TAB_K ? "k" : "nk");
  }
  return VR_OK;
}

/* ---------------------------------------------------------------------- */
/* Texts and properties */

/* A text field, trailing blanks and line breaks removed (block scalars end
 * in one); empty text leaves the field NULL. */
static vr_status text_field(rii_ctx *c, const yaml_node_t *v, const char *key, char **field) {
  if (!is_scalar(v)) return fail(c, v, VR_E_PARSE, "%s: expected text", key);
  size_t n = slen(v);
  const char *s = sval(v);
  while (n && (s[n - 1] == ' ' || s[n - 1] == '\t' || s[n - 1] == '\n' || s[n - 1] == '\r')) n--;
  char *copy = malloc(n + 1);
  if (!copy) return vr_error_set(c->err, VR_E_NOMEM, "out of memory");
  memcpy(copy, s, n);
  copy[n] = '\0';
  vr_status st = vr_material_set_text(field, n ? copy : NULL, c->err);
  free(copy);
  return st;
}

static vr_status add_prop(rii_ctx *c, const char *section, const char *key, const yaml_node_t *v) {
  char *alt = NULL;
  /* CONDITIONS and SPECS may both say "temperature"; the later one keeps
   * its section in the key rather than being lost. */
  if (vr_material_property(c->t, key)) {
    size_t n = strlen(section) + strlen(key) + 2;
    if (!(alt = malloc(n))) return vr_error_set(c->err, VR_E_NOMEM, "out of memory");
    snprintf(alt, n, "%s.%s", section, key);
    if (vr_material_property(c->t, alt)) {
      free(alt);
      return fail(c, v, VR_E_PARSE, "%s: property '%s' is given twice", section, key);
    }
    key = alt;
  }
  double x;
  /* Only plain scalars are numbers: a quoted "293" is text in YAML. */
  bool numeric = v->data.scalar.style == YAML_PLAIN_SCALAR_STYLE &&
                 strlen(sval(v)) == slen(v) && vr_parse_double(sval(v), &x) == 0;
  vr_status st = numeric ? vr_material_add_property(c->t, key, NULL, x, NULL, c->err)
                         : vr_material_add_property(c->t, key, sval(v), NAN, NULL, c->err);
  free(alt);
  return st;
}

/* Stores every scalar under a mapping as a property named by its path:
 * nested mappings give "parent.child", list items "parent.1", "parent.2"
 * (a one-item list, as "density: - value: 2510", adds no index). */
static vr_status flatten(rii_ctx *c, const char *section, const char *prefix, const yaml_node_t *n,
                         int depth) {
  if (++c->visits > RII_MAX_VISITS || depth > RII_MAX_DEPTH)
    return fail(c, n, VR_E_PARSE, "%s: nested too deeply or too large (aliases?)", section);
  if (n->type == YAML_SCALAR_NODE) {
    if (is_null(n) || !*prefix) return VR_OK;
    return add_prop(c, section, prefix, n);
  }
  size_t plen = strlen(prefix);
  if (n->type == YAML_MAPPING_NODE) {
    for (yaml_node_pair_t *p = n->data.mapping.pairs.start; p < n->data.mapping.pairs.top; p++) {
      const yaml_node_t *k = node(c, p->key), *v = node(c, p->value);
      if (!k || !v) continue;
      if (!is_scalar(k) || strlen(sval(k)) != slen(k) || slen(k) == 0)
        return fail(c, k, VR_E_PARSE, "%s: expected a plain key", section);
      char *key = malloc(plen + slen(k) + 2);
      if (!key) return vr_error_set(c->err, VR_E_NOMEM, "out of memory");
      snprintf(key, plen + slen(k) + 2, "%s%s%s", prefix, plen ? "." : "", sval(k));
      vr_status st = flatten(c, section, key, v, depth + 1);
      free(key);
      if (st) return st;
    }
  } else if (n->type == YAML_SEQUENCE_NODE) {
    size_t count = (size_t)(n->data.sequence.items.top - n->data.sequence.items.start), i = 0;
    for (yaml_node_item_t *it = n->data.sequence.items.start; it < n->data.sequence.items.top;
         it++) {
      const yaml_node_t *v = node(c, *it);
      i++;
      if (!v) continue;
      char *key = malloc(plen + 24);
      if (!key) return vr_error_set(c->err, VR_E_NOMEM, "out of memory");
      if (count == 1) snprintf(key, plen + 24, "%s", prefix);
      else snprintf(key, plen + 24, "%s.%zu", prefix, i);
      vr_status st = flatten(c, section, key, v, depth + 1);
      free(key);
      if (st) return st;
    }
  }
  return VR_OK;
}

/* ---------------------------------------------------------------------- */
/* Parse */

static vr_status parse_root(rii_ctx *c, const yaml_node_t *root, char *model, size_t msize) {
  if (!root) return vr_error_at(c->err, VR_E_PARSE, c->name, 0, 0, "empty file: no DATA section");
  if (root->type != YAML_MAPPING_NODE)
    return fail(c, root, VR_E_PARSE,
                "expected a mapping with REFERENCES, COMMENTS and DATA at the top level");
  const yaml_node_t *data = NULL;
  for (yaml_node_pair_t *p = root->data.mapping.pairs.start; p < root->data.mapping.pairs.top;
       p++) {
    const yaml_node_t *k = node(c, p->key), *v = node(c, p->value);
    if (!k || !v) continue;
    vr_status st = VR_OK;
    if (scalar_eq(k, "REFERENCES")) {
      st = text_field(c, v, "REFERENCES", &c->t->prov.reference);
    } else if (scalar_eq(k, "COMMENTS")) {
      st = text_field(c, v, "COMMENTS", &c->t->description);
    } else if (scalar_eq(k, "DATA")) {
      if (data) return fail(c, k, VR_E_PARSE, "a second DATA section");
      data = v;
    } else if (scalar_eq(k, "CONDITIONS") || scalar_eq(k, "SPECS") ||
               scalar_eq(k, "PROPERTIES")) {
      if (v->type == YAML_MAPPING_NODE) st = flatten(c, sval(k), "", v, 0);
      else if (!is_null(v)) st = fail(c, v, VR_E_PARSE, "%s: expected a mapping", sval(k));
    }
    if (st) return st;
  }
  if (!data)
    return fail(c, root, VR_E_PARSE, "no DATA section: nothing gives n or k");
  return parse_data(c, data, model, msize);
}

/* libyaml's complaint with its position ("did not find expected key"). */
static vr_status yaml_problem(rii_ctx *c, const yaml_parser_t *p) {
  if (p->error == YAML_MEMORY_ERROR) return vr_error_set(c->err, VR_E_NOMEM, "out of memory");
  const char *problem = p->problem ? p->problem : "unknown problem";
  if (p->error == YAML_READER_ERROR) {
    /* The reader reports a byte offset, not a line. */
    long line = 1, col = 1;
    for (size_t i = 0; i < p->problem_offset && i < c->len; i++, col++)
      if (c->text[i] == '\n') line++, col = 0;
    if (p->problem_value != -1)
      return fail_at(c, line, col, VR_E_PARSE, "malformed YAML: %s (#x%X)", problem,
                     (unsigned)p->problem_value);
    return fail_at(c, line, col, VR_E_PARSE, "malformed YAML: %s", problem);
  }
  long line = (long)p->problem_mark.line + 1, col = (long)p->problem_mark.column + 1;
  if (p->context)
    return fail_at(c, line, col, VR_E_PARSE, "malformed YAML: %s (%s at line %ld)", problem,
                   p->context, (long)p->context_mark.line + 1);
  return fail_at(c, line, col, VR_E_PARSE, "malformed YAML: %s", problem);
}

/* Moves what the scratch material holds into m.  Every allocation happens
 * before anything is moved, so a failure leaves m as it was. */
static vr_status commit(vr_material *m, vr_material *t, vr_error *err) {
  if (t->n_formula.type && (m->n_formula.type || vr_material_spectrum(m, "n")))
    return vr_error_set(err, VR_E_ARG, "material '%s' already has a refractive index", m->name);
  for (size_t i = 0; i < t->nspectra; i++)
    if (vr_material_spectrum(m, t->spectra[i].role) ||
        (!strcmp(t->spectra[i].role, "n") && m->n_formula.type))
      return vr_error_set(err, VR_E_ARG, "material '%s' already has '%s' data", m->name,
                          t->spectra[i].role);
  if (t->nspectra) {
    vr_role_spectrum *p = realloc(m->spectra, (m->nspectra + t->nspectra) * sizeof *p);
    if (!p) return vr_error_set(err, VR_E_NOMEM, "out of memory");
    m->spectra = p;
  }
  if (t->nprops) {
    vr_property *p = realloc(m->props, (m->nprops + t->nprops) * sizeof *p);
    if (!p) return vr_error_set(err, VR_E_NOMEM, "out of memory");
    m->props = p;
  }
  if (t->nspectra) memcpy(m->spectra + m->nspectra, t->spectra, t->nspectra * sizeof *t->spectra);
  m->nspectra += t->nspectra;
  t->nspectra = 0;
  if (t->nprops) memcpy(m->props + m->nprops, t->props, t->nprops * sizeof *t->props);
  m->nprops += t->nprops;
  t->nprops = 0;
  if (t->n_formula.type) m->n_formula = t->n_formula;
  char **from[] = {&t->description, &t->prov.reference, &t->prov.model};
  char **to[] = {&m->description, &m->prov.reference, &m->prov.model};
  for (int i = 0; i < 3; i++)
    if (*from[i]) {
      free(*to[i]);
      *to[i] = *from[i];
      *from[i] = NULL;
    }
  return VR_OK;
}

vr_status vr_rii_parse(const char *text, size_t len, const char *name, vr_material *m,
                       vr_error *err) {
  if (!m || (!text && len)) return vr_error_set(err, VR_E_ARG, "vr_rii_parse: NULL argument");
  vr_material *t = vr_material_create(m->name ? m->name : "", m->kind, err);
  if (!t) return VR_E_NOMEM;
  yaml_parser_t parser;
  if (!yaml_parser_initialize(&parser)) {
    vr_material_destroy(t);
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  yaml_parser_set_input_string(&parser, (const unsigned char *)(text ? text : ""), len);
  rii_ctx c = {.name = name, .text = text ? text : "", .len = len, .t = t, .err = err};
  yaml_document_t doc;
  vr_status st;
  if (!yaml_parser_load(&parser, &doc)) {
    st = yaml_problem(&c, &parser);
  } else {
    c.doc = &doc;
    char model[128];
    st = parse_root(&c, yaml_document_get_root_node(&doc), model, sizeof model);
    if (!st) st = vr_material_set_text(&t->prov.model, model, err);
    if (!st) st = commit(m, t, err);
    yaml_document_delete(&doc);
  }
  yaml_parser_delete(&parser);
  vr_material_destroy(t);
  return st;
}
