// Forward-only rendering of the adaptive display form of an MLI (textured triangle meshes per
// layer); the rules are documented in model/include/simpli/model/raster/render_adaptive.h.
// One pass, raster_adaptive_shade: one work item per target pixel walks the triangles binned to
// its screen tile (layer by layer, back to front), keeps the nearest covering fragment of each
// layer, samples that layer's texture there and composites it over what is behind.

#pragma OPENCL FP_CONTRACT OFF

#define INLINE inline __attribute__((always_inline))

// Per-triangle record written by render_adaptive.cpp (same order): for each of the 3 vertices
// x, y (target pixels), z (target camera), then gx, gy (corner-grid texel position).
#define TRI_STRIDE 15

// Bilinear sample of channel plane `plane` (H x W, row-major) at corner-grid position (gx, gy),
// clamped to the grid (texel (i, j) sits at (j, i)).
INLINE REAL sample_bilinear(__global const REAL* plane, const int H, const int W, REAL gx,
                            REAL gy) {
  gx = clamp(gx, (REAL)0, (REAL)(W - 1));
  gy = clamp(gy, (REAL)0, (REAL)(H - 1));
  const int j0 = min((int)floor(gx), W - 2), i0 = min((int)floor(gy), H - 2);
  const REAL s = gx - (REAL)j0, t = gy - (REAL)i0;
  const REAL a = plane[i0 * W + j0], b = plane[i0 * W + j0 + 1];
  const REAL c = plane[(i0 + 1) * W + j0], d = plane[(i0 + 1) * W + j0 + 1];
  return (1 - t) * ((1 - s) * a + s * b) + t * ((1 - s) * c + s * d);
}

// Perspective-correct interpolation at pixel centre (px, py) of triangle `tri`: false when the
// centre is outside (edges inclusive); else its target z and grid position.
INLINE bool cover(__global const REAL* tri, const REAL px, const REAL py, REAL* z, REAL* gx,
                  REAL* gy) {
  const REAL x0 = tri[0], y0 = tri[1], x1 = tri[5], y1 = tri[6], x2 = tri[10], y2 = tri[11];
  const REAL area = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0);
  if (area == 0)
    return false;
  REAL b0 = ((x1 - px) * (y2 - py) - (x2 - px) * (y1 - py)) / area;
  REAL b1 = ((x2 - px) * (y0 - py) - (x0 - px) * (y2 - py)) / area;
  REAL b2 = ((x0 - px) * (y1 - py) - (x1 - px) * (y0 - py)) / area;
  if (b0 < 0 || b1 < 0 || b2 < 0)
    return false;
  const REAL w0 = b0 / tri[2], w1 = b1 / tri[7], w2 = b2 / tri[12];
  const REAL sum = w0 + w1 + w2;
  *z = 1 / sum;
  *gx = (w0 * tri[3] + w1 * tri[8] + w2 * tri[13]) / sum;
  *gy = (w0 * tri[4] + w1 * tri[9] + w2 * tri[14]) / sum;
  return true;
}

// Composites layer `layer`'s fragment at grid position (gx, gy) over (colour, opacity); the
// first fragment of the pixel (the farthest) is opaque.
INLINE void composite(__global const REAL* rgba, const int layer, const int H, const int W,
                      const REAL gx, const REAL gy, REAL* colour, REAL* opacity, bool* any) {
  const int HW = H * W;
  __global const REAL* base = rgba + (size_t)layer * 4 * HW;
  REAL a = *any ? sample_bilinear(base + 3 * HW, H, W, gx, gy) : (REAL)1;
  for (int ch = 0; ch < 3; ++ch)
    colour[ch] = a * sample_bilinear(base + ch * HW, H, W, gx, gy) + (1 - a) * colour[ch];
  *opacity = a + (1 - a) * *opacity;
  *any = true;
}

__kernel void raster_adaptive_shade(const int H, const int W, const int Ht, const int Wt,
                                    const int tile, const int tilesX,
                                    __global const REAL* tris, __global const int* triLayer,
                                    __global const int* tileStart, __global const int* tileTris,
                                    __global const REAL* rgba, __global REAL* out) {
  const int c = get_global_id(0), r = get_global_id(1);
  if (c >= Wt || r >= Ht)
    return;
  const REAL px = (REAL)c + (REAL)0.5, py = (REAL)r + (REAL)0.5;
  const int t = (r / tile) * tilesX + c / tile;
  REAL colour[3] = {0, 0, 0}, opacity = 0;
  bool any = false;
  int layer = -1;
  REAL bestZ = 0, bestX = 0, bestY = 0;
  bool have = false;
  for (int e = tileStart[t]; e < tileStart[t + 1]; ++e) {
    const int tri = tileTris[e];
    const int l = triLayer[tri];
    if (l != layer) { // the list is in layer order: the previous layer is complete
      if (have)
        composite(rgba, layer, H, W, bestX, bestY, colour, &opacity, &any);
      layer = l;
      have = false;
    }
    REAL z, gx, gy;
    if (cover(tris + (size_t)tri * TRI_STRIDE, px, py, &z, &gx, &gy) && (!have || z < bestZ)) {
      bestZ = z;
      bestX = gx;
      bestY = gy;
      have = true;
    }
  }
  if (have)
    composite(rgba, layer, H, W, bestX, bestY, colour, &opacity, &any);
  const int plane = Ht * Wt, pix = r * Wt + c;
  for (int ch = 0; ch < 3; ++ch)
    out[ch * plane + pix] = colour[ch];
  out[3 * plane + pix] = opacity;
}
