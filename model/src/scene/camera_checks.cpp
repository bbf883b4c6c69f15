// The camera rules shared by every reader (scene/camera_checks.h) and checkCamera, the scene
// readers' pose check (scene/readers.h).
#include "simpli/model/scene/camera_checks.h"

#include "simpli/error.h"
#include "simpli/model/scene/readers.h"

#include <Eigen/LU>

#include <cmath>
#include <sstream>

namespace simpli::scene {

void validateCamera(const Camera& c, const std::string& context, double rotationTolerance) {
  if (!c.R.allFinite())
    fail(context, ": non-finite pose: rotation R = [", c.R.row(0), "; ", c.R.row(1), "; ",
         c.R.row(2), "] is not finite");
  if (!c.t.allFinite())
    fail(context, ": non-finite pose: translation t = (", c.t.transpose(), ") is not finite");
  const double intrinsics[4] = {c.fx, c.fy, c.cx, c.cy};
  const char* names[4] = {"fx", "fy", "cx", "cy"};
  for (int i = 0; i < 4; ++i)
    if (!std::isfinite(intrinsics[i]))
      fail(context, ": intrinsic ", names[i], " = ", intrinsics[i], " is not finite");
  if (!(c.fx > 0) || !(c.fy > 0))
    fail(context, ": focal lengths must be positive (> 0): relative fx = ", c.fx, ", fy = ", c.fy);
  for (int i = 0; i < 2; ++i)
    if (intrinsics[i] < kMinRelativeFocal || intrinsics[i] > kMaxRelativeFocal)
      fail(context, ": focal length ", names[i], " = ", intrinsics[i], " (relative to the image ",
           i == 0 ? "width" : "height", ") is outside [", kMinRelativeFocal, ", ",
           kMaxRelativeFocal, "], the range in which a pinhole camera means anything (a field of ",
           "view of 179.9 to 0.06 degrees)");
  const double err = (c.R.transpose() * c.R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (err > rotationTolerance)
    fail(context, ": rotation is not orthonormal, so R is not a rotation (max |R^T R - I| = ", err,
         " > ", rotationTolerance, ")");
  const double det = c.R.determinant();
  if (det < 0)
    fail(context, ": rotation is a reflection (determinant of R = ", det, ")");
}

std::vector<CameraConcern> cameraConcerns(const Camera& c) {
  std::vector<CameraConcern> concerns;
  std::ostringstream focalWhy;
  focalWhy << "a relative focal length outside [" << kGoodRelativeFocalMin << ", "
           << kGoodRelativeFocalMax
           << "] (a field of view beyond 157..2.9 degrees) is far from what the network was "
              "trained on, so the result will be poor; intrinsics in pixels instead of fractions "
              "of the image size?";
  const double focal[2] = {c.fx, c.fy};
  const char* focalNames[2] = {"fx", "fy"};
  for (int i = 0; i < 2; ++i)
    if (focal[i] < kGoodRelativeFocalMin || focal[i] > kGoodRelativeFocalMax)
      concerns.push_back({focalNames[i], focal[i], focalWhy.str()});
  const double centre[2] = {c.cx, c.cy};
  const char* centreNames[2] = {"cx", "cy"};
  for (int i = 0; i < 2; ++i)
    if (centre[i] < 0 || centre[i] > 1)
      concerns.push_back({centreNames[i], centre[i],
                          "the principal point lies outside the image (relative [0, 1]), so the "
                          "result will be poor; intrinsics in pixels instead of fractions of the "
                          "image size?"});
  return concerns;
}

void checkCamera(const Camera& c, const std::string& file, const std::string& view) {
  validateCamera(c, file + ": view " + view, kRotationTolerance);
}

} // namespace simpli::scene
