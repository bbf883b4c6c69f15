// GEMMs with one small output dimension ("skinny"): C[m, n] = alpha op(A)[m, k] op(B)[k, n] +
// beta C, row-major, batched through global dimension 1 with element strides. CLBlast pads
// and tiles such shapes for square-ish blocks (64 x 128 here) and wastes most of its work on
// them; here one work item owns a whole column (few rows, SKINNY_M) or a whole row (few
// columns, SKINNY_N) of C and keeps it in registers while it walks k.
//
// Compile-time parameters (the host builds one variant per combination it meets): SKINNY, the
// small dimension itself (1..32), so the accumulators are SKINNY registers in fully unrolled
// loops; TA and TB, whether A and B are used transposed: A(i, p) = a[i lda + p] (or
// a[p lda + i] with TA); B(p, j) = b[p ldb + j] (or b[j ldb + p] with TB). C is never read
// when beta == 0, so it may hold anything (NaN poison included). The ta / tb arguments are
// unused (kept so both kernels share one argument list).

#ifndef SKINNY
#define SKINNY 16
#endif
#ifndef TA
#define TA 0
#endif
#ifndef TB
#define TB 0
#endif

#if TA
#define SKINNY_A(a, lda, i, p) (a)[(p) * (lda) + (i)]
#else
#define SKINNY_A(a, lda, i, p) (a)[(i) * (lda) + (p)]
#endif
#if TB
#define SKINNY_B(b, ldb, p, j) (b)[(j) * (ldb) + (p)]
#else
#define SKINNY_B(b, ldb, p, j) (b)[(p) * (ldb) + (j)]
#endif

// Column j of C (SKINNY rows), accumulated in registers along k.
inline void skinny_column(const int j, const int k, const REAL alpha, __global const REAL* ab,
                          const int lda, __global const REAL* bb, const int ldb, const REAL beta,
                          __global REAL* cb, const int ldc) {
  REAL acc[SKINNY];
  for (int i = 0; i < SKINNY; ++i)
    acc[i] = 0;
  for (int p = 0; p < k; ++p) {
    const REAL bv = SKINNY_B(bb, ldb, p, j);
#pragma unroll
    for (int i = 0; i < SKINNY; ++i)
      acc[i] += SKINNY_A(ab, lda, i, p) * bv;
  }
  for (int i = 0; i < SKINNY; ++i) {
    __global REAL* ci = cb + i * ldc + j;
    *ci = beta != 0 ? alpha * acc[i] + beta * *ci : alpha * acc[i];
  }
}

// Few rows (m == SKINNY): one item per column j of C.
__kernel void gemm_skinny_m(const int m, const int n, const int k, const REAL alpha,
                            __global const REAL* a, const int a_off, const int lda, const int ta,
                            const int stride_a, __global const REAL* b, const int b_off,
                            const int ldb, const int tb, const int stride_b, const REAL beta,
                            __global REAL* c, const int c_off, const int ldc,
                            const int stride_c) {
  const int j = get_global_id(0), batch = get_global_id(1);
  if (j >= n) return;
  __global const REAL* ab = a + a_off + batch * stride_a;
  __global const REAL* bb = b + b_off + batch * stride_b;
  __global REAL* cb = c + c_off + batch * stride_c;
  skinny_column(j, k, alpha, ab, lda, bb, ldb, beta, cb, ldc);
}

// Few columns (n == SKINNY): one item per row i of C.
__kernel void gemm_skinny_n(const int m, const int n, const int k, const REAL alpha,
                            __global const REAL* a, const int a_off, const int lda, const int ta,
                            const int stride_a, __global const REAL* b, const int b_off,
                            const int ldb, const int tb, const int stride_b, const REAL beta,
                            __global REAL* c, const int c_off, const int ldc,
                            const int stride_c) {
  const int i = get_global_id(0), batch = get_global_id(1);
  if (i >= m) return;
  __global const REAL* ab = a + a_off + batch * stride_a;
  __global const REAL* bb = b + b_off + batch * stride_b;
  __global REAL* cb = c + c_off + batch * stride_c + i * ldc;
  REAL acc[SKINNY];
  for (int j = 0; j < SKINNY; ++j)
    acc[j] = 0;
  for (int p = 0; p < k; ++p) {
    const REAL av = SKINNY_A(ab, lda, i, p);
#pragma unroll
    for (int j = 0; j < SKINNY; ++j)
      acc[j] += av * SKINNY_B(bb, ldb, p, j);
  }
  for (int j = 0; j < SKINNY; ++j)
    cb[j] = beta != 0 ? alpha * acc[j] + beta * cb[j] : alpha * acc[j];
}

