// checkCamera: the pose sanity checks shared by all scene readers.
#include "simpli/error.h"
#include "simpli/model/scene/readers.h"

#include <Eigen/LU>

#include <cmath>

namespace simpli::scene {

void checkCamera(const Camera& c, const std::string& file, const std::string& view) {
  if (!c.R.allFinite() || !c.t.allFinite())
    fail(file, ": view ", view, ": pose has non-finite values (R = [", c.R.row(0), "; ", c.R.row(1),
         "; ", c.R.row(2), "], t = [", c.t.transpose(), "])");
  const double intrinsics[4] = {c.fx, c.fy, c.cx, c.cy};
  const char* names[4] = {"fx", "fy", "cx", "cy"};
  for (int i = 0; i < 4; ++i)
    if (!std::isfinite(intrinsics[i]))
      fail(file, ": view ", view, ": intrinsic ", names[i], " = ", intrinsics[i], " is not finite");
  if (!(c.fx > 0) || !(c.fy > 0))
    fail(file, ": view ", view, ": focal length must be positive (relative fx = ", c.fx,
         ", fy = ", c.fy, ")");
  const double err = (c.R.transpose() * c.R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (err > kRotationTolerance)
    fail(file, ": view ", view, ": rotation is not orthonormal (max |R^T R - I| = ", err, " > ",
         kRotationTolerance, ")");
  const double det = c.R.determinant();
  if (det < 0)
    fail(file, ": view ", view, ": rotation is a reflection (det R = ", det, ")");
}

} // namespace simpli::scene
