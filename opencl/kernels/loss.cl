// Losses: L1 / MSE, the reference's masked L1, total variation and the smooth-layers loss.
// Global sums use blocked partial sums (one slot per work group, see src/row_blocks.h), then a
// fixed-order final sum, so results are deterministic. Gradients of the scalar loss arrive as
// a one-element device buffer g (read in the kernel: no host round trip).

// Blocked layout (see src/row_blocks.h): GROUP items per block; item j of a block reads the
// REAL4 vectors j, j + GROUP, ... of the block, item 0 also the block's last < 4 elements.
// Elementwise kernels run 2-D (vector index within a row, row); the item past a row's last full
// vector handles its last < 4 elements.
#define GROUP 64

// Elements in block `block` of a row of L elements with per_vec vectors per item.
inline int block_count(const int L, const int block, const int per_vec) {
  return clamp(L - block * GROUP * 4 * per_vec, 0, GROUP * 4 * per_vec);
}

inline REAL hsum4(const REAL4 v) { return (v.x + v.y) + (v.z + v.w); }

#define MODE_ABS 0
#define MODE_SQUARE 1

// Sums the block's two accumulators into out[slot] and out[stride + slot]. Every item of the
// group must call it (it holds a barrier).
inline void block_sum2(const REAL a, const REAL b, __local REAL* sa, __local REAL* sb,
                       __global REAL* out, const int slot, const int stride) {
  const int j = get_local_id(0);
  sa[j] = a;
  sb[j] = b;
  barrier(CLK_LOCAL_MEM_FENCE);
  if (j == 0) {
    REAL ta = 0, tb = 0;
    for (int i = 0; i < GROUP; ++i) {
      ta += sa[i];
      tb += sb[i];
    }
    out[slot] = ta;
    out[stride + slot] = tb;
  }
}

inline REAL penalty(const int mode, const REAL d) { return mode == MODE_ABS ? fabs(d) : d * d; }
inline REAL4 penalty4(const int mode, const REAL4 d) { return mode == MODE_ABS ? fabs(d) : d * d; }

// out[0] = scale * sum of part[0 .. parts): one item, fixed order, compensated (Kahan) so that
// thousands of block partials do not dominate the error in float.
__kernel void finish_sum(const int parts, const REAL scale, __global const REAL* part,
                         __global REAL* out) {
  if (get_global_id(0) != 0) return;
  REAL s = 0, c = 0;
  for (int i = 0; i < parts; ++i) {
    const REAL y = part[i] - c;
    const REAL t = s + y;
    c = (t - s) - y;
    s = t;
  }
  out[0] = s * scale;
}

// ---- l1Loss / mseLoss -------------------------------------------------------------------------

// Block sums of |a - b| or (a - b)^2 over n elements (1-D launch of groups x GROUP items) into
// part[block]; part must hold 2 x groups values (the second half is scratch).
__kernel void pointwise_partial(const int mode, const int n, const int per_vec,
                                __global const REAL* a, __global const REAL* b,
                                __global REAL* part) {
  __local REAL sa[GROUP], sb[GROUP];
  const int j = get_local_id(0);
  const int block = get_group_id(0);
  const int in_block = block_count(n, block, per_vec);
  const int nvec = in_block / 4;
  const int tail = j == 0 ? in_block - 4 * nvec : 0;
  const int o = block * GROUP * 4 * per_vec;
  __global const REAL* pa = a + o;
  __global const REAL* pb = b + o;
  REAL4 acc4 = 0;
  for (int v = j; v < nvec; v += GROUP)
    acc4 += penalty4(mode, vload4(v, pa) - vload4(v, pb));
  REAL acc = hsum4(acc4);
  for (int t = 4 * nvec; t < 4 * nvec + tail; ++t)
    acc += penalty(mode, pa[t] - pb[t]);
  block_sum2(acc, 0, sa, sb, part, block, get_num_groups(0));
}

// ga = g scale d/da penalty(a - b), gb = -ga (each written only if wanted). One item per
// vector (plus one for the tail).
__kernel void pointwise_backward(const int mode, const int n, const REAL scale,
                                 __global const REAL* g, __global const REAL* a,
                                 __global const REAL* b, __global REAL* ga, __global REAL* gb,
                                 const int want_a, const int want_b) {
  const int v = get_global_id(0);
  const int nvec = n / 4;
  if (v > nvec) return;
  const REAL gs = g[0] * scale;
  if (v < nvec) {
    const REAL4 d = vload4(v, a) - vload4(v, b);
    const REAL4 r = gs * (mode == MODE_ABS ? sign(d) : 2 * d);
    if (want_a) vstore4(r, v, ga);
    if (want_b) vstore4(-r, v, gb);
  } else {
    for (int i = 4 * nvec; i < n; ++i) {
      const REAL d = a[i] - b[i];
      const REAL r = gs * (mode == MODE_ABS ? sign(d) : 2 * d);
      if (want_a) ga[i] = r;
      if (want_b) gb[i] = -r;
    }
  }
}

