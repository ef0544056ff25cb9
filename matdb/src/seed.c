/* The built-in library written into every new material database: standard
 * glasses and metals from refractiveindex.info files (each keeps its
 * REFERENCES), CIE illuminants, the ASTM G173 solar spectra and the
 * ColorChecker reflectances, each with its published source. */
#include "matdb_internal.h"
#include "rii.h"
#include "vr/colorchecker.h"
#include "vr/colour.h"
#include "vr/sha256.h"
#include "vr/version.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define TEXT(sym)                       \
  extern const unsigned char sym[];     \
  extern const unsigned long sym##_len;
TEXT(vr_seed_nbk7)
TEXT(vr_seed_nsf11)
TEXT(vr_seed_nbaf10)
TEXT(vr_seed_f2)
TEXT(vr_seed_fused_silica)
TEXT(vr_seed_soda_lime)
TEXT(vr_seed_si)
TEXT(vr_seed_tio2)
TEXT(vr_seed_au)
TEXT(vr_seed_ag)
TEXT(vr_seed_cu)
TEXT(vr_seed_al)
TEXT(vr_seed_sio2_film)
TEXT(vr_seed_si3n4)
TEXT(vr_seed_si3n4_philipp)
TEXT(vr_seed_al2o3)
TEXT(vr_seed_al2o3_film)
TEXT(vr_seed_ito)
TEXT(vr_seed_gaas)
TEXT(vr_seed_water)
TEXT(vr_seed_pmma)
TEXT(vr_seed_pc)
TEXT(vr_seed_ps)
extern const double vr_seed_astm_g173[];
extern const unsigned vr_seed_astm_g173_rows, vr_seed_astm_g173_cols;

typedef struct rii_seed {
  const char *name;
  vr_material_kind kind;
  const unsigned char *text;
  const unsigned long *len;
  const char *file;
} rii_seed;

static const rii_seed RII[] = {
    {"N-BK7", VR_KIND_DIELECTRIC, vr_seed_nbk7, &vr_seed_nbk7_len, "nbk7.yml"},
    {"N-SF11", VR_KIND_DIELECTRIC, vr_seed_nsf11, &vr_seed_nsf11_len, "nsf11.yml"},
    {"N-BAF10", VR_KIND_DIELECTRIC, vr_seed_nbaf10, &vr_seed_nbaf10_len, "nbaf10.yml"},
    {"F2", VR_KIND_DIELECTRIC, vr_seed_f2, &vr_seed_f2_len, "f2.yml"},
    {"fused-silica", VR_KIND_DIELECTRIC, vr_seed_fused_silica, &vr_seed_fused_silica_len,
     "fused_silica_malitson.yml"},
    {"SiO2", VR_KIND_DIELECTRIC, vr_seed_fused_silica, &vr_seed_fused_silica_len,
     "fused_silica_malitson.yml"},
    {"soda-lime-glass", VR_KIND_DIELECTRIC, vr_seed_soda_lime, &vr_seed_soda_lime_len,
     "soda_lime_rubin.yml"},
    {"Si", VR_KIND_DIELECTRIC, vr_seed_si, &vr_seed_si_len, "si_green2008.yml"},
    {"TiO2", VR_KIND_DIELECTRIC, vr_seed_tio2, &vr_seed_tio2_len, "tio2_devore.yml"},
    {"Au", VR_KIND_CONDUCTOR, vr_seed_au, &vr_seed_au_len, "au_johnson.yml"},
    {"Ag", VR_KIND_CONDUCTOR, vr_seed_ag, &vr_seed_ag_len, "ag_johnson.yml"},
    {"Cu", VR_KIND_CONDUCTOR, vr_seed_cu, &vr_seed_cu_len, "cu_johnson.yml"},
    {"Al", VR_KIND_CONDUCTOR, vr_seed_al, &vr_seed_al_len, "al_rakic.yml"},
    /* Layers and media of ellipsometry labs (matdb/data/SOURCES.md). */
    {"SiO2-film", VR_KIND_DIELECTRIC, vr_seed_sio2_film, &vr_seed_sio2_film_len,
     "sio2_film_rodriguez_de_marcos.yml"},
    {"Si3N4", VR_KIND_DIELECTRIC, vr_seed_si3n4, &vr_seed_si3n4_len, "si3n4_luke.yml"},
    {"Si3N4-Philipp", VR_KIND_DIELECTRIC, vr_seed_si3n4_philipp, &vr_seed_si3n4_philipp_len,
     "si3n4_philipp.yml"},
    {"Al2O3", VR_KIND_DIELECTRIC, vr_seed_al2o3, &vr_seed_al2o3_len, "al2o3_malitson_o.yml"},
    {"Al2O3-film", VR_KIND_DIELECTRIC, vr_seed_al2o3_film, &vr_seed_al2o3_film_len, "al2o3_boidin.yml"},
    {"ITO", VR_KIND_DIELECTRIC, vr_seed_ito, &vr_seed_ito_len, "ito_konig.yml"},
    {"GaAs", VR_KIND_DIELECTRIC, vr_seed_gaas, &vr_seed_gaas_len, "gaas_aspnes.yml"},
    {"water", VR_KIND_DIELECTRIC, vr_seed_water, &vr_seed_water_len, "h2o_daimon_20_0c.yml"},
    {"PMMA", VR_KIND_DIELECTRIC, vr_seed_pmma, &vr_seed_pmma_len, "pmma_sultanova.yml"},
    {"polycarbonate", VR_KIND_DIELECTRIC, vr_seed_pc, &vr_seed_pc_len, "pc_sultanova.yml"},
    {"polystyrene", VR_KIND_DIELECTRIC, vr_seed_ps, &vr_seed_ps_len, "ps_sultanova.yml"},
};

