#pragma once
// Triangle meshes of an MLI (spec §6.6, §10.3): one vertex per texel, on the
// corner grid u = j/(W-1), v = i/(H-1), back-projected at the texel depth through the reference
// camera into world coordinates; two triangles per texel quad, (b, b+W, b+W+1) and
// (b, b+W+1, b+1) with b = i*W + j, so the diagonal joins top-left and bottom-right.
#include <cstdint>
#include <vector>

#include "simpli/model/mli/mli.h"

namespace simpli::mli {

struct MLIMeshOptions {
  /// A triangle is dropped when the alphas of all three of its vertices are below this value.
  /// 0 (the default) drops nothing and reproduces the reference mesh exactly; 1/255 drops the
  /// triangles that an 8-bit export would make fully transparent. Vertices are never dropped,
  /// so vertex indices stay one-to-one with texels.
  float dropAlphaBelow = 0.0f;
};

struct MLIMesh {
  std::vector<float> points;           ///< N x 3 world coordinates
  std::vector<float> rgba;             ///< N x 4 straight RGBA in [0, 1] (texel values)
  std::vector<float> depth;            ///< N reference-camera z (texel depth)
  std::vector<float> uv;               ///< N x 2 corner-grid (u, v), v pointing down the image
  std::vector<std::int32_t> triangles; ///< F x 3 vertex indices into this mesh

  std::size_t numPoints() const { return depth.size(); }
  std::size_t numTriangles() const { return triangles.size() / 3; }
};

/// All layers as one mesh (the reference's representation): layer k's vertices are
/// k*H*W .. (k+1)*H*W - 1, layers in index order (back to front). Validates `mli` first.
MLIMesh buildMLIMesh(const MLI& mli, const MLIMeshOptions& options = {});

/// Layer `k` alone, indices starting at 0 (one vtkPolyData per layer). Validates `mli` first.
MLIMesh buildLayerMesh(const MLI& mli, int k, const MLIMeshOptions& options = {});

/// Reference-camera back-projection of corner-grid texel (i, j) at depth d, in world
/// coordinates: Xc = d ((u - cx)/fx, (v - cy)/fy, 1), Xw = R^T (Xc - t).
Eigen::Vector3d mliVertex(const scene::Camera& camera, int i, int j, double d);

} // namespace simpli::mli
