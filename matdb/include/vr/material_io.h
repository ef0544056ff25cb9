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

#ifdef __cplusplus
}
#endif
#endif
