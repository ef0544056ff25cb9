/* Reading Klems BSDF XML files with libxml2 (vr/bsdf_xml.h).
 *
 * Elements are found by their local name, so files with the windows.lbl.gov
 * namespace (WINDOW, IGSDB) and without it (genBSDF) read alike.  Every
 * refusal names the file, the line of the element and the element. */
#include "vr/bsdf_xml.h"

#include "bsdf_xml_tree.h"

#include <errno.h>
#include <stdarg.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include <libxml/parser.h>
#include <libxml/tree.h>
#include <libxml/xmlversion.h>

typedef struct reader {
  const char *path;
  vr_error *err;
} reader;

static vr_status fail(reader *r, const xmlNode *at, vr_status st, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

static vr_status fail(reader *r, const xmlNode *at, vr_status st, const char *fmt, ...) {
  char msg[768];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(msg, sizeof msg, fmt, ap);
  va_end(ap);
  long line = at ? xmlGetLineNo(at) : 0;
  return vr_error_at(r->err, st, r->path, line, 0, "%s", msg);
}

static int is(const xmlNode *n, const char *name) {
  return n && n->type == XML_ELEMENT_NODE && !strcmp((const char *)n->name, name);
}

static xmlNode *child(const xmlNode *n, const char *name) {
  for (xmlNode *c = n ? n->children : NULL; c; c = c->next)
    if (is(c, name)) return c;
  return NULL;
}

/* The element's text, trimmed, into buf (empty when absent). */
static const char *text(const xmlNode *n, char *buf, size_t size) {
  buf[0] = 0;
  if (!n) return buf;
  xmlChar *t = xmlNodeGetContent(n);
  if (!t) return buf;
  const char *s = (const char *)t;
  while (*s == ' ' || *s == '\t' || *s == '\n' || *s == '\r') s++;
  size_t len = strlen(s);
  while (len && (s[len - 1] == ' ' || s[len - 1] == '\t' || s[len - 1] == '\n' || s[len - 1] == '\r'))
    len--;
  if (len >= size) len = size - 1;
  memcpy(buf, s, len);
  buf[len] = 0;
  xmlFree(t);
  return buf;
}

/* A number child of n (required). */
static vr_status number(reader *r, const xmlNode *n, const char *name, double *v) {
  char buf[64], *end;
  xmlNode *c = child(n, name);
  if (!c) return fail(r, n, VR_E_PARSE, "<%s> has no <%s>", (const char *)n->name, name);
  text(c, buf, sizeof buf);
  errno = 0;
  *v = strtod(buf, &end);
  if (!buf[0] || *end || errno || !isfinite(*v))
    return fail(r, c, VR_E_PARSE, "<%s> '%s': expected a number", name, buf);
  return VR_OK;
}

static vr_status read_basis(reader *r, const xmlNode *ab, vr_klems_basis *b) {
  char buf[128];
  memset(b, 0, sizeof *b);
  snprintf(b->name, sizeof b->name, "%s", text(child(ab, "AngleBasisName"), buf, sizeof buf));
  int bounds = 0;
  for (xmlNode *c = ab->children; c; c = c->next) {
    if (!is(c, "AngleBasisBlock")) continue;
    if (b->nrings == VR_KLEMS_MAX_RINGS)
      return fail(r, c, VR_E_RANGE, "<AngleBasis> '%s': more than %d rings", b->name,
                  VR_KLEMS_MAX_RINGS);
    int k = b->nrings;
    double nphi;
    if (number(r, c, "Theta", &b->theta_c[k]) || number(r, c, "nPhis", &nphi)) return r->err->status;
    if (nphi != floor(nphi) || nphi < 1 || nphi > 100000)
      return fail(r, child(c, "nPhis"), VR_E_RANGE, "<nPhis> %g: expected a whole number >= 1", nphi);
    b->nphi[k] = (int)nphi;
    xmlNode *tb = child(c, "ThetaBounds");
    if (tb) {
      if (number(r, tb, "LowerTheta", &b->theta_lo[k]) || number(r, tb, "UpperTheta", &b->theta_hi[k]))
        return r->err->status;
      bounds++;
    }
    b->nrings++;
  }
  if (b->nrings == 0) return fail(r, ab, VR_E_PARSE, "<AngleBasis> '%s' has no <AngleBasisBlock>", b->name);
  if (bounds && bounds != b->nrings)
    return fail(r, ab, VR_E_PARSE, "<AngleBasis> '%s': %d of %d blocks give <ThetaBounds>", b->name,
                bounds, b->nrings);
  if (!bounds) {
    /* Without bounds, a basis LBNL defines is known by its name (as
     * Radiance reads it); any other needs its <ThetaBounds>. */
    vr_klems_basis known;
    if (!vr_klems_named(b->name, &known))
      return fail(r, ab, VR_E_PARSE,
                  "<AngleBasis> '%s' gives no <ThetaBounds>, and is not a basis known by name "
                  "(LBNL/Klems Full, Half or Quarter)", b->name);
    if (known.nrings != b->nrings)
      return fail(r, ab, VR_E_PARSE, "<AngleBasis> '%s' has %d blocks; that basis has %d rings",
                  b->name, b->nrings, known.nrings);
    for (int k = 0; k < b->nrings; k++)
      if (known.nphi[k] != b->nphi[k])
        return fail(r, ab, VR_E_PARSE, "<AngleBasis> '%s': ring %d has %d azimuths; that basis has %d",
                    b->name, k + 1, b->nphi[k], known.nphi[k]);
    *b = known;
  }
  vr_error e = {0};
  if (vr_klems_finish(b, &e)) return fail(r, ab, e.status, "%s", e.message);
  return VR_OK;
}

static int side_of(const char *s) {
  for (int i = 0; i < VR_BSDF_SIDES; i++)
    if (!strcasecmp(s, vr_bsdf_side_name((vr_bsdf_side)i))) return i;
  return -1;
}

/* n x n numbers from a <ScatteringData>, in m[out * n + in] order. */
static vr_status read_matrix(reader *r, const xmlNode *sd, int n, int rows, double *m) {
  xmlChar *t = xmlNodeGetContent(sd);
  if (!t) return fail(r, sd, VR_E_NOMEM, "out of memory reading <ScatteringData>");
  const char *s = (const char *)t;
  long line = xmlGetLineNo(sd);
  size_t want = (size_t)n * n, k = 0;
  vr_status st = VR_OK;
  for (;;) {
    while (*s == ' ' || *s == '\t' || *s == '\r' || *s == '\n' || *s == ',') {
      if (*s == '\n') line++;
      s++;
    }
    if (!*s) break;
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || errno || !isfinite(v) || v < 0) {
      int len = 0;
      while (s[len] && s[len] != ' ' && s[len] != ',' && s[len] != '\n' && len < 24) len++;
      st = vr_error_at(r->err, end == s || errno || !isfinite(v) ? VR_E_PARSE : VR_E_RANGE, r->path,
                       line, 0, "<ScatteringData> value %zu '%.*s': expected a finite BSDF >= 0 (1/sr)",
                       k + 1, len, s);
      break;
    }
    if (k < want) {
      size_t a = k / (size_t)n, b = k % (size_t)n; /* a-th line, b-th value in it */
      if (rows) m[b * n + a] = v;                  /* each line one incident direction */
      else m[a * n + b] = v;                       /* each column one incident direction */
    }
    k++;
    s = end;
  }
  xmlFree(t);
  if (!st && k != want)
    st = fail(r, sd, VR_E_PARSE, "<ScatteringData> holds %zu values; a %d-patch basis needs %d x %d = %zu",
              k, n, n, n, want);
  return st;
}

