// Direct convolutions for small channel counts: the forward, the input gradient and the weight
// gradient computed from the input, the output gradient and the weights, without conv.cl's
// column matrix, which for C * KD * KH * KW of a few hundred costs more memory traffic than the
// GEMM's flops. Every convolution is a 3-D one (a 2-D convolution has D = KD = 1); padding
// follows source_index in conv.cl exactly (zero padding reads nothing outside, replicate padding
// reads the edge sample, so in the input gradient an edge sample gathers every tap clamped onto
// it).
//
// In the forward and the input gradient one work item owns 8 consecutive positions along x of
// one row (d, h) for a block of BLOCK channels (output channels in the forward, input channels
// in the input gradient), accumulated as BLOCK REAL8 vectors. Vectors are written out because
// PoCL vectorises only innermost loops and the per-item channel and tap loops hide the
// work-item loop from it (as gemm_skinny_m8). Neighbouring work items take neighbouring x
// blocks of the same row. The weight gradient (conv_direct_weight_grad, at the end) reduces
// over the output positions instead and is described there.
//
// The weights are first regrouped (conv_direct_weights) so that the BLOCK weights one tap
// multiplies are contiguous, zero past the last channel. Where all taps of a work item read
// inside the row (all but the first and last x blocks at stride 1) the taps are plain vector
// loads; the edges take load8 / gather8, one sample at a time.
//
// Compile-time parameters: BLOCK (1..32), so the accumulators are registers in unrolled loops;
// KW, the kernel width, so the taps along x unroll; WG_BLOCK (below).

#include "conv_index.h"

#ifndef BLOCK
#define BLOCK 16 // channels per work item
#endif
#ifndef KW
#define KW 3 // kernel width
#endif

#if REAL_IS_DOUBLE
typedef double8 REAL8;
#else
typedef float8 REAL8;
#endif

// The 8 samples row[q0], row[q0 + step], ..., row[q0 + 7 step] of a row of n samples; outside
// [0, n) they are clamped to the edge (clamp) or 0. Vector loads in the interior for steps 1
// and 2, one sample at a time at the edges.
inline REAL8 load8(__global const REAL* row, const int q0, const int step, const int n,
                   const int clamp_edges) {
  if (q0 >= 0) {
    if (step == 1 && q0 + 8 <= n)
      return vload8(0, row + q0);
    if (step == 2 && q0 + 16 <= n) {
      // Two 8-wide loads, not one 16-wide: PoCL warns that a 16-float vector return changes
      // the ABI on CPUs without AVX-512 (printed as "1 warning generated." on a cold cache).
      const REAL8 lo = vload8(0, row + q0), hi = vload8(0, row + q0 + 8);
      return (REAL8)(lo.even, hi.even);
    }
  }
  REAL v[8];
  for (int k = 0; k < 8; ++k) {
    const int q = q0 + k * step;
    v[k] = clamp_edges ? row[clamp(q, 0, n - 1)] : ((q >= 0 && q < n) ? row[q] : 0);
  }
  return vload8(0, v);
}

// Stores the first `valid` (1..8) lanes of v at out.
inline void store8(const REAL8 v, const int valid, __global REAL* out) {
  if (valid == 8) {
    vstore8(v, 0, out);
    return;
  }
  REAL lanes[8];
  vstore8(v, 0, lanes);
  for (int k = 0; k < valid; ++k)
    out[k] = lanes[k];
}

// Weights regrouped into blocks of BLOCK channels: by_input == 0 (forward) blocks the output
// channels, wb[((k * C + c) * taps + t) * BLOCK + b] = w[k BLOCK + b, c, t]; by_input == 1
// (input gradient) blocks the input channels, wb[((k * O + o) * taps + t) * BLOCK + b] =
// w[o, k BLOCK + b, t]; 0 past the last channel. Global size: blocks * (C or O) * taps * BLOCK.
__kernel void conv_direct_weights(__global const REAL* w, const int O, const int C, const int taps,
                                  const int by_input, __global REAL* wb) {
  const int i = get_global_id(0);
  const int blocked = by_input ? C : O, other = by_input ? O : C;
  const int blocks = (blocked + BLOCK - 1) / BLOCK;
  if (i >= blocks * other * taps * BLOCK)
    return;
  const int b = i % BLOCK, t = (i / BLOCK) % taps, r = (i / (BLOCK * taps)) % other;
  const int ch = (i / (BLOCK * taps * other)) * BLOCK + b;
  const int o = by_input ? r : ch, c = by_input ? ch : r;
  wb[i] = ch < blocked ? w[((long)o * C + c) * taps + t] : 0;
}

