/* vr-test-exr-attrs FILE.exr: the header attributes of the first part of
 * an OpenEXR file, one a line as "name value...", read with the OpenEXR
 * core library (not ours): strings as they are, floats and doubles with 9
 * significant digits, chromaticities as their eight numbers (red x y,
 * green x y, blue x y, white x y); other types as "name <type>".  Exit 0,
 * or 2 if the file cannot be read.  For the command-line tests that check
 * what a viewer finds in vr-render's EXR files. */
#include <stdio.h>

#include <openexr.h>

int main(int argc, char **argv) {
  if (argc != 2) {
    fputs("usage: vr-test-exr-attrs FILE.exr\n", stderr);
    return 2;
  }
  exr_context_t ctxt = NULL;
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  if (exr_start_read(&ctxt, argv[1], &init) != EXR_ERR_SUCCESS) {
    fprintf(stderr, "%s: not a readable OpenEXR file\n", argv[1]);
    if (ctxt) exr_finish(&ctxt);
    return 2;
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
