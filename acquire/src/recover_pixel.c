/* Per-pixel regularised recovery: a precomputed linear operator, then the
 * bounded correction only where a pixel leaves [0, 1] (see
 * vr/recover_pixel.h for the mathematics). */
#include "vr/recover_pixel.h"

#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "recover_system.h"

#define CACHE_SLOTS 64

/* The operators for one pattern of clipped channels. */
typedef struct op {
  uint64_t mask; /* bit i: channel i clipped */
  int state;     /* 0 empty slot, 1 ready, 2 fewer than two channels, 3 H not positive definite */
  size_t used;   /* unclipped channels */
  double chi2_limit;
  double *M;     /* N x N, H^-1 */
  double *K;     /* N x m, zero columns for clipped channels */
  /* One column per channel k, `stride` floats (32-byte aligned): rows
   * 0..np-1 column k of K (zero-padded), np..np+m-1 column k of W (A K - I)
   * (the weighted residual map; zero rows for clipped channels), np+m..
   * np+m+2 column k of preview K.  One pass over the channels then gives a
   * pixel's spectrum, residual and preview together. */
  float *big;
} op;

#define RES_ROWS 16 /* the fast path takes up to 16 channels (5 lights) */

/* Four floats: one SSE register on every x86-64, so sums stay in registers
 * without asking for AVX. */
typedef float v4f __attribute__((vector_size(16)));
typedef int v4i __attribute__((vector_size(16)));

struct vr_pixel_recovery {
  const vr_recovery_system *s;
  vr_recovery_system fallback; /* s with lambda fixed: the general solver */
  size_t n, m, np;
  size_t stride; /* floats per column of op.big: np + m + 3 rounded up to 16 */
  int avx2;      /* the processor runs the AVX2/FMA kernel */
  double lambda;
  double *sigma, *w; /* m */
  double *reg;       /* N x N: lambda D2^T D2 */
  double *preview;   /* 3 x N, or NULL */
  /* For a spectrum r the rows W A r (m) and preview r (3) at once: column j
   * (gstride floats, 16-byte aligned) holds w_i a_ij then preview_cj. */
  float *g;
  size_t gstride;
  op base;           /* no channel clipped */
};

struct vr_pixel_workspace {
  const vr_pixel_recovery *p;
  op slot[CACHE_SLOTS];
  double *r0, *r, *mbb, *mu, *rhs, *cd; /* scratch */
  int *bidx;
  unsigned char *st, *nst; /* bound state per band: FREE, AT_LO, AT_HI */
};

static void op_free(op *o) {
  free(o->M);
  free(o->K);
  free(o->big);
  memset(o, 0, sizeof *o);
}

/* Builds the operators of pattern mask into o (allocating its arrays).
 * Returns 0, or -1 when out of memory. */
