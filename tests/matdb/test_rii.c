/* refractiveindex.info files and dispersion formulas: each of the nine
 * formula types on a real database file against the published formula
 * written out longhand, published indices of N-BK7, fused silica and Si,
 * multi-block files, exact write/read round trips, and error messages that
 * name the file, the line and the field. */
#include "vr_test.h"
#include "rii.h"
#include "vr/material.h"

/* ---------------------------------------------------------------------- */
/* Helpers */

static char *slurp(const char *path, size_t *len) {
  FILE *f = fopen(path, "rb");
  if (!f) fail_msg("cannot open %s", path);
  char *buf = NULL;
  size_t cap = 0, n = 0;
  for (;;) {
    if (n + 4096 > cap) {
      cap = cap ? 2 * cap : 65536;
      buf = realloc(buf, cap + 1);
      assert_non_null(buf);
    }
    size_t got = fread(buf + n, 1, cap - n, f);
    n += got;
    if (got == 0) break;
  }
  fclose(f);
  buf[n] = '\0';
  *len = n;
  return buf;
}

/* Parses a file; fails the test with the parser's message if it does not. */
static vr_material *load(const char *path) {
  size_t len;
  char *text = slurp(path, &len);
  vr_material *m = vr_material_create("test", VR_KIND_DIELECTRIC, NULL);
  assert_non_null(m);
  vr_error err = {0};
  if (vr_rii_parse(text, len, path, m, &err)) fail_msg("%s", err.message);
  free(text);
  return m;
}

static vr_material *load_data(const char *file) {
  char path[512];
  snprintf(path, sizeof path, "%s/%s", VR_TEST_DATA, file);
  return load(path);
}

static vr_material *load_matdb(const char *file) {
  char path[512];
  snprintf(path, sizeof path, "%s/matdb/data/%s", VR_SOURCE_DIR, file);
  return load(path);
}

/* Parses text expected to be refused; returns the status, message in err. */
static vr_status parse_bad(const char *text, const char **path, vr_error *err) {
  *path = vr_test_file(text);
  assert_non_null(*path);
  size_t len;
  char *buf = slurp(*path, &len);
  vr_material *m = vr_material_create("bad", VR_KIND_DIELECTRIC, NULL);
  vr_status st = vr_rii_parse(buf, len, *path, m, err);
  /* A refused file leaves the material untouched. */
  if (st) {
    assert_int_equal(m->n_formula.type, 0);
    assert_int_equal(m->nspectra, 0);
    assert_int_equal(m->nprops, 0);
    assert_null(m->description);
  }
  vr_material_destroy(m);
  free(buf);
  unlink(*path);
  return st;
}

/* A property that must exist. */
static const vr_property *prop(const vr_material *m, const char *key) {
  const vr_property *p = vr_material_property(m, key);
  if (!p) fail_msg("no property '%s'", key);
  return p;
}

static double n_at(const vr_material *m, double nm) {
  double n;
  vr_error err = {0};
  if (vr_formula_eval(&m->n_formula, nm, &n, &err)) fail_msg("%s", err.message);
  return n;
}

/* ---------------------------------------------------------------------- */
/* The nine formula types.  Each expected value is the formula as published
 * in refractiveindex.info's "Dispersion formulas" (database/doc), written
 * out with the file's own coefficients; λ in µm. */

static void formula_1_sellmeier(void **state) {
  (void)state;
  /* rii_formula_1.yml, fused silica, Malitson 1965:
   * n² - 1 = C1 + C2 λ²/(λ² - C3²) + C4 λ²/(λ² - C5²) + C6 λ²/(λ² - C7²) */
  vr_material *m = load_data("rii_formula_1.yml");
  assert_int_equal(m->n_formula.type, 1);
  assert_int_equal(m->n_formula.ncoeffs, 7);
  assert_near(m->n_formula.min_nm, 210, 1e-9);
  assert_near(m->n_formula.max_nm, 6700, 1e-9);
  const double ls[] = {0.4, 1.55};
  for (int i = 0; i < 2; i++) {
    double l = ls[i], l2 = l * l;
    double n2 = 1 + 0 + 0.6961663 * l2 / (l2 - 0.0684043 * 0.0684043) +
                0.4079426 * l2 / (l2 - 0.1162414 * 0.1162414) +
                0.8974794 * l2 / (l2 - 9.896161 * 9.896161);
    assert_rel(n_at(m, l * 1000), sqrt(n2), 1e-14);
  }
  const vr_property *t = vr_material_property(m, "temperature");
  assert_non_null(t);
  assert_null(t->text);
  assert_near(t->value, 293, 0);
  vr_material_destroy(m);
}

