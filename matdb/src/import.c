/* CSV tables as materials, and the file-level import entry point that picks
 * an importer and records provenance. */
#include "vr/file.h"
#include "import.h"
#include "rii.h"
#include "vr/sha256.h"
#include "vr/version.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

vr_status vr_csv_material_parse(const char *text, size_t len, const char *name, vr_material *m,
                                vr_error *err) {
  vr_spectrum_table t;
  vr_status st = vr_spectrum_table_parse(text, len, name, &t, err);
  if (st) return st;
  for (size_t i = 0; i < t.count && !st; i++) {
    const char *role = t.count == 1 ? "value" : t.names[i];
    if (!strcasecmp(role, "n")) role = "n";
    else if (!strcasecmp(role, "k")) role = "k";
    st = vr_material_add_spectrum(m, role, t.spectra[i], err);
    t.spectra[i] = NULL; /* taken over, also on failure */
  }
  vr_spectrum_table_free(&t);
  if (st) return st;
  return vr_material_set_text(&m->prov.model, "tabulated spectra (CSV)", err);
}

static const char *extension(const char *path) {
  const char *slash = strrchr(path, '/'), *dot = strrchr(path, '.');
  return dot && (!slash || dot > slash) ? dot + 1 : "";
}

static void stem(const char *path, char *out, size_t size) {
  const char *slash = strrchr(path, '/'), *base = slash ? slash + 1 : path;
  const char *dot = strrchr(base, '.');
  size_t n = dot && dot > base ? (size_t)(dot - base) : strlen(base);
  if (n >= size) n = size - 1;
  memcpy(out, base, n);
  out[n] = '\0';
}

/* A regular file of bounded size (a link to /dev/zero would never end), in
 * a text encoding this reads. */
static vr_status read_all(const char *path, char **text, size_t *len, vr_error *err) {
  vr_status st = vr_read_file(path, VR_TEXT_MAX_BYTES, text, len, err);
  if (!st && (st = vr_text_check_encoding(*text, *len, path, err))) {
    free(*text);
    *text = NULL;
  }
  return st;
}

vr_status vr_import_file(const char *path, const char *name, const char *kind_override,
                         const char *tool, vr_material **out, vr_error *err) {
  *out = NULL;
  const char *ext = extension(path);
  enum { RII, IGDB, CSV } format;
  vr_material_kind kind;
  if (!strcasecmp(ext, "yml") || !strcasecmp(ext, "yaml")) {
    format = RII;
    kind = VR_KIND_DIELECTRIC;
  } else if (!strcasecmp(ext, "dat")) {
    format = IGDB;
    kind = VR_KIND_GLAZING;
  } else if (!strcasecmp(ext, "csv") || !strcasecmp(ext, "txt")) {
    format = CSV;
    kind = VR_KIND_REFLECTANCE;
  } else {
    return vr_error_at(err, VR_E_ARG, path, 0, 0,
                       "unknown file type '.%s' (refractiveindex.info .yml, IGDB .DAT or .csv)", ext);
  }
  vr_status st;
  if (kind_override && (st = vr_kind_parse(kind_override, &kind, err))) return st;
  char *text = NULL;
  size_t len = 0;
  if ((st = read_all(path, &text, &len, err))) return st;
  char base[256];
  stem(path, base, sizeof base);
  vr_material *m = vr_material_create(name ? name : base, kind, err);
  if (!m) {
    free(text);
    return VR_E_NOMEM;
  }
  if (format == RII) st = vr_rii_parse(text, len, path, m, err);
  else if (format == IGDB) st = vr_igdb_parse(text, len, path, m, err);
  else st = vr_csv_material_parse(text, len, path, m, err);
  if (!st && format == CSV && !kind_override) {
    /* Guess the kind from the columns when not told. */
    if (vr_material_spectrum(m, "n")) m->kind = VR_KIND_DIELECTRIC;
    else if (vr_material_spectrum(m, "T") && vr_material_spectrum(m, "Rf")) m->kind = VR_KIND_GLAZING;
  }
  if (!st && format == RII && !kind_override) {
    /* A metal: k above n over most of the visible. */
    double n, k;
    if (vr_material_nk(m, 550.0, true, &n, &k, NULL, NULL) == VR_OK && k > n) m->kind = VR_KIND_CONDUCTOR;
  }
  if (!st) {
    vr_sha256_buffer(text, len, m->prov.sha256);
    if ((st = vr_material_set_text(&m->prov.source_path, path, err)) ||
        (st = vr_material_set_text(&m->prov.tool, tool, err)) ||
        (st = vr_material_set_text(&m->prov.tool_version, vr_version(), err))) {
    }
  }
  free(text);
  if (st) {
    vr_material_destroy(m);
    return st;
  }
  *out = m;
  return VR_OK;
}
