#pragma once
// Cameras for tests: a pinhole at the origin.
#include "simpli/model/scene/camera.h"

namespace simpli::test {

/// A camera at the world origin looking down +z (identity pose) with relative intrinsics.
inline scene::Camera pinholeCamera(int width, int height, double fx, double fy, double cx,
                                   double cy) {
  scene::Camera c;
  c.width = width;
  c.height = height;
  c.fx = fx;
  c.fy = fy;
  c.cx = cx;
  c.cy = cy;
  return c;
}

} // namespace simpli::test
