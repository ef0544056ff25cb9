/* The Virtuelium-C version string ("0.1.0"), recorded in provenance. */
#ifndef VR_VERSION_API_H
#define VR_VERSION_API_H
#ifdef __cplusplus
extern "C" {
#endif
const char *vr_version(void);
#ifdef __cplusplus
}
#endif
#endif
