/* vr-spectro: spectrophotometry of glass to n, k, pane tables, glazing
 * figures and tint-state models.  This file holds the option table, the
 * dispatch and what the commands share. */
#include "vr/file.h"
#include "spectro_cli.h"

#include <complex.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "vr/chromogenic.h"
#include "vr/csv.h"
#include "vr/optics.h"
#include "vr/out_guard.h"
#include "vr/sha256.h"
#include "vr/version.h"

static const vr_option OPTIONS[] = {
    {"thickness", 't', "MM", "pane thickness in mm (else the file's or material's)"},
    {"model", 'm', "NAME", "fit: n model sellmeier (default), sellmeier2 or cauchy"},
    {"sigma", 0, "S", "photometric noise of T and R (absolute, default 1e-3)"},
    {"save", 's', "NAME", "save the result in the material database under NAME"},
    {"db", 'd', "FILE", "material database (default: $VR_MATDB, else ./materials.db)"},
    {"json", 'j', NULL, "JSON output"},
    {"table", 0, "FILE.csv", "fit, btdf: write the per-wavelength table"},
    {"standard", 0, "NAME|FILE", "metrics, bsdf-xml: nfrc (default), en410, iso9050, or an LBNL .std file"},
    {"angle", 'a', "DEG", "metrics: angle of incidence (default 0)"},
    {"phi", 0, "DEG", "metrics of a BSDF XML file: azimuth of incidence (default 0)"},
    {"out", 'o', "FILE.xml", "bsdf-xml: the BSDF XML file to write"},
    {"panes", 0, "A,B,...", "metrics, bsdf-xml: several panes, outside first (files or database names)"},
    {"route", 0, "ROUTE", "metrics, btdf, bsdf-xml: angular route auto (default), physical or coated"},
    {"angles", 0, "LIST", "btdf: angles in degrees (default 0,10,...,80,85,90)"},
    {"stack", 0, "FILE.model", "btdf, bsdf-xml: a coated pane as layers on a substrate (model file)"},
    {"wavelengths", 'w', "FROM:TO:STEP", "btdf, bsdf-xml --stack: wavelengths for materials and stacks (default 300:2500:10)"},
    {"scatter", 0, "FILE.csv", "btdf: angle-resolved scattered transmittance to fit a GGX roughness"},
    {"index", 0, "N", "btdf: glass index for --scatter (default 1.52)"},
    {"states", 0, "LIST", "chromogenic: one state per spectrum (see --help text)"},
    {"state", 0, "S", "metrics, state: tint state in [0, 1] of a chromogenic material"},
    {"charge", 0, "MC_CM2", "metrics, state: electrochromic charge density (mC/cm2)"},
    {"uv", 0, "W_M2", "metrics, state: photochromic steady state under this UV irradiance"},
    {"temperature", 0, "T", "with --uv: glass temperature, e.g. 25C or 298K (default 25C)"},
    {"extrapolate", 0, NULL, "with --uv: evaluate outside the UV and temperatures the model was fitted on"},
    {"gaps", 0, "MM:GAS,...", "thermal: the gaps between panes, e.g. 12.7:air or 16:argon:0.9+air:0.1"},
    {"height", 0, "M", "thermal: glazing height for natural convection (default 1 m, NFRC)"},
    {"tilt", 0, "DEG", "thermal: tilt from horizontal (default 90: vertical)"},
    {"emissivity", 0, "LIST", "thermal: hemispherical emissivity per pane, F or F:B, comma-separated ('-': the pane's own)"},
    {"method", 0, "iso15099|en673", "thermal: the ISO 15099 heat balance under NFRC 100/200 (default) or EN 673's U and EN 410's g"},
    {"edition", 0, "2011|1997", "thermal --method en673: the standards' edition and its film coefficients (default 2011)"},
    {"force", 0, NULL, "fit: accept (exit 0) and --save a fit that does not describe the data"},
};
#define NOPT (sizeof OPTIONS / sizeof OPTIONS[0])