static vr_bsdf_band *band_for(reader *r, vr_bsdf_xml *x, const xmlNode *wd) {
  char name[64], unit[32] = "";
  xmlNode *w = child(wd, "Wavelength");
  if (!w) {
    fail(r, wd, VR_E_PARSE, "<WavelengthData> has no <Wavelength>");
    return NULL;
  }
  text(w, name, sizeof name);
  xmlChar *u = xmlGetProp(w, (const xmlChar *)"unit");
  if (u) {
    snprintf(unit, sizeof unit, "%s", (const char *)u);
    xmlFree(u);
  }
  double nm = NAN;
  if (unit[0] && strcasecmp(unit, "Integral")) {
    double scale = !strcasecmp(unit, "Nanometer") ? 1 : !strcasecmp(unit, "Micron") ? 1000 : 0;
    char *end;
    double v = strtod(name, &end);
    if (!scale) {
      fail(r, w, VR_E_PARSE, "<Wavelength unit=\"%s\">: expected Integral, Nanometer or Micron", unit);
      return NULL;
    }
    if (!name[0] || *end || !(v > 0) || !isfinite(v)) {
      fail(r, w, VR_E_PARSE, "<Wavelength unit=\"%s\"> '%s': expected a wavelength", unit, name);
      return NULL;
    }
    nm = v * scale;
  } else if (!name[0]) {
    fail(r, w, VR_E_PARSE, "<Wavelength> is empty: expected Visible, Solar or a wavelength");
    return NULL;
  }
  for (size_t i = 0; i < x->nbands; i++)
    if (!strcasecmp(x->bands[i].name, name)) return &x->bands[i];
  vr_bsdf_band *nb = realloc(x->bands, (x->nbands + 1) * sizeof *nb);
  if (!nb) {
    fail(r, wd, VR_E_NOMEM, "out of memory");
    return NULL;
  }
  x->bands = nb;
  vr_bsdf_band *b = &x->bands[x->nbands++];
  memset(b, 0, sizeof *b);
  snprintf(b->name, sizeof b->name, "%s", name);
  b->nm = nm;
  return b;
}

