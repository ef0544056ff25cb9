/* libFuzzer target: the delimited-text reader and the spectrum-table reader
 * on arbitrary bytes must either succeed or fail with a message, never crash,
 * leak or read out of bounds. */
#include "vr/csv.h"
#include "vr/spectrum.h"

#include <stddef.h>
#include <stdint.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  vr_error err;
  vr_csv *csv;
  if (vr_csv_parse((const char *)data, size, "fuzz.csv", &csv, &err) == VR_OK) {
    for (size_t r = 0; r < vr_csv_rows(csv); r++)
      for (size_t c = 0; c <= vr_csv_cols(csv, r); c++) {
        double v;
        vr_csv_number(csv, r, c, "f", &v, &err);
        (void)vr_csv_col_pos(csv, r, c);
      }
    vr_csv_destroy(csv);
  }
  vr_spectrum_table t;
  if (vr_spectrum_table_parse((const char *)data, size, "fuzz.csv", &t, &err) == VR_OK) {
    for (size_t i = 0; i < t.count; i++) {
      (void)vr_spectrum_eval(t.spectra[i], 550.0, VR_INTERP_CUBIC);
      (void)vr_spectrum_integrate(t.spectra[i], VR_SIMPSON);
    }
    vr_spectrum_table_free(&t);
  }
  return 0;
}