static vr_status provenance(vr_material *m, const char *source, const void *bytes, size_t len,
                            const char *model, const char *reference, vr_error *err) {
  vr_status st;
  if ((st = vr_material_set_text(&m->prov.source_path, source, err)) ||
      (st = vr_material_set_text(&m->prov.tool, "vr-matdb seed", err)) ||
      (st = vr_material_set_text(&m->prov.tool_version, vr_version(), err)))
    return st;
  if (model && (st = vr_material_set_text(&m->prov.model, model, err))) return st;
  if (reference && (st = vr_material_set_text(&m->prov.reference, reference, err))) return st;
  if (bytes) vr_sha256_buffer(bytes, len, m->prov.sha256);
  return VR_OK;
}

/* Saves and frees m (also on failure). */
static vr_status put(vr_matdb *db, vr_material *m, vr_error *err) {
  vr_status st = vr_matdb_validate(m, err);
  if (!st) st = vr_matdb_insert(db, m, err);
  if (st) vr_error_prefix(err, "built-in material '%s': ", m->name);
  vr_material_destroy(m);
  return st;
}

static vr_status seed_rii(vr_matdb *db, vr_error *err) {
  for (size_t i = 0; i < sizeof RII / sizeof RII[0]; i++) {
    const rii_seed *r = &RII[i];
    vr_material *m = vr_material_create(r->name, r->kind, err);
    if (!m) return VR_E_NOMEM;
    char source[128];
    snprintf(source, sizeof source, "built-in:matdb/data/%s (refractiveindex.info database)", r->file);
    vr_status st = vr_rii_parse((const char *)r->text, *r->len, source, m, err);
    if (!st) st = provenance(m, source, r->text, *r->len, NULL, NULL, err);
    if (st) {
      vr_material_destroy(m);
      return st;
    }
    if ((st = put(db, m, err))) return st;
  }
  return VR_OK;
}

