// ConvBlock, DoubleConvBlock, DoubleConvResnet and ConvMLP (reference §4.1, §4.3, §4.4).
#include "simpli/model/network/layers.h"

#include "simpli/error.h"

#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_norm.h"

namespace simpli::network {

ocl::Tensor activate(const ocl::Tensor& x, Activation activation) {
  switch (activation) {
  case Activation::None:
    return x;
  case Activation::Relu:
    return ocl::relu(x);
  case Activation::Elu:
    return ocl::elu(x, 1.0);
  }
  return x;
}

ConvBlock::ConvBlock(ParameterStore& store, const std::string& prefix, int inChannels,
                     int outChannels, const Options& options)
    : in_(inChannels), out_(outChannels), options_(options) {
  if (options.spatialDims != 2 && options.spatialDims != 3)
    fail("ConvBlock ", prefix, ": ", options.spatialDims, " spatial dimensions (2 or 3)");
  if (options.kernel < 1 || options.kernel % 2 == 0)
    fail("ConvBlock ", prefix, ": kernel ", options.kernel, " must be odd and positive");
  if (inChannels < 1 || outChannels < 1)
    fail("ConvBlock ", prefix, ": channels ", inChannels, " -> ", outChannels);
  ocl::Shape wshape{outChannels, inChannels};
  int64_t fanIn = inChannels;
  for (int d = 0; d < options.spatialDims; ++d) {
    wshape.push_back(options.kernel);
    fanIn *= options.kernel;
  }
  weight_ = store.add(prefix + ".conv.weight", wshape, {InitKind::FanInUniform, fanIn});
  bias_ = store.add(prefix + ".conv.bias", {outChannels}, {InitKind::FanInUniform, fanIn});
  if (options.norm) {
    gamma_ = store.add(prefix + ".norm.gamma", {outChannels}, {InitKind::Uniform01});
    beta_ = store.add(prefix + ".norm.beta", {outChannels}, {InitKind::Zeros});
  }
}

ocl::Tensor ConvBlock::forward(const ocl::Tensor& x) const {
  const int pad = options_.kernel / 2;
  ocl::Tensor y = options_.spatialDims == 2
                      ? ocl::conv2d(x, weight_, bias_, 1, pad, options_.padding)
                      : ocl::conv3d(x, weight_, bias_, 1, pad, options_.padding);
  if (options_.norm)
    y = ocl::layerNormTotal(y, gamma_, beta_, 1e-5);
  return activate(y, options_.activation);
}

DoubleConvBlock::DoubleConvBlock(ParameterStore& store, const std::string& prefix, int spatialDims,
                                 int in, int inner, int out, bool last)
    : hasResidualConv_(in != out), last_(last) {
  ConvBlock::Options conv;
  conv.spatialDims = spatialDims;
  conv.kernel = 3;
  conv.padding = ocl::PaddingMode::Replicate;
  conv.norm = true;
  // The reference registers the residual conv first; registration order is kept for readable
  // listings (the file format itself is keyed by name).
  if (hasResidualConv_) {
    ConvBlock::Options res;
    res.spatialDims = spatialDims;
    res.kernel = 1;
    res.norm = false;
    residual_ = ConvBlock(store, prefix + ".residual_conv", in, out, res);
  }
  conv.activation = Activation::Elu;
  first_ = ConvBlock(store, prefix + ".double_conv.0", in, inner, conv);
  conv.activation = Activation::None;
  second_ = ConvBlock(store, prefix + ".double_conv.1", inner, out, conv);
}

ocl::Tensor DoubleConvBlock::forward(const ocl::Tensor& x) const {
  const ocl::Tensor y = second_.forward(first_.forward(x));
  const ocl::Tensor r = hasResidualConv_ ? residual_.forward(x) : x;
  const ocl::Tensor sum = ocl::add(y, r);
  return last_ ? sum : ocl::elu(sum, 1.0);
}

DoubleConvResnet::DoubleConvResnet(ParameterStore& store, const std::string& prefix,
                                   int spatialDims, int in, const std::vector<BlockDims>& dims) {
  if (dims.empty())
    fail("DoubleConvResnet ", prefix, ": no blocks");
  int channels = in;
  for (std::size_t i = 0; i < dims.size(); ++i) {
    blocks_.emplace_back(store, prefix + ".model." + std::to_string(i), spatialDims, channels,
                         dims[i].inner, dims[i].out, i + 1 == dims.size());
    channels = dims[i].out;
  }
}

ocl::Tensor DoubleConvResnet::forward(const ocl::Tensor& x) const {
  ocl::Tensor y = x;
  for (const DoubleConvBlock& b : blocks_)
    y = b.forward(y);
  return y;
}

ConvMLP::ConvMLP(ParameterStore& store, const std::string& prefix, int in,
                 const DecoderConfig& config, int out) {
  std::vector<int> widths = config.hidden;
  widths.push_back(out);
  int channels = in;
  for (std::size_t i = 0; i < widths.size(); ++i) {
    ConvBlock::Options o;
    o.kernel = 1;
    o.norm = false;
    o.activation = i + 1 == widths.size() ? Activation::None : config.activation;
    layers_.emplace_back(store, prefix + ".model." + std::to_string(i), channels, widths[i], o);
    channels = widths[i];
  }
}

ocl::Tensor ConvMLP::forward(const ocl::Tensor& x) const {
  ocl::Tensor y = x;
  for (const ConvBlock& l : layers_)
    y = l.forward(y);
  return y;
}

} // namespace simpli::network
