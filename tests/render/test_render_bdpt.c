/* Bidirectional path tracing (render integrator=bdpt) against the path
 * tracer and against an analytic caustic.
 *
 * (a) The measured spectral Cornell box (samples/cornell/cornell.scn, its
 *     spectra imported into a temporary database as the scene's comments
 *     say): an area light and diffuse walls, where path tracing is the
 *     reference.  Both integrators render the same image K = 12 times with
 *     independent seeds; the mean luminance of five regions must agree
 *     within 4 combined standard errors (taken from the spread of the K
 *     runs).  A BDPT that counted a strategy twice (a weight of 1 where MIS
 *     splits), or lost one, is off by far more than that.
 *
 * (b) A caustic from a point light, where path tracing sees nothing: an
 *     isotropic 100 cd point light 1 m above a horizontal 2 x 2 m smooth
 *     metal mirror (constant N = 0.2 + 3.5i, so its reflectance is the same
 *     at every wavelength), beside a vertical Lambertian wall (rho = 0.5)
 *     2 m away, and a black 1.2 m square 5 cm above the light that shades
 *     the upper part of the wall from it.  By the image method (a plane
 *     mirror forms a virtual image of the source at its mirror point:
 *     Hecht, Optics, ch. 5, plane mirrors) and the inverse-square and
 *     cosine laws (as CIE 171:2006 uses them for its point-source cases), a
 *     wall point P receives
 *       E(P) = I cos(theta) / d^2  +  R(theta_i) I cos(theta') / d'^2
 *     from the light at (0, 0, 1) and its image at (0, 0, -1), each term
 *     only where its line to P is not blocked (the second must also cross
 *     the mirror); R is the unpolarised Fresnel reflectance of the metal
 *     (Born & Wolf, Principles of Optics, 7th ed., ch. 14, the Fresnel
 *     formulae with a complex index) at the angle theta_i on the mirror.
 *     The wall and its mirror image are coplanar, so no light goes wall ->
 *     mirror -> wall, and the shade is black: the wall's luminance is
 *     exactly rho E / pi.  On a patch of the wall in the shade's shadow
 *     and in the mirror's light, BDPT (16 runs, independent seeds) must
 *     give that within 4 standard errors; the path tracer must see nothing
 *     there (it cannot reach a point light through a mirror).
 *
 * (c) What BDPT handles besides diffuse walls, against the path tracer
 *     (which finds the same light from an area lamp, only more slowly): a
 *     lamp above a floor, half of it behind a thin pane (the pane is not a
 *     path vertex: connections cross it with its transmittance, walks with
 *     their choice of going through), a dispersive absorbing glass sphere
 *     (refraction keeps the hero wavelength; absorption inside), and a
 *     rough metal wall (glossy vertices are connected).  The mean luminance
 *     of each of 16 image regions must agree within 4 combined standard
 *     errors, as in (a).
 *
 * (d) The same on a daylit room: the sun and a CIE clear sky through a
 *     window pane, which BDPT leaves to its camera subpaths (next-event
 *     estimation and escapes, as the path tracer), with a spot lamp and a
 *     point lamp, which it traces from both ends, and a rough metal plate
 *     on the floor (glossy: the path tracer sees its reflections of the
 *     lamps too).  16 regions, 4 standard errors. */
#include <complex.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "vr/material_io.h"
#include "vr/matdb.h"
#include "vr/material.h"
#include "vr/render.h"
#include "vr/scene.h"
#include "cornell_import.h"
#include "vr/spectrum.h"

static char dbpath[256];
static vr_matdb *db;

static vr_spectrum *flat(double v) {
  double nm[2] = {250, 2500}, val[2] = {v, v};
  return vr_spectrum_create(2, nm, val, NULL);
}

#define MIRROR_N 0.2
#define MIRROR_K 3.5

