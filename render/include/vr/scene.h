/* A scene as the user wrote it in a .scn file: camera, objects, materials by
 * database name, lights, skies, illuminance sensors and render settings.
 * This is plain data, parsed and checked but not yet resolved: material
 * names are not looked up in the database and mesh files are not read here
 * (geometry.h and material resolution do that), so the parser can be tested
 * and fuzzed on its own.  The grammar is documented in docs/scene-format.md
 * and in vr_scene_parse below.
 *
 * Units inside: lengths in metres, angles in degrees as written (converted
 * where used), wavelengths in nm.  Light quantities keep the unit the user
 * gave (vr_light_unit) and are converted by the light code, which knows the
 * spectrum and the geometry needed to do so. */
#ifndef VR_SCENE_H
#define VR_SCENE_H

#include <stdbool.h>
#include <stddef.h>
#include "vr/error.h"
#include "vr/filter.h"
#include "vr/perez.h"
#include "vr/rng.h"
#include "vr/spectrum.h"

#ifdef __cplusplus
extern "C" {
#endif

/* An affine transform: p' = M p + t, row-major 3x4 (m[r][3] is t[r]). */
typedef struct vr_xform {
  double m[3][4];
} vr_xform;

void vr_xform_identity(vr_xform *x);
/* a then b: p -> b(a(p)). */
void vr_xform_then(const vr_xform *a, const vr_xform *b, vr_xform *out);
void vr_xform_point(const vr_xform *x, const double p[3], double out[3]);
void vr_xform_vector(const vr_xform *x, const double v[3], double out[3]);
/* Normals go through the inverse transpose; false if the matrix is singular. */
bool vr_xform_normal(const vr_xform *x, const double n[3], double out[3]);

/* Where a scene element was written, for messages. */
typedef struct vr_scene_loc {
  long line, col;
} vr_scene_loc;

typedef enum vr_camera_model { VR_CAM_PINHOLE = 0, VR_CAM_THINLENS, VR_CAM_FISHEYE } vr_camera_model;

/* Fisheye projections, r the distance from the image circle's centre over
 * its radius and theta the angle from the view direction (theta_max =
 * fov/2): equisolid r = sin(theta/2) / sin(theta_max/2) (equal areas hold
 * equal solid angles, as in glare analysis); angular (equidistant)
 * r = theta / theta_max. */
typedef enum vr_fisheye_projection { VR_FISHEYE_EQUISOLID = 0, VR_FISHEYE_ANGULAR } vr_fisheye_projection;

typedef struct vr_scene_camera {
  vr_camera_model model;
  double from[3], to[3], up[3]; /* from= and to= are required in a camera line; these
                                   defaults (0,0,0) looking at (0,1,0) only fill a
                                   sensor-only scene.  up: unit, default (0,0,1) */
  double fov_deg;               /* horizontal field of view, default 60 */
  int width, height;            /* default 320 x 240 */
  double aperture_m;            /* thin lens: lens radius, metres, default 0 (a pinhole) */
  double focus_m;               /* thin lens: focus distance, default |to - from| */
  double exposure_ev;           /* multiplies the image by 2^exposure_ev, default 0 */
  vr_fisheye_projection projection; /* fisheye: default equisolid; fov is the circle's,
                                       default 180, up to 360 */
  vr_filter filter;             /* pixel filter (filter=, filter_radius=, filter_sigma=),
                                   default box of radius 0.5 (vr/filter.h) */
  bool given;
  vr_scene_loc loc;
} vr_scene_camera;

/* A material alias: a scene name for a database material plus per-object
 * settings.  Lambertian reflectors may be written in the scene: a constant
 * ("material grey lambert reflectance=0.5", for analytic test scenes) or
 * an inline spectrum ("reflectance=[400:0.12,500:0.35,700:0.7]"). */
typedef enum vr_mat_source {
  VR_MATSRC_DB = 0,
  VR_MATSRC_LAMBERT_CONST,
  VR_MATSRC_BLACK,
  VR_MATSRC_BSDF_XML, /* a Klems BSDF XML file (bsdf file=F.xml) */
  VR_MATSRC_GLASS,    /* a non-dispersive dielectric given inline (a Radiance glass or
                         dielectric): ior and transmission below */
  VR_MATSRC_TRANSLUCENT /* a translucent diffuser (a Radiance trans without specular parts):
                           the reflectance as for lambert, the Lambertian transmittance in
                           transmission below */
} vr_mat_source;

typedef enum vr_pane_model {
  VR_PANE_DEFAULT = 0, /* a thin element when the object is a pane-like sheet */
  VR_PANE_THIN,        /* one element, exact multiple internal reflections */
  VR_PANE_INTERFACES   /* two real interfaces (refraction at each) */
} vr_pane_model;

/* How a texture's alpha cuts a surface out (vr_scene_material.alpha). */
typedef enum vr_alpha_mode {
  VR_ALPHA_OFF = 0, /* opaque whatever the alpha */
  VR_ALPHA_MASK,    /* cut out where alpha < alpha_cutoff (glTF alphaMode MASK) */
  VR_ALPHA_BLEND    /* let through with probability 1 - alpha (glTF BLEND, stochastically) */
} vr_alpha_mode;

typedef struct vr_scene_material {
  char *name;            /* scene alias */
  vr_mat_source source;
  char *db_name;         /* VR_MATSRC_DB: the database name (after "db:") */
  double reflectance;    /* VR_MATSRC_LAMBERT_CONST: in [0,1]; 0 for the others */
  char *reflectance_spectrum; /* VR_MATSRC_LAMBERT_CONST: an inline spectrum "[...]"
                                 (vr_scene_inline_spectrum) instead of the constant,
                                 or NULL */
  double roughness;      /* GGX alpha; NAN when not given (smooth) */
  double thickness_m;    /* pane thickness; NAN when not given */
  vr_pane_model pane;
  double state;          /* chromogenic tint state in [0,1]; NAN when not given */
  double charge_mC_cm2;  /* electrochromic charge instead of a state; NAN when not given */
  double temperature_K;  /* photochromic glass temperature; NAN -> 298.15 */
  bool extrapolate;      /* photochromic: evaluate outside the fitted UV and
                            temperature range (extrapolate=yes) */
  char *coating_db;      /* thin-film coating (layered material) name, NULL if none */
  /* VR_MATSRC_BSDF_XML: the file (resolved against the scene's folder) and
   * the world direction its azimuth 90 deg points to (up=; NAN: world up
   * +z, or +y for a horizontal surface). */
  char *bsdf_file;
  double bsdf_up[3];
  /* VR_MATSRC_GLASS: the index (constant over wavelength) and an inline
   * spectrum of transmission: with pane = VR_PANE_THIN a thin pane's
   * internal transmittance per pass at normal incidence (Radiance's glass
   * "transmissivity"), with VR_PANE_INTERFACES an interface whose medium
   * transmits that much per metre (Radiance's dielectric).
   * VR_MATSRC_TRANSLUCENT: transmission is its Lambertian transmittance. */
  double ior;
  char *transmission;
  /* A texture that multiplies the reflectance per point (lambert
   * texture=FILE, or a model's base colour map): a file (resolved against
   * the scene's or the model's folder), or the bytes of an image embedded
   * in a model (texture names it then, "MODEL#N" for messages). */
  char *texture;
  unsigned char *texture_bytes;
  size_t texture_len;
  bool texture_linear;   /* integer samples are linear (colorspace=linear), not sRGB */
  vr_alpha_mode alpha;   /* cut-outs from the texture's alpha */
  double alpha_cutoff;   /* VR_ALPHA_MASK: cut where alpha < this (default 0.5) */
  double tile[2];        /* (u, v) repeats of the texture (default 1, 1) */
  bool texture_off;      /* db:NAME texture=none: the database material's texture unused */
  /* A tangent-space normal map (lambert normal_map=FILE, a model's normal
   * texture): a file, or an embedded image's bytes, as for texture;
   * normal_scale multiplies its x and y (glTF normalTexture.scale). */
  char *normal_map;
  unsigned char *normal_bytes;
  size_t normal_len;
  double normal_scale;
  /* An opacity map (a model's MTL map_d): its alpha, or its grey where it
   * has none, cuts the surface out in place of the texture's alpha (with
   * alpha and alpha_cutoff); a file or an embedded image's bytes. */
  char *alpha_map;
  unsigned char *alpha_map_bytes;
  size_t alpha_map_len;
  /* glTF 2.0 metallic-roughness (the pbr source, a model's glTF
   * materials): the base colour is the reflectance above (times the
   * texture), metallic in [0, 1] and the perceptual roughness r in [0, 1]
   * (GGX alpha = r^2), each multiplied per point by a metallic-roughness
   * texture's blue and green channels (linear) when mr_map names one. */
  bool pbr;
  double metallic, pbr_roughness;
  /* A model's vertex colours (8-bit sRGB, a PLY file's own) multiply the
   * reflectance per point (the objects say vertex_colours too). */
  bool vertex_colours;
  char *mr_map;
  unsigned char *mr_bytes;
  size_t mr_len;
  vr_scene_loc loc;
} vr_scene_material;

typedef enum vr_shape_kind {
  VR_SHAPE_SPHERE = 0, /* center, radius */
  VR_SHAPE_RECT,       /* a finite rectangle: center, normal, size (w along u, h along v), up hint */
  VR_SHAPE_BOX,        /* axis-aligned before the transform: min, max */
  VR_SHAPE_MESH        /* OBJ, PLY or glTF through Assimp */
} vr_shape_kind;

/* Luminous or radiant units a light quantity may be given in. */
typedef enum vr_light_unit {
  VR_UNIT_NONE = 0,
  VR_UNIT_W,       /* radiant power, W */
  VR_UNIT_LM,      /* luminous flux, lm */
  VR_UNIT_CD,      /* luminous intensity, cd */
  VR_UNIT_W_SR,    /* radiant intensity, W/sr */
  VR_UNIT_LX,      /* illuminance, lx */
  VR_UNIT_W_M2,    /* irradiance, W/m2 */
  VR_UNIT_CD_M2,   /* luminance, cd/m2 */
  VR_UNIT_W_M2_SR  /* radiance, W/(m2 sr) */
} vr_light_unit;

/* A quantity as written, e.g. "1000cd" -> {1000, VR_UNIT_CD}. */
typedef struct vr_quantity {
  double value;
  vr_light_unit unit;
} vr_quantity;

/* A spectrum reference: "db:NAME" (an illuminant or reflectance in the
 * database), a CIE illuminant name known to the core (D65, A, ...), "bb:T"
 * for a blackbody, or an inline table "[W:V,W:V,...]" or "[W V W V ...]"
 * (vr_scene_inline_spectrum); NULL for the default of the element. */
typedef char *vr_spectrum_ref;

/* A linear sRGB colour (components in [0, 1]) as an inline reflectance
 * spectrum "[360:v,365:v,...,830:v]": Jakob & Hanika's sigmoid fitted to
 * it under D65 (vr/rgb_spectrum.h).  NULL with *err set when the colour is
 * out of range or no reflectance reaches it. */
char *vr_scene_colour_spectrum(const double rgb_linear[3], vr_error *err);

typedef struct vr_scene_object {
  char *name;             /* optional name=..., else NULL */
  vr_shape_kind shape;
  double center[3], radius;       /* sphere; rect center */
  double normal[3], up[3];        /* rect: unit normal; unit up, the hint made perpendicular
                                     to the normal (the v axis); default hint +z, or +y
                                     when the normal is within ~2.6 deg of vertical */
  double size[2];                 /* rect: width, height */
  double bmin[3], bmax[3];        /* box */
  char *mesh_path;                /* mesh: resolved against the scene file's folder */
  int mesh_material;              /* mesh: -1 for all its triangles, else only those of the
                                     file's material of that index (a mesh line with
                                     material.NAME= or without material= becomes one
                                     object per material of the file) */
  vr_xform xform;                 /* translate/rotate/scale options, in the order written */
  int material;                   /* index into vr_scene.materials; -1 for a mesh line
                                     without material= until vr_scene_load_models */
  vr_quantity emission;           /* emissive surface: cd/m2 or W/(m2 sr); value 0 if none */
  vr_spectrum_ref emission_spectrum;
  int texels[2];                  /* photochromic state map resolution, default 16 x 16 */
  bool vertex_colours;            /* mesh: its file's vertex colours are its material's
                                     reflectance (a PLY file's own colours, see vr/models.h) */
  bool units_given;               /* mesh: units= was written (else its file is read in m) */
  bool outside;                   /* outside=yes: an exterior surface (ground, neighbouring
                                     buildings): light it reflects to a sensor is the
                                     externally reflected component */
  vr_scene_loc loc;
} vr_scene_object;

/* The kind of a light line: its index in the registry of light kinds
 * (render/src/lights/light.c), whose first three are these; a kind added
 * there has the next index and needs no name here. */
typedef enum vr_light_kind {
  VR_LIGHT_POINT = 0,
  VR_LIGHT_SPOT,
  VR_LIGHT_SUN
} vr_light_kind;

typedef enum vr_distribution {
  VR_DIST_ISOTROPIC = 0,
  VR_DIST_LAMBERTIAN,  /* I(theta) = I0 cos(theta) about `normal`, 0 behind */
  VR_DIST_GONIOMETRIC  /* an IES LM-63 file */
} vr_distribution;

typedef struct vr_scene_light {
  vr_light_kind kind;
  double position[3];      /* point, spot */
  double direction[3];     /* spot: axis; sun: direction FROM the scene TO the sun (unit) */
  double normal[3];        /* point light: axis of the Lambertian cosine lobe or of the
                              goniometric file's photometric axis; unit, default (0,0,-1) */
  vr_distribution distribution;
  char *ies_path;          /* goniometric: resolved against the scene's folder */
  double cone_deg;         /* spot: full-power half angle */
  double falloff_deg;      /* spot: extra half angle over which it falls to 0 */
  vr_quantity amount;      /* point/spot: W, lm, cd or W/sr (cd = I0, on-axis for
                              Lambertian); sun: lx or W/m2 normal to the beam.
                              Goniometric without intensity=: {0, VR_UNIT_NONE},
                              the IES file's own candelas */
  vr_spectrum_ref spectrum;/* default: D65 for lamps, ASTM-G173-AM1.5D for the sun */
  double sun_radius_deg;   /* apparent radius, default 0.2665; 0 is a parallel beam */
  bool from_sky;           /* sun: no place given; a weather sky places it at the end
                              of parsing (a sun with no illuminance= has amount NAN
                              until a Perez sky sets it) */
  int day_of_year;         /* sun placed by date: its day (1..366), else 0 */
  double shape[8];         /* the kind's own numbers, laid out by its file in
                              render/src/lights/ (a tube's ends and radius) */
  vr_scene_loc loc;
} vr_scene_light;

/* The sky: one of the 15 CIE standard general skies (ISO 15469:2004 /
 * CIE S 011/E:2003, type 1..15), the traditional CIE overcast sky
 * (Moon & Spencer 1942; type 0 here) or a Perez all-weather sky
 * (VR_SKY_PEREZ, vr/perez.h) made from direct normal and diffuse
 * horizontal irradiances, given or read from a weather file.  The CIE
 * skies' absolute level is given as the diffuse horizontal illuminance (lx)
 * or the zenith luminance (cd/m2); a Perez sky's is computed (lx). */
typedef struct vr_scene_sky {
  bool present;
  int cie_type;              /* 0 = traditional overcast, 1..15 = CIE standard general sky,
                                VR_SKY_PEREZ = Perez all-weather */
  /* Perez: the inputs (from the line or the weather record) and, once the
   * whole file is read, the model's state (coefficients, illuminances). */
  double direct_normal_w_m2, diffuse_horizontal_w_m2, dew_point_c; /* dew point NAN: none */
  int day_of_year;           /* 0: mean Earth-Sun distance */
  char *weather_path;        /* weather=FILE (resolved), or NULL */
  long weather_line;         /* the record's line in that file */
  bool sun_from_weather;     /* sun_direction computed from the file's site, date and time */
  bool annual;               /* weather= with no date and time: a year of skies
                                (vr/annual.h), not one render */
  vr_perez_sky perez;        /* filled by the parser's last pass */
  double sun_direction[3];   /* unit, towards the sun: the sun line's, or the sky's sun= */
  bool sun_given;            /* the sky line gave sun=ALTITUDE,AZIMUTH itself */
  vr_quantity level;         /* lx (diffuse horizontal) or cd/m2 (zenith) */
  vr_spectrum_ref spectrum;  /* default CIE D65 */
  double ground_reflectance; /* below the horizon: a uniform ground, default 0.2 */
  vr_scene_loc loc;
} vr_scene_sky;

/* A sky portal: a rectangle corner + s u + t v (s, t in [0, 1]) through
 * which the sky lights the interior (a window).  Only a sampling hint for
 * the sky's next-event estimation; the estimate stays unbiased for light
 * that comes another way. */
#define VR_SCENE_MAX_PORTALS 64

typedef struct vr_scene_portal {
  double corner[3], u[3], v[3];
  vr_scene_loc loc;
} vr_scene_portal;

typedef struct vr_scene_sensor {
  char *name;
  bool grid;
  double position[3];        /* point; grid: origin corner */
  double normal[3];          /* unit */
  double u[3], v[3];         /* grid: edge vectors */
  int nu, nv;                /* grid: points along u and v (>= 1) */
  /* A points file (sensor NAME points file=F.pts): nu points, nv = 1, each
   * x y z dx dy dz (the normal unit) in pts[6 k ..]; it counts as a grid
   * (an analysis grid, as Radiance's .pts files are).  NULL otherwise. */
  double *pts;
  char *pts_path;
  vr_scene_loc loc;
} vr_scene_sensor;

/* The integrator: its index in the registry of integrators
 * (render/src/integrators/integrator.c), whose first five are these. */
typedef enum vr_integrator {
  VR_INT_PATH = 0,       /* reference path tracer */
  VR_INT_WHITTED,        /* the paper's local illumination: shadow rays + specular */
  VR_INT_PHOTON,         /* Jensen: global + caustic photon maps */
  VR_INT_PROGRESSIVE,    /* progressive photon mapping, shrinking radius */
  VR_INT_BDPT            /* bidirectional path tracing */
} vr_integrator;

typedef enum vr_spectral_mode { VR_SPECTRAL_HERO = 0, VR_SPECTRAL_BINS } vr_spectral_mode;

/* How sensors estimate irradiance: path tracing from the sensor point (the
 * reference, any sensor position), or density estimation in the direct,
 * caustic and global photon maps (the sensor must lie on a diffuse
 * surface, where photons are stored). */
typedef enum vr_sensor_estimator { VR_SENSORS_PATH = 0, VR_SENSORS_PHOTON } vr_sensor_estimator;

/* The most wavelengths one path carries. */
#define VR_SCENE_MAX_WAVELENGTHS 8

typedef struct vr_scene_settings {
  vr_integrator integrator;   /* default photon */
  int spp;                    /* samples per pixel, default 16 */
  int max_depth;              /* default 8 */
  vr_spectral_mode spectral;  /* default hero */
  int wavelengths;            /* per path, default 4 (hero), VR_SCENE_MAX_WAVELENGTHS (bins) */
  double lambda_min, lambda_max; /* sampled range, default 360..830 nm */
  long photons;               /* global photons per pass, default 200000 */
  long caustic_photons;       /* default 200000 */
  int knn;                    /* photons per estimate, default 50 */
  int sensor_knn;             /* photons per estimate at photon sensors' gather vertices
                                 (sensor_knn=, default knn): gathering averages many
                                 estimates, so fewer than an image's direct view needs */
  bool photon_portals;        /* photon_portals=on: the far sources also emit photons
                                 through the portals (portals.c); default off */
  bool photon_portals_given;  /* photon_portals= was written: when it was not, photon
                                 sensors (sensors=photon) in a scene with portals turn it
                                 on (vr_scene_photon_portals) */
  double radius_m;            /* fixed radius; NAN -> k-nearest */
  bool final_gather;          /* default false */
  int gather_rays;            /* default 32 */
  int passes;                 /* progressive: photon passes, default 16 */
  double alpha;               /* progressive radius reduction, default 2/3 */
  int sensor_samples;         /* paths per sensor point, default 4096 */
  vr_sensor_estimator sensors;/* default path */
  unsigned long long seed;    /* default 1 */
  vr_sampler_kind sampler;    /* sampler=: independent (default), stratified or sobol
                                 (vr/rng.h) */
  /* Spectral film: bins of the spectral EXR. */
  double film_min_nm, film_max_nm, film_step_nm; /* default 400, 700, 10 */
  vr_scene_loc loc;
  const char *source;         /* where the render line was written: NULL, the scene file;
                                 "--render", the command line (vr_scene_parse_with) */
} vr_scene_settings;

/* The annual study of a scene whose sky is a whole weather file (vr/annual.h):
 * the 'annual' line, or its defaults when the scene has none. */
#define VR_ANNUAL_MAX_STATES 16
#define VR_ANNUAL_MAX_VIEWS 16
typedef enum vr_annual_control {
  VR_CONTROL_FIXED = 0,   /* the glass keeps the scene's state all year */
  VR_CONTROL_ILLUMINANCE, /* the lightest state keeping every control point <= max (lx) */
  VR_CONTROL_SUN,         /* the lightest state keeping direct sun at every control point <= max (lx) */
  VR_CONTROL_GLARE,       /* the lightest state keeping DGPs (Wienold 2009) of the vertical
                             illuminance at every control point <= max */
  VR_CONTROL_UV,          /* photochromic glass: the state its own UV exposure gives */
  VR_CONTROL_LM83         /* a shade (shade= window=): drawn in the hours when more than 2 % of
                             the work plane sees 1000 lx of direct sun (IES LM-83-12) */
} vr_annual_control;

typedef struct vr_scene_annual {
  bool given;                /* an 'annual' line */
  double from_h, to_h;       /* occupied hours, local standard time: 8, 18 */
  double da_lx, sda_share;   /* 300 lx, 0.5 */
  double udi_lo, udi_hi;     /* 100, 3000 lx */
  double ase_lx, ase_hours;  /* 1000 lx, 250 h */
  int glass;                 /* material index of the switchable glass (glass=), -1 */
  int nstates;               /* tint states rendered (states=); 0 before the defaults */
  double states[VR_ANNUAL_MAX_STATES]; /* ascending, in [0, 1] */
  vr_annual_control control;
  double max;                /* the control's threshold; NAN: 3000 lx (illuminance), 1000 lx
                                (sun), DGPs 0.35 (glare) */
  int control_sensor;        /* sensor index, -1: every sensor */
  /* The work plane sDA and ASE are over (IES LM-83: the analysis grid,
   * not a view sensor): a grid or points-file sensor's index
   * (workplane=NAME), or -1: every grid and points-file sensor, whatever
   * its orientation (every sensor in a scene without them). */
  int workplane;
  /* occupancy=FILE: the occupied hours from a schedule (a Daysim
   * month,day,time,occupancy file or one 0/1 per weather record), the
   * path resolved against the scene's folder; NULL: the hours= window. */
  char *occupancy_path;
  /* en17037=yes: EN 17037:2018 daylight provision over the work plane, by
   * illuminance over the year's daylight hours (method 2) and by daylight
   * factor (method 1) against E_v,d,med: edmed= (lx, a national annex's
   * Table A.3 value), NAN: the median from the weather file. */
  bool en17037;
  double edmed_lx;
  /* shade=MATERIAL window=MATERIAL: an operable shade for sDA; every object
   * of the window material takes the shade material (a BSDF XML of the
   * shaded system, typically) in the hours the LM-83 rule draws it.
   * Material indices, -1: none. */
  int shade, shade_window;
  /* glare_views=NAME,...: point sensors at the eye facing a view (up is
   * +z), whose daylight glare probability DGP, contrast term included, is
   * computed hour by hour from fisheye image daylight coefficients of
   * glare_resolution x glare_resolution pixels (default 64).  Sensor
   * indices. */
  int nviews;
  int views[VR_ANNUAL_MAX_VIEWS];
  int view_resolution;
  vr_scene_loc loc;
} vr_scene_annual;

/* A mesh line's material.PATTERN=NAME: the file's materials whose names
 * match PATTERN (shell wildcards) take the scene material NAME. */
typedef struct vr_scene_mesh_map {
  size_t object;   /* the mesh line's object */
  char *pattern;
  int material;    /* index into vr_scene.materials */
  vr_scene_loc loc;
  char *file;      /* a materials=FILE entry: that file (loc is then its line there), else NULL */
} vr_scene_mesh_map;

typedef struct vr_scene {
  char *path, *dir;           /* the file and its folder ("." when the name has none) */
  vr_scene_camera camera;
  size_t nmaterials;
  vr_scene_material *materials;
  size_t nobjects;
  vr_scene_object *objects;
  size_t nlights;
  vr_scene_light *lights;
  vr_scene_sky sky;
  size_t nportals;
  vr_scene_portal *portals;
  size_t nsensors;
  vr_scene_sensor *sensors;
  vr_scene_settings settings;
  vr_scene_annual annual;
  size_t nmesh_maps;
  struct vr_scene_mesh_map *mesh_maps; /* mesh lines' material.PATTERN=NAME, in order,
                                          until vr_scene_load_models (vr/models.h) */
  size_t nnotes;
  char **notes;               /* what the parser decided for the user to hear once (a
                                 model's materials taken from its file), for the
                                 renderer's decision lines */
} vr_scene;

/* Parses a scene from text (name is used in messages and to resolve
 * relative paths; text may hold any bytes, CRLF line ends, no final
 * newline).  Errors are VR_E_PARSE "name:line:col: message", the column
 * that of the word at fault; a scene with neither a camera nor a sensor is
 * refused without a line ("name: no camera and no sensor: ...").  Every
 * object's material index is resolved (materials may come in any order);
 * the sky's sun_direction is the sun light's wherever it is written. */
vr_status vr_scene_parse(const char *text, size_t len, const char *name, vr_scene **out,
                         vr_error *err);
vr_status vr_scene_read(const char *path, vr_scene **out, vr_error *err);
/* The same with the file's render line replaced by `render` (a render
 * line's options, without the keyword: "integrator=progressive spp=16"),
 * as vr-render --render gives it; NULL: the file's.  The file's own render
 * line is still checked; the options `render` leaves out take their
 * defaults, not the file's.  Its errors are "--render:1:col: message", the
 * column that of the word in `render` (counted from 1). */
vr_status vr_scene_parse_with(const char *text, size_t len, const char *name, const char *render,
                              vr_scene **out, vr_error *err);
vr_status vr_scene_read_with(const char *path, const char *render, vr_scene **out, vr_error *err);
void vr_scene_destroy(vr_scene *s);

/* Whether s has a grid or points-file sensor: the annual study's default
 * work plane is theirs (vr_scene_annual.workplane). */
bool vr_scene_has_grid(const vr_scene *s);

/* Whether the far sources also emit photons through the portals: the
 * render line's photon_portals= when written; otherwise on for photon
 * sensors (sensors=photon, with sensor lines) in a scene with portals,
 * where the maps then hold the light that comes in by the windows
 * (docs/benchmarks.md, "The daylit room"), and off for the rest (an
 * image's photons gained nothing from them in the sample room). */
bool vr_scene_photon_portals(const vr_scene *s);

/* The spectrum reference light l uses: its own spectrum=, or its kind's
 * default (D65 for lamps, db:ASTM-G173-AM1.5D for the sun). */
const char *vr_scene_light_spectrum(const vr_scene_light *l);

/* The spectrum of an inline table as a scene file writes it (a reference
 * or a reflectance starting with '['): "[W:V,W:V,...]" or pbrt-v4's pairs
 * "[W V W V ...]", wavelengths in nm strictly increasing, at least two
 * points, values finite and not negative.  NULL (VR_E_PARSE) otherwise. */
vr_spectrum *vr_scene_inline_spectrum(const char *text, vr_error *err);

#ifdef __cplusplus
}
#endif
#endif