static vr_status read_block(reader *r, vr_bsdf_xml *x, vr_bsdf_band *band, const xmlNode *blk,
                            int rows) {
  char buf[128];
  xmlNode *dir = child(blk, "WavelengthDataDirection");
  if (!dir) return fail(r, blk, VR_E_PARSE, "<WavelengthDataBlock> has no <WavelengthDataDirection>");
  int side = side_of(text(dir, buf, sizeof buf));
  if (side < 0)
    return fail(r, dir, VR_E_PARSE,
                "<WavelengthDataDirection> '%s': expected Transmission Front, Transmission Back, "
                "Reflection Front or Reflection Back", buf);
  const char *bases[2] = {"ColumnAngleBasis", "RowAngleBasis"};
  for (int i = 0; i < 2; i++) {
    xmlNode *c = child(blk, bases[i]);
    char name[sizeof x->basis.name]; /* cut as the basis's own name was */
    if (!c || !strcasecmp(text(c, name, sizeof name), x->basis.name)) continue;
    text(c, buf, sizeof buf);
    return fail(r, c, VR_E_PARSE,
                "<%s> '%s': the file defines the basis '%s'; a block on another basis (or "
                "different incident and exiting bases) is not read", bases[i], buf, x->basis.name);
  }
  xmlNode *type = child(blk, "ScatteringDataType");
  if (type) {
    text(type, buf, sizeof buf);
    if (strcasecmp(buf, "BTDF") && strcasecmp(buf, "BRDF"))
      return fail(r, type, VR_E_PARSE, "<ScatteringDataType> '%s': expected BTDF or BRDF", buf);
  }
  if (band->m[side])
    return fail(r, dir, VR_E_PARSE, "'%s' of band %s is given twice", vr_bsdf_side_name((vr_bsdf_side)side),
                band->name);
  xmlNode *sd = child(blk, "ScatteringData");
  if (!sd) return fail(r, blk, VR_E_PARSE, "<WavelengthDataBlock> has no <ScatteringData>");
  int n = x->basis.n;
  band->m[side] = calloc((size_t)n * n, sizeof(double));
  if (!band->m[side]) return fail(r, blk, VR_E_NOMEM, "out of memory");
  return read_matrix(r, sd, n, rows, band->m[side]);
}

/* Incident directions a Klems patch takes from a tensor tree, each with a
 * 16 x 16 grid of exiting directions (bsdf_xml_tree.c).  256: the patch's
 * mean over incident directions is what limits the figures (32 left them
 * 1.3 % rms from Radiance's 16 384-sample bsdf2klems in transmission, 0.7 %
 * in reflection; 256 leaves 0.26 and 0.12 %, tests/matdb/
 * test_bsdf_xml_tree.c), while a finer exiting grid changed nothing: the
 * grid's Halton offset moves with each incident direction. */
#ifdef VR_FUZZING
#define TT_SAMPLES 1 /* a fuzzing build: the same paths, within libFuzzer's time limit */
#else
#define TT_SAMPLES 256
#endif

/* A tensor-tree file (TensorTree3 or 4, nd dimensions): every block's
 * tree, then each band resampled onto the Klems full basis
 * (bsdf_xml_tree.h). */
