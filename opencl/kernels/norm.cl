// Normalisation layers: SIMPLI's per-sample "total" layer norm and the standard last-axis
// LayerNorm, forward and backward.

// Blocked layout (see src/row_blocks.h): GROUP items per block; item j of a block reads the
// REAL4 vectors j, j + GROUP, ... of the block, item 0 also the block's last < 4 elements.
#define GROUP 64

// Elements in block `block` of a row of L elements with per_vec vectors per item.
inline int block_count(const int L, const int block, const int per_vec) {
  return clamp(L - block * GROUP * 4 * per_vec, 0, GROUP * 4 * per_vec);
}

inline REAL hsum4(const REAL4 v) { return (v.x + v.y) + (v.z + v.w); }

// Chan et al.'s combination of partial (count, mean, M2) statistics. Means are combined
// relative to the first non-empty part, so equal means (a constant input) give exactly that
// mean and M2 = 0; M2 of the parts is then corrected by the spread of their means.
#define DEFINE_CHAN_COMBINE(NAME, SPACE)                                                       \
  inline void NAME(const int parts, SPACE const REAL* cnt, SPACE const REAL* mean,             \
                   SPACE const REAL* m2, REAL* out_mean, REAL* out_m2) {                       \
    REAL n = 0, shift = 0, acc = 0;                                                            \
    int first = 1;                                                                             \
    for (int i = 0; i < parts; ++i) {                                                          \
      if (cnt[i] > 0) {                                                                        \
        if (first) {                                                                           \
          shift = mean[i];                                                                     \
          first = 0;                                                                           \
        }                                                                                      \
        n += cnt[i];                                                                           \
        acc += cnt[i] * (mean[i] - shift);                                                     \
      }                                                                                        \
    }                                                                                          \
    const REAL mu = n > 0 ? shift + acc / n : (REAL)0;                                         \
    REAL q = 0;                                                                                \
    for (int i = 0; i < parts; ++i) {                                                          \
      if (cnt[i] > 0) {                                                                        \
        const REAL d = mean[i] - mu;                                                           \
        q += m2[i] + cnt[i] * d * d;                                                           \
      }                                                                                        \
    }                                                                                          \
    *out_mean = mu;                                                                            \
    *out_m2 = q;                                                                               \
  }
DEFINE_CHAN_COMBINE(chan_combine_local, __local)
DEFINE_CHAN_COMBINE(chan_combine_global, __global)

// ---- layerNormTotal ---------------------------------------------------------------------------

// Statistics pass, stage 1. Rows are samples of L elements (launch: GROUP x groups, rows).
// Each item computes (count, mean, M2) of its elements with a two-pass shifted by its first
// element (exact for constant data; its elements stay in L1 for the second pass); item 0
// combines the block's items into part[slot], part[stride + slot], part[2 stride + slot]
// (count, mean, M2), slot = row * groups + block. No early return: every item must reach the
// barrier.
__kernel void lnt_stats_partial(const int L, const int per_vec, __global const REAL* x,
                                __global REAL* part, const int stride) {
  __local REAL s_cnt[GROUP], s_mean[GROUP], s_m2[GROUP];
  const int j = get_local_id(0);
  const int block = get_group_id(0);
  const int groups = get_num_groups(0);
  const int row = get_global_id(1);
  const int in_block = block_count(L, block, per_vec);
  const int nvec = in_block / 4;
  const int tail = j == 0 ? in_block - 4 * nvec : 0;
  __global const REAL* p = x + (long)row * L + block * GROUP * 4 * per_vec;
  __global const REAL* pt = p + 4 * nvec;
  const int cnt = 4 * max(0, (nvec - j + GROUP - 1) / GROUP) + tail;
  const REAL shift = j < nvec ? p[4 * j] : (tail > 0 ? pt[0] : (REAL)0);
  REAL4 a4 = 0;
  for (int v = j; v < nvec; v += GROUP)
    a4 += vload4(v, p) - shift;
  REAL acc = hsum4(a4);
  for (int t = 0; t < tail; ++t)
    acc += pt[t] - shift;
  const REAL mu = cnt > 0 ? shift + acc / (REAL)cnt : (REAL)0;
  REAL4 q4 = 0;
  for (int v = j; v < nvec; v += GROUP) {
    const REAL4 d = vload4(v, p) - mu;
    q4 += d * d;
  }
  REAL m2 = hsum4(q4);
  for (int t = 0; t < tail; ++t) {
    const REAL d = pt[t] - mu;
    m2 += d * d;
  }
  s_cnt[j] = (REAL)cnt;
  s_mean[j] = mu;
  s_m2[j] = m2;
  barrier(CLK_LOCAL_MEM_FENCE);
  if (j == 0) {
    REAL bm, bq, bn = 0;
    for (int i = 0; i < GROUP; ++i)
      bn += s_cnt[i];
    chan_combine_local(GROUP, s_cnt, s_mean, s_m2, &bm, &bq);
    const int slot = row * groups + block;
    part[slot] = bn;
    part[stride + slot] = bm;
    part[2 * stride + slot] = bq;
  }
}