static void formula_2_sellmeier2(void **state) {
  (void)state;
  /* rii_formula_2.yml, SCHOTT N-BK7 (Zemax catalogue 2017):
   * n² - 1 = C1 + C2 λ²/(λ² - C3) + C4 λ²/(λ² - C5) + C6 λ²/(λ² - C7) */
  vr_material *m = load_data("rii_formula_2.yml");
  assert_int_equal(m->n_formula.type, 2);
  const double ls[] = {0.365, 2.0};
  for (int i = 0; i < 2; i++) {
    double l = ls[i], l2 = l * l;
    double n2 = 1 + 0 + 1.03961212 * l2 / (l2 - 0.00600069867) +
                0.231792344 * l2 / (l2 - 0.0200179144) + 1.01046945 * l2 / (l2 - 103.560653);
    assert_rel(n_at(m, l * 1000), sqrt(n2), 1e-14);
  }
  assert_string_equal(m->prov.model, "rii formula 2 + tabulated k");
  /* PROPERTIES, flattened: nested mappings and list items get a path. */
  assert_near(prop(m, "nd")->value, 1.5168, 0);
  assert_string_equal(prop(m, "glass_status")->text, "standard");
  assert_near(prop(m, "density.value")->value, 2510, 0);
  assert_near(prop(m, "thermal_expansion.2.value")->value, 8.3e-06, 0);
  assert_string_equal(prop(m, "thermal_expansion.1.temperature_range")->text,
                      "243 343");
  assert_near(prop(m, "resistance.alkali")->value, 2.3, 0);
  vr_material_destroy(m);
}

static void formula_3_polynomial(void **state) {
  (void)state;
  /* rii_formula_3.yml, NIKON BK7-type glass:
   * n² = C1 + C2 λ^C3 + C4 λ^C5 + C6 λ^C7 + C8 λ^C9 + C10 λ^C11 */
  vr_material *m = load_data("rii_formula_3.yml");
  assert_int_equal(m->n_formula.type, 3);
  assert_int_equal(m->n_formula.ncoeffs, 11);
  const double ls[] = {0.45, 0.65};
  for (int i = 0; i < 2; i++) {
    double l = ls[i];
    double n2 = 2.271192 - 0.00966126763 * pow(l, 2) + 0.0110306969 * pow(l, -2) +
                7.00379964e-05 * pow(l, -4) + 1.39658544e-05 * pow(l, -6) -
                7.62560454e-07 * pow(l, -8);
    assert_rel(n_at(m, l * 1000), sqrt(n2), 1e-14);
  }
  /* The catalogue's own nd (587.56 nm) in the same file, to its 6 digits. */
  assert_near(n_at(m, 587.56), 1.516800, 5e-6);
  vr_material_destroy(m);
}

static void formula_4_refractiveindex_info(void **state) {
  (void)state;
  /* rii_formula_4.yml, rutile (o), Devore 1951; coefficients
   * "5.913 0.2441 0 0.0803 1 0 0 0 1":
   * n² = C1 + C2 λ^C3/(λ² - C4^C5) + C6 λ^C7/(λ² - C8^C9), i.e. Devore's
   * n² = 5.913 + 0.2441/(λ² - 0.0803); C10..C17 are absent. */
  vr_material *m = load_data("rii_formula_4.yml");
  assert_int_equal(m->n_formula.type, 4);
  assert_int_equal(m->n_formula.ncoeffs, 9);
  const double ls[] = {0.55, 1.2};
  for (int i = 0; i < 2; i++) {
    double l = ls[i], l2 = l * l;
    double n2 = 5.913 + 0.2441 * pow(l, 0) / (l2 - pow(0.0803, 1)) +
                0 * pow(l, 0) / (l2 - pow(0, 1));
    assert_rel(n_at(m, l * 1000), sqrt(n2), 1e-14);
  }
  assert_string_equal(prop(m, "direction")->text, "o");
  vr_material_destroy(m);

  /* The power-law terms C10 λ^C11 ... C16 λ^C17 (hand-made coefficients). */
  vr_formula f = {.type = 4, .ncoeffs = 17, .min_nm = 400, .max_nm = 800};
  const double c[17] = {2.0,  0.1, 2,     0.05, 2,     0.2, 0,    3.0, 1,
                        0.01, 2,   0.002, -2,   0.003, 1,   1e-4, -4};
  memcpy(f.c, c, sizeof c);
  double l = 0.6, l2 = l * l, n;
  double n2 = 2.0 + 0.1 * pow(l, 2) / (l2 - pow(0.05, 2)) + 0.2 * pow(l, 0) / (l2 - pow(3.0, 1)) +
              0.01 * pow(l, 2) + 0.002 * pow(l, -2) + 0.003 * pow(l, 1) + 1e-4 * pow(l, -4);
  assert_int_equal(vr_formula_eval(&f, 600, &n, NULL), VR_OK);
  assert_rel(n, sqrt(n2), 1e-14);
}

