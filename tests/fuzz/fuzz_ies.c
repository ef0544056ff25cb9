/* libFuzzer target: IES LM-63 files on arbitrary bytes parse or fail with
 * "name:line: message"; whatever parses must evaluate and integrate to
 * finite, non-negative numbers.  Never crash, leak or read out of bounds. */
#include "vr/ies.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  vr_error err;
  vr_ies *ies = NULL;
  if (vr_ies_parse((const char *)data, size, "fuzz.ies", &ies, &err) == VR_OK) {
    double d[3] = {0.3, -0.4, -0.5};
    double c = vr_ies_candela_dir(ies, d) + vr_ies_candela(ies, 37.0, 271.0);
    double lm = vr_ies_lumens(ies);
    if (!(c >= 0.0) || !(lm >= 0.0) || !isfinite(c) || !isfinite(lm)) __builtin_trap();
    vr_ies_destroy(ies);
  }
  return 0;
}
