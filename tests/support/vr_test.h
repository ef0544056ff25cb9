/* Shared helpers for the cmocka tests: includes in the order cmocka needs,
 * a tolerance assertion that prints both numbers, and temporary files. */
#ifndef VR_TEST_H
#define VR_TEST_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* |actual - expected| <= tol, with both values in the failure message. */
#define assert_near(actual, expected, tol)                                                   \
  do {                                                                                       \
    double a_ = (actual), e_ = (expected), t_ = (tol);                                       \
    if (!(fabs(a_ - e_) <= t_))                                                              \
      fail_msg("%s = %.15g, expected %.15g within %.3g (off by %.3g)", #actual, a_, e_, t_,  \
               fabs(a_ - e_));                                                               \
  } while (0)

/* Relative tolerance. */
#define assert_rel(actual, expected, rtol)                                                   \
  do {                                                                                       \
    double a_ = (actual), e_ = (expected), t_ = (rtol) * fabs(e_);                           \
    if (!(fabs(a_ - e_) <= t_))                                                              \
      fail_msg("%s = %.15g, expected %.15g within relative %.3g (off by %.3g)", #actual, a_, \
               e_, (double)(rtol), fabs(a_ - e_) / fabs(e_));                                \
  } while (0)

#define assert_contains(haystack, needle)                                                    \
  do {                                                                                       \
    const char *h_ = (haystack), *n_ = (needle);                                             \
    if (!strstr(h_, n_)) fail_msg("'%s' does not contain '%s'", h_, n_);                     \
  } while (0)

/* Writes text to a new temporary file; returns its path (static buffer
 * rotation of 8 names, enough for one test). */
static inline const char *vr_test_file(const char *text) {
  static char names[8][64];
  static int next;
  char *name = names[next++ % 8];
  snprintf(name, 64, "/tmp/vr_test_XXXXXX");
  int fd = mkstemp(name);
  if (fd < 0) return NULL;
  size_t len = strlen(text);
  if (write(fd, text, len) != (ssize_t)len) {
    close(fd);
    return NULL;
  }
  close(fd);
  return name;
}

#endif
