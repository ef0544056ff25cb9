/* Rough interfaces with the isotropic GGX (Trowbridge-Reitz) microfacet
 * distribution: the distribution D, Smith masking, the reflection and
 * transmission BSDFs of a rough dielectric (Walter, Marschner, Li, Torrance,
 * "Microfacet models for refraction through rough surfaces", EGSR 2007), the
 * BRDF of a rough conductor, and importance sampling of the visible normals
 * (Heitz, "Sampling the GGX distribution of visible normals", JCGT 7(4),
 * 2018).  Single scattering only: energy that would bounce again between
 * microfacets is lost, more of it for rough surfaces and grazing directions.
 *
 * Conventions:
 *  - local shading frame, macro normal +z; every direction is a unit vector
 *    pointing away from the surface point (wo towards the viewer or the
 *    previous vertex, wi towards the light or the next vertex);
 *  - alpha is the GGX roughness (alpha = linear slope width; D at the pole
 *    is 1/(pi alpha^2)).  Values below VR_GGX_ALPHA_MIN, zero and NaN are
 *    raised to it so everything stays finite, but a surface that smooth
 *    should be handed to the specular (delta) Fresnel BSDF by the caller:
 *    the lobes are then narrower than any quadrature or light sampling sees;
 *  - eta is the relative index n_below / n_above of a dielectric (the
 *    medium on the -z side over the one on the +z side), any eta > 0; from
 *    below the functions use 1/eta.  eta == 1 is no interface at all: the
 *    BSDF is a delta along -wo (evaluations return 0, the sampler returns
 *    -wo with weight 1 and pdf INFINITY).  Close to 1 the transmission lobe
 *    is narrow and single scattering loses more energy (the refracted ray is
 *    masked by the same microsurface), so 1 is a discontinuity;
 *  - a conductor is one-sided (+z) with complex relative index N = n + i k
 *    (metal over ambient), k >= 0;
 *  - Fresnel terms come from vr_fresnel_interface (vr/optics.h) at the angle
 *    between the incident ray and the microfacet normal, unpolarised:
 *    F = (Rs + Rp) / 2; a dielectric transmits 1 - F; total internal
 *    reflection gives F = 1 exactly;
 *  - masking-shadowing is Smith's, height-correlated (Heitz, "Understanding
 *    the masking-shadowing function in microfacet-based BRDFs", JCGT 3(2),
 *    2014): G2 = 1 / (1 + L(wi) + L(wo)) when wi and wo are on the same
 *    side, and B(1 + L(wi), 1 + L(wo)) (the Euler Beta function) across the
 *    surface, where the shadowing from below is the complement of the height
 *    distribution; it follows from integrating the two visibility
 *    probabilities C(h)^L(wo) and (1 - C(h))^L(wi) over the heights.
 *
 * All functions are pure (no state, thread-safe) and return 0 rather than
 * NaN for directions with no contribution (wrong side, grazing, back-facing
 * microfacet). */
#ifndef VR_MICROFACET_H
#define VR_MICROFACET_H

#include "vr/optics.h"
#include "vr/vec3.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Smallest roughness used; smaller values are raised to it. */
#define VR_GGX_ALPHA_MIN 1e-4

/* Which quantity a path carries.  Only the BTDF differs: for radiance
 * (camera paths, light flowing from wi to wo) it carries the factor
 * (n_o / n_i)^2 of Walter's eq. 21 (radiance is compressed into the solid
 * angle of the denser medium), so that f(wi, wo) / n_o^2 = f(wo, wi) / n_i^2
 * (Veach 1997, thesis ch. 5).  For importance (photon and light paths,
 * power flowing from wo to wi) the adjoint f*(wi, wo) = f(wo, wi) is
 * returned, without that factor. */
typedef enum vr_transport { VR_TRANSPORT_RADIANCE = 0, VR_TRANSPORT_IMPORTANCE = 1 } vr_transport;

/* D(m) = alpha^2 / (pi (1 + (alpha^2 - 1) cos^2)^2) for cos_theta_m > 0
 * (Walter eq. 33), else 0.  Normalised so that the integral of D(m) cos(m)
 * over the hemisphere is 1.  D at grazing (cos 0) is alpha^2 / pi. */
double vr_ggx_D(double alpha, double cos_theta_m);

/* Smith Lambda of the direction w (either side; |w.z| is used):
 * (sqrt(1 + alpha^2 tan^2) - 1) / 2 (Heitz 2014 eq. 86).  INFINITY at
 * grazing (w.z == 0), 0 along the normal. */
