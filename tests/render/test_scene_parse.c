/* Scene files: every statement read into the expected fields, defaults,
 * the order in which transforms compose, and each error naming the exact
 * line and column of the word at fault. */
#include "vr_test.h"
#include "vr/scene.h"
#include "vr/sun.h"

#define NAME "/scenes/room.scn"

static vr_status parse(const char *text, vr_scene **s, vr_error *err) {
  return vr_scene_parse(text, strlen(text), NAME, s, err);
}

static void assert_vec(const double *v, double x, double y, double z, double tol) {
  assert_near(v[0], x, tol);
  assert_near(v[1], y, tol);
  assert_near(v[2], z, tol);
}

static const char FULL[] =
    "# A room lit through glazing\n"
    "camera thinlens from=1,-3,1.5 to=1,0,1.5 up=0,0,2 fov=50 resolution=640x480 exposure=-1 "
    "aperture=5mm focus=3\n"
    "sphere center=0,0,1 radius=50cm material=grey name=ball emission=500cd/m2 "
    "emission_spectrum=D65 texels=8,4   # used before its material is defined\n"
    "material glass db:clear-float roughness=0.01 thickness=4mm model=interfaces state=0.25 "
    "temperature=300K coating=db:low-e\n"
    "material ec db:ec-wo3 charge=12mC/cm2\n"
    "material grey lambert reflectance=0.5\n"
    "material void black\n"
    "\n"
    "rect center=0,2,1.5 normal=0,-2,0 size=2,1.2 material=glass name=window\n"
    "plane center=0,0,0 normal=0,0,1 size=4,4 up=1,0,0 material=grey\n"
    "box min=0,0,0 max=1,2,3 material=ec rotate=0,0,1,90 translate=1,2,3\n"
    "mesh chair.obj material=grey scale=2\n"
    "mesh /abs/table.ply material=void scale=1,2,3\n"
    "\tlight point position=1,1,2.5 intensity=800lm distribution=lambertian normal=0,0,-1 "
    "spectrum=bb:2700\n"
    "light point position=2,1,2.5 ies=lamps/downlight.ies\n"
    "light spot position=0,0,3 direction=0,0,-1 cone=30 falloff=10 intensity=1000cd "
    "spectrum=LED-B3\n"
    "sky cie type=12 illuminance=15000 spectrum=D65 ground=0.3   # before the sun: still gets it\n"
    "light sun altitude=30 azimuth=90 illuminance=100000lx radius=0.3 spectrum=db:am15\n"
    "sensor desk point position=1,1,80cm normal=0,0,1\n"
    "sensor floor grid origin=0,0,0.85 u=4,0,0 v=0,3,0 n=8,6 normal=0,0,1\n"
    "render integrator=progressive depth=12 spectral=bins wavelengths=8 range=380,780 "
    "photons=1e6 caustic_photons=500000 knn=100 radius=2cm final_gather=on gather_rays=64 "
    "passes=32 alpha=0.7 sensor_samples=1000 sensors=photon sensor_knn=77 seed=18446744073709551615 film=380,780,5\n";