static void formula_5_cauchy(void **state) {
  (void)state;
  /* rii_formula_5.yml, soda-lime glass, Rubin 1985:
   * n = C1 + C2 λ^C3 + C4 λ^C5 */
  vr_material *m = load_data("rii_formula_5.yml");
  assert_int_equal(m->n_formula.type, 5);
  const double ls[] = {0.55, 2.5};
  for (int i = 0; i < 2; i++) {
    double l = ls[i];
    double n = 1.5130 - 0.003169 * pow(l, 2) + 0.003962 * pow(l, -2);
    assert_rel(n_at(m, l * 1000), n, 1e-14);
  }
  vr_material_destroy(m);
}

static void formula_6_gases(void **state) {
  (void)state;
  /* rii_formula_6.yml, standard air, Ciddor 1996:
   * n - 1 = C1 + C2/(C3 - λ⁻²) + C4/(C5 - λ⁻²) */
  vr_material *m = load_data("rii_formula_6.yml");
  assert_int_equal(m->n_formula.type, 6);
  const double ls[] = {0.3, 0.6328};
  for (int i = 0; i < 2; i++) {
    double l = ls[i];
    double n = 1 + 0 + 0.05792105 / (238.0185 - pow(l, -2)) + 0.00167917 / (57.362 - pow(l, -2));
    assert_rel(n_at(m, l * 1000), n, 1e-15);
  }
  vr_material_destroy(m);
}

static void formula_7_herzberger(void **state) {
  (void)state;
  /* rii_formula_7.yml, silicon, Edwards and Ochoa 1980:
   * n = C1 + C2/(λ² - 0.028) + C3 (1/(λ² - 0.028))² + C4 λ² + C5 λ⁴ + C6 λ⁶ */
  vr_material *m = load_data("rii_formula_7.yml");
  assert_int_equal(m->n_formula.type, 7);
  assert_int_equal(m->n_formula.ncoeffs, 5);
  const double ls[] = {3.0, 10.6};
  for (int i = 0; i < 2; i++) {
    double l = ls[i], l2 = l * l, L = 1 / (l2 - 0.028);
    double n = 3.41983 + 0.159906 * L - 0.123109 * L * L + 1.26878E-6 * l2 -
               1.95104E-9 * l2 * l2 + 0 * l2 * l2 * l2;
    assert_rel(n_at(m, l * 1000), n, 1e-14);
  }
  vr_material_destroy(m);
}

static void formula_8_retro(void **state) {
  (void)state;
  /* rii_formula_8.yml, Schröter 1931:
   * (n² - 1)/(n² + 2) = C1 + C2 λ²/(λ² - C3) + C4 λ², solved for n:
   * n = sqrt((1 + 2 r)/(1 - r)) with r the right-hand side. */
  vr_material *m = load_data("rii_formula_8.yml");
  assert_int_equal(m->n_formula.type, 8);
  const double ls[] = {0.5, 0.6563};
  for (int i = 0; i < 2; i++) {
    double l = ls[i], l2 = l * l;
    double r = 0.452505 + 0.09939 * l2 / (l2 - 0.070537) - 0.000150 * l2;
    double n = sqrt((1 + 2 * r) / (1 - r));
    assert_rel(n_at(m, l * 1000), n, 1e-14);
    /* and the definition itself holds for the n returned */
    double nn = n_at(m, l * 1000);
    assert_rel((nn * nn - 1) / (nn * nn + 2), r, 1e-14);
  }
  vr_material_destroy(m);
}

static void formula_9_exotic(void **state) {
  (void)state;
  /* rii_formula_9.yml, urea (e), Rosker, Cheng and Tang 1985:
   * n² = C1 + C2/(λ² - C3) + C4 (λ - C5)/((λ - C5)² + C6) */
  vr_material *m = load_data("rii_formula_9.yml");
  assert_int_equal(m->n_formula.type, 9);
  assert_int_equal(m->n_formula.ncoeffs, 6);
  const double ls[] = {0.532, 1.0};
  for (int i = 0; i < 2; i++) {
    double l = ls[i], l2 = l * l;
    double n2 = 2.51527 + 0.0240 / (l2 - 0.0300) +
                0.020 * (l - 1.52) / ((l - 1.52) * (l - 1.52) + 0.8771);
    assert_rel(n_at(m, l * 1000), sqrt(n2), 1e-14);
  }
  vr_material_destroy(m);
}

