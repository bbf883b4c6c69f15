// Shape ops: strided copies (slice, concat, permute, zero padding and their gradients), the
// padding gather, and index selection.

// Reads an int8 component by runtime index (OpenCL C has no dynamic vector indexing).
inline int comp8(const int8 v, const int d) {
  const int a[8] = {v.s0, v.s1, v.s2, v.s3, v.s4, v.s5, v.s6, v.s7};
  return a[d];
}

// dst view <- src view over up to three dimensions (i fastest), each addressed by its own
// global id and strides: no integer division per element, which on PoCL would stop the
// work-item loop from being vectorised (measured: 1.2 vs 9 GB/s). The host merges dimensions
// that are contiguous in both views and loops over any further leading dimensions.
__kernel void strided_copy(const int n0, const int n1, const int n2, __global const REAL* src,
                           const int src_base, const int s0, const int s1, const int s2,
                           __global REAL* dst, const int dst_base, const int d0, const int d1,
                           const int d2) {
  const int i = get_global_id(0), j = get_global_id(1), k = get_global_id(2);
  if (i >= n0 || j >= n1 || k >= n2) return;
  dst[dst_base + i * d0 + j * d1 + k * d2] = src[src_base + i * s0 + j * s1 + k * s2];
}

// Replicate padding as a gather: every output element reads the input element at its
// coordinate minus `before`, clamped into the input.
__kernel void pad_replicate_forward(const int n, const int ndim, const int8 out_shape,
                                    const int8 in_shape, const int8 before,
                                    __global const REAL* x, __global REAL* out) {
  const int i = get_global_id(0);
  if (i >= n) return;
  int rest = i, src = 0, stride = 1;
  for (int d = ndim - 1; d >= 0; --d) {
    const int os = comp8(out_shape, d), is = comp8(in_shape, d);
    const int c = clamp(rest % os - comp8(before, d), 0, is - 1);
    rest /= os;
    src += c * stride;
    stride *= is;
  }
  out[i] = x[src];
}

// Gradient of replicate padding: input element i collects every output element that read it,
// a box whose extent along each axis is 1, or reaches the padded edge for border elements.
__kernel void pad_replicate_backward(const int n, const int ndim, const int8 out_shape,
                                     const int8 in_shape, const int8 before,
                                     __global const REAL* g, __global REAL* gx) {
  const int i = get_global_id(0);
  if (i >= n) return;
  int lo[8], len[8], ostride[8];
  int rest = i, stride = 1, box = 1;
  for (int d = ndim - 1; d >= 0; --d) {
    const int os = comp8(out_shape, d), is = comp8(in_shape, d);
    const int c = rest % is;
    rest /= is;
    const int first = c == 0 ? 0 : c + comp8(before, d);
    const int last = c == is - 1 ? os - 1 : c + comp8(before, d);
    lo[d] = first;
    len[d] = last - first + 1;
    ostride[d] = stride;
    stride *= os;
    box *= len[d];
  }
  REAL acc = 0;
  for (int r = 0; r < box; ++r) {
    int rr = r, off = 0;
    for (int d = ndim - 1; d >= 0; --d) {
      off += (lo[d] + rr % len[d]) * ostride[d];
      rr /= len[d];
    }
    acc += g[off];
  }
  gx[i] = acc;
}

// x viewed as [outer, n, inner]; out[o, j, k] = x[o, idx[j], k].
__kernel void index_select_forward(const int outer, const int n, const int inner, const int count,
                                   __global const int* idx, __global const REAL* x,
                                   __global REAL* out) {
  const int i = get_global_id(0);
  if (i >= outer * count * inner) return;
  const int k = i % inner;
  const int j = (i / inner) % count;
  const int o = i / (inner * count);
  out[i] = x[(o * n + idx[j]) * inner + k];
}

// Gradient as a gather (indices may repeat): gx[o, m, k] = sum over j with idx[j] == m.
__kernel void index_select_backward(const int outer, const int n, const int inner,
                                    const int count, __global const int* idx,
                                    __global const REAL* g, __global REAL* gx) {
  const int i = get_global_id(0);
  if (i >= outer * n * inner) return;
  const int k = i % inner;
  const int m = (i / inner) % n;
  const int o = i / (inner * n);
  REAL acc = 0;
  for (int j = 0; j < count; ++j)
    if (idx[j] == m) acc += g[(o * count + j) * inner + k];
  gx[i] = acc;
}