static void full_scene(void **state) {
  (void)state;
  vr_scene *s = NULL;
  vr_error err = {0};
  assert_int_equal(parse(FULL, &s, &err), VR_OK);
  assert_string_equal(s->path, NAME);
  assert_string_equal(s->dir, "/scenes");

  const vr_scene_camera *c = &s->camera;
  assert_true(c->given);
  assert_int_equal(c->model, VR_CAM_THINLENS);
  assert_vec(c->from, 1, -3, 1.5, 0);
  assert_vec(c->to, 1, 0, 1.5, 0);
  assert_vec(c->up, 0, 0, 1, 0); /* normalised */
  assert_near(c->fov_deg, 50, 0);
  assert_int_equal(c->width, 640);
  assert_int_equal(c->height, 480);
  assert_near(c->exposure_ev, -1, 0);
  assert_near(c->aperture_m, 0.005, 1e-15);
  assert_near(c->focus_m, 3, 0);
  assert_int_equal(c->loc.line, 2);

  assert_int_equal(s->nmaterials, 4);
  const vr_scene_material *m = s->materials;
  assert_string_equal(m[0].name, "glass");
  assert_int_equal(m[0].source, VR_MATSRC_DB);
  assert_string_equal(m[0].db_name, "clear-float");
  assert_near(m[0].roughness, 0.01, 0);
  assert_near(m[0].thickness_m, 0.004, 1e-15);
  assert_int_equal(m[0].pane, VR_PANE_INTERFACES);
  assert_near(m[0].state, 0.25, 0);
  assert_true(isnan(m[0].charge_mC_cm2));
  assert_near(m[0].temperature_K, 300, 0);
  assert_string_equal(m[0].coating_db, "low-e");
  assert_string_equal(m[1].db_name, "ec-wo3");
  assert_near(m[1].charge_mC_cm2, 12, 0);
  assert_true(isnan(m[1].state));
  assert_true(isnan(m[1].roughness));
  assert_true(isnan(m[1].thickness_m));
  assert_true(isnan(m[1].temperature_K));
  assert_int_equal(m[1].pane, VR_PANE_DEFAULT);
  assert_null(m[1].coating_db);
  assert_int_equal(m[2].source, VR_MATSRC_LAMBERT_CONST);
  assert_near(m[2].reflectance, 0.5, 0);
  assert_int_equal(m[3].source, VR_MATSRC_BLACK);
  assert_int_equal(m[3].loc.line, 7);

  assert_int_equal(s->nobjects, 6);
  const vr_scene_object *o = s->objects;
  assert_int_equal(o[0].shape, VR_SHAPE_SPHERE);
  assert_vec(o[0].center, 0, 0, 1, 0);
  assert_near(o[0].radius, 0.5, 1e-15);
  assert_int_equal(o[0].material, 2);
  assert_string_equal(o[0].name, "ball");
  assert_near(o[0].emission.value, 500, 0);
  assert_int_equal(o[0].emission.unit, VR_UNIT_CD_M2);
  assert_string_equal(o[0].emission_spectrum, "D65");
  assert_int_equal(o[0].texels[0], 8);
  assert_int_equal(o[0].texels[1], 4);
  assert_int_equal(o[1].shape, VR_SHAPE_RECT);
  assert_vec(o[1].normal, 0, -1, 0, 0);
  assert_near(o[1].size[0], 2, 0);
  assert_near(o[1].size[1], 1.2, 0);
  assert_vec(o[1].up, 0, 0, 1, 0); /* a wall: default up is +z */
  assert_int_equal(o[1].material, 0);
  assert_int_equal(o[1].texels[0], 16); /* default */
  assert_int_equal(o[1].emission.unit, VR_UNIT_NONE);
  assert_near(o[1].emission.value, 0, 0);
  assert_int_equal(o[2].shape, VR_SHAPE_RECT); /* "plane" is a synonym */
  assert_vec(o[2].up, 1, 0, 0, 0);
  assert_null(o[2].name);
  assert_int_equal(o[3].shape, VR_SHAPE_BOX);
  assert_vec(o[3].bmin, 0, 0, 0, 0);
  assert_vec(o[3].bmax, 1, 2, 3, 0);
  assert_int_equal(o[3].material, 1);
  assert_int_equal(o[4].shape, VR_SHAPE_MESH);
  assert_string_equal(o[4].mesh_path, "/scenes/chair.obj");
  assert_near(o[4].xform.m[1][1], 2, 0);
  assert_string_equal(o[5].mesh_path, "/abs/table.ply");
  assert_int_equal(o[5].material, 3);
  assert_near(o[5].xform.m[2][2], 3, 0);
  assert_int_equal(o[5].loc.line, 13);
  assert_int_equal(o[5].loc.col, 1);

  assert_int_equal(s->nlights, 4);
  const vr_scene_light *l = s->lights;
  assert_int_equal(l[0].kind, VR_LIGHT_POINT);
  assert_int_equal(l[0].loc.col, 2); /* after the tab */
  assert_vec(l[0].position, 1, 1, 2.5, 0);
  assert_near(l[0].amount.value, 800, 0);
  assert_int_equal(l[0].amount.unit, VR_UNIT_LM);
  assert_int_equal(l[0].distribution, VR_DIST_LAMBERTIAN);
  assert_vec(l[0].normal, 0, 0, -1, 0);
  assert_string_equal(l[0].spectrum, "bb:2700");
  assert_int_equal(l[1].distribution, VR_DIST_GONIOMETRIC); /* implied by ies= */
  assert_string_equal(l[1].ies_path, "/scenes/lamps/downlight.ies");
  assert_int_equal(l[1].amount.unit, VR_UNIT_NONE); /* the file's own candelas */
  assert_null(l[1].spectrum);
  assert_int_equal(l[2].kind, VR_LIGHT_SPOT);
  assert_vec(l[2].direction, 0, 0, -1, 0);
  assert_near(l[2].cone_deg, 30, 0);
  assert_near(l[2].falloff_deg, 10, 0);
  assert_int_equal(l[2].amount.unit, VR_UNIT_CD);
  assert_string_equal(l[2].spectrum, "LED-B3");
  assert_int_equal(l[3].kind, VR_LIGHT_SUN);
  /* Altitude 30 deg, azimuth 90 deg (east): (cos 30, 0, sin 30). */
  assert_vec(l[3].direction, sqrt(3) / 2, 0, 0.5, 1e-15);
  assert_near(l[3].amount.value, 1e5, 0);
  assert_int_equal(l[3].amount.unit, VR_UNIT_LX);
  assert_near(l[3].sun_radius_deg, 0.3, 0);
  assert_string_equal(l[3].spectrum, "db:am15");

  assert_true(s->sky.present);
  assert_int_equal(s->sky.cie_type, 12);
  assert_near(s->sky.level.value, 15000, 0);
  assert_int_equal(s->sky.level.unit, VR_UNIT_LX);
  assert_string_equal(s->sky.spectrum, "D65");
  assert_near(s->sky.ground_reflectance, 0.3, 0);
  assert_vec(s->sky.sun_direction, l[3].direction[0], l[3].direction[1], l[3].direction[2], 0);

  assert_int_equal(s->nsensors, 2);
  assert_string_equal(s->sensors[0].name, "desk");
  assert_false(s->sensors[0].grid);
  assert_vec(s->sensors[0].position, 1, 1, 0.8, 1e-15);
  assert_string_equal(s->sensors[1].name, "floor");
  assert_true(s->sensors[1].grid);
  assert_vec(s->sensors[1].position, 0, 0, 0.85, 0);
  assert_vec(s->sensors[1].u, 4, 0, 0, 0);
  assert_vec(s->sensors[1].v, 0, 3, 0, 0);
  assert_int_equal(s->sensors[1].nu, 8);
  assert_int_equal(s->sensors[1].nv, 6);

  const vr_scene_settings *g = &s->settings;
  assert_int_equal(g->integrator, VR_INT_PROGRESSIVE);
  assert_int_equal(g->spp, 32); /* passes= is progressive's older name of spp= */
  assert_int_equal(g->max_depth, 12);
  assert_int_equal(g->spectral, VR_SPECTRAL_BINS);
  assert_int_equal(g->wavelengths, 8);
  assert_near(g->lambda_min, 380, 0);
  assert_near(g->lambda_max, 780, 0);
  assert_int_equal(g->photons, 1000000);
  assert_int_equal(g->caustic_photons, 500000);
  assert_int_equal(g->knn, 100);
  assert_int_equal(g->sensor_knn, 77);
  assert_near(g->radius_m, 0.02, 1e-15);
  assert_true(g->final_gather);
  assert_int_equal(g->gather_rays, 64);
  assert_int_equal(g->passes, 32);
  assert_near(g->alpha, 0.7, 0);
  assert_int_equal(g->sensor_samples, 1000);
  assert_int_equal(g->sensors, VR_SENSORS_PHOTON);
  assert_true(g->seed == 18446744073709551615ULL);
  assert_near(g->film_min_nm, 380, 0);
  assert_near(g->film_max_nm, 780, 0);
  assert_near(g->film_step_nm, 5, 0);
  vr_scene_destroy(s);
}

/* The defaults scene.h promises, from the smallest scene that renders. */
/* Fixed bins default to the most wavelengths a path carries (8); a given
 * count is kept. */
static void bins_default(void **state) {
  (void)state;
  vr_scene *s = NULL;
  vr_error err = {0};
  assert_int_equal(parse("camera pinhole from=0,0,0 to=0,4,0\nrender spectral=bins", &s, &err), VR_OK);
  assert_int_equal(s->settings.wavelengths, VR_SCENE_MAX_WAVELENGTHS);
  assert_int_equal(VR_SCENE_MAX_WAVELENGTHS, 8);
  vr_scene_destroy(s);
  assert_int_equal(parse("camera pinhole from=0,0,0 to=0,4,0\nrender spectral=bins wavelengths=3", &s, &err), VR_OK);
  assert_int_equal(s->settings.wavelengths, 3);
  vr_scene_destroy(s);
}

