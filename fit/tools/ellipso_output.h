/* What vr-ellipso prints, reports and saves after a fit. */
#ifndef VR_ELLIPSO_OUTPUT_H
#define VR_ELLIPSO_OUTPUT_H

#include <stdio.h>
#include "vr/ellipso_fit.h"
#include "vr/matdb.h"

typedef struct vr_fit_view {
  const vr_sample_model *model; /* the first sample's */
  const vr_ellipso_data *data;  /* ndata data sets, one per sample */
  size_t ndata;
  const vr_fit_result *fit;
  /* The reported layer's optical constants are fitted per sample: n, k
   * are the first sample's, and saving them would be ambiguous. */
  bool nk_per_sample;
  long layer;            /* the layer whose n, k are reported (VR_OWNER_SUBSTRATE for the substrate) */
  const char *layer_name;
  size_t nwl;            /* distinct wavelengths, increasing */
  double *wl;
  double *n, *k;         /* of that layer at wl */
} vr_fit_view;

/* Fills the view's wavelength list (over all nd data sets) and n, k (frees
 * with vr_fit_view_free). */
vr_status vr_fit_view_init(vr_fit_view *v, const vr_sample_model *m, const vr_ellipso_data *d, size_t nd,
                           const vr_fit_result *r, const char *layer, vr_error *err);
void vr_fit_view_free(vr_fit_view *v);

void vr_fit_print_text(FILE *f, const vr_fit_view *v);
void vr_fit_print_json(FILE *f, const vr_fit_view *v);
vr_status vr_fit_write_report(const char *path, const vr_fit_view *v, vr_error *err);
/* Saves the layer's n, k table, model, parameters and provenance (for
 * several data files: their names joined with "; " and the SHA-256 of
 * their SHA-256 digests in order), and the verdict: the provenance note
 * "verdict: ...; MSE ..." (and that it was saved with --force when forced)
 * and the properties fit_mse, fit_misfit_ratio, fit_parameters_at_bound,
 * fit_describes and fit_forced (0 or 1). */
vr_status vr_fit_save(vr_matdb *db, const char *name, const vr_fit_view *v, const char *const *data_paths,
                      size_t npaths, const char *model_path, bool forced, vr_error *err);

#endif
