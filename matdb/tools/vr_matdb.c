/* vr-matdb: the command line of the material database.  Creates it, lists
 * and shows materials with their provenance, evaluates n, k or spectra at
 * wavelengths, imports refractiveindex.info YAML, IGDB .DAT and CSV files,
 * exports, shows version history, removes, and checks integrity. */
#include "import.h"
#include "rii.h"
#include "vr/args.h"
#include "vr/atomic_file.h"
#include "vr/csv.h"
#include "vr/json.h"
#include "vr/matdb.h"
#include "vr/out_guard.h"
#include "vr_matdb_print.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static const vr_option OPTIONS[] = {
    {"db", 'd', "FILE", "material database (default: $VR_MATDB unless empty, else ./materials.db)"},
    {"kind", 'k', "KIND", "list: only this kind; import: store as this kind"},
    {"name", 'n', "NAME", "import: store under this name (default: the file's stem)"},
    {"version", 'v', "N", "show/eval/export: this version (1, 2, ...) instead of the newest"},
    {"role", 'r', "ROLE", "eval: a tabulated role (value, T, Rf, ...) instead of n, k"},
    {"extrapolate", 0, NULL, "eval: hold end values outside the data range (with a warning)"},
    {"csv", 0, NULL, "export as CSV"},
    {"yaml", 0, NULL, "export as refractiveindex.info YAML (n, k materials)"},
    {"output", 'o', "FILE", "export: write to FILE (atomically; never the database) instead of stdout"},
    {"yes", 0, NULL, "rm: really remove every version"},
    {"json", 'j', NULL, "JSON output"},
};
#define NOPT (sizeof OPTIONS / sizeof OPTIONS[0])

static const char USAGE[] =
    "COMMAND [options] [ARGS]\n"
    "  vr-matdb init\n"
    "  vr-matdb list [--kind K] [--json]\n"
    "  vr-matdb show NAME [--version N] [--json]\n"
    "  vr-matdb eval NAME NM... [--version N] [--role R] [--extrapolate] [--json]\n"
    "  vr-matdb import FILE [--name N] [--kind K] [--json]\n"
    "  vr-matdb export NAME --csv|--yaml [-o FILE] [--version N]\n"
    "  vr-matdb history NAME [--json]\n"
    "  vr-matdb rm NAME --yes\n"
    "  vr-matdb check";
static const char ABOUT[] =
    "The material database all Virtuelium-C tools write to and the renderer reads from.\n"
    "import reads refractiveindex.info YAML (.yml), LBNL Optics / IGDB glazing files (.DAT)\n"
    "and CSV spectra (.csv: a wavelength column, then n and k, or T, Rf, Rb, or any named\n"
    "spectra).  Saving a name again adds a version; the newest is used unless --version.\n"
    "Wavelengths are in nm.  Evaluating outside a material's data range is an error unless\n"
    "--extrapolate is given.  Kinds: dielectric conductor layered reflectance btdf\n"
    "chromogenic illuminant camera glazing.\n"
    "A database whose file or folder cannot be written is opened read-only: every command\n"
    "but import and rm works; those say the database is read-only.  A file that is not a\n"
    "material database is refused and left untouched.  export -o never writes over the\n"
    "database or its journals.  IGDB files in Windows-1252 are converted to UTF-8.  Options\n"
    "that do not apply to a command are refused.";

typedef struct ctx {
  vr_args *a;
  vr_matdb *db;
  vr_error err;
  bool json;
  int version; /* --version, 0 for the newest */
} ctx;

static int fail(ctx *c) {
  fprintf(stderr, "vr-matdb: %s\n", c->err.message);
  return 1;
}

/* --version N: 1, 2, ...; absent: 0, the newest.  A usage error (exit 2). */
static int version_option(ctx *c, int *version) {
  const char *text = vr_args_get(c->a, "version");
  double v = 0;
  *version = 0;
  if (!text) return 0;
  if (vr_parse_double(text, &v) || v < 1 || v != floor(v) || v > INT_MAX) {
    fprintf(stderr, "vr-matdb: option --version: '%s' is not a version number (1, 2, ...)\n"
                    "Try 'vr-matdb --help'.\n", text);
    return 2;
  }
  *version = (int)v;
  return 0;
}

