/* What the spectral OpenEXR reader (spectral_exr.c) and writer
 * (spectral_exr_write.c, spectral_exr_rows.c) share: channel names, made
 * and parsed in spectral_exr_names.c, and which wavelengths can be named at
 * all; and how the writer hands an open file to its workers.  Private to
 * image/. */
#ifndef VR_SPECTRAL_EXR_INTERNAL_H
#define VR_SPECTRAL_EXR_INTERNAL_H

#include <stddef.h>

#include <openexr.h>

#include "exr_stream.h"

#include "vr/spectral_exr.h"

/* Longest name we write: "S0." + 10 digits + ",000000nm" + NUL, with room. */
#define NAME_LEN 40
/* Wavelengths above 1 m make no optical sense, and the bound keeps
 * round(λ * 1e6) exact in a double and an int64. */
#define MAX_WAVELENGTH_NM 1e9
#define LAYOUT_VERSION "1.0"

/* "S0.550,000000nm" or "T.550,000000nm": the reference code's name for a
 * band of that kind, 6 decimals, decimal comma. */
void vr_spectral_channel_name(char out[NAME_LEN], vr_spectral_kind kind, double nm);

/* Finite, > 0, strictly increasing; VR_E_ARG naming the index otherwise. */
vr_status vr_spectral_check_wavelengths(const double *wl, size_t n, vr_error *err);

/* That every wavelength (already checked as above) has a name of its own
 * once written with 6 decimals, in (0, 1e9] nm; VR_E_ARG naming path, the
 * bands and the shared channel name otherwise. */
vr_status vr_spectral_check_names(const char *path, const double *wl, size_t n,
                                  vr_spectral_kind kind, vr_error *err);

/* Whether a channel name starts as the layout's spectral channels do
 * (S0. to S3. or T., then a digit or a comma), so that the reader takes it
 * for one of them. */
int vr_spectral_name_is_spectral(const char *name);

typedef enum {
  CH_OTHER,       /* not part of the layout: R, G, B, A, Y, layer.channel ... */
  CH_EMISSIVE,    /* S0.<λ> */
  CH_POLARISED,   /* S1..S3.<λ>: checked, skipped */
  CH_REFLECTIVE,  /* T.<λ> */
  CH_RERADIATION, /* T.<λ>.<λ'>: checked, skipped */
  CH_MALFORMED
} channel_class;

/* What a channel name is in the layout; *nm gets the wavelength of an
 * S0..S3 or T channel (the first one of a re-radiation pair). */
channel_class vr_spectral_classify(const char *name, double *nm);

/* Most workers a layout may ask for. */
#define VR_SPECTRAL_MAX_THREADS 256

/* A file whose header is written, and what fills its pixels. */
typedef struct vr_spectral_rows_job {
  exr_context_t ctxt;
  int part;
  const char *path;                      /* for messages */
  const vr_spectral_exr_layout *layout;  /* checked */
  vr_spectral_rows_fn fill;
  void *user;
  exr_stream *stream;                    /* the temporary file, its errno */
  char (*names)[NAME_LEN];               /* channel name of each band */
} vr_spectral_rows_job;

/* Fills, checks, compresses and writes every chunk of the part with
 * layout->threads workers, in increasing y order.  On error no further
 * chunk is written and the error of the first failing chunk (in y) is
 * returned; the caller then drops the file. */
vr_status vr_spectral_exr_write_chunks(const vr_spectral_rows_job *job, vr_error *err);

#endif
