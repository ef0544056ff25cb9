/* refractiveindex.info YAML files (the database's own format) in and out. */
#ifndef VR_MATDB_RII_H
#define VR_MATDB_RII_H

#include <stdio.h>
#include "vr/material.h"

/* Parses the text of a refractiveindex.info YAML file into m, which the
 * caller created (name and kind set).  Fills m->n_formula (a "formula N"
 * block) or the "n" spectrum ("tabulated n" / "tabulated nk"), the "k"
 * spectrum ("tabulated k" / "tabulated nk"), m->prov.reference from
 * REFERENCES, m->description from COMMENTS, and one property per entry of
 * CONDITIONS / SPECS.  Wavelengths are converted from micrometres to nm.
 * Errors name the file (name), the line and the field. */
vr_status vr_rii_parse(const char *text, size_t len, const char *name, vr_material *m,
                       vr_error *err);

/* Writes m in the same format: REFERENCES, COMMENTS, then a formula block
 * (wavelength_range and coefficients) or a tabulated n / nk block, and a
 * tabulated k block, numbers with 17 significant digits so that a re-import
 * gives identical data. */
vr_status vr_rii_write(FILE *f, const vr_material *m, vr_error *err);

/* A wavelength token in micrometres (len characters at tok, at most 90) as
 * nm, by moving the decimal point in the text so the result is the double
 * nearest the decimal value.  0 on success, -1 not a number, -2 not finite.
 * Shared by the reader and the writer, which checks its output with it. */
int vr_rii_um_to_nm(const char *tok, size_t len, double *nm);

#endif
