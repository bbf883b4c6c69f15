// Resampling: separable resize (bilinear or bicubic, chosen at build time with -DTAPS=2 or 4)
// and bilinear grid sampling with zero padding. Semantics follow PyTorch's F.interpolate and
// F.grid_sample with align_corners = False (see ops_resample.h).
//
// Work items loop over channels/planes so that tap positions and weights are computed once
// and reused for every channel.

#ifndef TAPS
#define TAPS 4
#endif
// Planes handled by one resize work item (keeps the weight computation amortised while still
// leaving enough items when the output is small).
#define PLANES_PER_ITEM 8
// Column weights cached by one resize_backward item.
#define WEIGHT_CACHE 16

// Tap offsets relative to floor(source position).
#if TAPS == 2
#define TAP_MIN 0
#define TAP_MAX 1
#else
#define TAP_MIN (-1)
#define TAP_MAX 2
#endif

inline int floor_div(const int a, const int b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }
inline int ceil_div(const int a, const int b) { return -floor_div(-a, b); }

// Source position of output sample p along an axis with `in` input and `out` output samples:
// s = (p + 0.5) in / out - 0.5 = num / den exactly, with num = (2p + 1) in - out, den = 2 out.
// floor(s) is estimated in floating point and corrected with exact integer products (an
// integer division per item costs more than the whole tap loop on PoCL), so it is exact, and
// the fraction is a single rounding, in float too. Returns floor(s), stores s - floor(s) in *t.
inline int source_floor(const int p, const int in, const int out, REAL* t) {
  int num = (2 * p + 1) * in - out;
  const int den = 2 * out;
#if TAPS == 2
  num = max(num, 0); // linear modes clamp the source position at 0 (PyTorch)
#endif
  int f = (int)floor((REAL)num / (REAL)den);
  f += (f + 1) * den <= num ? 1 : 0;
  f -= f * den > num ? 1 : 0;
  *t = (REAL)(num - f * den) / (REAL)den;
  return f;
}

// Keys cubic convolution with A = -0.75 (PyTorch's bicubic): |x| <= 1 and 1 < |x| < 2.
#define CUBIC_A ((REAL)-0.75)
inline REAL cubic_near(const REAL x) {
  return ((CUBIC_A + 2) * x - (CUBIC_A + 3)) * x * x + 1;
}
inline REAL cubic_far(const REAL x) {
  return ((CUBIC_A * x - 5 * CUBIC_A) * x + 8 * CUBIC_A) * x - 4 * CUBIC_A;
}

// Input indices (clamped to the border) and weights of output sample p along one axis.
inline void axis_taps(const int p, const int in, const int out, int* idx, REAL* w) {
  REAL t;
  const int f = source_floor(p, in, out, &t);
#if TAPS == 2
  idx[0] = f;
  idx[1] = min(f + 1, in - 1);
  w[0] = 1 - t;
  w[1] = t;
#else
  for (int k = 0; k < 4; ++k)
    idx[k] = clamp(f - 1 + k, 0, in - 1);
  w[0] = cubic_far(t + 1);
  w[1] = cubic_near(t);
  w[2] = cubic_near(1 - t);
  w[3] = cubic_far(2 - t);
#endif
}

// Total weight with which output sample p reads input sample i (taps clamped to the same
// border index add up).
inline REAL weight_to(const int p, const int i, const int in, const int out) {
  int idx[TAPS];
  REAL w[TAPS];
  axis_taps(p, in, out, idx, w);
  REAL s = 0;
  for (int k = 0; k < TAPS; ++k)
    if (idx[k] == i) s += w[k];
  return s;
}

// The contiguous range of output samples that may read input sample i: floor(s(p)) is
// monotone in p, so it is p with i - TAP_MAX <= floor(s(p)) <= i - TAP_MIN, widened to the
// ends for the border samples that clamped taps fall on. Solving floor(s(p)) >= m gives
// p >= ceil(((2m + 1) out - in) / (2 in)); floor(s(p)) <= M gives
// p <= ceil(((2M + 3) out - in) / (2 in)) - 1. (weight_to checks every p exactly.)
inline int2 outputs_reading(const int i, const int in, const int out) {
  const int m = i - TAP_MAX, big_m = i - TAP_MIN;
  const int lo = m <= 0 ? 0 : max(0, ceil_div((2 * m + 1) * out - in, 2 * in));
  const int hi =
      i == in - 1 ? out - 1 : min(out - 1, ceil_div((2 * big_m + 3) * out - in, 2 * in) - 1);
  return (int2)(lo, hi);
}

// x [planes, in_h, in_w] -> out [planes, out_h, out_w]; items over (column, row, plane group).
__kernel void resize_forward(const int planes, const int in_h, const int in_w, const int out_h,
                             const int out_w, __global const REAL* x, __global REAL* out) {
  const int q = get_global_id(0), p = get_global_id(1);
  const int b0 = get_global_id(2) * PLANES_PER_ITEM;
  if (q >= out_w || p >= out_h || b0 >= planes) return;
  int iy[TAPS], ix[TAPS];
  REAL wy[TAPS], wx[TAPS];
  axis_taps(p, in_h, out_h, iy, wy);
  axis_taps(q, in_w, out_w, ix, wx);
  const int b1 = min(planes, b0 + PLANES_PER_ITEM);
  for (int b = b0; b < b1; ++b) {
    __global const REAL* plane = x + b * in_h * in_w;
    REAL acc = 0;
    for (int a = 0; a < TAPS; ++a) {
      __global const REAL* row = plane + iy[a] * in_w;
      REAL r = 0;
      for (int k = 0; k < TAPS; ++k)
        r += wx[k] * row[ix[k]];
      acc += wy[a] * r;
    }
    out[(b * out_h + p) * out_w + q] = acc;
  }
}

