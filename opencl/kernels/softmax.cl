// Softmax and log-sum-exp along one axis. The tensor is viewed as [outer, n, inner]; one work
// item owns one (outer, inner) slice and walks the axis. The maximum is subtracted before exp,
// so no exp argument is positive, and exp is evaluated once per element (it dominates the
// cost: the output holds exp(x - max) until it is scaled).
//
// Two layouts: *_rows for inner == 1 (contiguous slices: attention over keys, the hot case),
// using REAL4 vectors so PoCL's CPU code stays SIMD; *_strided for any inner.

// ---- contiguous rows (inner == 1) ---------------------------------------------------------

inline REAL row_max(__global const REAL* p, const int n) {
  const int nv = n / 4;
  REAL4 m4 = (REAL4)(-INFINITY);
  for (int v = 0; v < nv; ++v)
    m4 = fmax(m4, vload4(v, p));
  REAL m = fmax(fmax(m4.x, m4.y), fmax(m4.z, m4.w));
  for (int k = 4 * nv; k < n; ++k)
    m = fmax(m, p[k]);
  return m;
}

// q = exp(p - m) (q may be null: sum only); returns the sum.
inline REAL row_exp_sum(__global const REAL* p, __global REAL* q, const int n, const REAL m,
                        const int store) {
  const int nv = n / 4;
  REAL4 s4 = 0;
  for (int v = 0; v < nv; ++v) {
    const REAL4 e = exp(vload4(v, p) - m);
    if (store) vstore4(e, v, q);
    s4 += e;
  }
  REAL s = (s4.x + s4.y) + (s4.z + s4.w);
  for (int k = 4 * nv; k < n; ++k) {
    const REAL e = exp(p[k] - m);
    if (store) q[k] = e;
    s += e;
  }
  return s;
}

__kernel void softmax_rows_forward(const int rows, const int n, __global const REAL* x,
                                   __global REAL* y) {
  const int r = get_global_id(0);
  if (r >= rows) return;
  __global const REAL* p = x + (long)r * n;
  __global REAL* q = y + (long)r * n;
  const REAL m = row_max(p, n);
  const REAL inv = 1 / row_exp_sum(p, q, n, m, 1); // sum >= 1: the maximum gives exp(0)
  const int nv = n / 4;
  for (int v = 0; v < nv; ++v)
    vstore4(vload4(v, q) * inv, v, q);
  for (int k = 4 * nv; k < n; ++k)
    q[k] *= inv;
}

// dx = y (g - sum(g y)).
__kernel void softmax_rows_backward(const int rows, const int n, __global const REAL* y,
                                    __global const REAL* g, __global REAL* dx) {
  const int r = get_global_id(0);
  if (r >= rows) return;
  const long o = (long)r * n;
  const int nv = n / 4;
  REAL4 d4 = 0;
  for (int v = 0; v < nv; ++v)
    d4 += vload4(v, g + o) * vload4(v, y + o);
  REAL dot = (d4.x + d4.y) + (d4.z + d4.w);
  for (int k = 4 * nv; k < n; ++k)
    dot += g[o + k] * y[o + k];
  for (int v = 0; v < nv; ++v)
    vstore4(vload4(v, y + o) * (vload4(v, g + o) - dot), v, dx + o);
  for (int k = 4 * nv; k < n; ++k)
    dx[o + k] = y[o + k] * (g[o + k] - dot);
}

// out = max + log(sum exp(x - max)); an infinite maximum is the result itself (no inf - inf).
__kernel void lse_rows_forward(const int rows, const int n, __global const REAL* x,
                               __global REAL* out) {
  const int r = get_global_id(0);
  if (r >= rows) return;
  __global const REAL* p = x + (long)r * n;
  const REAL m = row_max(p, n);
  out[r] = isinf(m) ? m : m + log(row_exp_sum(p, 0, n, m, 0));
}

// dx = g exp(x - lse) (the softmax); 0 where lse is infinite.
__kernel void lse_rows_backward(const int rows, const int n, __global const REAL* x,
                                __global const REAL* lse, __global const REAL* g,
                                __global REAL* dx) {
  const int r = get_global_id(0);
  if (r >= rows) return;
  const long o = (long)r * n;
  const REAL l = lse[r], gr = g[r];
  const int nv = n / 4;
  if (isinf(l)) {
    for (int k = 0; k < n; ++k)
      dx[o + k] = 0;
    return;
  }
  for (int v = 0; v < nv; ++v)
    vstore4(gr * exp(vload4(v, x + o) - l), v, dx + o);
  for (int k = 4 * nv; k < n; ++k)
    dx[o + k] = gr * exp(x[o + k] - l);
}

// ---- any inner (strided slices) -----------------------------------------------------------

__kernel void softmax_strided_forward(const int outer, const int n, const int inner,
                                      __global const REAL* x, __global REAL* y) {
  const int i = get_global_id(0);
  if (i >= outer * inner) return;
  const long base = (long)(i / inner) * n * inner + i % inner;
  REAL m = -INFINITY;
  for (int k = 0; k < n; ++k)
    m = fmax(m, x[base + (long)k * inner]);
  REAL sum = 0;
  for (int k = 0; k < n; ++k) {
    const long o = base + (long)k * inner;
    const REAL e = exp(x[o] - m);
    y[o] = e;
    sum += e;
  }
  const REAL inv = 1 / sum;
  for (int k = 0; k < n; ++k)
    y[base + (long)k * inner] *= inv;
}

__kernel void softmax_strided_backward(const int outer, const int n, const int inner,
                                       __global const REAL* y, __global const REAL* g,
                                       __global REAL* dx) {
  const int i = get_global_id(0);
  if (i >= outer * inner) return;
  const long base = (long)(i / inner) * n * inner + i % inner;
  REAL dot = 0;
  for (int k = 0; k < n; ++k) {
    const long o = base + (long)k * inner;
    dot += g[o] * y[o];
  }
  for (int k = 0; k < n; ++k) {
    const long o = base + (long)k * inner;
    dx[o] = y[o] * (g[o] - dot);
  }
}

__kernel void lse_strided_forward(const int outer, const int n, const int inner,
                                  __global const REAL* x, __global REAL* out) {
  const int i = get_global_id(0);
  if (i >= outer * inner) return;
  __global const REAL* p = x + (long)(i / inner) * n * inner + i % inner;
  REAL m = -INFINITY;
  for (int k = 0; k < n; ++k)
    m = fmax(m, p[(long)k * inner]);
  if (isinf(m)) {
    out[i] = m;
    return;
  }
  REAL sum = 0;
  for (int k = 0; k < n; ++k)
    sum += exp(p[(long)k * inner] - m);
  out[i] = m + log(sum);
}

__kernel void lse_strided_backward(const int outer, const int n, const int inner,
                                   __global const REAL* x, __global const REAL* lse,
                                   __global const REAL* g, __global REAL* dx) {
  const int i = get_global_id(0);
  if (i >= outer * inner) return;
  const long base = (long)(i / inner) * n * inner + i % inner;
  const REAL l = lse[i], gi = g[i];
  for (int k = 0; k < n; ++k) {
    const long o = base + (long)k * inner;
    dx[o] = isinf(l) ? (REAL)0 : gi * exp(x[o] - l);
  }
}
