#pragma once
// Camera trajectories for novel-view videos around a reference camera, like LLFF's spiral
// renders and the SIMPLI paper's user-study paths. Everything is expressed in the reference
// camera's frame (OpenCV axes: x right, y down, z forward; spec §1.2):
//
//  * Spiral (LLFF's render_path_spiral): for s = i / N, theta = 2 pi turns s, the centre is
//    C_ref + R_ref^T (rx cos theta, -ry sin theta, -rz sin(theta zRate)) — with the defaults
//    turns = 2 and zRate = 0.5 the depth term makes exactly one period, so the path is closed
//    (s = 1 gives the pose of s = 0).
//  * Orbit: one turn on the ellipse C_ref + R_ref^T (rx cos theta, ry sin theta, 0) in the
//    reference camera's image plane (constant depth), theta = 2 pi s.
//
// Every camera looks at the focus point F = C_ref + focusDepth * (reference viewing axis), so F
// projects to the principal point (cx, cy) of every frame; "down" follows the reference
// camera's +y as closely as the new viewing axis allows (no roll about it). Intrinsics and image
// size are the reference camera's.
//
// Defaults from the scene (trajectoryRadii, trajectoryFocusDepth) follow LLFF: radii = the 90th
// percentile of |camera centre offset| per axis in the reference frame; focus depth =
// 1 / ((1 - 0.75) / near + 0.75 / far), a disparity-weighted depth between the bounds.
#include "simpli/model/scene/camera.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace simpli::scene {

enum class TrajectoryKind { Spiral, Orbit };

const char* toString(TrajectoryKind kind); ///< "spiral", "orbit"
/// "spiral" or "orbit" (case-sensitive); throws simpli::Error naming the value otherwise.
TrajectoryKind parseTrajectoryKind(const std::string& name);

struct TrajectoryOptions {
  TrajectoryKind kind = TrajectoryKind::Spiral;
  int frames = 60; ///< N >= 1 frames, s = i / N for i = 0 .. N-1 (the closing pose is left out)
  /// Path radii along the reference camera's x, y, z (world units, >= 0, not all 0; orbit
  /// ignores z).
  Eigen::Vector3d radii = Eigen::Vector3d::Zero();
  double focusDepth = 0; ///< reference-camera z of the look-at point, > 0
  double turns = 2.0;    ///< spiral turns (LLFF: 2), > 0
  double zRate = 0.5;    ///< spiral depth frequency relative to the turns (LLFF: 0.5)
};

/// Throws simpli::Error naming the field and the value when `options` or `reference` cannot
/// make a trajectory: frames < 1, radii negative / non-finite / all zero, focusDepth <= 0 or
/// non-finite, turns <= 0, non-finite zRate, reference without a positive image size.
void validateTrajectory(const Camera& reference, const TrajectoryOptions& options);

/// The pose at path parameter s (0 = start, 1 = one full path; any real s is accepted).
Camera trajectoryCamera(const Camera& reference, const TrajectoryOptions& options, double s);

/// The N cameras of the path (validated first).
std::vector<Camera> makeTrajectory(const Camera& reference, const TrajectoryOptions& options);

/// LLFF's radii: per axis of the reference frame, the 90th percentile of |R_ref (C_v - C_ref)|
/// over the cameras. Zero for fewer than two distinct centres. Throws for no cameras.
Eigen::Vector3d trajectoryRadii(const Camera& reference, const std::vector<Camera>& cameras);

/// LLFF's focus depth 1 / ((1 - 0.75) / near + 0.75 / far); throws unless 0 < near <= far.
double trajectoryFocusDepth(double near, double far);

/// `options` with its automatic fields filled in: focusDepth <= 0 becomes
/// trajectoryFocusDepth(near, far); all-zero radii become trajectoryRadii(reference, cameras)
/// (the scene's cameras; may be empty), and when those are all zero too (no cameras, or all
/// at one centre) a small default motion of (0.05, 0.05, 0.025) x focusDepth. Explicit values
/// are kept as given. The result is validated (validateTrajectory).
TrajectoryOptions resolveTrajectory(TrajectoryOptions options, const Camera& reference,
                                    const std::vector<Camera>& cameras, double near, double far);

} // namespace simpli::scene