static void formula_edges(void **state) {
  (void)state;
  vr_error err = {0};
  double n;
  /* A pole: Sellmeier with a resonance at exactly 0.5 µm. */
  vr_formula f = {.type = 1, .ncoeffs = 3, .c = {0, 1.0, 0.5}, .min_nm = 400, .max_nm = 600};
  assert_int_equal(vr_formula_eval(&f, 500, &n, &err), VR_E_NUMERIC);
  assert_contains(err.message, "formula 1");
  assert_contains(err.message, "500 nm");
  /* n² <= 0 (Cauchy-like polynomial pushed negative). */
  vr_formula g = {.type = 3, .ncoeffs = 3, .c = {-1.0, 0.1, 2}, .min_nm = 400, .max_nm = 600};
  assert_int_equal(vr_formula_eval(&g, 450, &n, &err), VR_E_NUMERIC);
  assert_contains(err.message, "formula 3");
  assert_contains(err.message, "450 nm");
  /* Retro formula at its pole r = 1. */
  vr_formula h = {.type = 8, .ncoeffs = 1, .c = {1.0}, .min_nm = 400, .max_nm = 600};
  assert_int_equal(vr_formula_eval(&h, 450, &n, &err), VR_E_NUMERIC);
  assert_contains(err.message, "formula 8");
  /* Unknown types and bad wavelengths are the caller's mistake. */
  vr_formula u = {.type = 10, .ncoeffs = 1, .c = {1.0}};
  assert_int_equal(vr_formula_eval(&u, 500, &n, &err), VR_E_ARG);
  assert_contains(err.message, "10");
  u.type = 0;
  assert_int_equal(vr_formula_eval(&u, 500, &n, &err), VR_E_ARG);
  assert_int_equal(vr_formula_eval(&f, -1, &n, &err), VR_E_ARG);
  assert_int_equal(vr_formula_eval(&f, NAN, &n, &err), VR_E_ARG);
}

/* ---------------------------------------------------------------------- */
/* Published values */

static void published_values(void **state) {
  (void)state;
  /* SCHOTT N-BK7 data sheet: nd (587.56 nm) = 1.51680, nF (486.13 nm) = 1.52238
   * (1.522376 to six decimals). */
  vr_material *m = load_matdb("nbk7.yml");
  double n, k;
  bool ex;
  assert_int_equal(vr_material_nk(m, 587.56, false, &n, &k, &ex, NULL), VR_OK);
  assert_near(n, 1.516800, 1e-6);
  assert_false(ex);
  assert_int_equal(vr_material_nk(m, 486.13, false, &n, &k, NULL, NULL), VR_OK);
  assert_near(n, 1.522376, 1e-6);
  assert_true(k > 0 && k < 1e-7);
  vr_material_destroy(m);

  /* Malitson 1965, fused silica: n = 1.458464 at 587.56 nm (He d line). */
  m = load_matdb("fused_silica_malitson.yml");
  assert_int_equal(vr_material_nk(m, 587.56, false, &n, &k, NULL, NULL), VR_OK);
  assert_near(n, 1.458464, 1e-6);
  assert_near(k, 0, 0);
  vr_material_destroy(m);

  /* Green 2008, Si at 300 K: the 630 nm row of the table is
   * "6.3000e-01 3.8790e+00 1.6444e-02". */
  m = load_matdb("si_green2008.yml");
  assert_string_equal(m->prov.model, "rii tabulated nk");
  const vr_spectrum *ns = vr_material_spectrum(m, "n"), *ks = vr_material_spectrum(m, "k");
  assert_non_null(ns);
  assert_non_null(ks);
  bool found = false;
  for (size_t i = 0; i < ns->n; i++)
    if (ns->nm[i] == 630.0) {
      found = true;
      assert_near(ns->value[i], 3.879, 0);
      assert_near(ks->value[i], 0.016444, 0);
    }
  assert_true(found);
  assert_int_equal(vr_material_nk(m, 630, false, &n, &k, NULL, NULL), VR_OK);
  assert_near(n, 3.879, 1e-12);
  assert_near(k, 0.016444, 1e-12);
  assert_contains(m->prov.reference, "M. A. Green");
  assert_contains(m->description, "300 K");
  vr_material_destroy(m);
}

static void multi_block(void **state) {
  (void)state;
  /* rii_multi_block.yml: a quoted REFERENCES, a "formula 3 " type with a
   * trailing blank, a tabulated k block and an old-style SPECS mapping. */
  vr_material *m = load_data("rii_multi_block.yml");
  assert_int_equal(m->n_formula.type, 3);
  assert_int_equal(m->n_formula.ncoeffs, 11);
  assert_near(m->n_formula.min_nm, 365, 1e-9);
  assert_near(m->n_formula.max_nm, 1014, 1e-9);
  const vr_spectrum *k = vr_material_spectrum(m, "k");
  assert_non_null(k);
  assert_null(vr_material_spectrum(m, "n"));
  assert_int_equal(k->n, 35);
  assert_near(k->nm[0], 280, 1e-9);
  assert_near(k->value[0], 5.8625E-06, 0);
  assert_near(k->nm[34], 2400, 1e-9);
  assert_string_equal(m->prov.model, "rii formula 3 + tabulated k");
  assert_contains(m->prov.reference, "CDGM Zemax catalog 2017-09");
  assert_null(m->description);
  /* The catalogue's nd in SPECS against the formula (587.56 nm). */
  const vr_property *nd = vr_material_property(m, "nd");
  assert_non_null(nd);
  assert_near(nd->value, 1.516324, 0);
  assert_near(n_at(m, 587.56), nd->value, 5e-6);
  assert_string_equal(prop(m, "temperature")->text, "20.0 °C");
  assert_string_equal(prop(m, "thermal_expansion.2.coefficient")->text,
                      "7.8e-06 K<sup>-1</sup>");
  assert_string_equal(prop(m, "thermal_dispersion.type")->text, "Schott formula");
  /* n and k: k only where both are defined (the formula's range). */
  double lo, hi;
  assert_int_equal(vr_material_nk_range(m, &lo, &hi, NULL), VR_OK);
  assert_near(lo, 365, 1e-9);
  assert_near(hi, 1014, 1e-9);
  vr_material_destroy(m);
}

