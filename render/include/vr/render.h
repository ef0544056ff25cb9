/* Rendering a parsed scene: what vr-render and the tests call.
 *
 * vr_render_scene resolves the scene's materials in the material database,
 * builds the geometry and the sub-domains, analyses which passes the scene
 * calls for (printing each decision with its reason through `log`), runs
 * them through the domain-decomposed ray flow and returns the film, the
 * sensor readings and the statistics.
 *
 * Radiometry: the film holds spectral radiance in W/(m² sr nm), binned as
 * the scene's `film=` says, and CIE 1931 XYZ with Y in cd/m² (683 lm/W
 * times the integral against the CMFs).  Sensors hold spectral irradiance
 * in W/(m² nm) and illuminance in lx. */
#ifndef VR_RENDER_H
#define VR_RENDER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include "vr/error.h"
#include "vr/fisheye.h"
#include "vr/scene.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vr_matdb vr_matdb;

typedef struct vr_render_options {
  int subdomains;     /* S >= 1, default 1 */
  int threads;        /* P >= 1, default 1 */
  /* Image space, for comparison with the decomposed flow: the scene is one
   * cell (subdomains is ignored) seen whole by every thread, and each
   * thread claims work units (16 x 16 pixel tiles of the camera pass, the
   * other passes' own units) and traces all their rays to the end on a
   * stack of its own: no queues, no hand-over (vr_flow_run_image_space).
   * Same image as the decomposed flow.  Default false. */
  bool image_space;
  /* Folder of the geometry cache (docs/ddm.md); NULL: a private temporary
   * one, removed when the render ends.  vr-render's default is the scene's
   * name with .vrcache beside it. */
  const char *cache_dir;
  /* Bytes the render may hold in loaded sub-domains (their arrays and
   * Embree's BVHs), ray queues, photon maps and photochromic state maps;
   * sub-domains are loaded and unloaded as rays need them.  0: no budget,
   * every sub-domain loaded from the start.  Not with image_space. */
  size_t memory_budget;
  /* Ranks rendering together (vr/comm.h, docs/ddm.md "Ranks"): every rank
   * calls vr_render_scene with the same scene and options; each owns some
   * sub-domains and traces the rays in them, rays travel between ranks as
   * messages, and every rank returns the whole result.  NULL: one process. */
  struct vr_comm *comm;
  int send_batch;     /* rays per message between ranks (0: 256) */
  int send_credit;    /* rays a rank may send another before it credits them back (0: 4096) */
  /* What the ranks must agree they render (the caller's checksum of the
   * scene file and options); compared across ranks with the geometry
   * cache's key when has_digest. */
  bool has_digest;
  unsigned char scene_digest[32];
  int spp;            /* > 0 overrides the scene's samples per pixel */
  /* Adaptive sampling of the camera image (integrators path, whitted and
   * photon; docs/vr-render.md "Adaptive sampling"): with target_error > 0
   * or time_limit_s > 0 the camera pass runs in rounds, the first of two
   * halves of the smallest multiple of spp that is at least 4 (whole
   * blocks of the sampler) samples a pixel, each next one doubling a
   * pixel's samples,
   * and a pixel stops taking samples once its estimated relative standard
   * error is at most target_error (0: never, the time decides), or it has
   * max_spp samples; no round starts that would end past time_limit_s
   * seconds from the render's start (0: no limit), as predicted from the
   * last round (a shorter round when that fits).  max_spp 0: 65536, else
   * at least the first round. */
  double target_error;
  double time_limit_s;
  int max_spp;
  /* The display denoiser (vr/denoise.h; integrators path, whitted and
   * photon): the camera pass also records each sample's albedo, normal and
   * nearness, and keeps the XYZ of the second half of each pixel's samples
   * apart (with a fixed spp, which must then be even, the samples are two
   * passes of spp / 2, each a whole stratified set), and the result gains
   * features and xyz_display.  The raw film (xyz, spectral) and the
   * sensors are the same unbiased estimates, unfiltered (with a fixed spp
   * their random numbers are not those of a render without it: the
   * sampler's blocks are spp / 2).  Not with flow_profile (the halves are
   * two camera passes).  Default false. */
  bool denoise;
  long photons;       /* > 0 overrides the scene's photon counts */
  bool no_camera;     /* sensors only */
  /* Image daylight coefficients: the camera's film also keeps each pixel's
   * luminance by the sky patch (or the ground glow, or the sun) it came
   * from (the result's pixel_patch_Y),
   * for the annual study's glare views (vr/annual.h).  The path integrator
   * only, with a fixed spp (no adaptive sampling, no denoiser).  Such a
   * render leaves the sun's disc out of the picture (the study adds it at
   * the hour's true sun).  Default false. */
  bool pixel_patches;
  /* The camera's film keeps XYZ only, not its spectral bins: 3 doubles a
   * pixel instead of 3 + bins (33 with the default 30 bins), for a render
   * whose outputs do not include the spectral EXR.  The result's spectral
   * is then NULL (the sensors keep their bins).  Default false. */
  bool film_without_bins;
  /* Record what each pass's rays did (vr_flow_profile: each cell's rays
   * and time by kind, the moves between cells, the units' generation),
   * for the model of the decomposition (bench/bench_ddm_sim.c).  One
   * process, not image space; every ray is timed. */
  bool flow_profile;
  void (*log)(void *user, const char *line); /* decisions and timings; may be NULL */
  void (*progress)(void *user, const char *pass, long done, long total); /* may be NULL */
  void *user;
} vr_render_options;

