// ViewAttention::aggregate: the fused form of an MLI level's view aggregation, forward and
// backward (model/kernels/view_attention.cl). The composed form (MultiHeadAttention::forward
// plus the weighted mean / variance in generator/mli_corrections.cpp) stays the reference (and
// the path of stage hooks); tests/model/network/test_view_aggregation.cpp holds the two
// together, values and gradients.
#include "simpli/model/network/attention.h"

#include "model_kernels.h"
#include "simpli/error.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/launch.h"
#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_linalg.h"
#include "simpli/ocl/ops_reduce.h"
#include "simpli/ocl/ops_reshape.h"
#include "simpli/ocl/ops_shape.h"

#include <cmath>
#include <string>

namespace simpli::network {

namespace {

// Pixels one backward work item takes: its partial sums of the parameter gradients are one row
// of NPARAM values, so fewer rows to reduce, while enough items remain to fill the cores.
constexpr int kBackwardPixels = 16;

struct FusedInputs {
  ocl::Tensor samples, weights, scoreMap, valueMap, lnWeight, lnBias;
};

// The gradients of the fused aggregation's inputs (view_attention_meanvar_backward), in the
// order of FusedInputs.
std::vector<ocl::Tensor> fusedBackward(const FusedInputs& in, const ocl::Tensor& gradOut,
                                       const std::string& options) {
  const int64_t S = in.samples.size(1), C = in.samples.size(2);
  const int hw = static_cast<int>(in.samples.size(3) * in.samples.size(4));
  const int64_t tok = C + 1, nparam = tok * tok + C * tok + 2 * C;
  const int chunks = (hw + kBackwardPixels - 1) / kBackwardPixels;
  const ocl::Dtype dt = in.samples.dtype();
  ocl::Tensor gradSamples = ocl::Tensor::empty(in.samples.shape(), dt);
  ocl::Tensor gradWeights = ocl::Tensor::empty(in.weights.shape(), dt);
  const ocl::Tensor partial = ocl::Tensor::empty({S * chunks, nparam}, dt);
  ocl::Launch("view_attention", "view_attention_meanvar_backward", dt, options)
      .arg(static_cast<int>(S))
      .arg(hw)
      .arg(chunks)
      .arg(kBackwardPixels)
      .arg(in.samples)
      .arg(in.weights)
      .arg(in.scoreMap)
      .arg(in.valueMap)
      .arg(in.lnWeight)
      .arg(in.lnBias)
      .real(MultiHeadAttention::kLayerNormEps)
      .arg(gradOut)
      .arg(gradSamples)
      .arg(gradWeights)
      .arg(partial)
      .run2(chunks, S, 64, 1);
  const ocl::Tensor params = ocl::sum(partial, 0); // [nparam]
  int64_t at = 0;
  auto take = [&](const ocl::Shape& shape) {
    const int64_t count = ocl::numelOf(shape);
    const ocl::Tensor part = ocl::reshape(ocl::slice(params, 0, at, at + count), shape);
    at += count;
    return part;
  };
  ocl::Tensor gradMap = take({tok, tok}), gradValue = take({C, tok});
  ocl::Tensor gradGain = take({C}), gradShift = take({C});
  return {gradSamples, gradWeights, gradMap, gradValue, gradGain, gradShift};
}

} // namespace

ocl::Tensor ViewAttention::aggregate(const ocl::Tensor& samples, const ocl::Tensor& weights) const {
  const MultiHeadAttention& a = attention_;
  const int C = a.outChannels();
  if (!samples.defined() || samples.dim() != 5 || samples.size(2) != C)
    fail("ViewAttention::aggregate: samples ",
         samples.defined() ? samples.describe() : std::string("undefined"), " must be [V, S, ", C,
         ", h, w]");
  const int64_t V = samples.size(0), S = samples.size(1), h = samples.size(3), w = samples.size(4);
  if (!weights.defined() || weights.shape() != ocl::Shape{V, S, 1, h, w} ||
      weights.dtype() != samples.dtype())
    fail("ViewAttention::aggregate: weights ",
         weights.defined() ? weights.describe() : std::string("undefined"), " must be ",
         ocl::toString(samples.dtype()), ocl::toString(ocl::Shape{V, S, 1, h, w}), " (samples ",
         samples.describe(), ")");
  if (V < 1 || V > kMaxFusedViews)
    fail("ViewAttention::aggregate: ", V, " views; the fused kernel handles 1 .. ", kMaxFusedViews);
  if (a.heads() != 1)
    fail("ViewAttention::aggregate: ", a.heads(), " heads; the fused kernel handles one");
  if (a.wq_.dtype() != samples.dtype())
    fail("ViewAttention::aggregate: samples ", samples.describe(), " are not in the weights' ",
         ocl::toString(a.wq_.dtype()));
  const int hw = ocl::checkedInt(h * w, "ViewAttention::aggregate");
  ocl::checkedInt(V * S * C * int64_t(hw), "ViewAttention::aggregate");
  ensureModelKernels();
  // The folded projections (view_attention.cl): M = W_q^T W_k / sqrt(hidden) [C + 1, C + 1]
  // and P = fc W_v [C, C + 1].
  const ocl::Tensor scoreMap = ocl::mulScalar(ocl::matmul(a.wq_, a.wk_, true, false),
                                              1.0 / std::sqrt(static_cast<double>(a.headDim())));
  const ocl::Tensor valueMap = ocl::matmul(a.fc_, a.wv_);
  const std::string options = "-DVIEWS=" + std::to_string(V) + " -DCH=" + std::to_string(C);
  ocl::Tensor out = ocl::Tensor::empty({S, 4 * C, h, w}, samples.dtype());
  ocl::Launch("view_attention", "view_attention_meanvar", samples.dtype(), options)
      .arg(static_cast<int>(S))
      .arg(hw)
      .arg(samples)
      .arg(weights)
      .arg(scoreMap)
      .arg(valueMap)
      .arg(a.lnWeight_)
      .arg(a.lnBias_)
      .real(MultiHeadAttention::kLayerNormEps)
      .arg(out)
      .run2(hw, S, 64, 1);
  const std::vector<ocl::Tensor> inputs{samples,  weights,     scoreMap,
                                        valueMap, a.lnWeight_, a.lnBias_};
  if (!ocl::needsGrad(inputs))
    return out;
  FusedInputs saved{samples.detach(),  weights.detach(),     scoreMap.detach(),
                    valueMap.detach(), a.lnWeight_.detach(), a.lnBias_.detach()};
  return ocl::record("viewAttentionAggregate", out, inputs, [saved, options](const ocl::Tensor& g) {
    return fusedBackward(saved, g, options);
  });
}

} // namespace simpli::network