static int setup(void **state) {
  (void)state;
  snprintf(dbpath, sizeof dbpath, "/tmp/vr_test_bdpt_%d.db", (int)getpid());
  unlink(dbpath);
  vr_error err = {0};
  if (vr_matdb_open(dbpath, 0, &db, &err)) return -1;
  vr_material *m = vr_material_create("flat-metal", VR_KIND_CONDUCTOR, &err);
  vr_material_add_spectrum(m, "n", flat(MIRROR_N), &err);
  vr_material_add_spectrum(m, "k", flat(MIRROR_K), &err);
  if (vr_matdb_save(db, m, &err)) return -1;
  vr_material_destroy(m);
  /* Glass of constant n 1.52 for the pane; a dispersive, weakly absorbing
   * glass (n from 1.75 at 250 nm to 1.45 at 2500 nm, k = 2e-8: about 0.6
   * /m at 400 nm) for the sphere. */
  const double glass[2][3] = {{1.52, 1.52, 0}, {1.75, 1.45, 2e-8}};
  const char *gname[2] = {"glass-152", "disp-glass"};
  for (int i = 0; i < 2; i++) {
    double nm[2] = {250, 2500}, n[2] = {glass[i][0], glass[i][1]};
    m = vr_material_create(gname[i], VR_KIND_DIELECTRIC, &err);
    vr_material_add_spectrum(m, "n", vr_spectrum_create(2, nm, n, NULL), &err);
    vr_material_add_spectrum(m, "k", flat(glass[i][2]), &err);
    if (vr_matdb_save(db, m, &err)) return -1;
    vr_material_destroy(m);
  }
  return cornell_import_all(db);
}

static int teardown(void **state) {
  (void)state;
  vr_matdb_close(db);
  unlink(dbpath);
  return 0;
}

static vr_render_result *render(vr_scene *s) {
  vr_render_options o;
  vr_render_options_default(&o);
  o.threads = 2;
  vr_render_result *r = NULL;
  vr_error err = {0};
  if (vr_render_scene(s, db, &o, &r, &err)) fail_msg("render: %s", err.message);
  return r;
}

/* Mean luminance over the pixels [x0, x1) x [y0, y1). */
static double region_Y(const vr_render_result *r, int x0, int y0, int x1, int y1) {
  double sum = 0;
  for (int y = y0; y < y1; y++)
    for (int x = x0; x < x1; x++) sum += r->xyz[3 * ((size_t)y * r->width + x) + 1];
  return sum / ((x1 - x0) * (y1 - y0));
}

/* Mean and standard error of the mean of n values. */
static void mean_se(const double *v, int n, double *mean, double *se) {
  double m = 0, s = 0;
  for (int i = 0; i < n; i++) m += v[i];
  m /= n;
  for (int i = 0; i < n; i++) s += (v[i] - m) * (v[i] - m);
  *mean = m;
  *se = sqrt(s / (n - 1) / n);
}

enum { RUNS = 12, RUNS_CAUSTIC = 16, NREG = 5 };

/* Region means of RUNS renders of the Cornell box at 32 x 32 by one
 * integrator, seeds 1 .. RUNS. */
static void cornell_regions(vr_integrator integ, int spp, double mean[NREG], double se[NREG]) {
  char path[1024];
  snprintf(path, sizeof path, "%s/samples/cornell/cornell.scn", VR_SOURCE_DIR);
  /* Back wall, floor, ceiling beside the lamp, red and green walls (pixels
   * of the 32 x 32 image). */
  static const int reg[NREG][4] = {
      {10, 8, 22, 20}, {10, 26, 22, 31}, {4, 1, 10, 3}, {1, 10, 4, 22}, {28, 10, 31, 22}};
  double v[NREG][RUNS];
  for (int k = 0; k < RUNS; k++) {
    vr_scene *s = NULL;
    vr_error err = {0};
    if (vr_scene_read(path, &s, &err)) fail_msg("%s", err.message);
    s->camera.width = s->camera.height = 32;
    s->settings.integrator = integ;
    s->settings.spp = spp;
    s->settings.max_depth = 16;
    s->settings.seed = 1 + (unsigned)k;
    /* Independent samples: the 4-sigma bound and the 3 % precision
     * precondition were set on them (the samplers: test_sampler.c). */
    s->settings.sampler = VR_SAMPLER_INDEPENDENT;
    size_t nsensors = s->nsensors;
    s->nsensors = 0; /* the image only */
    vr_render_result *r = render(s);
    for (int i = 0; i < NREG; i++)
      v[i][k] = region_Y(r, reg[i][0], reg[i][1], reg[i][2], reg[i][3]);
    vr_render_result_destroy(r);
    s->nsensors = nsensors;
    vr_scene_destroy(s);
  }
  for (int i = 0; i < NREG; i++) mean_se(v[i], RUNS, &mean[i], &se[i]);
}

