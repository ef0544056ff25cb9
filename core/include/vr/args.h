/* One command-line style for every tool: GNU long options (--name VALUE or
 * --name=VALUE), optional one-letter aliases, "--" to end options, options
 * and operands in any order, and --help / --version handled the same way
 * everywhere (a tool that declares its own "version" option receives
 * --version N; --version alone still prints the program version).  Usage
 * errors print "tool: message" and a hint to stderr. */
#ifndef VR_ARGS_H
#define VR_ARGS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include "vr/error.h"
#include "vr/version.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vr_option {
  const char *name;   /* long name without the dashes */
  char short_name;    /* 0 for none */
  const char *arg;    /* metavar ("FILE") if it takes a value, NULL for a flag;
                         an empty value is a usage error unless the metavar
                         shows it ("P|''") */
  const char *help;   /* one line */
} vr_option;

typedef struct vr_args {
  const char *tool;
  const vr_option *options;
  size_t noptions;
  const char **values;      /* per option: its value, "" for a set flag, NULL if absent */
  const char **operands;    /* non-option arguments in order */
  size_t noperands;
} vr_args;

typedef enum vr_args_outcome {
  VR_ARGS_RUN = 0,      /* parsed; run the tool */
  VR_ARGS_EXIT_OK,      /* --help or --version was printed: exit 0 */
  VR_ARGS_EXIT_USAGE    /* a usage error was printed: exit 2 */
} vr_args_outcome;

/* usage: the synopsis lines after the tool name ("fit DATA [options]");
 * about: a paragraph printed under it by --help.  It also arranges for
 * standard output to be checked at exit (vr_stdout_check_at_exit). */
vr_args_outcome vr_args_parse(vr_args *a, const char *tool, const char *usage, const char *about,
                              const vr_option *opts, size_t nopts, int argc, char **argv);
void vr_args_free(vr_args *a);
/* At exit, standard output is flushed and checked: when a write to it
 * failed, "TOOL: cannot write standard output: REASON" goes to stderr and
 * the process ends with status 1 whatever main returned (once per
 * process; vr_args_parse calls it). */
void vr_stdout_check_at_exit(const char *tool);

const char *vr_args_get(const vr_args *a, const char *name); /* NULL if absent */
bool vr_args_flag(const vr_args *a, const char *name);
/* Parses an option's value as a finite number; absent -> *out = fallback. */
vr_status vr_args_double(const vr_args *a, const char *name, double fallback, double *out,
                         vr_error *err);

/* Parses an option's value as a size in bytes: a number with an optional
 * binary unit K, M, G or T (also KB/KiB, ...; any case): "512M" is 512 x
 * 2^20 bytes, "1.5G" 1.5 x 2^30, "4096" 4096.  Absent -> *out = fallback.
 * VR_E_ARG naming the option for anything else, for 0 and below, and past
 * 2^63 bytes. */
vr_status vr_args_size(const vr_args *a, const char *name, size_t fallback, size_t *out,
                       vr_error *err);
/* The same on a string; false on a bad size. */
bool vr_parse_size(const char *text, size_t *out);

void vr_args_print_help(FILE *f, const char *tool, const char *usage, const char *about,
                        const vr_option *opts, size_t nopts);
/* "tool (Virtuelium-C) 0.1.0" */
void vr_args_print_version(FILE *f, const char *tool);


#ifdef __cplusplus
}
#endif
#endif
