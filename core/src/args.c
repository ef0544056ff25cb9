/* Command-line parsing shared by the tools: see vr/args.h. */
#include "vr/args.h"

#include <math.h>
#include "vr/csv.h"
#include "vr_version.h"

#include <stdlib.h>
#include <string.h>

const char *vr_version(void) { return VR_VERSION_STRING; }

void vr_args_print_version(FILE *f, const char *tool) {
  fprintf(f, "%s (Virtuelium-C) %s\n", tool, VR_VERSION_STRING);
}

static bool declares(const vr_option *opts, size_t nopts, const char *name) {
  for (size_t i = 0; i < nopts; i++)
    if (!strcmp(opts[i].name, name)) return true;
  return false;
}

void vr_args_print_help(FILE *f, const char *tool, const char *usage, const char *about,
                        const vr_option *opts, size_t nopts) {
  fprintf(f, "Usage: %s %s\n", tool, usage);
  if (about && *about) fprintf(f, "\n%s\n", about);
  fprintf(f, "\nOptions:\n");
  for (size_t i = 0; i < nopts; i++) {
    char left[96];
    if (opts[i].short_name)
      snprintf(left, sizeof left, "-%c, --%s%s%s", opts[i].short_name, opts[i].name,
               opts[i].arg ? " " : "", opts[i].arg ? opts[i].arg : "");
    else
      snprintf(left, sizeof left, "    --%s%s%s", opts[i].name, opts[i].arg ? " " : "",
               opts[i].arg ? opts[i].arg : "");
    fprintf(f, "  %-30s %s\n", left, opts[i].help);
  }
  fprintf(f, "  %-30s %s\n", "-h, --help", "show this help and exit");
  fprintf(f, "  %-30s %s\n", "    --version",
          declares(opts, nopts, "version") ? "alone: show the program version and exit"
                                           : "show the version and exit");
}

static vr_args_outcome usage_error(vr_args *a, const char *fmt, const char *what) {
  fprintf(stderr, "%s: ", a->tool);
  fprintf(stderr, fmt, what);
  fprintf(stderr, "\nTry '%s --help' for more information.\n", a->tool);
  vr_args_free(a);
  return VR_ARGS_EXIT_USAGE;
}

vr_args_outcome vr_args_parse(vr_args *a, const char *tool, const char *usage, const char *about,
                              const vr_option *opts, size_t nopts, int argc, char **argv) {
  memset(a, 0, sizeof *a);
  vr_stdout_check_at_exit(tool);
  a->tool = tool;
  a->options = opts;
  a->noptions = nopts;
  a->values = calloc(nopts ? nopts : 1, sizeof(char *));
  a->operands = calloc(argc > 0 ? (size_t)argc : 1, sizeof(char *));
  if (!a->values || !a->operands) {
    fprintf(stderr, "%s: out of memory\n", tool);
    vr_args_free(a);
    return VR_ARGS_EXIT_USAGE;
  }
  int only_operands = 0;
  for (int i = 1; i < argc; i++) {
    const char *s = argv[i];
    if (only_operands || s[0] != '-' || s[1] == '\0') {
      a->operands[a->noperands++] = s;
      continue;
    }
    if (!strcmp(s, "--")) {
      only_operands = 1;
      continue;
    }
    if (!strcmp(s, "--help") || !strcmp(s, "-h")) {
      vr_args_print_help(stdout, tool, usage, about, opts, nopts);
      vr_args_free(a);
      return VR_ARGS_EXIT_OK;
    }
    /* A tool with its own --version option (vr-matdb: a material's version)
     * gets it; --version alone still prints the program's version. */
    if (!strcmp(s, "--version") && !(argc > 2 && declares(opts, nopts, "version"))) {
      vr_args_print_version(stdout, tool);
      vr_args_free(a);
      return VR_ARGS_EXIT_OK;
    }
    size_t k = nopts;
    const char *inline_value = NULL;
    if (s[1] == '-') {
      const char *name = s + 2, *eq = strchr(name, '=');
      size_t len = eq ? (size_t)(eq - name) : strlen(name);
      for (k = 0; k < nopts; k++)
        if (strlen(opts[k].name) == len && !strncmp(opts[k].name, name, len)) break;
      if (eq) inline_value = eq + 1;
    } else if (s[2] == '\0') {
      for (k = 0; k < nopts; k++)
        if (opts[k].short_name == s[1]) break;
    }
    if (k == nopts) {
      /* A negative number is an operand, not an option. */
      double d;
      if (vr_parse_double(s, &d) == 0) {
        a->operands[a->noperands++] = s;
        continue;
      }
      return usage_error(a, "unknown option '%s'", s);
    }
    if (!opts[k].arg) {
      if (inline_value) return usage_error(a, "option '%s' takes no value", s);
      a->values[k] = "";
      continue;
    }
    if (inline_value) {
      a->values[k] = inline_value;
    } else {
      if (i + 1 >= argc) return usage_error(a, "option '%s' needs a value", s);
      a->values[k] = argv[++i];
    }
  }
  /* No option takes an empty value: '' is a slip of the command line (an
   * unset shell variable), refused here, in every tool, as a usage error. */
  for (size_t k = 0; k < nopts; k++) {
    if (!opts[k].arg || strstr(opts[k].arg, "''") || !a->values[k] || a->values[k][0]) continue;
    if (!strcmp(opts[k].name, "db"))
      return usage_error(a, "%s: the material database path is empty: give --db a file name "
                            "(without --db: $VR_MATDB, else ./materials.db)", "--db ''");
    char what[96];
    snprintf(what, sizeof what, "--%s ''", opts[k].name);
    return usage_error(a, "%s: the value is empty (an unset shell variable?)", what);
  }
  return VR_ARGS_RUN;
}

