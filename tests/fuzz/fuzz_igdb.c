/* libFuzzer target: the IGDB .DAT importer on arbitrary bytes succeeds or
 * fails with a message; never crashes, leaks or reads out of bounds. */
#include "import.h"

#include <stddef.h>
#include <stdint.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  vr_error err;
  vr_material *m = vr_material_create("fuzz", VR_KIND_GLAZING, NULL);
  if (!m) return 0;
  vr_igdb_parse((const char *)data, size, "fuzz.DAT", m, &err);
  vr_material_destroy(m);
  m = vr_material_create("fuzz", VR_KIND_REFLECTANCE, NULL);
  if (!m) return 0;
  vr_csv_material_parse((const char *)data, size, "fuzz.csv", m, &err);
  vr_material_destroy(m);
  return 0;
}
