/* Importers: instrument and database files into materials. */
#ifndef VR_MATDB_IMPORT_H
#define VR_MATDB_IMPORT_H

#include "vr/material.h"

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

/* Reads a file, picks the importer from its extension (.yml/.yaml:
 * refractiveindex.info; .dat: IGDB; .csv/.txt: CSV), and fills provenance
 * (source path, SHA-256 of the bytes, tool).  name NULL: the file's stem.
 * kind_override may be NULL. */
vr_status vr_import_file(const char *path, const char *name, const char *kind_override,
                         const char *tool, vr_material **out, vr_error *err);

#endif
