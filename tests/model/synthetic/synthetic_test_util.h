#pragma once
// Helpers shared by the synthetic-scene tests: flat-colour textures and simple scenes for analytic
// checks (temporary folders: tests/support).
#include "simpli/model/synthetic/scene.h"
#include "support/temp_dir.h"

#include <gtest/gtest.h>

#include <string>

namespace simpli::test {

/// A texture of one flat colour (no pattern contrast, no detail noise).
inline synthetic::Texture flatTexture(double r, double g, double b) {
  synthetic::Texture t;
  t.pattern = synthetic::Pattern::Noise;
  t.colourA = t.colourB = Eigen::Vector3d(r, g, b);
  t.detail = 0;
  return t;
}

/// An infinite fronto-parallel plane at world depth z.
inline synthetic::Shape frontoPlane(double z, const synthetic::Texture& texture) {
  synthetic::Shape s;
  s.kind = synthetic::ShapeKind::Plane;
  s.role = synthetic::ShapeRole::Background;
  s.centre = Eigen::Vector3d(0, 0, z);
  s.texture = texture;
  return s;
}

/// A fronto-parallel rectangle centred at `centre` with half extents hx, hy.
inline synthetic::Shape frontoRectangle(const Eigen::Vector3d& centre, double hx, double hy,
                                        const synthetic::Texture& texture) {
  synthetic::Shape s;
  s.kind = synthetic::ShapeKind::Rectangle;
  s.role = synthetic::ShapeRole::FrontoPlane;
  s.centre = centre;
  s.size = Eigen::Vector3d(hx, hy, 0);
  s.texture = texture;
  return s;
}

/// Params for hand-built scenes: small images, the camera path still random (from `seed`).
inline synthetic::SyntheticSceneParams smallParams(int width, int height, int views = 3,
                                                   uint64_t seed = 1) {
  synthetic::SyntheticSceneParams p;
  p.width = width;
  p.height = height;
  p.views = views;
  p.seed = seed;
  p.objects = 0;
  return p;
}

} // namespace simpli::test
