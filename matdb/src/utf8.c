/* UTF-8 checks and the Windows-1252 conversion of IGDB files (utf8.h). */
#include "utf8.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* Length of the well-formed sequence at p (at most n bytes), 0 if none. */
static size_t sequence(const unsigned char *p, size_t n) {
  unsigned c = p[0];
  if (c < 0x80) return 1;
  size_t len;
  uint32_t cp, min;
  if (c >= 0xC2 && c <= 0xDF) len = 2, cp = c & 0x1F, min = 0x80;
  else if (c >= 0xE0 && c <= 0xEF) len = 3, cp = c & 0x0F, min = 0x800;
  else if (c >= 0xF0 && c <= 0xF4) len = 4, cp = c & 0x07, min = 0x10000;
  else return 0;
  if (len > n) return 0;
  for (size_t i = 1; i < len; i++) {
    if ((p[i] & 0xC0) != 0x80) return 0;
    cp = (cp << 6) | (p[i] & 0x3F);
  }
  if (cp < min || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return 0;
  return len;
}

bool vr_utf8_valid(const char *s, size_t n, size_t *bad) {
  const unsigned char *p = (const unsigned char *)s;
  for (size_t i = 0; i < n;) {
    size_t len = sequence(p + i, n - i);
    if (!len) {
      if (bad) *bad = i;
      return false;
    }
    i += len;
  }
  return true;
}

/* Windows-1252 0x80-0x9F (Unicode's "bestfit1252" table); 0xFFFD where the
 * code page defines nothing.  0xA0-0xFF are U+00A0-U+00FF. */
static const uint16_t CP1252_80[32] = {
    0x20AC, 0xFFFD, 0x201A, 0x0192, 0x201E, 0x2026, 0x2020, 0x2021, 0x02C6, 0x2030, 0x0160,
    0x2039, 0x0152, 0xFFFD, 0x017D, 0xFFFD, 0xFFFD, 0x2018, 0x2019, 0x201C, 0x201D, 0x2022,
    0x2013, 0x2014, 0x02DC, 0x2122, 0x0161, 0x203A, 0x0153, 0xFFFD, 0x017E, 0x0178};

static size_t put(char *o, uint32_t cp) {
  if (cp < 0x80) {
    o[0] = (char)cp;
    return 1;
  }
  if (cp < 0x800) {
    o[0] = (char)(0xC0 | (cp >> 6));
    o[1] = (char)(0x80 | (cp & 0x3F));
    return 2;
  }
  o[0] = (char)(0xE0 | (cp >> 12));
  o[1] = (char)(0x80 | ((cp >> 6) & 0x3F));
  o[2] = (char)(0x80 | (cp & 0x3F));
  return 3;
}

char *vr_cp1252_to_utf8(const char *s, size_t n, size_t *out_len) {
  char *o = malloc(3 * n + 1);
  if (!o) return NULL;
  size_t j = 0;
  for (size_t i = 0; i < n; i++) {
    unsigned char c = (unsigned char)s[i];
    j += put(o + j, c < 0x80 ? c : c < 0xA0 ? CP1252_80[c - 0x80] : c);
  }
  o[j] = '\0';
  if (out_len) *out_len = j;
  return o;
}

char *vr_utf8_sanitize(const char *s) {
  if (!s) return NULL;
  size_t n = strlen(s);
  char *o = malloc(3 * n + 1);
  if (!o) return NULL;
  const unsigned char *p = (const unsigned char *)s;
  size_t j = 0;
  for (size_t i = 0; i < n;) {
    size_t len = sequence(p + i, n - i);
    if (len) {
      memcpy(o + j, p + i, len);
      j += len;
      i += len;
    } else {
      j += put(o + j, 0xFFFD);
      i++;
    }
  }
  o[j] = '\0';
  return o;
}