static void defaults(void **state) {
  (void)state;
  vr_scene *s = NULL;
  vr_error err = {0};
  assert_int_equal(parse("camera pinhole from=0,0,0 to=0,4,0", &s, &err), VR_OK);
  assert_int_equal(s->nobjects, 0); /* an empty scene is the renderer's business */
  assert_int_equal(s->nlights, 0);
  assert_false(s->sky.present);
  assert_vec(s->sky.sun_direction, 0, 0, 1, 0);
  assert_near(s->sky.ground_reflectance, 0.2, 0);
  assert_vec(s->camera.up, 0, 0, 1, 0);
  assert_near(s->camera.fov_deg, 60, 0);
  assert_int_equal(s->camera.width, 320);
  assert_int_equal(s->camera.height, 240);
  assert_near(s->camera.focus_m, 4, 0); /* |to - from| */
  assert_near(s->camera.aperture_m, 0, 0);
  assert_near(s->camera.exposure_ev, 0, 0);
  const vr_scene_settings *g = &s->settings;
  assert_int_equal(g->integrator, VR_INT_PHOTON);
  assert_int_equal(g->spp, 16);
  assert_int_equal(g->max_depth, 8);
  assert_int_equal(g->spectral, VR_SPECTRAL_HERO);
  assert_int_equal(g->wavelengths, 4);
  assert_near(g->lambda_min, 360, 0);
  assert_near(g->lambda_max, 830, 0);
  assert_int_equal(g->photons, 200000);
  assert_int_equal(g->caustic_photons, 200000);
  assert_int_equal(g->knn, 50);
  assert_int_equal(g->sensor_knn, 50);
  assert_true(isnan(g->radius_m));
  assert_false(g->final_gather);
  assert_int_equal(g->gather_rays, 32);
  assert_int_equal(g->passes, 16);
  assert_near(g->alpha, 2.0 / 3.0, 0);
  assert_int_equal(g->sensor_samples, 4096);
  assert_int_equal(g->sensors, VR_SENSORS_PATH);
  assert_true(g->seed == 1);
  assert_near(g->film_min_nm, 400, 0);
  assert_near(g->film_max_nm, 700, 0);
  assert_near(g->film_step_nm, 10, 0);
  vr_scene_destroy(s);

  /* Sun and sky defaults; a sensor is enough to render without a camera. */
  assert_int_equal(parse("light sun direction=0,3,4 illuminance=1000\nsky overcast zenith=2000\n"
                         "light point position=0,0,2 intensity=100cd\n"
                         "sensor s point position=0,0,0 normal=0,0,5\n", &s, &err), VR_OK);
  assert_false(s->camera.given);
  assert_vec(s->lights[0].direction, 0, 0.6, 0.8, 1e-15);
  assert_int_equal(s->lights[0].amount.unit, VR_UNIT_LX); /* unitless illuminance */
  assert_near(s->lights[0].sun_radius_deg, 0.2665, 0);
  assert_null(s->lights[0].spectrum);
  assert_int_equal(s->sky.cie_type, 0);
  assert_int_equal(s->sky.level.unit, VR_UNIT_CD_M2);
  assert_vec(s->sky.sun_direction, 0, 0.6, 0.8, 1e-15);
  assert_int_equal(s->lights[1].distribution, VR_DIST_ISOTROPIC);
  assert_vec(s->lights[1].normal, 0, 0, -1, 0);
  assert_vec(s->sensors[0].normal, 0, 0, 1, 0);
  vr_scene_destroy(s);

  /* A floor's default up is north (+y); a tilted roof keeps +z's in-plane part. */
  assert_int_equal(parse("camera pinhole from=0,0,0 to=0,1,0\nmaterial m black\n"
                         "rect center=0,0,0 normal=0,0,-1 size=1,1 material=m\n"
                         "rect center=0,0,0 normal=0,-1,1 size=1,1 material=m\n"
                         "rect center=0,0,0 normal=0,0,1 size=1,1 up=1,0,1 material=m\n", &s, &err),
                   VR_OK);
  assert_vec(s->objects[0].up, 0, 1, 0, 0);
  assert_vec(s->objects[1].up, 0, sqrt(0.5), sqrt(0.5), 1e-15);
  assert_vec(s->objects[2].up, 1, 0, 0, 1e-15); /* made perpendicular to the normal */
  vr_scene_destroy(s);
}

static void transform_order(void **state) {
  (void)state;
  vr_scene *s = NULL;
  vr_error err = {0};
  assert_int_equal(parse("camera pinhole from=0,0,0 to=0,1,0\nmaterial m black\n"
                         "sphere center=0,0,0 radius=1 material=m rotate=0,0,1,90 translate=1,2,3\n"
                         "sphere center=0,0,0 radius=1 material=m translate=1,2,3 rotate=0,0,2,90\n"
                         "sphere center=0,0,0 radius=1 material=m scale=2 translate=100cm,0,0 scale=1,1,3\n"
                         "sphere center=0,0,0 radius=1 material=m rotate=1,1,1,120\n"
                         "sphere center=0,0,0 radius=1 material=m scale=-1,1,1\n",
                         &s, &err),
                   VR_OK);
  const double x[3] = {1, 0, 0}, z[3] = {0, 0, 1};
  double r[3];
  /* Rotating (1,0,0) by +90 deg about z gives (0,1,0) (right-hand rule);
   * translating by (1,2,3) then gives (1,3,3). */
  vr_xform_point(&s->objects[0].xform, x, r);
  assert_vec(r, 1, 3, 3, 0);
  /* The other order: (2,2,3) rotated about z: (-2,2,3). */
  vr_xform_point(&s->objects[1].xform, x, r);
  assert_vec(r, -2, 2, 3, 0);
  /* Vectors ignore the translation. */
  vr_xform_vector(&s->objects[1].xform, x, r);
  assert_vec(r, 0, 1, 0, 0);
  /* (1,0,0) -> (2,0,0) -> (3,0,0) -> (3,0,0); (0,0,1) -> (0,0,2) -> (1,0,2) -> (1,0,6). */
  vr_xform_point(&s->objects[2].xform, x, r);
  assert_vec(r, 3, 0, 0, 1e-15);
  vr_xform_point(&s->objects[2].xform, z, r);
  assert_vec(r, 1, 0, 6, 1e-15);
  /* 120 deg about the diagonal permutes the axes: x -> y. */
  vr_xform_point(&s->objects[3].xform, x, r);
  assert_vec(r, 0, 1, 0, 1e-15);
  /* A mirror is allowed (not singular). */
  vr_xform_point(&s->objects[4].xform, x, r);
  assert_vec(r, -1, 0, 0, 0);
  vr_scene_destroy(s);
}

typedef struct error_case {
  const char *name, *text;
  size_t len; /* 0: strlen(text) */
  const char *where, *message;
} error_case;

#define ERROR_CASE(name, text, where, message) {name, text, sizeof text - 1, where, message}