void vr_args_free(vr_args *a) {
  free(a->values);
  free(a->operands);
  a->values = NULL;
  a->operands = NULL;
  a->noperands = 0;
}

static long find(const vr_args *a, const char *name) {
  for (size_t k = 0; k < a->noptions; k++)
    if (!strcmp(a->options[k].name, name)) return (long)k;
  return -1;
}

const char *vr_args_get(const vr_args *a, const char *name) {
  long k = find(a, name);
  return k < 0 ? NULL : a->values[k];
}

bool vr_args_flag(const vr_args *a, const char *name) { return vr_args_get(a, name) != NULL; }

vr_status vr_args_double(const vr_args *a, const char *name, double fallback, double *out,
                         vr_error *err) {
  const char *v = vr_args_get(a, name);
  if (!v) {
    *out = fallback;
    return VR_OK;
  }
  if (vr_parse_double(v, out))
    return vr_error_set(err, VR_E_ARG, "option --%s: '%s' is not a finite number", name, v);
  return VR_OK;
}

bool vr_parse_size(const char *text, size_t *out) {
  if (!text || !*text) return false;
  char *end;
  double v = strtod(text, &end);
  if (end == text || !isfinite(v) || !(v > 0)) return false;
  double unit = 1;
  switch (*end) {
  case 'k': case 'K': unit = 1024.0, end++; break;
  case 'm': case 'M': unit = 1024.0 * 1024, end++; break;
  case 'g': case 'G': unit = 1024.0 * 1024 * 1024, end++; break;
  case 't': case 'T': unit = 1024.0 * 1024 * 1024 * 1024, end++; break;
  default: break;
  }
  if (unit > 1 && (*end == 'i' || *end == 'I')) end++;
  if (*end == 'b' || *end == 'B') end++;
  if (*end) return false;
  double bytes = v * unit;
  if (!(bytes >= 1) || bytes >= 9.2e18) return false;
  *out = (size_t)bytes;
  return true;
}

vr_status vr_args_size(const vr_args *a, const char *name, size_t fallback, size_t *out,
                       vr_error *err) {
  const char *v = vr_args_get(a, name);
  if (!v) {
    *out = fallback;
    return VR_OK;
  }
  if (!vr_parse_size(v, out))
    return vr_error_set(err, VR_E_ARG,
                        "option --%s: '%s' is not a size (a positive number of bytes, or with K, "
                        "M, G or T: 512M, 2G)",
                        name, v);
  return VR_OK;
}
