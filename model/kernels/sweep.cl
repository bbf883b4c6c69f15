// Surface sampling ("unprojection", spec §6.3 and §6.5): every reference pixel of
// every surface is placed in 3-D, projected into each source view and bilinearly gathered from
// the view's map (F.grid_sample semantics: zero padding, align_corners = False), with the
// validity mask |gx| <= 1 && |gy| <= 1.
//
// Surfaces are either fronto-parallel planes (depth[s], centre grid, the reference's ray-plane
// intersection) or deformable layers (depth[s, y, x], corner grid, plain back-projection).
// One work item handles one (surface, pixel) and loops over views and channels, so the
// projection is computed once per view and reused for every channel.
//
// Per-view camera block (CAM_STRIDE reals), built on the host from the reference camera and
// view v: R = R_v R_ref^T (row-major), t = t_v - R t_ref, then fx, fy, cx, cy of view v. A
// reference-camera point X_ref maps to view coordinates R X_ref + t.

#define CAM_STRIDE 16

// Largest number of views the fused mean/variance kernels keep in private arrays (the host
// picks the smallest power of two >= V, up to 64).
#ifndef MAX_VIEWS
#define MAX_VIEWS 8
#endif

// Bilinear taps (Taps, make_taps, gather, gather_grad, scatter) and atomic_add_real come
// from the engine's common.cl, which prefixes every program.

// ---- geometry --------------------------------------------------------------------------------

// Reference ray of output pixel (x, y) in reference camera coordinates, z = 1:
// q = ((u - cx) / fx, (v - cy) / fy, 1) with the centre grid u = (x + 0.5) / w or the corner
// grid u = x / (w - 1).
inline REAL2 reference_ray(const int x, const int y, const int h, const int w, const int corner,
                           const REAL rfx, const REAL rfy, const REAL rcx, const REAL rcy) {
  const REAL u = corner ? (REAL)x / (REAL)(w - 1) : ((REAL)x + (REAL)0.5) / (REAL)w;
  const REAL v = corner ? (REAL)y / (REAL)(h - 1) : ((REAL)y + (REAL)0.5) / (REAL)h;
  return (REAL2)((u - rcx) / rfx, (v - rcy) / rfy);
}

// Reference-camera z of the surface point on ray q. Layers: the depth map value (plain
// back-projection). Planes: the reference intersects the unit ray r = q / |q| with the plane,
// tau = d / (n.r + 1e-7) with n.r = 1 / |q|, so the point is tau r = d (n.r / (n.r + 1e-7)) q.
inline REAL surface_depth(const int depth_map, __global const REAL* depth, const int s,
                          const int pix, const int hw, const REAL2 q) {
  if (depth_map) return depth[s * hw + pix];
  const REAL nr = 1 / sqrt(q.x * q.x + q.y * q.y + 1);
  return depth[s] * (nr / (nr + (REAL)1e-7));
}

typedef struct {
  REAL gx, gy;   // sampling grid coordinates (inside the image when |g| <= 1)
  REAL dgx, dgy; // their derivatives with respect to the depth along the reference ray
  int inside;
} Projection;

// Projects the reference point d * q into the view of camera block `cam`. As the reference,
// z is pushed away from 0 keeping its sign (|z| >= 1e-6) and points behind the view are not
// rejected (only the in-image test is applied).
inline void project(__global const REAL* cam, const REAL2 q, const REAL d, Projection* p) {
  const REAL ax = cam[0] * q.x + cam[1] * q.y + cam[2];
  const REAL ay = cam[3] * q.x + cam[4] * q.y + cam[5];
  const REAL az = cam[6] * q.x + cam[7] * q.y + cam[8];
  const REAL X = d * ax + cam[9], Y = d * ay + cam[10], Z = d * az + cam[11];
  const REAL eps = (REAL)1e-6;
  REAL zc = Z, dz = az;
  if (Z >= 0) {
    if (Z < eps) {
      zc = eps;
      dz = 0;
    }
  } else if (Z > -eps) {
    zc = -eps;
    dz = 0;
  }
  const REAL fx = cam[12], fy = cam[13], cx = cam[14], cy = cam[15];
  const REAL u = fx * (X / zc) + cx, v = fy * (Y / zc) + cy;
  p->gx = 2 * u - 1;
  p->gy = 2 * v - 1;
  p->inside = fabs(p->gx) <= 1 && fabs(p->gy) <= 1;
  const REAL iz2 = 1 / (zc * zc);
  p->dgx = 2 * fx * (ax * zc - X * dz) * iz2;
  p->dgy = 2 * fy * (ay * zc - Y * dz) * iz2;
}