static const error_case ERRORS[] = {
    ERROR_CASE("unknown statement", "camera pinhole from=0,0,0 to=0,1,0\n  cube size=1\n", "room.scn:2:3: ", "unknown statement \"cube\""),
    ERROR_CASE("unknown option", "camera pinhole from=0,0,0 to=0,1,0\nmaterial m black\nsphere center=0,0,0 radius=1 material=m colour=red\n", "room.scn:3:41: ", "unknown option \"colour\" for a sphere"),
    ERROR_CASE("missing option", "camera pinhole from=0,0,0 to=0,1,0\nmaterial m black\nsphere center=0,0,0 material=m\n", "room.scn:3:1: ", "a sphere needs radius="),
    ERROR_CASE("missing positional", "camera from=0,0,0 to=0,1,0\n", "room.scn:1:8: ", "'camera' needs a model"),
    ERROR_CASE("repeated option", "camera pinhole from=0,0,0 to=0,1,0\nmaterial m black\nsphere center=0,0,0 radius=1 radius=2 material=m\n", "room.scn:3:30: ", "radius= is given twice (first at column 21)"),
    ERROR_CASE("malformed number", "camera pinhole from=0,0,0 to=0,1,0\nmaterial m black\nsphere center=0,0,0 radius=abc material=m\n", "room.scn:3:21: ", "expected a number, got \"abc\""),
    ERROR_CASE("malformed length unit", "camera pinhole from=0,0,0 to=0,1,0\nmaterial m black\nsphere center=0,0,0 radius=2km material=m\n", "room.scn:3:21: ", "unknown length unit \"km\""),
    ERROR_CASE("malformed vector", "camera pinhole from=0,0,0 to=0,1,0\nmaterial m black\nsphere center=0,0 radius=1 material=m\n", "room.scn:3:8: ", "expected 3 numbers"),
    ERROR_CASE("empty vector component", "camera pinhole from=0,0,0 to=0,1,0\nmaterial m black\nsphere center=0,,0 radius=1 material=m\n", "room.scn:3:8: ", "expected a number, got \"\""),
    ERROR_CASE("nan in a transform", "camera pinhole from=0,0,0 to=0,1,0\nmaterial m black\nbox min=0,0,0 max=1,1,1 material=m translate=nan,0,0\n", "room.scn:3:36: ", "nan is not a finite number"),
    ERROR_CASE("inf", "camera pinhole from=0,0,0 to=0,1,0 fov=inf\n", "room.scn:1:36: ", "inf is not a finite number"),
    ERROR_CASE("overflow", "camera pinhole from=0,0,0 to=0,1,0\nmaterial m black\nsphere center=0,0,0 radius=1e999 material=m\n", "room.scn:3:21: ", "1e999 is not a finite number"),
    ERROR_CASE("hex float", "camera pinhole from=0,0,0 to=0,1,0\nmaterial m black\nsphere center=0x10,0,0 radius=1 material=m\n", "room.scn:3:8: ", "unknown length unit \"x10\""),
    ERROR_CASE("zero normal", "camera pinhole from=0,0,0 to=0,1,0\nmaterial m black\nrect center=0,0,0 normal=0,0,0 size=1,1 material=m\n", "room.scn:3:19: ", "zero-length direction"),
    ERROR_CASE("zero direction", "camera pinhole from=0,0,0 to=0,1,0\nlight spot position=0,0,3 direction=0,-0,0 cone=30 intensity=10cd\n", "room.scn:2:27: ", "zero-length direction"),
    ERROR_CASE("up parallel to view", "camera pinhole from=0,0,0 to=0,0,-5 up=0,0,2\n", "room.scn:1:37: ", "parallel to the view direction"),
    ERROR_CASE("default up parallel to view", "camera pinhole from=0,0,5 to=0,0,0\n", "room.scn:1:27: ", "parallel to the view direction: give up="),
    ERROR_CASE("from equals to", "camera pinhole from=1,1,1 to=100cm,1,1\n", "room.scn:1:27: ", "same point"),
    ERROR_CASE("negative radius", "camera pinhole from=0,0,0 to=0,1,0\nmaterial m black\nsphere center=0,0,0 radius=-1 material=m\n", "room.scn:3:21: ", "must be positive"),
    ERROR_CASE("zero radius", "camera pinhole from=0,0,0 to=0,1,0\nmaterial m black\nsphere center=0,0,0 radius=0mm material=m\n", "room.scn:3:21: ", "must be positive"),
    ERROR_CASE("zero size", "camera pinhole from=0,0,0 to=0,1,0\nmaterial m black\nrect center=0,0,0 normal=0,0,1 size=0,1 material=m\n", "room.scn:3:32: ", "width and height must be positive"),
    ERROR_CASE("zero thickness", "camera pinhole from=0,0,0 to=0,1,0\nmaterial g db:float thickness=0mm\n", "room.scn:2:21: ", "must be positive"),
    ERROR_CASE("flat box", "camera pinhole from=0,0,0 to=0,1,0\nmaterial m black\nbox min=0,0,0 max=1,0,1 material=m\n", "room.scn:3:15: ", "max must exceed its min"),
    ERROR_CASE("resolution zero", "camera pinhole from=0,0,0 to=0,1,0 resolution=0x240\n", "room.scn:1:36: ", "expected 2 integers in [1, 16384] separated by 'x'"),
    ERROR_CASE("resolution too large", "camera pinhole from=0,0,0 to=0,1,0 resolution=16385x10\n", "room.scn:1:36: ", "in [1, 16384]"),
    ERROR_CASE("resolution malformed", "camera pinhole from=0,0,0 to=0,1,0 resolution=640,480\n", "room.scn:1:36: ", "separated by 'x'"),
    ERROR_CASE("unknown material", "camera pinhole from=0,0,0 to=0,1,0\nsphere center=0,0,0 radius=1 material=nope\nmaterial m black\n", "room.scn:2:30: ", "unknown material \"nope\""),
    ERROR_CASE("duplicate material", "camera pinhole from=0,0,0 to=0,1,0\nmaterial m black\nmaterial  m lambert reflectance=1\n", "room.scn:3:11: ", "material \"m\" is defined twice (first on line 2)"),
    ERROR_CASE("duplicate sensor", "sensor s point position=0,0,0 normal=0,0,1\nsensor s point position=1,0,0 normal=0,0,1\n", "room.scn:2:8: ", "sensor \"s\" is defined twice (first on line 1)"),
    ERROR_CASE("state outside [0,1]", "camera pinhole from=0,0,0 to=0,1,0\nmaterial e db:ec state=1.5\n", "room.scn:2:18: ", "must be in [0, 1]"),
    ERROR_CASE("state and charge", "camera pinhole from=0,0,0 to=0,1,0\nmaterial e db:ec state=0.5 charge=3mC/cm2\n", "room.scn:2:28: ", "give state= or charge=, not both"),
    ERROR_CASE("charge and state", "camera pinhole from=0,0,0 to=0,1,0\nmaterial e db:ec charge=3 state=0.5\n", "room.scn:2:27: ", "give state= or charge=, not both"),
    ERROR_CASE("sky type 16", "camera pinhole from=0,0,0 to=0,1,0\nsky cie type=16 illuminance=10000\n", "room.scn:2:9: ", "expected an integer in [1, 15]"),
    ERROR_CASE("sky type 0", "camera pinhole from=0,0,0 to=0,1,0\nsky cie type=0 illuminance=10000\n", "room.scn:2:9: ", "expected an integer in [1, 15]"),
    ERROR_CASE("sky type 2.5", "camera pinhole from=0,0,0 to=0,1,0\nsky cie type=2.5 illuminance=10000\n", "room.scn:2:9: ", "expected an integer in [1, 15]"),
    ERROR_CASE("sky without level", "camera pinhole from=0,0,0 to=0,1,0\nsky overcast\n", "room.scn:2:1: ", "a sky needs illuminance=LX"),
    ERROR_CASE("overcast with type", "camera pinhole from=0,0,0 to=0,1,0\nsky overcast type=3 zenith=5000\n", "room.scn:2:14: ", "unknown option \"type\" for an overcast sky"),
    ERROR_CASE("two suns", "camera pinhole from=0,0,0 to=0,1,0\nlight sun direction=0,0,1 illuminance=1lx\nlight sun direction=0,1,1 illuminance=1lx\n", "room.scn:3:1: ", "a second sun (the first is on line 2)"),
    ERROR_CASE("two skies", "camera pinhole from=0,0,0 to=0,1,0\nsky overcast zenith=1\n sky cie type=1 zenith=1\n", "room.scn:3:2: ", "a second sky (the first is on line 2)"),
    ERROR_CASE("two cameras", "camera pinhole from=0,0,0 to=0,1,0\n\ncamera pinhole from=0,0,0 to=0,1,0\n", "room.scn:3:1: ", "a second camera (the first is on line 1)"),
    ERROR_CASE("two render lines", "camera pinhole from=0,0,0 to=0,1,0\nrender spp=1\nrender spp=2\n", "room.scn:3:1: ", "a second render line"),
    ERROR_CASE("scale 0", "camera pinhole from=0,0,0 to=0,1,0\nmaterial m black\nsphere center=0,0,0 radius=1 material=m translate=1,0,0 scale=0\n", "room.scn:3:57: ", "singular transform"),
    ERROR_CASE("scale 0 on one axis", "camera pinhole from=0,0,0 to=0,1,0\nmaterial m black\nsphere center=0,0,0 radius=1 material=m scale=1,0,1\n", "room.scn:3:41: ", "singular transform"),
    ERROR_CASE("transform overflow", "camera pinhole from=0,0,0 to=0,1,0\nmaterial m black\nsphere center=0,0,0 radius=1 material=m scale=1e200 scale=1e200\n", "room.scn:3:41: ", "overflows"),
    ERROR_CASE("transform underflow", "camera pinhole from=0,0,0 to=0,1,0\nmaterial m black\nsphere center=0,0,0 radius=1 material=m scale=1e-200 scale=1e-200\n", "room.scn:3:41: ", "singular"),
    ERROR_CASE("zero rotation axis", "camera pinhole from=0,0,0 to=0,1,0\nmaterial m black\nsphere center=0,0,0 radius=1 material=m rotate=0,0,0,90\n", "room.scn:3:41: ", "rotation axis is a zero vector"),
    ERROR_CASE("wrong unit for a sun", "camera pinhole from=0,0,0 to=0,1,0\nlight sun direction=0,0,1 illuminance=5cd\n", "room.scn:2:27: ", "a sun's illuminance is in lx or W/m2, not cd"),
    ERROR_CASE("unknown unit", "camera pinhole from=0,0,0 to=0,1,0\nlight point position=0,0,0 intensity=5kcd\n", "room.scn:2:28: ", "unknown unit \"kcd\" (cd, lm, W or W/sr)"),
    ERROR_CASE("missing unit", "camera pinhole from=0,0,0 to=0,1,0\nlight point position=0,0,0 intensity=100\n", "room.scn:2:28: ", "an intensity needs a unit (cd, lm, W or W/sr)"),
    ERROR_CASE("wrong unit for emission", "camera pinhole from=0,0,0 to=0,1,0\nmaterial m black\nsphere center=0,0,0 radius=1 material=m emission=5lx\n", "room.scn:3:41: ", "an emission is in cd/m2 or W/m2/sr, not lx"),
    ERROR_CASE("negative emission", "camera pinhole from=0,0,0 to=0,1,0\nmaterial m black\nsphere center=0,0,0 radius=1 material=m emission=-5cd/m2\n", "room.scn:3:41: ", "must not be negative"),
    ERROR_CASE("unknown spectrum", "camera pinhole from=0,0,0 to=0,1,0\nlight point position=0,0,0 intensity=1W spectrum=D99x\n", "room.scn:2:41: ", "unknown spectrum \"D99x\""),
    ERROR_CASE("daylight out of range", "camera pinhole from=0,0,0 to=0,1,0\nlight point position=0,0,0 intensity=1W spectrum=D3000\n", "room.scn:2:41: ", "unknown spectrum"),
    ERROR_CASE("blackbody at 0 K", "camera pinhole from=0,0,0 to=0,1,0\nlight point position=0,0,0 intensity=1W spectrum=bb:0\n", "room.scn:2:41: ", "must be positive"),
    ERROR_CASE("empty db name", "camera pinhole from=0,0,0 to=0,1,0\nsky overcast zenith=1 spectrum=db:\n", "room.scn:2:23: ", "db: needs a name"),
    ERROR_CASE("NUL byte", "camera pinhole from=0,0,0 to=0,1,0\nsph\0ere\n", "room.scn:2:4: ", "NUL byte"),
    ERROR_CASE("stray word", "camera pinhole from=0,0,0 to=0,1,0\nmaterial m black\nsphere center=0,0,0 radius=1 material=m extra\n", "room.scn:3:41: ", "unexpected \"extra\" in a sphere"),
    ERROR_CASE("option without value", "camera pinhole from=0,0,0 to=0,1,0\nmaterial m black\nsphere center=0,0,0 radius= material=m\n", "room.scn:3:21: ", "radius= has no value"),
    ERROR_CASE("too many words", "camera pinhole from=0,0,0 to=0,1,0\nrender spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1 spp=1\n", "room.scn:2:386: ", "more than 64 words"),
    ERROR_CASE("direction and altitude", "camera pinhole from=0,0,0 to=0,1,0\nlight sun direction=0,0,1 altitude=30 illuminance=1\n", "room.scn:2:27: ", "not both"),
    ERROR_CASE("altitude without azimuth", "camera pinhole from=0,0,0 to=0,1,0\nlight sun altitude=30 illuminance=1\n", "room.scn:2:11: ", "needs both altitude= and azimuth="),
    ERROR_CASE("altitude above 90", "camera pinhole from=0,0,0 to=0,1,0\nlight sun altitude=91 azimuth=0 illuminance=1\n", "room.scn:2:11: ", "must be in [-90, 90]"),
    ERROR_CASE("goniometric without ies", "camera pinhole from=0,0,0 to=0,1,0\nlight point position=0,0,0 distribution=goniometric\n", "room.scn:2:28: ", "needs ies=FILE"),
    ERROR_CASE("ies with isotropic", "camera pinhole from=0,0,0 to=0,1,0\nlight point position=0,0,0 intensity=1cd distribution=isotropic ies=a.ies\n", "room.scn:2:65: ", "ies= needs distribution=goniometric"),
    ERROR_CASE("parallel grid edges", "sensor g grid origin=0,0,0 u=1,0,0 v=-2,0,0 n=2,2 normal=0,0,1\n", "room.scn:1:36: ", "u and v are parallel"),
    ERROR_CASE("grid count zero", "sensor g grid origin=0,0,0 u=1,0,0 v=0,1,0 n=0,2 normal=0,0,1\n", "room.scn:1:44: ", "expected 2 integers in [1, 10000]"),
    ERROR_CASE("unknown camera model", "camera orthographic from=0,0,0 to=0,1,0\n", "room.scn:1:8: ", "unknown camera model"),
    ERROR_CASE("fisheye fov", "camera fisheye from=0,0,0 to=0,1,0 fov=361\n", "room.scn:1:36: ", "must be in (0, 360]"),
    ERROR_CASE("fisheye projection", "camera fisheye from=0,0,0 to=0,1,0 projection=stereo\n", "room.scn:1:36: ", "stereo"),
    ERROR_CASE("aperture on a fisheye", "camera fisheye from=0,0,0 to=0,1,0 aperture=1mm\n", "room.scn:1:36: ", "unknown option \"aperture\" for a fisheye camera"),
    ERROR_CASE("aperture on a pinhole", "camera pinhole from=0,0,0 to=0,1,0 aperture=1mm\n", "room.scn:1:36: ", "unknown option \"aperture\" for a pinhole camera"),
    ERROR_CASE("too many wavelengths", "camera pinhole from=0,0,0 to=0,1,0\nrender wavelengths=9\n", "room.scn:2:8: ", "expected an integer in [1, 8]"),
    ERROR_CASE("unknown sensor estimator", "camera pinhole from=0,0,0 to=0,1,0\nrender sensors=radiosity\n", "room.scn:2:8: ", "expected path, photon"),
    ERROR_CASE("unknown integrator", "camera pinhole from=0,0,0 to=0,1,0\nrender integrator=mlt\n", "room.scn:2:8: ", "expected path, whitted, photon, progressive, bdpt"),
    ERROR_CASE("fov 180", "camera pinhole from=0,0,0 to=0,1,0 fov=180\n", "room.scn:1:36: ", "must be in (0, 180)"),
    ERROR_CASE("rect up along its normal", "camera pinhole from=0,0,0 to=0,1,0\nmaterial m black\nrect center=0,0,0 normal=0,0,1 size=1,1 up=0,0,-3 material=m\n", "room.scn:3:41: ", "up is parallel to the normal"),
    ERROR_CASE("spot cone plus falloff", "camera pinhole from=0,0,0 to=0,1,0\nlight spot position=0,0,3 direction=0,0,-1 cone=170 falloff=20 intensity=1cd\n", "room.scn:2:53: ", "exceeds 180"),
    ERROR_CASE("film step", "camera pinhole from=0,0,0 to=0,1,0\nrender film=400,700,0\n", "room.scn:2:8: ", "STEP"),
    ERROR_CASE("seed", "camera pinhole from=0,0,0 to=0,1,0\nrender seed=-1\n", "room.scn:2:8: ", "expected an integer"),
    ERROR_CASE("sensor_knn zero", "camera pinhole from=0,0,0 to=0,1,0\nrender sensor_knn=0\n", "room.scn:2:8: ", "sensor_knn"),
    ERROR_CASE("coating not db", "camera pinhole from=0,0,0 to=0,1,0\nmaterial g db:float coating=lowe\n", "room.scn:2:21: ", "a coating is db:NAME"),
    ERROR_CASE("lambert without reflectance", "camera pinhole from=0,0,0 to=0,1,0\nmaterial g lambert\n", "room.scn:2:1: ", "a material needs reflectance="),
    ERROR_CASE("reflectance above 1", "camera pinhole from=0,0,0 to=0,1,0\nmaterial g lambert reflectance=1.2\n", "room.scn:2:20: ", "must be in [0, 1]"),
};

