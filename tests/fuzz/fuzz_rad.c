/* libFuzzer target: Radiance scene descriptions (.rad) on arbitrary bytes,
 * written to a file of their own (the reader follows !xform lines from a
 * file's folder), read or refused with "FILE:LINE: message"; whatever
 * reads has triangles whose indices and materials are in range and whose
 * vertices are finite, and its coinciding polygons positive shared areas.  Never crash, leak or read out of bounds. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "geometry/rad_read.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  char dir[] = "/tmp/vr_fuzz_rad_XXXXXX";
  if (!mkdtemp(dir)) return 0;
  char path[64];
  snprintf(path, sizeof path, "%s/in.rad", dir);
  FILE *f = fopen(path, "wb");
  if (f) {
    fwrite(data, 1, size, f);
    fclose(f);
    vr_rad_model m;
    vr_error err = {0};
    if (vr_rad_read(path, &m, &err) == VR_OK) {
      for (size_t t = 0; t < m.mesh.ntris; t++) {
        if (m.mesh.tri_material[t] >= m.nmats) __builtin_trap();
        for (int k = 0; k < 3; k++)
          if (m.mesh.tris[3 * t + k] >= m.mesh.nverts) __builtin_trap();
      }
      for (size_t i = 0; i < 3 * m.mesh.nverts; i++)
        if (!isfinite(m.mesh.pos[i])) __builtin_trap();
      vr_rad_overlap *o;
      size_t n;
      if (vr_rad_overlaps(&m, &o, &n, &err) == VR_OK) {
        for (size_t k = 0; k < n; k++)
          if (!(o[k].area > 0) || o[k].a >= o[k].b || o[k].b >= m.npolys) __builtin_trap();
        free(o);
      }
      vr_rad_free(&m);
    } else if (!strstr(err.message, "in.rad")) {
      __builtin_trap(); /* every refusal names the file */
    }
  }
  unlink(path);
  rmdir(dir);
  return 0;
}
