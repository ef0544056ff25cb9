/* Float to half conversion in bulk (half_convert.c). */
#ifndef VR_HALF_CONVERT_H
#define VR_HALF_CONVERT_H

#include <stddef.h>
#include <stdint.h>

/* 1 when vr_half_convert can run here (F16C and the OS's AVX state, and
 * not disabled by a test); else the caller lets OpenEXR convert. */
int vr_half_available(void);

/* Converts n floats (finite, or +infinity, each within half's range) to
 * binary16, round to nearest even.  Only when vr_half_available(). */
void vr_half_convert(const float *in, uint16_t *out, size_t n);

/* Set by tests to compare against OpenEXR's own conversion. */
extern int vr_half_disable_f16c;

#endif