static int op_build(const vr_pixel_recovery *p, uint64_t mask, op *o) {
  size_t n = p->n, m = p->m, np = p->np;
  const double *a = p->s->a;
  memset(o, 0, sizeof *o);
  o->mask = mask;
  o->M = malloc(n * n * sizeof *o->M);
  o->K = calloc(n * m, sizeof *o->K);
  size_t stride = p->stride;
  o->big = aligned_alloc(32, m * stride * sizeof *o->big);
  if (o->big) memset(o->big, 0, m * stride * sizeof *o->big);
  if (!o->M || !o->K || !o->big) {
    op_free(o);
    return -1;
  }
  for (size_t i = 0; i < m; i++)
    if (!(mask >> i & 1u)) o->used++;
  o->chi2_limit = vr_recover_chi2_limit(o->used);
  if (o->used < 2) {
    o->state = 2;
    return 0;
  }
  /* H = lambda D2^T D2 + sum over unclipped channels of w_i^2 a_i a_i^T. */
  memcpy(o->M, p->reg, n * n * sizeof *o->M);
  for (size_t i = 0; i < m; i++) {
    if (mask >> i & 1u) continue;
    double w2 = p->w[i] * p->w[i];
    for (size_t j = 0; j < n; j++)
      for (size_t l = 0; l < n; l++) o->M[j * n + l] += w2 * a[i * n + j] * a[i * n + l];
  }
  if (LAPACKE_dpotrf(LAPACK_ROW_MAJOR, 'L', (lapack_int)n, o->M, (lapack_int)n) != 0 ||
      LAPACKE_dpotri(LAPACK_ROW_MAJOR, 'L', (lapack_int)n, o->M, (lapack_int)n) != 0) {
    o->state = 3;
    return 0;
  }
  for (size_t j = 0; j < n; j++) /* dpotri fills the lower triangle */
    for (size_t l = j + 1; l < n; l++) o->M[j * n + l] = o->M[l * n + j];
  for (size_t i = 0; i < m; i++) {
    if (mask >> i & 1u) continue;
    double w2 = p->w[i] * p->w[i];
    for (size_t j = 0; j < n; j++) {
      double v = 0.0;
      for (size_t l = 0; l < n; l++) v += o->M[j * n + l] * a[i * n + l];
      o->K[j * m + i] = w2 * v;
      o->big[i * stride + j] = (float)(w2 * v);
    }
  }
  for (size_t i = 0; i < m; i++) {
    if (mask >> i & 1u) continue;
    for (size_t k = 0; k < m; k++) {
      double v = 0.0;
      for (size_t j = 0; j < n; j++) v += a[i * n + j] * o->K[j * m + k];
      o->big[k * stride + np + i] = (float)(p->w[i] * (v - (i == k ? 1.0 : 0.0)));
    }
  }
  for (size_t ch = 0; p->preview && ch < 3; ch++)
    for (size_t k = 0; k < m; k++) {
      double v = 0.0;
      for (size_t j = 0; j < n; j++) v += p->preview[ch * n + j] * o->K[j * m + k];
      o->big[k * stride + np + m + ch] = (float)v;
    }
  o->state = 1;
  return 0;
}

#if (defined(__x86_64__) || defined(__i386__)) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define HAVE_AVX2_KERNEL 1

/* The same products with 8-float AVX2 fused multiply-adds, every block's
 * sum in its own register (stride 48 or 64 floats: 6 or 8 registers), so
 * the channels stream through once.  Returns 0 for other strides. */
#define PRODUCTS_FIXED(NB)                                                          \
  do {                                                                              \
    __m256 acc_[NB];                                                                \
    for (int b_ = 0; b_ < (NB); b_++) acc_[b_] = _mm256_setzero_ps();             \
    for (size_t k_ = 0; k_ < m; k_++) {                                           \
      const __m256 ck_ = _mm256_set1_ps(c[k_]);                                     \
      const float *col_ = big + k_ * stride;                                        \
      for (int b_ = 0; b_ < (NB); b_++)                                             \
        acc_[b_] = _mm256_fmadd_ps(ck_, _mm256_load_ps(col_ + 8 * b_), acc_[b_]);   \
    }                                                                               \
    __m256 bad_ = _mm256_setzero_ps();                                              \
    for (size_t b_ = 0; b_ < np / 8; b_++)                                          \
      bad_ = _mm256_or_ps(bad_, _mm256_or_ps(_mm256_cmp_ps(acc_[b_], zero_, _CMP_LT_OQ), \
                                             _mm256_cmp_ps(acc_[b_], one_, _CMP_GT_OQ))); \
    *outside = _mm256_movemask_ps(bad_) != 0;                                       \
    for (int b_ = 0; b_ < (NB); b_++) _mm256_storeu_ps(out + 8 * b_, acc_[b_]);     \
  } while (0)

__attribute__((target("avx2,fma"))) static int products_avx2(const float *big, size_t stride,
                                                             size_t m, size_t np,
                                                             const float *c, float *out,
                                                             int *outside) {
  const __m256 zero_ = _mm256_setzero_ps(), one_ = _mm256_set1_ps(1.0f);
  if (stride == 48) PRODUCTS_FIXED(6);
  else if (stride == 64) PRODUCTS_FIXED(8);
  else return 0;
  return 1;
}

static int cpu_has_avx2(void) {
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
}
#else
static int products_avx2(const float *big, size_t stride, size_t m, size_t np, const float *c,
                         float *out, int *outside) {
  (void)big, (void)stride, (void)m, (void)np, (void)c, (void)out, (void)outside;
  return 0;
}
static int cpu_has_avx2(void) { return 0; }
#endif

