/* libFuzzer target: the refractiveindex.info reader on arbitrary bytes must
 * either fill the material or fail with a message, never crash, leak or
 * read out of bounds.  Whatever it accepts, the writer must write, and the
 * reader must read that back to the same numbers and texts (a mismatch
 * traps, so the fuzzer reports it). */
#include "rii.h"
#include "vr/material.h"

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int same_text(const char *a, const char *b) {
  return (!a && !b) || (a && b && !strcmp(a, b));
}

static int same_spectrum(const vr_spectrum *a, const vr_spectrum *b) {
  if (!a || !b) return a == b;
  if (a->n != b->n) return 0;
  for (size_t i = 0; i < a->n; i++)
    if (a->nm[i] != b->nm[i] || a->value[i] != b->value[i]) return 0;
  return 1;
}

static int same(const vr_material *a, const vr_material *b) {
  if (a->n_formula.type != b->n_formula.type || a->n_formula.ncoeffs != b->n_formula.ncoeffs ||
      a->n_formula.min_nm != b->n_formula.min_nm || a->n_formula.max_nm != b->n_formula.max_nm)
    return 0;
  for (size_t i = 0; i < a->n_formula.ncoeffs; i++)
    if (a->n_formula.c[i] != b->n_formula.c[i]) return 0;
  if (!same_spectrum(vr_material_spectrum(a, "n"), vr_material_spectrum(b, "n")) ||
      !same_spectrum(vr_material_spectrum(a, "k"), vr_material_spectrum(b, "k")))
    return 0;
  if (!same_text(a->description, b->description) ||
      !same_text(a->prov.reference, b->prov.reference) || a->nprops != b->nprops)
    return 0;
  for (size_t i = 0; i < a->nprops; i++) {
    const vr_property *p = vr_material_property(b, a->props[i].key);
    if (!p || !same_text(p->text, a->props[i].text)) return 0;
    if (!p->text && p->value != a->props[i].value) return 0;
  }
  return 1;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  vr_error err;
  vr_material *m = vr_material_create("fuzz", VR_KIND_DIELECTRIC, NULL);
  if (!m) return 0;
  if (vr_rii_parse((const char *)data, size, "fuzz.yml", m, &err) == VR_OK) {
    double n, k;
    (void)vr_material_nk(m, 550.0, true, &n, &k, NULL, &err);
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    if (f) {
      vr_status st = vr_rii_write(f, m, &err);
      fclose(f);
      if (st == VR_OK) {
        vr_material *back = vr_material_create("fuzz", VR_KIND_DIELECTRIC, NULL);
        if (back) {
          if (vr_rii_parse(buf, len, "written.yml", back, &err) != VR_OK || !same(m, back)) {
            fprintf(stderr, "round trip failed: %s\n--- written:\n%s\n", err.message, buf);
            __builtin_trap();
          }
          vr_material_destroy(back);
        }
      }
    }
    free(buf);
  }
  vr_material_destroy(m);
  return 0;
}
