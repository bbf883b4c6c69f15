#pragma once
// Scene normalisation: one global scale s applied to all translations (and to depths, bounds
// and points), so that the scene sits where the network expects it. Rotations and relative
// intrinsics are scale-free and stay as they are.
//
// Why: the reference network always places its planes at depths 1..100 (disparity-uniform,
// spec §6.2, §9.3) and never adapts them to a scene. Instead its datasets divide
// translations by p10 / 1.25, where p10 is the 10th percentile of the SfM point depths over all
// views (§9.2), so that the near part of every scene lands just beyond the nearest plane.
//
// Our rule (NormalisationMode::Auto):
//  * when SfM points are available (COLMAP points3D.txt): the reference's rule,
//    s = pointTarget / percentile(depths of the points seen by the views, pointPercentile),
//    defaults 1.25 and 10;
//  * otherwise: s = minDepth / near, so that the scene's near bound lands on the network's
//    nearest plane (minDepth, default 1.0). For LLFF the near bound is LLFF's own low
//    percentile of point depths, so both rules aim at the same thing.
// The scale is stored in the Scene; the functions below map back to scene units exactly.
#include "simpli/model/scene/camera.h"

#include <string>
#include <vector>

namespace simpli::scene {

enum class NormalisationMode {
  Auto,           ///< PointPercentile when points are available, NearBound otherwise
  None,           ///< s = 1: keep scene units
  NearBound,      ///< s = minDepth / near
  PointPercentile ///< s = pointTarget / percentile(point depths, pointPercentile)
};

struct NormalisationOptions {
  NormalisationMode mode = NormalisationMode::Auto;
  double minDepth = 1.0;         ///< network's nearest plane depth (reference: 1)
  double pointPercentile = 10.0; ///< reference: p_10
  double pointTarget = 1.25;     ///< reference: scale_constant 1.25 (training data)
};

struct Normalisation {
  NormalisationMode rule = NormalisationMode::None; ///< the rule actually used (never Auto)
  double scale = 1.0;                               ///< normalised = scale * scene units
  double anchorScene = 0;  ///< the scene-unit depth that was mapped (near bound or percentile)
  double anchorTarget = 0; ///< ... onto this normalised depth

  double toNormalised(double sceneDepth) const { return scale * sceneDepth; }
  double toScene(double normalisedDepth) const { return normalisedDepth / scale; }
  Eigen::Vector3d toNormalised(const Eigen::Vector3d& scenePoint) const {
    return scale * scenePoint;
  }
  Eigen::Vector3d toScene(const Eigen::Vector3d& point) const { return point / scale; }
  Camera toNormalised(const Camera& sceneCamera) const;
  Camera toScene(const Camera& normalisedCamera) const;
  std::string describe() const; ///< one line, e.g. "near bound 2.5 -> 1 (scale 0.4)"
};

const char* toString(NormalisationMode mode);

/// Chooses the scale from the scene-unit near bound and the scene-unit depths of the SfM points
/// seen by the views (empty when the format has no points). Throws simpli::Error when the
/// chosen anchor is not positive (e.g. PointPercentile without points).
Normalisation chooseNormalisation(const NormalisationOptions& options, double sceneNear,
                                  const std::vector<double>& pointDepths);

/// Linear-interpolation percentile (numpy's default), p in [0, 100]. Throws for empty input.
double percentile(std::vector<double> values, double p);

} // namespace simpli::scene
