// MLI layer-mesh rasterizer; the rules are documented in model/include/simpli/model/rasterizer.h.
// Passes: raster_project (vertices -> target pixel coordinates), raster_bin_count and
// raster_bin_fill (triangles -> screen tiles), raster_fragments (per pixel k-buffer of the
// nearest triangles), raster_shade_forward / raster_shade_backward (interpolation, composite and
// its gradients). Build option: -DRASTER_K=<fragments per pixel>.

// The arithmetic exactly as written: contracting a*b - c*d into an fma would make a product
// minus the same product nonzero and change results between compilers.
#pragma OPENCL FP_CONTRACT OFF

// Parameter block written by raster_camera.cpp (same order).
#define PRM_RFX 0 // reference camera relative intrinsics
#define PRM_RFY 1
#define PRM_RCX 2
#define PRM_RCY 3
#define PRM_M 4   // 3x3 rotation reference camera -> target camera, row-major
#define PRM_TX 13 // translation reference camera -> target camera
#define PRM_TY 14
#define PRM_TZ 15
#define PRM_FX 16 // target intrinsics in pixels (pixel (c, r) has its centre at c+0.5, r+0.5)
#define PRM_FY 17
#define PRM_CX 18
#define PRM_CY 19
#define PRM_NEAR 20
#define PRM_FAR 21 // REAL_MAX when the far cut is off

// Coverage is decided exactly on vertices snapped to 2^-30 pixel: for float32 that is the float
// coordinates themselves (beyond 1/128 pixel from the origin), for float64 a 1e-9 pixel
// rounding. GUARD (2^22 px) keeps snapped coordinates k below 2^52, so k * 2^-30 is exact in
// both precisions and differences of k stay below 2^53 (128-bit products in the exact path).
#define SNAP 1073741824L
#define GUARD 4194304.0
// Shewchuk's orient2d error bound factor (3 + 16u) u, u = unit roundoff.
#define ORIENT_BOUND ((3 + 16 * (REAL_EPS / 2)) * (REAL_EPS / 2))
#define INLINE inline __attribute__((always_inline))
// Denominators of the clamped barycentrics below this (pixel^2) fall back to equal weights.
#define MIN_SUM 1e-12
// The reference's transmittance epsilon, inside every factor.
#define T_EPS 1e-6

// ---- geometry helpers -------------------------------------------------------------------------

// Vertex indices of triangle t (layer-major, two triangles per texel quad, diagonal top-left to
// bottom-right), its layer, the quad's top-left corner (qi, qj) and which of the two it is.
INLINE void tri_vertices(const int t, const int H, const int W, int* v, int* layer, int* qi,
                         int* qj, int* second) {
  const int quads = (H - 1) * (W - 1);
  *layer = t / (2 * quads);
  const int rest = t - *layer * 2 * quads;
  const int q = rest >> 1;
  *qi = q / (W - 1);
  *qj = q - *qi * (W - 1);
  *second = rest & 1;
  const int b = *layer * H * W + *qi * W + *qj;
  v[0] = b;
  if (!*second) {
    v[1] = b + W;
    v[2] = b + W + 1;
  } else {
    v[1] = b + W + 1;
    v[2] = b + 1;
  }
}

// Direction a = M * ((u - cx)/fx, (v - cy)/fy, 1) of corner-grid vertex (i, j) in the target
// camera: the vertex at reference depth d is d * a + t.
INLINE void vertex_direction(const int i, const int j, const int H, const int W,
                             __global const REAL* prm, REAL* ax, REAL* ay, REAL* az) {
  const REAL u = (REAL)j / (REAL)(W - 1);
  const REAL v = (REAL)i / (REAL)(H - 1);
  const REAL rx = (u - prm[PRM_RCX]) / prm[PRM_RFX];
  const REAL ry = (v - prm[PRM_RCY]) / prm[PRM_RFY];
  *ax = prm[PRM_M + 0] * rx + prm[PRM_M + 1] * ry + prm[PRM_M + 2];
  *ay = prm[PRM_M + 3] * rx + prm[PRM_M + 4] * ry + prm[PRM_M + 5];
  *az = prm[PRM_M + 6] * rx + prm[PRM_M + 7] * ry + prm[PRM_M + 8];
}

// Integer grid coordinate of a snapped value (exact: the value is a multiple of 2^-30 below 2^22).
inline long grid_coord(const REAL x) {
  return (long)(x * (REAL)SNAP);
}