// Statistics pass, stage 2: one item per sample combines its blocks into
// stats[3 r] = mean, stats[3 r + 1] = unbiased std s, stats[3 r + 2] = 1 / (s + eps).
__kernel void lnt_stats_finish(const int rows, const int groups, const int L, const REAL eps,
                               __global const REAL* part, const int stride,
                               __global REAL* stats) {
  const int r = get_global_id(0);
  if (r >= rows) return;
  const int o = r * groups;
  REAL mu, m2;
  chan_combine_global(groups, part + o, part + stride + o, part + 2 * stride + o, &mu, &m2);
  const REAL s = sqrt(m2 / (REAL)(L - 1));
  stats[3 * r] = mu;
  stats[3 * r + 1] = s;
  stats[3 * r + 2] = 1 / (s + eps);
}

// Apply pass: y = gamma[c] * (x - mu) / (s + eps) + beta[c]. 2-D launch: dim 0 = vector
// index within one (sample, channel) row of `inner` elements (the item past the last full
// vector does the < 4 tail elements), dim 1 = row.
__kernel void lnt_apply(const int inner, const int rows, const int C, __global const REAL* x,
                        __global const REAL* stats, __global const REAL* gamma,
                        __global const REAL* beta, __global REAL* y) {
  const int v = get_global_id(0);
  const int row = get_global_id(1);
  const int nvec = inner / 4;
  if (v > nvec || row >= rows) return;
  const int s = row / C, c = row % C;
  const REAL mu = stats[3 * s], r = stats[3 * s + 2], ga = gamma[c], be = beta[c];
  __global const REAL* px = x + (long)row * inner;
  __global REAL* py = y + (long)row * inner;
  if (v < nvec) {
    vstore4(ga * ((vload4(v, px) - mu) * r) + be, v, py);
  } else {
    for (int i = 4 * nvec; i < inner; ++i)
      py[i] = ga * ((px[i] - mu) * r) + be;
  }
}

