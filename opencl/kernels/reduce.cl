// Reductions. A tensor reduced over one axis is viewed as [outer, n, inner]; each work item
// owns one (outer, inner) pair and walks the axis.

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

// Two-pass variance: mean, then the sum of squared deviations, divided by (n - ddof).
__kernel void reduce_var_axis(const int outer, const int n, const int inner, const int ddof,
                              __global const REAL* x, __global REAL* out) {
  const int i = get_global_id(0);
  if (i >= outer * inner) return;
  const int o = i / inner, in = i % inner;
  __global const REAL* p = x + (long)o * n * inner + in;
  REAL acc = 0;
  for (int k = 0; k < n; ++k)
    acc += p[(long)k * inner];
  const REAL m = acc / (REAL)n;
  REAL ss = 0;
  for (int k = 0; k < n; ++k) {
    const REAL d = p[(long)k * inner] - m;
    ss += d * d;
  }
  out[i] = ss / (REAL)(n - ddof);
}

// First stage of a full reduction: work item p sums elements p, p + parts, p + 2 parts...
__kernel void reduce_sum_strided(const int n, const int parts, __global const REAL* x,
                                 __global REAL* out) {
  const int p = get_global_id(0);
  if (p >= parts) return;
  REAL acc = 0;
  for (int k = p; k < n; k += parts)
    acc += x[k];
  out[p] = acc;
}
