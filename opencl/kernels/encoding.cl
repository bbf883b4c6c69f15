// Sinusoidal positional code: out[i, c] = sin(theta) for even c, cos(theta) for odd c, with
// theta = pos[i] * 10000^(-2 floor(c / 2) / D).

// freq[c] = 10000^(-2 floor(c / 2) / D) comes from the host, computed in double: an
// in-kernel float pow/exp would put a few 1e-7 of relative error into theta, i.e. ~1e-5 at the
// positions SIMPLI uses (up to 40).

// Items over (channel, position).
__kernel void positional_encoding_forward(const int n, const int d, __global const REAL* freq,
                                          __global const REAL* pos, __global REAL* out) {
  const int c = get_global_id(0), i = get_global_id(1);
  if (c >= d || i >= n) return;
  const REAL theta = pos[i] * freq[c];
  out[i * d + c] = (c % 2 == 0) ? sin(theta) : cos(theta);
}

// d out[i, c] / d pos[i] = f sin'(theta) or f cos'(theta); each item sums one position's row.
__kernel void positional_encoding_backward(const int n, const int d, __global const REAL* freq,
                                           __global const REAL* pos, __global const REAL* g,
                                           __global REAL* gpos) {
  const int i = get_global_id(0);
  if (i >= n) return;
  REAL acc = 0;
  for (int c = 0; c < d; ++c) {
    const REAL f = freq[c];
    const REAL theta = pos[i] * f;
    acc += g[i * d + c] * ((c % 2 == 0) ? f * cos(theta) : -f * sin(theta));
  }
  gpos[i] = acc;
}
