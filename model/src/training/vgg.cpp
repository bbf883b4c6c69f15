// VGG-19 features and the perceptual loss (training/vgg.h).
#include "simpli/model/training/vgg.h"

#include "simpli/error.h"
#include "simpli/model/io/safetensors.h"

#include "simpli/ocl/autograd.h"
#include "simpli/ocl/ops_conv.h"
#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_loss.h"
#include "simpli/ocl/ops_pool.h"
#include "simpli/ocl/ops_resample.h"

#include <algorithm>

namespace simpli::training {

namespace {
// torchvision's cfg "E": the 16 convs, with a pool after conv indices 1, 3, 7, 11, 15.
constexpr std::array<int, 16> kConvIdx{0, 2, 5, 7, 10, 12, 14, 16, 19, 21, 23, 25, 28, 30, 32, 34};
constexpr std::array<int, 5> kPoolIdx{4, 9, 18, 27, 36};
constexpr std::array<double, 3> kMean{0.485, 0.456, 0.406};
constexpr std::array<double, 3> kStd{0.229, 0.224, 0.225};

std::string convKey(int idx, const char* part) {
  return "features." + std::to_string(idx) + "." + part;
}

// Every conv's weight and bias present as F32/F64 with chaining shapes [out, in, 3, 3] and
// [out]; the error lists every missing key, or names the first wrong shape or dtype. Returns the
// output widths.
std::vector<int64_t> checkedWidths(const io::SafeTensorsReader& r) {
  std::vector<std::string> missing;
  for (int idx : kConvIdx)
    for (const char* part : {"weight", "bias"})
      if (!r.contains(convKey(idx, part)))
        missing.push_back(convKey(idx, part));
  if (!missing.empty()) {
    std::string list;
    for (size_t k = 0; k < missing.size() && k < 6; ++k)
      list += (k ? ", " : "") + missing[k];
    if (missing.size() > 6)
      list += ", ...";
    fail(r.path(), ": not VGG-19 weights: ", missing.size(), " of the ", 2 * kConvIdx.size(),
         " keys of its 16 convolutions are missing (", list,
         "); expected torchvision's key names features.N.weight / features.N.bias");
  }
  std::vector<int64_t> widths;
  int64_t in = 3;
  for (int idx : kConvIdx) {
    const std::string wk = convKey(idx, "weight"), bk = convKey(idx, "bias");
    for (const std::string& key : {wk, bk}) {
      const std::string& dtype = r.info(key).dtype;
      if (dtype != "F32" && dtype != "F64")
        fail(r.path(), ": key '", key, "' has dtype ", dtype, "; expected F32 or F64");
    }
    const std::vector<int64_t> ws = r.info(wk).shape;
    if (ws.size() != 4 || ws[1] != in || ws[2] != 3 || ws[3] != 3 || ws[0] < 1)
      fail(r.path(), ": key '", wk, "' has shape ", ocl::toString(ws), "; expected [out, ", in,
           ", 3, 3]");
    const std::vector<int64_t> bs = r.info(bk).shape;
    if (bs.size() != 1 || bs[0] != ws[0])
      fail(r.path(), ": key '", bk, "' has shape ", ocl::toString(bs), "; expected [", ws[0], "]");
    widths.push_back(ws[0]);
    in = ws[0];
  }
  return widths;
}

ocl::Tensor load(const io::SafeTensorsReader& r, const std::string& key, ocl::Dtype dtype) {
  io::HostTensor<double> t = r.readF64(key);
  return ocl::Tensor::fromHost(t.data, t.shape, dtype);
}

} // namespace

const std::array<int, 16>& Vgg19Features::convIndices() {
  return kConvIdx;
}

void Vgg19Features::check(const std::string& path) {
  checkedWidths(io::SafeTensorsReader(path));
}

Vgg19Features::Vgg19Features(const std::string& path, ocl::Dtype dtype) : path_(path) {
  const io::SafeTensorsReader r(path);
  checkedWidths(r);
  for (int idx : kConvIdx) {
    weights_.push_back(load(r, convKey(idx, "weight"), dtype));
    biases_.push_back(load(r, convKey(idx, "bias"), dtype));
  }
}

ocl::Tensor Vgg19Features::normalise(const ocl::Tensor& x) const {
  if (x.dim() != 4 || x.size(1) != 3)
    fail("Vgg19Features: input ", x.describe(), " is not [N, 3, H, W]");
  std::vector<double> mean(3), scale(3);
  for (int c = 0; c < 3; ++c) {
    mean[size_t(c)] = 2 * kMean[size_t(c)] - 1;
    scale[size_t(c)] = 1.0 / (2 * kStd[size_t(c)]);
  }
  const ocl::Tensor m = ocl::Tensor::fromHost(mean, {1, 3, 1, 1}, x.dtype());
  const ocl::Tensor s = ocl::Tensor::fromHost(scale, {1, 3, 1, 1}, x.dtype());
  return ocl::mul(ocl::sub(x, m), s);
}

std::vector<ocl::Tensor> Vgg19Features::features(const ocl::Tensor& x) const {
  if (!loaded())
    fail("Vgg19Features: no weights loaded");
  if (x.dim() != 4 || x.size(2) % 16 != 0 || x.size(3) % 16 != 0)
    fail("Vgg19Features: input ", x.describe(), " must be [N, 3, H, W] with H, W divisible by 16");
  std::vector<ocl::Tensor> out;
  ocl::Tensor h = normalise(x);
  size_t conv = 0;
  for (int idx = 0; idx < kPoolIdx.back(); ++idx) {
    if (std::find(kPoolIdx.begin(), kPoolIdx.end(), idx) != kPoolIdx.end()) {
      out.push_back(h); // the output of features[:idx]
      h = ocl::avgPool2d(h, 2, 2);
    } else if (conv < kConvIdx.size() && kConvIdx[conv] == idx) {
      h = ocl::conv2d(h, weights_[conv], biases_[conv], 1, 1);
      ++conv;
    } else {
      h = ocl::relu(h); // every other index is the ReLU after a conv
    }
  }
  out.push_back(h); // index 36: relu5_4 (the last pool is never applied)
  return out;
}

ocl::Tensor perceptualLoss(const Vgg19Features& vgg, const ocl::Tensor& pred,
                           const ocl::Tensor& target, const ocl::Tensor& mask) {
  if (pred.shape() != target.shape())
    fail("perceptualLoss: pred ", pred.describe(), " and target ", target.describe(), " differ");
  if (mask.dim() != 4 || mask.size(0) != pred.size(0) || mask.size(1) != 1 ||
      mask.size(2) != pred.size(2) || mask.size(3) != pred.size(3))
    fail("perceptualLoss: mask ", mask.describe(), " does not fit pred ", pred.describe());
  const std::vector<ocl::Tensor> fp = vgg.features(pred);
  std::vector<ocl::Tensor> ft;
  {
    ocl::NoGradGuard noGrad;
    ft = vgg.features(target.detach());
  }
  ocl::Tensor total;
  for (size_t l = 0; l < fp.size(); ++l) {
    const ocl::Tensor& f = fp[l];
    const ocl::Tensor m = f.size(2) == mask.size(2) && f.size(3) == mask.size(3)
                              ? mask
                              : ocl::resizeBilinear(mask, f.size(2), f.size(3));
    const ocl::Tensor term =
        ocl::mulScalar(ocl::maskedL1(f, ft[l].detach(), m), Vgg19Features::kLevelWeights[l]);
    total = total.defined() ? ocl::add(total, term) : term;
  }
  return total;
}

} // namespace simpli::training