static vr_status read_trees(reader *r, const xmlNode *layer, vr_bsdf_xml *x, int nd) {
  char buf[128];
  vr_klems_full(&x->basis);
  x->tensor_tree = nd;
  vr_tt_tree *(*trees)[VR_BSDF_SIDES] = NULL;
  size_t ntrees = 0;
  vr_status st = VR_OK;
  size_t blocks = 0;
  for (xmlNode *wd = layer->children; wd && !st; wd = wd->next) {
    if (!is(wd, "WavelengthData")) continue;
    vr_bsdf_band *band = band_for(r, x, wd);
    if (!band) {
      st = r->err->status;
      break;
    }
    size_t bi = (size_t)(band - x->bands);
    if (bi >= ntrees) {
      void *g = realloc(trees, (bi + 1) * sizeof *trees);
      if (!g) {
        st = fail(r, wd, VR_E_NOMEM, "out of memory");
        break;
      }
      trees = g;
      memset(trees + ntrees, 0, (bi + 1 - ntrees) * sizeof *trees);
      ntrees = bi + 1;
    }
    for (xmlNode *blk = wd->children; blk && !st; blk = blk->next) {
      if (!is(blk, "WavelengthDataBlock")) continue;
      xmlNode *dir = child(blk, "WavelengthDataDirection");
      int side = dir ? side_of(text(dir, buf, sizeof buf)) : -1;
      if (side < 0) {
        st = fail(r, dir ? dir : blk, VR_E_PARSE,
                  "<WavelengthDataDirection> '%s': expected Transmission Front, Transmission "
                  "Back, Reflection Front or Reflection Back", dir ? buf : "");
        break;
      }
      xmlNode *ab = child(blk, "AngleBasis");
      if (ab && strcasecmp(text(ab, buf, sizeof buf), "LBNL/Shirley-Chiu")) {
        st = fail(r, ab, VR_E_PARSE, "<AngleBasis> '%s': a tensor tree is on LBNL/Shirley-Chiu", buf);
        break;
      }
      if (trees[bi][side]) {
        st = fail(r, dir, VR_E_PARSE, "'%s' of band %s is given twice",
                  vr_bsdf_side_name((vr_bsdf_side)side), band->name);
        break;
      }
      xmlNode *sd = child(blk, "ScatteringData");
      if (!sd) {
        st = fail(r, blk, VR_E_PARSE, "<WavelengthDataBlock> has no <ScatteringData>");
        break;
      }
      xmlChar *t = xmlNodeGetContent(sd);
      char msg[200];
      long line = 0;
      trees[bi][side] = t ? vr_tt_parse((const char *)t, nd, msg, sizeof msg, &line) : NULL;
      xmlFree(t);
      if (!trees[bi][side]) {
        st = vr_error_at(r->err, VR_E_PARSE, r->path, xmlGetLineNo(sd) + line - 1, 0,
                         "<ScatteringData> (TensorTree%d): %s", nd, t ? msg : "empty");
        break;
      }
      blocks++;
    }
  }
  if (!st && !blocks) st = fail(r, layer, VR_E_PARSE, "<Layer> has no <WavelengthData> block with data");
  size_t nn = (size_t)x->basis.n * x->basis.n;
  for (size_t b = 0; !st && b < x->nbands; b++) {
    vr_tt_tree **tr = trees[b];
    bool any_t = tr[VR_BSDF_TF] || tr[VR_BSDF_TB];
    for (int s = 0; s < VR_BSDF_SIDES && !st; s++) {
      bool transmission = s == VR_BSDF_TF || s == VR_BSDF_TB;
      if (!(tr[s] || (transmission && any_t))) continue;
      if (!(x->bands[b].m[s] = calloc(nn, sizeof(double)))) st = fail(r, layer, VR_E_NOMEM, "out of memory");
    }
    if (!st && vr_tt_to_klems(tr, &x->basis, TT_SAMPLES, x->bands[b].m))
      st = fail(r, layer, VR_E_NOMEM, "out of memory");
  }
  for (size_t b = 0; b < ntrees; b++)
    for (int s = 0; s < VR_BSDF_SIDES; s++) vr_tt_destroy(trees[b][s]);
  free(trees);
  return st;
}

