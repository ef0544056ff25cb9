/* vr-test-exr-attrs FILE.exr: the header attributes of the first part of
 * an OpenEXR file, one a line as "name value...", read with the OpenEXR
 * core library (not ours): strings as they are, floats and doubles with 9
 * significant digits, chromaticities as their eight numbers (red x y,
 * green x y, blue x y, white x y); other types as "name <type>".
 * vr-test-exr-attrs --channels FILE.exr: each channel as "name type"
 * (uint, half or float), and with --values NAME also that channel's
 * minimum, maximum and mean over the pixels as "NAME min max mean"
 * (decoded by OpenEXR from a scanline file).  Exit 0, or 2 if the file
 * cannot be read.  For the command-line tests that check what a viewer
 * finds in vr-render's EXR files. */
#include <float.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <openexr.h>

/* The minimum, maximum and mean of channel name (a uint or float channel)
 * of part 0, read scanline chunk by chunk. */
static int channel_values(exr_context_t ctxt, const char *name) {
  exr_attr_box2i_t dw;
  int32_t lines = 0;
  if (exr_get_data_window(ctxt, 0, &dw) || exr_get_scanlines_per_chunk(ctxt, 0, &lines)) return 2;
  int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
  float *buf = malloc((size_t)w * (size_t)lines * 4);
  double lo = DBL_MAX, hi = -DBL_MAX, sum = 0;
  int found = 0, rc = buf ? 0 : 2;
  exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
  int started = 0;
  for (int y = dw.min.y; y <= dw.max.y && !rc; y += lines) {
    exr_chunk_info_t ci;
    if (exr_read_scanline_chunk_info(ctxt, 0, y, &ci)) {
      rc = 2;
      break;
    }
    if (started ? exr_decoding_update(ctxt, 0, &ci, &dec)
                : exr_decoding_initialize(ctxt, 0, &ci, &dec)) {
      rc = 2;
      break;
    }
    int is_uint = 0;
    for (int c = 0; c < dec.channel_count; c++) {
      exr_coding_channel_info_t *ch = &dec.channels[c];
      if (strcmp(ch->channel_name, name)) {
        ch->decode_to_ptr = NULL;
        continue;
      }
      found = 1;
      is_uint = ch->data_type == EXR_PIXEL_UINT;
      ch->decode_to_ptr = (uint8_t *)buf;
      ch->user_pixel_stride = 4;
      ch->user_line_stride = 4 * w;
      ch->user_bytes_per_element = 4;
      ch->user_data_type = is_uint ? EXR_PIXEL_UINT : EXR_PIXEL_FLOAT;
    }
    if (!started) {
      started = 1;
      if (exr_decoding_choose_default_routines(ctxt, 0, &dec)) {
        rc = 2;
        break;
      }
    }
    if (exr_decoding_run(ctxt, 0, &dec)) {
      rc = 2;
      break;
    }
    for (int i = 0; found && i < w * ci.height; i++) {
      double v = is_uint ? (double)((uint32_t *)(void *)buf)[i] : (double)buf[i];
      lo = v < lo ? v : lo;
      hi = v > hi ? v : hi;
      sum += v;
    }
  }
  if (started) exr_decoding_destroy(ctxt, &dec);
  free(buf);
  if (rc || !found) {
    fprintf(stderr, "channel %s: %s\n", name, found ? "cannot be decoded" : "not in the file");
    return 2;
  }
  printf("%s %.9g %.9g %.9g\n", name, lo, hi, sum / ((double)w * h));
  return 0;
}

static int channels(exr_context_t ctxt, const char *values) {
  const exr_attr_chlist_t *cl = NULL;
  if (exr_get_channels(ctxt, 0, &cl)) return 2;
  for (int i = 0; i < cl->num_channels; i++) {
    exr_pixel_type_t t = cl->entries[i].pixel_type;
    printf("%s %s\n", cl->entries[i].name.str,
           t == EXR_PIXEL_UINT ? "uint" : t == EXR_PIXEL_HALF ? "half" : "float");
  }
  return values ? channel_values(ctxt, values) : 0;
}

int main(int argc, char **argv) {
  int list = argc >= 3 && !strcmp(argv[1], "--channels");
  const char *values = list && argc == 5 && !strcmp(argv[3], "--values") ? argv[4] : NULL;
  if (!(argc == 2 || (list && (argc == 3 || values)))) {
    fputs("usage: vr-test-exr-attrs [--channels] FILE.exr [--values NAME]\n", stderr);
    return 2;
  }
  const char *path = list ? argv[2] : argv[1];
  exr_context_t ctxt = NULL;
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  if (exr_start_read(&ctxt, path, &init) != EXR_ERR_SUCCESS) {
    fprintf(stderr, "%s: not a readable OpenEXR file\n", path);
    if (ctxt) exr_finish(&ctxt);
    return 2;
  }
  if (list) {
    int rc = channels(ctxt, values);
    exr_finish(&ctxt);
    return rc;
  }
  int32_t n = 0;
  exr_get_attribute_count(ctxt, 0, &n);
  for (int32_t i = 0; i < n; i++) {
    const exr_attribute_t *a = NULL;
    if (exr_get_attribute_by_index(ctxt, 0, EXR_ATTR_LIST_FILE_ORDER, i, &a) != EXR_ERR_SUCCESS)
      continue;
    switch (a->type) {
    case EXR_ATTR_STRING: printf("%s %s\n", a->name, a->string->str); break;
    case EXR_ATTR_FLOAT: printf("%s %.9g\n", a->name, (double)a->f); break;
    case EXR_ATTR_DOUBLE: printf("%s %.9g\n", a->name, a->d); break;
    case EXR_ATTR_CHROMATICITIES: {
      const exr_attr_chromaticities_t *c = a->chromaticities;
      printf("%s %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g\n", a->name, (double)c->red_x,
             (double)c->red_y, (double)c->green_x, (double)c->green_y, (double)c->blue_x,
             (double)c->blue_y, (double)c->white_x, (double)c->white_y);
      break;
    }
    default: printf("%s <%s>\n", a->name, a->type_name); break;
    }
  }
  exr_finish(&ctxt);
  return 0;
}
