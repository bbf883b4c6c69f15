#include "simpli/model/scene/reference_camera.h"

#include "simpli/error.h"

#include <Eigen/Eigenvalues>

namespace simpli::scene {

Eigen::Quaterniond averageRotation(const std::vector<Eigen::Matrix3d>& rotations) {
  if (rotations.empty())
    fail("averageRotation: no rotations");
  Eigen::Matrix4d A = Eigen::Matrix4d::Zero();
  for (const Eigen::Matrix3d& R : rotations) {
    const Eigen::Vector4d q = Eigen::Quaterniond(R).normalized().coeffs(); // (x, y, z, w)
    A += q * q.transpose(); // invariant under q -> -q
  }
  A /= double(rotations.size());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> solver(A);
  if (solver.info() != Eigen::Success)
    fail("averageRotation: eigen decomposition failed");
  // Eigenvalues come in increasing order: the last column belongs to the largest.
  Eigen::Vector4d q = solver.eigenvectors().col(3).normalized();
  // Deterministic sign: w first, then x, y, z.
  const int order[4] = {3, 0, 1, 2};
  for (int k : order) {
    if (q[k] != 0) {
      if (q[k] < 0)
        q = -q;
      break;
    }
  }
  return Eigen::Quaterniond(q[3], q[0], q[1], q[2]);
}

Camera referenceCamera(const std::vector<Camera>& sources) {
  if (sources.empty())
    fail("referenceCamera: no source cameras");
  std::vector<Eigen::Matrix3d> rotations;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const Camera& c : sources) {
    rotations.push_back(c.R);
    centre += c.centre();
  }
  centre /= double(sources.size());
  Camera ref = sources[0]; // intrinsics and size of view 0
  ref.R = averageRotation(rotations).toRotationMatrix();
  ref.t = -ref.R * centre;
  return ref;
}

Camera widenedCamera(const Camera& camera, double margin) {
  if (!(margin >= 0 && margin <= maxReferenceMargin))
    fail("reference margin ", margin,
         ": must be between 0 and 0.5 (a fraction of the image "
         "size added on every side)");
  Camera wide = camera;
  const double scale = 1 + 2 * margin;
  wide.fx /= scale;
  wide.fy /= scale;
  wide.cx = (camera.cx + margin) / scale;
  wide.cy = (camera.cy + margin) / scale;
  return wide;
}

} // namespace simpli::scene
