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

// Weighted mean / variance over the views, backward, for one channel's values x[v] with
// weights w[v]: given the gradients of mean = sum_v w_v x_v (gmean) and of
// var = sum_v w_v (x_v - mean)^2 (gvar), adds d/dx to dx[v] and d/dw to dw[v]. The mean's
// dependence on x and w is followed too (sum_v w_v is not exactly 1).
inline void weighted_meanvar_backward(const REAL* x, const REAL* w, const REAL gmean,
                                      const REAL gvar, REAL* dx, REAL* dw) {
  REAL mean = 0;
  for (int v = 0; v < VIEWS; ++v)
    mean += w[v] * x[v];
  REAL spread = 0; // sum_v w_v (x_v - mean)
  for (int v = 0; v < VIEWS; ++v)
    spread += w[v] * (x[v] - mean);
  const REAL gm = gmean - 2 * gvar * spread; // the whole gradient reaching the mean
  for (int v = 0; v < VIEWS; ++v) {
    const REAL d = x[v] - mean;
    dx[v] += w[v] * (gm + 2 * gvar * d);
    dw[v] += x[v] * gm + d * d * gvar;
  }
}

// The backward of view_attention_meanvar, for training. Each work item takes `pixels` of one
// surface (p = chunk + j * chunks: neighbouring items read neighbouring pixels), recomputes
// their forward pass in private memory and writes the gradients of the samples and weights;
// the gradients of the folded maps and of the LayerNorm, summed over its pixels, go to its row
// of `partial` ([S * chunks, NPARAM], summed over the rows by the host side):
//   d score_map (TOK x TOK) | d value_map (CH x TOK) | d ln_weight (CH) | d ln_bias (CH).
// Per pixel (a = softmax rows, r = attended, n = normalised, y = n g + b):
//   dy from the attended mean / variance; dn = dy g; dr_v = inv_v (dn_v - mean_c(dn_v)
//   - n_v mean_c(dn_v n_v)); da_vu = dr_v . z_u; dz_u = sum_v a_vu dr_v;
//   ds_vu = a_vu (da_vu - sum_u' a_vu' da_vu'); score_vu = t_v^T M t_u gives
//   dt_v += M (sum_u ds_vu t_u), dt_u += M^T (sum_v ds_vu t_v), dM += sum_v t_v (sum_u ds_vu t_u)^T;
//   z_u = P t_u gives dt_u += P^T dz_u, dP += dz_u t_u^T.
#define NPARAM (TOK * TOK + CH * TOK + 2 * CH)

