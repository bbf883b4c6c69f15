#pragma once
// The reference camera in which SIMPLI builds its planes and layers (spec §6.1):
// rotation = average of the source world->camera rotations by Markley's method, centre = mean
// of the source camera centres, intrinsics and image size of source view 0.
#include "simpli/model/scene/camera.h"

#include <Eigen/Geometry>

#include <vector>

namespace simpli::scene {

/// Markley et al. (2007) quaternion average: the unit eigenvector of the largest eigenvalue of
/// sum_v q_v q_v^T. The result does not depend on the signs of the inputs (q and -q are the same
/// rotation); the output's sign is fixed to w > 0 (or, when w == 0, to the first non-zero of
/// x, y, z positive) so that the result is deterministic. Throws simpli::Error when empty.
Eigen::Quaterniond averageRotation(const std::vector<Eigen::Matrix3d>& rotations);

/// The reference camera of a set of source cameras; throws simpli::Error when empty.
Camera referenceCamera(const std::vector<Camera>& sources);

/// The widest margin widenedCamera takes: the frame doubled in width and height.
inline constexpr double maxReferenceMargin = 0.5;
/// The margin `simpli infer` / `eval` and vtkSIMPLIBuildMLI use unless told otherwise (the library
/// and the reference use 0). Flower, rff protocol, shipped network, paired over 160 views at 5
/// sources: 0 -> 0.06 +0.83 dB; 0.03, 0.1 and 0.15 score 0.15, 0.05 and 0.12 dB below 0.06.
inline constexpr double recommendedReferenceMargin = 0.06;

/// `camera` with its image widened by `margin` x its width (height) on every side, on the same
/// pixel grid: relative fx, fy divided by 1 + 2 margin, the principal point moved to match, so
/// a point at relative u maps to (u + margin) / (1 + 2 margin). An MLI built on the widened
/// reference also covers what novel views off to the side see beyond the sources' frame (flower,
/// 5 sources at 256x192, margin 0.06: +0.77 +- 0.48 dB over 32 views, docs/training.md).
/// margin 0 returns `camera`; throws simpli::Error unless 0 <= margin <= maxReferenceMargin.
Camera widenedCamera(const Camera& camera, double margin);

} // namespace simpli::scene