// x rounded to the 2^-30 pixel grid (exact in REAL for |x| <= 2^22).
INLINE REAL snapped(const REAL x) {
  return rint(x * (REAL)SNAP) * ((REAL)1 / (REAL)SNAP);
}

// Sign of a*b - c*d, exact (128-bit products: signed high halves, then unsigned low halves).
inline int det_sign(const long a, const long b, const long c, const long d) {
  const long h1 = mul_hi(a, b), h2 = mul_hi(c, d);
  if (h1 != h2)
    return h1 > h2 ? 1 : -1;
  const ulong l1 = (ulong)a * (ulong)b, l2 = (ulong)c * (ulong)d;
  return l1 > l2 ? 1 : (l1 < l2 ? -1 : 0);
}

// Exact sign of cross(b - a, c - a) for snapped points, in 128-bit integers (the rare slow path;
// kept out of line so the fast paths stay small).
__attribute__((noinline)) int orient_exact(const REAL ax, const REAL ay, const REAL bx,
                                           const REAL by, const REAL cx, const REAL cy) {
  const long kax = grid_coord(ax), kay = grid_coord(ay);
  return det_sign(grid_coord(bx) - kax, grid_coord(cy) - kay, grid_coord(by) - kay,
                  grid_coord(cx) - kax);
}

// Exact sign (-1, 0, 1) of cross(b - a, c - a) for snapped points: a floating-point evaluation
// with Shewchuk's orient2d error bound decides unless the result is within rounding of 0; then
// orient_exact does.
INLINE int orient(const REAL ax, const REAL ay, const REAL bx, const REAL by, const REAL cx,
                  const REAL cy) {
  const REAL l = (ax - cx) * (by - cy);
  const REAL r = (ay - cy) * (bx - cx);
  const REAL det = l - r; // orient2d(a, b, c) = cross(b - a, c - a)
  // The absolute term only sends more cases to the exact path (denormal flushing).
  const REAL bound = (REAL)ORIENT_BOUND * (fabs(l) + fabs(r)) + (REAL)1e-30;
  if (det > bound)
    return 1;
  if (det < -bound)
    return -1;
  return orient_exact(ax, ay, bx, by, cx, cy);
}

// Exact side (+1 / -1) of the pixel centre q relative to the directed edge o -> e (snapped
// coordinates). Callers pass the edge in a canonical direction (lower vertex index first) and
// negate the result otherwise, so the two triangles sharing an edge see exactly opposite signs.
// A point exactly on the line is treated as moved by an infinitesimal (eps, eps^2), the same
// for every triangle, which makes every point covered exactly once by an unfolded mesh (the
// top-left rule).
INLINE int edge_side(const REAL ox, const REAL oy, const REAL ex, const REAL ey, const REAL qx,
                     const REAL qy) {
  const int s = orient(ox, oy, ex, ey, qx, qy);
  if (s != 0)
    return s;
  // E(q + (eps, eps^2)) = -dy eps + dx eps^2; dx = dy = 0 only in zero-area triangles.
  const REAL dx = ex - ox, dy = ey - oy;
  return dy != 0 ? (dy < 0 ? 1 : -1) : (dx > 0 ? 1 : -1);
}

// Side of q for the triangle edge a -> b with vertex indices (or ranks) ia, ib.
INLINE int tri_edge_side(const REAL ax, const REAL ay, const int ia, const REAL bx, const REAL by,
                         const int ib, const REAL qx, const REAL qy) {
  return ia < ib ? edge_side(ax, ay, bx, by, qx, qy) : -edge_side(bx, by, ax, ay, qx, qy);
}

// Projected triangle: pixel coordinates, target z, snapped coordinates and orientation.
typedef struct {
  int v[3];
  int layer, qi, qj, second; // see tri_vertices
  REAL x[3], y[3], z[3];
  REAL sx[3], sy[3]; // snapped to 2^-30 pixel (exact multiples)
  int orient;        // sign of the snapped signed area (0: degenerate)
  int valid;         // every vertex in front of the near plane and inside the guard band
} Tri;

// Grid row and column of vertex k (0..2) of T.
INLINE void tri_vertex_ij(const Tri* T, const int k, int* i, int* j) {
  *i = T->qi + (k == 0 ? 0 : (T->second ? (k == 1) : 1));
  *j = T->qj + (k == 0 ? 0 : (T->second ? 1 : (k == 2)));
}

