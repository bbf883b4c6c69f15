#include "simpli/model/geometry/mpi_render.h"

#include "geometry/sampling.h"
#include "model_kernels.h"
#include "simpli/error.h"

#include "simpli/ocl/autograd.h"
#include "simpli/ocl/launch.h"
#include "simpli/ocl/ops_shape.h"

#include <cmath>
#include <string>

namespace simpli::geometry {

using ocl::Launch;
using ocl::Tensor;

namespace {

// 16 values per target (kernels/mpi.cl TARGET_STRIDE): M = R_ref R_c^T (row-major),
// a = R_ref C_c + t_ref, then fx, fy, cx, cy of the target.
std::vector<double> targetBlocks(const scene::Camera& reference,
                                 const std::vector<scene::Camera>& targets) {
  std::vector<double> blocks;
  blocks.reserve(16 * targets.size());
  for (const scene::Camera& c : targets) {
    const Eigen::Matrix3d M = reference.R * c.R.transpose();
    const Eigen::Vector3d a = reference.R * c.centre() + reference.t;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        blocks.push_back(M(i, j));
    blocks.insert(blocks.end(), {a.x(), a.y(), a.z(), c.fx, c.fy, c.cx, c.cy});
  }
  return blocks;
}

struct RenderDims {
  int P, C1, h, w, N, ht, wt;
  double rfx, rfy, rcx, rcy;
};

Launch& addCommon(Launch& l, const RenderDims& d, const Tensor& targets, const Tensor& depths) {
  return l.arg(d.P)
      .arg(d.C1)
      .arg(d.h)
      .arg(d.w)
      .arg(d.N)
      .arg(d.ht)
      .arg(d.wt)
      .arg(targets)
      .real(d.rfx)
      .real(d.rfy)
      .real(d.rcx)
      .real(d.rcy)
      .arg(depths);
}

} // namespace

MpiRendering renderMpi(const Tensor& mpi, const std::vector<double>& depths,
                       const scene::Camera& reference, const std::vector<scene::Camera>& targets,
                       int height, int width) {
  const char* op = "renderMpi";
  if (!mpi.defined())
    fail(op, ": undefined MPI");
  if (mpi.dim() != 4 || mpi.shape()[1] < 2)
    fail(op, ": MPI ", mpi.describe(), " must be [P, C + 1, h, w] with C >= 1 feature channels");
  if (mpi.numel() == 0)
    fail(op, ": MPI ", mpi.describe(), " is empty");
  if (static_cast<int64_t>(depths.size()) != mpi.shape()[0])
    fail(op, ": ", depths.size(), " plane depths for MPI ", mpi.describe());
  for (std::size_t p = 0; p < depths.size(); ++p)
    if (!std::isfinite(depths[p]) || !(depths[p] > 0))
      fail(op, ": plane depth ", p, " = ", depths[p], " must be finite and positive");
  if (targets.empty())
    fail(op, ": no target cameras (MPI ", mpi.describe(), ")");
  if (height < 1 || width < 1)
    fail(op, ": output size ", height, "x", width, " must be at least 1x1");
  geometry::checkCamera(reference, op, "reference camera");
  for (std::size_t n = 0; n < targets.size(); ++n)
    geometry::checkCamera(targets[n], op, "target camera " + std::to_string(n));

  ocl::checkedInt(mpi.numel(), op);
  // Packed output [N, C + 1 + P, Ht, Wt].
  const int64_t outChannels = mpi.shape()[0] + mpi.shape()[1];
  ocl::checkedInt(outChannels * static_cast<int64_t>(targets.size()) * height * width, op);
  RenderDims d{};
  d.P = static_cast<int>(mpi.shape()[0]);
  d.C1 = static_cast<int>(mpi.shape()[1]);
  d.h = static_cast<int>(mpi.shape()[2]);
  d.w = static_cast<int>(mpi.shape()[3]);
  d.N = static_cast<int>(targets.size());
  d.ht = height;
  d.wt = width;
  d.rfx = reference.fx;
  d.rfy = reference.fy;
  d.rcx = reference.cx;
  d.rcy = reference.cy;

  ensureModelKernels();
  const ocl::Dtype dtype = mpi.dtype();
  const Tensor blocks = Tensor::fromHost(targetBlocks(reference, targets),
                                         {static_cast<int64_t>(16 * targets.size())}, dtype);
  const Tensor planeDepth = Tensor::fromHost(depths, {static_cast<int64_t>(depths.size())}, dtype);

  // One packed output [N, C + 1 + P, Ht, Wt] = [colour | opacity | weights] carries the single
  // tape node, so one backward pass serves all three outputs; they are sliced from it.
  Tensor packed = Tensor::empty({d.N, d.C1 + d.P, height, width}, dtype);
  Launch l("mpi", "mpi_render_forward", dtype);
  addCommon(l, d, blocks, planeDepth).arg(mpi).arg(packed).run3(width, height, d.N);
  packed =
      ocl::record(op, packed, {mpi}, [d, blocks, planeDepth, m = mpi.detach()](const Tensor& g) {
        Tensor gmpi = Tensor::zeros(m.shape(), g.dtype());
        Tensor trans = Tensor::empty({d.N, d.P, d.ht, d.wt}, g.dtype());
        Launch l("mpi", "mpi_render_backward", g.dtype());
        addCommon(l, d, blocks, planeDepth)
            .arg(m)
            .arg(g)
            .arg(trans)
            .arg(gmpi)
            .run3(d.wt, d.ht, d.N);
        return std::vector<Tensor>{gmpi};
      });
  const int C = d.C1 - 1;
  MpiRendering r;
  r.color = ocl::slice(packed, 1, 0, C);
  r.opacity = ocl::slice(packed, 1, C, C + 1);
  r.weights = ocl::reshape(ocl::slice(packed, 1, C + 1, C + 1 + d.P), {d.N, d.P, 1, height, width});
  return r;
}

} // namespace simpli::geometry
