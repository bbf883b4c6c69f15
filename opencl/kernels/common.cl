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

// ---- atomic add of a REAL -------------------------------------------------------------------
// OpenCL 1.2 has no floating-point atomics: compare-and-swap on the bit pattern. The double
// version needs cl_khr_int64_base_atomics; on a device without it only kernels that call
// atomic_add_real fail to build (with the program's name in the error).
#if REAL_IS_DOUBLE
#ifdef cl_khr_int64_base_atomics
#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable
inline void atomic_add_real(__global REAL* p, const REAL v) {
  volatile __global long* bits = (volatile __global long*)p;
  union {
    long i;
    double f;
  } expected, desired;
  long current = *bits;
  do {
    expected.i = current;
    desired.f = expected.f + v;
    current = atom_cmpxchg(bits, expected.i, desired.i);
  } while (current != expected.i);
}
#endif
#else
inline void atomic_add_real(__global REAL* p, const REAL v) {
  volatile __global int* bits = (volatile __global int*)p;
  union {
    int i;
    float f;
  } expected, desired;
  int current = *bits;
  do {
    expected.i = current;
    desired.f = expected.f + v;
    current = atomic_cmpxchg(bits, expected.i, desired.i);
  } while (current != expected.i);
}
#endif

// ---- bilinear taps with grid_sample semantics -----------------------------------------------
// The four taps of one sample point (normalised coordinates gx, gy in [-1, 1]; align_corners =
// False: -1 and +1 are the outer edges of the border pixels; zero padding) in an h x w plane.
// Offsets are clamped into the plane so every read is in bounds; taps outside have weight 0
// and their values are replaced by 0 (so a non-finite value at the clamped position cannot
// leak in). Computed once per sample point and reused for every channel.
typedef struct {
  int o00, o01, o10, o11; // top-left, top-right, bottom-left, bottom-right offsets in a plane
  int valid;              // bit 0..3: tap 00, 01, 10, 11 inside the image
  REAL tx, ty;            // fractions
  REAL w00, w01, w10, w11;
} Taps;

inline void make_taps(const REAL gx, const REAL gy, const int h, const int w, Taps* t) {
  const REAL sx = ((gx + 1) * w - 1) / 2;
  const REAL sy = ((gy + 1) * h - 1) / 2;
  t->valid = 0;
  t->o00 = t->o01 = t->o10 = t->o11 = 0;
  t->tx = t->ty = 0;
  t->w00 = t->w01 = t->w10 = t->w11 = 0;
  // Far outside (or NaN): no tap reads anything; this also keeps the int conversion in range.
  if (!(sx > -2 && sx < w + 1 && sy > -2 && sy < h + 1)) return;
  const REAL fx = floor(sx), fy = floor(sy);
  const int x0 = (int)fx, y0 = (int)fy;
  const REAL tx = sx - fx, ty = sy - fy;
  const bool vx0 = x0 >= 0 && x0 < w, vx1 = x0 + 1 >= 0 && x0 + 1 < w;
  const bool vy0 = y0 >= 0 && y0 < h, vy1 = y0 + 1 >= 0 && y0 + 1 < h;
  const int cx0 = clamp(x0, 0, w - 1), cx1 = clamp(x0 + 1, 0, w - 1);
  const int cy0 = clamp(y0, 0, h - 1) * w, cy1 = clamp(y0 + 1, 0, h - 1) * w;
  t->valid = (vy0 && vx0 ? 1 : 0) | (vy0 && vx1 ? 2 : 0) | (vy1 && vx0 ? 4 : 0) |
             (vy1 && vx1 ? 8 : 0);
  t->tx = tx;
  t->ty = ty;
  t->o00 = cy0 + cx0;
  t->o01 = cy0 + cx1;
  t->o10 = cy1 + cx0;
  t->o11 = cy1 + cx1;
  t->w00 = (t->valid & 1) ? (1 - ty) * (1 - tx) : 0;
  t->w01 = (t->valid & 2) ? (1 - ty) * tx : 0;
  t->w10 = (t->valid & 4) ? ty * (1 - tx) : 0;
  t->w11 = (t->valid & 8) ? ty * tx : 0;
}

inline REAL gather(__global const REAL* plane, const Taps* t) {
  const REAL i00 = (t->valid & 1) ? plane[t->o00] : 0;
  const REAL i01 = (t->valid & 2) ? plane[t->o01] : 0;
  const REAL i10 = (t->valid & 4) ? plane[t->o10] : 0;
  const REAL i11 = (t->valid & 8) ? plane[t->o11] : 0;
  return t->w00 * i00 + t->w01 * i01 + t->w10 * i10 + t->w11 * i11;
}

// The gathered value and its derivatives with respect to the plane's pixel coordinates.
inline REAL gather_grad(__global const REAL* plane, const Taps* t, REAL* dsx, REAL* dsy) {
  const REAL i00 = (t->valid & 1) ? plane[t->o00] : 0;
  const REAL i01 = (t->valid & 2) ? plane[t->o01] : 0;
  const REAL i10 = (t->valid & 4) ? plane[t->o10] : 0;
  const REAL i11 = (t->valid & 8) ? plane[t->o11] : 0;
  *dsx = (1 - t->ty) * (i01 - i00) + t->ty * (i11 - i10);
  *dsy = (1 - t->tx) * (i10 - i00) + t->tx * (i11 - i01);
  return t->w00 * i00 + t->w01 * i01 + t->w10 * i10 + t->w11 * i11;
}

// Adds g times each tap's weight to the plane (atomically: sample points share pixels).
inline void scatter(__global REAL* plane, const Taps* t, const REAL g) {
  if (g == 0) return;
  if (t->w00 != 0) atomic_add_real(plane + t->o00, t->w00 * g);
  if (t->w01 != 0) atomic_add_real(plane + t->o01, t->w01 * g);
  if (t->w10 != 0) atomic_add_real(plane + t->o10, t->w10 * g);
  if (t->w11 != 0) atomic_add_real(plane + t->o11, t->w11 * g);
}