static void test_cornell_bdpt_matches_path(void **state) {
  (void)state;
  static const char *names[NREG] = {"back wall", "floor", "ceiling", "red wall", "green wall"};
  double mb[NREG], sb[NREG], mp[NREG], sp[NREG];
  cornell_regions(VR_INT_BDPT, 16, mb, sb);
  cornell_regions(VR_INT_PATH, 32, mp, sp);
  for (int i = 0; i < NREG; i++) {
    double se = sqrt(sb[i] * sb[i] + sp[i] * sp[i]);
    printf("%-10s bdpt %9.4f +- %.4f  path %9.4f +- %.4f cd/m2  (%+.2f sigma)\n", names[i], mb[i],
           sb[i], mp[i], sp[i], (mb[i] - mp[i]) / se);
    assert_true(mp[i] > 1); /* every region is lit */
    assert_true(se < 0.03 * mp[i]); /* and the comparison is a sharp one */
    if (fabs(mb[i] - mp[i]) > 4 * se)
      fail_msg("%s: bdpt %.4f vs path %.4f cd/m2, more than 4 standard errors (%.4f) apart",
               names[i], mb[i], mp[i], se);
  }
}

/* The caustic scene: mirror at z = 0, light at (0, 0, 1), wall in the plane
 * x = 2 facing -x; the camera looks at the wall from (-1, 0, 1.6). */
#define WALL_X 2.0
#define LIGHT_Z 1.0
#define INTENSITY 100.0
#define RHO 0.5
#define CAM_W 48
#define CAM_H 36
#define FOV 50.0
#define SHADE_Z 1.05
#define SHADE_HALF 0.6
static const double CAM_FROM[3] = {-1, 0, 1.6}, CAM_TO[3] = {2, 0, 1.6};

static vr_scene *caustic_scene(const char *integrator, int spp, unsigned seed) {
  char text[2048];
  snprintf(text, sizeof text,
           "camera pinhole from=%g,%g,%g to=%g,%g,%g fov=%g resolution=%dx%d\n"
           "material mirror db:flat-metal\n"
           "material wall lambert reflectance=%g\n"
           "material shade black\n"
           "rect center=0,0,%g normal=0,0,1 size=%g,%g material=shade\n"
           "rect center=0,0,0 normal=0,0,1 size=2,2 material=mirror\n"
           "rect center=%g,0,1.5 normal=-1,0,0 size=4,3 material=wall\n"
           "light point position=0,0,%g intensity=%gcd\n"
           "render integrator=%s spp=%d depth=6 seed=%u\n",
           CAM_FROM[0], CAM_FROM[1], CAM_FROM[2], CAM_TO[0], CAM_TO[1], CAM_TO[2], FOV, CAM_W,
           CAM_H, RHO, SHADE_Z, 2 * SHADE_HALF, 2 * SHADE_HALF, WALL_X, LIGHT_Z, INTENSITY,
           integrator, spp, seed);
  vr_scene *s = NULL;
  vr_error err = {0};
  if (vr_scene_parse(text, strlen(text), "caustic.scn", &s, &err)) fail_msg("%s", err.message);
  return s;
}

/* Unpolarised Fresnel reflectance of air -> N = n + ik at cos_i (Born &
 * Wolf, 7th ed., ch. 14): r_s = (c - w)/(c + w), r_p = (N^2 c - w)/(N^2 c + w),
 * w = sqrt(N^2 - sin^2). */