static const char USAGE[] =
    "fit FILE [--thickness MM] [--model sellmeier|sellmeier2|cauchy] [--save NAME [--force]] [--json]\n"
    "       vr-spectro metrics FILE|NAME [--standard nfrc|en410|iso9050] [--angle DEG] [--panes A,B] [--json]\n"
    "       vr-spectro metrics FILE.xml [--angle DEG] [--phi DEG] [--json]\n"
    "       vr-spectro bsdf-xml FILE|NAME|--panes A,B|--stack FILE.model --out F.xml [--standard S] [--state S]\n"
    "       vr-spectro btdf FILE|NAME|--stack FILE [--angles LIST] [--wavelengths A:B:S] [--scatter FILE] [--save NAME] [--json]\n"
    "       vr-spectro chromogenic FILES... --states LIST [--save NAME] [--json]\n"
    "       vr-spectro thermal FILE|NAME|--panes A,B --gaps MM:GAS,... [--emissivity LIST] [--state S] [--height M] [--tilt DEG] [--json]\n"
    "       vr-spectro thermal --method en673 [--edition 2011|1997] FILE|NAME|--panes A,B --gaps MM:GAS,... [--emissivity LIST] [--json]\n"
    "       vr-spectro state NAME [--state S | --charge Q | --uv E [--temperature T] [--extrapolate]] [--json]";
static const char ABOUT[] =
    "Spectrophotometry of glass (T, Rf, Rb; CSV, Cary/Lambda CSV exports, LBNL Optics/IGDB\n"
    "  .DAT and .LOF; docs/vr-spectro.md).  Outputs never replace an input of the run.\n"
    "fit: n, k of an uncoated pane from T and R (slab equations with every internal\n"
    "  reflection, physical root, ill-conditioned wavelengths flagged), smoothed by a\n"
    "  Sellmeier or Cauchy model with standard errors.  A fit whose reduced chi-square (with\n"
    "  the photometric accuracy 0.005 as sigma) exceeds the chi-square test's upper 0.1%\n"
    "  point does not describe the data: exit 1, not saved unless --force.\n"
    "metrics: visible, solar and UV transmittance and reflectance under NFRC 300 (the\n"
    "  Windows-CalcEngine method), EN 410 or ISO 9050; CIELAB of the transmitted light;\n"
    "  several panes with --panes; angles by the physical route (uncoated) or\n"
    "  Windows-CalcEngine's coated-glass polynomials (coated).  R is optional: T alone\n"
    "  gives the T figures (R figures need R).  Data must cover each figure's range.\n"
    "metrics FILE.xml: a BSDF XML file's (WINDOW, IGSDB, genBSDF; Klems) direct-direct,\n"
    "  direct-diffuse, direct-hemispherical and diffuse-diffuse T and R, front and back, by band.\n"
    "bsdf-xml: a pane, several (--panes) or a chromogenic state as a Klems BSDF XML file\n"
    "  (Visible and Solar under --standard) for WINDOW, Radiance and EnergyPlus.\n"
    "btdf: angle x wavelength tables of T and R (s, p) for the renderer; a measured pane\n"
    "  is resampled onto --wavelengths inside its data, never extrapolated.\n"
    "chromogenic: state model of electrochromic (states: charge 12mC/cm2 or voltage -1V)\n"
    "  or photochromic glass (E=40 steady state, t=60:E=40 activation, fade=120:E=40;\n"
    "  add :T=25C for temperature) with 90% limits.\n"
    "thermal: U-factor and SHGC (g-value) by ISO 15099 under NFRC 100/200, as WINDOW and\n"
    "  Windows-CalcEngine: layer solar absorptances from the spectra, emissivities from\n"
    "  thermal-infrared data (NFRC 301) or the file's header, gas gaps of air, argon,\n"
    "  krypton, xenon or mixtures; chromogenic panes at --state/--charge/--uv.\n"
    "  --method en673: the European declared figures, EN 673's U (fixed film coefficients,\n"
    "  its gas table at 10 C, declared to one decimal) and EN 410's g, optics under en410.\n"
    "state: a chromogenic material's spectrum at a state, a charge (within the range the\n"
    "  model was fitted on) or a UV irradiance.";

int spectro_fail(const vr_error *e) {
  fprintf(stderr, "vr-spectro: %s\n", e->message);
  return spectro_exit(e);
}

int spectro_exit(const vr_error *e) {
  return e->status == VR_E_RANGE && !strncmp(e->message, "--", 2) ? 2 : 1;
}

const char *spectro_db_path(const vr_args *a) {
  const char *p = vr_args_get(a, "db");
  if (p) return p;
  p = getenv("VR_MATDB");
  return p && *p ? p : "materials.db";
}

/* One file name from a reference file, relative to that file's folder. */
static void reference(vr_out_guard *g, const char *dir, const char *name, size_t n,
                      const char *role) {
  char path[1100];
  size_t d = name[0] == '/' ? 0 : strlen(dir);
  if (n == 0 || n >= 512 || d >= 512) return;
  if (d) {
    memcpy(path, dir, d);
    path[d++] = '/';
  }
  memcpy(path + d, name, n);
  path[d + n] = '\0';
  vr_out_guard_input(g, path, role);
}

