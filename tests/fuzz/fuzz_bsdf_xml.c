/* libFuzzer target: BSDF XML on arbitrary bytes, then WINDOW's figures of
 * every block that parses for every incident patch.  Succeeds or fails with
 * a message; never crashes, leaks or reads out of bounds. */
#include "vr/bsdf_xml.h"

#include <stddef.h>
#include <stdint.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  vr_error err;
  vr_bsdf_xml *x = NULL;
  if (vr_bsdf_xml_parse((const char *)data, size, "fuzz.xml", &x, &err) == VR_OK) {
    for (size_t b = 0; b < x->nbands; b++)
      for (int s = 0; s < VR_BSDF_SIDES; s++)
        for (int in = 0; x->bands[b].m[s] && in < x->basis.n && in < 64; in++) {
          vr_klems_figures f;
          vr_klems_figures_of(&x->basis, x->bands[b].m[s], in, &f);
        }
    vr_bsdf_xml_destroy(x);
  }
  return 0;
}
