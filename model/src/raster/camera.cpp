#include "raster/camera.h"

#include "model_kernels.h"
#include "simpli/error.h"

#include "simpli/ocl/buffer_pool.h"
#include "simpli/ocl/device.h"
#include "simpli/ocl/launch.h"

#include <Eigen/LU>

#include <cfloat>
#include <cmath>

namespace simpli::raster {

void checkCamera(const scene::Camera& c, const char* op, const char* which, bool needSize) {
  if (!c.R.allFinite() || !c.t.allFinite())
    fail(op, ": ", which, " camera pose has non-finite values (R = [", c.R.row(0), "; ", c.R.row(1),
         "; ", c.R.row(2), "], t = [", c.t.transpose(), "])");
  const double values[4] = {c.fx, c.fy, c.cx, c.cy};
  const char* names[4] = {"fx", "fy", "cx", "cy"};
  for (int i = 0; i < 4; ++i)
    if (!std::isfinite(values[i]))
      fail(op, ": ", which, " camera intrinsic ", names[i], " = ", values[i], " is not finite");
  if (!(c.fx > 0) || !(c.fy > 0))
    fail(op, ": ", which, " camera focal lengths must be positive (relative fx = ", c.fx,
         ", fy = ", c.fy, ")");
  const double err = (c.R.transpose() * c.R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (err > 1e-4)
    fail(op, ": ", which, " camera rotation is not orthonormal (max |R^T R - I| = ", err, ")");
  if (c.R.determinant() < 0)
    fail(op, ": ", which, " camera rotation is a reflection (det R = ", c.R.determinant(), ")");
  if (needSize && (c.width < 1 || c.height < 1))
    fail(op, ": ", which, " camera image size ", c.width, "x", c.height,
         " must be at least 1x1 (width x height)");
}

void checkSettings(const RasterSettings& s, const char* op) {
  if (s.maxFragments < 1 || s.maxFragments > 64)
    fail(op, ": settings.maxFragments = ", s.maxFragments, " must be in 1..64");
  if (!(s.nearZ > 0) || !std::isfinite(s.nearZ))
    fail(op, ": settings.nearZ = ", s.nearZ, " must be positive and finite");
  if (std::isnan(s.farZ))
    fail(op, ": settings.farZ is NaN (use <= 0 or infinity to disable the far cut)");
  if (s.farZ > 0 && s.farZ <= s.nearZ)
    fail(op, ": settings.farZ = ", s.farZ, " must exceed nearZ = ", s.nearZ,
         " (or be <= 0 to disable the far cut)");
  if (s.tileSize != 4 && s.tileSize != 8 && s.tileSize != 16 && s.tileSize != 32)
    fail(op, ": settings.tileSize = ", s.tileSize, " must be 4, 8, 16 or 32");
  if (s.maxBinEntries < 1)
    fail(op, ": settings.maxBinEntries = ", s.maxBinEntries, " must be positive");
  if (s.interpolation != RasterInterpolation::ScreenLinear &&
      s.interpolation != RasterInterpolation::PerspectiveCorrect)
    fail(op, ": settings.interpolation = ", static_cast<int>(s.interpolation),
         " is not a RasterInterpolation value");
}

std::vector<double> projectionParameters(const scene::Camera& ref, const scene::Camera& tgt,
                                         double nearZ, double farZ, double farDisabled) {
  const Eigen::Matrix3d M = tgt.R * ref.R.transpose();
  const Eigen::Vector3d t = tgt.t - M * ref.t;
  std::vector<double> p(22);
  p[0] = ref.fx;
  p[1] = ref.fy;
  p[2] = ref.cx;
  p[3] = ref.cy;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      p[4 + 3 * r + c] = M(r, c);
  p[13] = t.x();
  p[14] = t.y();
  p[15] = t.z();
  p[16] = tgt.fx * tgt.width;
  p[17] = tgt.fy * tgt.height;
  p[18] = tgt.cx * tgt.width;
  p[19] = tgt.cy * tgt.height;
  p[20] = nearZ;
  p[21] = (farZ > 0 && std::isfinite(farZ)) ? farZ : farDisabled;
  return p;
}

ocl::Tensor parameterTensor(const scene::Camera& reference, const scene::Camera& target,
                            double nearZ, double farZ, ocl::Dtype dtype) {
  const double farDisabled = dtype == ocl::Dtype::F64 ? DBL_MAX : static_cast<double>(FLT_MAX);
  const std::vector<double> p = projectionParameters(reference, target, nearZ, farZ, farDisabled);
  return ocl::Tensor::fromHost(p, {static_cast<int64_t>(p.size())}, dtype);
}

void checkDepth(const ocl::Tensor& depth, const char* op) {
  if (!depth.defined())
    fail(op, ": depth is undefined");
  if (depth.dim() != 3)
    fail(op, ": depth ", depth.describe(), " must be [L, H, W]");
  const auto& s = depth.shape();
  if (s[0] < 1 || s[1] < 2 || s[2] < 2)
    fail(op, ": depth ", depth.describe(),
         " needs L >= 1 layers and an H x W grid of at least 2 x 2 vertices");
  // Vertex indices, triangle ids (2 per quad, 6 corner values each) and attribute indices are
  // 32-bit in the kernels.
  ocl::checkedInt(depth.numel() * 4, op);
  ocl::checkedInt(s[0] * 2 * (s[1] - 1) * (s[2] - 1) * 6, op);
}

ocl::Tensor projectVertices(const ocl::Tensor& depth, const ocl::Tensor& params, int maxFragments) {
  ensureModelKernels();
  const int L = static_cast<int>(depth.size(0));
  const int H = static_cast<int>(depth.size(1));
  const int W = static_cast<int>(depth.size(2));
  const int nv = L * H * W;
  ocl::Tensor verts = ocl::Tensor::empty({nv, 4}, depth.dtype());
  ocl::Launch("raster", "raster_project", depth.dtype(), programOptions(maxFragments))
      .arg(nv)
      .arg(H)
      .arg(W)
      .arg(depth)
      .arg(params)
      .arg(verts)
      .run(nv);
  return verts;
}

std::string programOptions(int maxFragments) {
  return "-DRASTER_K=" + std::to_string(maxFragments);
}

std::shared_ptr<ocl::Buffer> intBuffer(std::size_t count) {
  return ocl::Device::current().pool().acquire(count * sizeof(cl_int));
}

} // namespace simpli::raster
