/* Inside vr_bsdf: the struct, the wavelength and angle grids it is
 * tabulated on, and the per-kind functions the dispatcher (bsdf_eval.c)
 * calls in the local shading frame, where the surface normal is +z. */
#ifndef VR_BSDF_INTERNAL_H
#define VR_BSDF_INTERNAL_H

#include <math.h>
#include <stddef.h>

#include "vr/bsdf.h"

/* Nodes of the pane tables, uniform in sqrt(cos(theta)) on [0, 1].  Near
 * grazing the face reflectance r -> 1 and an absorbing pane's
 * T ~ (1 - r)^2 a / (1 - a^2) turns into the lossless T ~ (1 - r) / 2
 * within cos ~ 1e-3: uniform nodes in cos miss that bend (1.4e-3 error
 * with 181 of them for 4 mm soda-lime), nodes uniform in sqrt(cos) are
 * 30 times finer there.  Measured against direct vr_slab on a 2000 x 1880
 * grid of (cos, wavelength), 360-830 nm, 4 mm: largest |dT|, |dR|
 * 2.2e-5 (soda-lime), 1.4e-5 (N-BK7), 1.1e-5 (fused silica); the test
 * (tests/render/test_bsdf_pane.c) asserts < 1e-4. */
#define VR_BSDF_PANE_NODES 256

typedef enum vr_bsdf_kind {
  VR_BK_BLACK = 0,
  VR_BK_LAMBERT,
  VR_BK_CONDUCTOR, /* smooth mirror or GGX */
  VR_BK_INTERFACE, /* refracting dielectric interface, smooth or GGX */
  VR_BK_PANE,      /* thin element from tables over (cos, wavelength) */
  VR_BK_CHROMO,    /* thin element whose normal-incidence T, R follow the state */
  VR_BK_PBR,       /* glTF metallic-roughness (bsdf_pbr.c) */
  VR_BK_KLEMS,     /* a Klems BSDF XML file (bsdf_klems.c) */
  VR_BK_TRANSLUCENT /* Lambertian reflection (refl) and transmission (trans), bsdf_translucent.c */
} vr_bsdf_kind;

typedef struct vr_klems_bsdf vr_klems_bsdf;

struct vr_bsdf {
  vr_bsdf_kind kind;
  unsigned lobes;
  bool rough, dispersive, photochromic, extrapolated;
  double alpha;          /* GGX roughness when rough */
  /* pbr: metallic and perceptual roughness (alpha = pbr_r^2) where no
   * texture says otherwise; the base colour is refl, its mean refl_mean. */
  double metallic, pbr_r, refl_mean;
  double default_state;  /* chromogenic */
  char desc[200];

  /* Wavelength grid: lmin + i nm, i = 0 .. nl - 1 (nl >= 2). */
  double lmin;
  size_t nl;
  double *refl;           /* Lambertian reflectance */
  double *trans;          /* translucent: Lambertian transmittance */
  double refl_share;      /* translucent: the mean reflectance over reflectance + transmittance,
                             the probability of sampling the reflection */
  double *n, *k;          /* conductor, interface (and a pane's glass while building) */
  double *sigma_a;        /* interface: 4 pi k / lambda, 1/m */

  /* Pane tables, nl x VR_BSDF_PANE_NODES, row per wavelength: unpolarised
   * T (the same from both sides), Rf (from the +n side), Rb (from -n). */
  double *T, *Rf, *Rb;

  /* Chromogenic model per wavelength (vr/chromogenic.h): T0, dOD and the
   * optional Rf0, dRf, Rb0, dRb (NULL when not stored; Rb falls back to
   * Rf, a missing Rf to an uncoated face of index 1.52). */
  double *T0, *dOD, *Rf0, *dRf, *Rb0, *dRb;

  vr_klems_bsdf *klems;   /* VR_BK_KLEMS */
};

/* A shading frame: s, t in the surface, n its normal (right-handed). */
typedef struct vr_shading_frame {
  vr_vec3 s, t, n;
} vr_shading_frame;

static inline vr_vec3 vr_bsdfi_to_local(const vr_shading_frame *f, vr_vec3 v) {
  return (vr_vec3){vr_vec3_dot(v, f->s), vr_vec3_dot(v, f->t), vr_vec3_dot(v, f->n)};
}

