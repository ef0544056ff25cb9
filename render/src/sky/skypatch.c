/* The Tregenza sky subdivision (vr/skypatch.h). */
#include "vr/skypatch.h"

#include <math.h>

#define PI 3.14159265358979323846

static const int COUNT[8] = {30, 30, 24, 24, 18, 12, 6, 1};

/* Band of patch k and its index within the band. */
static int band_of(int k, int *j) {
  int b = 0;
  while (b < 7 && k >= COUNT[b]) k -= COUNT[b++];
  *j = k;
  return b;
}

int vr_sky_patch_of(const double d[3]) {
  if (d[2] < 0) return VR_SKY_GROUND_PATCH;
  double alt = asin(fmin(1.0, d[2])) * 180.0 / PI;
  int b = (int)(alt / 12.0);
  if (b > 7) b = 7;
  if (b == 7) return VR_SKY_PATCHES - 1;
  double az = atan2(d[0], d[1]) * 180.0 / PI;
  if (az < 0) az += 360.0;
  double w = 360.0 / COUNT[b];
  int j = (int)floor(az / w + 0.5) % COUNT[b];
  int k = 0;
  for (int i = 0; i < b; i++) k += COUNT[i];
  return k + j;
}

void vr_sky_patch_bounds(int k, double *alt_lo, double *alt_hi, double *az_lo, double *az_hi) {
  int j, b = band_of(k, &j);
  *alt_lo = 12.0 * b;
  *alt_hi = b == 7 ? 90.0 : 12.0 * (b + 1);
  double w = 360.0 / COUNT[b];
  *az_lo = b == 7 ? 0.0 : (j - 0.5) * w;
  *az_hi = b == 7 ? 360.0 : (j + 0.5) * w;
}

void vr_sky_patch_centre(int k, double d[3]) {
  double a0, a1, z0, z1;
  vr_sky_patch_bounds(k, &a0, &a1, &z0, &z1);
  if (k == VR_SKY_PATCHES - 1) {
    d[0] = d[1] = 0, d[2] = 1;
    return;
  }
  double alt = 0.5 * (a0 + a1) * PI / 180, az = 0.5 * (z0 + z1) * PI / 180;
  d[0] = cos(alt) * sin(az), d[1] = cos(alt) * cos(az), d[2] = sin(alt);
}

double vr_sky_patch_solid_angle(int k) {
  double a0, a1, z0, z1;
  vr_sky_patch_bounds(k, &a0, &a1, &z0, &z1);
  return (z1 - z0) * PI / 180 * (sin(a1 * PI / 180) - sin(a0 * PI / 180));
}
