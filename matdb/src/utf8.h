/* Text encodings at the edges of the database: every text in it is UTF-8,
 * and JSON output never carries an invalid byte sequence. */
#ifndef VR_MATDB_UTF8_H
#define VR_MATDB_UTF8_H

#include <stdbool.h>
#include <stddef.h>

/* Well-formed UTF-8 (RFC 3629: no overlong forms, no surrogates, nothing
 * past U+10FFFF)?  On false, *bad (if not NULL) is the offset of the first
 * byte of the first invalid sequence. */
bool vr_utf8_valid(const char *s, size_t n, size_t *bad);

/* Windows-1252 text as UTF-8 (malloc'ed, NUL-terminated, its length in
 * *out_len).  The five bytes that code page leaves undefined (0x81, 0x8D,
 * 0x8F, 0x90, 0x9D) become U+FFFD.  NULL when out of memory. */
char *vr_cp1252_to_utf8(const char *s, size_t n, size_t *out_len);

/* s with every invalid UTF-8 sequence replaced by U+FFFD (malloc'ed); NULL
 * when out of memory.  NULL in, NULL out. */
char *vr_utf8_sanitize(const char *s);

#endif