/* ---------------------------------------------------------------------- */
/* Round trips */

static void assert_same_spectrum(const vr_spectrum *a, const vr_spectrum *b) {
  if (!a || !b) {
    assert_true(a == b);
    return;
  }
  assert_int_equal(a->n, b->n);
  for (size_t i = 0; i < a->n; i++) {
    if (a->nm[i] != b->nm[i]) fail_msg("row %zu: nm %.17g != %.17g", i, a->nm[i], b->nm[i]);
    if (a->value[i] != b->value[i])
      fail_msg("row %zu: value %.17g != %.17g", i, a->value[i], b->value[i]);
  }
}

static void assert_same_text(const char *a, const char *b) {
  if (!a || !b) assert_true(a == b);
  else assert_string_equal(a, b);
}

/* Writes m, reads it back, and demands identical numbers and texts. */
static void round_trip(const vr_material *m) {
  char *buf = NULL;
  size_t len = 0;
  FILE *f = open_memstream(&buf, &len);
  assert_non_null(f);
  vr_error err = {0};
  if (vr_rii_write(f, m, &err)) fail_msg("%s", err.message);
  fclose(f);
  vr_material *r = vr_material_create("back", m->kind, NULL);
  if (vr_rii_parse(buf, len, "written.yml", r, &err)) fail_msg("%s\n%s", err.message, buf);
  assert_int_equal(r->n_formula.type, m->n_formula.type);
  assert_int_equal(r->n_formula.ncoeffs, m->n_formula.ncoeffs);
  for (size_t i = 0; i < m->n_formula.ncoeffs; i++)
    assert_true(r->n_formula.c[i] == m->n_formula.c[i]);
  assert_true(r->n_formula.min_nm == m->n_formula.min_nm);
  assert_true(r->n_formula.max_nm == m->n_formula.max_nm);
  assert_int_equal(r->nspectra, m->nspectra);
  assert_same_spectrum(vr_material_spectrum(r, "n"), vr_material_spectrum(m, "n"));
  assert_same_spectrum(vr_material_spectrum(r, "k"), vr_material_spectrum(m, "k"));
  assert_same_text(r->prov.reference, m->prov.reference);
  assert_same_text(r->description, m->description);
  assert_int_equal(r->nprops, m->nprops);
  for (size_t i = 0; i < m->nprops; i++) {
    const vr_property *p = vr_material_property(r, m->props[i].key);
    if (!p) fail_msg("property '%s' lost", m->props[i].key);
    assert_same_text(p->text, m->props[i].text);
    if (!p->text) assert_true(p->value == m->props[i].value);
  }
  vr_material_destroy(r);
  free(buf);
}

static void round_trips(void **state) {
  (void)state;
  const char *files[] = {"nbk7.yml", "si_green2008.yml", "al_rakic.yml"};
  for (int i = 0; i < 3; i++) {
    vr_material *m = load_matdb(files[i]);
    round_trip(m);
    vr_material_destroy(m);
  }
  for (int t = 1; t <= 9; t++) {
    char name[32];
    snprintf(name, sizeof name, "rii_formula_%d.yml", t);
    vr_material *m = load_data(name);
    round_trip(m);
    vr_material_destroy(m);
  }
}

/* Any nm double must come back bit for bit, not only those read from µm
 * text: a computed grid holds values for which strtod(nm/1000 as text) *
 * 1000 is one ulp off (about 1 in 80), which the reader's decimal shift and
 * the writer's digit search avoid.  Texts with quotes, tabs and leading
 * blanks, and keys that need quoting, must survive too. */
