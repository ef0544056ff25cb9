/* libFuzzer target: spectrophotometer CSV on arbitrary bytes, then what
 * vr-spectro does with whatever parses (point inversion and smoothing, the
 * physical route to 45 deg), and the chromogenic state-token grammar on the
 * same bytes.  Succeeds or fails with a message; never crashes, leaks or
 * reads out of bounds. */
#include "vr/chromogenic_fit.h"
#include "vr/glazing.h"
#include "vr/spectro_fit.h"

#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  vr_error err;
  vr_spectro_data *d = NULL;
  if (vr_spectro_parse_csv((const char *)data, size, "fuzz.csv", &d, &err) == VR_OK) {
    const vr_spectro_curve *c = &d->curves[0];
    if (d->has_Rf && c->n <= 256) {
      vr_spectro_fit_result r;
      if (vr_spectro_fit(d, 3e6, NULL, &r, &err) == VR_OK) vr_spectro_fit_free(&r);
      vr_pane *p = NULL;
      if (vr_pane_from_curve(c, 3e6, 45, VR_ROUTE_AUTO, 0.8, &p, NULL, &err) == VR_OK)
        vr_pane_destroy(p);
    }
    vr_spectro_destroy(d);
  }
  char *text = malloc(size + 1);
  if (!text) return 0;
  memcpy(text, data, size);
  text[size] = '\0';
  vr_chromo_state *st = NULL;
  size_t n = 0;
  if (vr_chromo_states_parse(text, &st, &n, &err) == VR_OK) free(st);
  free(text);
  return 0;
}