/* The files a model file or an LBNL standard names (a stack's "file:"
 * materials, a standard's source and detector tables): each word, and the
 * text after a line's ':', taken as a name beside the file.  Names that are
 * not files are skipped by vr_out_guard_input. */
static void referenced_files(vr_out_guard *g, const char *path, const char *role) {
  struct stat sb;
  if (stat(path, &sb) || !S_ISREG(sb.st_mode) || sb.st_size > (1 << 20)) return;
  FILE *f = fopen(path, "rb");
  if (!f) return;
  char dir[1024];
  snprintf(dir, sizeof dir, "%s", path);
  char *slash = strrchr(dir, '/');
  if (slash) *slash = '\0';
  else snprintf(dir, sizeof dir, ".");
  char line[1024];
  while (fgets(line, sizeof line, f)) {
    size_t n = strcspn(line, "\r\n");
    line[n] = '\0';
    const char *colon = strrchr(line, ':');
    if (colon) {
      const char *v = colon + 1;
      while (*v == ' ' || *v == '\t') v++;
      size_t k = strlen(v);
      while (k && (v[k - 1] == ' ' || v[k - 1] == '\t')) k--;
      reference(g, dir, v, k, role);
    }
    for (const char *w = line; *w;) {
      while (*w == ' ' || *w == '\t') w++;
      const char *e = w;
      while (*e && *e != ' ' && *e != '\t') e++;
      if (!strncmp(w, "file:", 5)) w += 5;
      if (e > w) reference(g, dir, w, (size_t)(e - w), role);
      w = e;
    }
  }
  fclose(f);
}

/* Every input of the run recorded, every output checked, before any work. */
static vr_status guard_outputs(const vr_args *a, vr_error *err) {
  vr_out_guard g;
  vr_out_guard_init(&g);
  const char *cmd = a->operands[0];
  for (size_t i = 1; i < a->noperands; i++)
    vr_out_guard_input(&g, a->operands[i], !strcmp(cmd, "chromogenic") || !strcmp(cmd, "fit")
                                               ? "the measurement" : "an input");
  const struct {
    const char *opt, *role;
  } IN[] = {{"stack", "the stack model"}, {"scatter", "the scattering measurement"},
            {"standard", "the optical standard"}};
  for (size_t i = 0; i < sizeof IN / sizeof IN[0]; i++) {
    const char *v = vr_args_get(a, IN[i].opt);
    if (v) vr_out_guard_input(&g, v, IN[i].role);
  }
  if (vr_args_get(a, "stack")) referenced_files(&g, vr_args_get(a, "stack"), "a file of the stack model");
  if (vr_args_get(a, "standard"))
    referenced_files(&g, vr_args_get(a, "standard"), "a table of the optical standard");
  const char *panes = vr_args_get(a, "panes");
  if (panes) {
    char *list = strdup(panes), *save = NULL;
    if (!list) return vr_error_set(err, VR_E_NOMEM, "out of memory");
    for (char *t = strtok_r(list, ",", &save); t; t = strtok_r(NULL, ",", &save))
      vr_out_guard_input(&g, t, "a pane");
    free(list);
  }
  vr_out_guard_database(&g, spectro_db_path(a));
  const char *table = vr_args_get(a, "table"), *out = vr_args_get(a, "out");
  if (table && vr_out_guard_check(&g, table, "--table", err)) return err->status;
  return out ? vr_out_guard_check(&g, out, "--out", err) : VR_OK;
}

vr_status spectro_db(const vr_args *a, vr_matdb **db, vr_error *err) {
  if (*db) return VR_OK;
  /* Only a run that saves may create the --db it names. */
  int flags = vr_args_get(a, "save") ? 0 : VR_MATDB_MUST_EXIST;
  return vr_matdb_open(vr_args_get(a, "db"), flags, db, err);
}

vr_status spectro_thickness(const vr_args *a, double *nm, vr_error *err) {
  *nm = NAN;
  const char *t = vr_args_get(a, "thickness");
  if (!t) return VR_OK;
  double mm;
  if (vr_parse_double(t, &mm) || !(mm > 0))
    return vr_error_set(err, VR_E_ARG, "--thickness '%s': expected a positive number of mm", t);
  *nm = mm * 1e6;
  if (vr_spectro_pane_plausible(*nm, "--thickness", 0, err)) return VR_E_ARG;
  return VR_OK;
}

