/* Float to half conversion in bulk (half_convert.c). */
#ifndef VR_HALF_CONVERT_H
#define VR_HALF_CONVERT_H

#include <stddef.h>
#include <stdint.h>

/* Converts n floats (finite, or +infinity, each within half's range) to
 * binary16, round to nearest even; returns 1, or 0 without doing anything
 * when the processor has no F16C (the caller then lets OpenEXR convert). */
int vr_half_convert(const float *in, uint16_t *out, size_t n);

/* Set by tests to compare against OpenEXR's own conversion. */
extern int vr_half_disable_f16c;

#endif