// Vertex data of triangle t; `withOrient` also computes the exact orientation.
INLINE Tri load_tri(const int t, const int H, const int W, __global const REAL* verts,
                    const int withOrient) {
  Tri T;
  tri_vertices(t, H, W, T.v, &T.layer, &T.qi, &T.qj, &T.second);
  T.valid = 1;
  for (int k = 0; k < 3; ++k) {
    __global const REAL* p = verts + 4 * T.v[k];
    T.x[k] = p[0];
    T.y[k] = p[1];
    T.z[k] = p[2];
    T.valid = T.valid && p[3] != 0;
    T.sx[k] = snapped(T.x[k]);
    T.sy[k] = snapped(T.y[k]);
  }
  T.orient = withOrient ? orient(T.sx[0], T.sy[0], T.sx[1], T.sy[1], T.sx[2], T.sy[2]) : 0;
  return T;
}

// Whether triangle T can produce fragments at all (binning test).
INLINE int tri_usable(const Tri* T, const REAL far) {
  if (!T->valid || T->orient == 0)
    return 0;
  return !(T->z[0] > far && T->z[1] > far && T->z[2] > far);
}

// Range of pixels whose centres (c + 1/2, r + 1/2) lie in the snapped bounding box, clamped to
// the image. Returns 0 when empty.
INLINE int tri_pixel_rect(const Tri* T, const int Ht, const int Wt, int* c0, int* c1, int* r0,
                          int* r1) {
  const REAL xmin = min(T->sx[0], min(T->sx[1], T->sx[2]));
  const REAL xmax = max(T->sx[0], max(T->sx[1], T->sx[2]));
  const REAL ymin = min(T->sy[0], min(T->sy[1], T->sy[2]));
  const REAL ymax = max(T->sy[0], max(T->sy[1], T->sy[2]));
  // x - 1/2 is exact for the snapped x >= 1/4 (and x <= -1/4) in both precisions; closer to 0
  // rounding cannot move it across an integer that survives the clamp to the image.
  const REAL a0 = max(ceil(xmin - (REAL)0.5), (REAL)0);
  const REAL a1 = min(floor(xmax - (REAL)0.5), (REAL)(Wt - 1));
  const REAL b0 = max(ceil(ymin - (REAL)0.5), (REAL)0);
  const REAL b1 = min(floor(ymax - (REAL)0.5), (REAL)(Ht - 1));
  if (a0 > a1 || b0 > b1)
    return 0;
  *c0 = (int)a0;
  *c1 = (int)a1;
  *r0 = (int)b0;
  *r1 = (int)b1;
  return 1;
}

// The orientation of the triangle with snapped corners (x, y) when it covers the pixel centre
// (qx, qy), else 0 (exact, with the tie rule); v are the vertex indices or any numbers in the
// same order.
INLINE int covers(const REAL* x, const REAL* y, const int* v, const REAL qx, const REAL qy) {
  const int s0 = tri_edge_side(x[1], y[1], v[1], x[2], y[2], v[2], qx, qy);
  const int s1 = tri_edge_side(x[2], y[2], v[2], x[0], y[0], v[0], qx, qy);
  if (s0 != s1)
    return 0;
  return s1 == tri_edge_side(x[0], y[0], v[0], x[1], y[1], v[1], qx, qy) ? s1 : 0;
}

// Interpolation of pixel centre (px, py) in the unsnapped triangle: edge functions e, clamped
// and renormalised barycentrics b, interpolation weights lam (b, or perspective-corrected) and
// the interpolated target z. Returns the barycentric denominator (0 for the equal-weight
// fallback of a numerically degenerate triangle).
INLINE REAL tri_weights(const Tri* T, const REAL px, const REAL py, const int perspective, REAL* e,
                        REAL* b, REAL* lam, REAL* z) {
  REAL sum = 0;
  for (int i = 0; i < 3; ++i) {
    const int a = (i + 1) % 3, c = (i + 2) % 3;
    e[i] = (T->x[c] - T->x[a]) * (py - T->y[a]) - (T->y[c] - T->y[a]) * (px - T->x[a]);
    sum += max((REAL)T->orient * e[i], (REAL)0);
  }
  if (sum > (REAL)MIN_SUM) {
    for (int i = 0; i < 3; ++i)
      b[i] = max((REAL)T->orient * e[i], (REAL)0) / sum;
  } else {
    sum = 0;
    for (int i = 0; i < 3; ++i)
      b[i] = (REAL)1 / (REAL)3;
  }
  if (perspective) {
    REAL q = 0;
    for (int i = 0; i < 3; ++i) {
      lam[i] = b[i] / T->z[i];
      q += lam[i];
    }
    for (int i = 0; i < 3; ++i)
      lam[i] /= q;
    *z = (REAL)1 / q;
  } else {
    REAL zz = 0;
    for (int i = 0; i < 3; ++i) {
      lam[i] = b[i];
      zz += b[i] * T->z[i];
    }
    *z = zz;
  }
  return sum;
}

