/* A point light's caustic under a glass slab, the case a window scene is
 * made of, in whole renders (integrator=progressive, and bdpt):
 *
 *   - a slab far wider than its height above the floor: right under the
 *     light the floor's irradiance is the plate's paraxial answer
 *     E = I T tau / (d - t (1 - 1/n))^2: a ray at a small angle u crosses
 *     the thickness t at u/n, as if through t/n of air, so the floor sees
 *     the source from d - t (1 - 1/n) (the paraxial shift of a
 *     plane-parallel plate),
 *     with T = (1 - R) / (1 + R), R = ((n - 1) / (n + 1))^2 (the two faces
 *     and their internal reflections at normal incidence) and tau the
 *     internal transmittance; n of Schott N-BK7 from Schott's Sellmeier
 *     coefficients, k from the database's copy of Schott's catalogue;
 *   - a slab only 0.6 m wide: its polished sides reflect totally the
 *     light that reaches them from inside (at over 41.8 degrees from their
 *     normal for n = 1.5) and fold it back into bands through the light's
 *     foot, so the floor about the foot gets over a third more than under
 *     a wide slab.  The reference is a second, independent tracer written
 *     here for this one geometry (rays from the light, exact Fresnel at
 *     every face, the box's six planes by hand);
 *   - BDPT, unbiased, against the same tracer;
 *   - a floor lit through a dispersive slab and seen through it: SPPM
 *     against the path tracer (the factor that stands for the wavelengths
 *     a refraction drops must count once when camera path and photon both
 *     refract, since they share the iteration's hero).
 * This geometry was once taken for a transport fault (a bright cross
 * through the light's foot under a slab, docs/benchmarks.md): it is the
 * slab's edges, and the tracer below reproduces it. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "bsdf_test_util.h"
#undef I /* complex.h's, from bsdf_test_util.h: here I is a luminous intensity */
#include "render_test_util.h"
#include "vr/colour.h"

static vr_matdb *db;
static char dbpath[64];

/* The seeded library (N-BK7) and a dispersionless glass of n = 1.5. */
static int setup(void **state) {
  (void)state;
  db = temp_db(dbpath, sizeof dbpath);
  vr_material *m = flat_nk("glass-150", VR_KIND_DIELECTRIC, 1.5, 0.0);
  vr_error err = {0};
  vr_status st = vr_matdb_save(db, m, &err);
  vr_material_destroy(m);
  return st ? -1 : 0;
}

static int teardown(void **state) {
  (void)state;
  temp_db_close(db, dbpath);
  return 0;
}

/* The mean luminance Y (cd/m2) of the image of scene text scn, rendered
 * with the test's database on one sub-domain and two threads. */
static double mean_y(const char *scn) {
  vr_scene *s = parse_text(scn, "slab.scn");
  vr_render_result *r = render_scene_with(s, db, 1, 2, false, false);
  double sum = 0;
  size_t n = (size_t)r->width * (size_t)r->height;
  for (size_t i = 0; i < n; i++) sum += r->xyz[3 * i + 1];
  vr_render_result_destroy(r);
  vr_scene_destroy(s);
  return sum / (double)n;
}

/* The scene: a floor of reflectance 0.05 at z = 0 (low, so that light
 * going back and forth between floor and slab stays near 0.2 %), the
 * slab `slab` (scene lines), a 100 cd point light at (0, 0, 1), and a
 * camera at (0, 0, 0.4) looking straight down with field `fov`: its
 * pixels cover equal areas of the floor, so the image's mean is the mean
 * radiance over a square of half side 0.4 tan(fov / 2) about the foot. */
static double foot_radiance(const char *glass, const char *slab, const char *light, double fov,
                            int res, const char *render) {
  char scn[2048];
  snprintf(scn, sizeof scn,
           "material floor lambert reflectance=0.05\n"
           "material glass db:%s model=interfaces\n"
           "rect center=0,0,0 normal=0,0,1 size=8,8 material=floor\n"
           "%s"
           "%s\n"
           "camera pinhole from=0,0,0.4 to=0,0,0 up=0,1,0 fov=%g resolution=%dx%d\n"
           "render range=400,700 depth=16 seed=5 %s\n",
           glass, slab, light, fov, res, res, render);
  return mean_y(scn);
}

