/* libFuzzer target: scene files on arbitrary bytes parse or fail with a
 * message naming the line and column; never crash, leak or read out of
 * bounds. */
#include "vr/scene.h"

#include <stddef.h>
#include <stdint.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  vr_error err;
  vr_scene *s = NULL;
  if (vr_scene_parse((const char *)data, size, "fuzz/room.scn", &s, &err) == VR_OK) vr_scene_destroy(s);
  return 0;
}