static inline vr_vec3 vr_bsdfi_to_world(const vr_shading_frame *f, vr_vec3 v) {
  return (vr_vec3){v.x * f->s.x + v.y * f->t.x + v.z * f->n.x,
                   v.x * f->s.y + v.y * f->t.y + v.z * f->n.y,
                   v.x * f->s.z + v.y * f->t.z + v.z * f->n.z};
}

/* Where a wavelength falls on the grid: node i and fraction t to i + 1. */
typedef struct vr_bsdf_at {
  size_t i;
  double t;
} vr_bsdf_at;

static inline vr_bsdf_at vr_bsdfi_at(const vr_bsdf *b, double nm) {
  double x = nm - b->lmin, last = (double)(b->nl - 1);
  if (!(x > 0.0)) x = 0.0; /* NaN too */
  if (x > last) x = last;
  size_t i = (size_t)x;
  if (i > b->nl - 2) i = b->nl - 2;
  return (vr_bsdf_at){i, x - (double)i};
}

static inline double vr_bsdfi_lerp(const double *v, vr_bsdf_at a) {
  return v[a.i] + a.t * (v[a.i + 1] - v[a.i]);
}

/* Directions closer to the plane than this scatter nothing from a GGX
 * surface: the Smith terms (lgamma of Lambda ~ 1/cos) lose all precision
 * beyond it. */
#define VR_BSDF_GRAZING 1e-9

static inline double vr_bsdfi_clamp01(double x) { return x < 0.0 ? 0.0 : (x > 1.0 ? 1.0 : x); }

/* The chromogenic state to use: s clamped to [0, 1], NAN -> the default. */
static inline double vr_bsdfi_state(const vr_bsdf *b, double s) {
  return isnan(s) ? b->default_state : vr_bsdfi_clamp01(s);
}

/* bsdf_fresnel.c: unpolarised Fresnel reflectance of an interface between
 * air (index 1) and a medium N = n + i k, for light arriving at |cos_i|
 * from outside (complex N) or from inside (real n: the medium's absorption
 * belongs to the path, not the interface).  *cos_t receives the cosine of
 * the refracted ray (real Snell with n), 0 when there is none (total
 * internal reflection, or n < 1 beyond its critical angle from outside). */
double vr_bsdfi_fresnel(double n, double k, bool inside, double cos_i, double *cos_t);

/* bsdf_slab.c: T and R (unpolarised) at |cos| of the uncoated slab of real
 * index n >= 1 and normal-incidence internal transmittance a0, in closed
 * form (real Fresnel faces, path length 1 / cos(theta_t)). */
void vr_bsdfi_slab_angular(double n, double a0, double cos_i, double *T, double *R);
/* Adjusts a model's *T, *R at some angle so that the model, which gives T1,
 * R1 at normal incidence, reproduces the measured Tn, Rn there exactly
 * (the inversion clamps data no slab can produce); keeps R = 1 at grazing,
 * both in [0, 1] and R + T <= 1. */
void vr_bsdfi_match(double Tn, double Rn, double T1, double R1, double *T, double *R);

/* bsdf_pane.c: R (of the side cos_i comes from) and T of a thin element at
 * one wavelength. */
void vr_bsdfi_pane_rt(const vr_bsdf *b, double state, double cos_i, double nm, double *R,
                      double *T);

/* bsdf_tables.c: fill b->T, Rf, Rb for each thin-element source
 * (bsdf_btdf.c for stored btdf tables); node j of the cos axis, the
 * allocation, and storing one node (clamped to [0, 1], R + T <= 1). */
double vr_bsdfi_node_cos(size_t j);
vr_status vr_bsdfi_tables_alloc(vr_bsdf *b, vr_error *err);
void vr_bsdfi_store(vr_bsdf *b, size_t i, size_t j, double T, double Rf, double Rb);
vr_status vr_bsdfi_table_slab(vr_bsdf *b, double d_nm, vr_error *err);
vr_status vr_bsdfi_table_glazing(vr_bsdf *b, const vr_material *m, double d_nm, vr_error *err);
vr_status vr_bsdfi_table_btdf(vr_bsdf *b, const vr_material *m, vr_error *err);
vr_status vr_bsdfi_table_coated(vr_bsdf *b, const vr_material *film, double film_nm,
                                double d_nm, vr_error *err);

/* Per-kind evaluation and sampling in the local frame (normal +z).  The
 * samplers fill out->wi in that frame. */
void vr_bsdfi_conductor_eval(const vr_bsdf *b, vr_vec3 wo, vr_vec3 wi, int nwl, const double *nm,
                             double *f, double *pdf);
