/* Reading a material straight from a file, without a database: the
 * importers of vr-matdb (refractiveindex.info .yml, IGDB .DAT, CSV) for tools
 * that take a material file as input. */
#ifndef VR_MATERIAL_IO_H
#define VR_MATERIAL_IO_H

#include "vr/material.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Picks the importer from the extension (.yml/.yaml, .dat, .csv/.txt),
 * fills provenance (source path, SHA-256 of the bytes, tool).  name NULL:
 * the file's stem.  kind_override may be NULL. */
vr_status vr_import_file(const char *path, const char *name, const char *kind_override,
                         const char *tool, vr_material **out, vr_error *err);

/* LBNL Optics file (IGDB ".DAT", Optics 5 ".LOF": the same layout): brace
 * header lines ("{ Thickness } 3.048", "{ Product Name: ... }") and rows
 * "lambda T Rf Rb" (micrometres unless "{ Units, Wavelength Units }" says
 * Nanometers), at least 3 of them, wavelengths increasing.  Fills m with
 * spectra T, Rf, Rb (nm) and every header field as a property; text that is
 * not UTF-8 is read as Windows-1252.  Errors name the file, line and field. */
vr_status vr_igdb_parse(const char *text, size_t len, const char *name, vr_material *m,
                        vr_error *err);

#ifdef __cplusplus
}
#endif
#endif
