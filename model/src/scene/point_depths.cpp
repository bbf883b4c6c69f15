// visiblePointDepths: the SfM points a view sees, as camera-space depths (for bounds and for
// the reference's p10 scene scaling).
#include "simpli/model/scene/readers.h"

namespace simpli::scene {

std::vector<double> visiblePointDepths(const Camera& camera,
                                       const std::vector<Eigen::Vector3d>& points) {
  std::vector<double> depths;
  for (const Eigen::Vector3d& X : points) {
    const Eigen::Vector3d Xc = camera.worldToCamera(X);
    if (!(Xc.z() > 0))
      continue;
    const double u = camera.fx * Xc.x() / Xc.z() + camera.cx;
    const double v = camera.fy * Xc.y() / Xc.z() + camera.cy;
    // Points outside the frustum are not part of what the view sees; including them would let
    // geometry beside the camera pull the near bound towards 0.
    if (u >= 0 && u <= 1 && v >= 0 && v <= 1)
      depths.push_back(Xc.z());
  }
  return depths;
}

} // namespace simpli::scene
