// Handheld-like forward-facing camera paths (see synthetic/camera_path.h).
#include "simpli/model/synthetic/camera_path.h"

#include "simpli/error.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace simpli::synthetic {

namespace {

// A smooth random 1-D signal over tau in [0, 1]: two sinusoids of random frequency and phase.
struct Wobble {
  double amplitude[2], frequency[2], phase[2];
  explicit Wobble(Random& rng) {
    for (int k = 0; k < 2; ++k) {
      amplitude[k] = rng.uniform(0.1, 0.35);
      frequency[k] = rng.uniform(0.4, 1.8);
      phase[k] = rng.uniform(0.0, 2.0 * M_PI);
    }
  }
  double operator()(double tau) const {
    double v = 0;
    for (int k = 0; k < 2; ++k)
      v += amplitude[k] * std::sin(2.0 * M_PI * frequency[k] * tau + phase[k]);
    return v;
  }
};

Eigen::Matrix3d yawPitchRollMatrix(double yaw, double pitch, double roll) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitX()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ()))
      .toRotationMatrix();
}

// Recentres the values on their mean and scales them so the largest |value| is `bound`.
void centreAndScale(std::vector<double>& values, double bound) {
  double mean = 0;
  for (double v : values)
    mean += v;
  mean /= double(values.size());
  double largest = 0;
  for (double& v : values) {
    v -= mean;
    largest = std::max(largest, std::abs(v));
  }
  for (double& v : values)
    v = largest > 0 ? v * bound / largest : 0.0;
}

} // namespace

Eigen::Vector3d yawPitchRoll(const Eigen::Matrix3d& m) {
  // m = Ry(a) Rx(b) Rz(c): m(1,2) = -sin b, m(0,2) = sin a cos b, m(2,2) = cos a cos b,
  // m(1,0) = cos b sin c, m(1,1) = cos b cos c.
  const double pitch = std::asin(std::max(-1.0, std::min(1.0, -m(1, 2))));
  return {std::atan2(m(0, 2), m(2, 2)), pitch, std::atan2(m(1, 0), m(1, 1))};
}

std::vector<scene::Camera> makeCameraPath(const CameraPathParams& p, Random& rng) {
  if (p.views < 1)
    fail("makeCameraPath: views ", p.views, " must be >= 1");
  const int n = p.views;
  // Centres: a sweep in a random, mostly horizontal image-plane direction, plus smooth wobble
  // on every axis (weaker along y and much weaker along z: a hand moves sideways while the
  // photographer keeps the distance), plus per-view jitter.
  const double sweepAngle = rng.uniform(-0.35, 0.35);
  const Eigen::Vector3d sweep(std::cos(sweepAngle), std::sin(sweepAngle), 0.0);
  const Eigen::Vector3d axisWeight(1.0, 0.6, 0.3);
  const Wobble wobble[3] = {Wobble(rng), Wobble(rng), Wobble(rng)};
  std::vector<Eigen::Vector3d> centres(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    const double tau = n > 1 ? double(i) / (n - 1) : 0.5;
    Eigen::Vector3d c = sweep * (2.0 * tau - 1.0);
    for (int a = 0; a < 3; ++a)
      c[a] += axisWeight[a] * (wobble[a](tau) + 0.05 * rng.normal());
    centres[size_t(i)] = c;
  }
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& c : centres)
    mean += c;
  mean /= double(n);
  double largest = 0;
  for (auto& c : centres) {
    c -= mean;
    largest = std::max(largest, c.norm());
  }
  for (auto& c : centres)
    c = largest > 0 ? Eigen::Vector3d(c * (p.maxOffset / largest)) : Eigen::Vector3d::Zero();

  // Rotations: smooth wobble + jitter per angle, recentred so the mean camera looks along +z,
  // each scaled so its largest magnitude is a random fraction (0.5 .. 1) of the bound.
  const double bound = p.maxRotationDegrees * M_PI / 180.0;
  std::vector<double> angles[3];
  for (auto& a : angles) {
    const Wobble w(rng);
    const double fraction = rng.uniform(0.5, 1.0);
    for (int i = 0; i < n; ++i) {
      const double tau = n > 1 ? double(i) / (n - 1) : 0.5;
      a.push_back(w(tau) + 0.1 * rng.normal());
    }
    centreAndScale(a, fraction * bound);
  }

  std::vector<scene::Camera> cams;
  for (int i = 0; i < n; ++i) {
    const Eigen::Matrix3d c2w =
        yawPitchRollMatrix(angles[0][size_t(i)], angles[1][size_t(i)], angles[2][size_t(i)]);
    scene::Camera cam;
    cam.R = c2w.transpose();
    cam.t = -cam.R * centres[size_t(i)];
    cam.fx = p.fx;
    cam.fy = p.fy;
    cam.cx = 0.5;
    cam.cy = 0.5;
    cam.width = p.width;
    cam.height = p.height;
    cams.push_back(cam);
  }
  return cams;
}

} // namespace simpli::synthetic