// Attributes [L, A, H, W]: channel ch of vertex v (in layer l) is at v + l (A-1) HW + ch HW.
INLINE int attr_base(const Tri* T, const int k, const int A, const int HW) {
  return T->v[k] + T->layer * (A - 1) * HW;
}

// ---- pass 0: vertices -------------------------------------------------------------------------

// verts[4v..4v+3] = (x pixel, y pixel, target z, valid) for every vertex.
__kernel void raster_project(const int nv, const int H, const int W, __global const REAL* depth,
                             __global const REAL* prm, __global REAL* verts) {
  const int v = get_global_id(0);
  if (v >= nv)
    return;
  const int loc = v % (H * W);
  const int i = loc / W, j = loc - (loc / W) * W;
  REAL ax, ay, az;
  vertex_direction(i, j, H, W, prm, &ax, &ay, &az);
  const REAL d = depth[v];
  const REAL x = d * ax + prm[PRM_TX];
  const REAL y = d * ay + prm[PRM_TY];
  const REAL z = d * az + prm[PRM_TZ];
  REAL px = 0, py = 0, ok = 0;
  if (isfinite(x) && isfinite(y) && isfinite(z) && z > prm[PRM_NEAR]) {
    px = prm[PRM_FX] * (x / z) + prm[PRM_CX];
    py = prm[PRM_FY] * (y / z) + prm[PRM_CY];
    if (fabs(px) <= (REAL)GUARD && fabs(py) <= (REAL)GUARD) {
      ok = 1;
    } else {
      px = 0;
      py = 0;
    }
  }
  verts[4 * v + 0] = px;
  verts[4 * v + 1] = py;
  verts[4 * v + 2] = isfinite(z) ? z : 0;
  verts[4 * v + 3] = ok;
}

// ---- pass 1: binning --------------------------------------------------------------------------
//
// Small triangles (pixel rectangle of at most SMALL_RECT pixels, nearly all of them) are
// rasterized right here: each covered pixel centre gets a candidate fragment in a per-pixel
// list. Large triangles go to per-tile lists that every pixel of the tile tests itself, which
// keeps the work per item bounded.
#define SMALL_RECT 64

// Pixel rectangle and kind (1 small, 2 large) of usable triangle t; 0 when t cannot produce
// fragments.
INLINE int tri_kind(const Tri* T, const REAL far, const int Ht, const int Wt, int* c0, int* c1,
                    int* r0, int* r1) {
  if (!tri_usable(T, far) || !tri_pixel_rect(T, Ht, Wt, c0, c1, r0, r1))
    return 0;
  const int w = *c1 - *c0 + 1, h = *r1 - *r0 + 1; // each <= 2^20: test before multiplying
  return w <= SMALL_RECT && h <= SMALL_RECT && w * h <= SMALL_RECT ? 1 : 2;
}

INLINE int covers_pixel(const Tri* T, const int c, const int r) {
  return covers(T->sx, T->sy, T->v, (REAL)c + (REAL)0.5, (REAL)r + (REAL)0.5);
}

