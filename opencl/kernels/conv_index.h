// Index arithmetic shared by the convolution programs (conv.cl, conv_direct.cl): which input
// sample an output tap reads, and which outputs read an input sample.

// Input coordinate read by output coordinate o at kernel offset k: zero padding reads nothing
// (returns -1) outside [0, n), replicate padding clamps to the edge.
inline int source_index(const int o, const int k, const int s, const int p, const int n,
                        const int replicate) {
  const int q = o * s - p + k;
  if (replicate)
    return clamp(q, 0, n - 1);
  return (q < 0 || q >= n) ? -1 : q;
}

inline int floor_div(const int a, const int b) {
  return a >= 0 ? a / b : -((-a + b - 1) / b);
}

// Output coordinates o in [0, n_out) whose tap at kernel offset k reads input coordinate h:
// o * s - p + k == h, or with replicate padding also every tap clamped onto an edge sample.
inline int2 taps_reading(const int h, const int k, const int s, const int p, const int n_in,
                         const int n_out, const int replicate) {
  const int far = 1 << 28;
  const int lo_q = (replicate && h == 0) ? -far : h;
  const int hi_q = (replicate && h == n_in - 1) ? far : h;
  const int lo = -floor_div(-(lo_q + p - k), s); // ceil((lo_q + p - k) / s)
  const int hi = floor_div(hi_q + p - k, s);
  return (int2)(max(lo, 0), min(hi, n_out - 1));
}