static void round_trip_hard_values(void **state) {
  (void)state;
  enum { N = 3000 };
  double *nm = malloc(N * sizeof *nm), *v = malloc(N * sizeof *v);
  assert_non_null(nm);
  assert_non_null(v);
  size_t misses = 0;
  for (int i = 0; i < N; i++) {
    nm[i] = 200.0 + i * 0.987654321 + 1e-7 * i * i;
    v[i] = 1.0 / (i + 3.0);
    if (nm[i] / 1000.0 * 1000.0 != nm[i]) misses++;
  }
  assert_true(misses > 0); /* the naive conversion would fail this test */
  nm[0] = 1e-4;            /* far ends: scientific notation in µm */
  nm[N - 1] = 1e9;
  vr_material *m = vr_material_create("hard", VR_KIND_DIELECTRIC, NULL);
  assert_int_equal(vr_material_add_spectrum(m, "n", vr_spectrum_create(N, nm, v, NULL), NULL),
                   VR_OK);
  assert_int_equal(vr_material_add_spectrum(m, "k", vr_spectrum_create(N / 2, nm, v, NULL), NULL),
                   VR_OK);
  vr_material_set_text(&m->description, "  leading blanks, \"quotes\",\ttab\nand \\ a second line",
                       NULL);
  vr_material_set_text(&m->prov.reference, "Ref. 1\n\n  indented line", NULL);
  /* NEL and LS are line breaks to YAML, U+0080 is not allowed raw */
  vr_material_add_property(m, "unicode", "a\xc2\x85" "b\xe2\x80\xa8" "c\xc2\x80" "d °C", NAN,
                           NULL, NULL);
  vr_material_add_property(m, "key with: colon", "text: #not a comment", NAN, NULL, NULL);
  vr_material_add_property(m, "quoted number", "293", NAN, NULL, NULL);
  vr_material_add_property(m, "pressure", NULL, 101325.0, NULL, NULL);
  round_trip(m);
  vr_material_destroy(m);
  free(nm);
  free(v);
}

static void write_refuses(void **state) {
  (void)state;
  vr_error err = {0};
  FILE *f = fopen("/dev/null", "w");
  assert_non_null(f);
  vr_material *m = vr_material_create("empty", VR_KIND_DIELECTRIC, NULL);
  assert_int_equal(vr_rii_write(f, m, &err), VR_E_ARG);
  assert_contains(err.message, "no n or k");
  double nm[] = {400, 500}, v[] = {0.5, 0.6};
  vr_material_add_spectrum(m, "T", vr_spectrum_create(2, nm, v, NULL), NULL);
  assert_int_equal(vr_rii_write(f, m, &err), VR_E_ARG);
  assert_contains(err.message, "'T'");
  vr_material_destroy(m);
  fclose(f);
}

/* ---------------------------------------------------------------------- */
/* Bad input: file, line, field */

static void expect_error(const char *text, vr_status status, const char *where,
                         const char *what) {
  vr_error err = {0};
  const char *path;
  vr_status st = parse_bad(text, &path, &err);
  if (st != status) fail_msg("status %d, expected %d: %s", st, status, err.message);
  assert_contains(err.message, path);
  char loc[600];
  snprintf(loc, sizeof loc, "%s%s", path, where);
  assert_contains(err.message, loc);
  assert_contains(err.message, what);
}

static void bad_yaml(void **state) {
  (void)state;
  /* Line 4 is indented deeper than its sibling: the plain scalar on line 3
   * runs on, and libyaml stops at the ':' of line 4. */
  expect_error("REFERENCES: x\n"
               "DATA:\n"
               "  - type: formula 1\n"
               "     wavelength_range: 0.2 1.0\n"
               "    coefficients: 0 1 0.1\n",
               VR_E_PARSE, ":4:", "malformed YAML: mapping values are not allowed");
  /* An unclosed quote. */
  expect_error("REFERENCES: \"x\nDATA: []\n", VR_E_PARSE, ":3:", "malformed YAML");
  /* Not a mapping at the top. */
  expect_error("- a\n- b\n", VR_E_PARSE, ":1:1:", "expected a mapping");
  /* Invalid UTF-8: the reader's byte offset becomes a line. */
  expect_error("COMMENTS: ok\nREFERENCES: \xff\n", VR_E_PARSE, ":2:", "malformed YAML");
}

static void bad_type(void **state) {
  (void)state;
  expect_error("DATA:\n"
               "  - type: formula 12\n"
               "    wavelength_range: 0.2 1\n"
               "    coefficients: 1\n",
               VR_E_PARSE, ":2:11:", "field 'type': unknown type 'formula 12'");
  expect_error("DATA:\n"
               "  - type: tabulated x\n"
               "    data: 0.5 1\n",
               VR_E_PARSE, ":2:", "field 'type'");
  expect_error("COMMENTS: x\n"
               "DATA:\n"
               "  - wavelength_range: 0.2 1\n"
               "    coefficients: 1\n",
               VR_E_PARSE, ":3:5:", "DATA block 1: no 'type'");
}