vr_pixel_recovery *vr_pixel_recovery_create(const vr_recovery_system *s, const double *sigma,
                                            double lambda, const double *preview, vr_error *err) {
  if (!s || !sigma) {
    vr_error_set(err, VR_E_ARG, "per-pixel recovery: NULL system or noise");
    return NULL;
  }
  if (!(isfinite(lambda) && lambda > 0.0)) {
    vr_error_set(err, VR_E_ARG, "per-pixel recovery: lambda %g, need a finite value > 0", lambda);
    return NULL;
  }
  if (s->m > 64 || s->n > 128) {
    vr_error_set(err, VR_E_ARG, "per-pixel recovery: at most 64 channels (21 lights) and 128 "
                                "wavelengths");
    return NULL;
  }
  for (size_t i = 0; i < s->m; i++)
    if (!(isfinite(sigma[i]) && sigma[i] > 0.0)) {
      vr_error_set(err, VR_E_ARG, "per-pixel recovery: noise of channel %zu is %g, need > 0", i,
                   sigma[i]);
      return NULL;
    }
  vr_pixel_recovery *p = calloc(1, sizeof *p);
  if (!p) goto nomem;
  size_t n = s->n, m = s->m;
  p->s = s;
  p->n = n;
  p->m = m;
  p->np = (n + 7) & ~(size_t)7;
  p->stride = (p->np + m + 3 + 15) & ~(size_t)15;
  p->avx2 = cpu_has_avx2() && !getenv("VR_NO_AVX2");
  p->lambda = lambda;
  p->fallback = *s;
  p->fallback.opt.lambda = lambda;
  p->sigma = malloc(m * sizeof *p->sigma);
  p->w = malloc(m * sizeof *p->w);
  p->reg = calloc(n * n, sizeof *p->reg);
  if (!p->sigma || !p->w || !p->reg) goto nomem;
  if (preview) {
    if (!(p->preview = malloc(3 * n * sizeof *p->preview))) goto nomem;
    memcpy(p->preview, preview, 3 * n * sizeof *p->preview);
  }
  for (size_t i = 0; i < m; i++) {
    p->sigma[i] = sigma[i];
    p->w[i] = 1.0 / sigma[i];
  }
  for (size_t k = 0; k + 2 < n; k++)
    for (size_t j = 0; j < n; j++)
      for (size_t l = 0; l < n; l++)
        p->reg[j * n + l] += lambda * s->d2[k * n + j] * s->d2[k * n + l];
  p->gstride = (m + 3 + 3) & ~(size_t)3;
  if (!(p->g = aligned_alloc(16, n * p->gstride * sizeof *p->g))) goto nomem;
  memset(p->g, 0, n * p->gstride * sizeof *p->g);
  for (size_t j = 0; j < n; j++) {
    for (size_t i = 0; i < m; i++) p->g[j * p->gstride + i] = (float)(p->w[i] * s->a[i * n + j]);
    for (size_t ch = 0; preview && ch < 3; ch++)
      p->g[j * p->gstride + m + ch] = (float)preview[ch * n + j];
  }
  if (op_build(p, 0, &p->base)) goto nomem;
  if (p->base.state == 3) {
    vr_error_set(err, VR_E_NUMERIC, "per-pixel recovery: the normal matrix is not positive "
                                    "definite at lambda %g (the lights do not determine the "
                                    "straight lines)", lambda);
    vr_pixel_recovery_destroy(p);
    return NULL;
  }
  return p;
nomem:
  vr_pixel_recovery_destroy(p);
  vr_error_set(err, VR_E_NOMEM, "per-pixel recovery: out of memory");
  return NULL;
}

void vr_pixel_recovery_destroy(vr_pixel_recovery *p) {
  if (!p) return;
  op_free(&p->base);
  free(p->sigma);
  free(p->w);
  free(p->reg);
  free(p->preview);
  free(p->g);
  free(p);
}

double vr_pixel_recovery_lambda(const vr_pixel_recovery *p) { return p->lambda; }