static vr_status read_doc(reader *r, xmlNode *root, vr_bsdf_xml *x) {
  char buf[128];
  if (!is(root, "WindowElement"))
    return fail(r, root, VR_E_PARSE, "the root element is <%s>, not <WindowElement>: not a BSDF XML file",
                root ? (const char *)root->name : "?");
  xmlNode *optical = child(root, "Optical");
  if (!optical) return fail(r, root, VR_E_PARSE, "<WindowElement> has no <Optical>");
  xmlNode *layer = child(optical, "Layer");
  if (!layer) return fail(r, optical, VR_E_PARSE, "<Optical> has no <Layer>");
  for (xmlNode *c = layer->next; c; c = c->next)
    if (is(c, "Layer"))
      return fail(r, c, VR_E_PARSE, "a second <Layer>: files of several layers are not read");
  xmlNode *mat = child(layer, "Material");
  text(child(mat, "Name"), x->name, sizeof x->name);
  text(child(mat, "Manufacturer"), x->manufacturer, sizeof x->manufacturer);
  text(child(mat, "DeviceType"), x->device_type, sizeof x->device_type);
  x->thickness_mm = NAN;
  xmlNode *th = child(mat, "Thickness");
  if (th) {
    double v;
    if (number(r, mat, "Thickness", &v)) return r->err->status;
    xmlChar *u = xmlGetProp(th, (const xmlChar *)"unit");
    const char *us = u ? (const char *)u : "Millimeter";
    double scale = !strcasecmp(us, "Millimeter") ? 1 : !strcasecmp(us, "Meter") ? 1000
                   : !strcasecmp(us, "Micron") ? 1e-3 : 0;
    if (u) xmlFree(u);
    if (!scale || v < 0)
      return fail(r, th, VR_E_RANGE, "<Thickness> %g: expected a length >= 0 in Millimeter, Meter or Micron", v);
    x->thickness_mm = v * scale;
  }
  xmlNode *dd = child(layer, "DataDefinition");
  if (!dd) return fail(r, layer, VR_E_PARSE, "<Layer> has no <DataDefinition>");
  xmlNode *ids = child(dd, "IncidentDataStructure");
  if (!ids) return fail(r, dd, VR_E_PARSE, "<DataDefinition> has no <IncidentDataStructure>");
  text(ids, buf, sizeof buf);
  int rows;
  if (!strcasecmp(buf, "Columns")) rows = 0;
  else if (!strcasecmp(buf, "Rows")) rows = 1;
  else if (!strcasecmp(buf, "TensorTree3") || !strcasecmp(buf, "TensorTree4"))
    return read_trees(r, layer, x, buf[10] - '0');
  else
    return fail(r, ids, VR_E_PARSE, "<IncidentDataStructure> '%s': expected Columns or Rows", buf);
  xmlNode *ab = child(dd, "AngleBasis");
  if (!ab) return fail(r, dd, VR_E_PARSE, "<DataDefinition> has no <AngleBasis>");
  for (xmlNode *c = ab->next; c; c = c->next)
    if (is(c, "AngleBasis"))
      return fail(r, c, VR_E_PARSE, "a second <AngleBasis>: files on several bases are not read");
  if (read_basis(r, ab, &x->basis)) return r->err->status;
  size_t blocks = 0;
  for (xmlNode *wd = layer->children; wd; wd = wd->next) {
    if (!is(wd, "WavelengthData")) continue;
    vr_bsdf_band *band = band_for(r, x, wd);
    if (!band) return r->err->status;
    xmlNode *det = child(wd, "DetectorSpectrum");
    if (det && !band->detector[0]) text(det, band->detector, sizeof band->detector);
    for (xmlNode *blk = wd->children; blk; blk = blk->next) {
      if (!is(blk, "WavelengthDataBlock")) continue;
      if (read_block(r, x, band, blk, rows)) return r->err->status;
      blocks++;
    }
  }
  if (!blocks) return fail(r, layer, VR_E_PARSE, "<Layer> has no <WavelengthData> block with data");
  return VR_OK;
}