static void bad_rows(void **state) {
  (void)state;
  /* Non-numeric k on the third row; the column points at it. */
  expect_error("# comment\n"
               "DATA:\n"
               "  - type: tabulated nk\n"
               "    data: |\n"
               "        0.40 1.5 0.1\n"
               "        0.50 1.5 0.1\n"
               "        0.60 1.5 abc\n",
               VR_E_PARSE, ":7:18:", "data row 3: field 'k': expected a number, got 'abc'");
  /* The same with CR LF line ends. */
  expect_error("# comment\r\n"
               "DATA:\r\n"
               "  - type: tabulated nk\r\n"
               "    data: |\r\n"
               "        0.40 1.5 0.1\r\n"
               "        0.50 1.5 0.1\r\n"
               "        0.60 1.5 abc\r\n",
               VR_E_PARSE, ":7:18:", "data row 3: field 'k'");
  /* A repeated wavelength after a blank line: row 3 is on line 7. */
  expect_error("DATA:\n"
               "  - type: tabulated n\n"
               "    data: |\n"
               "        0.40 1.5\n"
               "        0.50 1.6\n"
               "\n"
               "        0.50 1.7\n",
               VR_E_PARSE, ":7:9:", "data row 3: field 'wavelength'");
  /* Decreasing. */
  expect_error("DATA:\n"
               "  - type: tabulated k\n"
               "    data: |\n"
               "        0.40 1e-3\n"
               "        0.30 1e-3\n",
               VR_E_PARSE, ":5:", "data row 2: field 'wavelength'");
  /* NaN is not a number a table may hold. */
  expect_error("DATA:\n"
               "  - type: tabulated n\n"
               "    data: |\n"
               "        0.40 1.5\n"
               "        0.50 nan\n",
               VR_E_RANGE, ":5:14:", "data row 2: field 'n': not a finite number");
  /* Too few and too many fields. */
  expect_error("DATA:\n"
               "  - type: tabulated nk\n"
               "    data: |\n"
               "        0.40 1.5 0.1\n"
               "        0.50 1.5\n",
               VR_E_PARSE, ":5:", "data row 2: field 'k' is missing");
  expect_error("DATA:\n"
               "  - type: tabulated n\n"
               "    data: |\n"
               "        0.40 1.5 0.1\n",
               VR_E_PARSE, ":4:18:", "data row 1: an extra field '0.1' after 'n'");
  /* No rows, no data, negative wavelength. */
  expect_error("DATA:\n"
               "  - type: tabulated n\n"
               "    data: |\n"
               "\n",
               VR_E_PARSE, ":3:", "field 'data': no rows");
  expect_error("DATA:\n"
               "  - type: tabulated n\n",
               VR_E_PARSE, ":2:5:", "field 'data' is missing");
  expect_error("DATA:\n"
               "  - type: tabulated n\n"
               "    data: |\n"
               "        -0.4 1.5\n",
               VR_E_RANGE, ":4:", "data row 1: field 'wavelength'");
}

static void bad_formula(void **state) {
  (void)state;
  expect_error("REFERENCES: |\n"
               "    someone\n"
               "DATA:\n"
               "  - type: formula 2\n"
               "    wavelength_range: 0.3 2.5\n",
               VR_E_PARSE, ":4:5:", "field 'coefficients' is missing");
  expect_error("DATA:\n"
               "  - type: formula 2\n"
               "    coefficients: 0 1 0.01\n",
               VR_E_PARSE, ":2:5:", "field 'wavelength_range' is missing");
  expect_error("DATA:\n"
               "  - type: formula 2\n"
               "    wavelength_range: 0.3\n"
               "    coefficients: 0 1 0.01\n",
               VR_E_PARSE, ":3:", "field 'wavelength_range'");
  expect_error("DATA:\n"
               "  - type: formula 2\n"
               "    wavelength_range: 0.3 2.5\n"
               "    coefficients: 0 1 x\n",
               VR_E_PARSE, ":4:", "field 'coefficients': item 3");
  expect_error("DATA:\n"
               "  - type: formula 3\n"
               "    wavelength_range: 0.3 2.5\n"
               "    coefficients: 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18\n",
               VR_E_PARSE, ":4:", "18 coefficients");
  /* A pole inside the stated range. */
  expect_error("DATA:\n"
               "  - type: formula 1\n"
               "    wavelength_range: 0.3 0.7\n"
               "    coefficients: 0 1 0.5\n",
               VR_E_NUMERIC, ":4:", "formula 1 at 500 nm");
}

