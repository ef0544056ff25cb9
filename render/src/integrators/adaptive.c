/* Adaptive sampling of the camera image (--target-error, --time-limit):
 * the camera pass in rounds, each pixel taking samples until its estimated
 * error reaches the target.
 *
 * The estimate.  A round gives each pixel still sampling 2h more samples
 * in two passes of h, halves A and B, each a whole stratified set on its
 * own: h consecutive sample numbers (the wavelengths' strata and the pixel
 * filter's are those of a pass) made of whole blocks of the sampler's
 * `count` (its permutations and nets are per block).  So a pixel's A and B
 * samples are two independent, identically distributed estimates of the
 * same mean (the random numbers are keyed by pixel and sample alone).  The
 * film keeps B's XYZ apart (vr_accum_keep_halves); per channel c, with m_c
 * the pixel's mean and a_c, b_c the halves' means, (a_c - b_c)^2 / 4 is an
 * unbiased estimate of the variance of m_c with one degree of freedom
 * (Var(a - b) = 2 sigma^2 / (N/2) = 4 Var(m)).  This is the "two half
 * buffers" estimate of Cycles' adaptive sampler and of Rousselle, Knaus &
 * Zwicker 2012, read here as a variance.  (Halves by sample parity would
 * not do: with strata taken in sample order, odd samples take odd strata,
 * and the halves differ by the spectrum's shape, not by noise: 70 times the
 * true variance on a uniformly lit floor.)
 *
 * A pixel's relative error is the square root of those variances summed
 * over X, Y and Z and averaged over its 3 x 3 neighbourhood (nine pixels'
 * degrees of freedom instead of one: a single pixel's estimate would call
 * a pixel done by luck one time in a few), divided by the neighbourhood's
 * root-mean-square |XYZ|, but by no less than 1 % of the image's mean |XYZ|
 * (VR_ADAPTIVE_FLOOR): a pixel in deep shade is held to an error of 1 % of
 * the image's mean times the target rather than to ever more samples.
 * A pixel that reached the target (or max_spp) takes no more samples; the
 * next round doubles the samples of those that did not.
 *
 * What it cannot see: light that no sample has found yet (a caustic found
 * by one sample in a thousand looks converged at 8 samples), as every
 * sample-variance criterion; and where the variance is infinite or nearly
 * (next-event estimation into a corner, as in a closed furnace box) the
 * estimate is low and so is the mean of a few samples.  The first round is
 * therefore two halves of spp samples, and of at least VR_ADAPTIVE_HALF.  Stopping on a sample
 * estimate also biases a pixel slightly towards values whose noise looked
 * small; the tests bound it on a scene whose answer is known.
 *
 * Ranks: the estimates are computed from the film summed over the ranks,
 * so every rank takes the same decisions; the time limit is judged on the
 * slowest rank's clock. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "integrators/integrator.h"
#include "vr/comm.h"

enum { VR_ADAPTIVE_HALF = 4, VR_ADAPTIVE_MAX_SPP = 65536 };
#define VR_ADAPTIVE_FLOOR 0.01

typedef struct adaptive {
  int W, H;
  size_t px;
  uint32_t *count;
  uint8_t *active;
  double *sums;   /* per pixel: X Y Z of all samples, X Y Z of half B's */
  double *num, *den; /* per pixel: summed variance of the mean, |mean|^2 */
  double *err;    /* per pixel: the estimated relative error */
} adaptive;

int vr_adaptive_half(int spp) {
  if (spp < 1) spp = 1;
  return (VR_ADAPTIVE_HALF + spp - 1) / spp * spp;
}