static double fresnel(double cos_i) {
  double complex N = MIRROR_N + MIRROR_K * I, N2 = N * N;
  double s2 = 1 - cos_i * cos_i;
  double complex w = csqrt(N2 - s2);
  double complex rs = (cos_i - w) / (cos_i + w), rp = (N2 * cos_i - w) / (N2 * cos_i + w);
  double a = cabs(rs), b = cabs(rp);
  return 0.5 * (a * a + b * b);
}

/* Whether the segment from a to b crosses the shade. */
static bool shaded(const double a[3], const double b[3]) {
  if ((a[2] - SHADE_Z) * (b[2] - SHADE_Z) >= 0) return false;
  double t = (SHADE_Z - a[2]) / (b[2] - a[2]);
  double x = a[0] + t * (b[0] - a[0]), y = a[1] + t * (b[1] - a[1]);
  return fabs(x) <= SHADE_HALF && fabs(y) <= SHADE_HALF;
}

/* Illuminance at wall point (WALL_X, y, z): direct, and by the mirror. */
static void wall_E(double y, double z, double *direct, double *mirror) {
  const double light[3] = {0, 0, LIGHT_Z}, p[3] = {WALL_X, y, z};
  double d2 = WALL_X * WALL_X + y * y + (z - LIGHT_Z) * (z - LIGHT_Z);
  *direct = shaded(light, p) ? 0 : INTENSITY * (WALL_X / sqrt(d2)) / d2;
  /* The image at (0, 0, -LIGHT_Z); the line to P meets z = 0 at s. */
  double s = LIGHT_Z / (z + LIGHT_Z), mx = s * WALL_X, my = s * y;
  const double m[3] = {mx, my, 0};
  *mirror = 0;
  if (fabs(mx) <= 1 && fabs(my) <= 1 && !shaded(light, m) && !shaded(m, p)) {
    double e2 = WALL_X * WALL_X + y * y + (z + LIGHT_Z) * (z + LIGHT_Z), e = sqrt(e2);
    *mirror = fresnel((z + LIGHT_Z) / e) * INTENSITY * (WALL_X / e) / e2;
  }
}

/* The analytic mean luminance over the pixels [x0, x1) x [y0, y1): each
 * pixel's 8 x 8 sub-points projected onto the wall with the camera's frame
 * (vr-render's pinhole: fov horizontal, y down), rho E / pi. */
static void analytic_Y(int x0, int y0, int x1, int y1, double *total, double *direct_only) {
  double w[3], u[3], v[3], up[3] = {0, 0, 1}, l = 0;
  for (int a = 0; a < 3; a++) w[a] = CAM_TO[a] - CAM_FROM[a], l += w[a] * w[a];
  for (int a = 0; a < 3; a++) w[a] /= sqrt(l);
  u[0] = w[1] * up[2] - w[2] * up[1], u[1] = w[2] * up[0] - w[0] * up[2],
  u[2] = w[0] * up[1] - w[1] * up[0];
  l = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
  for (int a = 0; a < 3; a++) u[a] /= l;
  v[0] = u[1] * w[2] - u[2] * w[1], v[1] = u[2] * w[0] - u[0] * w[2],
  v[2] = u[0] * w[1] - u[1] * w[0];
  double th = tan(0.5 * FOV * M_PI / 180), aspect = (double)CAM_H / CAM_W, sum = 0, sumd = 0;
  int n = 0;
  for (int py = y0; py < y1; py++)
    for (int px = x0; px < x1; px++)
      for (int j = 0; j < 8; j++)
        for (int i = 0; i < 8; i++) {
          double fx = px + (i + 0.5) / 8, fy = py + (j + 0.5) / 8;
          double sx = (2 * fx / CAM_W - 1) * th, sy = (1 - 2 * fy / CAM_H) * th * aspect, d[3];
          for (int a = 0; a < 3; a++) d[a] = w[a] + sx * u[a] + sy * v[a];
          double t = (WALL_X - CAM_FROM[0]) / d[0];
          double y = CAM_FROM[1] + t * d[1], z = CAM_FROM[2] + t * d[2], ed, em;
          wall_E(y, z, &ed, &em);
          sum += RHO * (ed + em) / M_PI;
          sumd += RHO * ed / M_PI;
          n++;
        }
  *total = sum / n;
  *direct_only = sumd / n;
}

