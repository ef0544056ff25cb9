/* libFuzzer target: the geometry cache's manifest reader on arbitrary bytes
 * (render/src/cache_format.c).  A file that is not a manifest of this
 * version, is cut short, fails its checksums or holds an inconsistent
 * kd-tree must be refused with VR_E_PARSE; what is accepted must describe a
 * tree whose walk from the root reaches a leaf in at most nnodes steps and
 * cells whose layouts fit their payloads.  Never crash, leak or read out of
 * bounds.  (The checksum makes random inputs fail early; the seed corpus
 * holds real manifests, and the target also feeds each input with its
 * checksums recomputed, so the parser behind them is reached.) */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cache_format.h"
#include "vr/hash64.h"

static void check(const char *path) {
  vr_cache_manifest *m = NULL;
  vr_error err;
  vr_status st = vr_cache_manifest_read(path, &m, &err);
  if (st == VR_OK) {
    int n = 0, steps = 0;
    while (m->nodes[n].axis >= 0) {
      n = m->nodes[n].child[steps & 1];
      if (++steps > m->nnodes) __builtin_trap();
    }
    if (m->nodes[n].cell < 0 || m->nodes[n].cell >= m->ncells) __builtin_trap();
    for (int c = 0; c < m->ncells; c++) {
      vr_cell_layout L;
      if (!vr_cell_layout_of(m->cells[c].nverts, m->cells[c].ntris, m->cells[c].nspheres,
                             m->cells[c].flags, &L) ||
          L.total != m->cells[c].payload_bytes)
        __builtin_trap();
    }
    vr_cache_manifest_free(m);
  } else if (st != VR_E_PARSE && st != VR_E_IO && st != VR_E_NOMEM) {
    __builtin_trap();
  }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  char path[64];
  snprintf(path, sizeof path, "/tmp/vr_fuzz_cache_%d.vrm", (int)getpid());
  FILE *f = fopen(path, "wb");
  if (!f) return 0;
  fwrite(data, 1, size, f);
  fclose(f);
  check(path);
  /* The same bytes with the header's sizes and checksums made right, so
   * that mutations reach the contents' parser. */
  if (size >= 64) {
    unsigned char *d = malloc(size);
    memcpy(d, data, size);
    uint64_t n = size - 64, h = vr_hash64_buffer(d + 64, n, 0);
    memcpy(d + 16, &n, 8);
    memcpy(d + 24, &h, 8);
    uint64_t hh = vr_hash64_buffer(d, 32, 0);
    memcpy(d + 32, &hh, 8);
    f = fopen(path, "wb");
    if (f) {
      fwrite(d, 1, size, f);
      fclose(f);
      check(path);
    }
    free(d);
  }
  unlink(path);
  return 0;
}
