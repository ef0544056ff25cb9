/* libFuzzer target: spectral OpenEXR (the layout of Fichet et al., JCGT
 * 2021) from arbitrary bytes through vr_spectral_exr_read_memory, with and
 * without an RGB preview asked for.  Succeeds or fails with a message
 * naming the file; never crashes, leaks, reads out of bounds or allocates
 * what a lying header claims. */
#include "vr/spectral_exr.h"

#include <stddef.h>
#include <stdint.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  vr_error err;
  vr_spectral_image img;
  vr_image rgb;
  if (vr_spectral_exr_read_memory(data, size, "fuzz.exr", &img, &rgb, &err) == VR_OK) {
    vr_spectral_image_free(&img);
    vr_image_free(&rgb);
  }
  if (vr_spectral_exr_read_memory(data, size, "fuzz.exr", &img, NULL, &err) == VR_OK)
    vr_spectral_image_free(&img);
  return 0;
}
