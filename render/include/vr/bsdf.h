/* The renderer's materials: one vr_bsdf per scene material, built once from
 * the database material and the per-object settings (vr_scene_material),
 * then evaluated and sampled from any number of threads (read-only after
 * vr_bsdf_create; no allocation and no database call on the hot path).
 *
 * What a material becomes, from its kind and the settings:
 *   black, lambert reflectance=R        Lambertian (R constant or 0)
 *   pbr color=C metallic=M roughness=R  glTF 2.0 metallic-roughness BRDF
 *                                       (the specification's Appendix B):
 *                                       a Lambertian base under a GGX
 *                                       dielectric coat (ior 1.5, Schlick
 *                                       F0 0.04) mixed with a GGX metal
 *                                       whose Schlick F0 is the base
 *                                       colour, by M; alpha = R^2, a
 *                                       mirror below alpha 1e-3
 *   reflectance (role "value")          Lambertian with that spectrum
 *   conductor                           Fresnel mirror with complex N;
 *                                       GGX (roughness=alpha) when rough
 *   dielectric, thickness, model=thin   thin pane: one straight-through
 *   (default when a thickness is known) element, R and T from the exact
 *                                       thick-slab series (vr_slab)
 *   dielectric, model=interfaces or no  one refracting interface (Fresnel
 *   thickness                           with complex N, Snell, total
 *                                       internal reflection); absorption
 *                                       inside is the caller's, through
 *                                       vr_bsdf_medium_sigma_a; GGX
 *                                       reflection + transmission when a
 *                                       roughness is given
 *   dielectric + coating=db:FILM        thin pane with one coherent film
 *                                       (a dielectric or conductor with a
 *                                       "thickness" property) on the
 *                                       coated face, solved with
 *                                       vr_stack_solve; a coating of kind
 *                                       btdf replaces the pane by its table
 *   btdf                                thin pane from its tables
 *   glazing (T, Rf, Rb at 0 deg)        thin pane: the uncoated slab with
 *                                       the same T and R at normal
 *                                       incidence (back-solved n, k), front
 *                                       and back separately
 *   bsdf file=F.xml [up=X,Y,Z]          a Klems BSDF XML file's Visible
 *                                       band, grey, patch by patch
 *                                       (bsdf_klems.c): glossy reflection
 *                                       and transmission, not thin
 *   glass (inline, a Radiance glass)    thin pane: n constant, k from the
 *                                       internal transmittance per pass
 *   glass model=interfaces (a Radiance  one interface, n constant, the
 *   dielectric)                         medium transmitting t per metre
 *   translucent (inline, a Radiance     Lambertian reflection on either
 *   trans without specular parts)       side, Lambertian transmission to
 *                                       the other (a glossy-T lobe)
 *   chromogenic                         thin pane whose normal-incidence
 *                                       T, Rf, Rb follow the state s; the
 *                                       angles through the same equivalent
 *                                       slab, solved per evaluation
 *
 * Conventions.  Directions are unit vectors pointing away from the surface
 * point: wo towards the viewer (camera paths) or back where the photon came
 * from, wi the other one.  n is the surface normal: for a pane its front
 * (Rf) side, for an interface the outside (the medium is on the -n side).
 * Opaque materials (Lambertian, conductors) reflect on whichever side wo is.
 * Wavelengths in nm; nm[0] is the hero wavelength; at most
 * VR_BSDF_MAX_WAVELENGTHS per call.  Outside [lambda_min, lambda_max] the
 * end values are held.  Transport mode as in vr/microfacet.h: radiance
 * transmissions carry (n_o / n_i)^2, importance ones do not. */
#ifndef VR_BSDF_H
#define VR_BSDF_H

#include <stdbool.h>
#include "vr/error.h"
#include "vr/material.h"
#include "vr/microfacet.h"
#include "vr/scene.h"