// Gradient of resize as a gather: input sample (i, j) collects the output gradient of every
// output sample that read it, so no atomics are needed. Items over (column, row, plane group).
__kernel void resize_backward(const int planes, const int in_h, const int in_w, const int out_h,
                              const int out_w, __global const REAL* g, __global REAL* gx) {
  const int j = get_global_id(0), i = get_global_id(1);
  const int b0 = get_global_id(2) * PLANES_PER_ITEM;
  if (j >= in_w || i >= in_h || b0 >= planes) return;
  const int nb = min(planes - b0, PLANES_PER_ITEM);
  const int out_plane = out_h * out_w;
  REAL acc[PLANES_PER_ITEM];
  for (int k = 0; k < PLANES_PER_ITEM; ++k)
    acc[k] = 0;
  const int2 rows = outputs_reading(i, in_h, out_h);
  const int2 cols = outputs_reading(j, in_w, out_w);
  // The column weights do not depend on the row: computed once when the range is short
  // (up-sampling up to about x3.5), else recomputed per row.
  REAL wxc[WEIGHT_CACHE];
  const bool cached = cols.y - cols.x < WEIGHT_CACHE;
  if (cached)
    for (int q = cols.x; q <= cols.y; ++q)
      wxc[q - cols.x] = weight_to(q, j, in_w, out_w);
  for (int p = rows.x; p <= rows.y; ++p) {
    const REAL wy = weight_to(p, i, in_h, out_h);
    if (wy == 0) continue;
    for (int q = cols.x; q <= cols.y; ++q) {
      const REAL wx = cached ? wxc[q - cols.x] : weight_to(q, j, in_w, out_w);
      if (wx == 0) continue;
      const REAL w = wy * wx;
      __global const REAL* gp = g + b0 * out_plane + p * out_w + q;
      for (int k = 0; k < nb; ++k)
        acc[k] += w * gp[k * out_plane];
    }
  }
  for (int k = 0; k < nb; ++k)
    gx[((b0 + k) * in_h + i) * in_w + j] = acc[k];
}

// ---- grid sampling --------------------------------------------------------------------------

// Bilinear taps (Taps, make_taps, gather, gather_grad, scatter) and atomic_add_real come from
// common.cl.

// x [n, c, h, w], grid [n, oh, ow, 2] (x, y in [-1, 1]) -> out [n, c, oh, ow].
// Items over (output column, output row, batch); each loops over the channels.
__kernel void grid_sample_forward(const int n, const int c, const int h, const int w,
                                  const int oh, const int ow, __global const REAL* x,
                                  __global const REAL* grid, __global REAL* out) {
  const int q = get_global_id(0), p = get_global_id(1), b = get_global_id(2);
  if (q >= ow || p >= oh || b >= n) return;
  const int point = (b * oh + p) * ow + q;
  const int out_plane = oh * ow, in_plane = h * w;
  __global REAL* o = out + b * c * out_plane + p * ow + q;
  Taps t;
  make_taps(grid[2 * point], grid[2 * point + 1], h, w, &t);
  __global const REAL* xb = x + b * c * in_plane;
  for (int ch = 0; ch < c; ++ch)
    o[ch * out_plane] = gather(xb + ch * in_plane, &t);
}

// Gradients of grid_sample_forward: to the input (scattered with atomic adds, since any number
// of sample points may share a pixel; gx must be zeroed) when want_input, and to the grid
// (one point per item, no conflicts) when want_grid. Unused outputs may be any buffer.
__kernel void grid_sample_backward(const int n, const int c, const int h, const int w,
                                   const int oh, const int ow, __global const REAL* x,
                                   __global const REAL* grid, __global const REAL* g,
                                   const int want_input, __global REAL* gx, const int want_grid,
                                   __global REAL* ggrid) {
  const int q = get_global_id(0), p = get_global_id(1), b = get_global_id(2);
  if (q >= ow || p >= oh || b >= n) return;
  const int point = (b * oh + p) * ow + q;
  const int out_plane = oh * ow, in_plane = h * w;
  Taps t;
  make_taps(grid[2 * point], grid[2 * point + 1], h, w, &t);
  __global const REAL* gb = g + b * c * out_plane + p * ow + q;
  REAL dx = 0, dy = 0;
  for (int ch = 0; ch < c; ++ch) {
    const REAL go = gb[ch * out_plane];
    const int base = (b * c + ch) * in_plane;
    if (want_input) scatter(gx + base, &t, go);
    if (want_grid) {
      REAL dsx, dsy;
      gather_grad(x + base, &t, &dsx, &dsy);
      dx += go * dsx;
      dy += go * dsy;
    }
  }
  if (want_grid) {
    // d sx / d gx = w / 2, d sy / d gy = h / 2.
    ggrid[2 * point] = dx * (REAL)w / 2;
    ggrid[2 * point + 1] = dy * (REAL)h / 2;
  }
}

// 1 where |gx| <= 1 and |gy| <= 1 (inclusive), else 0 (also for NaN).
__kernel void grid_sample_mask(const int points, __global const REAL* grid,
                               __global REAL* mask) {
  const int i = get_global_id(0);
  if (i >= points) return;
  const REAL gx = grid[2 * i], gy = grid[2 * i + 1];
  mask[i] = (fabs(gx) <= 1 && fabs(gy) <= 1) ? (REAL)1 : (REAL)0;
}
