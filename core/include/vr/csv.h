/* A small delimited-text reader that remembers where every field came from.
 *
 * Instrument exports and hand-made tables are read through it so that every
 * complaint can name file, line and column.  Accepted: comma, semicolon, tab
 * or blank separated fields (detected from the first data line); '#' starts
 * a comment line; blank lines are skipped; CRLF and a UTF-8 BOM are fine;
 * double quotes protect separators ("a,b") and escape themselves (""). */
#ifndef VR_CSV_H
#define VR_CSV_H

#include <stddef.h>
#include <stdio.h>
#include "vr/error.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vr_csv vr_csv;

/* Reads and splits a whole file. */
vr_status vr_csv_read(const char *path, vr_csv **out, vr_error *err);
/* Splits text already in memory; name is used in messages. */
vr_status vr_csv_parse(const char *text, size_t len, const char *name,
                       vr_csv **out, vr_error *err);
void vr_csv_destroy(vr_csv *csv);

const char *vr_csv_name(const vr_csv *csv);
size_t vr_csv_rows(const vr_csv *csv);               /* non-comment, non-blank lines */
size_t vr_csv_cols(const vr_csv *csv, size_t row);
const char *vr_csv_field(const vr_csv *csv, size_t row, size_t col); /* NULL past the end */
long vr_csv_line(const vr_csv *csv, size_t row);      /* 1-based line in the file */
long vr_csv_col_pos(const vr_csv *csv, size_t row, size_t col); /* 1-based character column */

/* Number of '#' comment lines and their text (without the '#'). */
size_t vr_csv_comment_count(const vr_csv *csv);
const char *vr_csv_comment(const vr_csv *csv, size_t i);

/* Parses field (row, col) as a finite double.  field_name names the column in
 * messages: "file:line:col: field 'T': expected a number, got 'abc'". */
vr_status vr_csv_number(const vr_csv *csv, size_t row, size_t col,
                        const char *field_name, double *out, vr_error *err);

/* Index of the header column whose name matches (case-insensitive), or -1. */
long vr_csv_find_column(const vr_csv *csv, size_t header_row, const char *name);

/* Parses a whole string as a finite double (leading/trailing blanks allowed).
 * Returns 0 on success. */
int vr_parse_double(const char *s, double *out);
/* A comma-separated list of such numbers ("65,70,75"), at most max of
 * them; *n receives the count.  Returns 0 on success, non-zero for an empty
 * list, a bad number or more than max. */
int vr_parse_doubles(const char *s, double *out, size_t max, size_t *n);

/* Writes one field as RFC 4180 wants it: in double quotes, its own quotes
 * doubled, when it holds a comma, a quote or a line break; as is otherwise. */
void vr_csv_write_field(FILE *f, const char *s);

#ifdef __cplusplus
}
#endif
#endif