// Forward: y[n, o, od, oh, ow0 .. ow0 + 7] for the BLOCK output channels k BLOCK .. (k + 1)
// BLOCK - 1 (those >= O are not stored). bias is read when has_bias. Global size
// (ceil(Wo / 8), Do * Ho, N * blocks).
__kernel void conv_direct_forward(__global const REAL* x, __global const REAL* wb,
                                  __global const REAL* bias, const int has_bias, const int N,
                                  const int C, const int D, const int H, const int W, const int O,
                                  const int KD, const int KH, const int SD, const int SH,
                                  const int SW, const int PD, const int PH, const int PW,
                                  const int Do, const int Ho, const int Wo, const int replicate,
                                  __global REAL* y) {
  const int ow0 = get_global_id(0) * 8, row = get_global_id(1), nk = get_global_id(2);
  const int blocks = (O + BLOCK - 1) / BLOCK;
  if (ow0 >= Wo || row >= Do * Ho || nk >= N * blocks)
    return;
  const int n = nk / blocks, k = nk % blocks, o0 = k * BLOCK;
  const int od = row / Ho, oh = row % Ho;
  const int q0 = ow0 * SW - PW;                                  // tap 0 of lane 0 reads x = q0
  const int inside = SW == 1 && q0 >= 0 && q0 + KW - 1 + 8 <= W; // every tap inside the row
  REAL8 acc[BLOCK];
#pragma unroll
  for (int b = 0; b < BLOCK; ++b)
    acc[b] = (REAL8)(has_bias ? bias[min(o0 + b, O - 1)] : 0);
  for (int c = 0; c < C; ++c) {
    __global const REAL* xc = x + (long)(n * C + c) * D * H * W;
    for (int i = 0; i < KD; ++i) {
      const int z = source_index(od, i, SD, PD, D, replicate);
      if (z < 0)
        continue;
      for (int j = 0; j < KH; ++j) {
        const int yy = source_index(oh, j, SH, PH, H, replicate);
        if (yy < 0)
          continue;
        __global const REAL* in = xc + (z * H + yy) * W + q0;
        __global const REAL* wt = wb + ((((long)k * C + c) * KD + i) * KH + j) * KW * BLOCK;
        if (inside) {
#pragma unroll
          for (int l = 0; l < KW; ++l) {
            const REAL8 v = vload8(0, in + l);
#pragma unroll
            for (int b = 0; b < BLOCK; ++b)
              acc[b] += wt[l * BLOCK + b] * v;
          }
        } else {
#pragma unroll
          for (int l = 0; l < KW; ++l) {
            const REAL8 v = load8(in - q0, q0 + l, SW, W, replicate);
#pragma unroll
            for (int b = 0; b < BLOCK; ++b)
              acc[b] += wt[l * BLOCK + b] * v;
          }
        }
      }
    }
  }
  const int valid = min(8, Wo - ow0);
#pragma unroll
  for (int b = 0; b < BLOCK; ++b)
    if (o0 + b < O)
      store8(acc[b], valid, y + ((long)(n * O + o0 + b) * Do * Ho + row) * Wo + ow0);
}

