/* vr-spectro's commands and what they share: options, resolving a pane
 * given as a file or a database name, saving with provenance. */
#ifndef VR_SPECTRO_CLI_H
#define VR_SPECTRO_CLI_H

#include <stdbool.h>

#include "vr/args.h"
#include "vr/glazing.h"
#include "vr/glazing_en673.h"
#include "vr/glazing_thermal.h"
#include "vr/optical_standard.h"
#include "vr/matdb.h"
#include "vr/spectro_data.h"

/* "vr-spectro: message" on stderr; returns spectro_exit(e). */
int spectro_fail(const vr_error *e);
/* 2 for an option's value outside its domain (VR_E_RANGE with a message
 * naming the option, "--charge ..."), else 1. */
int spectro_exit(const vr_error *e);

/* The material database this run uses: --db, else $VR_MATDB, else
 * ./materials.db (the resolution of vr_matdb_open). */
const char *spectro_db_path(const vr_args *a);

/* The database named by --db (or the default), opened once on demand. */
vr_status spectro_db(const vr_args *a, vr_matdb **db, vr_error *err);

/* A pane from a spectrophotometer file (CSV or IGDB .DAT) if the path
 * exists, else from the database: a glazing material, a chromogenic one at
 * --state/--charge/--uv (bleached by default), or a dielectric with
 * --thickness (its exact slab at normal incidence, 300-2500 nm every 5 nm).
 * thickness_nm: the file's or material's thickness, else --thickness, else
 * NAN. */
vr_status spectro_pane_source(const vr_args *a, const char *item, vr_matdb **db,
                              vr_spectro_data **out, vr_error *err);

/* --thickness in mm as nm (NAN when absent); VR_E_ARG for a bad value. */
vr_status spectro_thickness(const vr_args *a, double *nm, vr_error *err);

/* Fills the provenance of m (source file and its SHA-256 when path is a
 * file, tool "vr-spectro CMD", version) and saves it. */
vr_status spectro_save(vr_matdb *db, vr_material *m, const char *cmd, const char *path,
                       vr_error *err);

#define SPECTRO_MAX_PANES 16

/* --route auto|physical|coated. */
vr_status spectro_parse_route(const vr_args *a, vr_angular_route *r, vr_error *err);
/* The panes a command names: --panes A,B (split in *list, which the caller
 * frees) or its one operand. */
vr_status spectro_pane_items(const vr_args *a, char **list, char **items, size_t *n, vr_error *err);
/* The figures of the panes data[0..n) (outside first) at angle (degrees),
 * by route; unsolved[i] gains pane i's wavelengths that fit no slab. */
vr_status spectro_panes_metrics(const vr_standard *std, vr_spectro_data *const *data, char **items,
                                size_t n, double angle, vr_angular_route route,
                                vr_glazing_metrics *m, const char **used_route, size_t *unsolved,
                                vr_error *err);

/* The normal-incidence curve of a source (item names it in messages);
 * a file of several tint states is refused (use chromogenic, then the
 * model at --state). */
vr_status spectro_normal_curve(const vr_spectro_data *d, const char *item,
                               const vr_spectro_curve **c, vr_error *err);

/* --wavelengths FROM:TO:STEP (default 300:2500:10 nm) as a grid the caller
 * frees. */
vr_status spectro_wavelengths(const vr_args *a, double **nm, size_t *n, vr_error *err);

/* A path vr-spectro reads as BSDF XML (.xml or .xml.gz, any case). */
bool spectro_is_bsdf_xml(const char *path);
/* metrics of a BSDF XML file: WINDOW's figures at --angle/--phi. */
int spectro_metrics_bsdf_xml(vr_args *a, const char *path);

int spectro_cmd_fit(vr_args *a);
int spectro_cmd_bsdf_xml(vr_args *a);
int spectro_cmd_metrics(vr_args *a);
int spectro_cmd_btdf(vr_args *a);
int spectro_cmd_chromogenic(vr_args *a);
int spectro_cmd_state(vr_args *a);
int spectro_cmd_thermal(vr_args *a);

/* thermal --method en673 (spectro_cmd_en673.c): --edition, and the report
 * of EN 673's U and EN 410's g for the system sys (emissivities already
 * corrected, from[i] saying where each came from), tau_e its solar
 * transmittance under std_name. */
vr_status spectro_en673_parse_edition(const char *s, vr_en673_edition *e, vr_error *err);
vr_status spectro_en673_report(const vr_thermal_system *sys, char **items,
                               const char *const (*from)[2], const char *std_name, double tau_e,
                               vr_en673_edition edition, bool json, vr_error *err);

/* The state of a chromogenic material asked for by --state S, --charge Q
 * or --uv E [--temperature T]; 0 (bleached) when none is given. */
vr_status spectro_state_of(const vr_args *a, const vr_material *m, double *s, vr_error *err);

#endif
