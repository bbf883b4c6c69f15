#pragma once
// Attention modules (spec §4.6 - §4.8).
#include "simpli/model/network/parameter_store.h"

#include "simpli/ocl/tensor.h"

#include <string>

namespace simpli::network {

/// The reference's MultiHeadAttention with residual = False: bias-free projections
/// Q = q W_q, K = x W_k, V = x W_v to heads x headDim channels (hidden index head * headDim + i),
/// per head softmax((Q / sqrt(headDim)) K^T) over the keys, heads concatenated, then
/// out = LayerNorm(O W_fc) (bias-free fc; biased variance, eps 1e-6). No masking, no residual.
/// Keys: <prefix>.{w_qs,w_ks,w_vs}.weight [heads * headDim, in], <prefix>.fc.weight
/// [out, heads * headDim], <prefix>.layer_norm.{weight,bias} [out].
class MultiHeadAttention {
public:
  MultiHeadAttention() = default;
  MultiHeadAttention(ParameterStore& store, const std::string& prefix, int in, int heads,
                     int headDim, int out);

  /// queries [N, nq, in] (or [nq, in], shared by every batch entry), keysValues [N, nk, in]
  /// -> [N, nq, out]. When `attention` is given it receives the softmax weights
  /// [N, heads, nq, nk].
  ocl::Tensor forward(const ocl::Tensor& queries, const ocl::Tensor& keysValues,
                      ocl::Tensor* attention = nullptr) const;

  /// The output LayerNorm's epsilon (the reference's), shared with the fused aggregation.
  static constexpr double kLayerNormEps = 1e-6;

  int inChannels() const { return in_; }
  int outChannels() const { return out_; }
  int heads() const { return heads_; }
  int headDim() const { return headDim_; }

private:
  friend class ViewAttention; // its fused path reads the weights directly
  int in_ = 0, heads_ = 1, headDim_ = 0, out_ = 0;
  ocl::Tensor wq_, wk_, wv_, fc_, lnWeight_, lnBias_;
};

/// The MLI blocks' view self-attention (`samli_block_lvlK.attention_agg`, §4.7 step 7): per
/// (surface, pixel) the V tokens [samples (Cin) | aggregation weight (1)] attend to each other
/// with one head of `hidden` channels (temperature sqrt(hidden) = 4) and are mapped back to
/// Cin channels. Invalid views are not masked (they carry zero samples and zero weight).
class ViewAttention {
public:
  ViewAttention() = default;
  ViewAttention(ParameterStore& store, const std::string& prefix, int sourceChannels, int hidden);

  /// tokens [N, V, Cin + 1] -> [N, V, Cin].
  ocl::Tensor forward(const ocl::Tensor& tokens, ocl::Tensor* attention = nullptr) const;

  /// The whole aggregation of an MLI correction level in one kernel (and one for its
  /// gradients, to the samples, weights and all attention parameters): samples
  /// [V, S, Cin, h, w] and their view weights
  /// [V, S, 1, h, w] -> [S, 4 Cin, h, w] = the weighted mean and variance over the views of
  /// the samples, then of forward([samples | weight]) (view_aggregation.cpp).
  ocl::Tensor aggregate(const ocl::Tensor& samples, const ocl::Tensor& weights) const;
  /// Views the fused kernel keeps in private memory (more fall back to the composed form).
  static constexpr int kMaxFusedViews = 32;
  int sourceChannels() const { return attention_.outChannels(); }

private:
  MultiHeadAttention attention_;
};

/// AnchoredRayAttention (`planes_deformer_lvl1`, §4.8): per reference pixel, the P plane
/// tokens plus PE_C(position * (P - 1)) are pooled into L layer tokens by attention from L
/// learned anchors (<prefix>.anchor [L, C], drawn N(0, 1)); <prefix>.ray_attention is a
/// MultiHeadAttention C -> heads x headDim -> C (2 x 10 in the reference). Anchors carry no
/// positional code; there is no residual. Layer k is anchor k (layer 0 = farthest).
class AnchoredRayAttention {
public:
  AnchoredRayAttention() = default;
  AnchoredRayAttention(ParameterStore& store, const std::string& prefix, int channels, int layers,
                       int heads, int headDim);

  /// planes [B, P, C, H, W], positions [P] (normalised disparities in [0, 1], p / (P - 1) for
  /// the reference's planes; same dtype) -> [B, L, C, H, W]. Pixels are independent, so any
  /// crop of the planes gives the same crop of the output.
  ocl::Tensor forward(const ocl::Tensor& planes, const ocl::Tensor& positions) const;
  int layers() const { return layers_; }
  int channels() const { return channels_; }

private:
  int channels_ = 0, layers_ = 0;
  ocl::Tensor anchor_;
  MultiHeadAttention attention_;
};

} // namespace simpli::network