/* The sun placed by site and local time.  Reference: the test case of the
 * NREL Solar Position Algorithm (Reda & Andreas, NREL/TP-560-34302, 2008,
 * table A4.1): Golden, Colorado, 39.742476 N, 105.1786 W, 2003-10-17
 * 12:30:30 at UTC-7 gives a topocentric zenith angle of 50.11162 deg and an
 * azimuth of 194.34024 deg (from north, eastward).  SPA's case has 820 hPa
 * and 11 C; the scene uses standard air, which moves the refraction by
 * about 0.004 deg at this altitude: 0.02 deg is allowed.  The same instant
 * written in other zones (the date rolling over) must give the same
 * direction bit for bit. */
static void sun_by_site_and_time(void **state) {
  (void)state;
  static const char *const LINES[] = {
      "light sun latitude=39.742476 longitude=-105.1786 date=2003-10-17 time=12:30:30 "
      "timezone=-7 illuminance=80000lx\n",
      "light sun latitude=39.742476 longitude=-105.1786 date=2003-10-17 time=19:30:30 "
      "illuminance=80000lx\n",
      "light sun latitude=39.742476 longitude=254.8214 date=2003-10-18 time=04:30:30 "
      "timezone=9 illuminance=80000lx\n"};
  double first[3];
  for (int i = 0; i < 3; i++) {
    char text[512];
    snprintf(text, sizeof text, "%ssky cie type=12 illuminance=15000\n"
                                "sensor s point position=0,0,0 normal=0,0,1\n", LINES[i]);
    vr_scene *s = NULL;
    vr_error err = {0};
    if (parse(text, &s, &err) != VR_OK) fail_msg("line %d: %s", i, err.message);
    double alt, az;
    assert_true(vr_sun_angles_of(s->lights[0].direction, &alt, &az));
    print_message("  %s  altitude %.5f, azimuth %.5f deg\n", i == 0 ? "UTC-7" : i == 1 ? "UTC  " : "UTC+9", alt, az);
    assert_near(90.0 - alt, 50.11162, 0.02);
    assert_near(az, 194.34024, 0.02);
    /* The sky takes the sun line's place. */
    assert_memory_equal(s->sky.sun_direction, s->lights[0].direction, sizeof first);
    if (i == 0) memcpy(first, s->lights[0].direction, sizeof first);
    else assert_memory_equal(first, s->lights[0].direction, sizeof first);
    vr_scene_destroy(s);
  }
}

