/* Shared pieces of the ellipsometry readers: the reader table's entry
 * type, each format's sniff and parse, and the helpers they share. */
#ifndef VR_ELLIPSO_READ_H
#define VR_ELLIPSO_READ_H

#include "vr/ellipso_data.h"

/* A reader of ellipso_data.c's table: sniff says whether text (len bytes,
 * not NUL-terminated) is in its format, parse reads it (o is never NULL).
 * name is for people reading the table; a NULL sniff marks the fallback. */
typedef struct vr_ellipso_reader {
  const char *name;
  int (*sniff)(const char *text, size_t len);
  vr_status (*parse)(const char *text, size_t len, const char *name,
                     const vr_ellipso_read_options *o, vr_ellipso_data *out, vr_error *err);
} vr_ellipso_reader;

/* The sniffs, each beside its reader. */
int vr_ellipso_sniff_woollam(const char *text, size_t len);
int vr_ellipso_sniff_accurion(const char *text, size_t len);
int vr_ellipso_sniff_filmsense(const char *text, size_t len);

/* The readers; o is never NULL. */
vr_status vr_ellipso_parse_csv(const char *text, size_t len, const char *name,
                               const vr_ellipso_read_options *o, vr_ellipso_data *out,
                               vr_error *err);
vr_status vr_ellipso_parse_woollam(const char *text, size_t len, const char *name,
                                   const vr_ellipso_read_options *o, vr_ellipso_data *out,
                                   vr_error *err);
vr_status vr_ellipso_parse_accurion(const char *text, size_t len, const char *name,
                                    const vr_ellipso_read_options *o, vr_ellipso_data *out,
                                    vr_error *err);
vr_status vr_ellipso_parse_filmsense(const char *text, size_t len, const char *name,
                                     const vr_ellipso_read_options *o, vr_ellipso_data *out,
                                     vr_error *err);
/* Splits s at tabs in place (empty fields kept); returns the count, at
 * most max (the last field then holds the rest of the line). */
size_t vr_ellipso_split_tabs(char *s, char **tok, size_t max);
/* A new point with the fields a file may leave out set to "not given". */
void vr_ellipso_point_init(vr_ellipso_point *p);
/* Counts a skipped row of type tag. */
void vr_ellipso_note_skipped(vr_ellipso_data *d, const char *tag);
/* Converts the wavelength w given in unit to nm, normalises Δ and checks
 * the point's domain (0 < AOI < 90, 0 <= Ψ <= 90, σ > 0), naming the line. */
vr_status vr_ellipso_point_finish(vr_ellipso_point *p, double w, const char *unit,
                                  const char *name, vr_error *err);
/* w in unit ("nm", "um", "A", "eV") as nm; NAN for an unknown unit. */
double vr_ellipso_to_nm(double w, const char *unit);
#endif
