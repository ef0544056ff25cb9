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

/* The same for rows of interleaved spectra, written band by band: in
 * holds lines x width pixels of nb floats each (pixel-major); out gets,
 * for each line, nb runs of width halves (band-major), i.e. out[(line nb
 * + b) width + x] = half(in[(line width + x) nb + b]).  The layout of an
 * EXR scanline's channels, so packing becomes a copy per run. */
void vr_half_convert_planar(const float *in, uint16_t *out, size_t lines, size_t width,
                            size_t nb);

/* Set by tests to compare against OpenEXR's own conversion. */
extern int vr_half_disable_f16c;

#endif
