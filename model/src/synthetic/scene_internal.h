#pragma once
// What the two scene styles share (scene.cpp: the objects style, scene_world.cpp: the world
// style): random streams, frames, object shapes, photo textures.
#include "simpli/model/synthetic/camera_path.h"
#include "simpli/model/synthetic/scene.h"

#include <Eigen/Core>

#include <cmath>
#include <memory>
#include <vector>

namespace simpli::synthetic::detail {

constexpr double kDeg = M_PI / 180.0;
/// The world style's far plane (scenes without sky) tilts by at most this.
constexpr double kWorldMaxSlantDegrees = 20.0;

// Independent random streams derived from the scene seed (the renderer's jitter is 7).
enum Stream : uint64_t {
  kCameras = 2,
  kBackground = 3,
  kKinds = 4,
  kObjects = 5,
  kLight = 6,
  kWorldLayout = 8,
  kPhotoTextures = 9,
  kSky = 10,
  kThin = 11,
  kBushes = 12,
};

/// Ry(yaw) Rx(pitch) Rz(roll).
Eigen::Matrix3d rotation(double yaw, double pitch, double roll);

/// The camera path of a scene with these params (fx, fy from params.fovDegrees, offsets
/// translation * nearDepth, rotations rotationDegrees).
CameraPathParams pathParams(const SyntheticSceneParams& p);

/// The shape of one object of the given role, centred at the origin, `scale` = half the
/// apparent size in scene units at its depth; `pixel` = scene units per pixel there.
Shape makeObjectShape(ShapeRole role, double scale, double pixel, Random& rng);

/// Log-uniform in [lo, hi] (lo > 0), or lo when hi == lo.
double logUniform(Random& rng, double lo, double hi);

/// Gives shape number `index` of the scene (0 = background, i + 1 = objects[i]) a photo texture
/// with probability params.photoProbability when the params use photos; `unitsPerPixel` is the
/// size of an image pixel on the surface. Draws from its own stream (kPhotoTextures, index),
/// so the procedural draws of the shape are unchanged either way.
void maybePhotoTexture(const SyntheticSceneParams& p, uint64_t index, double unitsPerPixel,
                       bool upright, Shape& shape);

/// Every photo of params.photos (usesPhotos() must hold).
std::vector<std::shared_ptr<const Photo>> allPhotos(const SyntheticSceneParams& p);

/// The light over the photographer's shoulder (stream kLight).
Eigen::Vector3d randomLightDirection(uint64_t seed);

/// The world-style generator (scene_world.cpp); params validated, style World.
SyntheticScene generateWorldScene(const SyntheticSceneParams& params);

} // namespace simpli::synthetic::detail
