/* Text and JSON views of materials for vr-matdb, and CSV export. */
#include "vr_matdb_print.h"
#include "utf8.h"
#include "vr/json.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void vr_print_json_text(FILE *f, const char *s) {
  char *clean = vr_utf8_sanitize(s);
  vr_json_string(f, clean ? clean : s);
  free(clean);
}

static void kv(FILE *f, const char *key, const char *value) {
  if (value && *value) fprintf(f, "  %-14s %s\n", key, value);
}

void vr_print_material(FILE *f, const vr_material *m, bool json) {
  if (!json) {
    fprintf(f, "%s (version %d, %s)\n", m->name, m->version, vr_kind_name(m->kind));
    kv(f, "description", m->description);
    kv(f, "reference", m->prov.reference);
    kv(f, "source", m->prov.source_path);
    kv(f, "sha256", m->prov.sha256);
    char tool[160];
    snprintf(tool, sizeof tool, "%s %s", m->prov.tool ? m->prov.tool : "", m->prov.tool_version ? m->prov.tool_version : "");
    kv(f, "tool", tool);
    kv(f, "model", m->prov.model);
    kv(f, "created", m->prov.created_at);
    kv(f, "note", m->prov.note);
    if (isfinite(m->prov.residual)) fprintf(f, "  %-14s %.6g\n", "residual", m->prov.residual);
    if (m->n_formula.type) {
      fprintf(f, "  %-14s refractiveindex.info formula %d on %g-%g nm:", "n", m->n_formula.type,
              m->n_formula.min_nm, m->n_formula.max_nm);
      for (size_t i = 0; i < m->n_formula.ncoeffs; i++) fprintf(f, " %.10g", m->n_formula.c[i]);
      fputc('\n', f);
    }
    for (size_t i = 0; i < m->nspectra; i++) {
      const vr_spectrum *s = m->spectra[i].s;
      fprintf(f, "  %-14s %zu samples, %g-%g nm\n", m->spectra[i].role, s->n, s->nm[0], s->nm[s->n - 1]);
    }
    for (size_t i = 0; i < m->nprops; i++) {
      const vr_property *p = &m->props[i];
      fprintf(f, "  %-14s ", p->key);
      if (p->text) fputs(p->text, f);
      else if (isfinite(p->value)) fprintf(f, "%.10g", p->value);
      if (p->unit) fprintf(f, " %s", p->unit);
      fputc('\n', f);
    }
    for (size_t i = 0; i < m->nparams; i++) {
      const vr_parameter *p = &m->params[i];
      fprintf(f, "  %-14s %.10g", p->name, p->value);
      if (isfinite(p->stderr_)) fprintf(f, " ± %.3g", p->stderr_);
      if (p->unit) fprintf(f, " %s", p->unit);
      fputc('\n', f);
    }
    return;
  }
  fputs("{\"name\": ", f);
  vr_print_json_text(f, m->name);
  fprintf(f, ", \"version\": %d, \"kind\": \"%s\", \"description\": ", m->version, vr_kind_name(m->kind));
  vr_print_json_text(f, m->description);
  fputs(", \"provenance\": {\"source_path\": ", f);
  vr_print_json_text(f, m->prov.source_path);
  fputs(", \"source_sha256\": ", f);
  vr_print_json_text(f, m->prov.sha256[0] ? m->prov.sha256 : NULL);
  fputs(", \"tool\": ", f);
  vr_print_json_text(f, m->prov.tool);
  fputs(", \"tool_version\": ", f);
  vr_print_json_text(f, m->prov.tool_version);
  fputs(", \"model\": ", f);
  vr_print_json_text(f, m->prov.model);
  fputs(", \"reference\": ", f);
  vr_print_json_text(f, m->prov.reference);
  fputs(", \"note\": ", f);
  vr_print_json_text(f, m->prov.note);
  fputs(", \"residual\": ", f);
  vr_json_number(f, m->prov.residual);
  fputs(", \"created_at\": ", f);
  vr_print_json_text(f, m->prov.created_at);
  fputs("}, \"formula\": ", f);
  if (m->n_formula.type) {
    fprintf(f, "{\"type\": %d, \"range_nm\": [", m->n_formula.type);
    vr_json_number(f, m->n_formula.min_nm);
    fputs(", ", f);
    vr_json_number(f, m->n_formula.max_nm);
    fputs("], \"coefficients\": [", f);
    for (size_t i = 0; i < m->n_formula.ncoeffs; i++) {
      if (i) fputs(", ", f);
      vr_json_number(f, m->n_formula.c[i]);
    }
    fputs("]}", f);
  } else {
    fputs("null", f);
  }
  fputs(", \"spectra\": {", f);
  for (size_t i = 0; i < m->nspectra; i++) {
    const vr_spectrum *s = m->spectra[i].s;
    fprintf(f, "%s", i ? ", " : "");
    vr_print_json_text(f, m->spectra[i].role);
    fputs(": [", f);
    for (size_t j = 0; j < s->n; j++) {
      fputs(j ? ", [" : "[", f);
      vr_json_number(f, s->nm[j]);
      fputs(", ", f);
      vr_json_number(f, s->value[j]);
      fputc(']', f);
    }
    fputc(']', f);
  }
  fputs("}, \"properties\": [", f);
  for (size_t i = 0; i < m->nprops; i++) {
    fputs(i ? ", {\"key\": " : "{\"key\": ", f);
    vr_print_json_text(f, m->props[i].key);
    fputs(", \"text\": ", f);
    vr_print_json_text(f, m->props[i].text);
    fputs(", \"value\": ", f);
    vr_json_number(f, m->props[i].value);
    fputs(", \"unit\": ", f);
    vr_print_json_text(f, m->props[i].unit);
    fputc('}', f);
  }
  fputs("], \"parameters\": [", f);
  for (size_t i = 0; i < m->nparams; i++) {
    fputs(i ? ", {\"name\": " : "{\"name\": ", f);
    vr_print_json_text(f, m->params[i].name);
    fputs(", \"value\": ", f);
    vr_json_number(f, m->params[i].value);
    fputs(", \"stderr\": ", f);
    vr_json_number(f, m->params[i].stderr_);
    fputs(", \"unit\": ", f);
    vr_print_json_text(f, m->params[i].unit);
    fputc('}', f);
  }
  fputs("]}\n", f);
}

