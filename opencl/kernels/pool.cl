// 2-D max and average pooling over the last two dimensions of x viewed as [planes, H, W]
// (no padding, floor mode). Launched over (column, row, plane). Backward passes are gathers
// (every input element collects from the windows that contain it), so overlapping windows
// need no atomics and the result is deterministic.

// The first maximum of a window in row-major order wins ties; a NaN wins (the last NaN), as in
// PyTorch. Selects instead of branches (a branch on random data mispredicts half the time) and
// no integer division (on PoCL one per item costs more than the whole window).
inline REAL window_max(__global const REAL* plane, const int w, const int y0, const int x0,
                       const int kh, const int kw) {
  REAL best = -INFINITY;
  for (int dy = 0; dy < kh; ++dy)
    for (int dx = 0; dx < kw; ++dx) {
      const REAL v = plane[(y0 + dy) * w + x0 + dx];
      best = (v > best || v != v) ? v : best;
    }
  return best;
}

// (row, column) within the window of the maximum that window_max picks.
inline int2 window_argmax(__global const REAL* plane, const int w, const int y0, const int x0,
                          const int kh, const int kw) {
  REAL best = -INFINITY;
  int2 arg = (int2)(0, 0);
  for (int dy = 0; dy < kh; ++dy)
    for (int dx = 0; dx < kw; ++dx) {
      const REAL v = plane[(y0 + dy) * w + x0 + dx];
      const bool take = v > best || v != v;
      best = take ? v : best;
      arg = take ? (int2)(dy, dx) : arg;
    }
  return arg;
}

__kernel void max_pool_forward(const int planes, const int h, const int w, const int oh,
                               const int ow, const int kh, const int kw, const int sh,
                               const int sw, __global const REAL* x, __global REAL* out) {
  const int q = get_global_id(0), p = get_global_id(1), b = get_global_id(2);
  if (q >= ow || p >= oh || b >= planes) return;
  out[(b * oh + p) * ow + q] = window_max(x + b * h * w, w, p * sh, q * sw, kh, kw);
}

// First and last window index (along one axis) whose window [o*s, o*s + k) contains i.
inline int2 windows_containing(const int i, const int k, const int s, const int n_out) {
  const int first = i - k + 1 <= 0 ? 0 : (i - k + 1 + s - 1) / s;
  const int last = min(i / s, n_out - 1);
  return (int2)(first, last);
}

__kernel void max_pool_backward(const int planes, const int h, const int w, const int oh,
                                const int ow, const int kh, const int kw, const int sh,
                                const int sw, __global const REAL* x, __global const REAL* g,
                                __global REAL* gx) {
  const int j = get_global_id(0), i = get_global_id(1), b = get_global_id(2);
  if (j >= w || i >= h || b >= planes) return;
  __global const REAL* plane = x + b * h * w;
  __global const REAL* gplane = g + b * oh * ow;
  const int2 rows = windows_containing(i, kh, sh, oh);
  const int2 cols = windows_containing(j, kw, sw, ow);
  REAL acc = 0;
  for (int p = rows.x; p <= rows.y; ++p)
    for (int q = cols.x; q <= cols.y; ++q) {
      const int2 arg = window_argmax(plane, w, p * sh, q * sw, kh, kw);
      if (p * sh + arg.x == i && q * sw + arg.y == j) acc += gplane[p * ow + q];
    }
  gx[(b * h + i) * w + j] = acc;
}

__kernel void avg_pool_forward(const int planes, const int h, const int w, const int oh,
                               const int ow, const int kh, const int kw, const int sh,
                               const int sw, __global const REAL* x, __global REAL* out) {
  const int q = get_global_id(0), p = get_global_id(1), b = get_global_id(2);
  if (q >= ow || p >= oh || b >= planes) return;
  __global const REAL* plane = x + b * h * w + p * sh * w + q * sw;
  REAL acc = 0;
  for (int dy = 0; dy < kh; ++dy)
    for (int dx = 0; dx < kw; ++dx)
      acc += plane[dy * w + dx];
  out[(b * oh + p) * ow + q] = acc / (REAL)(kh * kw);
}

__kernel void avg_pool_backward(const int planes, const int h, const int w, const int oh,
                                const int ow, const int kh, const int kw, const int sh,
                                const int sw, __global const REAL* g, __global REAL* gx) {
  const int j = get_global_id(0), i = get_global_id(1), b = get_global_id(2);
  if (j >= w || i >= h || b >= planes) return;
  __global const REAL* gplane = g + b * oh * ow;
  const int2 rows = windows_containing(i, kh, sh, oh);
  const int2 cols = windows_containing(j, kw, sw, ow);
  REAL acc = 0;
  for (int p = rows.x; p <= rows.y; ++p)
    for (int q = cols.x; q <= cols.y; ++q)
      acc += gplane[p * ow + q];
  gx[(b * h + i) * w + j] = acc / (REAL)(kh * kw);
}