typedef struct list_state { FILE *f; bool json; int count; } list_state;
static int list_visit(const vr_matdb_entry *e, void *user) {
  list_state *s = user;
  vr_print_entry(s->f, e, s->json, s->count == 0);
  s->count++;
  return 0;
}

static int cmd_list(ctx *c, bool history) {
  list_state s = {stdout, c->json, 0};
  if (c->json) fputs("[\n", stdout);
  vr_status st = history ? vr_matdb_history(c->db, c->a->operands[1], list_visit, &s, &c->err)
                         : vr_matdb_list(c->db, vr_args_get(c->a, "kind"), list_visit, &s, &c->err);
  if (c->json) fputs("\n]\n", stdout);
  if (st) return fail(c);
  if (!c->json) fprintf(stderr, "%d material%s in %s\n", s.count, s.count == 1 ? "" : "s", vr_matdb_path(c->db));
  return 0;
}

static int cmd_show(ctx *c) {
  vr_material *m;
  if (vr_matdb_load(c->db, c->a->operands[1], c->version, &m, &c->err)) return fail(c);
  vr_print_material(stdout, m, c->json);
  vr_material_destroy(m);
  return 0;
}

static int cmd_eval(ctx *c) {
  vr_material *m;
  if (vr_matdb_load(c->db, c->a->operands[1], c->version, &m, &c->err)) return fail(c);
  const char *role = vr_args_get(c->a, "role");
  int rc = 0;
  bool allow = vr_args_flag(c->a, "extrapolate");
  bool nk = !role && (m->n_formula.type || vr_material_spectrum(m, "n"));
  if (!role && !nk) role = m->nspectra ? m->spectra[0].role : "value";
  size_t count = c->a->noperands - 2;
  double *wl = malloc((count ? count : 1) * sizeof *wl), *v1 = malloc((count ? count : 1) * sizeof *v1),
         *v2 = malloc((count ? count : 1) * sizeof *v2);
  for (size_t i = 0; i < count && !rc; i++) {
    const char *arg = c->a->operands[2 + i];
    if (vr_parse_double(arg, &wl[i]) || wl[i] <= 0) {
      vr_error_set(&c->err, VR_E_ARG, "wavelength '%s' is not a positive number of nm", arg);
      rc = fail(c);
      break;
    }
    bool extrap = false;
    vr_status st = nk ? vr_material_nk(m, wl[i], allow, &v1[i], &v2[i], &extrap, &c->err)
                      : vr_material_eval(m, role, wl[i], allow, &v1[i], &extrap, &c->err);
    if (st) rc = fail(c);
    else if (extrap)
      fprintf(stderr, "vr-matdb: warning: %g nm is outside the data of '%s'; end value held\n", wl[i], m->name);
  }
  if (!rc) {
    if (c->json) {
      fputs("{\"name\": ", stdout);
      vr_print_json_text(stdout, m->name);
      printf(", \"version\": %d, \"values\": [", m->version);
      for (size_t i = 0; i < count; i++) {
        printf("%s{\"wavelength_nm\": ", i ? ", " : "");
        vr_json_number(stdout, wl[i]);
        if (nk) {
          fputs(", \"n\": ", stdout);
          vr_json_number(stdout, v1[i]);
          fputs(", \"k\": ", stdout);
          vr_json_number(stdout, v2[i]);
        } else {
          fputs(", ", stdout);
          vr_print_json_text(stdout, role);
          fputs(": ", stdout);
          vr_json_number(stdout, v1[i]);
        }
        fputc('}', stdout);
      }
      fputs("]}\n", stdout);
    } else {
      printf(nk ? "%-12s %-12s %s\n" : "%-12s %s\n", "nm", nk ? "n" : role, "k");
      for (size_t i = 0; i < count; i++) {
        if (nk) printf("%-12.6g %-12.8g %.8g\n", wl[i], v1[i], v2[i]);
        else printf("%-12.6g %.8g\n", wl[i], v1[i]);
      }
    }
  }
  free(wl);
  free(v1);
  free(v2);
  vr_material_destroy(m);
  return rc;
}