#ifdef __cplusplus
extern "C" {
#endif

#define VR_BSDF_MAX_WAVELENGTHS 16

typedef enum vr_lobe {
  VR_LOBE_DIFFUSE = 1,
  VR_LOBE_SPECULAR_R = 2,
  VR_LOBE_SPECULAR_T = 4, /* refraction through an interface */
  VR_LOBE_GLOSSY_R = 8,
  VR_LOBE_GLOSSY_T = 16,
  VR_LOBE_STRAIGHT = 32   /* thin pane: transmission without deflection */
} vr_lobe;
#define VR_LOBE_DELTA (VR_LOBE_SPECULAR_R | VR_LOBE_SPECULAR_T | VR_LOBE_STRAIGHT)

typedef struct vr_bsdf vr_bsdf;

/* sm: the scene's settings; m: the database material (NULL for lambert
 * constants and black); coating: the material named by coating=db:...
 * (NULL if none).  Tables cover [lambda_min, lambda_max] on a 1 nm grid.
 * Errors start with "LINE:COL: material 'ALIAS' (db:NAME): " so the caller
 * prepends the scene's path (vr_error_prefix(err, "%s:", path)). */
vr_status vr_bsdf_create(const vr_scene_material *sm, const vr_material *m,
                         const vr_material *coating, double lambda_min, double lambda_max,
                         vr_bsdf **out, vr_error *err);
void vr_bsdf_destroy(vr_bsdf *b);

/* The lobes this material can scatter into (vr_lobe bits). */
unsigned vr_bsdf_lobes(const vr_bsdf *b);
/* A refracting interface whose n varies over [lambda_min, lambda_max]:
 * its refractions keep the hero wavelength only (terminate_secondary). */
bool vr_bsdf_dispersive(const vr_bsdf *b);
bool vr_bsdf_is_chromogenic(const vr_bsdf *b);
bool vr_bsdf_is_photochromic(const vr_bsdf *b);
/* A thin element shadow rays go through (pane, glazing, btdf, chromogenic). */
bool vr_bsdf_is_thin(const vr_bsdf *b);
/* The state the settings give (state=, or charge= for electrochromic glass;
 * 0 when neither); used when a call passes state = NAN. */
double vr_bsdf_default_state(const vr_bsdf *b);
/* Whether some table had to hold its end values to cover the range (the
 * material's data stop short of lambda_min or lambda_max). */
bool vr_bsdf_extrapolated(const vr_bsdf *b);
/* Short description for the scene analysis ("thin pane (vr_slab, 4 mm)"). */
const char *vr_bsdf_describe(const vr_bsdf *b);

/* BSDF value (no cosine) of the non-delta lobes for each of nwl wavelengths
 * into f, and the density (per solid angle of wi) with which
 * vr_bsdf_sample_dir would pick wi given wo into *pdf (may be NULL).  Delta
 * lobes contribute 0 to both.  state: chromogenic state in [0, 1], NAN for
 * the default; ignored by other kinds. */
void vr_bsdf_eval(const vr_bsdf *b, double state, vr_vec3 n, vr_vec3 wo, vr_vec3 wi, int nwl,
                  const double *nm, vr_transport mode, double *f, double *pdf);

typedef struct vr_bsdf_sample {
  vr_vec3 wi;
  double weight[VR_BSDF_MAX_WAVELENGTHS]; /* f |cos(wi)| / pdf, delta lobes included */
  double pdf;      /* per solid angle; for a delta lobe the probability of choosing it */
  unsigned lobe;   /* the one vr_lobe bit sampled */
  bool terminate_secondary; /* dispersive refraction: only weight[0] is non-zero and it
                               already carries the factor nwl (pbrt-v4's convention) */
  double eta;      /* index on wi's side over wo's side; 1 if no interface crossed */
} vr_bsdf_sample;

/* Draws wi from three uniform numbers in [0, 1).  The lobe is chosen with
 * probabilities proportional to its albedo averaged over the nwl wavelengths
 * (so a wavelength that one lobe serves keeps a finite weight); every
 * wavelength's weight is its own value over that probability, so all stay
 * unbiased.  Returns false when the path ends (absorbed, black, wo
 * grazing, microfacet sample below the surface). */
bool vr_bsdf_sample_dir(const vr_bsdf *b, double state, vr_vec3 n, vr_vec3 wo, int nwl,
                        const double *nm, vr_transport mode, double u1, double u2, double u3,
                        vr_bsdf_sample *out);

/* What one surface point changes in its material (textures), for the
 * *_at calls; NULL there is the material as created.
 *   - base: per wavelength (nwl values), multiplies a pbr material's base
 *     colour (its base-colour texture); NULL: 1.  Other kinds ignore it
 *     (the caller multiplies their BSDF by a texture's factor itself);
 *     base_mean is its mean over the wavelengths (it sets the probability
 *     of choosing the diffuse or the specular lobe, which must not depend
 *     on how many wavelengths a call evaluates);
 *   - metallic, roughness: a pbr material's at this point (its
 *     metallic-roughness texture times its factors), NAN: the material's;
 *   - only: the lobes (vr_lobe bits) to evaluate and sample, 0: all.  The
 *     photon integrators estimate a pbr surface's diffuse part from their
 *     maps and follow its specular part only. */
typedef struct vr_bsdf_point {
  bool has_base;
  double base[VR_BSDF_MAX_WAVELENGTHS];
  double base_mean;
  double metallic, roughness;
  unsigned only;
} vr_bsdf_point;
/* The point of the material as created: no texture, every lobe. */
vr_bsdf_point vr_bsdf_point_plain(void);
/* vr_bsdf_eval and vr_bsdf_sample_dir at a point (pt may be NULL). */
void vr_bsdf_eval_at(const vr_bsdf *b, const vr_bsdf_point *pt, double state, vr_vec3 n,
                     vr_vec3 wo, vr_vec3 wi, int nwl, const double *nm, vr_transport mode,
                     double *f, double *pdf);
bool vr_bsdf_sample_at(const vr_bsdf *b, const vr_bsdf_point *pt, double state, vr_vec3 n,
                       vr_vec3 wo, int nwl, const double *nm, vr_transport mode, double u1,
                       double u2, double u3, vr_bsdf_sample *out);
/* A glTF metallic-roughness material (source pbr): its base colour is
 * inside the BSDF, so a texture reaches it through vr_bsdf_point.base. */
bool vr_bsdf_is_pbr(const vr_bsdf *b);
/* A BSDF XML material (bsdf file=F.xml): a window or shade given by its
 * Klems matrices (VR_LOBE_GLOSSY_R | VR_LOBE_GLOSSY_T). */
bool vr_bsdf_is_klems(const vr_bsdf *b);

/* Shadow rays: transmittance (unpolarised) of a thin element along a
 * straight line meeting it at cos_theta (either sign), per wavelength.
 * false, with T untouched, for every other kind (they block shadow rays). */
bool vr_bsdf_straight_transmittance(const vr_bsdf *b, double state, double cos_theta, int nwl,
                                    const double *nm, double *T);

/* Directional-hemispherical reflectance R, transmittance T and A = 1 - R - T
 * at one wavelength for light arriving at cos_theta (> 0 from the n side,
 * < 0 from behind: inside an interface dielectric, the back of a pane).
 * Analytic for specular lobes and the Lambertian; glossy lobes by a fixed
 * stratified quadrature over the visible normals (power, importance mode).
 * For an interface T is what enters the other medium; for GGX, A includes
 * the energy single scattering loses. */
void vr_bsdf_rta(const vr_bsdf *b, double state, double cos_theta, double nm, double *R,
                 double *T, double *A);

/* Absorption coefficient (1/m) inside an interface dielectric,
 * 4 pi k / lambda; 0 for every other kind. */
double vr_bsdf_medium_sigma_a(const vr_bsdf *b, double nm);

/* The uncoated slab that has normal-incidence transmittance T and
 * reflectance R (thick-slab series, all internal reflections in power):
 * its real index n and internal single-pass transmittance a in [0, 1]
 * (k = -lambda ln(a) / (4 pi d)).  The algebra of fit/'s
 * vr_slab_invert_normal (smaller root of the quadratic in the face
 * reflectance) without its flags and derivatives, and total: T = 0 gives
 * a = 0 with the face reflectance R; data no slab matches are clamped to
 * the nearest one (a = 1 when a > 1, n = 1 when R = 0). */
void vr_bsdf_equivalent_slab(double T, double R, double *n, double *a);

#ifdef __cplusplus
}
#endif
#endif
