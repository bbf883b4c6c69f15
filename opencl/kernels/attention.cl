// Scaled dot-product attention over many small independent sequences (fused: the scores and
// softmax weights are never stored). Sequence n has nq queries q[n, i, :] (or queries shared by
// all sequences, shared_q), nk keys k[n, j, :] of width d and values v[n, j, :] of width dv:
//   s_ij = scale q_i . k_j,  p_ij = softmax_j(s_ij),  out_i = sum_j p_ij v_j.
// One work item per (sequence, query) in the forward pass and the query-side backward, one per
// (sequence, key) in the key-side backward. Channels are accumulated in private tiles of
// ATT_TILE, so any d and dv work; scores are recomputed where needed (d is small here).

#define ATT_TILE 16
#define ATT_MAXK 32 // keys whose weights the forward pass keeps in registers (more: recomputed)

inline REAL att_score(__global const REAL* q, __global const REAL* k, const int d,
                      const REAL scale) {
  REAL s = 0;
  for (int c = 0; c < d; ++c)
    s += q[c] * k[c];
  return scale * s;
}

// stats[2 * row] = max_j s_ij, stats[2 * row + 1] = sum_j exp(s_ij - max): enough to recompute
// p_ij in the backward pass.
__kernel void attention_forward(const int N, const int nq, const int nk, const int d,
                                const int dv, const int shared_q, const REAL scale,
                                __global const REAL* q, __global const REAL* k,
                                __global const REAL* v, __global REAL* out,
                                __global REAL* stats) {
  const int row = get_global_id(0);
  if (row >= N * nq) return;
  const int n = row / nq, i = row % nq;
  __global const REAL* qi = q + (shared_q ? i : row) * d;
  __global const REAL* kn = k + n * nk * d;
  __global const REAL* vn = v + n * nk * dv;
  __global REAL* o = out + row * dv;
  if (nk <= ATT_MAXK) {
    // Few keys (the view attention: one per source view): every score and weight computed
    // once and kept in registers.
    REAL p[ATT_MAXK];
    REAL m = -INFINITY;
    for (int j = 0; j < nk; ++j) {
      p[j] = att_score(qi, kn + j * d, d, scale);
      m = fmax(m, p[j]);
    }
    REAL l = 0;
    for (int j = 0; j < nk; ++j) {
      p[j] = exp(p[j] - m);
      l += p[j];
    }
    stats[2 * row] = m;
    stats[2 * row + 1] = l;
    const REAL inv_l = 1 / l;
    for (int c0 = 0; c0 < dv; c0 += ATT_TILE) {
      const int nc = min(ATT_TILE, dv - c0);
      REAL acc[ATT_TILE];
      for (int c = 0; c < ATT_TILE; ++c)
        acc[c] = 0;
      for (int j = 0; j < nk; ++j) {
        __global const REAL* vj = vn + j * dv + c0;
        for (int c = 0; c < nc; ++c)
          acc[c] += p[j] * vj[c];
      }
      for (int c = 0; c < nc; ++c)
        o[c0 + c] = acc[c] * inv_l;
    }
    return;
  }
  // Online maximum and normaliser in one pass over the keys; the weights are recomputed below.
  REAL m = -INFINITY, l = 0;
  for (int j = 0; j < nk; ++j) {
    const REAL s = att_score(qi, kn + j * d, d, scale);
    if (s > m) {
      l = l * exp(m - s) + 1;
      m = s;
    } else {
      l += exp(s - m);
    }
  }
  stats[2 * row] = m;
  stats[2 * row + 1] = l;
  const REAL inv_l = 1 / l;
  for (int c0 = 0; c0 < dv; c0 += ATT_TILE) {
    const int nc = min(ATT_TILE, dv - c0);
    REAL acc[ATT_TILE];
    for (int c = 0; c < ATT_TILE; ++c)
      acc[c] = 0;
    for (int j = 0; j < nk; ++j) {
      const REAL p = exp(att_score(qi, kn + j * d, d, scale) - m) * inv_l;
      __global const REAL* vj = vn + j * dv + c0;
      for (int c = 0; c < nc; ++c)
        acc[c] += p * vj[c];
    }
    for (int c = 0; c < nc; ++c)
      o[c0 + c] = acc[c];
  }
}

inline REAL att_dot(__global const REAL* a, __global const REAL* b, const int n) {
  REAL s = 0;
  for (int c = 0; c < n; ++c)
    s += a[c] * b[c];
  return s;
}