static int cmd_import(ctx *c) {
  vr_material *m;
  if (vr_import_file(c->a->operands[1], vr_args_get(c->a, "name"), vr_args_get(c->a, "kind"),
                     "vr-matdb import", &m, &c->err))
    return fail(c);
  vr_status st = vr_matdb_save(c->db, m, &c->err);
  if (st) {
    vr_material_destroy(m);
    return fail(c);
  }
  if (c->json) {
    fputs("{\"name\": ", stdout);
    vr_print_json_text(stdout, m->name);
    printf(", \"version\": %d, \"kind\": \"%s\", \"sha256\": \"%s\"}\n", m->version, vr_kind_name(m->kind),
           m->prov.sha256);
  } else {
    printf("imported %s as '%s' version %d (%s)\n", c->a->operands[1], m->name, m->version,
           vr_kind_name(m->kind));
  }
  vr_material_destroy(m);
  return 0;
}

static int cmd_export(ctx *c) {
  bool csv = vr_args_flag(c->a, "csv");
  vr_material *m;
  if (vr_matdb_load(c->db, c->a->operands[1], c->version, &m, &c->err)) return fail(c);
  const char *out = vr_args_get(c->a, "output");
  if (out && !strcmp(out, "-")) out = NULL; /* standard output */
  vr_atomic_file af = {0};
  FILE *f = stdout;
  vr_status st = VR_OK;
  if (out) {
    if ((st = vr_atomic_file_open(&af, out, &c->err))) goto done;
    f = af.fp;
  }
  st = csv ? vr_export_csv(f, m, &c->err) : vr_rii_write(f, m, &c->err);
  if (out) {
    if (st) vr_atomic_file_abort(&af);
    else st = vr_atomic_file_commit(&af, &c->err);
  }
done:
  vr_material_destroy(m);
  return st ? fail(c) : 0;
}

static int cmd_rm(ctx *c) {
  if (!vr_args_flag(c->a, "yes")) {
    fprintf(stderr, "vr-matdb: rm removes every version of '%s'; add --yes to confirm\n", c->a->operands[1]);
    return 2;
  }
  int n;
  if (vr_matdb_remove(c->db, c->a->operands[1], &n, &c->err)) return fail(c);
  printf("removed '%s' (%d version%s)\n", c->a->operands[1], n, n == 1 ? "" : "s");
  return 0;
}

static int cmd_check(ctx *c) {
  bool ok;
  char report[4096];
  if (vr_matdb_check(c->db, &ok, report, sizeof report, &c->err)) return fail(c);
  printf("%s: %s", vr_matdb_path(c->db), ok ? "ok\n" : report);
  return ok ? 0 : 1;
}

/* Which options each command takes; any other is refused rather than
 * silently ignored.  --db goes with every command. */
static const struct command {
  const char *name;
  size_t min_operands, max_operands; /* counting the command; 0: no limit */
  const char *need;
  const char *options; /* space-separated */
} CMDS[] = {
    {"init", 1, 1, "", ""},
    {"list", 1, 1, "", "kind json"},
    {"check", 1, 1, "", ""},
    {"show", 2, 2, "show needs a material name", "version json"},
    {"eval", 3, 0, "eval needs a material name and wavelengths", "version role extrapolate json"},
    {"import", 2, 2, "import needs a file", "name kind json"},
    {"export", 2, 2, "export needs a material name", "version csv yaml output"},
    {"history", 2, 2, "history needs a material name", "json"},
    {"rm", 2, 2, "rm needs a material name", "yes"},
};

