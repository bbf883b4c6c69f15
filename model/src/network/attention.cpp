// MultiHeadAttention, ViewAttention and AnchoredRayAttention (reference §4.6 - §4.8).
#include "simpli/model/network/attention.h"

#include "simpli/error.h"

#include "simpli/ocl/ops_attention.h"
#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_encoding.h"
#include "simpli/ocl/ops_linalg.h"
#include "simpli/ocl/ops_norm.h"
#include "simpli/ocl/ops_shape.h"
#include "simpli/ocl/ops_softmax.h"

#include <cmath>

namespace simpli::network {
namespace {

std::string describe(const ocl::Tensor& t) {
  return t.defined() ? t.describe() : "undefined";
}

} // namespace

MultiHeadAttention::MultiHeadAttention(ParameterStore& store, const std::string& prefix, int in,
                                       int heads, int headDim, int out)
    : in_(in), heads_(heads), headDim_(headDim), out_(out) {
  if (in < 1 || heads < 1 || headDim < 1 || out < 1)
    fail("MultiHeadAttention ", prefix, ": in ", in, ", heads ", heads, ", head dim ", headDim,
         ", out ", out, " must be positive");
  const int hidden = heads * headDim;
  wq_ = store.add(prefix + ".w_qs.weight", {hidden, in}, {InitKind::FanInUniform, in});
  wk_ = store.add(prefix + ".w_ks.weight", {hidden, in}, {InitKind::FanInUniform, in});
  wv_ = store.add(prefix + ".w_vs.weight", {hidden, in}, {InitKind::FanInUniform, in});
  fc_ = store.add(prefix + ".fc.weight", {out, hidden}, {InitKind::FanInUniform, hidden});
  lnWeight_ = store.add(prefix + ".layer_norm.weight", {out}, {InitKind::Ones});
  lnBias_ = store.add(prefix + ".layer_norm.bias", {out}, {InitKind::Zeros});
}

ocl::Tensor MultiHeadAttention::forward(const ocl::Tensor& queries, const ocl::Tensor& keysValues,
                                        ocl::Tensor* attention) const {
  if (!keysValues.defined() || keysValues.dim() != 3 || keysValues.size(2) != in_)
    fail("MultiHeadAttention: keys/values ", describe(keysValues), " must be [N, nk, ", in_, "]");
  const bool shared = queries.defined() && queries.dim() == 2;
  if (!queries.defined() || (queries.dim() != 3 && !shared) || queries.size(-1) != in_ ||
      (!shared && queries.size(0) != keysValues.size(0)))
    fail("MultiHeadAttention: queries ", describe(queries), " must be [", keysValues.size(0),
         ", nq, ", in_, "] or [nq, ", in_, "] (keys/values ", keysValues.describe(), ")");
  const int64_t N = keysValues.size(0), nk = keysValues.size(1), nq = queries.size(-2);
  const double invTemperature = 1.0 / std::sqrt(static_cast<double>(headDim_));
  std::vector<ocl::Tensor> outputs, maps;
  for (int h = 0; h < heads_; ++h) {
    // Per-head projections with row slices of the (tiny) weights: the activations are never
    // split or permuted by head.
    auto rows = [&](const ocl::Tensor& w) {
      return heads_ == 1 ? w : ocl::slice(w, 0, int64_t(h) * headDim_, int64_t(h + 1) * headDim_);
    };
    const ocl::Tensor q = ocl::mulScalar(ocl::linear(queries, rows(wq_)), invTemperature);
    const ocl::Tensor k = ocl::linear(keysValues, rows(wk_)); // [N, nk, d]
    const ocl::Tensor v = ocl::linear(keysValues, rows(wv_));
    ocl::Tensor o, a;
    if (!attention) {
      // The fused kernel: one work item per query, no [N, nq, nk] score tensors (the composed
      // form below costs one tiny GEMM per sequence, ~100x slower for per-pixel sequences).
      o = ocl::attention(q, k, v, 1.0);
    } else if (shared) {
      // Shared queries (anchors): the scores of all rays are one GEMM, K [N*nk, d] x q^T,
      // giving [N, nk, nq]; the softmax runs over the keys (axis 1).
      const ocl::Tensor at = ocl::softmax(ocl::matmul(k, q, false, true), 1);
      o = ocl::matmul(at, v, true, false); // [N, nq, d]
      if (attention)
        a = ocl::transpose(at, 1, 2);
    } else {
      a = ocl::softmax(ocl::matmul(q, k, false, true), 2); // [N, nq, nk]
      o = ocl::matmul(a, v);
    }
    outputs.push_back(o);
    if (attention)
      maps.push_back(ocl::reshape(a, {N, 1, nq, nk}));
  }
  const ocl::Tensor joined = heads_ == 1 ? outputs[0] : ocl::concat(outputs, 2);
  if (attention)
    *attention = heads_ == 1 ? maps[0] : ocl::concat(maps, 1);
  return ocl::layerNorm(ocl::linear(joined, fc_), lnWeight_, lnBias_, kLayerNormEps);
}

ViewAttention::ViewAttention(ParameterStore& store, const std::string& prefix, int sourceChannels,
                             int hidden)
    : attention_(store, prefix, sourceChannels + 1, 1, hidden, sourceChannels) {}

ocl::Tensor ViewAttention::forward(const ocl::Tensor& tokens, ocl::Tensor* attention) const {
  if (!tokens.defined() || tokens.dim() != 3 || tokens.size(2) != attention_.inChannels())
    fail("ViewAttention: tokens ", describe(tokens), " must be [N, V, ", attention_.inChannels(),
         "] (", attention_.outChannels(), " samples + weight)");
  return attention_.forward(tokens, tokens, attention);
}

AnchoredRayAttention::AnchoredRayAttention(ParameterStore& store, const std::string& prefix,
                                           int channels, int layers, int heads, int headDim)
    : channels_(channels), layers_(layers) {
  if (layers < 1)
    fail("AnchoredRayAttention ", prefix, ": ", layers, " layers");
  anchor_ = store.add(prefix + ".anchor", {layers, channels}, {InitKind::Normal01});
  attention_ =
      MultiHeadAttention(store, prefix + ".ray_attention", channels, heads, headDim, channels);
}

ocl::Tensor AnchoredRayAttention::forward(const ocl::Tensor& planes,
                                          const ocl::Tensor& positions) const {
  if (!planes.defined() || planes.dim() != 5 || planes.size(2) != channels_)
    fail("AnchoredRayAttention: planes ", describe(planes), " must be [B, P, ", channels_,
         ", H, W]");
  const int64_t B = planes.size(0), P = planes.size(1), H = planes.size(3), W = planes.size(4);
  if (!positions.defined() || positions.dim() != 1 || positions.size(0) != P ||
      positions.dtype() != planes.dtype())
    fail("AnchoredRayAttention: positions ", describe(positions), " must be [", P,
         "] in the dtype of planes ", planes.describe());
  // One token sequence per pixel: [B, H, W, P, C] -> [B*H*W, P, C] (the one layout copy in).
  ocl::Tensor tokens =
      ocl::reshape(ocl::permute(planes, {0, 3, 4, 1, 2}), {B * H * W, P, channels_});
  // PE of the plane index, computed like the reference from the normalised position.
  const ocl::Tensor code =
      ocl::positionalEncoding(ocl::mulScalar(positions, static_cast<double>(P - 1)), channels_);
  tokens = ocl::add(tokens, code);
  const ocl::Tensor pooled = attention_.forward(anchor_, tokens); // [B*H*W, L, C]
  // ... and the one layout copy out.
  return ocl::permute(ocl::reshape(pooled, {B, H, W, layers_, channels_}), {0, 3, 4, 1, 2});
}

} // namespace simpli::network