// Backward, stage 1: rows are (sample, channel) pairs of `inner` elements, blocked like
// lnt_stats_partial. Per block, the sums of g and of g * xhat go to part[slot] and
// part[stride + slot].
__kernel void lnt_bwd_partial(const int L, const int per_vec, const int C,
                              __global const REAL* x, __global const REAL* g,
                              __global const REAL* stats, __global REAL* part, const int stride) {
  __local REAL s_g[GROUP], s_gx[GROUP];
  const int j = get_local_id(0);
  const int block = get_group_id(0);
  const int groups = get_num_groups(0);
  const int row = get_global_id(1);
  const int sample = row / C;
  const REAL mu = stats[3 * sample], r = stats[3 * sample + 2];
  const int in_block = block_count(L, block, per_vec);
  const int nvec = in_block / 4;
  const int tail = j == 0 ? in_block - 4 * nvec : 0;
  const long o = (long)row * L + block * GROUP * 4 * per_vec;
  __global const REAL* px = x + o;
  __global const REAL* pg = g + o;
  REAL4 ag = 0, agx = 0;
  for (int v = j; v < nvec; v += GROUP) {
    const REAL4 gv = vload4(v, pg);
    ag += gv;
    agx += gv * ((vload4(v, px) - mu) * r);
  }
  REAL acc_g = hsum4(ag), acc_gx = hsum4(agx);
  for (int t = 4 * nvec; t < 4 * nvec + tail; ++t) {
    acc_g += pg[t];
    acc_gx += pg[t] * ((px[t] - mu) * r);
  }
  s_g[j] = acc_g;
  s_gx[j] = acc_gx;
  barrier(CLK_LOCAL_MEM_FENCE);
  if (j == 0) {
    REAL a = 0, b = 0;
    for (int i = 0; i < GROUP; ++i) {
      a += s_g[i];
      b += s_gx[i];
    }
    const int slot = row * groups + block;
    part[slot] = a;
    part[stride + slot] = b;
  }
}

// Backward, stage 2 (items 0..max(N, C)-1). With dxhat = g * gamma, for sample i < N:
// coef[2 i] = mean(dxhat), coef[2 i + 1] = sum(dxhat * xhat) / ((M - 1) s) (0 when s = 0: the
// std has no derivative there; xhat = 0 then anyway). For channel i < C: dgamma = sum g * xhat,
// dbeta = sum g over all samples.
__kernel void lnt_bwd_coeffs(const int N, const int C, const int groups, const int M,
                             __global const REAL* part, const int stride,
                             __global const REAL* stats, __global const REAL* gamma,
                             __global REAL* coef, __global REAL* dgamma, __global REAL* dbeta) {
  const int i = get_global_id(0);
  if (i < N) {
    REAL sum_dxhat = 0, sum_dxhat_xhat = 0;
    for (int c = 0; c < C; ++c) {
      const int o = (i * C + c) * groups;
      REAL sg = 0, sgx = 0;
      for (int b = 0; b < groups; ++b) {
        sg += part[o + b];
        sgx += part[stride + o + b];
      }
      sum_dxhat += gamma[c] * sg;
      sum_dxhat_xhat += gamma[c] * sgx;
    }
    const REAL s = stats[3 * i + 1];
    coef[2 * i] = sum_dxhat / (REAL)M;
    coef[2 * i + 1] = s > 0 ? sum_dxhat_xhat / ((REAL)(M - 1) * s) : (REAL)0;
  }
  if (i < C) {
    REAL dg = 0, db = 0;
    for (int n = 0; n < N; ++n) {
      const int o = (n * C + i) * groups;
      for (int b = 0; b < groups; ++b) {
        db += part[o + b];
        dg += part[stride + o + b];
      }
    }
    dgamma[i] = dg;
    dbeta[i] = db;
  }
}

// Backward, stage 3: dx = r (g gamma[c] - mean(dxhat)) - xhat * sum(dxhat xhat) / ((M - 1) s).
// Launched like lnt_apply.
__kernel void lnt_bwd_dx(const int inner, const int rows, const int C, __global const REAL* x,
                         __global const REAL* g, __global const REAL* stats,
                         __global const REAL* gamma, __global const REAL* coef,
                         __global REAL* dx) {
  const int v = get_global_id(0);
  const int row = get_global_id(1);
  const int nvec = inner / 4;
  if (v > nvec || row >= rows) return;
  const int s = row / C, c = row % C;
  const REAL mu = stats[3 * s], r = stats[3 * s + 2], ga = gamma[c];
  const REAL mean_dxhat = coef[2 * s], k = coef[2 * s + 1];
  const long o = (long)row * inner;
  __global const REAL* px = x + o;
  __global const REAL* pg = g + o;
  __global REAL* pd = dx + o;
  if (v < nvec) {
    const REAL4 xhat = (vload4(v, px) - mu) * r;
    vstore4(r * (vload4(v, pg) * ga - mean_dxhat) - xhat * k, v, pd);
  } else {
    for (int i = 4 * nvec; i < inner; ++i) {
      const REAL xhat = (px[i] - mu) * r;
      pd[i] = r * (pg[i] * ga - mean_dxhat) - xhat * k;
    }
  }
}

