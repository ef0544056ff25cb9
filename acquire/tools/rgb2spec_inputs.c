/* Checks of vr-rgb2spec's photos once read (rgb2spec_inputs.h).  A region
 * mean is only a measurement of light when every pixel in it is what the
 * camera recorded: transparency means some of them are not, a JPEG smears
 * colour across edges, and a linear file decoded as sRGB bends every value.
 * The first is refused, the others are said, with what to do. */
#include "rgb2spec_inputs.h"

#include <stdio.h>
#include <string.h>

#include "vr/matdb.h"

const char *rg_encoding_hint(const vr_capture *cap, const vr_capture_photo *p,
                             const vr_image *img) {
  if (!cap || !p || !img) return NULL;
  /* The default decoding (vr_capture_decode) is sRGB for integer files;
   * encoding= or a calibrated camera's tone curves replace it. */
  if (img->bit_depth != 16 || p->encoding != 0 || cap->has_tone) return NULL;
  return "this 16-bit photo has no encoding= and is decoded as sRGB, but 16-bit files from raw "
         "converters are usually linear: if the recovery reports regions out of gamut, add "
         "encoding=linear to its photo line";
}

vr_status rg_check_photo(const vr_capture *cap, const vr_capture_photo *p, const vr_image *img,
                         FILE *notes, vr_error *err) {
  if (!cap || !p || !img) return vr_error_set(err, VR_E_ARG, "rg_check_photo: NULL argument");
  const long pixels = (long)img->width * (long)img->height;
  if (img->transparent > 0) {
    if (img->format == VR_IMAGE_FORMAT_EXR)
      return vr_error_set(err, VR_E_ARG,
                          "%s: %ld of %ld pixels are not fully opaque (OpenEXR channel A below "
                          "1): OpenEXR colour is premultiplied by alpha, so they are darkened "
                          "by it; flatten the photo onto the scene or remove its alpha channel",
                          p->path, img->transparent, pixels);
    return vr_error_set(err, VR_E_ARG,
                        "%s: %ld of %ld pixels are not fully opaque (alpha channel): their "
                        "colour is not all light the camera saw; flatten the photo onto the "
                        "scene or remove its alpha channel",
                        p->path, img->transparent, pixels);
  }
  if (!notes) return VR_OK;
  if (img->alpha)
    fprintf(notes, "vr-rgb2spec: note: %s: has an alpha channel, every pixel opaque: it is "
                   "ignored\n", p->path);
  if (img->format == VR_IMAGE_FORMAT_JPEG)
    fprintf(notes, "vr-rgb2spec: warning: %s: JPEG is lossy: its 8x8-block compression and "
                   "chroma subsampling bleed colour across patch edges; keep regions a few "
                   "pixels inside the patches, or use PNG, TIFF or a 16-bit TIFF converted "
                   "from raw\n", p->path);
  const char *hint = rg_encoding_hint(cap, p, img);
  if (hint)
    fprintf(notes, "vr-rgb2spec: warning: %s: %s (%s:%ld)\n", p->path, hint, cap->path, p->line);
  return VR_OK;
}

/* A file: reference of the manifest, resolved as vr_capture_spectrum does. */
static void guard_file_ref(vr_out_guard *g, const vr_capture *cap, const char *ref, const char *role) {
  if (!ref || strncmp(ref, "file:", 5)) return;
  const char *rel = ref + 5;
  char path[4200];
  if (rel[0] == '/' || !cap->dir || !cap->dir[0]) snprintf(path, sizeof path, "%s", rel);
  else snprintf(path, sizeof path, "%s/%s", cap->dir, rel);
  vr_out_guard_input(g, path, role);
}

void rg_guard_capture(vr_out_guard *g, const vr_capture *cap, bool photos) {
  if (!g || !cap) return;
  if (!cap->stream) vr_out_guard_input(g, cap->path, "the capture manifest");
  for (size_t i = 0; i < cap->nphotos; i++) {
    if (photos) vr_out_guard_input(g, cap->photos[i].path, "a photo");
    guard_file_ref(g, cap, cap->photos[i].light_name, "a light's spectrum");
  }
  if (cap->labels_path) vr_out_guard_input(g, cap->labels_path, "the label image");
  guard_file_ref(g, cap, cap->camera_name, "the camera's sensitivities");
  for (size_t i = 0; i < cap->nregions; i++)
    guard_file_ref(g, cap, cap->regions[i].reference_name, "a reference spectrum");
}

