// Elementwise arithmetic with broadcasting, unary functions and their derivatives.
//
// The op code is a kernel argument, but the host also compiles one variant per op with
// -DBINARY_OP=k / -DUNARY_OP=k, which replaces the argument by a constant: the switch folds
// away and PoCL can vectorise the kernel across work items.
#ifdef BINARY_OP
#define BOP BINARY_OP
#else
#define BOP op
#endif
#ifdef UNARY_OP
#define UOP UNARY_OP
#else
#define UOP op
#endif

#include "elementwise_op_codes.h"

inline REAL binary_apply(const int op, const REAL a, const REAL b) {
  switch (op) {
  case OP_ADD: return a + b;
  case OP_SUB: return a - b;
  case OP_MUL: return a * b;
  case OP_DIV: return a / b;
  case OP_MAX: return fmax(a, b);
  case OP_MIN: return fmin(a, b);
  case OP_GE: return a >= b ? (REAL)1 : (REAL)0;
  default: return a <= b ? (REAL)1 : (REAL)0;
  }
}

// Same shapes: no index arithmetic.
__kernel void binary_same(const int n, const int op, __global const REAL* a,
                          __global const REAL* b, __global REAL* out) {
  const int i = get_global_id(0);
  if (i >= n) return;
  out[i] = binary_apply(BOP, a[i], b[i]);
}

// Broadcast collapsed on the host to at most three dimensions (n0, n1, n2), n2 fastest;
// strides 0 on broadcast dimensions. Two divisions per element instead of a loop over up to
// eight dimensions.
__kernel void binary_broadcast3(const int n, const int op, const int n1, const int n2,
                                __global const REAL* a, const int sa0, const int sa1,
                                const int sa2, __global const REAL* b, const int sb0,
                                const int sb1, const int sb2, __global REAL* out) {
  const int i = get_global_id(0);
  if (i >= n) return;
  const int i2 = i % n2, i01 = i / n2;
  const int i1 = i01 % n1, i0 = i01 / n1;
  out[i] = binary_apply(BOP, a[i0 * sa0 + i1 * sa1 + i2 * sa2], b[i0 * sb0 + i1 * sb1 + i2 * sb2]);
}

// The same over a 3-D range (i2, i1, i0) = global ids (0, 1, 2), for inner runs n2 long enough
// to fill the work-group's first dimension: no integer divisions (PoCL cannot vectorise them).
__kernel void binary_broadcast3_grid(const int op, const int n1, const int n2,
                                     __global const REAL* a, const int sa0, const int sa1,
                                     const int sa2, __global const REAL* b, const int sb0,
                                     const int sb1, const int sb2, __global REAL* out) {
  const int i2 = get_global_id(0), i1 = get_global_id(1), i0 = get_global_id(2);
  if (i2 >= n2) return; // only the first dimension is rounded up to the work-group size
  out[(i0 * n1 + i1) * n2 + i2] =
      binary_apply(BOP, a[i0 * sa0 + i1 * sa1 + i2 * sa2], b[i0 * sb0 + i1 * sb1 + i2 * sb2]);
}

// General broadcast: a and b are addressed through strides (0 on broadcast dimensions).
__kernel void binary_broadcast(const int n, const int op, const int ndim, const int8 shape,
                               __global const REAL* a, const int8 stride_a,
                               __global const REAL* b, const int8 stride_b,
                               __global REAL* out) {
  const int i = get_global_id(0);
  if (i >= n) return;
  out[i] = binary_apply(BOP, a[offset_of(i, shape, stride_a, ndim)],
                        b[offset_of(i, shape, stride_b, ndim)]);
}

// Sums `src` (shape src_shape) into `out` whose shape is src_shape with some dimensions
// reduced to 1 (those marked in `reduced`). Each work item owns one output element and
// loops over the reduced dimensions.
__kernel void sum_to_shape(const int n_out, const int ndim, const int8 out_shape,
                           const int8 src_strides, const int8 red_shape,
                           const int n_red, __global const REAL* src, __global REAL* out) {
  const int j = get_global_id(0);
  if (j >= n_out) return;
  const int base = offset_of(j, out_shape, src_strides, ndim);
  REAL acc = 0;
  for (int r = 0; r < n_red; ++r)
    acc += src[base + offset_of(r, red_shape, src_strides, ndim)];
  out[j] = acc;
}

// Every form is finite for |x| up to 1e30 (and beyond): no exp of a large positive number.
inline REAL stable_sigmoid(const REAL x) {
  if (x >= 0) return 1 / (1 + exp(-x));
  const REAL e = exp(x);
  return e / (1 + e);
}

// exp(x) - 1 for x <= 0. PoCL's expm1 is a slow scalar routine (10x exp: ELU cost 40x ReLU in
// the feature extractor), so float uses exp(x) - 1, which loses digits only near 0, and there a
// Taylor polynomial (|x| <= 1/2: truncation < 2e-10 relative, below float rounding). Double
// (reference runs and gradient checks) keeps the library expm1.
inline REAL expm1_nonpositive(const REAL x) {
#if REAL_IS_DOUBLE
  return expm1(x);
#else
  if (x < -0.5f) return exp(x) - 1;
  float p = 1.0f / 362880;  // 1/9!
  p = fma(p, x, 1.0f / 40320); // 1/8!
  p = fma(p, x, 1.0f / 5040);
  p = fma(p, x, 1.0f / 720);
  p = fma(p, x, 1.0f / 120);
  p = fma(p, x, 1.0f / 24);
  p = fma(p, x, 1.0f / 6);
  p = fma(p, x, 0.5f);
  p = fma(p, x, 1.0f);
  return p * x;
#endif
}

