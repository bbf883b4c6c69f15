// shadeFragments: attribute interpolation and the front-to-back composite of the rasterized
// fragments, with its gradients (kernels raster_shade_* in model/kernels/raster.cl).
#include "model_kernels.h"
#include "raster/camera.h"
#include "simpli/error.h"
#include "simpli/model/raster/rasterizer.h"

#include "simpli/ocl/autograd.h"
#include "simpli/ocl/buffer_pool.h"
#include "simpli/ocl/launch.h"
#include "simpli/ocl/ops_shape.h"

namespace simpli::raster {
namespace {

constexpr const char* kOp = "shadeFragments";

void checkInputs(const RasterFragments& f, const ocl::Tensor& depth,
                 const ocl::Tensor& attributes) {
  if (!f.triangles || !f.depth.defined())
    fail(kOp, ": fragments are empty (default-constructed RasterFragments)");
  raster::checkDepth(depth, kOp);
  if (depth.shape() != ocl::Shape{f.layers, f.height, f.width})
    fail(kOp, ": depth ", depth.describe(), " differs from the rasterized grid [", f.layers, ", ",
         f.height, ", ", f.width, "]");
  if (depth.dtype() != f.dtype)
    fail(kOp, ": depth ", depth.describe(), " has another dtype than the fragments (",
         ocl::toString(f.dtype), ")");
  if (!attributes.defined())
    fail(kOp, ": attributes are undefined");
  if (attributes.dim() != 4 || attributes.size(0) != f.layers || attributes.size(2) != f.height ||
      attributes.size(3) != f.width)
    fail(kOp, ": attributes ", attributes.describe(), " must be [L, A, H, W] = [", f.layers,
         ", A, ", f.height, ", ", f.width, "]");
  if (attributes.size(1) < 2)
    fail(kOp, ": attributes ", attributes.describe(),
         " need A >= 2 channels (at least one colour or feature channel, then alpha)");
  if (attributes.dtype() != depth.dtype())
    fail(kOp, ": dtype mismatch, attributes ", attributes.describe(), " vs depth ",
         depth.describe());
  ocl::checkedInt(attributes.numel(), kOp);
  ocl::checkedInt(
      (attributes.size(1) + 1 + f.maxFragments) * int64_t(f.targetHeight) * f.targetWidth, kOp);
}

} // namespace

RenderedLayers shadeFragments(const RasterFragments& f, const ocl::Tensor& depth,
                              const ocl::Tensor& attributes) {
  checkInputs(f, depth, attributes);
  ensureModelKernels();
  const ocl::Dtype dt = depth.dtype();
  const int H = f.height, W = f.width, Ht = f.targetHeight, Wt = f.targetWidth;
  const int K = f.maxFragments;
  const int A = static_cast<int>(attributes.size(1));
  const int perspective = f.interpolation == RasterInterpolation::PerspectiveCorrect;
  const std::string options = raster::programOptions(K);
  const ocl::Tensor params = raster::parameterTensor(f.reference, f.target, f.nearZ, f.farZ, dt);
  const ocl::Tensor verts = raster::projectVertices(depth, params, K);

  // One packed output [colour, opacity, depth, weights (K)] so that a single tape node
  // carries every output's gradient; the public tensors are recorded slices of it.
  ocl::Tensor packed = ocl::Tensor::empty({A + 1 + K, Ht, Wt}, dt);
  ocl::Launch("raster", "raster_shade_forward", dt, options)
      .arg(H)
      .arg(W)
      .arg(A)
      .arg(Ht)
      .arg(Wt)
      .arg(perspective)
      .arg(verts)
      .arg(attributes)
      .arg(f.triangles->mem())
      .arg(packed)
      .run2(Wt, Ht, 16, 4);

  if (ocl::needsGrad({depth, attributes})) {
    const bool wantDepth = depth.requiresGrad(), wantAttr = attributes.requiresGrad();
    packed = ocl::record("renderLayers", packed, {depth, attributes},
                         [=, attrs = attributes.detach(), depthShape = depth.shape(),
                          ids = f.triangles](const ocl::Tensor& grad) {
                           // Scattered with atomic adds, so both start at zero.
                           ocl::Tensor gd =
                               wantDepth ? ocl::Tensor::zeros(depthShape, dt) : ocl::Tensor();
                           ocl::Tensor ga =
                               wantAttr ? ocl::Tensor::zeros(attrs.shape(), dt) : ocl::Tensor();
                           ocl::Launch("raster", "raster_shade_backward", dt, options)
                               .arg(H)
                               .arg(W)
                               .arg(A)
                               .arg(Ht)
                               .arg(Wt)
                               .arg(perspective)
                               .arg(verts)
                               .arg(params)
                               .arg(attrs)
                               .arg(ids->mem())
                               .arg(grad)
                               .arg(wantAttr ? 1 : 0)
                               .arg(wantAttr ? ga : grad) // unused placeholder when not wanted
                               .arg(wantDepth ? 1 : 0)
                               .arg(wantDepth ? gd : grad)
                               .run2(Wt, Ht, 16, 4);
                           return std::vector<ocl::Tensor>{gd, ga};
                         });
  }
  RenderedLayers out;
  out.colour = ocl::slice(packed, 0, 0, A - 1);
  out.opacity = ocl::slice(packed, 0, A - 1, A);
  out.depth = ocl::slice(packed, 0, A, A + 1);
  out.weights = ocl::slice(packed, 0, A + 1, A + 1 + K);
  return out;
}

RenderedLayers renderLayers(const ocl::Tensor& depth, const ocl::Tensor& attributes,
                            const scene::Camera& reference, const scene::Camera& target,
                            const RasterSettings& settings) {
  // Check the attributes before the (costlier) rasterization; shadeFragments repeats it.
  raster::checkDepth(depth, "renderLayers");
  if (!attributes.defined() || attributes.dim() != 4)
    fail("renderLayers: attributes ", attributes.defined() ? attributes.describe() : "undefined",
         " must be [L, A, H, W] for depth ", depth.describe());
  const RasterFragments f = rasterizeLayers(depth, reference, target, settings);
  return shadeFragments(f, depth, attributes);
}

} // namespace simpli::raster