double vr_ggx_lambda(double alpha, vr_vec3 w);

/* Masking of microfacet m (m.z > 0) seen from w: 1 / (1 + Lambda(w)) when m
 * faces w from w's side ((w.m) w.z > 0), else 0. */
double vr_ggx_G1(double alpha, vr_vec3 w, vr_vec3 m);

/* Height-correlated masking-shadowing of m for the pair (wi, wo): reflection
 * when both are on the same side, transmission otherwise (see above); 0 when
 * m is back-facing for either direction or either is grazing. */
double vr_ggx_G2(double alpha, vr_vec3 wi, vr_vec3 wo, vr_vec3 m);

/* D G2 / (4 |wi.z| |wo.z|) at the half vector: the BRDF of a rough perfect
 * reflector (F = 1), symmetric in wi and wo.  0 unless both are above the
 * surface (z > 0). */
double vr_ggx_reflection(double alpha, vr_vec3 wi, vr_vec3 wo);

/* Rough conductor BRDF: F(wi.h) times vr_ggx_reflection.  N is the metal's
 * index relative to the (transparent) ambient.  Symmetric; 0 below. */
double vr_ggx_conductor_brdf(double alpha, vr_complex N, vr_vec3 wi, vr_vec3 wo);

/* Rough dielectric, reflected part (Walter eq. 20): wi and wo on the same
 * side, either side; 0 otherwise. */
double vr_ggx_dielectric_brdf(double alpha, double eta, vr_vec3 wi, vr_vec3 wo);

/* Rough dielectric, transmitted part (Walter eq. 21, generalised half vector
 * h = -(n_i wi + n_o wo) turned towards +z): wi and wo on opposite sides; 0
 * when they are on the same side, when no microfacet refracts one into the
 * other, or when eta == 1.  mode chooses radiance or importance (above). */
double vr_ggx_dielectric_btdf(double alpha, double eta, vr_vec3 wi, vr_vec3 wo,
                              vr_transport mode);

/* A microfacet normal m (m.z >= 0) drawn with the density of the normals
 * visible from wo, D_wo(m) = G1(wo, m) max(0, wo.m) D(m) / wo.z (Heitz 2018
 * and 2014), from two uniform numbers in [0, 1).  Needs wo.z > 0 (mirror z for
 * directions below); returns +z otherwise. */
vr_vec3 vr_ggx_sample_vndf(double alpha, vr_vec3 wo, double u1, double u2);
/* D_wo(m) above; 0 for wo.z <= 0 or m.z <= 0. */
double vr_ggx_vndf_pdf(double alpha, vr_vec3 wo, vr_vec3 m);

/* One scattering event.  weight = f |wi.z| / pdf, the factor by which the
 * path throughput is multiplied; pdf is per solid angle of wi and includes
 * the probability of choosing reflection or transmission. */
typedef struct vr_ggx_sample {
  vr_vec3 wi;
  double weight;
  double pdf;      /* INFINITY for the pass-through at eta == 1 */
  int transmitted; /* wi on the other side of the surface from wo */
} vr_ggx_sample;

/* Rough conductor: visible normal, mirror reflection.  Returns 1 with a
 * sample, 0 when the path ends (wo at or below the horizon, or the reflected
 * ray points into the surface: energy lost by single scattering). */
int vr_ggx_conductor_sample(double alpha, vr_complex N, vr_vec3 wo, double u1, double u2,
                            vr_ggx_sample *s);

/* Rough dielectric, from either side: visible normal, then reflection with
 * probability F and refraction otherwise (u3 decides).  The weight is
 * F-free: G2 / G1(wo) for reflection, and the same times (n_o / n_i)^2 for
 * a transmission in radiance mode.  Returns 0 when the path ends (wo
 * grazing, or the new ray lands on the wrong side). */
int vr_ggx_dielectric_sample(double alpha, double eta, vr_vec3 wo, double u1, double u2,
                             double u3, vr_transport mode, vr_ggx_sample *s);

/* Density of wi under vr_ggx_dielectric_sample (by the side of wi), and of
 * the mirror reflection of a visible normal (conductors):
 * D_wo(h) / (4 |wo.h|).  0 where the sampler never goes. */
double vr_ggx_dielectric_pdf(double alpha, double eta, vr_vec3 wo, vr_vec3 wi);
double vr_ggx_reflection_pdf(double alpha, vr_vec3 wo, vr_vec3 wi);

#ifdef __cplusplus
}
#endif
#endif