// ---- maskedL1 ---------------------------------------------------------------------------------

// Rows are (image n, channel c) pairs of L = H * W pixels (launch: GROUP x groups, N * C); the
// mask row is (n, 0) when the mask has one channel (Cm = 1), else (n, c). Block sums of
// |p - t| * m and of m go to part[slot], part[stride + slot].
__kernel void masked_l1_partial(const int C, const int Cm, const int L, const int per_vec,
                                __global const REAL* p, __global const REAL* t,
                                __global const REAL* m, __global REAL* part, const int stride) {
  __local REAL sa[GROUP], sb[GROUP];
  const int j = get_local_id(0);
  const int block = get_group_id(0);
  const int row = get_global_id(1);
  const int mrow = (row / C) * Cm + (Cm == 1 ? 0 : row % C);
  const int in_block = block_count(L, block, per_vec);
  const int nvec = in_block / 4;
  const int tail = j == 0 ? in_block - 4 * nvec : 0;
  const int ob = block * GROUP * 4 * per_vec;
  __global const REAL* pp = p + (long)row * L + ob;
  __global const REAL* pt = t + (long)row * L + ob;
  __global const REAL* pm = m + (long)mrow * L + ob;
  REAL4 s4 = 0, z4 = 0;
  for (int v = j; v < nvec; v += GROUP) {
    const REAL4 mv = vload4(v, pm);
    s4 += fabs(vload4(v, pp) - vload4(v, pt)) * mv;
    z4 += mv;
  }
  REAL acc_s = hsum4(s4), acc_z = hsum4(z4);
  for (int i = 4 * nvec; i < 4 * nvec + tail; ++i) {
    acc_s += fabs(pp[i] - pt[i]) * pm[i];
    acc_z += pm[i];
  }
  block_sum2(acc_s, acc_z, sa, sb, part, row * get_num_groups(0) + block, stride);
}

// One item per row: sz[2 r] = S = sum |p - t| m, sz[2 r + 1] = Z = sum m + eps,
// ratio[r] = S / Z.
__kernel void masked_l1_rows(const int rows, const int groups, const REAL eps,
                             __global const REAL* part, const int stride, __global REAL* sz,
                             __global REAL* ratio) {
  const int r = get_global_id(0);
  if (r >= rows) return;
  REAL s = 0, z = 0;
  for (int b = 0; b < groups; ++b) {
    s += part[r * groups + b];
    z += part[stride + r * groups + b];
  }
  z += eps;
  sz[2 * r] = s;
  sz[2 * r + 1] = z;
  ratio[r] = s / z;
}

// gp = g scale sign(p - t) m / Z, gt = -gp. 2-D launch (vector within a row of L, row n * C + c).
__kernel void masked_l1_bwd_pt(const int rows, const int C, const int Cm, const int L,
                               const REAL scale, __global const REAL* g, __global const REAL* p,
                               __global const REAL* t, __global const REAL* m,
                               __global const REAL* sz, __global REAL* gp, __global REAL* gt,
                               const int want_p, const int want_t) {
  const int v = get_global_id(0);
  const int row = get_global_id(1);
  const int nvec = L / 4;
  if (v > nvec || row >= rows) return;
  const int mrow = (row / C) * Cm + (Cm == 1 ? 0 : row % C);
  const REAL k = g[0] * scale / sz[2 * row + 1];
  const long o = (long)row * L;
  __global const REAL* pp = p + o;
  __global const REAL* pt = t + o;
  __global const REAL* pm = m + (long)mrow * L;
  if (v < nvec) {
    const REAL4 r = k * sign(vload4(v, pp) - vload4(v, pt)) * vload4(v, pm);
    if (want_p) vstore4(r, v, gp + o);
    if (want_t) vstore4(-r, v, gt + o);
  } else {
    for (int i = 4 * nvec; i < L; ++i) {
      const REAL r = k * sign(pp[i] - pt[i]) * pm[i];
      if (want_p) gp[o + i] = r;
      if (want_t) gt[o + i] = -r;
    }
  }
}