// ---- plain sampling: samples [V, S, C, h, w] and mask [V, S, 1, h, w] ------------------------

// Source maps are [V, C, Hs, Ws], or [V, S, C, Hs, Ws] when per_surface (surface s gathers its
// own slice). Items over (x, y, surface).
__kernel void sweep_forward(const int S, const int h, const int w, const int V, const int C,
                            const int Hs, const int Ws, const int corner, const int depth_map,
                            const int per_surface, __global const REAL* cams, const REAL rfx,
                            const REAL rfy, const REAL rcx, const REAL rcy,
                            __global const REAL* depth, __global const REAL* src,
                            __global REAL* out, __global REAL* mask) {
  const int x = get_global_id(0), y = get_global_id(1), s = get_global_id(2);
  if (x >= w || y >= h || s >= S) return;
  const int hw = h * w, pix = y * w + x, in_plane = Hs * Ws;
  const REAL2 q = reference_ray(x, y, h, w, corner, rfx, rfy, rcx, rcy);
  const REAL d = surface_depth(depth_map, depth, s, pix, hw, q);
  for (int v = 0; v < V; ++v) {
    Projection p;
    project(cams + v * CAM_STRIDE, q, d, &p);
    Taps t;
    make_taps(p.gx, p.gy, Hs, Ws, &t);
    mask[(v * S + s) * hw + pix] = p.inside ? (REAL)1 : (REAL)0;
    __global const REAL* sv = src + (per_surface ? (v * S + s) * C : v * C) * in_plane;
    __global REAL* o = out + (v * S + s) * C * hw + pix;
    for (int c = 0; c < C; ++c)
      o[c * hw] = gather(sv + c * in_plane, &t);
  }
}

// Gradients of sweep_forward: scattered into gsrc (zeroed by the host) when want_src, and to the
// depth map (one writer per element) when want_depth (layers only).
__kernel void sweep_backward(const int S, const int h, const int w, const int V, const int C,
                             const int Hs, const int Ws, const int corner, const int depth_map,
                             const int per_surface, __global const REAL* cams, const REAL rfx,
                             const REAL rfy, const REAL rcx, const REAL rcy,
                             __global const REAL* depth, __global const REAL* src,
                             __global const REAL* g, const int want_src, __global REAL* gsrc,
                             const int want_depth, __global REAL* gdepth) {
  const int x = get_global_id(0), y = get_global_id(1), s = get_global_id(2);
  if (x >= w || y >= h || s >= S) return;
  const int hw = h * w, pix = y * w + x, in_plane = Hs * Ws;
  const REAL2 q = reference_ray(x, y, h, w, corner, rfx, rfy, rcx, rcy);
  const REAL d = surface_depth(depth_map, depth, s, pix, hw, q);
  REAL gd = 0;
  for (int v = 0; v < V; ++v) {
    Projection p;
    project(cams + v * CAM_STRIDE, q, d, &p);
    Taps t;
    make_taps(p.gx, p.gy, Hs, Ws, &t);
    if (t.valid == 0) continue;
    const int base = (per_surface ? (v * S + s) * C : v * C) * in_plane;
    __global const REAL* go = g + (v * S + s) * C * hw + pix;
    // d sx / d gx = Ws / 2 and d sy / d gy = Hs / 2 (align_corners = False).
    const REAL kx = p.dgx * (REAL)Ws / 2, ky = p.dgy * (REAL)Hs / 2;
    for (int c = 0; c < C; ++c) {
      const REAL gc = go[c * hw];
      if (want_src) scatter(gsrc + base + c * in_plane, &t, gc);
      if (want_depth) {
        REAL dsx, dsy;
        gather_grad(src + base + c * in_plane, &t, &dsx, &dsy);
        gd += gc * (dsx * kx + dsy * ky);
      }
    }
  }
  if (want_depth) gdepth[s * hw + pix] = gd;
}