static void test_point_light_caustic(void **state) {
  (void)state;
  /* A patch of the wall from z = 1.75 to 2.5, 1.1 m wide: the mirror's
   * light reaches the wall above z = 1, the shade hides the light from it
   * above z = 1.17. */
  const int x0 = 15, y0 = 4, x1 = 33, y1 = 15;
  double want, direct;
  analytic_Y(x0, y0, x1, y1, &want, &direct);
  assert_true(direct == 0 && want > 0.5); /* all of it from the mirror */
  double vb[RUNS_CAUSTIC], vp[RUNS_CAUSTIC];
  for (int k = 0; k < RUNS_CAUSTIC; k++) {
    vr_scene *s = caustic_scene("bdpt", 64, 1 + (unsigned)k);
    vr_render_result *r = render(s);
    vb[k] = region_Y(r, x0, y0, x1, y1);
    vr_render_result_destroy(r);
    vr_scene_destroy(s);
    s = caustic_scene("path", 64, 1 + (unsigned)k);
    r = render(s);
    vp[k] = region_Y(r, x0, y0, x1, y1);
    vr_render_result_destroy(r);
    vr_scene_destroy(s);
  }
  double mb, sb, mp, sp;
  mean_se(vb, RUNS_CAUSTIC, &mb, &sb);
  mean_se(vp, RUNS_CAUSTIC, &mp, &sp);
  printf("wall patch: analytic %.5f cd/m2 (direct %.5f + mirror %.5f); bdpt %.5f +- %.5f; "
         "path %.5f +- %.5f\n",
         want, direct, want - direct, mb, sb, mp, sp);
  assert_true(sb < 0.03 * want); /* a sharp comparison */
  if (fabs(mb - want) > 4 * sb)
    fail_msg("bdpt %.5f +- %.5f cd/m2, the image method gives %.5f", mb, sb, want);
  /* The path tracer sees none of it. */
  if (!(mp < 1e-3 * want)) fail_msg("path %.5f +- %.5f cd/m2, expected 0", mp, sp);
}

static const char *GLASS_SCENE =
    "camera pinhole from=0,-3.2,2.2 to=0,0,0.3 fov=55 resolution=32x24\n"
    "material floor lambert reflectance=0.6\n"
    "material lamp black\n"
    "material pane db:glass-152 thickness=4mm\n"
    "material glass db:disp-glass\n"
    "material metal db:flat-metal roughness=0.3\n"
    "rect center=0,0,0 normal=0,0,1 size=4,4 material=floor\n"
    "rect center=0,2,1 normal=0,-1,0 size=4,2 material=metal\n"
    "rect center=0,0,2.2 normal=0,0,-1 size=0.8,0.8 material=lamp emission=2000cd/m2\n"
    "rect center=-0.7,0,1.4 normal=0,0,1 size=1.4,3 material=pane\n"
    "sphere center=0.7,0,0.45 radius=0.45 material=glass\n"
    "render integrator=%s spp=%d depth=12 seed=%u\n";

