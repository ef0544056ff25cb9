/* The 24 patches of the X-Rite (Macbeth) ColorChecker Classic: BabelColor's
 * average spectral reflectances (Pascale, BabelColor 2006-2012), 380-730 nm
 * at 10 nm, embedded from core/data/colorchecker_babelcolor.csv. */
#ifndef VR_COLORCHECKER_H
#define VR_COLORCHECKER_H

#include "vr/spectrum.h"

#ifdef __cplusplus
extern "C" {
#endif

#define VR_COLORCHECKER_PATCHES 24

/* Patch name in chart order, e.g. "dark_skin" for index 0; NULL past 23. */
const char *vr_colorchecker_name(size_t index);
/* New spectrum of patch index (0-23). */
vr_spectrum *vr_colorchecker_patch(size_t index, vr_error *err);

#ifdef __cplusplus
}
#endif
#endif