inline REAL unary_apply(const int op, const REAL x, const REAL p0, const REAL p1) {
  switch (op) {
  case U_NEG: return -x;
  case U_EXP: return exp(x);
  case U_LOG: return log(x);
  case U_SQRT: return sqrt(x);
  case U_SQUARE: return x * x;
  case U_ABS: return fabs(x);
  case U_RELU: return x > 0 ? x : (REAL)0;
  case U_ELU: return x > 0 ? x : p0 * expm1_nonpositive(x);
  case U_SIGMOID: return stable_sigmoid(x);
  case U_TANH: return tanh(x);
  case U_SOFTPLUS: return fmax(x, (REAL)0) + log1p(exp(-fabs(x)));
  case U_ADD_SCALAR: return x + p0;
  case U_MUL_SCALAR: return x * p0;
  case U_CLAMP: return fmin(fmax(x, p0), p1);
  default: return pow(x, p0);
  }
}

// d y / d x, given x and y = f(x).
inline REAL unary_derivative(const int op, const REAL x, const REAL y, const REAL p0,
                             const REAL p1) {
  switch (op) {
  case U_NEG: return -1;
  case U_EXP: return y;
  case U_LOG: return 1 / x;
  case U_SQRT: return (REAL)0.5 / y;
  case U_SQUARE: return 2 * x;
  case U_ABS: return x > 0 ? (REAL)1 : (x < 0 ? (REAL)-1 : (REAL)0);
  case U_RELU: return x > 0 ? (REAL)1 : (REAL)0;
  case U_ELU: return x > 0 ? (REAL)1 : y + p0;
  case U_SIGMOID: return y * (1 - y);
  case U_TANH: return 1 - y * y;
  case U_SOFTPLUS: return stable_sigmoid(x);
  case U_ADD_SCALAR: return 1;
  case U_MUL_SCALAR: return p0;
  case U_CLAMP: return (x >= p0 && x <= p1) ? (REAL)1 : (REAL)0;
  default: return p0 * pow(x, p0 - 1);
  }
}

__kernel void unary_forward(const int n, const int op, const REAL p0, const REAL p1,
                            __global const REAL* x, __global REAL* y) {
  const int i = get_global_id(0);
  if (i >= n) return;
  y[i] = unary_apply(UOP, x[i], p0, p1);
}

__kernel void unary_backward(const int n, const int op, const REAL p0, const REAL p1,
                             __global const REAL* x, __global const REAL* y,
                             __global const REAL* gy, __global REAL* gx) {
  const int i = get_global_id(0);
  if (i >= n) return;
  gx[i] = gy[i] * unary_derivative(UOP, x[i], y[i], p0, p1);
}

__kernel void fill(const int n, const REAL value, __global REAL* out) {
  const int i = get_global_id(0);
  if (i >= n) return;
  out[i] = value;
}

__kernel void arange(const int n, const REAL start, const REAL step, __global REAL* out) {
  const int i = get_global_id(0);
  if (i >= n) return;
  out[i] = start + step * (REAL)i;
}

// Counter-based generator: element i depends only on (seed, i), so results are identical
// on every device and launch configuration. splitmix64 finaliser on seed ^ counter.
inline ulong mix64(ulong z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9UL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebUL;
  return z ^ (z >> 31);
}

// Uniform in (0, 1): 53 (double) or 24 (float) random bits, offset by half a step so that
// log() of it is finite.
inline REAL uniform01(const ulong seed, const ulong counter) {
  const ulong bits = mix64(seed * 0x9e3779b97f4a7c15UL + counter + 1);
#if REAL_IS_DOUBLE
  return ((double)(bits >> 11) + 0.5) * (1.0 / 9007199254740992.0);
#else
  return ((float)(uint)(bits >> 40) + 0.5f) * (1.0f / 16777216.0f);
#endif
}

__kernel void random_uniform(const int n, const ulong seed, const REAL low, const REAL high,
                             __global REAL* out) {
  const int i = get_global_id(0);
  if (i >= n) return;
  out[i] = low + (high - low) * uniform01(seed, (ulong)i);
}

// Box-Muller with two counters per element (2i, 2i+1).
__kernel void random_normal(const int n, const ulong seed, const REAL mean, const REAL stddev,
                            __global REAL* out) {
  const int i = get_global_id(0);
  if (i >= n) return;
  const REAL u1 = uniform01(seed, 2 * (ulong)i);
  const REAL u2 = uniform01(seed, 2 * (ulong)i + 1);
  const REAL r = sqrt(-2 * log(u1));
  out[i] = mean + stddev * r * cos((REAL)6.283185307179586 * u2);
}

// Converts between precisions (the program is built for the destination type REAL).
__kernel void convert_from_f32(const int n, __global const float* x, __global REAL* y) {
  const int i = get_global_id(0);
  if (i >= n) return;
  y[i] = (REAL)x[i];
}
#if REAL_IS_DOUBLE
__kernel void convert_to_f32(const int n, __global const double* x, __global float* y) {
  const int i = get_global_id(0);
  if (i >= n) return;
  y[i] = (float)x[i];
}
#endif