// Few rows with B not transposed (the convolutions' weights x columns): one item per 8
// consecutive columns, accumulated as REAL8 vectors, because PoCL vectorises only innermost
// loops and the per-item k loop of gemm_skinny_m hides the work-item loop from it. The last
// partial block of columns takes the scalar path.
#if !TB
__kernel void gemm_skinny_m8(const int m, const int n, const int k, const REAL alpha,
                             __global const REAL* a, const int a_off, const int lda, const int ta,
                             const int stride_a, __global const REAL* b, const int b_off,
                             const int ldb, const int tb, const int stride_b, const REAL beta,
                             __global REAL* c, const int c_off, const int ldc,
                             const int stride_c) {
  const int j0 = get_global_id(0) * 8, batch = get_global_id(1);
  if (j0 >= n) return;
  __global const REAL* ab = a + a_off + batch * stride_a;
  __global const REAL* bb = b + b_off + batch * stride_b;
  __global REAL* cb = c + c_off + batch * stride_c;
  if (j0 + 8 > n) { // tail: scalar
    for (int j = j0; j < n; ++j)
      skinny_column(j, k, alpha, ab, lda, bb, ldb, beta, cb, ldc);
    return;
  }
#if REAL_IS_DOUBLE
  typedef double8 REAL8;
#else
  typedef float8 REAL8;
#endif
  REAL8 acc[SKINNY];
#pragma unroll
  for (int i = 0; i < SKINNY; ++i)
    acc[i] = (REAL8)(0);
  for (int p = 0; p < k; ++p) {
    const REAL8 bv = vload8(0, bb + p * ldb + j0);
#pragma unroll
    for (int i = 0; i < SKINNY; ++i)
      acc[i] += SKINNY_A(ab, lda, i, p) * bv;
  }
#pragma unroll
  for (int i = 0; i < SKINNY; ++i) {
    __global REAL* ci = cb + i * ldc + j0;
    REAL8 r = alpha * acc[i];
    if (beta != 0) r += beta * vload8(0, ci);
    vstore8(r, 0, ci);
  }
}
#endif

// Few columns with A as is and B transposed (linear layers: x [m, k] times W^T): both operands
// run along k, so one item per row i of C takes dot products in 8-lane vectors along k.
#if !TA && TB
__kernel void gemm_skinny_n8(const int m, const int n, const int k, const REAL alpha,
                             __global const REAL* a, const int a_off, const int lda, const int ta,
                             const int stride_a, __global const REAL* b, const int b_off,
                             const int ldb, const int tb, const int stride_b, const REAL beta,
                             __global REAL* c, const int c_off, const int ldc,
                             const int stride_c) {
  const int i = get_global_id(0), batch = get_global_id(1);
  if (i >= m) return;
#if REAL_IS_DOUBLE
  typedef double8 REAL8;
#else
  typedef float8 REAL8;
#endif
  __global const REAL* ai = a + a_off + batch * stride_a + i * lda;
  __global const REAL* bb = b + b_off + batch * stride_b;
  __global REAL* ci = c + c_off + batch * stride_c + i * ldc;
  REAL8 acc[SKINNY];
  REAL tail[SKINNY];
#pragma unroll
  for (int j = 0; j < SKINNY; ++j) {
    acc[j] = (REAL8)(0);
    tail[j] = 0;
  }
  int p = 0;
  for (; p + 8 <= k; p += 8) {
    const REAL8 av = vload8(0, ai + p);
#pragma unroll
    for (int j = 0; j < SKINNY; ++j)
      acc[j] += av * vload8(0, bb + j * ldb + p);
  }
  for (; p < k; ++p) {
    const REAL av = ai[p];
#pragma unroll
    for (int j = 0; j < SKINNY; ++j)
      tail[j] += av * bb[j * ldb + p];
  }
#pragma unroll
  for (int j = 0; j < SKINNY; ++j) {
    const REAL8 v = acc[j];
    const REAL sum = ((v.s0 + v.s1) + (v.s2 + v.s3)) + ((v.s4 + v.s5) + (v.s6 + v.s7)) + tail[j];
    ci[j] = beta != 0 ? alpha * sum + beta * ci[j] : alpha * sum;
  }
}
#endif
