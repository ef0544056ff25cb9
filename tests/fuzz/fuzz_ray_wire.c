/* libFuzzer target: a message body of rays from another rank, as
 * flow_net.c reads it (render/src/ddm/ray_wire.c with the paths' payload
 * codec, render/src/integrators/payload_wire.c).  Bytes that are not a ray
 * must be refused (0); a ray that is read must never read past the bytes
 * given, and written again it must be read back as the same ray, field for
 * field (exactness: the image of several ranks equals one process's only
 * if a ray arrives as it left).  The first byte picks the scene's
 * wavelengths (hero or bins, 1 to 8), which the codec rebuilds from the
 * hero.  Never crash, leak or read out of bounds.  The seed corpus holds
 * rays captured from a run of the sample room on 2 ranks. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "ddm/ray_wire.h"
#include "integrators/pass.h"

static const vr_flow_ops ops = {NULL, NULL, NULL, NULL, VR_PAYLOAD_WIRE};

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  if (size < 1) return 0;
  vr_rscene rs;
  memset(&rs, 0, sizeof rs);
  rs.lmin = 360;
  rs.lmax = 830;
  rs.nwl = 1 + (data[0] & 7);
  rs.bins_mode = (data[0] & 8) != 0;
  vr_pass c;
  memset(&c, 0, sizeof c);
  c.rs = &rs;
  const vr_flow_ops *o = data[0] & 16 ? NULL : &ops;
  data++, size--;
  /* A copy of exactly the bytes given: ASan sees a read past them. */
  unsigned char *in = malloc(size ? size : 1);
  if (!in) return 0;
  memcpy(in, data, size);
  size_t off = 0;
  while (off < size) {
    vr_ray r, back;
    size_t used = vr_ray_unpack(o, &c, in + off, size - off, &r);
    if (!used) break;
    if (used > size - off) __builtin_trap();
    unsigned char out[VR_RAY_WIRE_MAX];
    size_t n = vr_ray_pack(o, &c, &r, out);
    if (n > VR_RAY_WIRE_MAX || vr_ray_unpack(o, &c, out, n, &back) != n) __builtin_trap();
    if (memcmp(&back, &r, sizeof r) != 0) __builtin_trap();
    off += used;
  }
  free(in);
  return 0;
}