vr_status spectro_state_of(const vr_args *a, const vr_material *m, double *s, vr_error *err) {
  const char *st = vr_args_get(a, "state"), *q = vr_args_get(a, "charge"),
             *uv = vr_args_get(a, "uv"), *temp = vr_args_get(a, "temperature");
  *s = 0;
  if ((st != NULL) + (q != NULL) + (uv != NULL) > 1)
    return vr_error_set(err, VR_E_ARG, "give one of --state, --charge and --uv");
  double x;
  if (st) {
    if (vr_parse_double(st, &x) || !(x >= 0 && x <= 1))
      return vr_error_set(err, VR_E_RANGE, "--state '%s': expected a number in [0, 1]", st);
    *s = x;
    return VR_OK;
  }
  if (q) {
    if (vr_parse_double(q, &x)) return vr_error_set(err, VR_E_RANGE, "--charge '%s': not a number", q);
    /* Outside the fitted charges the library refuses (never clamps); as
     * the option's value it is a usage error, so the message names it. */
    vr_status r = vr_chromo_state_of_charge(m, x, s, err);
    if (r == VR_E_RANGE) vr_error_prefix(err, "--");
    return r;
  }
  if (uv) {
    double T = 298.15;
    if (vr_parse_double(uv, &x) || x < 0)
      return vr_error_set(err, VR_E_RANGE, "--uv '%s': expected W/m2 >= 0", uv);
    if (temp) {
      char buf[32];
      snprintf(buf, sizeof buf, "%s", temp);
      size_t n = strlen(buf);
      double add = 0;
      if (n && (buf[n - 1] == 'C' || buf[n - 1] == 'c')) add = 273.15, buf[n - 1] = '\0';
      else if (n && (buf[n - 1] == 'K' || buf[n - 1] == 'k')) buf[n - 1] = '\0';
      if (vr_parse_double(buf, &T) || !(T + add > 0))
        return vr_error_set(err, VR_E_RANGE, "--temperature '%s': use 25C or 298K", temp);
      T += add;
    }
    unsigned flags = vr_args_flag(a, "extrapolate") ? VR_CHROMO_EXTRAPOLATE : 0;
    vr_status r = vr_chromo_steady_state(m, x, T, flags, s, err);
    /* The options' values: exit 2, naming the one at fault. */
    if (r == VR_E_RANGE && temp && vr_chromo_check_domain(m, 0, T, 0, NULL))
      vr_error_prefix(err, "--temperature %s: ", temp);
    else if (r == VR_E_RANGE)
      vr_error_prefix(err, "--uv %s: ", uv);
    if (!r && flags && vr_chromo_check_domain(m, x, T, 0, NULL))
      fprintf(stderr, "vr-spectro: warning: --uv %g W/m2 at %.2f K is outside the range material "
                      "%s was fitted on; extrapolated as asked\n", x, T, m->name);
    return r;
  }
  return VR_OK;
}

static bool is_file(const char *p) {
  struct stat sb;
  return stat(p, &sb) == 0 && S_ISREG(sb.st_mode);
}

/* A curve from a material evaluated on a grid: chromogenic at a state, or
 * a dielectric slab. */