static const char *ROOM_SCENE =
    "camera pinhole from=0.2,-1.8,1.4 to=0,1,1 fov=70 resolution=32x24\n"
    "material wall lambert reflectance=0.6\n"
    "material pane db:glass-152 thickness=4mm\n"
    "material metal db:flat-metal roughness=0.2\n"
    "rect center=0,0,0 normal=0,0,1 size=4,4 material=wall\n"
    "rect center=0,0,2.6 normal=0,0,-1 size=4,4 material=wall\n"
    "rect center=-2,0,1.3 normal=1,0,0 size=4,2.6 material=wall\n"
    "rect center=2,0,1.3 normal=-1,0,0 size=4,2.6 material=wall\n"
    "rect center=0,-2,1.3 normal=0,1,0 size=4,2.6 material=wall\n"
    /* the north wall, with a 1 x 1 m window glazed by the pane */
    "rect center=-1.25,2,1.3 normal=0,-1,0 size=1.5,2.6 material=wall\n"
    "rect center=1.25,2,1.3 normal=0,-1,0 size=1.5,2.6 material=wall\n"
    "rect center=0,2,0.4 normal=0,-1,0 size=1,0.8 material=wall\n"
    "rect center=0,2,2.2 normal=0,-1,0 size=1,0.8 material=wall\n"
    "rect center=0,2,1.3 normal=0,-1,0 size=1,1 material=pane\n"
    "rect center=1,-1,0.01 normal=0,0,1 size=0.6,0.6 material=metal\n"
    "light sun altitude=40 azimuth=10 illuminance=60000lx\n"
    "sky cie type=12 illuminance=10000\n"
    "light spot position=-1,-1,2.5 direction=0,0,-1 cone=30 falloff=10 intensity=500lm\n"
    "light point position=1.2,0.5,1.0 intensity=50cd\n"
    "render integrator=%s spp=%d depth=8 seed=%u\n";

/* The 4 x 4 region means of RUNS renders of scene (a format taking the
 * integrator, spp and seed). */
static void grid_regions(const char *scene, const char *integrator, int spp, double mean[16],
                         double se[16]) {
  double v[16][RUNS];
  for (int k = 0; k < RUNS; k++) {
    char text[4096];
    snprintf(text, sizeof text, scene, integrator, spp, 1 + (unsigned)k);
    vr_scene *s = NULL;
    vr_error err = {0};
    if (vr_scene_parse(text, strlen(text), "glass.scn", &s, &err)) fail_msg("%s", err.message);
    vr_render_result *r = render(s);
    for (int i = 0; i < 16; i++) {
      int gx = i % 4, gy = i / 4, w = r->width / 4, h = r->height / 4;
      v[i][k] = region_Y(r, gx * w, gy * h, (gx + 1) * w, (gy + 1) * h);
    }
    vr_render_result_destroy(r);
    vr_scene_destroy(s);
  }
  for (int i = 0; i < 16; i++) mean_se(v[i], RUNS, &mean[i], &se[i]);
}

/* Both integrators on scene, region by region. */
static void grid_compare(const char *scene, int bdpt_spp, int path_spp) {
  double mb[16], sb[16], mp[16], sp[16];
  grid_regions(scene, "bdpt", bdpt_spp, mb, sb);
  grid_regions(scene, "path", path_spp, mp, sp);
  for (int i = 0; i < 16; i++) {
    double se = sqrt(sb[i] * sb[i] + sp[i] * sp[i]);
    printf("region %2d  bdpt %9.4f +- %.4f  path %9.4f +- %.4f cd/m2  (%+.2f sigma)\n", i, mb[i],
           sb[i], mp[i], sp[i], (mb[i] - mp[i]) / se);
    assert_true(mp[i] > 1);
    if (fabs(mb[i] - mp[i]) > 4 * se)
      fail_msg("region %d: bdpt %.4f vs path %.4f cd/m2, more than 4 standard errors (%.4f) apart",
               i, mb[i], mp[i], se);
  }
}

static void test_glass_bdpt_matches_path(void **state) {
  (void)state;
  grid_compare(GLASS_SCENE, 32, 64);
}

static void test_daylit_room_bdpt_matches_path(void **state) {
  (void)state;
  grid_compare(ROOM_SCENE, 32, 64);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_point_light_caustic),
      cmocka_unit_test(test_cornell_bdpt_matches_path),
      cmocka_unit_test(test_glass_bdpt_matches_path),
      cmocka_unit_test(test_daylit_room_bdpt_matches_path),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