// ---- coverage: out [S, 1, h, w] = how many views see each surface point ------------------------
//
// The sum over views of sweep_forward's mask without gathering a single texel: the photo prior
// needs only where at least two sources see a point, and a sweep of the maps would cost a gather
// per view and channel for it. No gradient (the masks are piecewise constant).
__kernel void sweep_coverage(const int S, const int h, const int w, const int V, const int C,
                             const int Hs, const int Ws, const int corner, const int depth_map,
                             __global const REAL* cams, const REAL rfx, const REAL rfy,
                             const REAL rcx, const REAL rcy, __global const REAL* depth,
                             __global REAL* out) {
  const int x = get_global_id(0), y = get_global_id(1), s = get_global_id(2);
  if (x >= w || y >= h || s >= S) return;
  const int hw = h * w, pix = y * w + x;
  const REAL2 q = reference_ray(x, y, h, w, corner, rfx, rfy, rcx, rcy);
  const REAL d = surface_depth(depth_map, depth, s, pix, hw, q);
  int seen = 0;
  for (int v = 0; v < V; ++v) {
    Projection p;
    project(cams + v * CAM_STRIDE, q, d, &p);
    seen += p.inside;
  }
  out[s * hw + pix] = (REAL)seen;
}

// ---- fused aggregation: out [S, 2C, h, w] = [mean | variance] -------------------------------
//
// w_v = m_v / (sum_v m_v + 1e-7), times omega_v (surface s's own slice of weights
// [V, S, 1, Hs, Ws], gathered like the maps) when has_weights; mean = sum_v w_v s_v,
// var = sum_v w_v (s_v - mean)^2 (not normalised by sum w: the reference's fused_mean_variance).
// The view samples are never stored: a work item keeps the taps of its V views in private
// arrays and loops channel by channel.

// Mask-normalised weights n_v, gathered weights omega_v (1 without weight maps) and the taps of
// every view; returns sum_v n_v omega_v.
inline REAL view_weights(const int V, const int S, const int s, const int Hs, const int Ws,
                         __global const REAL* cams, const REAL2 q, const REAL d,
                         const int has_weights, __global const REAL* weights, Taps* taps,
                         REAL* nv, REAL* omega, REAL* kx, REAL* ky) {
  REAL msum = 0;
  for (int v = 0; v < V; ++v) {
    Projection p;
    project(cams + v * CAM_STRIDE, q, d, &p);
    make_taps(p.gx, p.gy, Hs, Ws, &taps[v]);
    nv[v] = p.inside ? (REAL)1 : (REAL)0;
    kx[v] = p.dgx * (REAL)Ws / 2;
    ky[v] = p.dgy * (REAL)Hs / 2;
    msum += nv[v];
  }
  const REAL denom = msum + (REAL)1e-7;
  REAL total = 0;
  for (int v = 0; v < V; ++v) {
    nv[v] = nv[v] / denom;
    omega[v] = 1;
    if (has_weights && nv[v] != 0)
      omega[v] = gather(weights + (v * S + s) * Hs * Ws, &taps[v]);
    total += nv[v] * omega[v];
  }
  return total;
}

__kernel void sweep_meanvar_forward(const int S, const int h, const int w, const int V,
                                    const int C, const int Hs, const int Ws, const int corner,
                                    const int depth_map, __global const REAL* cams,
                                    const REAL rfx, const REAL rfy, const REAL rcx,
                                    const REAL rcy, __global const REAL* depth,
                                    __global const REAL* src, const int has_weights,
                                    __global const REAL* weights, __global REAL* out) {
  const int x = get_global_id(0), y = get_global_id(1), s = get_global_id(2);
  if (x >= w || y >= h || s >= S) return;
  const int hw = h * w, pix = y * w + x, in_plane = Hs * Ws;
  const REAL2 q = reference_ray(x, y, h, w, corner, rfx, rfy, rcx, rcy);
  const REAL d = surface_depth(depth_map, depth, s, pix, hw, q);
  Taps taps[MAX_VIEWS];
  REAL nv[MAX_VIEWS], omega[MAX_VIEWS], kx[MAX_VIEWS], ky[MAX_VIEWS], sv[MAX_VIEWS];
  view_weights(V, S, s, Hs, Ws, cams, q, d, has_weights, weights, taps, nv, omega, kx, ky);
  __global REAL* o = out + s * 2 * C * hw + pix;
  for (int c = 0; c < C; ++c) {
    REAL mean = 0;
    for (int v = 0; v < V; ++v) {
      const REAL wv = nv[v] * omega[v];
      if (wv == 0) continue; // invalid views contribute exactly 0
      sv[v] = gather(src + (v * C + c) * in_plane, &taps[v]);
      mean += wv * sv[v];
    }
    REAL var = 0;
    for (int v = 0; v < V; ++v) {
      const REAL wv = nv[v] * omega[v];
      if (wv == 0) continue;
      const REAL dl = sv[v] - mean;
      var += wv * dl * dl;
    }
    o[c * hw] = mean;
    o[(C + c) * hw] = var;
  }
}