// The output-gradient samples g[ow] of one row that tap l sends to inputs x0 .. x0 + 7 in
// their own right (ow * s - p + l == x, lanes without such an ow get 0); with `left` / `right`
// (replicate padding, the row's first / last input in lane 0 / lane `right`) also the samples
// of the columns whose tap l reads past that edge: ow < lo and ow >= hi, im2col3d's lo / hi.
inline REAL8 gather8(__global const REAL* g, const int x0, const int l, const int s, const int p,
                     const int n_in, const int n_out, const int left, const int right) {
  REAL v[8];
  if (s == 1) {
    vstore8(load8(g, x0 + p - l, 1, n_out, 0), 0, v);
  } else {
    for (int k = 0; k < 8; ++k) {
      const int t = x0 + k + p - l; // ow * s
      const int ow = t >= 0 ? t / s : -1;
      v[k] = (t >= 0 && ow * s == t && ow < n_out) ? g[ow] : 0;
    }
  }
  if (left | (right >= 0)) {
    const int first = p - l;
    const int lo = clamp(first > 0 ? (first + s - 1) / s : 0, 0, n_out);
    const int last = n_in - 1 + p - l;
    const int hi = clamp(last < 0 ? 0 : last / s + 1, lo, n_out);
    if (left)
      for (int ow = 0; ow < lo; ++ow)
        v[0] += g[ow];
    if (right >= 0)
      for (int ow = hi; ow < n_out; ++ow)
        v[right] += g[ow];
  }
  return vload8(0, v);
}

// Input gradient (the transposed convolution): gx[n, c, d, h, x0 .. x0 + 7] for the BLOCK input
// channels k BLOCK .. (k + 1) BLOCK - 1, written (not accumulated). Along d and h the output
// rows that read (d, h) come from taps_reading (with replicate padding an edge row gathers
// every tap clamped onto it); along x, vector loads in the interior, gather8 at the edges.
// Global size (ceil(W / 8), D * H, N * blocks).
__kernel void conv_direct_input_grad(__global const REAL* gy, __global const REAL* wb, const int N,
                                     const int C, const int D, const int H, const int W,
                                     const int O, const int KD, const int KH, const int SD,
                                     const int SH, const int SW, const int PD, const int PH,
                                     const int PW, const int Do, const int Ho, const int Wo,
                                     const int replicate, __global REAL* gx) {
  const int x0 = get_global_id(0) * 8, row = get_global_id(1), nk = get_global_id(2);
  const int blocks = (C + BLOCK - 1) / BLOCK;
  if (x0 >= W || row >= D * H || nk >= N * blocks)
    return;
  const int n = nk / blocks, k = nk % blocks, c0 = k * BLOCK;
  const int d = row / H, h = row % H;
  const int left = replicate && x0 == 0;                        // lane 0 is x == 0
  const int right = replicate && x0 + 8 >= W ? W - 1 - x0 : -1; // lane of x == W - 1
  // Lane x takes g[x + PW - l] from tap l (stride 1): all inside the row, no edge lanes.
  const int inside = SW == 1 && x0 + PW - (KW - 1) >= 0 && x0 + PW + 8 <= Wo && !left && right < 0;
  REAL8 acc[BLOCK];
#pragma unroll
  for (int b = 0; b < BLOCK; ++b)
    acc[b] = (REAL8)(0);
  for (int i = 0; i < KD; ++i) {
    const int2 rd = taps_reading(d, i, SD, PD, D, Do, replicate);
    for (int j = 0; j < KH; ++j) {
      const int2 rh = taps_reading(h, j, SH, PH, H, Ho, replicate);
      for (int od = rd.x; od <= rd.y; ++od)
        for (int oh = rh.x; oh <= rh.y; ++oh)
          for (int o = 0; o < O; ++o) {
            __global const REAL* g = gy + (((long)(n * O + o) * Do + od) * Ho + oh) * Wo;
            __global const REAL* wt = wb + ((((long)k * O + o) * KD + i) * KH + j) * KW * BLOCK;
            if (inside) {
#pragma unroll
              for (int l = 0; l < KW; ++l) {
                const REAL8 v = vload8(0, g + x0 + PW - l);
#pragma unroll
                for (int b = 0; b < BLOCK; ++b)
                  acc[b] += wt[l * BLOCK + b] * v;
              }
            } else {
#pragma unroll
              for (int l = 0; l < KW; ++l) {
                const REAL8 v = gather8(g, x0, l, SW, PW, W, Wo, left, right);
#pragma unroll
                for (int b = 0; b < BLOCK; ++b)
                  acc[b] += wt[l * BLOCK + b] * v;
              }
            }
          }
    }
  }
  const int valid = min(8, W - x0);
#pragma unroll
  for (int b = 0; b < BLOCK; ++b)
    if (c0 + b < C)
      store8(acc[b], valid, gx + ((long)(n * C + c0 + b) * D * H + row) * W + x0);
}

