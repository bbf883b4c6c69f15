#include "simpli/ocl/ops_resample.h"

#include "simpli/error.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/launch.h"

#include <algorithm>
#include <limits>

namespace simpli::ocl {
namespace {

// Must match PLANES_PER_ITEM in resample.cl.
constexpr int kPlanesPerItem = 8;
// Kernel options: the tap count selects bilinear (2) or bicubic (4). Grid sampling does not
// depend on it and shares the bicubic build.
constexpr const char* kLinear = "-DTAPS=2";
constexpr const char* kCubic = "-DTAPS=4";

struct ResizeGeometry {
  int planes, inH, inW, outH, outW;
  Shape outShape;
};

ResizeGeometry resizeGeometry(const Tensor& x, int64_t outH, int64_t outW, const char* op) {
  if (!x.defined())
    fail(op, ": undefined tensor");
  if (x.dim() < 2)
    fail(op, ": input ", x.describe(), " needs at least 2 dimensions (..., H, W)");
  const Shape& s = x.shape();
  const int64_t inH = s[s.size() - 2], inW = s[s.size() - 1];
  if (outH < 1 || outW < 1)
    fail(op, ": output size ", outH, "x", outW, " for input ", x.describe(), " must be positive");
  if (x.numel() == 0)
    fail(op, ": input ", x.describe(), " is empty");
  // The kernels compute source positions as (2p + 1) * in - out and gradient ranges as
  // (2 in + 5) * out in 32-bit integers.
  const int64_t limit = std::numeric_limits<int>::max();
  for (auto [in, out] : {std::pair{inH, outH}, std::pair{inW, outW}})
    if ((2 * out + 1) * in >= limit || (2 * in + 5) * out >= limit)
      fail(op, ": resizing ", x.describe(), " to ", outH, "x", outW, " exceeds 32-bit indexing");
  ResizeGeometry g{};
  g.outShape = s;
  g.outShape[s.size() - 2] = outH;
  g.outShape[s.size() - 1] = outW;
  checkedInt(x.numel(), op);
  checkedInt(numelOf(g.outShape), op);
  g.planes = static_cast<int>(x.numel() / (inH * inW));
  g.inH = static_cast<int>(inH);
  g.inW = static_cast<int>(inW);
  g.outH = static_cast<int>(outH);
  g.outW = static_cast<int>(outW);
  return g;
}

int planeGroups(int planes) {
  return (planes + kPlanesPerItem - 1) / kPlanesPerItem;
}

Tensor resize(const Tensor& x, int64_t outH, int64_t outW, const char* op, const char* taps) {
  const ResizeGeometry g = resizeGeometry(x, outH, outW, op);
  Tensor out = Tensor::empty(g.outShape, x.dtype());
  Launch("resample", "resize_forward", x.dtype(), taps)
      .arg(g.planes)
      .arg(g.inH)
      .arg(g.inW)
      .arg(g.outH)
      .arg(g.outW)
      .arg(x)
      .arg(out)
      .run3(g.outW, g.outH, planeGroups(g.planes));
  return record(op, out, {x}, [g, taps, xs = x.shape()](const Tensor& grad) {
    Tensor gx = Tensor::empty(xs, grad.dtype());
    Launch("resample", "resize_backward", grad.dtype(), taps)
        .arg(g.planes)
        .arg(g.inH)
        .arg(g.inW)
        .arg(g.outH)
        .arg(g.outW)
        .arg(grad)
        .arg(gx)
        .run3(g.inW, g.inH, planeGroups(g.planes));
    return std::vector<Tensor>{gx};
  });
}

void checkGrid(const Tensor& grid, const char* op) {
  if (!grid.defined())
    fail(op, ": undefined grid");
  if (grid.dim() != 4 || grid.shape()[3] != 2)
    fail(op, ": grid ", grid.describe(), " must be [N, Ho, Wo, 2]");
  if (grid.numel() == 0)
    fail(op, ": grid ", grid.describe(), " gives a zero-size output");
  checkedInt(grid.numel(), op);
}

} // namespace

Tensor resizeBilinear(const Tensor& x, int64_t outH, int64_t outW) {
  return resize(x, outH, outW, "resizeBilinear", kLinear);
}

Tensor resizeBicubic(const Tensor& x, int64_t outH, int64_t outW) {
  return resize(x, outH, outW, "resizeBicubic", kCubic);
}

Tensor gridSample(const Tensor& input, const Tensor& grid) {
  if (!input.defined())
    fail("gridSample: undefined input");
  checkGrid(grid, "gridSample");
  if (input.dim() != 4)
    fail("gridSample: input ", input.describe(), " must be [N, C, H, W] (grid ", grid.describe(),
         ")");
  if (input.dtype() != grid.dtype())
    fail("gridSample: dtype mismatch, input ", input.describe(), " vs grid ", grid.describe());
  const Shape& s = input.shape();
  if (s[0] != grid.shape()[0])
    fail("gridSample: batch of input ", input.describe(), " differs from grid ", grid.describe());
  if (input.numel() == 0)
    fail("gridSample: input ", input.describe(), " is empty (grid ", grid.describe(), ")");
  const Shape outShape{s[0], s[1], grid.shape()[1], grid.shape()[2]};
  checkedInt(input.numel(), "gridSample");
  const int n = static_cast<int>(s[0]), c = static_cast<int>(s[1]);
  const int h = static_cast<int>(s[2]), w = static_cast<int>(s[3]);
  const int oh = static_cast<int>(outShape[2]), ow = static_cast<int>(outShape[3]);
  checkedInt(numelOf(outShape), "gridSample");
  Tensor out = Tensor::empty(outShape, input.dtype());
  Launch("resample", "grid_sample_forward", input.dtype(), kCubic)
      .arg(n)
      .arg(c)
      .arg(h)
      .arg(w)
      .arg(oh)
      .arg(ow)
      .arg(input)
      .arg(grid)
      .arg(out)
      .run3(ow, oh, n);
  if (!needsGrad({input, grid}))
    return out;
  const bool wantInput = input.requiresGrad(), wantGrid = grid.requiresGrad();
  return record("gridSample", out, {input, grid},
                [xd = input.detach(), gd = grid.detach(), wantInput, wantGrid, n, c, h, w, oh,
                 ow](const Tensor& g) {
                  // Input gradients are scattered with atomic adds, so they start at zero.
                  Tensor gx = wantInput ? Tensor::zeros(xd.shape(), g.dtype()) : Tensor();
                  Tensor gg = wantGrid ? Tensor::empty(gd.shape(), g.dtype()) : Tensor();
                  Launch("resample", "grid_sample_backward", g.dtype(), kCubic)
                      .arg(n)
                      .arg(c)
                      .arg(h)
                      .arg(w)
                      .arg(oh)
                      .arg(ow)
                      .arg(xd)
                      .arg(gd)
                      .arg(g)
                      .arg(wantInput ? 1 : 0)
                      .arg(wantInput ? gx : g) // unused placeholder when not wanted
                      .arg(wantGrid ? 1 : 0)
                      .arg(wantGrid ? gg : g)
                      .run3(ow, oh, n);
                  return std::vector<Tensor>{gx, gg};
                });
}

Tensor gridSampleMask(const Tensor& grid) {
  checkGrid(grid, "gridSampleMask");
  const Shape& s = grid.shape();
  Tensor mask = Tensor::empty({s[0], 1, s[1], s[2]}, grid.dtype());
  const int points = static_cast<int>(mask.numel());
  Launch("resample", "grid_sample_mask", grid.dtype(), kCubic)
      .arg(points)
      .arg(grid)
      .arg(mask)
      .run(points);
  return mask;
}

} // namespace simpli::ocl
