/* The UV pass of photochromic glass (uv.c): each texel's UV irradiance and
 * the state it settles in, into the result and every cell's state maps. */
#ifndef VR_INTEGRATORS_UV_H
#define VR_INTEGRATORS_UV_H

#include "integrators/pass.h"

vr_status vr_uv_run(vr_run *r, vr_error *err);

#endif