void vr_print_entry(FILE *f, const vr_matdb_entry *e, bool json, bool first) {
  if (!json) {
    const char *src = e->reference && *e->reference ? e->reference : (e->source_path ? e->source_path : "");
    char one[100];
    size_t n = 0;
    for (const char *p = src; *p && n + 1 < sizeof one; p++) one[n++] = (*p == '\n') ? ' ' : *p;
    /* Never cut a UTF-8 sequence in two. */
    if (src[n])
      while (n && ((unsigned char)src[n] & 0xC0) == 0x80) n--;
    one[n] = '\0';
    fprintf(f, "%-26s %-12s v%-3d %s\n", e->name, e->kind, e->version, one);
    return;
  }
  fputs(first ? "  {\"name\": " : ",\n  {\"name\": ", f);
  vr_print_json_text(f, e->name);
  fputs(", \"kind\": ", f);
  vr_print_json_text(f, e->kind);
  fprintf(f, ", \"version\": %d, \"versions\": %d, \"created_at\": ", e->version, e->versions);
  vr_print_json_text(f, e->created_at);
  fputs(", \"tool\": ", f);
  vr_print_json_text(f, e->tool);
  fputs(", \"source_path\": ", f);
  vr_print_json_text(f, e->source_path);
  fputs(", \"source_sha256\": ", f);
  vr_print_json_text(f, e->source_sha256);
  fputs(", \"model\": ", f);
  vr_print_json_text(f, e->model);
  fputs(", \"reference\": ", f);
  vr_print_json_text(f, e->reference);
  fputs(", \"residual\": ", f);
  vr_json_number(f, e->residual);
  fputc('}', f);
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

vr_status vr_export_csv(FILE *f, const vr_material *m, vr_error *err) {
  /* Columns: every tabulated role, plus n from the formula if there is one. */
  size_t total = 0;
  for (size_t i = 0; i < m->nspectra; i++) total += m->spectra[i].s->n;
  double lo = 0, hi = 0;
  bool formula = m->n_formula.type != 0;
  if (formula) {
    if (vr_material_nk_range(m, &lo, &hi, err)) return err ? err->status : VR_E_RANGE;
    /* Tabulate the formula at 1 nm inside its range. */
    total += (size_t)(hi - lo) + 2;
  }
  if (total == 0) return vr_error_set(err, VR_E_ARG, "material '%s' has no tabulated data", m->name);
  double *grid = malloc(total * sizeof *grid);
  if (!grid) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  size_t n = 0;
  for (size_t i = 0; i < m->nspectra; i++) {
    const vr_spectrum *s = m->spectra[i].s;
    for (size_t j = 0; j < s->n; j++)
      if (!formula || (s->nm[j] >= lo && s->nm[j] <= hi)) grid[n++] = s->nm[j];
  }
  if (formula && !vr_material_spectrum(m, "k"))
    for (double x = lo; x <= hi; x += 1.0) grid[n++] = x;
  qsort(grid, n, sizeof *grid, cmp_double);
  size_t u = 0;
  for (size_t i = 0; i < n; i++)
    if (!u || grid[i] != grid[u - 1]) grid[u++] = grid[i];
  fputs("nm", f);
  if (formula) fputs(",n", f);
  for (size_t i = 0; i < m->nspectra; i++) fprintf(f, ",%s", m->spectra[i].role);
  fputc('\n', f);
  for (size_t r = 0; r < u; r++) {
    fprintf(f, "%.17g", grid[r]);
    if (formula) {
      double nv;
      if (vr_formula_eval(&m->n_formula, grid[r], &nv, err)) {
        free(grid);
        return err ? err->status : VR_E_NUMERIC;
      }
      fprintf(f, ",%.17g", nv);
    }
    for (size_t i = 0; i < m->nspectra; i++)
      fprintf(f, ",%.17g", vr_spectrum_eval(m->spectra[i].s, grid[r], VR_INTERP_LINEAR));
    fputc('\n', f);
  }
  free(grid);
  return VR_OK;
}