// Query side: delta[row] = sum_j p_ij gp_ij with gp_ij = g_i . v_j, and (when want_q)
// gq[row, :] = scale sum_j p_ij (gp_ij - delta) k_j (per sequence even for shared queries;
// the host sums those over the sequences).
__kernel void attention_backward_query(const int N, const int nq, const int nk, const int d,
                                       const int dv, const int shared_q, const REAL scale,
                                       __global const REAL* q, __global const REAL* k,
                                       __global const REAL* v, __global const REAL* stats,
                                       __global const REAL* g, __global REAL* delta,
                                       const int want_q, __global REAL* gq) {
  const int row = get_global_id(0);
  if (row >= N * nq) return;
  const int n = row / nq, i = row % nq;
  __global const REAL* qi = q + (shared_q ? i : row) * d;
  __global const REAL* kn = k + n * nk * d;
  __global const REAL* vn = v + n * nk * dv;
  __global const REAL* gi = g + row * dv;
  const REAL m = stats[2 * row], inv_l = 1 / stats[2 * row + 1];
  REAL dl = 0;
  for (int j = 0; j < nk; ++j) {
    const REAL p = exp(att_score(qi, kn + j * d, d, scale) - m) * inv_l;
    dl += p * att_dot(gi, vn + j * dv, dv);
  }
  delta[row] = dl;
  if (!want_q) return;
  __global REAL* gqi = gq + row * d;
  for (int c0 = 0; c0 < d; c0 += ATT_TILE) {
    const int nc = min(ATT_TILE, d - c0);
    REAL acc[ATT_TILE];
    for (int c = 0; c < ATT_TILE; ++c)
      acc[c] = 0;
    for (int j = 0; j < nk; ++j) {
      __global const REAL* kj = kn + j * d;
      const REAL p = exp(att_score(qi, kj, d, scale) - m) * inv_l;
      const REAL gs = p * (att_dot(gi, vn + j * dv, dv) - dl);
      for (int c = 0; c < nc; ++c)
        acc[c] += gs * kj[c0 + c];
    }
    for (int c = 0; c < nc; ++c)
      gqi[c0 + c] = scale * acc[c];
  }
}

// Key side, one item per (sequence, key): gk[n, j, :] = scale sum_i gs_ij q_i and
// gv[n, j, :] = sum_i p_ij g_i.
__kernel void attention_backward_key(const int N, const int nq, const int nk, const int d,
                                     const int dv, const int shared_q, const REAL scale,
                                     __global const REAL* q, __global const REAL* k,
                                     __global const REAL* v, __global const REAL* stats,
                                     __global const REAL* g, __global const REAL* delta,
                                     const int want_k, __global REAL* gk, const int want_v,
                                     __global REAL* gv) {
  const int key = get_global_id(0);
  if (key >= N * nk) return;
  const int n = key / nk;
  __global const REAL* kj = k + key * d;
  __global const REAL* vj = v + key * dv;
  __global const REAL* qn = q + (shared_q ? 0 : n * nq * d);
  if (want_k) {
    for (int c0 = 0; c0 < d; c0 += ATT_TILE) {
      const int nc = min(ATT_TILE, d - c0);
      REAL acc[ATT_TILE];
      for (int c = 0; c < ATT_TILE; ++c)
        acc[c] = 0;
      for (int i = 0; i < nq; ++i) {
        const int row = n * nq + i;
        __global const REAL* qi = qn + i * d;
        const REAL p = exp(att_score(qi, kj, d, scale) - stats[2 * row]) / stats[2 * row + 1];
        const REAL gs = p * (att_dot(g + row * dv, vj, dv) - delta[row]);
        for (int c = 0; c < nc; ++c)
          acc[c] += gs * qi[c0 + c];
      }
      for (int c = 0; c < nc; ++c)
        gk[key * d + c0 + c] = scale * acc[c];
    }
  }
  if (want_v) {
    for (int c0 = 0; c0 < dv; c0 += ATT_TILE) {
      const int nc = min(ATT_TILE, dv - c0);
      REAL acc[ATT_TILE];
      for (int c = 0; c < ATT_TILE; ++c)
        acc[c] = 0;
      for (int i = 0; i < nq; ++i) {
        const int row = n * nq + i;
        const REAL p =
            exp(att_score(qn + i * d, kj, d, scale) - stats[2 * row]) / stats[2 * row + 1];
        __global const REAL* gi = g + row * dv + c0;
        for (int c = 0; c < nc; ++c)
          acc[c] += p * gi[c];
      }
      for (int c = 0; c < nc; ++c)
        gv[key * dv + c0 + c] = acc[c];
    }
  }
}