bool vr_bsdfi_conductor_sample(const vr_bsdf *b, vr_vec3 wo, int nwl, const double *nm,
                               double u1, double u2, vr_bsdf_sample *out);
double vr_bsdfi_conductor_fresnel(const vr_bsdf *b, double nm, double cos_i);
double vr_bsdfi_conductor_albedo(const vr_bsdf *b, double nm, double cos_i);

void vr_bsdfi_dielectric_eval(const vr_bsdf *b, vr_vec3 wo, vr_vec3 wi, int nwl,
                              const double *nm, vr_transport mode, double *f, double *pdf);
bool vr_bsdfi_dielectric_sample(const vr_bsdf *b, vr_vec3 wo, int nwl, const double *nm,
                                vr_transport mode, double u1, double u2, double u3,
                                vr_bsdf_sample *out);
void vr_bsdfi_dielectric_rt(const vr_bsdf *b, double cos_i, double nm, double *R, double *T);

/* bsdf_pbr.c: the glTF metallic-roughness BRDF at one point, set up from
 * the material and the point's textures (vr_bsdf_point, may be NULL) for
 * nwl wavelengths, then evaluated and sampled in the local frame with wo
 * above the surface. */
typedef struct vr_bsdfi_pbr {
  double base[VR_BSDF_MAX_WAVELENGTHS]; /* the base colour per wavelength */
  double base_mean, metallic, alpha;
  bool mirror;    /* alpha below the mirror threshold: a delta specular lobe */
  unsigned only;  /* the lobes asked for */
} vr_bsdfi_pbr;
bool vr_bsdfi_pbr_mirror(double alpha);
void vr_bsdfi_pbr_setup(const vr_bsdf *b, const vr_bsdf_point *pt, int nwl, const double *nm,
                        vr_bsdfi_pbr *q);
void vr_bsdfi_pbr_eval(const vr_bsdfi_pbr *q, vr_vec3 wo, vr_vec3 wi, int nwl, double *f,
                       double *pdf);
bool vr_bsdfi_pbr_sample(const vr_bsdfi_pbr *q, vr_vec3 wo, int nwl, double u1, double u2,
                         double u3, vr_bsdf_sample *out);
double vr_bsdfi_pbr_albedo(const vr_bsdf *b, double nm, double cos_i);

/* bsdf_klems.c: a BSDF XML file's Visible band as a grey BSDF, evaluated
 * and sampled patch by patch in its own frame (z the normal n, y the
 * settings' up direction in the surface), from world vectors. */
vr_status vr_bsdfi_klems_create(vr_bsdf *b, const vr_scene_material *sm, vr_error *err);
void vr_bsdfi_klems_destroy(vr_klems_bsdf *k);
void vr_bsdfi_klems_eval(const vr_bsdf *b, vr_vec3 n, vr_vec3 wo, vr_vec3 wi, int nwl,
                         vr_transport mode, double *f, double *pdf);
bool vr_bsdfi_klems_sample(const vr_bsdf *b, vr_vec3 n, vr_vec3 wo, int nwl, vr_transport mode,
                           double u1, double u2, double u3, vr_bsdf_sample *out);
/* R and T for light from the patch at cos_i and azimuth 0 (the
 * directional-hemispherical figures of vr_bsdf_rta, which take no
 * azimuth: exact for layers the same at every azimuth). */
void vr_bsdfi_klems_rt(const vr_bsdf *b, double cos_i, double *R, double *T);

bool vr_bsdfi_pane_sample(const vr_bsdf *b, double state, vr_vec3 wo, int nwl, const double *nm,
                          double u3, vr_bsdf_sample *out);

/* Translucent (bsdf_translucent.c), in the local frame: Lambertian
 * reflection on wo's side (VR_LOBE_DIFFUSE) and Lambertian transmission to
 * the other side (VR_LOBE_GLOSSY_T: not a delta, not stored in photon
 * maps), chosen in proportion to their mean albedos; `only` restricts both
 * to those lobes. */
void vr_bsdfi_translucent_eval(const vr_bsdf *b, unsigned only, vr_vec3 o, vr_vec3 i, int nwl,
                               const double *nm, double *f, double *pdf);
bool vr_bsdfi_translucent_sample(const vr_bsdf *b, vr_vec3 o, int nwl, const double *nm, double u1,
                                 double u2, double u3, vr_bsdf_sample *out);

#endif