#ifndef WG_BLOCK
#define WG_BLOCK 8 // output channels per work item of the weight gradient
#endif

// Weight gradient, partial sums over one part of the output rows: partial[s, o, c, i, j, l] =
// sum over the rows (n, od, oh) of part s and all ow of gy[n, o, od, oh, ow] x[n, c, tap
// (i, j, l) of (od, oh, ow)], for the WG_BLOCK output channels k WG_BLOCK .. of one (c, i, j).
// A work item keeps KW x WG_BLOCK REAL8 accumulators (lanes: 8 consecutive ow) and per 8
// outputs loads KW input vectors and WG_BLOCK output-gradient vectors for KW x WG_BLOCK
// multiply-adds. Rows are split into `parts` contiguous ranges. Global size (parts,
// C * KD * KH, ceil(O / WG_BLOCK)).
__kernel void conv_direct_weight_grad(__global const REAL* x, __global const REAL* gy, const int N,
                                      const int C, const int D, const int H, const int W,
                                      const int O, const int KD, const int KH, const int SD,
                                      const int SH, const int SW, const int PD, const int PH,
                                      const int PW, const int Do, const int Ho, const int Wo,
                                      const int replicate, const int parts,
                                      __global REAL* partial) {
  const int s = get_global_id(0), cij = get_global_id(1), k = get_global_id(2);
  if (s >= parts || cij >= C * KD * KH || k * WG_BLOCK >= O)
    return;
  const int c = cij / (KD * KH), i = (cij / KH) % KD, j = cij % KH, o0 = k * WG_BLOCK;
  const long plane = (long)Do * Ho * Wo;
  const int rows = N * Do * Ho;
  const int r0 = (int)((long)rows * s / parts), r1 = (int)((long)rows * (s + 1) / parts);
  REAL8 acc[KW * WG_BLOCK];
#pragma unroll
  for (int a = 0; a < KW * WG_BLOCK; ++a)
    acc[a] = (REAL8)(0);
  for (int r = r0; r < r1; ++r) {
    const int n = r / (Do * Ho), od = (r / Ho) % Do, oh = r % Ho;
    const int z = source_index(od, i, SD, PD, D, replicate);
    const int yy = source_index(oh, j, SH, PH, H, replicate);
    if (z < 0 || yy < 0)
      continue;
    __global const REAL* in = x + (((long)(n * C + c) * D + z) * H + yy) * W;
    __global const REAL* g = gy + (long)(n * O + o0) * plane + (od * Ho + oh) * Wo;
    for (int ow0 = 0; ow0 < Wo; ow0 += 8) {
      const int q0 = ow0 * SW - PW;
      REAL8 xv[KW];
      if (SW == 1 && q0 >= 0 && q0 + KW - 1 + 8 <= W) {
#pragma unroll
        for (int l = 0; l < KW; ++l)
          xv[l] = vload8(0, in + q0 + l);
      } else {
#pragma unroll
        for (int l = 0; l < KW; ++l)
          xv[l] = load8(in, q0 + l, SW, W, replicate);
      }
      const int full = ow0 + 8 <= Wo;
#pragma unroll
      for (int b = 0; b < WG_BLOCK; ++b) {
        // Channels past O read channel O - 1 (their sums are not stored); lanes past Wo read 0.
        __global const REAL* gb = g + min(b, O - 1 - o0) * plane + ow0;
        const REAL8 gv = full ? vload8(0, gb) : load8(gb, 0, 1, Wo - ow0, 0);
#pragma unroll
        for (int l = 0; l < KW; ++l)
          acc[l * WG_BLOCK + b] += gv * xv[l];
      }
    }
  }
  const int taps = KD * KH * KW;
  __global REAL* out = partial + (long)s * O * C * taps + c * taps + (i * KH + j) * KW;
#pragma unroll
  for (int b = 0; b < WG_BLOCK; ++b)
    if (o0 + b < O) {
#pragma unroll
      for (int l = 0; l < KW; ++l) {
        const REAL8 v = acc[l * WG_BLOCK + b];
        const REAL4 h = v.lo + v.hi;
        out[(long)(o0 + b) * C * taps + l] = (h.s0 + h.s1) + (h.s2 + h.s3);
      }
    }
}