static vr_status seed_spectrum(vr_matdb *db, const char *name, vr_material_kind kind,
                               vr_spectrum *s, const char *source, const char *reference,
                               const char *description, vr_error *err) {
  vr_material *m = vr_material_create(name, kind, err);
  if (!m) {
    vr_spectrum_destroy(s);
    return VR_E_NOMEM;
  }
  vr_status st = vr_material_add_spectrum(m, "value", s, err);
  if (!st) st = provenance(m, source, NULL, 0, "tabulated spectrum", reference, err);
  if (!st && description) st = vr_material_set_text(&m->description, description, err);
  if (st) {
    vr_material_destroy(m);
    return st;
  }
  return put(db, m, err);
}

static vr_status seed_illuminants(vr_matdb *db, vr_error *err) {
  size_t n;
  const char *const *names = vr_illuminant_names(&n);
  for (size_t i = 0; i < n; i++) {
    vr_spectrum *s = vr_illuminant(names[i], err);
    if (!s) return err ? err->status : VR_E_ARG;
    char name[32];
    snprintf(name, sizeof name, "CIE-%s", names[i]);
    const char *ref = !strcmp(names[i], "A")
                          ? "CIE 015:2018 eq. 2.1 (Planckian, T = 2848 K, c2 = 1.435e-2 m K)"
                          : "CIE 015:2018 / ISO/CIE 11664-2 relative spectral power distribution";
    vr_status st = seed_spectrum(db, name, VR_KIND_ILLUMINANT, s, "built-in:core/data (CIE tables)",
                                 ref, "relative spectral power, 100 at 560 nm", err);
    if (st) return st;
  }
  static const struct { const char *name; unsigned col; const char *what; } G173[] = {
      {"ASTM-G173-AM0", 1, "extraterrestrial spectral irradiance, W m^-2 nm^-1"},
      {"ASTM-G173-AM1.5G", 2, "global tilted (37 deg) spectral irradiance, W m^-2 nm^-1"},
      {"ASTM-G173-AM1.5D", 3, "direct + circumsolar spectral irradiance, W m^-2 nm^-1"}};
  for (size_t k = 0; k < 3; k++) {
    unsigned rows = vr_seed_astm_g173_rows, cols = vr_seed_astm_g173_cols;
    vr_spectrum *s = vr_spectrum_create_uniform(0, 1, rows, 0, err);
    if (!s) return VR_E_NOMEM;
    for (unsigned r = 0; r < rows; r++) {
      s->nm[r] = vr_seed_astm_g173[r * cols];
      s->value[r] = vr_seed_astm_g173[r * cols + G173[k].col];
    }
    vr_status st = seed_spectrum(db, G173[k].name, VR_KIND_ILLUMINANT, s,
                                 "built-in:matdb/data/astm_g173.csv",
                                 "ASTM G173-03, Standard Tables for Reference Solar Spectral "
                                 "Irradiances (SMARTS 2.9.2)",
                                 G173[k].what, err);
    if (st) return st;
  }
  return VR_OK;
}

static vr_status seed_colorchecker(vr_matdb *db, vr_error *err) {
  for (size_t p = 0; p < VR_COLORCHECKER_PATCHES; p++) {
    vr_spectrum *s = vr_colorchecker_patch(p, err);
    if (!s) return VR_E_NOMEM;
    char name[64];
    snprintf(name, sizeof name, "ColorChecker-%s", vr_colorchecker_name(p));
    vr_status st = seed_spectrum(db, name, VR_KIND_REFLECTANCE, s,
                                 "built-in:core/data/colorchecker_babelcolor.csv",
                                 "BabelColor average of 30 ColorChecker Classic charts (D. Pascale, "
                                 "BabelColor 2012)",
                                 "spectral reflectance factor, 380-730 nm", err);
    if (st) return st;
  }
  return VR_OK;
}

vr_status vr_matdb_seed(vr_matdb *db, vr_error *err) {
  vr_status st = seed_rii(db, err);
  if (!st) st = seed_illuminants(db, err);
  if (!st) st = seed_colorchecker(db, err);
  return st;
}