/* text, with a sensor added, must be refused with a message holding needle. */
static void refused(const char *text, const char *needle) {
  char buf[512];
  snprintf(buf, sizeof buf, "%ssensor s point position=0,0,0 normal=0,0,1\n", text);
  vr_scene *s = NULL;
  vr_error err = {0};
  assert_int_equal(parse(buf, &s, &err), VR_E_PARSE);
  if (!strstr(err.message, needle)) fail_msg("'%s' does not say '%s'", err.message, needle);
  assert_null(s);
}

/* A sky brighter towards the sun needs to know where the sun is; sun=
 * places it without a sun line; a sky that does not depend on the sun
 * (type 1, azimuthally uniform) needs neither. */
static void sky_needs_the_sun(void **state) {
  (void)state;
  vr_scene *s = NULL;
  vr_error err = {0};
  refused("sky cie type=12 illuminance=15000\n", "room.scn:1:1: CIE sky type 12");
  refused("sky cie type=12 illuminance=15000\n", "sun=ALTITUDE,AZIMUTH");
  assert_int_equal(parse("sky cie type=12 illuminance=15000 sun=30,90\n"
                         "sensor s point position=0,0,0 normal=0,0,1\n", &s, &err), VR_OK);
  /* 30 deg up in the east: (cos 30, 0, sin 30). */
  assert_vec(s->sky.sun_direction, cos(M_PI / 6), 0, 0.5, 1e-15);
  vr_scene_destroy(s);
  assert_int_equal(parse("sky cie type=1 illuminance=15000\n"
                         "sensor s point position=0,0,0 normal=0,0,1\n", &s, &err), VR_OK);
  vr_scene_destroy(s);
  refused("sky cie type=12 illuminance=15000 sun=30,90\n"
          "light sun altitude=30 azimuth=90 illuminance=1000\n", "give it once");
  /* Site and time: all four, not mixed with angles, the sun up, real dates. */
  refused("light sun latitude=40 longitude=0 time=12:00 illuminance=1\n", "date= is missing");
  refused("light sun latitude=40 longitude=0 date=2026-06-21 time=12:00 altitude=30 "
          "illuminance=1\n", "not both");
  refused("light sun latitude=39.742476 longitude=-105.1786 date=2003-10-17 time=23:00 "
          "timezone=-7 illuminance=1\n", "below the horizon");
  refused("light sun latitude=40 longitude=0 date=2026-02-30 time=12:00 illuminance=1\n",
          "not a calendar date");
  refused("light sun latitude=40 longitude=0 date=2026-06-21 time=24:00 illuminance=1\n",
          "time=24:00");
}

