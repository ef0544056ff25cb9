/* The film as a Radiance picture (PREFIX.hdr, vr/film.h): XYZ turned into
 * Radiance's RGB and units, and the view as rpict would write it, so that
 * Radiance's tools (evalglare, pcomb, falsecolor, pvalue) read the render
 * as one of their own.
 *
 * Radiance's RGB has the primaries (0.640, 0.330), (0.290, 0.600),
 * (0.150, 0.060) and the equal-energy white (Radiance's src/common/color.h,
 * STDPRIMS); its pixels are radiance in W sr^-1 m^-2 of "white light" whose
 * luminous efficacy is 179 lm/W (WHTEFFICACY), so a pixel's luminance is
 * 179 (0.265 R + 0.670 G + 0.065 B) cd/m2, the coefficients being the Y
 * row of that RGB.  The film holds XYZ with Y in cd/m2: RGB = M^-1 XYZ /
 * 179, M the RGB-to-XYZ matrix of those primaries and white. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "vr/colour.h"
#include "vr/film.h"
#include "vr/rgbe.h"

#define RADIANCE_EFFICACY 179.0 /* lm/W, Radiance's WHTEFFICACY */
static const double PRIMARIES[8] = {0.640, 0.330, 0.290, 0.600, 0.150, 0.060, 1.0 / 3, 1.0 / 3};

/* m (row-major 3 x 3) = RGB to XYZ for the primaries p and white p[6..7]
 * (the white at Y = 1). */
static void rgb_to_xyz_matrix(const double p[8], double m[9]) {
  double P[9]; /* columns: each primary's XYZ at Y = 1 */
  for (int c = 0; c < 3; c++) {
    double x = p[2 * c], y = p[2 * c + 1];
    P[0 * 3 + c] = x / y, P[1 * 3 + c] = 1.0, P[2 * 3 + c] = (1 - x - y) / y;
  }
  double W[3] = {p[6] / p[7], 1.0, (1 - p[6] - p[7]) / p[7]}, inv[9], S[3];
  vr_mat3_inverse(P, inv);
  for (int r = 0; r < 3; r++) S[r] = inv[3 * r] * W[0] + inv[3 * r + 1] * W[1] + inv[3 * r + 2] * W[2];
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 3; c++) m[3 * r + c] = P[3 * r + c] * S[c];
}

void vr_film_radiance_rgb_matrix(double rgb_to_xyz[9]) { rgb_to_xyz_matrix(PRIMARIES, rgb_to_xyz); }

bool vr_film_radiance_view(const vr_scene_camera *c, int W, int H, char *buf, size_t n) {
  double d[3], len = 0;
  for (int a = 0; a < 3; a++) d[a] = c->to[a] - c->from[a], len += d[a] * d[a];
  len = sqrt(len);
  if (!(len > 0) || W < 1 || H < 1) return false;
  for (int a = 0; a < 3; a++) d[a] /= len;
  const char *type;
  double vh, vv;
  if (c->model == VR_CAM_FISHEYE) {
    /* Radiance has no equisolid view; its angular one (-vta) is linear in
     * the angle over the whole picture, the circle spanning fov over the
     * picture's smaller side. */
    if (c->projection != VR_FISHEYE_ANGULAR) return false;
    int m = W < H ? W : H;
    type = "-vta", vh = c->fov_deg * W / m, vv = c->fov_deg * H / m;
    if (vh > 360 || vv > 360) return false; /* Radiance's setview refuses a view over 360 deg */
  } else {
    type = "-vtv", vh = c->fov_deg;
    vv = 2 * atan(tan(c->fov_deg * M_PI / 360) * H / W) * 180 / M_PI;
  }
  int k = snprintf(buf, n, " %s -vp %.9g %.9g %.9g -vd %.9g %.9g %.9g -vu %.9g %.9g %.9g -vh %.9g "
                   "-vv %.9g -vo 0 -va 0 -vs 0 -vl 0", type, c->from[0], c->from[1], c->from[2],
                   d[0], d[1], d[2], c->up[0], c->up[1], c->up[2], vh, vv);
  return k > 0 && (size_t)k < n;
}

vr_status vr_film_write_hdr(const vr_render_result *r, const vr_scene_camera *cam,
                            const char *path, vr_error *err) {
  double m[9], inv[9];
  rgb_to_xyz_matrix(PRIMARIES, m);
  vr_mat3_inverse(m, inv);
  vr_image img = {0};
  vr_status st = vr_image_alloc(&img, r->width, r->height, err);
  if (st) return st;
  double gain = exp2(r->exposure_ev);
  size_t npix = (size_t)r->width * (size_t)r->height;
  for (size_t p = 0; p < npix; p++) {
    const double *xyz = &r->xyz[3 * p];
    double rgb[3], lo = 0;
    for (int c = 0; c < 3; c++) {
      rgb[c] = inv[3 * c] * xyz[0] + inv[3 * c + 1] * xyz[1] + inv[3 * c + 2] * xyz[2];
      lo = fmin(lo, rgb[c]);
    }
    /* A colour outside Radiance's RGB (a noisy pixel of a few wavelengths)
     * is desaturated toward white at its own luminance Y until no
     * component is negative: RGBE holds none, and clipping would change
     * the luminance glare tools read.  White at Y is (Y, Y, Y). */
    double Y = xyz[1];
    if (lo < 0) {
      if (Y > 0) {
        double t = Y / (Y - lo);
        for (int c = 0; c < 3; c++) rgb[c] = fmax(0.0, Y + t * (rgb[c] - Y));
      } else {
        rgb[0] = rgb[1] = rgb[2] = 0;
      }
    }
    for (int c = 0; c < 3; c++)
      img.data[3 * p + (size_t)c] = (float)(gain * rgb[c] / RADIANCE_EFFICACY);
  }
  char view[512];
  vr_rgbe_header h = {.exposure = gain, .software = "vr-render"};
  memcpy(h.primaries, PRIMARIES, sizeof PRIMARIES);
  if (cam && vr_film_radiance_view(cam, r->width, r->height, view, sizeof view)) h.view = view;
  st = vr_rgbe_write(path, &img, &h, err);
  vr_image_free(&img);
  return st;
}
