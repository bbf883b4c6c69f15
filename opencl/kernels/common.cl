// Prefix of every program. REAL is the working precision: float for work, double for the
// reference runs of the same kernels (the host passes -DREAL_IS_DOUBLE=0/1).
#if REAL_IS_DOUBLE
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#define REAL double
#define REAL2 double2
#define REAL4 double4
#define REAL_MAX DBL_MAX
#define REAL_EPS DBL_EPSILON
#else
#define REAL float
#define REAL2 float2
#define REAL4 float4
#define REAL_MAX FLT_MAX
#define REAL_EPS FLT_EPSILON
#endif

// Shapes and strides travel as int8 (up to 6 dimensions used; unused trailing entries are
// shape 1, stride 0). Row-major: the last dimension is fastest.
inline int offset_of(int index, const int8 shape, const int8 strides, const int ndim) {
  int off = 0;
  int rest = index;
  const int s[8] = {shape.s0, shape.s1, shape.s2, shape.s3, shape.s4, shape.s5, shape.s6, shape.s7};
  const int st[8] = {strides.s0, strides.s1, strides.s2, strides.s3,
                     strides.s4, strides.s5, strides.s6, strides.s7};
  for (int d = ndim - 1; d >= 0; --d) {
    const int c = rest % s[d];
    rest /= s[d];
    off += c * st[d];
  }
  return off;
}