size_t vr_adaptive_bytes_per_pixel(void) {
  /* half_xyz, then count, active, sums, num, den, err. */
  return 3 * sizeof(double) + sizeof(uint32_t) + 1 + 6 * sizeof(double) + 3 * sizeof(double);
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* The film's sums over the ranks, copied out (the accumulators go on
 * holding this rank's own). */
static vr_status gather(vr_run *r, const vr_accum *acc, adaptive *ad, vr_error *err) {
  for (size_t p = 0; p < ad->px; p++)
    for (int k = 0; k < 3; k++) {
      ad->sums[6 * p + (size_t)k] = vr_atomic_get(&acc->xyz[3 * p + (size_t)k]);
      ad->sums[6 * p + 3 + (size_t)k] = vr_atomic_get(&acc->half_xyz[3 * p + (size_t)k]);
    }
  if (r->nranks == 1) return VR_OK;
  return vr_comm_sum_doubles(r->comm, ad->sums, 6 * ad->px, err);
}

/* Each pixel's estimated relative error from the sums and counts. */
static void estimate(adaptive *ad) {
  double mean_norm = 0;
  for (size_t p = 0; p < ad->px; p++) {
    double n = ad->count[p], var = 0, m2 = 0;
    for (int k = 0; n > 0 && k < 3; k++) {
      double S = ad->sums[6 * p + (size_t)k], B = ad->sums[6 * p + 3 + (size_t)k];
      double m = S / n, d = 2 * B / n - 2 * (S - B) / n;
      var += d * d / 4;
      m2 += m * m;
    }
    ad->num[p] = var;
    ad->den[p] = m2;
    mean_norm += sqrt(m2);
  }
  mean_norm /= (double)ad->px;
  double floor2 = VR_ADAPTIVE_FLOOR * mean_norm * VR_ADAPTIVE_FLOOR * mean_norm;
  for (int y = 0; y < ad->H; y++)
    for (int x = 0; x < ad->W; x++) {
      double num = 0, den = 0;
      int k = 0;
      for (int j = y > 0 ? y - 1 : 0; j <= y + 1 && j < ad->H; j++)
        for (int i = x > 0 ? x - 1 : 0; i <= x + 1 && i < ad->W; i++, k++) {
          num += ad->num[(size_t)j * (size_t)ad->W + (size_t)i];
          den += ad->den[(size_t)j * (size_t)ad->W + (size_t)i];
        }
      num /= k;
      den /= k;
      size_t p = (size_t)y * (size_t)ad->W + (size_t)x;
      /* Black and noiseless (no light reaches it): done. */
      ad->err[p] = num > 0 ? sqrt(num / fmax(den, floor2)) : 0.0;
    }
}

static void summarise(const adaptive *ad, struct vr_adaptive_summary *s, double target) {
  double sum = 0;
  size_t ok = 0;
  s->spp_min = UINT32_MAX;
  s->spp_max = 0;
  for (size_t p = 0; p < ad->px; p++) {
    uint32_t c = ad->count[p];
    if (c < s->spp_min) s->spp_min = c;
    if (c > s->spp_max) s->spp_max = c;
    sum += c;
    if (target > 0 && ad->err[p] <= target) ok++;
  }
  if (!ad->px) return;
  s->spp_mean = sum / (double)ad->px;
  s->converged_share = target > 0 ? (double)ok / (double)ad->px : NAN;
  /* The 95th percentile of the errors (the num array is free by now). */
  memcpy(ad->num, ad->err, ad->px * sizeof *ad->num);
  qsort(ad->num, ad->px, sizeof *ad->num, cmp_double);
  s->error_p95 = ad->num[(size_t)floor(0.95 * (double)(ad->px - 1))];
}

static void adaptive_free(adaptive *ad) {
  free(ad->active);
  free(ad->sums);
  free(ad->num);
  free(ad->den);
  free(ad->err);
}

vr_status vr_adaptive_camera(vr_camera_job *job, vr_pass *c, const vr_flow_ops *ops,
                             vr_error *err) {
  vr_run *r = job->run;
  const vr_render_options *o = r->opt;
  adaptive ad = {.W = job->W, .H = job->H, .px = (size_t)job->W * (size_t)job->H};
  ad.count = calloc(ad.px ? ad.px : 1, sizeof *ad.count);
  ad.active = malloc(ad.px ? ad.px : 1);
  ad.sums = malloc((ad.px ? ad.px : 1) * 6 * sizeof *ad.sums);
  ad.num = malloc((ad.px ? ad.px : 1) * sizeof *ad.num);
  ad.den = malloc((ad.px ? ad.px : 1) * sizeof *ad.den);
  ad.err = malloc((ad.px ? ad.px : 1) * sizeof *ad.err);
  vr_status st = VR_OK;
  if (!ad.count || !ad.active || !ad.sums || !ad.num || !ad.den || !ad.err) {
    st = vr_error_set(err, VR_E_NOMEM, "adaptive sampling of %d x %d pixels: out of memory",
                      job->W, job->H);
    goto out;
  }
  if ((st = vr_accum_keep_halves(job->acc, err))) goto out;
  memset(ad.active, 1, ad.px);
  /* A half of a round is whole blocks of the sampler's count. */
  long block = job->rs->seed.count > 0 ? (long)job->rs->seed.count : 1;
  long cap = o->max_spp > 0 ? o->max_spp : VR_ADAPTIVE_MAX_SPP;
  long h = vr_adaptive_half((int)block); /* samples of a half */
  if (cap < 2 * h) cap = 2 * h;
  struct vr_adaptive_summary *sum = &job->adaptive_summary;
  memset(sum, 0, sizeof *sum);
  sum->spp_first = (uint32_t)(2 * h);
  c->active = ad.active;
  c->sum_samples = true;
  long done = 0;
  size_t nactive = ad.px;
  for (;;) {
    double t0 = vr_run_now();
    for (int half = 0; half < 2 && !st; half++) {
      c->spp = (int)h;
      c->sample_offset = (int)(done + half * h);
      c->second_half = half == 1;
      st = vr_camera_pass(r, c, ops, job->W, job->H, err);
    }
    if (st) goto out;
    for (size_t p = 0; p < ad.px; p++)
      if (ad.active[p]) ad.count[p] += (uint32_t)(2 * h);
    done += 2 * h;
    sum->rounds++;
    if ((st = gather(r, job->acc, &ad, err))) goto out;
    estimate(&ad);
    /* The round's figures on the log (a batch job's progress, with its
     * error). */
    summarise(&ad, sum, o->target_error);
    /* The round's time: its passes, the sum over the ranks, the estimate. */
    double dt = vr_run_now() - t0;
    job->seconds += dt;
    if (o->target_error > 0)
      vr_run_say(r, "camera round %d: %ld samples a pixel so far, %.1f %% of pixels at %.3g, "
                 "95 %% within %.3g (%.1f s)", sum->rounds, done, 100 * sum->converged_share,
                 o->target_error, sum->error_p95, dt);
    else
      vr_run_say(r, "camera round %d: %ld samples a pixel, 95 %% of pixels within %.3g relative "
                 "error (%.1f s)", sum->rounds, done, sum->error_p95, dt);
    /* The next round doubles the samples, in whole blocks, up to the cap. */
    long h_next = done / 2;
    if (done + 2 * h_next > cap) h_next = (cap - done) / 2 / block * block;
    size_t next = 0;
    for (size_t p = 0; p < ad.px; p++) {
      if (ad.active[p] &&
          (h_next <= 0 || (o->target_error > 0 && ad.err[p] <= o->target_error)))
        ad.active[p] = 0;
      next += ad.active[p];
    }
    if (!next) {
      snprintf(sum->stop, sizeof sum->stop, "%s",
               h_next <= 0 && o->target_error > 0 ? "target reached or max spp at every pixel"
               : h_next <= 0                      ? "max spp reached"
                                                  : "target reached at every pixel");
      break;
    }
    if (o->time_limit_s > 0) {
      /* The next round's time, predicted from this one's: its samples
       * scale with the active pixels and the round's count. */
      uint64_t t[2] = {(uint64_t)((vr_run_now() - r->t_start) * 1e6), (uint64_t)(dt * 1e6)};
      if (r->nranks > 1 && (st = vr_comm_max_u64(r->comm, t, 2, err))) goto out;
      double predicted = 1e-6 * (double)t[1] * ((double)next / (double)nactive) *
                         ((double)h_next / (double)h);
      double left = o->time_limit_s - 1e-6 * (double)t[0];
      if (predicted > left) {
        /* A shorter round that fits what is left (whole blocks), else
         * the end: doubling alone would leave up to half the time unused. */
        long h_fit = predicted > 0 ? (long)((double)h_next * left / predicted) / block * block : 0;
        if (h_fit < block) {
          snprintf(sum->stop, sizeof sum->stop,
                   "time limit: even the shortest round (about %.1f s) would end past %.1f s",
                   predicted * (double)block / (double)h_next, o->time_limit_s);
          break;
        }
        h_next = h_fit;
      }
    }
    nactive = next;
    h = h_next;
  }
  /* The summary is the last round's (summarised in the loop; nothing has
   * changed since). */
  job->pixel_samples = ad.count;
  ad.count = NULL;
out:
  c->active = NULL;
  c->second_half = false;
  free(ad.count);
  adaptive_free(&ad);
  return st;
}