__kernel void view_attention_meanvar_backward(
    const int S, const int hw, const int chunks, const int pixels, __global const REAL* samples,
    __global const REAL* weights, __global const REAL* score_map, __global const REAL* value_map,
    __global const REAL* ln_weight, __global const REAL* ln_bias, const REAL eps,
    __global const REAL* grad_out, __global REAL* grad_samples, __global REAL* grad_weights,
    __global REAL* partial) {
  const int chunk = get_global_id(0), s = get_global_id(1);
  if (chunk >= chunks || s >= S) return;
  REAL dmap[TOK][TOK], dval[CH][TOK], dgain[CH], dshift[CH];
  for (int i = 0; i < TOK; ++i)
    for (int j = 0; j < TOK; ++j)
      dmap[i][j] = 0;
  for (int c = 0; c < CH; ++c) {
    for (int j = 0; j < TOK; ++j)
      dval[c][j] = 0;
    dgain[c] = dshift[c] = 0;
  }
  for (int p = chunk, step = 0; step < pixels && p < hw; ++step, p += chunks) {
    REAL tok[VIEWS][TOK], z[VIEWS][CH], a[VIEWS][VIEWS], n[VIEWS][CH], inv[VIEWS], w[VIEWS];
    for (int v = 0; v < VIEWS; ++v) {
      __global const REAL* x = samples + ((v * S + s) * CH) * hw + p;
      for (int c = 0; c < CH; ++c)
        tok[v][c] = x[c * hw];
      w[v] = tok[v][CH] = weights[(v * S + s) * hw + p];
    }
    // Forward, as view_attention_meanvar: z, the softmax rows a, the LayerNorm's n and inv.
    for (int u = 0; u < VIEWS; ++u)
      for (int c = 0; c < CH; ++c) {
        REAL zc = 0;
        for (int i = 0; i < TOK; ++i)
          zc += value_map[c * TOK + i] * tok[u][i];
        z[u][c] = zc;
      }
    for (int v = 0; v < VIEWS; ++v) {
      REAL mv[TOK], top = -INFINITY, total = 0;
      for (int j = 0; j < TOK; ++j) { // mv = M^T t_v, so score_vu = mv . t_u
        REAL m = 0;
        for (int i = 0; i < TOK; ++i)
          m += score_map[i * TOK + j] * tok[v][i];
        mv[j] = m;
      }
      for (int u = 0; u < VIEWS; ++u) {
        REAL d = 0;
        for (int j = 0; j < TOK; ++j)
          d += mv[j] * tok[u][j];
        a[v][u] = d;
        top = fmax(top, d);
      }
      for (int u = 0; u < VIEWS; ++u)
        total += (a[v][u] = exp(a[v][u] - top));
      REAL mu = 0;
      for (int c = 0; c < CH; ++c) {
        REAL rc = 0;
        for (int u = 0; u < VIEWS; ++u)
          rc += a[v][u] * z[u][c];
        n[v][c] = rc / total;
        mu += n[v][c];
      }
      for (int u = 0; u < VIEWS; ++u)
        a[v][u] /= total;
      mu /= CH;
      REAL sigma2 = 0;
      for (int c = 0; c < CH; ++c)
        sigma2 += (n[v][c] - mu) * (n[v][c] - mu);
      inv[v] = 1 / sqrt(sigma2 / CH + eps);
      for (int c = 0; c < CH; ++c)
        n[v][c] = (n[v][c] - mu) * inv[v];
    }
    // Both weighted mean / variance pairs: dt (the samples) and dn (the attended tokens).
    __global const REAL* g = grad_out + s * 4 * CH * hw + p;
    REAL dt[VIEWS][TOK], dn[VIEWS][CH], dw[VIEWS];
    for (int v = 0; v < VIEWS; ++v)
      dw[v] = 0;
    for (int c = 0; c < CH; ++c) {
      REAL xc[VIEWS], yc[VIEWS], dx[VIEWS], dy[VIEWS];
      for (int v = 0; v < VIEWS; ++v) {
        xc[v] = tok[v][c];
        yc[v] = n[v][c] * ln_weight[c] + ln_bias[c];
        dx[v] = dy[v] = 0;
      }
      weighted_meanvar_backward(xc, w, g[c * hw], g[(CH + c) * hw], dx, dw);
      weighted_meanvar_backward(yc, w, g[(2 * CH + c) * hw], g[(3 * CH + c) * hw], dy, dw);
      for (int v = 0; v < VIEWS; ++v) {
        dt[v][c] = dx[v];
        dgain[c] += dy[v] * n[v][c];
        dshift[c] += dy[v];
        dn[v][c] = dy[v] * ln_weight[c];
      }
    }
    for (int v = 0; v < VIEWS; ++v)
      dt[v][CH] = dw[v];
    // LayerNorm, then the attention-weighted sum: dr (kept in dn), dz, the score gradients ds.
    REAL dz[VIEWS][CH], q[VIEWS][TOK];
    for (int u = 0; u < VIEWS; ++u)
      for (int c = 0; c < CH; ++c)
        dz[u][c] = 0;
    for (int v = 0; v < VIEWS; ++v) {
      REAL mdn = 0, mdnn = 0;
      for (int c = 0; c < CH; ++c) {
        mdn += dn[v][c];
        mdnn += dn[v][c] * n[v][c];
      }
      mdn /= CH;
      mdnn /= CH;
      for (int c = 0; c < CH; ++c)
        dn[v][c] = inv[v] * (dn[v][c] - mdn - n[v][c] * mdnn);
      REAL da[VIEWS], centre = 0;
      for (int u = 0; u < VIEWS; ++u) {
        REAL d = 0;
        for (int c = 0; c < CH; ++c) {
          d += dn[v][c] * z[u][c];
          dz[u][c] += a[v][u] * dn[v][c];
        }
        da[u] = d;
        centre += a[v][u] * d;
      }
      for (int j = 0; j < TOK; ++j)
        q[v][j] = 0;
      for (int u = 0; u < VIEWS; ++u) {
        const REAL ds = a[v][u] * (da[u] - centre);
        a[v][u] = ds; // the softmax row is not needed again: keep ds_vu in its place
        for (int j = 0; j < TOK; ++j)
          q[v][j] += ds * tok[u][j];
      }
    }
    for (int v = 0; v < VIEWS; ++v) {
      REAL kq[TOK]; // sum_u ds_uv t_u: the key side of view v
      for (int i = 0; i < TOK; ++i)
        kq[i] = 0;
      for (int u = 0; u < VIEWS; ++u)
        for (int i = 0; i < TOK; ++i)
          kq[i] += a[u][v] * tok[u][i];
      for (int i = 0; i < TOK; ++i) {
        REAL d = 0;
        for (int j = 0; j < TOK; ++j)
          d += score_map[i * TOK + j] * q[v][j] + score_map[j * TOK + i] * kq[j];
        for (int c = 0; c < CH; ++c)
          d += value_map[c * TOK + i] * dz[v][c];
        dt[v][i] += d;
        for (int j = 0; j < TOK; ++j)
          dmap[i][j] += tok[v][i] * q[v][j];
      }
      for (int c = 0; c < CH; ++c)
        for (int j = 0; j < TOK; ++j)
          dval[c][j] += dz[v][c] * tok[v][j];
      __global REAL* gx = grad_samples + ((v * S + s) * CH) * hw + p;
      for (int c = 0; c < CH; ++c)
        gx[c * hw] = dt[v][c];
      grad_weights[(v * S + s) * hw + p] = dt[v][CH];
    }
  }
  __global REAL* row = partial + (s * chunks + chunk) * NPARAM;
  for (int i = 0; i < TOK; ++i)
    for (int j = 0; j < TOK; ++j)
      row[i * TOK + j] = dmap[i][j];
  for (int c = 0; c < CH; ++c)
    for (int j = 0; j < TOK; ++j)
      row[TOK * TOK + c * TOK + j] = dval[c][j];
  for (int c = 0; c < CH; ++c) {
    row[TOK * TOK + CH * TOK + c] = dgain[c];
    row[TOK * TOK + CH * TOK + CH + c] = dshift[c];
  }
}