void vr_render_options_default(vr_render_options *o);

#define VR_MAX_PASSES 16

typedef struct vr_pass_record {
  char name[32];
  bool ran;
  char reason[160];
  double seconds;
} vr_pass_record;

/* The parts of a reading (sensors=path; NaN with sensors=photon, whose
 * map radiance has no single source): daylight by the way it arrives, the
 * split-flux components of the daylight factor (CIE 16-1970; BRE Digest
 * 309), each for the sky and the sun, and electric light. */
enum {
  VR_PART_SKY = 0,   /* sky component: from the sky, no reflection on the way */
  VR_PART_SUN,       /* sunlight, no reflection on the way */
  VR_PART_ERC_SKY,   /* externally reflected: last reflected by an outside=yes object or */
  VR_PART_ERC_SUN,   /*   the sky's ground below the horizon; sky light, sunlight */
  VR_PART_IRC_SKY,   /* internally reflected: last reflected by any other surface */
  VR_PART_IRC_SUN,
  VR_PART_ELECTRIC,  /* lamps and emitting surfaces, however they arrive */
  VR_SENSOR_PARTS
};

typedef struct vr_sensor_reading {
  const char *sensor;     /* name in the scene (a copy the result owns) */
  int i, j;               /* grid indices (0,0 for a point) */
  double position[3];
  double illuminance_lx;
  double stderr_lx;       /* standard error of the estimate */
  uint64_t paths;         /* path sensors: the paths it took (adaptive: its own count) */
  double part_lx[VR_SENSOR_PARTS];
  /* Daylight factor: 100 (SC + ERC + IRC of the sky) / E_h, E_h the
   * unobstructed sky's horizontal illuminance (sky_horizontal_lx of the
   * result), and its three components, in %; NaN without a sky or with
   * sensors=photon.  Sunlight is left out, as the definition asks. */
  double df_pct, df_sc_pct, df_erc_pct, df_irc_pct;
} vr_sensor_reading;

/* One rank's share of a render over several ranks. */
typedef struct vr_rank_stats {
  int cells_loaded;           /* cells it held at the end of the render */
  uint64_t credit_waits;      /* times its rays for another rank waited for credit */
  uint64_t ray_messages, ray_bytes_sent; /* its messages of rays, and their bytes */
  uint64_t peak_uncredited;   /* the most rays it held from one rank before crediting them back */
  size_t peak_queue_bytes;    /* its queues', push buffers' and outboxes' peak */
  uint64_t rays_sent, rays_received, messages, bytes_sent, waves;
  uint64_t rays_traced;       /* rays taken from this rank's queues */
  double idle_seconds;        /* its workers' time without a ray or a load, summed over threads */
  uint64_t cell_loads;
  double load_seconds;        /* the time its cells took to load (read, check, build) */
  size_t peak_cells_bytes;
  long long peak_rss_bytes;
  long long rss_base_bytes;   /* budget: its anonymous resident memory before the render added any */
  long long rss_start_bytes;  /* budget: all its resident memory then */
} vr_rank_stats;

enum { VR_RESULT_FEATURES = 7 };

