/* The hotel's two texture images (hotel_textures.h): a wood grain for the
 * desks, chairs, bed frames and wardrobes, and a woven fabric for the
 * curtains, duvets, headboards and armchairs.  Procedural, so that the
 * floor is self-contained: what they measure is the renderer's texture
 * path (memory, filtering, time) at 20 million triangles, not a
 * photograph's content.  8-bit sRGB PNG, written through vr_image. */
#include "hotel_textures.h"

#include <math.h>
#include <stdio.h>

#include "vr/image.h"

/* A smooth value noise in [0, 1] (bilinear over a hashed lattice). */
static double lattice(int x, int y) {
  unsigned h = (unsigned)x * 374761393u + (unsigned)y * 668265263u;
  h = (h ^ (h >> 13)) * 1274126177u;
  return (double)((h ^ (h >> 16)) & 0xffff) / 65535.0;
}
static double noise(double x, double y) {
  int ix = (int)floor(x), iy = (int)floor(y);
  double fx = x - ix, fy = y - iy;
  fx = fx * fx * (3 - 2 * fx), fy = fy * fy * (3 - 2 * fy);
  double a = lattice(ix, iy), b = lattice(ix + 1, iy), c = lattice(ix, iy + 1), d = lattice(ix + 1, iy + 1);
  return (a + (b - a) * fx) * (1 - fy) + (c + (d - c) * fx) * fy;
}

static void mix(const double a[3], const double b[3], double t, float out[3]) {
  for (int k = 0; k < 3; k++) out[k] = (float)(a[k] + (b[k] - a[k]) * t);
}

/* Wood: growth rings along v, bent by noise, with fine pores. */
static void wood(double u, double v, float rgb[3]) {
  static const double light[3] = {0.80, 0.62, 0.42}, dark[3] = {0.52, 0.34, 0.19};
  double ring = 9 * v + 1.8 * noise(3 * u, 2 * v) + 0.4 * noise(20 * u, 40 * v);
  double t = 0.5 + 0.5 * sin(2 * M_PI * ring);
  t = pow(t, 3) * 0.8 + 0.2 * noise(200 * u, 6 * v);
  mix(light, dark, t, rgb);
}

/* Fabric: a plain weave of two yarns with slubs. */
static void fabric(double u, double v, float rgb[3], int w) {
  static const double warp[3] = {0.62, 0.58, 0.50}, weft[3] = {0.50, 0.46, 0.40};
  int x = (int)(u * w), y = (int)(v * w);
  int over = ((x / 4) + (y / 4)) & 1;
  double slub = 0.85 + 0.3 * noise(u * 40, v * 7 + over * 13);
  double shade = 0.75 + 0.25 * sin(M_PI * ((over ? x : y) % 4 + 0.5) / 4);
  mix(over ? warp : weft, over ? warp : weft, 0, rgb);
  for (int k = 0; k < 3; k++) rgb[k] = (float)fmin(1, rgb[k] * slub * shade);
}

static bool write(const char *path, int size, int which) {
  vr_image img;
  vr_error e = {0};
  if (vr_image_alloc(&img, size, size, &e)) return false;
  for (int y = 0; y < size; y++)
    for (int x = 0; x < size; x++) {
      double u = (x + 0.5) / size, v = (y + 0.5) / size;
      float *p = img.data + ((size_t)y * size + x) * 3;
      if (which == 0) wood(u, v, p);
      else fabric(u, v, p, size);
    }
  bool ok = vr_image_write_png(path, &img, 8, &e) == VR_OK;
  if (!ok) fprintf(stderr, "vr-hotel: %s\n", e.message);
  vr_image_free(&img);
  return ok;
}

bool hotel_write_textures(const char *dir) {
  char path[4200];
  snprintf(path, sizeof path, "%s/wood.png", dir);
  if (!write(path, 1024, 0)) return false;
  snprintf(path, sizeof path, "%s/fabric.png", dir);
  return write(path, 512, 1);
}