// Counts candidate fragments per pixel (small triangles) and triangles per tile (large ones);
// the snapped corners of large triangles go to rec[6t .. 6t+5] for the fragment pass.
__kernel void raster_bin_count(const int t0, const int nt, const int H, const int W, const int Ht,
                               const int Wt, const int tile, const int tilesX,
                               __global const REAL* verts, __global const REAL* prm,
                               __global int* pixelCounts, __global int* tileCounts,
                               __global REAL* rec) {
  const int g = get_global_id(0);
  if (g >= nt)
    return;
  const int t = t0 + g;
  const Tri T = load_tri(t, H, W, verts, 1);
  int c0, c1, r0, r1;
  const int kind = tri_kind(&T, prm[PRM_FAR], Ht, Wt, &c0, &c1, &r0, &r1);
  if (kind == 1) {
    for (int r = r0; r <= r1; ++r)
      for (int c = c0; c <= c1; ++c)
        if (covers_pixel(&T, c, r))
          atomic_inc(pixelCounts + r * Wt + c);
  } else if (kind == 2) {
    for (int k = 0; k < 3; ++k) {
      rec[6 * t + 2 * k] = T.sx[k];
      rec[6 * t + 2 * k + 1] = T.sy[k];
    }
    for (int ty = r0 / tile; ty <= r1 / tile; ++ty)
      for (int tx = c0 / tile; tx <= c1 / tile; ++tx)
        atomic_inc(tileCounts + ty * tilesX + tx);
  }
}

// Fills the per-pixel candidate lists (z, id) at pixelOffsets and the per-tile lists of large
// triangles at tileOffsets; the cursors start at 0. Orders within a list vary between runs; the
// k-buffer orders by (z, id), so the result does not.
__kernel void raster_bin_fill(const int t0, const int nt, const int H, const int W, const int Ht,
                              const int Wt, const int tile, const int tilesX, const int perspective,
                              __global const REAL* verts, __global const REAL* prm,
                              __global const int* pixelOffsets, __global int* pixelCursor,
                              __global REAL* fragZ, __global int* fragId,
                              __global const int* tileOffsets, __global int* tileCursor,
                              __global int* tileList) {
  const int g = get_global_id(0);
  if (g >= nt)
    return;
  const int t = t0 + g;
  const Tri T = load_tri(t, H, W, verts, 1);
  int c0, c1, r0, r1;
  const int kind = tri_kind(&T, prm[PRM_FAR], Ht, Wt, &c0, &c1, &r0, &r1);
  if (kind == 1) {
    for (int r = r0; r <= r1; ++r)
      for (int c = c0; c <= c1; ++c)
        if (covers_pixel(&T, c, r)) {
          REAL e[3], b[3], lam[3], z;
          tri_weights(&T, (REAL)c + (REAL)0.5, (REAL)r + (REAL)0.5, perspective, e, b, lam, &z);
          const int pix = r * Wt + c;
          const int slot = pixelOffsets[pix] + atomic_inc(pixelCursor + pix);
          fragZ[slot] = z;
          fragId[slot] = t;
        }
  } else if (kind == 2) {
    for (int ty = r0 / tile; ty <= r1 / tile; ++ty)
      for (int tx = c0 / tile; tx <= c1 / tile; ++tx) {
        const int id = ty * tilesX + tx;
        tileList[tileOffsets[id] + atomic_inc(tileCursor + id)] = t;
      }
  }
}

// ---- pass 2: k-buffer -------------------------------------------------------------------------

INLINE void kbuffer_insert(REAL* zs, int* ids, int* n, const REAL z, const int t) {
  if (*n == RASTER_K && !(z < zs[RASTER_K - 1] || (z == zs[RASTER_K - 1] && t < ids[RASTER_K - 1])))
    return;
  int pos = *n < RASTER_K ? *n : RASTER_K - 1;
  while (pos > 0 && (z < zs[pos - 1] || (z == zs[pos - 1] && t < ids[pos - 1]))) {
    zs[pos] = zs[pos - 1];
    ids[pos] = ids[pos - 1];
    --pos;
  }
  zs[pos] = z;
  ids[pos] = t;
  if (*n < RASTER_K)
    ++*n;
}

