// ViewAttention::aggregate: the fused inference form of an MLI level's view aggregation
// (model/kernels/view_attention.cl). The composed form (MultiHeadAttention::forward plus the
// weighted mean / variance in generator/mli_corrections.cpp) stays the reference and the
// training path; tests/model/network/test_view_aggregation.cpp holds the two together.
#include "simpli/model/network/attention.h"

#include "model_kernels.h"
#include "simpli/error.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/launch.h"
#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_linalg.h"

#include <cmath>
#include <string>

namespace simpli::network {

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
  if (ocl::needsGrad({samples, weights, a.wq_, a.wk_, a.wv_, a.fc_, a.lnWeight_, a.lnBias_}))
    fail("ViewAttention::aggregate: a gradient is needed; the fused kernel is forward only "
         "(use forward() and the composed mean / variance)");
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
      .real(1e-6)
      .arg(out)
      .run2(hw, S, 64, 1);
  return out;
}

} // namespace simpli::network
