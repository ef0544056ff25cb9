/* Printing materials and database entries for vr-matdb, as text or JSON. */
#ifndef VR_MATDB_PRINT_H
#define VR_MATDB_PRINT_H

#include <stdbool.h>
#include <stdio.h>
#include "vr/matdb.h"

/* A JSON string; an invalid UTF-8 sequence (a database row written before
 * texts were checked, a file name) becomes U+FFFD, so the output is always
 * valid JSON. */
void vr_print_json_text(FILE *f, const char *s);
void vr_print_material(FILE *f, const vr_material *m, bool json);
void vr_print_entry(FILE *f, const vr_matdb_entry *e, bool json, bool first);
/* CSV of a material's data: nm and one column per role (n, k for optical
 * constants) on the union of their grids; 17 significant digits. */
vr_status vr_export_csv(FILE *f, const vr_material *m, vr_error *err);

#endif
