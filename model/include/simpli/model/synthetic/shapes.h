#pragma once
// Geometric primitives of the synthetic scenes and their exact ray intersections.
//
// Every shape lives in a local frame: centre + orthonormal axes (columns of `axes` are the local
// x, y, z directions in world coordinates). Ray parameters are preserved by the rigid change
// of frame, so a hit's `t` is the same in both frames. Rays need not be unit length: the
// renderer uses camera-space directions with z = 1, for which t is exactly the hit's
// camera-space z (the depth the reference uses).
#include "simpli/model/synthetic/texture.h"

#include <Eigen/Core>

#include <limits>

namespace simpli::synthetic {

enum class ShapeKind {
  Plane,     ///< infinite plane local z = 0 (two-sided)
  Rectangle, ///< local z = 0, |x| <= size.x, |y| <= size.y (two-sided)
  Box,       ///< |x| <= size.x, |y| <= size.y, |z| <= size.z
  Sphere,    ///< radius size.x; polar axis local z
  Cylinder,  ///< radius size.x, axis local z, |z| <= size.z, capped
  /// local z = 0, |x| <= size.x, |y| <= size.y (1 - (x / size.x)^2) (two-sided): a pointed
  /// leaf, the region between two parabolas (convex)
  Leaf,
};

/// What the generator meant a shape to be (recorded in scene.json; used by tests).
/// Distant: a wall of the world style's skyline; Post: a thin vertical box; Branch: a thin box
/// of a branch (a limb and its twigs); Leaf: one leaf of a bush.
enum class ShapeRole {
  Background,
  FrontoPlane,
  SlantedPlane,
  Box,
  Sphere,
  Pole,
  Wire,
  Distant,
  Post,
  Branch,
  Leaf
};

const char* toString(ShapeKind kind);
const char* toString(ShapeRole role);

struct Ray {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ(); ///< any non-zero length
};

struct SurfaceHit {
  double t = std::numeric_limits<double>::infinity(); ///< ray parameter; inf = no hit
  Eigen::Vector2d st = Eigen::Vector2d::Zero();       ///< surface coordinates (scene units)
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  ///< world, unit, outward (planes: +z local)
  int shape = -1;                                     ///< index set by the caller
  bool hit() const { return t < std::numeric_limits<double>::infinity(); }
};

struct Shape {
  ShapeKind kind = ShapeKind::Plane;
  ShapeRole role = ShapeRole::Background;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity(); ///< columns: local x, y, z in world
  Eigen::Vector3d size = Eigen::Vector3d::Ones();     ///< see ShapeKind
  Texture texture;

  /// If the ray meets the shape at a parameter in (tMin, hit.t), overwrites hit.t, st and normal
  /// and returns true; otherwise leaves `hit` unchanged. Texture coordinates: planes and
  /// rectangles (x, y); box faces the two in-face local coordinates plus a per-face offset;
  /// spheres and cylinder sides (radius * longitude, latitude * radius or z) with the longitude
  /// seam on the local +y side, which the generator turns away from the cameras.
  bool intersect(const Ray& ray, double tMin, SurfaceHit& hit) const;

  /// Radius of a sphere around `centre` that holds the shape (infinity for a plane).
  double boundingRadius() const;

  /// Support function: max over the shape's points X of dir . (X - centre), i.e. how far the
  /// shape reaches along `dir` (unit) from its centre; exact for every kind (infinity for a
  /// plane unless dir is its normal). Used to keep objects in front of the background and
  /// beyond the near depth.
  double extent(const Eigen::Vector3d& dir) const;
};

/// Orthonormal right-handed frame whose local z is `axis` and whose local y points as much as
/// possible along `away` (which must not be parallel to `axis`).
Eigen::Matrix3d frameFromAxis(const Eigen::Vector3d& axis, const Eigen::Vector3d& away);

} // namespace simpli::synthetic
