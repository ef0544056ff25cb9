/* SHA-256 (FIPS 180-4) of files and buffers, for the provenance of every
 * material: the database records the hash of the exact bytes it was made
 * from. */
#ifndef VR_SHA256_H
#define VR_SHA256_H

#include <stddef.h>
#include <stdint.h>
#include "vr/error.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vr_sha256 {
  uint32_t h[8];
  uint64_t length;
  unsigned char block[64];
  size_t used;
} vr_sha256;

void vr_sha256_init(vr_sha256 *c);
void vr_sha256_update(vr_sha256 *c, const void *data, size_t len);
/* Writes 64 lowercase hex digits and a NUL into hex[65]. */
void vr_sha256_final(vr_sha256 *c, char hex[65]);

void vr_sha256_buffer(const void *data, size_t len, char hex[65]);
vr_status vr_sha256_file(const char *path, char hex[65], vr_error *err);

#ifdef __cplusplus
}
#endif
#endif