// One item per pixel: keeps the RASTER_K nearest of its candidate fragments and of the covering
// large triangles of its tile, sorted by (z, id), dropping those beyond the far cut. With
// first == 0 it merges into the k-buffer a previous chunk of triangles left in kz / kid.
__kernel void raster_fragments(const int H, const int W, const int Ht, const int Wt, const int tile,
                               const int tilesX, const int first, const int perspective,
                               __global const REAL* verts, __global const REAL* prm,
                               __global const int* pixelOffsets, __global const int* pixelCounts,
                               __global const REAL* fragZ, __global const int* fragId,
                               __global const int* tileOffsets, __global const int* tileCounts,
                               __global const int* tileList, __global const REAL* rec,
                               __global REAL* kz, __global int* kid) {
  const int c = get_global_id(0), r = get_global_id(1);
  if (c >= Wt || r >= Ht)
    return;
  const int plane = Ht * Wt;
  const int pix = r * Wt + c;
  REAL zs[RASTER_K];
  int ids[RASTER_K];
  int n = 0;
  if (!first) {
    for (int k = 0; k < RASTER_K; ++k) {
      ids[k] = kid[k * plane + pix];
      zs[k] = kz[k * plane + pix];
      if (ids[k] >= 0)
        n = k + 1;
    }
  }
  const REAL far = prm[PRM_FAR];
  const int fbegin = pixelOffsets[pix], fend = fbegin + pixelCounts[pix];
  for (int e = fbegin; e < fend; ++e) {
    const REAL z = fragZ[e];
    if (!(z > far))
      kbuffer_insert(zs, ids, &n, z, fragId[e]);
  }
  const REAL px = (REAL)c + (REAL)0.5, py = (REAL)r + (REAL)0.5;
  const int tid = (r / tile) * tilesX + c / tile;
  const int tbegin = tileOffsets[tid], tend = tbegin + tileCounts[tid];
  for (int e = tbegin; e < tend; ++e) {
    const int t = tileList[e];
    __global const REAL* q = rec + 6 * t;
    const REAL x[3] = {q[0], q[2], q[4]}, y[3] = {q[1], q[3], q[5]};
    // Relative vertex order decides the canonical edge directions: v0 < v1 < v2 for the first
    // triangle of a quad, v0 < v2 < v1 for the second.
    const int second = t & 1; // 2 (H-1)(W-1) triangles per layer: an even count
    const int v[3] = {0, second ? 2 : 1, second ? 1 : 2};
    const int side = covers(x, y, v, px, py);
    if (side == 0)
      continue;
    Tri T = load_tri(t, H, W, verts, 0);
    T.orient = side; // inside: all three edge signs equal the orientation
    REAL ed[3], b[3], lam[3], z;
    tri_weights(&T, px, py, perspective, ed, b, lam, &z);
    if (!(z > far))
      kbuffer_insert(zs, ids, &n, z, t);
  }
  for (int k = 0; k < RASTER_K; ++k) {
    kid[k * plane + pix] = k < n ? ids[k] : -1;
    kz[k * plane + pix] = k < n ? zs[k] : (REAL)0;
  }
}

// out[i] = layer of fragment i (or -1), for the [K, Ht, Wt] slots.
__kernel void raster_fragment_layer(const int n, const int trianglesPerLayer,
                                    __global const int* kid, __global REAL* out) {
  const int i = get_global_id(0);
  if (i >= n)
    return;
  const int t = kid[i];
  out[i] = t < 0 ? (REAL)-1 : (REAL)(t / trianglesPerLayer);
}

// ---- pass 3: shading --------------------------------------------------------------------------

// Packed output planes [A-1 colour, opacity, depth, K weights] x Ht x Wt.
__kernel void raster_shade_forward(const int H, const int W, const int A, const int Ht,
                                   const int Wt, const int perspective, __global const REAL* verts,
                                   __global const REAL* attrs, __global const int* kid,
                                   __global REAL* out) {
  const int c = get_global_id(0), r = get_global_id(1);
  if (c >= Wt || r >= Ht)
    return;
  const int plane = Ht * Wt, pix = r * Wt + c, HW = H * W;
  const REAL px = (REAL)c + (REAL)0.5, py = (REAL)r + (REAL)0.5;
  int vv[RASTER_K * 3];
  REAL lam[RASTER_K * 3], w[RASTER_K], zk[RASTER_K];
  int n = 0;
  for (int k = 0; k < RASTER_K; ++k) {
    const int t = kid[k * plane + pix];
    if (t < 0)
      break;
    const Tri T = load_tri(t, H, W, verts, 1);
    REAL e[3], b[3];
    tri_weights(&T, px, py, perspective, e, b, lam + 3 * k, zk + k);
    for (int i = 0; i < 3; ++i)
      vv[3 * k + i] = attr_base(&T, i, A, HW);
    n = k + 1;
  }
  // Front-to-back weights; the farthest fragment is opaque.
  REAL trans = 1;
  for (int k = 0; k < n; ++k) {
    REAL a = 0;
    for (int i = 0; i < 3; ++i)
      a += lam[3 * k + i] * attrs[vv[3 * k + i] + (A - 1) * HW];
    if (k == n - 1)
      a = 1;
    w[k] = a * trans;
    trans *= (1 - a) + (REAL)T_EPS;
  }
  for (int k = n; k < RASTER_K; ++k)
    trans *= (REAL)1 + (REAL)T_EPS; // empty slots, as the reference's peeling passes
  for (int ch = 0; ch < A - 1; ++ch) {
    REAL acc = 0;
    for (int k = 0; k < n; ++k) {
      REAL f = 0;
      for (int i = 0; i < 3; ++i)
        f += lam[3 * k + i] * attrs[vv[3 * k + i] + ch * HW];
      acc += w[k] * f;
    }
    out[ch * plane + pix] = acc;
  }
  REAL dep = 0;
  for (int k = 0; k < n; ++k)
    dep += w[k] * zk[k];
  out[(A - 1) * plane + pix] = n > 0 ? 1 - trans : (REAL)0;
  out[A * plane + pix] = dep;
  for (int k = 0; k < RASTER_K; ++k)
    out[(A + 1 + k) * plane + pix] = k < n ? w[k] : (REAL)0;
}