/* Schott N-BK7, Sellmeier (Schott data sheet; refractiveindex.info). */
static double n_bk7(double um) {
  double l2 = um * um;
  return sqrt(1 + 1.03961212 * l2 / (l2 - 0.00600069867) + 0.231792344 * l2 / (l2 - 0.0200179144) +
              1.01046945 * l2 / (l2 - 103.560653));
}

/* A spot of 5 degrees half angle sends every photon near the foot (the
 * rays that reach the viewed square leave within 1.2 degrees of the axis),
 * so the estimate there is not starved. */
#define SPOT "light spot position=0,0,1 direction=0,0,-1 cone=5 intensity=100cd"

static void test_plate_formula(void **state) {
  (void)state;
  const double I = 100, d = 1.0, t = 0.05, rho = 0.05;
  /* Y of the foot's radiance, D65 x ybar weighted over the render's
   * 400-700 nm: the plate formula times the internal transmittance
   * exp(-4 pi k t / lambda) of the 5 cm of glass, k the database's
   * (Schott's catalogue, through refractiveindex.info; about 0.9 % lost). */
  vr_error err = {0};
  vr_material *bk7 = db_load(db, "N-BK7");
  vr_spectrum *d65 = vr_illuminant("D65", &err);
  assert_non_null(d65);
  double num = 0, den = 0, tau555 = 0;
  for (double nm = 400.5; nm < 700; nm += 1) {
    double xyz[3], nn, k;
    vr_cmf_eval(VR_CIE1931_2DEG, nm, xyz);
    assert_int_equal(vr_material_nk(bk7, nm, false, &nn, &k, NULL, &err), VR_OK);
    double n = n_bk7(nm / 1000), R = (n - 1) / (n + 1) * ((n - 1) / (n + 1)), T = (1 - R) / (1 + R);
    double dd = d - t * (1 - 1 / n), tau = exp(-4 * M_PI * k * t / (nm * 1e-9));
    if (fabs(nm - 555.5) < 0.1) tau555 = tau;
    double w = vr_spectrum_eval(d65, nm, VR_INTERP_LINEAR) * xyz[1];
    num += w * T * tau / (dd * dd);
    den += w;
  }
  vr_material_destroy(bk7);
  vr_spectrum_destroy(d65);
  double want = rho / M_PI * I * num / den;
  double got = foot_radiance("N-BK7", "box min=-2,-2,0.5 max=2,2,0.55 material=glass\n", SPOT, 4,
                             8, "integrator=progressive spp=128 photons=100000");
  double open =
      foot_radiance("N-BK7", "", SPOT, 4, 8, "integrator=progressive spp=16 photons=10000");
  print_message("    4 m slab, 5 cm N-BK7 (internal transmittance %.4f at 555 nm): foot %.4f "
                "cd/m2, plate formula %.4f (%+.2f %%); no slab %.4f, I rho/(pi d^2) %.4f\n",
                tau555, got, want, 100 * (got / want - 1), open, rho / M_PI * I);
  if (fabs(got / want - 1) > 0.01)
    fail_msg("under a wide slab the foot's radiance %.4f is not within 1 %% of the plate "
             "formula's %.4f",
             got, want);
  if (fabs(open / (rho / M_PI * I) - 1) > 0.01) fail_msg("without the slab: %.4f", open);
}

/* ---- the independent reference: one geometry, plain Monte Carlo ---- */

typedef struct ref_rng {
  uint64_t s;
} ref_rng;

static double ref_u(ref_rng *g) { /* splitmix64 (Steele, Lea & Flood 2014) */
  uint64_t z = (g->s += 0x9e3779b97f4a7c15ull);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  z ^= z >> 31;
  return (double)(z >> 11) * 0x1.0p-53;
}

/* Unpolarised Fresnel reflectance from index n1 into n2 at cos ci;
 * *ct the transmitted cosine (R = 1 past the critical angle). */
static double ref_fresnel(double ci, double n1, double n2, double *ct) {
  double s = n1 / n2 * sqrt(fmax(0, 1 - ci * ci));
  if (s >= 1) return 1;
  *ct = sqrt(1 - s * s);
  double rs = (n1 * ci - n2 * *ct) / (n1 * ci + n2 * *ct);
  double rp = (n2 * ci - n1 * *ct) / (n2 * ci + n1 * *ct);
  return 0.5 * (rs * rs + rp * rp);
}

