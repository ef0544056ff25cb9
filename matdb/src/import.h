/* Importers: instrument and database files into materials. */
#ifndef VR_MATDB_IMPORT_H
#define VR_MATDB_IMPORT_H

#include "vr/material.h"
#include "vr/material_io.h"

/* LBNL Optics / IGDB ".DAT" glazing file: brace header lines ("{ Thickness }
 * 3.048", "{ Product Name: ... }") and rows "lambda(um) T Rf Rb".  Gives a
 * glazing material with spectra T, Rf, Rb (nm) and every header field as a
 * property. */
vr_status vr_igdb_parse(const char *text, size_t len, const char *name, vr_material *m,
                        vr_error *err);

/* A CSV table of spectra (vr_spectrum_table_read rules).  Columns named n
 * and k give n, k; T, Rf, Rb a glazing; anything else one role per column
 * ("value" if there is a single column). */
vr_status vr_csv_material_parse(const char *text, size_t len, const char *name, vr_material *m,
                                vr_error *err);

#endif