// atomic_add_real comes from the engine's common.cl.

// Gradients of raster_shade_forward. One item per pixel recomputes its fragments and scatters
// into gattr [L, A, H, W] and gdepth [L, H, W] (both zeroed by the host) with atomic adds.
__kernel void raster_shade_backward(const int H, const int W, const int A, const int Ht,
                                    const int Wt, const int perspective, __global const REAL* verts,
                                    __global const REAL* prm, __global const REAL* attrs,
                                    __global const int* kid, __global const REAL* gout,
                                    const int wantAttr, __global REAL* gattr, const int wantDepth,
                                    __global REAL* gdepth) {
  const int c = get_global_id(0), r = get_global_id(1);
  if (c >= Wt || r >= Ht)
    return;
  const int plane = Ht * Wt, pix = r * Wt + c, HW = H * W;
  const REAL px = (REAL)c + (REAL)0.5, py = (REAL)r + (REAL)0.5;
  int vv[RASTER_K * 3];
  REAL lam[RASTER_K * 3], gl[RASTER_K * 3];
  REAL zk[RASTER_K], al[RASTER_K], tr[RASTER_K], w[RASTER_K], s[RASTER_K];
  int n = 0;
  for (int k = 0; k < RASTER_K; ++k) {
    const int t = kid[k * plane + pix];
    if (t < 0)
      break;
    const Tri T = load_tri(t, H, W, verts, 1);
    REAL e[3], b[3];
    tri_weights(&T, px, py, perspective, e, b, lam + 3 * k, zk + k);
    for (int i = 0; i < 3; ++i) {
      vv[3 * k + i] = attr_base(&T, i, A, HW);
      gl[3 * k + i] = 0;
    }
    n = k + 1;
  }
  if (n == 0)
    return; // constant outputs: no gradient
  REAL trans = 1;
  for (int k = 0; k < n; ++k) {
    REAL a = 0;
    for (int i = 0; i < 3; ++i)
      a += lam[3 * k + i] * attrs[vv[3 * k + i] + (A - 1) * HW];
    al[k] = k == n - 1 ? (REAL)1 : a;
    tr[k] = trans;
    w[k] = al[k] * trans;
    trans *= (1 - al[k]) + (REAL)T_EPS;
  }
  const REAL gOpacity = gout[(A - 1) * plane + pix];
  const REAL gDep = gout[A * plane + pix];
  for (int k = 0; k < n; ++k)
    s[k] = gDep * zk[k] + gout[(A + 1 + k) * plane + pix]; // dL/dw_k, colour part added below
  // Colour channels: dL/df_k = w_k G_ch.
  for (int ch = 0; ch < A - 1; ++ch) {
    const REAL g = gout[ch * plane + pix];
    if (g == 0)
      continue;
    for (int k = 0; k < n; ++k) {
      REAL f = 0;
      for (int i = 0; i < 3; ++i) {
        const int idx = vv[3 * k + i] + ch * HW;
        const REAL val = attrs[idx];
        f += lam[3 * k + i] * val;
        gl[3 * k + i] += w[k] * g * val;
        if (wantAttr)
          atomic_add_real(gattr + idx, lam[3 * k + i] * w[k] * g);
      }
      s[k] += g * f;
    }
  }
  // Alphas, back to front. With q_j = 1 - a_j + eps, w_m = a_m prod_{j<m} q_j:
  // dL/da_k = T_k (s_k - R_k) + G_op T_k prod_{j>k} q_j, R_k = sum_{m>k} s_m a_m prod_{k<j<m} q_j.
  REAL rsum = 0, qsuffix = 1;
  for (int k = n; k < RASTER_K; ++k)
    qsuffix *= (REAL)1 + (REAL)T_EPS;
  for (int k = n - 1; k >= 0; --k) {
    const REAL q = (1 - al[k]) + (REAL)T_EPS;
    if (k < n - 1) { // the farthest fragment's alpha is the constant 1
      const REAL ga = tr[k] * (s[k] - rsum) + gOpacity * tr[k] * qsuffix;
      for (int i = 0; i < 3; ++i) {
        const int idx = vv[3 * k + i] + (A - 1) * HW;
        gl[3 * k + i] += ga * attrs[idx];
        if (wantAttr)
          atomic_add_real(gattr + idx, lam[3 * k + i] * ga);
      }
    }
    rsum = s[k] * al[k] + q * rsum;
    qsuffix *= q;
  }
  if (!wantDepth)
    return;
  // Geometry: lam and z depend on the projected vertex positions and target z's, which depend
  // on the reference depths.
  for (int k = 0; k < n; ++k) {
    const int t = kid[k * plane + pix];
    const Tri T = load_tri(t, H, W, verts, 1);
    REAL e[3], b[3], lm[3], z;
    const REAL sum = tri_weights(&T, px, py, perspective, e, b, lm, &z);
    const REAL gz = gDep * w[k]; // dL/dz of the fragment
    REAL gb[3], gzv[3];          // dL/db_i, direct dL/dz_i
    if (perspective) {
      // lam_i = rho_i / Q, rho_i = b_i / z_i, z = 1 / Q.
      REAL q = 0, gsum = 0;
      for (int i = 0; i < 3; ++i) {
        q += b[i] / T.z[i];
        gsum += gl[3 * k + i] * lm[i];
      }
      for (int i = 0; i < 3; ++i) {
        const REAL grho = (gl[3 * k + i] - gsum) / q - gz / (q * q);
        gb[i] = grho / T.z[i];
        gzv[i] = -grho * b[i] / (T.z[i] * T.z[i]);
      }
    } else {
      for (int i = 0; i < 3; ++i) {
        gb[i] = gl[3 * k + i] + gz * T.z[i];
        gzv[i] = gz * b[i];
      }
    }
    REAL gx[3] = {0, 0, 0}, gy[3] = {0, 0, 0};
    if (sum > 0) {
      // b_i = max(o e_i, 0) / sum_j max(o e_j, 0).
      REAL bg = 0;
      for (int i = 0; i < 3; ++i)
        bg += b[i] * gb[i];
      for (int i = 0; i < 3; ++i) {
        if (!((REAL)T.orient * e[i] > 0))
          continue;
        const REAL ge = (REAL)T.orient * (gb[i] - bg) / sum;
        const int a = (i + 1) % 3, cc = (i + 2) % 3;
        // e_i = (x_c - x_a)(py - y_a) - (y_c - y_a)(px - x_a)
        gx[a] += ge * (T.y[cc] - py);
        gy[a] += ge * (px - T.x[cc]);
        gx[cc] += ge * (py - T.y[a]);
        gy[cc] += ge * (T.x[a] - px);
      }
    }
    for (int i = 0; i < 3; ++i) {
      const int v = T.v[i];
      int vi, vj;
      tri_vertex_ij(&T, i, &vi, &vj);
      REAL ax, ay, az;
      vertex_direction(vi, vj, H, W, prm, &ax, &ay, &az);
      // x_pix = Fx X/Z + Cx with (X, Y, Z) = d a + t.
      const REAL dxd = (prm[PRM_FX] * ax - (T.x[i] - prm[PRM_CX]) * az) / T.z[i];
      const REAL dyd = (prm[PRM_FY] * ay - (T.y[i] - prm[PRM_CY]) * az) / T.z[i];
      const REAL gd = gx[i] * dxd + gy[i] * dyd + gzv[i] * az;
      if (gd != 0)
        atomic_add_real(gdepth + v, gd);
    }
  }
}
