// The SSIM loss (ops_loss.h), composed of differentiable ops: a separable Gaussian blur by two
// one-channel convolutions, then the elementwise SSIM formula. Its gradient is the composition's.
#include "simpli/error.h"
#include "simpli/ocl/ops_conv.h"
#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_loss.h"
#include "simpli/ocl/ops_reduce.h"
#include "simpli/ocl/ops_shape.h"

#include <cmath>
#include <vector>

namespace simpli::ocl {
namespace {

void checkSsimArguments(const Tensor& a, const Tensor& b, const SsimOptions& o) {
  if (!a.defined() || !b.defined())
    fail("ssimLoss: undefined ", !a.defined() ? "a" : "b");
  if (a.dtype() != b.dtype())
    fail("ssimLoss: dtype mismatch, a ", a.describe(), " vs b ", b.describe());
  if (a.shape() != b.shape())
    fail("ssimLoss: shapes differ, a ", a.describe(), " vs b ", b.describe());
  if (a.dim() != 4)
    fail("ssimLoss: inputs ", a.describe(), " must be [N, C, H, W]");
  if (o.windowSize < 1 || o.windowSize % 2 == 0)
    fail("ssimLoss: window size ", o.windowSize, " must be odd and >= 1");
  if (!(o.sigma > 0.0) || !std::isfinite(o.sigma))
    fail("ssimLoss: window sigma ", o.sigma, " must be finite and > 0");
  if (!(o.dataRange > 0.0) || !std::isfinite(o.dataRange))
    fail("ssimLoss: data range ", o.dataRange, " must be finite and > 0");
  if (a.numel() == 0 || a.size(2) < o.windowSize || a.size(3) < o.windowSize)
    fail("ssimLoss: inputs ", a.describe(), " are smaller than the ", o.windowSize, " x ",
         o.windowSize, " window");
}

} // namespace

std::vector<double> ssimWindow(int size, double sigma) {
  if (size < 1 || size % 2 == 0)
    fail("ssim: window size ", size, " must be odd and >= 1");
  if (!(sigma > 0.0) || !std::isfinite(sigma))
    fail("ssim: window sigma ", sigma, " must be finite and > 0");
  std::vector<double> w(static_cast<size_t>(size));
  const int r = size / 2;
  double sum = 0.0;
  for (int i = 0; i < size; ++i) {
    const double d = i - r;
    w[size_t(i)] = std::exp(-d * d / (2.0 * sigma * sigma));
    sum += w[size_t(i)];
  }
  for (double& v : w)
    v /= sum;
  return w;
}

Tensor ssimLoss(const Tensor& a, const Tensor& b, const SsimOptions& options) {
  checkSsimArguments(a, b, options);
  const int64_t planes = a.size(0) * a.size(1), H = a.size(2), W = a.size(3);
  const std::vector<double> win = ssimWindow(options.windowSize, options.sigma);
  const int n = options.windowSize;
  const Tensor down = Tensor::fromHost(win, {1, 1, n, 1}, a.dtype());
  const Tensor across = Tensor::fromHost(win, {1, 1, 1, n}, a.dtype());
  // The five local moments in one blur: [x, y, x^2, y^2, xy] stacked as one-channel planes, of
  // the images shifted by half the data range: the (co)variances are E[x^2] - E[x]^2 and the
  // like, which cancel; centring the values first loses fewer digits in float32.
  const double shift = 0.5 * options.dataRange;
  const Tensor x = addScalar(reshape(a, {planes, 1, H, W}), -shift);
  const Tensor y = addScalar(reshape(b, {planes, 1, H, W}), -shift);
  const Tensor stacked = concat({x, y, mul(x, x), mul(y, y), mul(x, y)}, 0);
  const Tensor blurred = conv2d(conv2d(stacked, down), across);
  auto moment = [&](int k) { return slice(blurred, 0, k * planes, (k + 1) * planes); };
  const Tensor cx = moment(0), cy = moment(1); // local means of the shifted images
  const Tensor sxx = sub(moment(2), mul(cx, cx)), syy = sub(moment(3), mul(cy, cy));
  const Tensor sxy = sub(moment(4), mul(cx, cy));
  const Tensor mx = addScalar(cx, shift), my = addScalar(cy, shift);
  const Tensor mxx = mul(mx, mx), myy = mul(my, my), mxy = mul(mx, my);
  const double c1 = std::pow(options.k1 * options.dataRange, 2);
  const double c2 = std::pow(options.k2 * options.dataRange, 2);
  const Tensor numerator =
      mul(addScalar(mulScalar(mxy, 2.0), c1), addScalar(mulScalar(sxy, 2.0), c2));
  const Tensor denominator = mul(addScalar(add(mxx, myy), c1), addScalar(add(sxx, syy), c2));
  // 1 - mean SSIM: every plane has the same number of windows, so the mean over all windows is
  // the mean of the per-plane means (the metric's channel average).
  return addScalar(neg(meanAll(div(numerator, denominator))), 1.0);
}

} // namespace simpli::ocl