vr_pixel_workspace *vr_pixel_workspace_create(const vr_pixel_recovery *p, vr_error *err) {
  vr_pixel_workspace *w = calloc(1, sizeof *w);
  size_t n = p ? p->n : 0;
  if (!p || !w) goto fail;
  w->p = p;
  w->r0 = malloc(n * sizeof *w->r0);
  w->r = malloc(n * sizeof *w->r);
  w->mbb = malloc(n * n * sizeof *w->mbb);
  w->mu = malloc(n * sizeof *w->mu);
  w->rhs = malloc(n * sizeof *w->rhs);
  w->cd = malloc(p->m * sizeof *w->cd);
  w->bidx = malloc(n * sizeof *w->bidx);
  w->st = malloc(2 * n);
  if (!w->r0 || !w->r || !w->mbb || !w->mu || !w->rhs || !w->cd || !w->bidx || !w->st) goto fail;
  w->nst = w->st + n;
  return w;
fail:
  vr_pixel_workspace_destroy(w);
  vr_error_set(err, p ? VR_E_NOMEM : VR_E_ARG,
               p ? "per-pixel recovery: out of memory" : "per-pixel recovery: NULL recovery");
  return NULL;
}

void vr_pixel_workspace_destroy(vr_pixel_workspace *w) {
  if (!w) return;
  for (int k = 0; k < CACHE_SLOTS; k++) op_free(&w->slot[k]);
  free(w->r0);
  free(w->r);
  free(w->mbb);
  free(w->mu);
  free(w->rhs);
  free(w->cd);
  free(w->bidx);
  free(w->st);
  free(w);
}

/* The operators of a clip pattern: the shared ones, a cached slot, or a
 * slot rebuilt (NULL when out of memory). */
static const op *find_op(vr_pixel_workspace *w, uint64_t mask) {
  if (mask == 0) return &w->p->base;
  uint64_t h = mask * 0x9e3779b97f4a7c15ULL;
  op *o = &w->slot[h >> 58]; /* 64 slots */
  if (o->state && o->mask == mask) return o;
  op_free(o);
  return op_build(w->p, mask, o) ? NULL : o;
}

/* Solves the nb x nb symmetric positive definite system a x = b in place
 * (Cholesky, row-major); returns 0, or -1 when a is not positive definite. */
static int spd_solve(size_t nb, double *a, double *b) {
  for (size_t j = 0; j < nb; j++) {
    double d = a[j * nb + j];
    for (size_t k = 0; k < j; k++) d -= a[j * nb + k] * a[j * nb + k];
    if (!(d > 0.0)) return -1;
    d = sqrt(d);
    a[j * nb + j] = d;
    for (size_t i = j + 1; i < nb; i++) {
      double v = a[i * nb + j];
      for (size_t k = 0; k < j; k++) v -= a[i * nb + k] * a[j * nb + k];
      a[i * nb + j] = v / d;
    }
  }
  for (size_t i = 0; i < nb; i++) {
    double v = b[i];
    for (size_t k = 0; k < i; k++) v -= a[i * nb + k] * b[k];
    b[i] = v / a[i * nb + i];
  }
  for (size_t i = nb; i-- > 0;) {
    double v = b[i];
    for (size_t k = i + 1; k < nb; k++) v -= a[k * nb + i] * b[k];
    b[i] = v / a[i * nb + i];
  }
  return 0;
}

/* The bounded correction of r0 = K c into w->r by the primal-dual active
 * set; returns 0, or -1 when it does not settle (or M[B,B] is not positive
 * definite to rounding). */
enum { FREE = 0, AT_LO = 1, AT_HI = 2 };

