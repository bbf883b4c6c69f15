#pragma once
// Random forward-facing scenes with exact geometry: a textured background plane (fronto-
// parallel or slanted) and textured objects in front of it — fronto-parallel and slanted
// rectangles, boxes, spheres, and thin poles and wires (thin cylinders) — at random depths,
// overlapping so that nearer objects occlude farther ones; plus a handheld-like path of cameras
// looking along +z (camera_path.h). Everything follows from the seed (random.h explains why
// the distributions are our own).
//
// Units and frames: world = the OpenCV frame of the mean camera (x right, y down, z forward),
// scene units with the nearest object at depth >= nearDepth. Cameras: simpli::Camera
// (world->camera R, t; relative intrinsics; square pixels; principal point at the centre).
#include "simpli/model/scene/camera.h"
#include "simpli/model/synthetic/shapes.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace simpli::synthetic {

struct SyntheticSceneParams {
  uint64_t seed = 0;
  int views = 12;
  int width = 192, height = 128;           ///< pixels (the network needs multiples of 16)
  int objects = 8;                         ///< objects in front of the background
  double fovDegrees = 60.0;                ///< horizontal field of view
  double nearDepth = 2.0;                  ///< objects are placed at depths >= this (scene units)
  double backgroundDepthMin = 10.0;        ///< background depth on the optical axis: uniform in
  double backgroundDepthMax = 16.0;        ///< [min, max] (scene units)
  double maxBackgroundSlantDegrees = 25.0; ///< tilt of the background plane's normal from -z
  /// Camera centres lie within translation * nearDepth of their mean (exactly that far for the
  /// farthest one); the motion is mostly in the image plane.
  double translation = 0.04;
  double rotationDegrees = 1.5; ///< bound on each camera's yaw, pitch and roll
  int antialias = 4;            ///< antialias^2 jittered samples per pixel (1 = centre only)

  /// Throws simpli::Error naming the field and value when a parameter is out of range.
  void validate() const;
  /// Relative focal lengths for square pixels: fx = 0.5 / tan(fov / 2), fy = fx * width / height.
  double fx() const;
  double fy() const;
};

struct SyntheticScene {
  SyntheticSceneParams params;
  Shape background; ///< ShapeKind::Plane
  std::vector<Shape> objects;
  Eigen::Vector3d lightDirection = Eigen::Vector3d(0, 0, -1); ///< unit, towards the light
  std::vector<scene::Camera> cameras;

  /// Background first (index 0), then the objects (index i + 1) — the indices SurfaceHit uses.
  const Shape& shape(int index) const {
    return index == 0 ? background : objects[size_t(index) - 1];
  }
  int shapeCount() const { return int(objects.size()) + 1; }
};

/// Generates the scene for params.seed (validating the parameters first). Objects, cameras and
/// textures come from separate streams derived from the seed, so changing --views keeps the
/// geometry and changing --objects keeps the cameras and the first objects.
SyntheticScene generateSyntheticScene(const SyntheticSceneParams& params);

/// A scene with the given background and objects and the params' camera path; for tests and
/// hand-built scenes (no randomness except the cameras, which come from params.seed).
SyntheticScene makeSyntheticScene(const SyntheticSceneParams& params, const Shape& background,
                                  const std::vector<Shape>& objects);

} // namespace simpli::synthetic