/* sensor_knn not given is knn's, whatever knn is. */
static void sensor_knn_follows_knn(void **state) {
  (void)state;
  vr_scene *s = NULL;
  vr_error err = {0};
  const char *text = "camera pinhole from=0,0,0 to=0,1,0\nrender knn=600 sensors=photon\n";
  assert_int_equal(vr_scene_parse(text, strlen(text), NAME, &s, &err), VR_OK);
  assert_int_equal(s->settings.knn, 600);
  assert_int_equal(s->settings.sensor_knn, 600);
  vr_scene_destroy(s);
  /* outside=yes marks an exterior surface; no is the default. */
  const char *ground = "material g lambert reflectance=0.2\n"
                       "rect center=0,0,0 normal=0,0,1 size=9,9 material=g outside=yes\n"
                       "rect center=0,0,3 normal=0,0,-1 size=9,9 material=g\n"
                       "sensor s point position=0,0,1 normal=0,0,1\n";
  assert_int_equal(vr_scene_parse(ground, strlen(ground), NAME, &s, &err), VR_OK);
  assert_true(s->objects[0].outside);
  assert_false(s->objects[1].outside);
  vr_scene_destroy(s);
  refused("material g lambert reflectance=0.2\n"
          "rect center=0,0,0 normal=0,0,1 size=9,9 material=g outside=maybe\n", "outside");
}

/* photon_portals: off unless written, except for photon sensors in a
 * scene with portals (vr_scene_photon_portals; docs/scene-format.md). */
static void photon_portals_default(void **state) {
  (void)state;
  static const char BASE[] = "camera pinhole from=0,0,0 to=0,1,0\n"
                             "sky cie type=1 illuminance=15000lx\n%s%s%s";
  static const char PORTAL[] = "portal center=0,2,1.5 normal=0,-1,0 size=2,1\n";
  static const char SENSOR[] = "sensor s point position=0,0,1 normal=0,0,1\n";
  static const struct {
    const char *portal, *sensor, *render;
    bool want;
  } C[] = {
      {PORTAL, SENSOR, "render sensors=photon\n", true},
      {PORTAL, SENSOR, "render sensors=photon photon_portals=off\n", false},
      {PORTAL, SENSOR, "render sensors=path\n", false},
      {PORTAL, SENSOR, "render integrator=photon\n", false},
      {"", SENSOR, "render sensors=photon\n", false},
      {PORTAL, "", "render sensors=photon\n", false},
      {PORTAL, "", "render integrator=progressive photon_portals=on\n", true},
  };
  for (size_t i = 0; i < sizeof C / sizeof C[0]; i++) {
    char text[1024];
    snprintf(text, sizeof text, BASE, C[i].portal, C[i].sensor, C[i].render);
    vr_scene *s = NULL;
    vr_error err = {0};
    if (vr_scene_parse(text, strlen(text), NAME, &s, &err)) fail_msg("case %zu: %s", i, err.message);
    if (vr_scene_photon_portals(s) != C[i].want) fail_msg("case %zu: photon portals %d", i, !C[i].want);
    vr_scene_destroy(s);
  }
}

static void errors(void **state) {
  (void)state;
  for (size_t i = 0; i < sizeof ERRORS / sizeof ERRORS[0]; i++) {
    const error_case *e = &ERRORS[i];
    vr_scene *s = (vr_scene *)&s; /* must come back NULL */
    vr_error err = {0};
    vr_status st = vr_scene_parse(e->text, e->len, NAME, &s, &err);
    if (st != VR_E_PARSE || !strstr(err.message, e->where) || !strstr(err.message, e->message))
      fail_msg("%s: status %d, message '%s', expected '%s...%s'", e->name, (int)st, err.message,
               e->where, e->message);
    assert_null(s);
  }
}

static void whole_file_errors(void **state) {
  (void)state;
  vr_scene *s = NULL;
  vr_error err = {0};
  /* Nothing to render: reported without a line. */
  assert_int_equal(parse("", &s, &err), VR_E_PARSE);
  assert_string_equal(err.message, NAME ": no camera and no sensor: nothing to render");
  assert_int_equal(parse("# only comments\nmaterial m black\n", &s, &err), VR_E_PARSE);
  assert_contains(err.message, "nothing to render");
  assert_null(s);
  /* The first unknown material in file order is the one reported. */
  assert_int_equal(parse("camera pinhole from=0,0,0 to=0,1,0\n"
                         "sphere center=0,0,0 radius=1 material=a\n"
                         "sphere center=0,0,0 radius=1   material=b\nmaterial a black\n",
                         &s, &err),
                   VR_E_PARSE);
  assert_contains(err.message, "room.scn:3:32: unknown material \"b\"");
  assert_null(s);
  assert_int_equal(vr_scene_parse(NULL, 1, NAME, &s, &err), VR_E_ARG);
}