static int bounded(vr_pixel_workspace *w, const op *o) {
  const size_t n = w->p->n;
  const double *M = o->M, *r0 = w->r0;
  double *r = w->r;
  unsigned char *st = w->st, *nst = w->nst;
  for (size_t j = 0; j < n; j++) st[j] = r0[j] < 0.0 ? AT_LO : r0[j] > 1.0 ? AT_HI : FREE;
  for (size_t it = 0; it < 3 * n + 10; it++) {
    size_t nb = 0;
    for (size_t j = 0; j < n; j++)
      if (st[j]) w->bidx[nb++] = (int)j;
    for (size_t a = 0; a < nb; a++) {
      const double *row = M + (size_t)w->bidx[a] * n;
      w->rhs[a] = (st[w->bidx[a]] == AT_HI ? 1.0 : 0.0) - r0[w->bidx[a]];
      for (size_t b = 0; b < nb; b++) w->mbb[a * nb + b] = row[w->bidx[b]];
    }
    if (nb && spd_solve(nb, w->mbb, w->rhs)) return -1;
    /* r = r0 + M[:, B] mu_B, by rows of M (symmetric: op_build mirrors it),
     * so the inner loop runs along memory. */
    memcpy(r, r0, n * sizeof *r);
    for (size_t a = 0; a < nb; a++) {
      const double *row = M + (size_t)w->bidx[a] * n, mu = w->rhs[a];
      for (size_t j = 0; j < n; j++) r[j] += mu * row[j];
      w->mu[w->bidx[a]] = mu;
    }
    int same = 1;
    for (size_t j = 0; j < n; j++) {
      unsigned char v = st[j] == AT_LO   ? (w->mu[j] > 0.0 ? AT_LO : FREE)
                        : st[j] == AT_HI ? (w->mu[j] < 0.0 ? AT_HI : FREE)
                        : r[j] < 0.0     ? AT_LO
                        : r[j] > 1.0     ? AT_HI
                                         : FREE;
      nst[j] = v;
      same &= v == st[j];
    }
    if (same) {
      for (size_t j = 0; j < n; j++) {
        double v = r[j] < 0.0 ? 0.0 : r[j] > 1.0 ? 1.0 : r[j];
        r[j] = st[j] == AT_LO ? 0.0 : st[j] == AT_HI ? 1.0 : v;
      }
      return 0;
    }
    memcpy(st, nst, n);
  }
  return -1;
}

