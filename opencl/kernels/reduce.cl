// Reductions. A tensor reduced over one axis is viewed as [outer, n, inner]. Three shapes of
// work (chosen in ops_reduce.cpp):
//  * direct: one item per (outer, inner) pair walks the axis (many outputs, short axes);
//  * blocks: inner == 1 and a long axis: each row is cut into blocks of GROUP items reading
//    REAL4 vectors (layout of src/row_blocks.h), one partial per block;
//  * split: few outputs and a long strided axis: the axis is cut into P chunks, one partial
//    per (outer, chunk, inner).
// Partials are then summed in a fixed order, so results are deterministic. `mode` selects the
// summed term: x (RED_SUM) or (x - mean)^2 (RED_SQDEV, mean per (outer, inner)).

#define GROUP 64
#define RED_SUM 0
#define RED_SQDEV 1

inline REAL red_term(const int mode, const REAL x, const REAL m) {
  const REAL d = x - m;
  return mode == RED_SUM ? x : d * d;
}
inline REAL4 red_term4(const int mode, const REAL4 x, const REAL m) {
  const REAL4 d = x - m;
  return mode == RED_SUM ? x : d * d;
}

// Direct: out[i] = scale * sum_k term(x[o, k, in]).
__kernel void reduce_axis(const int mode, const int outer, const int n, const int inner,
                          const REAL scale, __global const REAL* x, __global const REAL* mean,
                          __global REAL* out) {
  const int i = get_global_id(0);
  if (i >= outer * inner) return;
  const int o = i / inner, in = i % inner;
  const REAL m = mode == RED_SUM ? (REAL)0 : mean[i];
  __global const REAL* p = x + (long)o * n * inner + in;
  REAL acc = 0;
  for (int k = 0; k < n; ++k)
    acc += red_term(mode, p[(long)k * inner], m);
  out[i] = acc * scale;
}

// Blocks (inner == 1): rows of L elements, launch (GROUP x groups, rows); the block sum goes to
// part[row * groups + block]. No early return: every item reaches the barrier.
__kernel void reduce_blocks(const int mode, const int L, const int per_vec,
                            __global const REAL* x, __global const REAL* mean,
                            __global REAL* part) {
  __local REAL s[GROUP];
  const int j = get_local_id(0);
  const int block = get_group_id(0);
  const int groups = get_num_groups(0);
  const int row = get_global_id(1);
  const int in_block = clamp(L - block * GROUP * 4 * per_vec, 0, GROUP * 4 * per_vec);
  const int nvec = in_block / 4;
  const int tail = j == 0 ? in_block - 4 * nvec : 0;
  const REAL m = mode == RED_SUM ? (REAL)0 : mean[row];
  __global const REAL* p = x + (long)row * L + block * GROUP * 4 * per_vec;
  REAL4 a4 = 0;
  for (int v = j; v < nvec; v += GROUP)
    a4 += red_term4(mode, vload4(v, p), m);
  REAL acc = (a4.x + a4.y) + (a4.z + a4.w);
  for (int t = 4 * nvec; t < 4 * nvec + tail; ++t)
    acc += red_term(mode, p[t], m);
  s[j] = acc;
  barrier(CLK_LOCAL_MEM_FENCE);
  if (j == 0) {
    REAL total = 0;
    for (int i = 0; i < GROUP; ++i)
      total += s[i];
    part[row * groups + block] = total;
  }
}

// Split: item i = (o * P + p) * inner + in sums k in [p * chunk, (p + 1) * chunk) of the axis
// into part[i] (part is [outer, P, inner]; adjacent items read adjacent `inner` elements).
__kernel void reduce_split(const int mode, const int outer, const int n, const int inner,
                           const int chunk, const int P, __global const REAL* x,
                           __global const REAL* mean, __global REAL* part) {
  const int i = get_global_id(0);
  if (i >= outer * P * inner) return;
  const int in = i % inner;
  const int p = (i / inner) % P;
  const int o = i / (inner * P);
  const REAL m = mode == RED_SUM ? (REAL)0 : mean[o * inner + in];
  __global const REAL* base = x + (long)o * n * inner + in;
  const int k1 = min(n, (p + 1) * chunk);
  REAL acc = 0;
  for (int k = p * chunk; k < k1; ++k)
    acc += red_term(mode, base[(long)k * inner], m);
  part[i] = acc;
}

// Second stage of the blocks and split layouts: out[i] = scale * sum over the P partials of
// (outer, inner) pair i. Compensated (Kahan) summation: the partials are few but large, and a
// plain float sum of ~1e3 of them would dominate the error of the whole reduction. (No
// fast-math build options, so the compiler keeps the compensation.)
__kernel void reduce_partials(const int outer, const int P, const int inner, const REAL scale,
                              __global const REAL* part, __global REAL* out) {
  const int i = get_global_id(0);
  if (i >= outer * inner) return;
  const int o = i / inner, in = i % inner;
  __global const REAL* p = part + (long)o * P * inner + in;
  REAL sum = 0, c = 0;
  for (int k = 0; k < P; ++k) {
    const REAL y = p[(long)k * inner] - c;
    const REAL t = sum + y;
    c = (t - sum) - y;
    sum = t;
  }
  out[i] = sum * scale;
}

// Plain sum over the axis, one item per (outer, inner) pair (also used by other ops for their
// second stage).
__kernel void reduce_sum_axis(const int outer, const int n, const int inner,
                              __global const REAL* x, __global REAL* out) {
  const int i = get_global_id(0);
  if (i >= outer * inner) return;
  const int o = i / inner, in = i % inner;
  __global const REAL* p = x + (long)o * n * inner + in;
  REAL acc = 0;
  for (int k = 0; k < n; ++k)
    acc += p[(long)k * inner];
  out[i] = acc;
}
