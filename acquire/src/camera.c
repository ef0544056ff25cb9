/* Camera models: see vr/camera.h.  The sensitivities are held at the 1 nm
 * steps of the CIE tables (360-830 nm), where every colorimetric sum of the
 * project runs, so that the responses of the sRGB camera agree with
 * vr_xyz_reflectance() to rounding. */
#include "vr/camera.h"
#include "vr/colour.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define CAM_FIRST_NM 360.0
#define CAM_ROWS 471 /* 360..830 nm at 1 nm, the rows of the CMF tables */

struct vr_camera {
  vr_camera_kind kind;
  size_t n;
  double *grid;
  double sens[3][CAM_ROWS]; /* x̄ ȳ z̄ or r g b at CAM_FIRST_NM + i nm */
};

static vr_status check_grid(size_t n, const double *grid, vr_error *err) {
  if (n < 3) return vr_error_set(err, VR_E_ARG, "camera grid: %zu samples, need at least 3", n);
  for (size_t j = 0; j < n; j++) {
    if (!isfinite(grid[j]))
      return vr_error_set(err, VR_E_ARG, "camera grid: sample %zu is not a finite number", j);
    if (j > 0 && !(grid[j] > grid[j - 1]))
      return vr_error_set(err, VR_E_ARG,
                          "camera grid: sample %zu (%g nm) does not increase on %g nm", j, grid[j],
                          grid[j - 1]);
  }
  return VR_OK;
}

static vr_camera *camera_new(size_t n, const double *grid_nm, vr_error *err) {
  double def[VR_CAMERA_DEFAULT_SAMPLES];
  if (!grid_nm) {
    n = VR_CAMERA_DEFAULT_SAMPLES;
    for (size_t j = 0; j < n; j++) def[j] = VR_CAMERA_DEFAULT_START_NM + VR_CAMERA_DEFAULT_STEP_NM * (double)j;
    grid_nm = def;
  }
  if (check_grid(n, grid_nm, err) != VR_OK) return NULL;
  vr_camera *cam = calloc(1, sizeof *cam);
  double *grid = malloc(n * sizeof *grid);
  if (!cam || !grid) {
    free(cam);
    free(grid);
    vr_error_set(err, VR_E_NOMEM, "camera: out of memory");
    return NULL;
  }
  memcpy(grid, grid_nm, n * sizeof *grid);
  cam->n = n;
  cam->grid = grid;
  return cam;
}

vr_camera *vr_camera_create_srgb(size_t n, const double *grid_nm, vr_error *err) {
  vr_camera *cam = camera_new(n, grid_nm, err);
  if (!cam) return NULL;
  cam->kind = VR_CAMERA_CIE1931_SRGB;
  size_t rows;
  const double *t = vr_cmf_table(VR_CIE1931_2DEG, &rows);
  for (size_t i = 0; i < CAM_ROWS && i < rows; i++)
    for (int c = 0; c < 3; c++) cam->sens[c][i] = t[i * 4 + 1 + c];
  return cam;
}

vr_camera *vr_camera_create_measured(const vr_spectrum *const sens[3], size_t n,
                                     const double *grid_nm, vr_error *err) {
  static const char *const channel[3] = {"red", "green", "blue"};
  if (!sens) {
    vr_error_set(err, VR_E_ARG, "camera: no sensitivity curves given");
    return NULL;
  }
  for (int c = 0; c < 3; c++) {
    if (!sens[c] || sens[c]->n == 0) {
      vr_error_set(err, VR_E_ARG, "camera: the %s sensitivity curve is missing", channel[c]);
      return NULL;
    }
    for (size_t i = 0; i < sens[c]->n; i++)
      if (!isfinite(sens[c]->value[i]) || !isfinite(sens[c]->nm[i])) {
        vr_error_set(err, VR_E_ARG, "camera: %s sensitivity sample %zu is not finite", channel[c], i);
        return NULL;
      }
  }
  vr_camera *cam = camera_new(n, grid_nm, err);
  if (!cam) return NULL;
  cam->kind = VR_CAMERA_MEASURED;
  for (int c = 0; c < 3; c++) {
    const vr_spectrum *s = sens[c];
    for (size_t i = 0; i < CAM_ROWS; i++) {
      double nm = CAM_FIRST_NM + (double)i;
      /* Zero outside the data: a sensor's response is not held at its end
       * values the way a reflectance is. */
      cam->sens[c][i] = (nm < s->nm[0] || nm > s->nm[s->n - 1])
                            ? 0.0
                            : vr_spectrum_eval(s, nm, VR_INTERP_LINEAR);
    }
  }
  return cam;
}