/* Mean irradiance (lx) over |x|, |y| < h on the floor z = 0 under the
 * box |x|, |y| <= w, z0 <= z <= z1 of index n, from a point light of I cd
 * at (0, 0, 1): rays sampled uniformly in the cone that holds the box's
 * top, followed through every reflection and refraction (chosen with the
 * Fresnel probabilities), counted where they land. */
static double ref_slab(double w, double z0, double z1, double n, double h, double I, long rays) {
  ref_rng g = {12345};
  double top = 1 - z1, cmin = top / sqrt(top * top + 2 * w * w);
  double omega = 2 * M_PI * (1 - cmin), lo[3] = {-w, -w, z0}, hi[3] = {w, w, z1};
  long hits = 0;
  for (long i = 0; i < rays; i++) {
    double c = cmin + (1 - cmin) * ref_u(&g), s = sqrt(1 - c * c), ph = 2 * M_PI * ref_u(&g);
    double p[3] = {0, 0, 1}, d[3] = {s * cos(ph), s * sin(ph), -c};
    bool inside = false;
    for (int bounce = 0; bounce < 100; bounce++) {
      int axis = -1;
      double tb = INFINITY, side = 0;
      if (inside) { /* the nearest face ahead */
        for (int a = 0; a < 3; a++) {
          if (d[a] == 0) continue;
          double ta = ((d[a] > 0 ? hi[a] : lo[a]) - p[a]) / d[a];
          if (ta < tb) tb = ta, axis = a, side = d[a] > 0 ? 1 : -1;
        }
      } else { /* slabs: entry t0 must lie before the exit and ahead */
        double t0 = -INFINITY, t1 = INFINITY;
        for (int a = 0; a < 3; a++) {
          if (d[a] == 0) {
            if (p[a] < lo[a] || p[a] > hi[a]) t0 = INFINITY;
            continue;
          }
          double ta = (lo[a] - p[a]) / d[a], tc = (hi[a] - p[a]) / d[a];
          double sg = -1;
          if (ta > tc) {
            double x = ta;
            ta = tc, tc = x, sg = 1;
          }
          if (ta > t0) t0 = ta, axis = a, side = sg;
          t1 = fmin(t1, tc);
        }
        if (t0 <= t1 && t0 > 1e-12) tb = t0;
      }
      if (!isfinite(tb)) {
        if (!inside && d[2] < 0) {
          double t = -p[2] / d[2], x = p[0] + t * d[0], y = p[1] + t * d[1];
          if (fabs(x) < h && fabs(y) < h) hits++;
        }
        break;
      }
      for (int a = 0; a < 3; a++) p[a] += tb * d[a];
      p[axis] = side > 0 ? hi[axis] : lo[axis];
      double ct = 0, R = ref_fresnel(fabs(d[axis]), inside ? n : 1, inside ? 1 : n, &ct);
      if (ref_u(&g) < R) {
        d[axis] = -d[axis];
        continue;
      }
      /* Refraction: the tangential part scales by n1/n2, the normal part
       * is the transmitted cosine along the direction of travel. */
      double k = inside ? n : 1 / n, sg = d[axis] > 0 ? 1 : -1;
      for (int a = 0; a < 3; a++) d[a] *= k;
      d[axis] = sg * ct;
      inside = !inside;
    }
  }
  return (double)hits * I * omega / (double)rays / (4 * h * h);
}

#define POINT "light point position=0,0,1 intensity=100cd"
#define BOX "box min=-0.3,-0.3,0.5 max=0.3,0.3,0.55 material=glass\n"

/* The square under a 40-degree view (half side 0.146 m) takes in the
 * bands the edges throw about the foot. */
static void test_slab_edges(void **state) {
  (void)state;
  const double rho = 0.05, h = 0.4 * tan(20 * M_PI / 180);
  double want = rho / M_PI * ref_slab(0.3, 0.5, 0.55, 1.5, h, 100, 8000000);
  double wide = rho / M_PI * ref_slab(3.0, 0.5, 0.55, 1.5, h, 100, 8000000);
  double got = foot_radiance("glass-150", BOX, POINT, 40, 32,
                             "integrator=progressive spp=128 photons=100000");
  print_message("    0.6 m box, n = 1.5, 0.29 m square: SPPM %.4f cd/m2, independent tracer "
                "%.4f (%+.2f %%); the tracer under a 6 m slab %.4f\n",
                got, want, 100 * (got / want - 1), wide);
  if (fabs(got / want - 1) > 0.02)
    fail_msg("under a 0.6 m box the floor's radiance %.4f is not within 2 %% of the independent "
             "tracer's %.4f",
             got, want);
  if (!(want > 1.05 * wide)) fail_msg("the tracer finds no edge light: %.4f, %.4f", want, wide);
}