static vr_status curve_from_material(const vr_args *a, const vr_material *m, double d_nm,
                                     vr_spectro_data **out, vr_error *err) {
  const vr_spectrum *grid = NULL;
  double s = 0;
  vr_status st = VR_OK;
  if (m->kind == VR_KIND_CHROMOGENIC) {
    grid = vr_material_spectrum(m, "T0");
    if ((st = spectro_state_of(a, m, &s, err))) return st;
  } else if (m->kind == VR_KIND_DIELECTRIC || m->kind == VR_KIND_CONDUCTOR) {
    if (!(d_nm > 0))
      return vr_error_set(err, VR_E_ARG, "material %s is a %s: give the pane's --thickness MM",
                          m->name, vr_kind_name(m->kind));
  } else {
    return vr_error_set(err, VR_E_ARG, "material %s is a %s; a pane needs a glazing, chromogenic "
                                       "or dielectric material", m->name, vr_kind_name(m->kind));
  }
  double lo = 300, hi = 2500;
  if (!grid && (st = vr_material_nk_range(m, &lo, &hi, err))) return st;
  size_t n = grid ? grid->n : (size_t)floor((fmin(hi, 2500) - fmax(lo, 300)) / 5) + 1;
  vr_spectro_data *d = calloc(1, sizeof *d);
  vr_spectro_curve *c = d ? calloc(1, sizeof *c) : NULL;
  vr_spectro_point *p = c ? calloc(n, sizeof *p) : NULL;
  if (!p) {
    free(c);
    free(d);
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  d->source = strdup(m->name);
  d->thickness_nm = d_nm;
  d->has_Rf = d->has_Rb = true;
  d->ncurves = 1;
  d->curves = c;
  c->p = p;
  for (size_t i = 0; i < n && !st; i++) {
    vr_spectro_point *q = &p[c->n];
    q->nm = grid ? grid->nm[i] : fmax(lo, 300) + 5.0 * (double)i;
    if (grid) {
      st = vr_chromo_eval(m, s, q->nm, &q->T, &q->Rf, &q->Rb, err);
    } else {
      double nn, kk;
      vr_slab_result r;
      st = vr_material_nk(m, q->nm, false, &nn, &kk, NULL, err);
      if (!st) st = vr_slab(1.0, nn + I * kk, d_nm, 0, q->nm, &r, err);
      if (!st) q->T = r.T[0], q->Rf = q->Rb = r.R[0];
    }
    c->n++;
  }
  if (!st && isnan(p[0].Rf)) d->has_Rf = d->has_Rb = false;
  if (st) {
    vr_spectro_destroy(d);
    return st;
  }
  *out = d;
  return VR_OK;
}

vr_status spectro_pane_source(const vr_args *a, const char *item, vr_matdb **db,
                              vr_spectro_data **out, vr_error *err) {
  double d_nm;
  vr_status st = spectro_thickness(a, &d_nm, err);
  if (st) return st;
  struct stat sb;
  if (stat(item, &sb) == 0 && !S_ISREG(sb.st_mode)) return vr_file_check_regular(item, err);
  if (is_file(item)) {
    if ((st = vr_spectro_read(item, out, err))) return st;
    if (!isnan(d_nm)) (*out)->thickness_nm = d_nm;
    return VR_OK;
  }
  if (strchr(item, '/') || strchr(item, '.')) {
    FILE *f = fopen(item, "rb");
    if (!f) return vr_error_set(err, VR_E_IO, "%s: no such file", item);
    fclose(f);
  }
  if ((st = spectro_db(a, db, err))) return st;
  vr_material *m;
  if ((st = vr_matdb_load(*db, item, 0, &m, err))) return st;
  if (m->kind == VR_KIND_GLAZING) {
    st = vr_spectro_from_material(m, out, err);
    if (!st && !isnan(d_nm)) (*out)->thickness_nm = d_nm;
  } else {
    const vr_property *th = vr_material_property(m, "thickness");
    if (isnan(d_nm) && th && th->value > 0) d_nm = th->value * 1e6;
    st = curve_from_material(a, m, d_nm, out, err);
    if (!st) vr_spectro_thermal_from_material(m, &(*out)->thermal);
  }
  vr_material_destroy(m);
  return st;
}

vr_status spectro_save(vr_matdb *db, vr_material *m, const char *cmd, const char *path,
                       vr_error *err) {
  char tool[64];
  snprintf(tool, sizeof tool, "vr-spectro %s", cmd);
  vr_status st;
  if ((st = vr_material_set_text(&m->prov.tool, tool, err)) ||
      (st = vr_material_set_text(&m->prov.tool_version, vr_version(), err)))
    return st;
  if (path) {
    if ((st = vr_material_set_text(&m->prov.source_path, path, err))) return st;
    if (is_file(path) && (st = vr_sha256_file(path, m->prov.sha256, err))) return st;
  }
  if ((st = vr_matdb_save(db, m, err))) return st;
  fprintf(stderr, "vr-spectro: saved '%s' (version %d) to %s\n", m->name, m->version,
          vr_matdb_path(db));
  return VR_OK;
}

/* Which commands take each option: an option a command would ignore is
 * refused instead (exit 2). */
static bool foreign_option(const vr_args *a, const char *cmd) {
  static const struct {
    const char *opt, *cmds, *why;
  } TAKES[] = {
      {"thickness", "fit metrics btdf chromogenic bsdf-xml thermal", NULL},
      {"model", "fit", NULL},
      {"sigma", "fit chromogenic", NULL},
      {"save", "fit btdf chromogenic", NULL},
      {"table", "fit btdf", "only fit and btdf write a table"},
      {"force", "fit", "only fit accepts a flagged fit"},
      {"standard", "metrics bsdf-xml thermal", NULL},
      {"gaps", "thermal", NULL},
      {"height", "thermal", NULL},
      {"tilt", "thermal", NULL},
      {"emissivity", "thermal", NULL},
      {"method", "thermal", NULL},
      {"edition", "thermal", NULL},
      {"angle", "metrics", NULL},
      {"phi", "metrics", NULL},
      {"out", "bsdf-xml", NULL},
      {"panes", "metrics bsdf-xml thermal", NULL},
      {"route", "metrics btdf bsdf-xml", NULL},
      {"angles", "btdf", NULL},
      {"stack", "btdf bsdf-xml", NULL},
      {"wavelengths", "btdf bsdf-xml", NULL},
      {"scatter", "btdf", NULL},
      {"index", "btdf", NULL},
      {"states", "chromogenic", NULL},
      {"state", "metrics state bsdf-xml thermal", NULL},
      {"charge", "metrics state bsdf-xml thermal", NULL},
      {"uv", "metrics state bsdf-xml thermal", NULL},
      {"temperature", "metrics state bsdf-xml thermal", NULL},
      {"extrapolate", "metrics state bsdf-xml thermal", NULL},
  };
  for (size_t i = 0; i < sizeof TAKES / sizeof TAKES[0]; i++) {
    if (!vr_args_get(a, TAKES[i].opt)) continue;
    const char *c = TAKES[i].cmds;
    size_t n = strlen(cmd);
    bool ok = false;
    for (const char *p = strstr(c, cmd); p && !ok; p = strstr(p + 1, cmd))
      ok = (p == c || p[-1] == ' ') && (p[n] == '\0' || p[n] == ' ');
    if (ok) continue;
    if (TAKES[i].why)
      fprintf(stderr, "vr-spectro: --%s: %s; '%s' does not take it\n", TAKES[i].opt, TAKES[i].why, cmd);
    else
      fprintf(stderr, "vr-spectro: --%s: '%s' does not take it (an option of: %s)\n", TAKES[i].opt,
              cmd, c);
    return true;
  }
  if (vr_args_get(a, "temperature") && !vr_args_get(a, "uv")) {
    fprintf(stderr, "vr-spectro: --temperature: only with --uv (the photochromic steady state)\n");
    return true;
  }
  if (vr_args_flag(a, "extrapolate") && !vr_args_get(a, "uv")) {
    fprintf(stderr, "vr-spectro: --extrapolate: only with --uv (a charge outside the fitted "
                    "range has no state: the model's state is at most 1)\n");
    return true;
  }
  return false;
}

int main(int argc, char **argv) {
  vr_args a;
  vr_args_outcome o = vr_args_parse(&a, "vr-spectro", USAGE, ABOUT, OPTIONS, NOPT, argc, argv);
  if (o == VR_ARGS_EXIT_OK) return 0;
  if (o == VR_ARGS_EXIT_USAGE) return 2;
  static const struct {
    const char *name;
    size_t min_operands;
    int (*run)(vr_args *);
  } CMDS[] = {{"fit", 2, spectro_cmd_fit},
              {"metrics", 1, spectro_cmd_metrics},
              {"btdf", 1, spectro_cmd_btdf},
              {"bsdf-xml", 1, spectro_cmd_bsdf_xml},
              {"chromogenic", 2, spectro_cmd_chromogenic},
              {"thermal", 1, spectro_cmd_thermal},
              {"state", 2, spectro_cmd_state}};
  int rc = -1;
  for (size_t i = 0; i < sizeof CMDS / sizeof CMDS[0]; i++)
    if (a.noperands >= 1 && !strcmp(a.operands[0], CMDS[i].name)) {
      vr_error err = {0};
      if (a.noperands < CMDS[i].min_operands) {
        fprintf(stderr, "vr-spectro: '%s' needs its input (see vr-spectro --help)\n", CMDS[i].name);
        rc = 2;
      } else if (foreign_option(&a, CMDS[i].name)) {
        rc = 2;
      } else if (guard_outputs(&a, &err)) {
        fprintf(stderr, "vr-spectro: %s\n", err.message);
        rc = 1;
      } else {
        rc = CMDS[i].run(&a);
      }
    }
  if (rc < 0) {
    fprintf(stderr, "vr-spectro: expected a command: fit, metrics, btdf, bsdf-xml, chromogenic, thermal or state\n"
                    "Try 'vr-spectro --help'.\n");
    rc = 2;
  }
  vr_args_free(&a);
  return rc;
}
