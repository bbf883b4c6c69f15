// The MLI blocks' view aggregation with self-attention (spec §4.7 steps 6-7), fused for
// inference. One work item handles one (surface, pixel): its V tokens
// t_v = [samples[v, s, :, p] | weights[v, s, 0, p]] stay in private memory through the
// projections, the softmax over views, the output projection and the LayerNorm, and only the
// four aggregates are written:
//   out[s, 0C + c] = sum_v w_v x_vc            out[s, 1C + c] = sum_v w_v (x_vc - mean_c)^2
//   out[s, 2C + c] = sum_v w_v y_vc            out[s, 3C + c] = sum_v w_v (y_vc - ymean_c)^2
// with y_v = LayerNorm(fc (sum_u softmax_u(scale q_v . k_u) v_u)), q, k, v = W_{q,k,v} t.
// The composed form (one permuted copy of the tokens in, GEMMs, a score pass, a copy out and
// six broadcast passes for the two mean/variance pairs) streams the V x S x C x h x w samples
// about a dozen times; this reads them once.
//
// The projections are folded on the host, which is exact up to rounding (associativity):
//   scale q_v . k_u = t_v^T (scale W_q^T W_k) t_u = t_v . (M t_u),   M = scale W_q^T W_k,
//   fc sum_u a_vu v_u = sum_u a_vu (fc W_v) t_u = sum_u a_vu z_u,     z_u = P t_u, P = fc W_v,
// so a work item does ~3 k instead of ~11 k flops at V = 8, C = 6, hidden = 16.
//
// Sizes are compile-time constants (VIEWS, CH = sample channels), so the private arrays are
// exact and the loops unroll.

#define TOK (CH + 1)

__kernel void view_attention_meanvar(const int S, const int hw, __global const REAL* samples,
                                     __global const REAL* weights, __global const REAL* score_map,
                                     __global const REAL* value_map,
                                     __global const REAL* ln_weight,
                                     __global const REAL* ln_bias, const REAL eps,
                                     __global REAL* out) {
  const int p = get_global_id(0), s = get_global_id(1);
  if (p >= hw || s >= S) return;
  REAL tok[VIEWS][TOK], mt[VIEWS][TOK], z[VIEWS][CH], y[VIEWS][CH], w[VIEWS];
  for (int v = 0; v < VIEWS; ++v) {
    __global const REAL* x = samples + ((v * S + s) * CH) * hw + p;
    for (int c = 0; c < CH; ++c)
      tok[v][c] = x[c * hw];
    w[v] = weights[(v * S + s) * hw + p];
    tok[v][CH] = w[v];
  }
  __global REAL* o = out + s * 4 * CH * hw + p;
  // Weighted mean and variance of the samples (two passes, like the composed form). Written
  // out here and for the attended tokens below: the measured form (a helper taking pointers
  // into the private arrays was not faster and may keep PoCL from keeping them in registers).
  for (int c = 0; c < CH; ++c) {
    REAL mean = 0, var = 0;
    for (int v = 0; v < VIEWS; ++v)
      mean += w[v] * tok[v][c];
    for (int v = 0; v < VIEWS; ++v) {
      const REAL d = tok[v][c] - mean;
      var += w[v] * d * d;
    }
    o[c * hw] = mean;
    o[(CH + c) * hw] = var;
  }
  for (int u = 0; u < VIEWS; ++u) {
    for (int i = 0; i < TOK; ++i) {
      REAL m = 0;
      for (int j = 0; j < TOK; ++j)
        m += score_map[i * TOK + j] * tok[u][j];
      mt[u][i] = m;
    }
    for (int c = 0; c < CH; ++c) {
      REAL zc = 0;
      for (int j = 0; j < TOK; ++j)
        zc += value_map[c * TOK + j] * tok[u][j];
      z[u][c] = zc;
    }
  }
  for (int v = 0; v < VIEWS; ++v) {
    // Softmax over the views with the maximum subtracted (large logits stay finite).
    REAL score[VIEWS], top = -INFINITY;
    for (int u = 0; u < VIEWS; ++u) {
      REAL d = 0;
      for (int i = 0; i < TOK; ++i)
        d += tok[v][i] * mt[u][i];
      score[u] = d;
      top = fmax(top, d);
    }
    REAL total = 0;
    for (int u = 0; u < VIEWS; ++u)
      total += (score[u] = exp(score[u] - top));
    REAL mu = 0;
    for (int c = 0; c < CH; ++c) {
      REAL yc = 0;
      for (int u = 0; u < VIEWS; ++u)
        yc += score[u] * z[u][c];
      y[v][c] = yc / total;
      mu += y[v][c];
    }
    // LayerNorm over the CH channels (biased variance).
    mu /= CH;
    REAL sigma2 = 0;
    for (int c = 0; c < CH; ++c)
      sigma2 += (y[v][c] - mu) * (y[v][c] - mu);
    const REAL inv = 1 / sqrt(sigma2 / CH + eps);
    for (int c = 0; c < CH; ++c)
      y[v][c] = (y[v][c] - mu) * inv * ln_weight[c] + ln_bias[c];
  }
  for (int c = 0; c < CH; ++c) {
    REAL mean = 0, var = 0;
    for (int v = 0; v < VIEWS; ++v)
      mean += w[v] * y[v][c];
    for (int v = 0; v < VIEWS; ++v) {
      const REAL d = y[v][c] - mean;
      var += w[v] * d * d;
    }
    o[(2 * CH + c) * hw] = mean;
    o[(3 * CH + c) * hw] = var;
  }
}
