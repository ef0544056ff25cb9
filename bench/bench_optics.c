/* Prints how long the core's hot kernels take: a coherent thin-film solve,
 * a thick-slab evaluation, an incoherent film-on-glass solve and a
 * tristimulus integration.  Figures go to docs/benchmarks.md. */
#include "vr/colour.h"
#include "vr/optics.h"

#include <stdio.h>
#include <time.h>

static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int main(void) {
  volatile double sink = 0;
  const int N = 200000;
  vr_layer five[5] = {{1.0, 0, 0}, {1.38, 99.6, 0}, {2.35 + 0.001 * I, 58.5, 0}, {1.46, 120, 0},
                      {3.9 + 0.02 * I, 0, 0}};
  double t0 = now();
  for (int i = 0; i < N; i++) {
    vr_tmm_result r;
    vr_tmm_coherent(five, 5, 0.01 * (i % 150), 400 + (i % 400), (vr_pol)(i & 1), &r, NULL, NULL);
    sink += r.R;
  }
  double t_tmm = (now() - t0) / N;

  t0 = now();
  for (int i = 0; i < N; i++) {
    vr_slab_result s;
    vr_slab(1.0, 1.52 + 1e-7 * I, 4e6, 0.01 * (i % 150), 400 + (i % 400), &s, NULL);
    sink += s.T[0];
  }
  double t_slab = (now() - t0) / N;

  vr_layer coated[5] = {{1.0, 0, 0}, {2.0 + 0.001 * I, 40, 0}, {0.1 + 3.0 * I, 10, 0},
                        {1.52 + 1e-7 * I, 4e6, 1}, {1.0, 0, 0}};
  t0 = now();
  for (int i = 0; i < N; i++) {
    vr_tmm_result r;
    vr_stack_solve(coated, 5, 0.01 * (i % 150), 400 + (i % 400), (vr_pol)(i & 1), &r, NULL);
    sink += r.T;
  }
  double t_inc = (now() - t0) / N;

  vr_spectrum *d65 = vr_illuminant("D65", NULL);
  vr_spectrum *refl = vr_spectrum_create_uniform(380, 10, 36, 0.5, NULL);
  const int M = 2000;
  t0 = now();
  for (int i = 0; i < M; i++) {
    double xyz[3];
    refl->value[i % 36] = 0.001 * (i % 1000);
    vr_xyz_reflectance(refl, d65, VR_CIE1931_2DEG, xyz);
    sink += xyz[1];
  }
  double t_xyz = (now() - t0) / M;
  vr_spectrum_destroy(d65);
  vr_spectrum_destroy(refl);

  printf("kernel                                   time per call\n");
  printf("coherent 5-layer stack, one polarisation %10.1f ns\n", t_tmm * 1e9);
  printf("thick slab, s and p                      %10.1f ns\n", t_slab * 1e9);
  printf("2 films on incoherent glass, one pol.    %10.1f ns\n", t_inc * 1e9);
  printf("reflectance -> XYZ (471 CMF rows)        %10.1f us\n", t_xyz * 1e6);
  return sink == 12345.678 ? 1 : 0;
}