// Gradients of sweep_meanvar_forward. With W = sum_v w_v:
//   d L / d s_v   = w_v (g_mean - 2 g_var mean (1 - W) + 2 g_var (s_v - mean)),
//   d L / d w_v   = sum_c g_mean s_v + g_var ((s_v - mean)^2 - 2 mean (1 - W) s_v),
//   d L / d omega_v = n_v d L / d w_v; the masks are piecewise constant (no gradient).
// Maps and weight maps receive scattered gradients (zeroed by the host); the depth map
// (layers) receives the gradient through the sampling coordinates of maps and weight maps.
__kernel void sweep_meanvar_backward(const int S, const int h, const int w, const int V,
                                     const int C, const int Hs, const int Ws, const int corner,
                                     const int depth_map, __global const REAL* cams,
                                     const REAL rfx, const REAL rfy, const REAL rcx,
                                     const REAL rcy, __global const REAL* depth,
                                     __global const REAL* src, const int has_weights,
                                     __global const REAL* weights, __global const REAL* g,
                                     const int want_src, __global REAL* gsrc,
                                     const int want_weights, __global REAL* gweights,
                                     const int want_depth, __global REAL* gdepth) {
  const int x = get_global_id(0), y = get_global_id(1), s = get_global_id(2);
  if (x >= w || y >= h || s >= S) return;
  const int hw = h * w, pix = y * w + x, in_plane = Hs * Ws;
  const REAL2 q = reference_ray(x, y, h, w, corner, rfx, rfy, rcx, rcy);
  const REAL d = surface_depth(depth_map, depth, s, pix, hw, q);
  Taps taps[MAX_VIEWS];
  REAL nv[MAX_VIEWS], omega[MAX_VIEWS], kx[MAX_VIEWS], ky[MAX_VIEWS], sv[MAX_VIEWS];
  REAL dsx[MAX_VIEWS], dsy[MAX_VIEWS], gw[MAX_VIEWS];
  const REAL total =
      view_weights(V, S, s, Hs, Ws, cams, q, d, has_weights, weights, taps, nv, omega, kx, ky);
  const REAL rest = 1 - total;
  for (int v = 0; v < V; ++v)
    gw[v] = 0;
  REAL gd = 0;
  __global const REAL* go = g + s * 2 * C * hw + pix;
  for (int c = 0; c < C; ++c) {
    REAL mean = 0;
    for (int v = 0; v < V; ++v) {
      if (nv[v] == 0) continue; // masked views: no value, no gradient
      sv[v] = gather_grad(src + (v * C + c) * in_plane, &taps[v], &dsx[v], &dsy[v]);
      mean += nv[v] * omega[v] * sv[v];
    }
    const REAL gm = go[c * hw], gv = go[(C + c) * hw];
    const REAL k = gm - 2 * gv * mean * rest;
    for (int v = 0; v < V; ++v) {
      if (nv[v] == 0) continue;
      const REAL dl = sv[v] - mean;
      const REAL gs = nv[v] * omega[v] * (k + 2 * gv * dl);
      gw[v] += gm * sv[v] + gv * (dl * dl - 2 * mean * rest * sv[v]);
      if (want_src) scatter(gsrc + (v * C + c) * in_plane, &taps[v], gs);
      if (want_depth) gd += gs * (dsx[v] * kx[v] + dsy[v] * ky[v]);
    }
  }
  if (has_weights && (want_weights || want_depth)) {
    for (int v = 0; v < V; ++v) {
      if (nv[v] == 0) continue;
      const REAL gomega = gw[v] * nv[v];
      const int base = (v * S + s) * in_plane;
      if (want_weights) scatter(gweights + base, &taps[v], gomega);
      if (want_depth) {
        REAL ox, oy;
        gather_grad(weights + base, &taps[v], &ox, &oy);
        gd += gomega * (ox * kx[v] + oy * ky[v]);
      }
    }
  }
  if (want_depth) gdepth[s * hw + pix] = gd;
}