typedef struct vr_render_result {
  int width, height;
  double *xyz;            /* width*height*3, Y in cd/m² */
  size_t nbins;
  double *bin_nm;         /* centre wavelength of each film bin */
  double bin_width_nm;
  double *spectral;       /* width*height*nbins, W/(m² sr nm); NULL with film_without_bins */
  size_t film_bytes;      /* the camera film's sums in each process (XYZ and bins, doubles) */
  /* Adaptive sampling (target_error or time_limit_s): each pixel's samples
   * and the variance of its mean luminance ((cd/m²)², from the means of
   * its two halves of samples: (m_a - m_b)² / 4, unbiased with one degree
   * of freedom); NULL otherwise.  A denoised render of fixed spp has the
   * variance alone (from its halves, or SPPM's two chains), where its
   * files are written. */
  uint32_t *pixel_samples;
  double *pixel_variance;
  struct vr_adaptive_summary {
    int rounds;
    uint32_t spp_first, spp_min, spp_max;
    double spp_mean;
    double converged_share;   /* pixels whose estimate reached target_error */
    double error_p95;         /* the 95th percentile of the pixels' estimated relative error */
    char stop[96];            /* why the last round was the last */
  } adaptive;
  /* Denoising (denoise): per pixel the means of the camera samples'
   * features, albedo R G B (linear sRGB; white is 1), shading normal x y z
   * and nearness 1 / (1 + t / 1 m) (t the distance from the camera; 0 for
   * the sky), VR_RESULT_FEATURES floats;
   * and the denoised XYZ the PNG shows (on the rank that writes the
   * files, rank 0; NULL elsewhere).  NULL without denoise. */
  float *features;
  double *xyz_display;
  double denoise_seconds;
  double exposure_ev;
  size_t nreadings;
  vr_sensor_reading *readings;
  double *sensor_spectral; /* nreadings*nbins, W/(m² nm) */
  char *sensor_names;     /* storage of the readings' names (freed with the result) */
  /* sensors=photon: the share of the sensor paths' diffuse vertices that
   * read the photon maps (the rest went on as paths); 0 otherwise. */
  double sensor_map_share;
  double sky_horizontal_lx; /* the unobstructed sky's horizontal illuminance, 0 without a sky */
  /* Path sensors: each reading's sky light by the Tregenza patch it came
   * from (vr/skypatch.h; VR_SKY_PATCHES + 1 values per reading, the last
   * the ground glow), lx; they sum to the sky and ground parts.  The
   * daylight coefficients of vr/annual.h.  NULL for photon sensors. */
  double *sky_patch_lx;
  /* With pixel_patches: each pixel's luminance by where it came from:
   * VR_SKY_PATCHES + 2 values a pixel, the Tregenza patches
   * (vr/skypatch.h), the ground glow, then the sun; cd/m2, row-major like
   * xyz; NULL otherwise. */
  double *pixel_patch_Y;
  /* A fisheye camera: the illuminance at the lens on the plane facing the
   * view (vr_fisheye_vertical_illuminance of the image's luminance); NaN
   * for other cameras or without a camera pass. */
  double eye_illuminance_lx;
  /* The same camera: the daylight glare probability and its glare sources
   * (vr_fisheye_dgp, evalglare's default threshold); NaN likewise. */
  vr_dgp_result glare;
  size_t npasses;
  vr_pass_record passes[VR_MAX_PASSES];
  uint64_t rays_camera, rays_shadow, rays_photon, rays_other, crossings;
  uint64_t rays_created, rays_finished;
  size_t photons_global, photons_caustic, photons_direct;
  size_t photochromic_texels;
  double *photochromic_state; /* per texel, in object order then v then u */
  double photochromic_state_min, photochromic_state_max;
  size_t photochromic_extrapolated; /* texels outside the fitted UV or temperature
                                       range, evaluated as extrapolate=yes asked */
  /* Per texel (same order): the UV irradiance (300-400 nm, W/m2, both
   * faces) the state came from, and the part of it each Tregenza patch of
   * the sky and the ground glow gave (VR_SKY_PATCHES + 1 values a texel,
   * vr/skypatch.h): the UV daylight coefficients of vr/annual.h. */
  double *photochromic_uv, *photochromic_uv_patch;
  uint32_t *photochromic_object; /* per texel: the scene object it lies on */
  size_t degenerate_triangles;
  /* Sub-domains and memory (docs/ddm.md). */
  int subdomains;
  size_t memory_budget;       /* 0: none */
  uint64_t cell_loads, cell_unloads, cell_bytes_read;
  double cell_load_seconds;
  size_t peak_cells_bytes;    /* loaded sub-domains: arrays + Embree, the most at once */
  size_t peak_geometry_bytes, peak_embree_bytes;
  size_t peak_queue_bytes;    /* rays in memory */
  size_t peak_map_bytes;      /* photon maps and photochromic state maps */
  size_t peak_spill_bytes;    /* rays waiting on disk */
  long long rss_base_bytes;   /* budget: anonymous resident memory when the render began to add to it */
  long long rss_start_bytes;  /* budget: all resident memory then */
  size_t peak_uncounted_bytes; /* budget: the most resident memory above that and the counted bytes */
  uint64_t rays_spilled;
  size_t textures;            /* textures loaded (images and spectral), each once */
  size_t texture_bytes;       /* their memory, mip-maps included */
  double texture_seconds;     /* reading them, with the RGB-to-spectrum table's build */
  bool cache_built;           /* the geometry cache was (re)built by this render */
  char cache_reason[1024];    /* why, or "reused" */
  double cache_seconds;       /* checking or building it */
  uint64_t cache_bytes;       /* its cell files */
  size_t ncells;              /* sub-domains: */
  double *cell_seconds;       /* time spent tracing in each, all passes, summed over ranks */
  int *cell_ranks;            /* how many ranks held each at the end of the render */
  /* flow_profile: per pass that ran the ray flow, its name and profile,
   * and each cell's bytes and last load time (seconds). */
  int nprofiles;
  struct vr_pass_profile {
    char name[32];
    struct vr_flow_profile *p;
  } profiles[VR_MAX_PASSES];
  double *profile_load_seconds; /* per cell: its last load's seconds */
  double *profile_cell_bytes;   /* per cell: its bytes when loaded (arrays + Embree) */
  int ranks;                  /* processes that rendered (1 without MPI) */
  vr_rank_stats *rank_stats;  /* one per rank */
  double seconds_total;
} vr_render_result;

vr_status vr_render_scene(const vr_scene *scene, vr_matdb *db, const vr_render_options *opt,
                          vr_render_result **out, vr_error *err);
void vr_render_result_destroy(vr_render_result *r);

#ifdef __cplusplus
}
#endif
#endif