static bool takes(const struct command *k, const char *option) {
  size_t n = strlen(option);
  for (const char *p = k->options; (p = strstr(p, option)); p += n)
    if ((p == k->options || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  return false;
}

static int usage(const char *fmt, const char *a, const char *b) {
  fprintf(stderr, "vr-matdb: ");
  fprintf(stderr, fmt, a, b);
  fprintf(stderr, "\nTry 'vr-matdb --help'.\n");
  return 2;
}

/* Everything that can be told from the command line alone, before any file
 * is opened: exit 2 with a message, or 0. */
static int check_command_line(ctx *c, const struct command *k) {
  vr_args *a = c->a;
  for (size_t i = 0; i < NOPT; i++)
    if (a->values[i] && strcmp(OPTIONS[i].name, "db") && !takes(k, OPTIONS[i].name))
      return usage("option --%s does not apply to '%s'", OPTIONS[i].name, k->name);
  if (a->noperands < k->min_operands) return usage("%s%s", k->need, "");
  if (k->max_operands && a->noperands > k->max_operands)
    return usage("unexpected argument '%s' after '%s'", a->operands[k->max_operands], k->name);
  if (!strcmp(k->name, "export") && vr_args_flag(a, "csv") == vr_args_flag(a, "yaml"))
    return usage("export needs exactly one of --csv and --yaml%s%s", "", "");
  return version_option(c, &c->version);
}

int main(int argc, char **argv) {
  vr_args a;
  vr_args_outcome o = vr_args_parse(&a, "vr-matdb", USAGE, ABOUT, OPTIONS, NOPT, argc, argv);
  if (o == VR_ARGS_EXIT_OK) return 0;
  if (o == VR_ARGS_EXIT_USAGE) return 2;
  ctx c = {.a = &a, .json = vr_args_flag(&a, "json")};
  int rc;
  const char *cmd = a.noperands ? a.operands[0] : NULL;
  size_t k = 0, ncmds = sizeof CMDS / sizeof CMDS[0];
  while (cmd && k < ncmds && strcmp(cmd, CMDS[k].name)) k++;
  if (!cmd || k == ncmds) {
    fprintf(stderr, cmd ? "vr-matdb: unknown command '%s'\nTry 'vr-matdb --help'.\n"
                        : "vr-matdb: no command given%s\nTry 'vr-matdb --help'.\n", cmd ? cmd : "");
    vr_args_free(&a);
    return 2;
  }
  if ((rc = check_command_line(&c, &CMDS[k]))) {
    vr_args_free(&a);
    return rc;
  }
  const char *path = vr_args_get(&a, "db");
  const char *db_path = path ? path : vr_matdb_default_path();
  /* Outputs never replace an input of the run: the database (and its
   * journals) and the imported file; checked before any work. */
  vr_out_guard guard;
  vr_out_guard_init(&guard);
  vr_out_guard_database(&guard, db_path);
  if (!strcmp(cmd, "import")) vr_out_guard_input(&guard, a.operands[1], "the imported file");
  const char *out = vr_args_get(&a, "output");
  if (out && vr_out_guard_check(&guard, out, "-o", &c.err)) {
    rc = fail(&c);
    vr_args_free(&a);
    return rc;
  }
  bool writes = !strcmp(cmd, "init") || !strcmp(cmd, "import") || !strcmp(cmd, "rm");
  /* Readers open read-only so they never change a database by accident, but
   * a missing or 0-byte database is created (and seeded) on first use.  The
   * library opens a database it cannot write read-only by itself. */
  int flags = writes ? 0 : VR_MATDB_READONLY;
  struct stat sb;
  if (!writes && (stat(db_path, &sb) != 0 || sb.st_size == 0)) flags = 0;
  /* A reader never creates the database a --db names (a mistyped path). */
  if (!writes) flags |= VR_MATDB_MUST_EXIST;
  if (vr_matdb_open(path, flags, &c.db, &c.err)) {
    rc = fail(&c);
    vr_args_free(&a);
    return rc;
  }
  if (writes && strcmp(cmd, "init") && vr_matdb_require_writable(c.db, &c.err)) {
    rc = fail(&c);
  } else if (!strcmp(cmd, "init")) {
    const char *ro = vr_matdb_readonly(c.db);
    printf("%s: material database ready (schema %d%s%s)\n", vr_matdb_path(c.db), VR_MATDB_SCHEMA_VERSION,
           ro ? "; read-only: " : "", ro ? ro : "");
    rc = 0;
  } else if (!strcmp(cmd, "list")) rc = cmd_list(&c, false);
  else if (!strcmp(cmd, "history")) rc = cmd_list(&c, true);
  else if (!strcmp(cmd, "show")) rc = cmd_show(&c);
  else if (!strcmp(cmd, "eval")) rc = cmd_eval(&c);
  else if (!strcmp(cmd, "import")) rc = cmd_import(&c);
  else if (!strcmp(cmd, "export")) rc = cmd_export(&c);
  else if (!strcmp(cmd, "rm")) rc = cmd_rm(&c);
  else rc = cmd_check(&c);
  vr_matdb_close(c.db);
  vr_args_free(&a);
  return rc;
}