/* Reads doc (NULL: the parse failed, as ctxt tells) into *out. */
static vr_status finish(xmlParserCtxtPtr ctxt, xmlDocPtr doc, const char *path, vr_bsdf_xml **out,
                        vr_error *err) {
  vr_status st;
  if (!doc) {
    const xmlError *e = xmlCtxtGetLastError(ctxt);
    st = vr_error_at(err, VR_E_PARSE, path, e ? e->line : 0, 0, "malformed XML: %s",
                     e && e->message ? e->message : "unreadable");
    size_t len = err ? strlen(err->message) : 0;
    if (len && err->message[len - 1] == '\n') err->message[len - 1] = 0;
    xmlFreeParserCtxt(ctxt);
    return st;
  }
  vr_error local = {0};
  reader r = {path, err ? err : &local};
  vr_bsdf_xml *x = calloc(1, sizeof *x);
  st = x ? read_doc(&r, xmlDocGetRootElement(doc), x) : vr_error_set(err, VR_E_NOMEM, "out of memory");
  xmlFreeDoc(doc);
  xmlFreeParserCtxt(ctxt);
  if (st) {
    vr_bsdf_xml_destroy(x);
    return st;
  }
  *out = x;
  return VR_OK;
}

/* No network, line numbers past 65535, errors kept in the context rather
 * than printed, gzip-compressed files read.  Some errors (encoding) go to
 * libxml2's generic handler whatever the options: it is silenced for the
 * parse, then restored.  That handler is per thread in libxml2 2.9 (its
 * globals are thread-local), so parses on other threads are untouched.
 * Debian 12's libxml2 (2.9.14) is built with zlib; a libxml2 built
 * without it reads no .xml.gz (the file is then refused as malformed). */
#if LIBXML_VERSION >= 21400 /* gzip is read only when asked from 2.14 on */
#define PARSE_UNZIP XML_PARSE_UNZIP
#else
#define PARSE_UNZIP 0
#endif
#define PARSE_OPTIONS \
  (XML_PARSE_NONET | XML_PARSE_BIG_LINES | XML_PARSE_NOERROR | XML_PARSE_NOWARNING | PARSE_UNZIP)

static void quiet(void *ctx, const char *msg, ...) {
  (void)ctx;
  (void)msg;
}

static xmlDocPtr parse_quietly(xmlParserCtxtPtr ctxt, const char *path, const char *text, size_t size) {
  xmlGenericErrorFunc handler = xmlGenericError;
  void *handler_ctx = xmlGenericErrorContext;
  xmlSetGenericErrorFunc(NULL, quiet);
  xmlDocPtr doc = path ? xmlCtxtReadFile(ctxt, path, NULL, PARSE_OPTIONS)
                       : xmlCtxtReadMemory(ctxt, text, (int)size, NULL, NULL, PARSE_OPTIONS);
  xmlSetGenericErrorFunc(handler_ctx, handler);
  return doc;
}

vr_status vr_bsdf_xml_read(const char *path, vr_bsdf_xml **out, vr_error *err) {
  *out = NULL;
  FILE *f = fopen(path, "rb");
  if (!f) return vr_error_set(err, VR_E_IO, "%s: cannot open: %s", path, strerror(errno));
  fclose(f);
  xmlParserCtxtPtr ctxt = xmlNewParserCtxt();
  if (!ctxt) return vr_error_set(err, VR_E_NOMEM, "%s: out of memory", path);
  return finish(ctxt, parse_quietly(ctxt, path, NULL, 0), path, out, err);
}

vr_status vr_bsdf_xml_parse(const char *text, size_t size, const char *name, vr_bsdf_xml **out,
                            vr_error *err) {
  *out = NULL;
  if (size > 1u << 30) return vr_error_set(err, VR_E_RANGE, "%s: over 1 GiB", name);
  xmlParserCtxtPtr ctxt = xmlNewParserCtxt();
  if (!ctxt) return vr_error_set(err, VR_E_NOMEM, "%s: out of memory", name);
  return finish(ctxt, parse_quietly(ctxt, NULL, text, size), name, out, err);
}

const char *vr_bsdf_side_name(vr_bsdf_side s) {
  static const char *names[] = {"Transmission Front", "Transmission Back", "Reflection Front",
                                "Reflection Back"};
  return s >= 0 && s < VR_BSDF_SIDES ? names[s] : "?";
}

void vr_bsdf_xml_destroy(vr_bsdf_xml *x) {
  if (!x) return;
  for (size_t i = 0; i < x->nbands; i++)
    for (int s = 0; s < VR_BSDF_SIDES; s++) free(x->bands[i].m[s]);
  free(x->bands);
  free(x);
}

const vr_bsdf_band *vr_bsdf_xml_band(const vr_bsdf_xml *x, const char *name) {
  for (size_t i = 0; i < x->nbands; i++)
    if (!strcasecmp(x->bands[i].name, name)) return &x->bands[i];
  return NULL;
}