unsigned vr_pixel_recover(vr_pixel_workspace *w, const float *c, const unsigned char *clipped,
                          float *r, float *rgb, float *chi2) {
  const vr_pixel_recovery *p = w->p;
  size_t n = p->n, m = p->m, np = p->np;
  unsigned flags = 0;
  uint64_t mask = 0;
  for (size_t i = 0; clipped && i < m; i++)
    if (clipped[i] != VR_CLIP_NONE) {
      mask |= (uint64_t)1 << i;
      flags |= clipped[i] == VR_CLIP_HIGH ? VR_PIXEL_CLIPPED_HIGH : VR_PIXEL_CLIPPED_LOW;
    }
  const op *o = find_op(w, mask);
  if (!o || o->state == 2) {
    memset(r, 0, n * sizeof *r);
    if (rgb) rgb[0] = rgb[1] = rgb[2] = 0.0f;
    if (chi2) *chi2 = 0.0f;
    return flags | VR_PIXEL_NO_DATA;
  }
  /* The fast path needs the residual map to fit its rows (m <= 16). */
  int inside = o->state == 1 && m <= RES_ROWS, have_r0 = 0;
  if (inside) {
    /* Spectrum, weighted residual and preview at once, 4 floats a step. */
    size_t stride = p->stride, nv = stride / 4;
    v4f acc[(128 + RES_ROWS + 3 + 15) / 4];
    int outside = 0;
    if (p->avx2 && products_avx2(o->big, stride, m, np, c, (float *)acc, &outside)) {
      inside = !outside;
    } else {
      v4f cv[RES_ROWS];
      for (size_t k = 0; k < m; k++) cv[k] = (v4f){c[k], c[k], c[k], c[k]};
      /* Four blocks at a time, the channels inside: four independent sums
       * stay in registers and hide the adds' latency. */
      for (size_t b = 0; b < nv; b += 4) {
        const float *base = o->big + 4 * b;
        v4f s0 = {0, 0, 0, 0}, s1 = s0, s2 = s0, s3 = s0;
        for (size_t k = 0; k < m; k++) {
          const v4f *col = (const v4f *)(base + k * stride);
          s0 += cv[k] * col[0];
          s1 += cv[k] * col[1];
          s2 += cv[k] * col[2];
          s3 += cv[k] * col[3];
        }
        acc[b] = s0;
        acc[b + 1] = s1;
        acc[b + 2] = s2;
        acc[b + 3] = s3;
      }
      /* Lanes past n are zero (K is zero-padded), so whole blocks are tested. */
      v4i bad = {0, 0, 0, 0};
      const v4f zero = {0, 0, 0, 0}, one = {1, 1, 1, 1};
      for (size_t b = 0; b < np / 4; b++) bad |= (acc[b] < zero) | (acc[b] > one);
      inside = !(bad[0] | bad[1] | bad[2] | bad[3]);
    }
    const float *out = (const float *)acc;
    if (!inside) {
      /* The bounded correction starts from this estimate (float rounding,
       * 1e-7 relative, is far below what the correction changes). */
      for (size_t j = 0; j < n; j++) w->r0[j] = out[j];
      have_r0 = 1;
    }
    if (inside) {
      memcpy(r, out, n * sizeof *r);
      float x2 = 0.0f;
      for (size_t i = 0; i < m; i++) x2 += out[np + i] * out[np + i];
      if (rgb) memcpy(rgb, out + np + m, 3 * sizeof *rgb);
      if (chi2) *chi2 = x2;
      return flags | (x2 > o->chi2_limit ? VR_PIXEL_MISFIT : 0u);
    }
  }
  /* Out of [0, 1] (or no operator for this pattern): in double. */
  for (size_t k = 0; k < m; k++) w->cd[k] = c[k];
  int solved = 0;
  if (o->state == 1) {
    for (size_t j = 0; j < n && !have_r0; j++) {
      double v = 0.0;
      for (size_t k = 0; k < m; k++) v += o->K[j * m + k] * w->cd[k];
      w->r0[j] = v;
    }
    int in01 = 1;
    for (size_t j = 0; j < n && in01; j++) in01 = w->r0[j] >= 0.0 && w->r0[j] <= 1.0;
    if (in01) {
      memcpy(w->r, w->r0, n * sizeof *w->r);
      solved = 1;
    } else {
      solved = bounded(w, o) == 0;
      flags |= VR_PIXEL_BOUNDED;
    }
  }
  if (!solved) {
    vr_recover_info info;
    if (vr_recover_noisy(&p->fallback, VR_RECOVER_REGULARISED, w->cd, p->sigma, clipped, w->r,
                         &info, NULL) != VR_OK) {
      memset(r, 0, n * sizeof *r);
      if (rgb) rgb[0] = rgb[1] = rgb[2] = 0.0f;
      if (chi2) *chi2 = 0.0f;
      return flags | VR_PIXEL_NO_DATA | VR_PIXEL_FALLBACK;
    }
    flags |= VR_PIXEL_FALLBACK;
    for (size_t j = 0; j < n; j++) w->r[j] = w->r[j] < 0.0 ? 0.0 : w->r[j] > 1.0 ? 1.0 : w->r[j];
  }
  /* Residual and preview of the corrected spectrum, 4 rows a step. */
  v4f gacc[(64 + 3 + 3) / 4];
  size_t gb = p->gstride / 4;
  for (size_t b = 0; b < gb; b++) gacc[b] = (v4f){0, 0, 0, 0};
  if (gb <= 4) {
    /* Up to 13 channels (4 lights) plus the preview: four sums held in
     * registers instead of going through memory each band. */
    v4f a0 = {0, 0, 0, 0}, a1 = a0, a2 = a0, a3 = a0;
    for (size_t j = 0; j < n; j++) {
      float rj = (float)w->r[j];
      v4f rv = {rj, rj, rj, rj};
      const v4f *col = (const v4f *)(p->g + j * p->gstride);
      a0 += rv * col[0];
      if (gb > 1) a1 += rv * col[1];
      if (gb > 2) a2 += rv * col[2];
      if (gb > 3) a3 += rv * col[3];
      r[j] = rj;
    }
    gacc[0] = a0;
    if (gb > 1) gacc[1] = a1;
    if (gb > 2) gacc[2] = a2;
    if (gb > 3) gacc[3] = a3;
  } else {
    for (size_t j = 0; j < n; j++) {
      float rj = (float)w->r[j];
      v4f rv = {rj, rj, rj, rj};
      const v4f *col = (const v4f *)(p->g + j * p->gstride);
      for (size_t b = 0; b < gb; b++) gacc[b] += rv * col[b];
      r[j] = rj;
    }
  }
  const float *gout = (const float *)gacc;
  double x2 = 0.0;
  for (size_t i = 0; i < m; i++) {
    if (mask >> i & 1u) continue;
    double d = (double)gout[i] - p->w[i] * w->cd[i];
    x2 += d * d;
  }
  for (int ch = 0; rgb && ch < 3; ch++) rgb[ch] = p->preview ? gout[m + (size_t)ch] : 0.0f;
  if (chi2) *chi2 = (float)x2;
  return flags | (x2 > o->chi2_limit ? VR_PIXEL_MISFIT : 0u);
}