void vr_camera_destroy(vr_camera *cam) {
  if (!cam) return;
  free(cam->grid);
  free(cam);
}

vr_camera_kind vr_camera_get_kind(const vr_camera *cam) { return cam->kind; }
size_t vr_camera_samples(const vr_camera *cam) { return cam->n; }
const double *vr_camera_grid(const vr_camera *cam) { return cam->grid; }

vr_status vr_camera_grid_uniform(double start, double stop, double step, double *grid, size_t cap,
                                 size_t *n, vr_error *err) {
  if (!(isfinite(start) && isfinite(stop) && isfinite(step)) || !(step > 0.0) || stop < start)
    return vr_error_set(err, VR_E_ARG, "grid %g-%g nm step %g: need finite start <= stop, step > 0",
                        start, stop, step);
  double count = floor((stop - start) / step + 1e-9) + 1.0;
  if (count > (double)cap)
    return vr_error_set(err, VR_E_ARG, "grid %g-%g nm step %g has %.0f samples, room for %zu",
                        start, stop, step, count, cap);
  size_t k = (size_t)count;
  for (size_t j = 0; j < k; j++) grid[j] = start + step * (double)j;
  *n = k;
  return VR_OK;
}

vr_status vr_camera_response(const vr_camera *cam, const vr_spectrum *light, double *a,
                             vr_error *err) {
  if (!cam || !light || !a) return vr_error_set(err, VR_E_ARG, "camera response: NULL argument");
  size_t n = cam->n;
  const double *g = cam->grid;
  memset(a, 0, 3 * n * sizeof *a);
  double white = 0.0;
  size_t j = 0; /* interval index, advanced as the wavelength grows */
  for (size_t i = 0; i < CAM_ROWS; i++) {
    double nm = CAM_FIRST_NM + (double)i;
    double S = vr_spectrum_eval(light, nm, VR_INTERP_LINEAR);
    white += S * cam->sens[1][i];
    /* Weights of the two hats that are non-zero at nm (one beyond the ends). */
    size_t j0, j1;
    double w0, w1;
    if (nm <= g[0]) {
      j0 = j1 = 0;
      w0 = 1.0;
      w1 = 0.0;
    } else if (nm >= g[n - 1]) {
      j0 = j1 = n - 1;
      w0 = 1.0;
      w1 = 0.0;
    } else {
      while (j + 1 < n - 1 && nm >= g[j + 1]) j++;
      double t = (nm - g[j]) / (g[j + 1] - g[j]);
      j0 = j;
      j1 = j + 1;
      w0 = 1.0 - t;
      w1 = t;
    }
    for (int c = 0; c < 3; c++) {
      double v = S * cam->sens[c][i];
      a[c * n + j0] += w0 * v;
      a[c * n + j1] += w1 * v;
    }
  }
  if (!(white > 0.0) || !isfinite(white))
    return vr_error_set(err, VR_E_ARG,
                        "light gives no response in the camera's %s channel (a white would be "
                        "black), so its exposure cannot be normalised",
                        cam->kind == VR_CAMERA_CIE1931_SRGB ? "Y" : "green");
  double k = 1.0 / white;
  for (size_t q = 0; q < 3 * n; q++) a[q] *= k;
  if (cam->kind == VR_CAMERA_CIE1931_SRGB)
    for (size_t col = 0; col < n; col++) {
      double xyz[3] = {a[col], a[n + col], a[2 * n + col]}, rgb[3];
      vr_xyz_to_srgb_linear(xyz, rgb);
      for (int c = 0; c < 3; c++) a[c * n + col] = rgb[c];
    }
  for (size_t q = 0; q < 3 * n; q++)
    if (!isfinite(a[q]))
      return vr_error_set(err, VR_E_ARG, "light gives a non-finite camera response");
  return VR_OK;
}