/* BDPT (light tracing carries this light: no other strategy reaches a
 * point light through two refractions) against the same tracer. */
static void test_bdpt_agrees(void **state) {
  (void)state;
  const double rho = 0.05, h = 0.4 * tan(20 * M_PI / 180);
  double want = rho / M_PI * ref_slab(0.3, 0.5, 0.55, 1.5, h, 100, 8000000);
  double bd = foot_radiance("glass-150", BOX, POINT, 40, 32, "integrator=bdpt spp=2048");
  print_message("    0.6 m box, 0.29 m square: BDPT %.4f cd/m2, independent tracer %.4f (%+.2f %%)\n",
                bd, want, 100 * (bd / want - 1));
  if (fabs(bd / want - 1) > 0.02)
    fail_msg("BDPT %.4f and the independent tracer %.4f differ by over 2 %%", bd, want);
}

/* Light that crosses a dispersive slab and is seen through it: SPPM's
 * camera path and photon both refract, each keeping the iteration's one
 * hero wavelength with the weight of all nwl; the factor must count once.
 * A glowing panel above a wide N-BK7 slab (an area light, so the path
 * tracer, unbiased, finds it by sampling through the glass); the camera
 * between them sees the floor only through the slab, far from the slab's
 * edges, where the floor's radiance varies slowly (no junction in view:
 * the density estimate's smoothing bias is below the noise here).
 *
 * The bound: one run's image mean carries noise every pixel shares (the
 * iteration's photons and wavelengths; SPPM's mean scattered by about 2 %
 * between seeds at 128 iterations), which no run reports.  So K = 12
 * seeds, each a path render (1024 samples) and an SPPM render (32
 * iterations) with that seed; their difference's mean is held to T = 7 of
 * its standard error (Student's t with 11 degrees of freedom: 2.3e-5
 * two-sided), the standard error required under 1 % of the path mean.
 * Before the fix SPPM was 4.4 x the path tracer's. */
static void test_seen_through_glass(void **state) {
  (void)state;
  enum { K = 12 };
  const double T = 7.0;
  const char *scn_fmt =
      "material floor lambert reflectance=0.5\n"
      "material glass db:N-BK7 model=interfaces\n"
      "material em black\n"
      "rect center=0,0,0 normal=0,0,1 size=8,8 material=floor\n"
      "box min=-1,-1,0.5 max=1,1,0.55 material=glass\n"
      "rect center=0,0,1.5 normal=0,0,-1 size=1,1 material=em emission=1000cd/m2\n"
      "camera pinhole from=0,0.5,1.0 to=0,0,0 up=0,0,1 fov=40 resolution=16x16\n"
      "render range=400,700 depth=16 seed=%d %s\n";
  seed_stats path_st = {0}, diff = {0};
  for (int k = 0; k < K; k++) {
    double v[2];
    const char *render[2] = {"integrator=path spp=1024",
                             "integrator=progressive spp=32 photons=100000"};
    for (int i = 0; i < 2; i++) {
      char scn[2048];
      snprintf(scn, sizeof scn, scn_fmt, k + 1, render[i]);
      v[i] = mean_y(scn);
    }
    seed_add(&path_st, v[0]);
    seed_add(&diff, v[1] - v[0]);
  }
  double path = seed_mean(&path_st), d = seed_mean(&diff), se = seed_stderr(&diff);
  print_message("    floor seen through the slab it is lit through, %d seeds: path %.4f cd/m2, "
                "SPPM - path %+.4f (%+.2f %%, stderr %.4f: %+.1f standard errors)\n",
                K, path, d, 100 * d / path, se, d / se);
  if (!(se < 0.01 * path)) fail_msg("the seeds' standard error %.4f is over 1 %% of %.4f", se, path);
  if (fabs(d) > T * se)
    fail_msg("through dispersive glass both ways SPPM differs from the path tracer by %+.4f "
             "cd/m2 (mean of %d seeds), over %.0f standard errors (%.4f)", d, K, T, se);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_plate_formula),
      cmocka_unit_test(test_slab_edges),
      cmocka_unit_test(test_bdpt_agrees),
      cmocka_unit_test(test_seen_through_glass),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