/* Line ends, a missing final newline, comments, names without a folder. */
static void text_robustness(void **state) {
  (void)state;
  vr_scene *s = NULL;
  vr_error err = {0};
  static const char CRLF[] = "camera pinhole from=0,0,0 to=0,1,0\r\n\r\n  # comment\r\n"
                             "mesh a.obj material=m#trailing comment\r\nmaterial m black";
  assert_int_equal(vr_scene_parse(CRLF, sizeof CRLF - 1, "room.scn", &s, &err), VR_OK);
  assert_string_equal(s->dir, ".");
  assert_string_equal(s->objects[0].mesh_path, "a.obj");
  assert_int_equal(s->objects[0].material, 0);
  vr_scene_destroy(s);
  assert_int_equal(parse("camera pinhole from=0,0,0 to=0,1,0\r\nsphere center=0,0,0 radius=-1 material=m\r\n",
                         &s, &err),
                   VR_E_PARSE);
  assert_contains(err.message, "room.scn:2:21: ");
  assert_int_equal(vr_scene_parse("camera pinhole from=0,0,0 to=0,1,0\nmesh x.ply material=m\nmaterial m black",
                                  strlen("camera pinhole from=0,0,0 to=0,1,0\nmesh x.ply material=m\nmaterial m black"),
                                  "/room.scn", &s, &err),
                   VR_OK);
  assert_string_equal(s->dir, "/");
  assert_string_equal(s->objects[0].mesh_path, "/x.ply");
  vr_scene_destroy(s);
  /* A UTF-8 byte order mark (Windows editors write one) is not text, and
   * columns on the first line count from after it. */
  static const char BOM[] = "\xEF\xBB\xBF"
                            "camera pinhole from=0,0,0 to=0,1,0 fov=200\n";
  assert_int_equal(vr_scene_parse(BOM, sizeof BOM - 1, "room.scn", &s, &err), VR_E_PARSE);
  assert_contains(err.message, "room.scn:1:36: ");
  assert_int_equal(vr_scene_parse(BOM, 3, "room.scn", &s, &err), VR_E_PARSE);
  assert_contains(err.message, "nothing to render");
  static const char BOM_OK[] = "\xEF\xBB\xBF"
                               "camera pinhole from=0,0,0 to=0,1,0\n";
  assert_int_equal(vr_scene_parse(BOM_OK, sizeof BOM_OK - 1, "room.scn", &s, &err), VR_OK);
  assert_true(s->camera.given);
  vr_scene_destroy(s);
  /* Text cut short in the middle of a statement fails cleanly. */
  const char *full = FULL;
  for (size_t n = 0; n < strlen(full); n += 7) {
    if (vr_scene_parse(full, n, NAME, &s, &err) == VR_OK) vr_scene_destroy(s);
  }
  /* Arbitrary bytes: deterministic noise over the scene's alphabet. */
  char noise[512];
  unsigned x = 12345;
  for (int round = 0; round < 2000; round++) {
    for (size_t i = 0; i < sizeof noise; i++) {
      x = x * 1103515245u + 12345u;
      noise[i] = (x >> 16) % 7 == 0 ? FULL[(x >> 8) % (sizeof FULL - 1)] : (char)(x >> 20);
    }
    if (vr_scene_parse(noise, sizeof noise, NAME, &s, &err) == VR_OK) vr_scene_destroy(s);
  }
}

static void read_file(void **state) {
  (void)state;
  vr_scene *s = NULL;
  vr_error err = {0};
  const char *path = vr_test_file("camera pinhole from=0,0,0 to=0,1,0\nmaterial m black\n"
                                  "mesh chair.obj material=m\nlight point position=0,0,2 ies=/ies/a.ies\n");
  assert_non_null(path);
  assert_int_equal(vr_scene_read(path, &s, &err), VR_OK);
  assert_string_equal(s->path, path);
  assert_string_equal(s->dir, "/tmp");
  assert_string_equal(s->objects[0].mesh_path, "/tmp/chair.obj");
  assert_string_equal(s->lights[0].ies_path, "/ies/a.ies");
  vr_scene_destroy(s);
  unlink(path);
  assert_int_equal(vr_scene_read("/nonexistent/x.scn", &s, &err), VR_E_IO);
  assert_null(s);
  vr_scene_destroy(NULL);
}

/* vr-render --render: the command line's options replace the file's
 * render line; those it leaves out take the defaults of
 * docs/scene-format.md's render line (knn=50, depth=8, seed=1), not the
 * file's; its errors name "--render" and the column in its own text. */
static void render_line_override(void **state) {
  (void)state;
  vr_scene *s = NULL;
  vr_error err = {0};
  const char *file = "camera pinhole from=0,0,0 to=0,4,0\n"
                     "render integrator=photon photons=2000000 knn=400 spp=16 depth=5 seed=9\n";
  assert_int_equal(vr_scene_parse_with(file, strlen(file), NAME, "integrator=progressive spp=8",
                                       &s, &err), VR_OK);
  const vr_scene_settings *g = &s->settings;
  assert_int_equal(g->integrator, VR_INT_PROGRESSIVE);
  assert_int_equal(g->spp, 8);
  assert_int_equal(g->photons, 200000); /* the default, not the file's 2000000 */
  assert_int_equal(g->knn, 50);
  assert_int_equal(g->max_depth, 8);
  assert_true(g->seed == 1);
  /* progressive's own rule (its 8 wavelengths) applies to the new line */
  assert_int_equal(g->wavelengths, VR_SCENE_MAX_WAVELENGTHS);
  assert_string_equal(g->source, "--render");
  assert_int_equal(g->loc.line, 1);
  vr_scene_destroy(s);
  /* Without --render the file's line, its source the file. */
  assert_int_equal(vr_scene_parse_with(file, strlen(file), NAME, NULL, &s, &err), VR_OK);
  assert_int_equal(s->settings.knn, 400);
  assert_null(s->settings.source);
  vr_scene_destroy(s);
  /* A file without a render line takes the command line's. */
  const char *bare = "camera pinhole from=0,0,0 to=0,4,0\n";
  assert_int_equal(vr_scene_parse_with(bare, strlen(bare), NAME, "integrator=path", &s, &err), VR_OK);
  assert_int_equal(s->settings.integrator, VR_INT_PATH);
  vr_scene_destroy(s);
  /* An empty line: every default. */
  assert_int_equal(vr_scene_parse_with(file, strlen(file), NAME, "", &s, &err), VR_OK);
  assert_int_equal(s->settings.integrator, VR_INT_PHOTON);
  assert_int_equal(s->settings.spp, 16);
  vr_scene_destroy(s);
  /* Errors: the word's column in the option's text. */
  assert_int_equal(vr_scene_parse_with(file, strlen(file), NAME, "spp=4 integrator=nope", &s, &err),
                   VR_E_PARSE);
  assert_null(s);
  assert_non_null(strstr(err.message, "--render:1:7:"));
  assert_non_null(strstr(err.message, "integrator"));
  assert_int_equal(vr_scene_parse_with(file, strlen(file), NAME, "spp=4 colour=red", &s, &err),
                   VR_E_PARSE);
  assert_non_null(strstr(err.message, "--render:1:7:"));
  assert_int_equal(vr_scene_parse_with(file, strlen(file), NAME, "spp=4\ncamera x", &s, &err),
                   VR_E_PARSE);
  assert_non_null(strstr(err.message, "--render:1:6:"));
  assert_int_equal(vr_scene_parse_with(file, strlen(file), NAME, "spp=4 # a comment", &s, &err),
                   VR_E_PARSE);
  assert_non_null(strstr(err.message, "no line break or comment"));
  /* The file's own render line is still checked, and named. */
  const char *badfile = "camera pinhole from=0,0,0 to=0,4,0\nrender spp=zero\n";
  assert_int_equal(vr_scene_parse_with(badfile, strlen(badfile), NAME, "spp=4", &s, &err),
                   VR_E_PARSE);
  assert_non_null(strstr(err.message, NAME ":2:8:"));
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(render_line_override),
      cmocka_unit_test(full_scene),      cmocka_unit_test(defaults),
      cmocka_unit_test(bins_default),
      cmocka_unit_test(transform_order), cmocka_unit_test(errors),
      cmocka_unit_test(whole_file_errors), cmocka_unit_test(text_robustness),
      cmocka_unit_test(read_file), cmocka_unit_test(sensor_knn_follows_knn),
      cmocka_unit_test(photon_portals_default),
      cmocka_unit_test(sun_by_site_and_time), cmocka_unit_test(sky_needs_the_sun)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
