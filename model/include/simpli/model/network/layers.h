#pragma once
// The reference's basic layers (spec §4.1, §4.3, §4.4). Every module registers
// its parameters in a ParameterStore under the reference's state-dict names and keeps handles
// to them; forward() runs in the store's dtype and records on the autograd tape.
//
// Tensor layouts: 2-D modules take [N, C, H, W], 3-D modules [N, C, D, H, W]. N is a batch of
// independent samples (views, planes or layers): every normalisation here is per sample.
#include "simpli/model/network/config.h"
#include "simpli/model/network/parameter_store.h"

#include "simpli/ocl/ops_conv.h"
#include "simpli/ocl/tensor.h"

#include <string>
#include <vector>

namespace simpli::network {

ocl::Tensor activate(const ocl::Tensor& x, Activation activation);

/// Padding -> convolution (with bias) -> optional LayerNormTotal -> optional activation. Keys:
/// <prefix>.conv.{weight,bias} and, with the norm, <prefix>.norm.{gamma,beta}.
class ConvBlock {
public:
  struct Options {
    int spatialDims = 2; ///< 2 (Conv2d) or 3 (Conv3d)
    int kernel = 3;      ///< odd; padding kernel / 2 keeps the size
    ocl::PaddingMode padding = ocl::PaddingMode::Zeros;
    bool norm = true; ///< LayerNormTotal (unbiased std, std + 1e-5)
    Activation activation = Activation::None;
  };

  ConvBlock() = default;
  ConvBlock(ParameterStore& store, const std::string& prefix, int inChannels, int outChannels,
            const Options& options);

  ocl::Tensor forward(const ocl::Tensor& x) const;
  int inChannels() const { return in_; }
  int outChannels() const { return out_; }

private:
  int in_ = 0, out_ = 0;
  Options options_;
  ocl::Tensor weight_, bias_, gamma_, beta_;
};

/// The TBlock's DoubleConvBlock (§4.3): y = LN(conv(pad_rep(ELU(LN(conv(pad_rep(x))))))) with
/// 3x3 (x3) kernels and replicate padding, plus the residual r = x, or a 1x1 conv with bias when
/// in != out; out = y + r, then ELU unless this is the last block of its stack.
/// Keys: <prefix>.double_conv.{0,1}.*, <prefix>.residual_conv.conv.{weight,bias}.
class DoubleConvBlock {
public:
  DoubleConvBlock() = default;
  DoubleConvBlock(ParameterStore& store, const std::string& prefix, int spatialDims, int in,
                  int inner, int out, bool last);

  ocl::Tensor forward(const ocl::Tensor& x) const;
  int inChannels() const { return first_.inChannels(); }
  int outChannels() const { return second_.outChannels(); }

private:
  ConvBlock first_, second_, residual_;
  bool hasResidualConv_ = false;
  bool last_ = false;
};

/// A stack of DoubleConvBlocks (the TBlock's post_aggregate_block): <prefix>.model.<i>; block i
/// has [inner, out] = dims[i] and takes the previous block's output (the first takes `in`); the
/// last block has no output activation.
class DoubleConvResnet {
public:
  DoubleConvResnet() = default;
  DoubleConvResnet(ParameterStore& store, const std::string& prefix, int spatialDims, int in,
                   const std::vector<BlockDims>& dims);

  ocl::Tensor forward(const ocl::Tensor& x) const;
  int inChannels() const { return blocks_.front().inChannels(); }
  int outChannels() const { return blocks_.back().outChannels(); }
  const std::vector<DoubleConvBlock>& blocks() const { return blocks_; }

private:
  std::vector<DoubleConvBlock> blocks_;
};

/// The reference's ConvMLP decoder (§4.4): 1x1 convolutions with bias, in -> hidden... -> out,
/// the activation after every layer but the last. Keys <prefix>.model.<i>.conv.{weight,bias}.
class ConvMLP {
public:
  ConvMLP() = default;
  ConvMLP(ParameterStore& store, const std::string& prefix, int in, const DecoderConfig& config,
          int out);

  /// x [N, in, H, W] -> [N, out, H, W] (raw, before any output squashing).
  ocl::Tensor forward(const ocl::Tensor& x) const;
  int inChannels() const { return layers_.front().inChannels(); }
  int outChannels() const { return layers_.back().outChannels(); }

private:
  std::vector<ConvBlock> layers_;
};

} // namespace simpli::network
