// GEMMs whose output is small but whose inner dimension k is long (weight gradients: a sum
// over every pixel), split along k: each work item reduces one chunk of k into a partial
// result, and gemm_splitk_finish sums the chunks: C = alpha sum_chunks + beta C. CLBlast runs
// these shapes on a handful of work groups.
//
// Compile-time parameters: TA, TB (transposes, as gemm_skinny.cl), and per kernel the register
// block: SKINNY = m for gemm_dot_m, SM = m and SN = n for gemm_outer. KCHUNK = k per item.
// Partials: part[((batch * chunks + chunk) * m + i) * n + j].

#ifndef TA
#define TA 0
#endif
#ifndef TB
#define TB 0
#endif
#ifndef KCHUNK
#define KCHUNK 512
#endif

#if TA
#define SPLIT_A(a, lda, i, p) (a)[(p) * (lda) + (i)]
#else
#define SPLIT_A(a, lda, i, p) (a)[(i) * (lda) + (p)]
#endif
#if TB
#define SPLIT_B(b, ldb, p, j) (b)[(j) * (ldb) + (p)]
#else
#define SPLIT_B(b, ldb, p, j) (b)[(p) * (ldb) + (j)]
#endif

#if REAL_IS_DOUBLE
typedef double8 SPLIT_REAL8;
#else
typedef float8 SPLIT_REAL8;
#endif

// A not transposed and B transposed (both contiguous along k), m = SKINNY rows: one item per
// (column j, chunk); dot products in 8-lane vectors along k. Global (n, chunks, batch).
#if defined(SKINNY) && !TA && TB
__kernel void gemm_dot_m(const int m, const int n, const int k, __global const REAL* a,
                         const int a_off, const int lda, const int stride_a,
                         __global const REAL* b, const int b_off, const int ldb,
                         const int stride_b, const int chunks, __global REAL* part) {
  const int j = get_global_id(0), chunk = get_global_id(1), batch = get_global_id(2);
  if (j >= n || chunk >= chunks) return;
  __global const REAL* ab = a + a_off + batch * stride_a;
  __global const REAL* bj = b + b_off + batch * stride_b + j * ldb;
  const int p0 = chunk * KCHUNK, p1 = min(k, p0 + KCHUNK);
  SPLIT_REAL8 acc[SKINNY];
  REAL tail[SKINNY];
#pragma unroll
  for (int i = 0; i < SKINNY; ++i) {
    acc[i] = (SPLIT_REAL8)(0);
    tail[i] = 0;
  }
  int p = p0;
  for (; p + 8 <= p1; p += 8) {
    const SPLIT_REAL8 bv = vload8(0, bj + p);
#pragma unroll
    for (int i = 0; i < SKINNY; ++i)
      acc[i] += vload8(0, ab + i * lda + p) * bv;
  }
  for (; p < p1; ++p) {
    const REAL bv = bj[p];
#pragma unroll
    for (int i = 0; i < SKINNY; ++i)
      tail[i] += ab[i * lda + p] * bv;
  }
  __global REAL* out = part + (batch * chunks + chunk) * m * n + j;
#pragma unroll
  for (int i = 0; i < SKINNY; ++i) {
    const SPLIT_REAL8 v = acc[i];
    out[i * n] = ((v.s0 + v.s1) + (v.s2 + v.s3)) + ((v.s4 + v.s5) + (v.s6 + v.s7)) + tail[i];
  }
}
#endif

// Any transposes, m = SM and n = SN small: one item per (chunk, batch) accumulates the whole
// m x n block as a sum of outer products. Global (chunks, batch).
#if defined(SM) && defined(SN)
__kernel void gemm_outer(const int m, const int n, const int k, __global const REAL* a,
                         const int a_off, const int lda, const int stride_a,
                         __global const REAL* b, const int b_off, const int ldb,
                         const int stride_b, const int chunks, __global REAL* part) {
  const int chunk = get_global_id(0), batch = get_global_id(1);
  if (chunk >= chunks) return;
  __global const REAL* ab = a + a_off + batch * stride_a;
  __global const REAL* bb = b + b_off + batch * stride_b;
  const int p0 = chunk * KCHUNK, p1 = min(k, p0 + KCHUNK);
  REAL acc[SM * SN];
  for (int e = 0; e < SM * SN; ++e)
    acc[e] = 0;
  for (int p = p0; p < p1; ++p) {
    REAL bv[SN];
#pragma unroll
    for (int j = 0; j < SN; ++j)
      bv[j] = SPLIT_B(bb, ldb, p, j);
#pragma unroll
    for (int i = 0; i < SM; ++i) {
      const REAL av = SPLIT_A(ab, lda, i, p);
#pragma unroll
      for (int j = 0; j < SN; ++j)
        acc[i * SN + j] += av * bv[j];
    }
  }
  __global REAL* out = part + (batch * chunks + chunk) * m * n;
  for (int e = 0; e < SM * SN; ++e)
    out[e] = acc[e];
}
#endif

// C[i, j] = alpha sum_chunk part[...] + beta C[i, j]. Global (n, m, batch).
__kernel void gemm_splitk_finish(const int m, const int n, const int chunks, const REAL alpha,
                                 __global const REAL* part, const REAL beta, __global REAL* c,
                                 const int c_off, const int ldc, const int stride_c) {
  const int j = get_global_id(0), i = get_global_id(1), batch = get_global_id(2);
  if (j >= n || i >= m) return;
  __global const REAL* p = part + batch * chunks * m * n + i * n + j;
  REAL s = 0;
  for (int q = 0; q < chunks; ++q)
    s += p[q * m * n];
  __global REAL* ci = c + c_off + batch * stride_c + i * ldc + j;
  *ci = beta != 0 ? alpha * s + beta * *ci : alpha * s;
}
