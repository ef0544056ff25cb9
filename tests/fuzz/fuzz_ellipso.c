/* libFuzzer target: the ellipsometry readers (CSV, Woollam and WVASE-format
 * exports, Accurion EP4 tables, Film Sense static and kinetic exports,
 * Sentech; with and without a wavelength given for single-wavelength files
 * and a record for runs) and
 * the model-file parser on arbitrary bytes succeed or fail with a message;
 * never crash, leak or read out of bounds. */
#include "vr/ellipso_data.h"
#include "vr/ellipso_model.h"

#include <stddef.h>
#include <stdint.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  vr_error err;
  vr_ellipso_data d;
  if (vr_ellipso_parse((const char *)data, size, "fuzz.dat", NULL, &d, &err) == VR_OK) vr_ellipso_data_free(&d);
  vr_ellipso_read_options o = {.wavelength_nm = 658};
  if (vr_ellipso_parse_with((const char *)data, size, "fuzz.dat", &o, &d, &err) == VR_OK)
    vr_ellipso_data_free(&d);
  vr_ellipso_read_options r = {.record = 2};
  if (vr_ellipso_parse_with((const char *)data, size, "fuzz.dat", &r, &d, &err) == VR_OK)
    vr_ellipso_data_free(&d);
  vr_sample_model *m;
  /* No base directory and no database: file: and db: materials fail cleanly. */
  if (vr_model_parse((const char *)data, size, "fuzz.model", NULL, NULL, &m, &err) == VR_OK) {
    double psi, delta;
    vr_model_psi_delta(m, 550.0, 70.0, &psi, &delta, NULL, &err);
    vr_model_response resp; /* with an instrument bandwidth, as a data point may give */
    vr_model_measure(m, 550.0, 70.0, 5.0, &resp, &err);
    vr_model_destroy(m);
  }
  return 0;
}
