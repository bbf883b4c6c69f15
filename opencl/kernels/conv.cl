// Convolution lowering. Every convolution runs as a 3-D one (a 2-D convolution has D = KD = 1).
// The output positions are taken in blocks of whole output rows (od, oh) so that the column
// matrix of one block stays small; `row0` is the first flattened row (od * Ho + oh) of the
// block and `rows` its row count, so the block's columns are p = row0 * Wo .. (row0 + rows) * Wo.
// Column matrix layout: col[r][p - p0], r = ((c * KD + i) * KH + j) * KW + l.

#include "conv_index.h"

// Global size (rows, C * KD * KH * KW): one work item writes one output row (Wo consecutive
// columns) of one column-matrix row r, so the index arithmetic is done once per row and the
// inner loops are plain strided copies (the edges split off) that the compiler vectorises.
__kernel void im2col3d(__global const REAL* x, const int xOff, const int C, const int D,
                       const int H, const int W, const int KD, const int KH, const int KW,
                       const int SD, const int SH, const int SW, const int PD, const int PH,
                       const int PW, const int Ho, const int Wo, const int row0, const int rows,
                       const int replicate, __global REAL* col) {
  const int rl = get_global_id(0), r = get_global_id(1);
  if (rl >= rows || r >= C * KD * KH * KW) return;
  const int l = r % KW, j = (r / KW) % KH, i = (r / (KW * KH)) % KD, c = r / (KW * KH * KD);
  const int row = row0 + rl, od = row / Ho, oh = row % Ho;
  const int z = source_index(od, i, SD, PD, D, replicate);
  const int y = source_index(oh, j, SH, PH, H, replicate);
  __global REAL* out = col + (long)r * (rows * Wo) + rl * Wo;
  if (z < 0 || y < 0) { // a zero-padding row
    for (int ow = 0; ow < Wo; ++ow) out[ow] = 0;
    return;
  }
  __global const REAL* in = x + xOff + ((c * D + z) * H + y) * W;
  // Columns ow with 0 <= ow * SW - PW + l < W read inside the row: [lo, hi).
  const int first = PW - l;
  const int lo = clamp(first > 0 ? (first + SW - 1) / SW : 0, 0, Wo);
  const int last = W - 1 + PW - l; // may be negative: no column reads inside then
  const int hi = clamp(last < 0 ? 0 : last / SW + 1, lo, Wo);
  const REAL left = replicate ? in[0] : 0, right = replicate ? in[W - 1] : 0;
  for (int ow = 0; ow < lo; ++ow) out[ow] = left;
  __global const REAL* src = in + l - PW;
  for (int ow = lo; ow < hi; ++ow) out[ow] = src[ow * SW];
  for (int ow = hi; ow < Wo; ++ow) out[ow] = right;
}

// The adjoint of im2col3d for one block: dx[c, d, h, :] += the column entries that read it.
// One work item per input row (c, d, h) of the region the block touches (depths d0 ..
// d0 + dCount - 1, rows h0 .. h0 + hCount - 1), so there are no write conflicts and no
// atomics; along the row it walks the column rows as plain strided copies, like im2col3d
// (with replicate padding the entries that read past an edge add onto the edge sample).
// Global size (dCount * hCount, C).
__kernel void col2im3d(__global const REAL* col, const int C, const int D, const int H,
                       const int W, const int KD, const int KH, const int KW, const int SD,
                       const int SH, const int SW, const int PD, const int PH, const int PW,
                       const int Do, const int Ho, const int Wo, const int row0, const int rows,
                       const int replicate, const int d0, const int dCount, const int h0,
                       const int hCount, __global REAL* dx, const int dxOff, const int clear) {
  const int dh = get_global_id(0), c = get_global_id(1);
  if (dh >= dCount * hCount || c >= C) return;
  const int d = d0 + dh / hCount, h = h0 + dh % hCount;
  const int p0 = row0 * Wo, p1 = (row0 + rows) * Wo, chunk = rows * Wo;
  __global REAL* out = dx + dxOff + ((c * D + d) * H + h) * W;
  if (clear) // the one block of a batch item: this item owns the row, no zero fill before
    for (int x = 0; x < W; ++x)
      out[x] = 0;
  for (int i = 0; i < KD; ++i) {
    const int2 rd = taps_reading(d, i, SD, PD, D, Do, replicate);
    for (int od = rd.x; od <= rd.y; ++od) {
      for (int j = 0; j < KH; ++j) {
        const int2 rh = taps_reading(h, j, SH, PH, H, Ho, replicate);
        for (int oh = rh.x; oh <= rh.y; ++oh) {
          const int rowBase = (od * Ho + oh) * Wo;
          if (rowBase + Wo <= p0 || rowBase >= p1) continue;
          for (int l = 0; l < KW; ++l) {
            const long r = ((c * KD + i) * KH + j) * KW + l;
            __global const REAL* src = col + r * chunk + rowBase - p0;
            // Columns ow with 0 <= ow * SW - PW + l < W read inside the row: [lo, hi).
            const int first = PW - l;
            const int lo = clamp(first > 0 ? (first + SW - 1) / SW : 0, 0, Wo);
            const int last = W - 1 + PW - l;
            const int hi = clamp(last < 0 ? 0 : last / SW + 1, lo, Wo);
            if (replicate) {
              REAL left = 0, right = 0;
              for (int ow = 0; ow < lo; ++ow) left += src[ow];
              for (int ow = hi; ow < Wo; ++ow) right += src[ow];
              out[0] += left;
              out[W - 1] += right;
            }
            __global REAL* dst = out + l - PW;
            for (int ow = lo; ow < hi; ++ow) dst[ow * SW] += src[ow];
          }
        }
      }
    }
  }
}

// y[n, o, p] = bias[o] for the GEMMs to accumulate onto (beta = 1).
// y[n, o, p] = bias[o]. Global size (ceil(P / 8), N * O): each item stores 8 consecutive
// pixels of one row (one vector store; a flat one-element-per-item index needed a division per
// element and was 3x slower on PoCL).
__kernel void conv_bias_fill(const int rows, const int O, const int P,
                             __global const REAL* bias, __global REAL* y) {
  const int p0 = get_global_id(0) * 8, row = get_global_id(1);
  if (p0 >= P || row >= rows) return;
  const REAL v = bias[row % O];
  __global REAL* out = y + (long)row * P + p0;
  if (p0 + 8 <= P) {
#if REAL_IS_DOUBLE
    vstore8((double8)(v), 0, out);
#else
    vstore8((float8)(v), 0, out);
#endif
  } else {
    for (int p = 0; p < P - p0; ++p)
      out[p] = v;
  }
}

// Partial bias gradients: partial[o, part] = sum over n and p = part, part + parts, ... of
// g[n, o, p]. Global size (parts, O); neighbouring work items read neighbouring elements.
__kernel void conv_bias_grad(const int N, const int O, const int P, const int parts,
                             __global const REAL* g, __global REAL* partial) {
  const int part = get_global_id(0), o = get_global_id(1);
  if (part >= parts || o >= O) return;
  REAL acc = 0;
  for (int n = 0; n < N; ++n) {
    __global const REAL* row = g + ((long)n * O + o) * P;
    for (int p = part; p < P; p += parts) acc += row[p];
  }
  partial[o * parts + part] = acc;
}
