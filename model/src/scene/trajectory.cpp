#include "simpli/model/scene/trajectory.h"

#include "simpli/error.h"
#include "simpli/model/scene/normalisation.h"

#include <Eigen/Geometry>

#include <cmath>

namespace simpli::scene {

namespace {

constexpr double kPi = 3.14159265358979323846;

bool finite(const Eigen::Vector3d& v) {
  return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z());
}

// World->camera pose at centre C looking at F, keeping "down" as close to `down` as possible.
Camera lookAt(const Camera& reference, const Eigen::Vector3d& C, const Eigen::Vector3d& F,
              const Eigen::Vector3d& down) {
  const Eigen::Vector3d z = (F - C).normalized();
  // OpenCV axes: x = y cross z; with y ~ down this gives x = down cross z (right-handed).
  Eigen::Vector3d x = down.cross(z);
  if (x.norm() < 1e-12)
    fail("trajectory: the viewing direction is parallel to the reference camera's down axis");
  x.normalize();
  const Eigen::Vector3d y = z.cross(x);
  Camera cam = reference;
  cam.R.row(0) = x.transpose();
  cam.R.row(1) = y.transpose();
  cam.R.row(2) = z.transpose();
  cam.t = -cam.R * C;
  return cam;
}

} // namespace

const char* toString(TrajectoryKind kind) {
  return kind == TrajectoryKind::Orbit ? "orbit" : "spiral";
}

TrajectoryKind parseTrajectoryKind(const std::string& name) {
  if (name == "spiral")
    return TrajectoryKind::Spiral;
  if (name == "orbit")
    return TrajectoryKind::Orbit;
  fail("unknown trajectory '", name, "' (expected spiral or orbit)");
}

void validateTrajectory(const Camera& reference, const TrajectoryOptions& o) {
  if (o.frames < 1)
    fail("trajectory: frames = ", o.frames, ", need at least 1");
  if (!finite(o.radii) || o.radii.minCoeff() < 0)
    fail("trajectory: radii (", o.radii.x(), ", ", o.radii.y(), ", ", o.radii.z(),
         ") must be finite and >= 0");
  const double used =
      o.kind == TrajectoryKind::Orbit ? o.radii.head<2>().maxCoeff() : o.radii.maxCoeff();
  if (used <= 0)
    fail("trajectory: radii (", o.radii.x(), ", ", o.radii.y(), ", ", o.radii.z(),
         ") are all 0 for the ", toString(o.kind), " path",
         " (give radii, or cameras whose centres differ)");
  if (!(std::isfinite(o.focusDepth) && o.focusDepth > 0))
    fail("trajectory: focus depth = ", o.focusDepth, ", must be finite and > 0");
  if (!(std::isfinite(o.turns) && o.turns > 0))
    fail("trajectory: turns = ", o.turns, ", must be finite and > 0");
  if (!std::isfinite(o.zRate))
    fail("trajectory: zRate = ", o.zRate, ", must be finite");
  if (reference.width <= 0 || reference.height <= 0)
    fail("trajectory: reference camera image size ", reference.width, " x ", reference.height,
         " is not positive");
  if (!finite(reference.t) || !reference.R.allFinite())
    fail("trajectory: the reference camera's pose is not finite");
}

Camera trajectoryCamera(const Camera& reference, const TrajectoryOptions& o, double s) {
  const Eigen::Vector3d Cref = reference.centre();
  const Eigen::Matrix3d Rt = reference.R.transpose(); // reference frame -> world directions
  Eigen::Vector3d offset;                             // in the reference frame
  if (o.kind == TrajectoryKind::Spiral) {
    const double theta = 2.0 * kPi * o.turns * s;
    offset = Eigen::Vector3d(o.radii.x() * std::cos(theta), -o.radii.y() * std::sin(theta),
                             -o.radii.z() * std::sin(theta * o.zRate));
  } else {
    const double theta = 2.0 * kPi * s;
    offset = Eigen::Vector3d(o.radii.x() * std::cos(theta), o.radii.y() * std::sin(theta), 0.0);
  }
  const Eigen::Vector3d C = Cref + Rt * offset;
  const Eigen::Vector3d F = Cref + o.focusDepth * Rt.col(2);
  return lookAt(reference, C, F, Rt.col(1));
}

std::vector<Camera> makeTrajectory(const Camera& reference, const TrajectoryOptions& options) {
  validateTrajectory(reference, options);
  std::vector<Camera> cameras;
  cameras.reserve(static_cast<std::size_t>(options.frames));
  for (int i = 0; i < options.frames; ++i)
    cameras.push_back(
        trajectoryCamera(reference, options, static_cast<double>(i) / options.frames));
  return cameras;
}

Eigen::Vector3d trajectoryRadii(const Camera& reference, const std::vector<Camera>& cameras) {
  if (cameras.empty())
    fail("trajectory radii: no cameras");
  std::vector<double> axis[3];
  const Eigen::Vector3d Cref = reference.centre();
  for (const Camera& c : cameras) {
    const Eigen::Vector3d d = reference.R * (c.centre() - Cref);
    for (int a = 0; a < 3; ++a)
      axis[a].push_back(std::abs(d[a]));
  }
  Eigen::Vector3d r;
  for (int a = 0; a < 3; ++a)
    r[a] = percentile(axis[a], 90.0);
  return r;
}

double trajectoryFocusDepth(double near, double far) {
  if (!(std::isfinite(near) && std::isfinite(far) && near > 0 && far >= near))
    fail("trajectory focus depth: bounds near = ", near, ", far = ", far,
         " (need 0 < near <= far)");
  constexpr double dt = 0.75;
  return 1.0 / ((1.0 - dt) / near + dt / far);
}

TrajectoryOptions resolveTrajectory(TrajectoryOptions o, const Camera& reference,
                                    const std::vector<Camera>& cameras, double near, double far) {
  if (o.focusDepth <= 0)
    o.focusDepth = trajectoryFocusDepth(near, far);
  if (o.radii == Eigen::Vector3d::Zero()) {
    if (!cameras.empty())
      o.radii = trajectoryRadii(reference, cameras);
    const double used =
        o.kind == TrajectoryKind::Orbit ? o.radii.head<2>().maxCoeff() : o.radii.maxCoeff();
    if (!(used > 0))
      o.radii = o.focusDepth * Eigen::Vector3d(0.05, 0.05, 0.025);
  }
  validateTrajectory(reference, o);
  return o;
}

} // namespace simpli::scene
