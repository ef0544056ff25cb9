/* Importers: instrument and database files into materials. */
#ifndef VR_MATDB_IMPORT_H
#define VR_MATDB_IMPORT_H

#include "vr/material.h"
#include "vr/material_io.h"

/* A CSV table of spectra (vr_spectrum_table_read rules).  Columns named n
 * and k give n, k; T, Rf, Rb a glazing; anything else one role per column
 * ("value" if there is a single column). */
vr_status vr_csv_material_parse(const char *text, size_t len, const char *name, vr_material *m,
                                vr_error *err);

#endif
