#pragma once
// A handheld-like forward-facing capture: N cameras that all look roughly along world +z,
// with centres on a smooth wobbly sweep (mostly in the image plane, a little along z) plus
// small per-view jitter, and small smooth rotations. Centres are recentred on their mean
// (the world origin) and scaled so that the farthest lies exactly `maxOffset` from it.
#include "simpli/model/scene/camera.h"
#include "simpli/model/synthetic/random.h"

#include <vector>

namespace simpli::synthetic {

struct CameraPathParams {
  int views = 12;
  int width = 192, height = 128;
  double fx = 0.866, fy = 1.3;     ///< relative focal lengths
  double maxOffset = 0.08;         ///< largest distance of a centre from the mean centre
  double maxRotationDegrees = 1.5; ///< bound on |yaw|, |pitch|, |roll| of every view
};

/// World->camera cameras (OpenCV axes, relative intrinsics, cx = cy = 0.5).
std::vector<scene::Camera> makeCameraPath(const CameraPathParams& params, Random& rng);

/// Yaw (about camera y), pitch (about x) and roll (about z), in radians, of a camera-to-world
/// rotation built as Ry(yaw) Rx(pitch) Rz(roll) — the decomposition makeCameraPath uses.
Eigen::Vector3d yawPitchRoll(const Eigen::Matrix3d& cameraToWorld);

} // namespace simpli::synthetic