static void bad_structure(void **state) {
  (void)state;
  expect_error("REFERENCES: x\nCOMMENTS: y\n", VR_E_PARSE, ":1:", "no DATA section");
  expect_error("", VR_E_PARSE, "", "no DATA");
  expect_error("DATA: x\n", VR_E_PARSE, ":1:7:", "expected a list of blocks");
  /* Two n definitions, two k definitions. */
  expect_error("DATA:\n"
               "  - type: formula 5\n"
               "    wavelength_range: 0.3 2.5\n"
               "    coefficients: 1.5\n"
               "  - type: tabulated nk\n"
               "    data: |\n"
               "        0.4 1.5 0\n",
               VR_E_PARSE, ":5:5:", "a second definition of n (block 1");
  expect_error("DATA:\n"
               "  - type: tabulated k\n"
               "    data: 0.4 0.1\n"
               "  - type: tabulated k\n"
               "    data: 0.5 0.1\n",
               VR_E_PARSE, ":4:5:", "a second definition of k");
  expect_error("CONDITIONS: 12\nDATA: []\n", VR_E_PARSE, ":1:13:",
               "CONDITIONS: expected a mapping");
}

static void conditions_and_specs(void **state) {
  (void)state;
  const char *path = vr_test_file("CONDITIONS:\n"
                                  "    temperature: 293\n"
                                  "    pressure: \"101325\"\n"
                                  "SPECS:\n"
                                  "    temperature: 20.0 °C\n"
                                  "    empty:\n"
                                  "    a:\n"
                                  "        b:\n"
                                  "            c: 1.5e3\n"
                                  "DATA:\n"
                                  "  - type: tabulated n\n"
                                  "    data: 0.5 1.5\n");
  vr_material *m = load(path);
  unlink(path);
  assert_near(prop(m, "temperature")->value, 293, 0);
  /* a quoted number is text */
  assert_string_equal(prop(m, "pressure")->text, "101325");
  /* the second "temperature" keeps its section */
  assert_string_equal(prop(m, "SPECS.temperature")->text, "20.0 °C");
  assert_null(vr_material_property(m, "empty"));
  assert_near(prop(m, "a.b.c")->value, 1500, 0);
  /* a plain one-line data scalar is one row */
  const vr_spectrum *n = vr_material_spectrum(m, "n");
  assert_int_equal(n->n, 1);
  assert_near(n->nm[0], 500, 0);
  assert_string_equal(m->prov.model, "rii tabulated n");
  vr_material_destroy(m);
}

/* ---------------------------------------------------------------------- */
/* Range rules through vr_material_nk */

static void formula_range(void **state) {
  (void)state;
  vr_material *m = load_matdb("fused_silica_malitson.yml"); /* 0.21 - 6.7 µm */
  double n, k;
  bool ex = false;
  vr_error err = {0};
  assert_int_equal(vr_material_nk(m, 7000, false, &n, &k, &ex, &err), VR_E_RANGE);
  assert_contains(err.message, "7000 nm");
  assert_int_equal(vr_material_nk(m, 200, false, &n, &k, &ex, &err), VR_E_RANGE);
  assert_int_equal(vr_material_nk(m, 7000, true, &n, &k, &ex, &err), VR_OK);
  assert_true(ex);
  assert_true(n == n_at(m, 6700));
  assert_near(k, 0, 0);
  assert_int_equal(vr_material_nk(m, 100, true, &n, &k, &ex, &err), VR_OK);
  assert_true(ex);
  assert_true(n == n_at(m, 210));
  assert_int_equal(vr_material_nk(m, 210, false, &n, &k, &ex, &err), VR_OK);
  assert_false(ex);
  vr_material_destroy(m);

  /* A formula with tabulated k: the k table narrows nothing here (N-BK7's
   * k spans the formula's 0.3 - 2.5 µm), and outside it both hold. */
  m = load_matdb("nbk7.yml");
  assert_int_equal(vr_material_nk(m, 2600, false, &n, &k, &ex, &err), VR_E_RANGE);
  assert_int_equal(vr_material_nk(m, 2600, true, &n, &k, &ex, &err), VR_OK);
  assert_true(ex);
  assert_true(n == n_at(m, 2500));
  assert_near(k, 8.1300E-06, 0);
  vr_material_destroy(m);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(formula_1_sellmeier),
      cmocka_unit_test(formula_2_sellmeier2),
      cmocka_unit_test(formula_3_polynomial),
      cmocka_unit_test(formula_4_refractiveindex_info),
      cmocka_unit_test(formula_5_cauchy),
      cmocka_unit_test(formula_6_gases),
      cmocka_unit_test(formula_7_herzberger),
      cmocka_unit_test(formula_8_retro),
      cmocka_unit_test(formula_9_exotic),
      cmocka_unit_test(formula_edges),
      cmocka_unit_test(published_values),
      cmocka_unit_test(multi_block),
      cmocka_unit_test(round_trips),
      cmocka_unit_test(round_trip_hard_values),
      cmocka_unit_test(write_refuses),
      cmocka_unit_test(bad_yaml),
      cmocka_unit_test(bad_type),
      cmocka_unit_test(bad_rows),
      cmocka_unit_test(bad_formula),
      cmocka_unit_test(bad_structure),
      cmocka_unit_test(conditions_and_specs),
      cmocka_unit_test(formula_range),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
