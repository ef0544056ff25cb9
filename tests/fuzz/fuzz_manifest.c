/* libFuzzer target: capture manifests on arbitrary bytes parse or fail with
 * a message naming the line; never crash, leak or read out of bounds. */
#include "vr/manifest.h"

#include <stddef.h>
#include <stdint.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  vr_error err;
  vr_capture *c = NULL;
  if (vr_capture_parse((const char *)data, size, "fuzz/manifest.txt", NULL, &c, &err) == VR_OK)
    vr_capture_destroy(c);
  return 0;
}