// gm = g scale sum over the channels using this mask row of (|p - t| / Z - S / Z^2).
// 2-D launch (vector within a row of L, mask row n * Cm + cm).
__kernel void masked_l1_bwd_mask(const int mrows, const int C, const int Cm, const int L,
                                 const REAL scale, __global const REAL* g,
                                 __global const REAL* p, __global const REAL* t,
                                 __global const REAL* sz, __global REAL* gm) {
  const int v = get_global_id(0);
  const int mrow = get_global_id(1);
  const int nvec = L / 4;
  if (v > nvec || mrow >= mrows) return;
  const int img = mrow / Cm;
  const int c0 = Cm == 1 ? 0 : mrow % Cm;
  const int c1 = Cm == 1 ? C : c0 + 1;
  const REAL gs = g[0] * scale;
  __global REAL* pg = gm + (long)mrow * L;
  if (v < nvec) {
    REAL4 acc = 0;
    for (int c = c0; c < c1; ++c) {
      const int row = img * C + c;
      const REAL s = sz[2 * row], z = sz[2 * row + 1];
      const long o = (long)row * L;
      acc += fabs(vload4(v, p + o) - vload4(v, t + o)) / z - s / (z * z);
    }
    vstore4(gs * acc, v, pg);
  } else {
    for (int i = 4 * nvec; i < L; ++i) {
      REAL acc = 0;
      for (int c = c0; c < c1; ++c) {
        const int row = img * C + c;
        const REAL s = sz[2 * row], z = sz[2 * row + 1];
        const long o = (long)row * L + i;
        acc += fabs(p[o] - t[o]) / z - s / (z * z);
      }
      pg[i] = gs * acc;
    }
  }
}

// ---- totalVariation / smoothLayersLoss -----------------------------------------------------

// x is a stack of H x W images (n elements). Block sums of penalty(vertical difference) and
// penalty(horizontal difference) go to part[block], part[stride + block]. Scalar items (each
// element needs its own row / column test): item j of a block reads elements j, j + GROUP, ...
// of the block's GROUP * 4 * per_vec elements.
__kernel void grad2d_partial(const int mode, const int n, const int H, const int W,
                             const int per_vec, __global const REAL* x, __global REAL* part,
                             const int stride) {
  __local REAL sa[GROUP], sb[GROUP];
  const int per_item = 4 * per_vec;
  const int start = get_group_id(0) * GROUP * per_item + get_local_id(0);
  REAL acc_y = 0, acc_x = 0;
  for (int k = 0; k < per_item && start + GROUP * k < n; ++k) {
    const int e = start + GROUP * k;
    const int j = e % W, i = (e / W) % H;
    const REAL xe = x[e];
    if (i + 1 < H) acc_y += penalty(mode, x[e + W] - xe);
    if (j + 1 < W) acc_x += penalty(mode, x[e + 1] - xe);
  }
  block_sum2(acc_y, acc_x, sa, sb, part, get_group_id(0), stride);
}

// Final value. MODE_ABS (total variation): out = cy sum_y + cx sum_x. MODE_SQUARE (smooth
// layers): root = sqrt(sum_y + sum_x + eps), out = cy root, aux[0] = root (for the backward).
__kernel void grad2d_finish(const int mode, const int groups, const REAL cy, const REAL cx,
                            const REAL eps, __global const REAL* part, const int stride,
                            __global REAL* out, __global REAL* aux) {
  if (get_global_id(0) != 0) return;
  REAL sy = 0, sx = 0;
  for (int b = 0; b < groups; ++b) {
    sy += part[b];
    sx += part[stride + b];
  }
  if (mode == MODE_ABS) {
    out[0] = cy * sy + cx * sx;
  } else {
    const REAL root = sqrt(sy + sx + eps);
    aux[0] = root;
    out[0] = cy * root;
  }
}

// Gradient of the final value with respect to each element: every difference the element
// takes part in contributes (+ as the later element, - as the earlier one).
__kernel void grad2d_backward(const int mode, const int n, const int H, const int W,
                              const REAL cy, const REAL cx, __global const REAL* g,
                              __global const REAL* aux, __global const REAL* x,
                              __global REAL* gx) {
  const int e = get_global_id(0);
  if (e >= n) return;
  const int j = e % W, i = (e / W) % H;
  const REAL xe = x[e];
  REAL vy = 0, vx = 0;
  if (mode == MODE_ABS) {
    if (i > 0) vy += sign(xe - x[e - W]);
    if (i + 1 < H) vy -= sign(x[e + W] - xe);
    if (j > 0) vx += sign(xe - x[e - 1]);
    if (j + 1 < W) vx -= sign(x[e + 1] - xe);
    gx[e] = g[0] * (cy * vy + cx * vx);
  } else {
    // d sqrt(S) / dx = (1 / (2 root)) dS/dx, dS/dx = 2 (sum of signed differences).
    if (i > 0) vy += xe - x[e - W];
    if (i + 1 < H) vy -= x[e + W] - xe;
    if (j > 0) vx += xe - x[e - 1];
    if (j + 1 < W) vx -= x[e + 1] - xe;
    gx[e] = g[0] * cy / aux[0] * (vy + vx);
  }
}
