#pragma once
// Pinhole camera in the reference implementation's conventions (spec §1.2):
// world->camera extrinsics Xc = R Xw + t, OpenCV axes (+x right, +y down, +z forward),
// intrinsics relative to the image size (u in [0,1] spans the image from the left edge of the
// first pixel to the right edge of the last), depth = camera-space z.
#include <Eigen/Core>

namespace simpli::scene {

struct Camera {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity(); ///< world -> camera rotation
  Eigen::Vector3d t = Eigen::Vector3d::Zero();     ///< world -> camera translation
  double fx = 1.0, fy = 1.0;                       ///< focal lengths / (W, H)
  double cx = 0.5, cy = 0.5;                       ///< principal point / (W, H)
  int width = 0, height = 0;                       ///< image size in pixels

  Eigen::Vector3d centre() const { return -R.transpose() * t; }
  Eigen::Matrix3d relativeK() const {
    Eigen::Matrix3d K;
    K << fx, 0, cx, 0, fy, cy, 0, 0, 1;
    return K;
  }

  /// Intrinsics in pixels for the camera's width x height (pixel-edge origin: the centre of
  /// pixel (0, 0) is at (0.5, 0.5), as in COLMAP).
  Eigen::Matrix3d pixelK() const {
    Eigen::Matrix3d K;
    K << fx * width, 0, cx * width, 0, fy * height, cy * height, 0, 0, 1;
    return K;
  }

  /// The 3x4 world->camera matrix [R | t].
  Eigen::Matrix<double, 3, 4> extrinsic() const {
    Eigen::Matrix<double, 3, 4> E;
    E << R, t;
    return E;
  }

  Eigen::Vector3d worldToCamera(const Eigen::Vector3d& Xw) const { return R * Xw + t; }
  Eigen::Vector3d cameraToWorld(const Eigen::Vector3d& Xc) const {
    return R.transpose() * (Xc - t);
  }

  /// Relative image coordinates (u, v) of a world point. As in the reference, z is pushed away
  /// from 0 keeping its sign (|z| >= 1e-6) and points behind the camera are not rejected; use
  /// depth() to test for them.
  Eigen::Vector2d project(const Eigen::Vector3d& Xw) const {
    const Eigen::Vector3d Xc = worldToCamera(Xw);
    double z = Xc.z();
    z = z >= 0 ? (z < 1e-6 ? 1e-6 : z) : (z > -1e-6 ? -1e-6 : z);
    return {fx * Xc.x() / z + cx, fy * Xc.y() / z + cy};
  }

  /// Camera-space z of a world point (the reference's "depth").
  double depth(const Eigen::Vector3d& Xw) const { return R.row(2).dot(Xw) + t.z(); }

  /// World point seen at relative coordinates (u, v) with camera-space z = depth.
  Eigen::Vector3d backproject(const Eigen::Vector2d& uv, double depth) const {
    const Eigen::Vector3d Xc(depth * (uv.x() - cx) / fx, depth * (uv.y() - cy) / fy, depth);
    return cameraToWorld(Xc);
  }
};

} // namespace simpli::scene