// ---- layerNorm (last axis) --------------------------------------------------------------------

// One item per row of D elements: shifted two-pass mean and biased variance, then
// y = (x - mean) / sqrt(var + eps) * w + b. stats[2 r] = mean, stats[2 r + 1] = 1 / sqrt(var + eps).
__kernel void ln_forward(const int rows, const int D, const REAL eps, __global const REAL* x,
                         __global const REAL* w, __global const REAL* b, __global REAL* y,
                         __global REAL* stats) {
  const int r = get_global_id(0);
  if (r >= rows) return;
  __global const REAL* p = x + (long)r * D;
  __global REAL* q = y + (long)r * D;
  const REAL shift = p[0];
  REAL acc = 0;
  for (int d = 0; d < D; ++d)
    acc += p[d] - shift;
  const REAL mu = shift + acc / (REAL)D;
  REAL ss = 0;
  for (int d = 0; d < D; ++d) {
    const REAL u = p[d] - mu;
    ss += u * u;
  }
  const REAL rstd = 1 / sqrt(ss / (REAL)D + eps);
  for (int d = 0; d < D; ++d)
    q[d] = (p[d] - mu) * rstd * w[d] + b[d];
  stats[2 * r] = mu;
  stats[2 * r + 1] = rstd;
}

// dx = rstd (dxhat - mean(dxhat) - xhat mean(dxhat xhat)), dxhat = g w; one item per row.
__kernel void ln_bwd_dx(const int rows, const int D, __global const REAL* x,
                        __global const REAL* g, __global const REAL* w,
                        __global const REAL* stats, __global REAL* dx) {
  const int r = get_global_id(0);
  if (r >= rows) return;
  const long o = (long)r * D;
  const REAL mu = stats[2 * r], rstd = stats[2 * r + 1];
  REAL s1 = 0, s2 = 0;
  for (int d = 0; d < D; ++d) {
    const REAL dxhat = g[o + d] * w[d];
    s1 += dxhat;
    s2 += dxhat * ((x[o + d] - mu) * rstd);
  }
  s1 /= (REAL)D;
  s2 /= (REAL)D;
  for (int d = 0; d < D; ++d) {
    const REAL xhat = (x[o + d] - mu) * rstd;
    dx[o + d] = rstd * (g[o + d] * w[d] - s1 - xhat * s2);
  }
}

// Partial weight / bias gradients: item (p, d) sums g * xhat and g over rows
// [p * rows_per, (p + 1) * rows_per) of column d (adjacent items read adjacent columns).
__kernel void ln_bwd_wb_partial(const int rows, const int D, const int rows_per, const int parts,
                                __global const REAL* x, __global const REAL* g,
                                __global const REAL* stats, __global REAL* pw,
                                __global REAL* pb) {
  const int i = get_global_id(0);
  if (i >= parts * D) return;
  const int d = i % D, p = i / D;
  const int r0 = p * rows_per;
  const int r1 = min(rows, r0 + rows_per);
  REAL aw = 0, ab = 0;
  for (int r = r0; r < r1; ++r) {
    const long o = (long)r * D + d;
    aw += g[o] * ((x[o] - stats[2 * r]) * stats[2 * r + 1]);
    ab += g[o];
  }
  pw[i] = aw;
  pb[i] = ab;
}
