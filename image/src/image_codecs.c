/* Finding and loading the OpenCV module (image_cv_module.h) the first time
 * a PNG, TIFF or JPEG is read or written: a program that only touches
 * OpenEXR never maps OpenCV's hundred-odd shared objects.
 *
 * Where the module is looked for, first found wins:
 *   1. $VR_IMAGE_CV_MODULE, the module's path (then nothing else is tried);
 *   2. beside the running program (/proc/self/exe): DIR/vr-image-cv.so,
 *      then DIR/../lib/virtuelium-c/vr-image-cv.so, for copied or installed
 *      programs;
 *   3. where the build put it (VR_IMAGE_CV_BUILD_PATH), for programs run
 *      from the build tree, the tests among them.
 * The module is loaded once per process and never unloaded; a failure is
 * kept too, so every later PNG names the same paths.  The only process-wide
 * state of vr_image, set once under pthread_once: like the dynamic loader's
 * own, it does not change once it is set. */
#include <dlfcn.h>
#include <limits.h>
#include <pthread.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "image_cv_module.h"
#include "image_internal.h"

#ifndef VR_IMAGE_CV_BUILD_PATH
#define VR_IMAGE_CV_BUILD_PATH ""
#endif
#define MODULE_NAME "vr-image-cv.so"

typedef struct loaded {
  const vr_image_cv_codecs *codecs; /* NULL when the module could not be loaded */
  char why[VR_ERROR_MESSAGE_MAX - 200]; /* then why, naming every path tried */
} loaded;

static pthread_once_t once = PTHREAD_ONCE_INIT;
static loaded module;

static const vr_image_cv_host HOST = {vr_image_pixels_alloc, vr_image_alloc, vr_image_free,
                                      vr_error_at, vr_error_prefix};

static void append(char *out, size_t cap, const char *fmt, const char *a, const char *b) {
  size_t used = strlen(out);
  /* Cut at cap: a message, not a path to open. */
  if (used < cap && snprintf(out + used, cap - used, fmt, a, b) < 0) out[used] = '\0';
}

/* dlopen and check one path: true when loaded; else false with *exists
 * telling a missing file from one that failed to load (why says how). */
static bool try_path(const char *path, bool *exists) {
  *exists = access(path, F_OK) == 0;
  if (!*exists) return false;
  void *h = dlopen(path, RTLD_NOW | RTLD_LOCAL);
  if (!h) {
    const char *e = dlerror();
    append(module.why, sizeof module.why, "%s%s", module.why[0] ? "; " : "", e ? e : path);
    return false;
  }
  vr_image_cv_entry entry;
  /* POSIX's sanctioned way from a data pointer to a function pointer. */
  *(void **)&entry = dlsym(h, VR_IMAGE_CV_ENTRY);
  const vr_image_cv_codecs *c = entry ? entry() : NULL;
  if (!c || c->abi != VR_IMAGE_CV_ABI || c->vr_image_size != sizeof(vr_image) ||
      c->vr_error_size != sizeof(vr_error) || !c->decode || !c->encode) {
    append(module.why, sizeof module.why, "%s%s: not a vr-image-cv module of this build "
           "(another version of the program?)", module.why[0] ? "; " : "", path);
    dlclose(h);
    return false;
  }
  module.codecs = c;
  return true;
}

static void load_once(void) {
  const char *env = getenv("VR_IMAGE_CV_MODULE");
  bool exists;
  if (env && *env) {
    if (!try_path(env, &exists) && !exists)
      append(module.why, sizeof module.why, "VR_IMAGE_CV_MODULE=%s: no such file%s", env, "");
    return;
  }
  char tried[3][PATH_MAX + 64];
  int n = 0;
  char exe[PATH_MAX];
  ssize_t len = readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (len > 0) {
    exe[len] = '\0';
    char *slash = strrchr(exe, '/');
    if (slash) *slash = '\0';
    snprintf(tried[n++], sizeof tried[0], "%s/%s", exe, MODULE_NAME);
    snprintf(tried[n++], sizeof tried[0], "%s/../lib/virtuelium-c/%s", exe, MODULE_NAME);
  }
  if (VR_IMAGE_CV_BUILD_PATH[0]) snprintf(tried[n++], sizeof tried[0], "%s", VR_IMAGE_CV_BUILD_PATH);
  char missing[sizeof module.why] = "";
  for (int i = 0; i < n; i++) {
    if (try_path(tried[i], &exists)) return;
    if (!exists) append(missing, sizeof missing, "%s%s", missing[0] ? ", " : "", tried[i]);
  }
  if (missing[0])
    append(module.why, sizeof module.why, "%snot found at %s (set VR_IMAGE_CV_MODULE to its path)",
           module.why[0] ? "; " : "", missing);
}

/* The module, or NULL with err saying what needed it and every path tried. */
static const vr_image_cv_codecs *codecs(const char *path, const char *what, vr_error *err) {
  pthread_once(&once, load_once);
  if (module.codecs) return module.codecs;
  const char *fmt = "%s needs OpenCV, through the module " MODULE_NAME
                    ", which could not be loaded: %s";
  if (path) vr_error_at(err, VR_E_IO, path, 0, 0, fmt, what, module.why);
  else vr_error_set(err, VR_E_IO, fmt, what, module.why);
  return NULL;
}

vr_status vr_image_codecs_load(vr_error *err) {
  return codecs(NULL, "reading or writing a PNG, TIFF or JPEG", err) ? VR_OK : VR_E_IO;
}

/* "PNG", "TIFF" or "JPEG" for a writer's extension. */
static const char *format_of(const char *ext) {
  return !strcmp(ext, ".png") ? "PNG" : !strcmp(ext, ".jpg") ? "JPEG" : "TIFF";
}

vr_status vr_image_decode_cv(const unsigned char *buf, size_t len, const char *path,
                             const char *format, int keep, vr_image *out, vr_error *err) {
  memset(out, 0, sizeof *out);
  char what[64];
  snprintf(what, sizeof what, "reading a %s", format);
  const vr_image_cv_codecs *c = codecs(path, what, err);
  return c ? c->decode(&HOST, buf, len, path, format, keep, out, err) : VR_E_IO;
}

vr_status vr_image_encode_cv(const vr_image *img, const char *path, const char *ext, int bits,
                             unsigned char **bytes, size_t *len, vr_error *err) {
  *bytes = NULL;
  *len = 0;
  char what[64];
  snprintf(what, sizeof what, "writing a %s", format_of(ext));
  const vr_image_cv_codecs *c = codecs(path, what, err);
  return c ? c->encode(&HOST, img, path, ext, bits, bytes, len, err) : VR_E_IO;
}
