// Function-preserving widening (widen.h).
#include "simpli/model/network/widen.h"

#include "simpli/error.h"

#include <cmath>
#include <map>
#include <random>
#include <set>
#include <string>
#include <vector>

namespace simpli::network {
namespace {

/// Where each channel of a widened layer comes from: the old channel and which of its copies it
/// is. A fixed (not widened) width maps every channel to itself as copy 0 of 1.
struct ChannelMap {
  std::vector<int> source; ///< old channel of each new channel
  std::vector<int> copy;   ///< 0 .. copies - 1
  int copies = 1;
  int oldSize = 0;
  int size() const { return int(source.size()); }
};

ChannelMap fixedChannels(int channels) {
  ChannelMap m;
  m.oldSize = channels;
  for (int c = 0; c < channels; ++c) {
    m.source.push_back(c);
    m.copy.push_back(0);
  }
  return m;
}

/// Channel c + k C of the new layer is copy k of old channel c.
ChannelMap copiedChannels(int channels, int factor) {
  ChannelMap m;
  m.copies = factor;
  m.oldSize = channels;
  for (int k = 0; k < factor; ++k)
    for (int c = 0; c < channels; ++c) {
      m.source.push_back(c);
      m.copy.push_back(k);
    }
  return m;
}

/// The maps of concatenated inputs, old channels offset by the parts before (all parts must
/// have the same number of copies).
ChannelMap concatenated(const std::vector<ChannelMap>& parts) {
  ChannelMap m;
  m.copies = parts.front().copies;
  for (const ChannelMap& p : parts) {
    for (int c = 0; c < p.size(); ++c) {
      m.source.push_back(m.oldSize + p.source[size_t(c)]);
      m.copy.push_back(p.copy[size_t(c)]);
    }
    m.oldSize += p.oldSize;
  }
  return m;
}

struct HostTensor {
  ocl::Shape shape;
  std::vector<double> values;
};

/// Writes the new network's parameters from the old one's, each exactly once.
class WeightMapper {
public:
  WeightMapper(const ParameterStore& from, ParameterStore& to, const WidenOptions& options)
      : from_(from), to_(to), options_(options) {}

  /// A layer's weight [out, in, k...] and bias [out]: rows follow `out`, columns `in`; the
  /// copies of an input channel share its weight (+- the perturbation, zero-sum over copies).
  void linear(const std::string& weight, const std::string& bias, const ChannelMap& out,
              const ChannelMap& in) {
    const HostTensor old = read(weight);
    if (old.shape.size() < 2 || old.shape[0] != out.oldSize || old.shape[1] != in.oldSize)
      fail("widen: ", weight, " has shape ", ocl::toString(old.shape), ", expected [", out.oldSize,
           ", ", in.oldSize, ", ...]");
    const int64_t oldIn = old.shape[1], inner = kernelVolume(old.shape);
    const double sigma = options_.noise * rms(old.values);
    const std::vector<double> z = perturbation(weight, int64_t(out.size()) * oldIn * inner);
    std::vector<double> v(size_t(out.size()) * size_t(in.size()) * size_t(inner));
    for (int o = 0; o < out.size(); ++o)
      for (int i = 0; i < in.size(); ++i)
        for (int64_t r = 0; r < inner; ++r) {
          const int64_t src = int64_t(in.source[size_t(i)]) * inner + r;
          const int64_t row = int64_t(o) * oldIn * inner;
          const double w = old.values[size_t(int64_t(out.source[size_t(o)]) * oldIn * inner + src)];
          v[size_t((int64_t(o) * in.size() + i) * inner + r)] =
              w / in.copies + share(in, i) * sigma * z[size_t(row + src)];
        }
    write(weight, v);
    if (!bias.empty())
      rows(bias, out);
  }

  /// A 1-D per-channel parameter (bias, norm gain or shift) following `out`.
  void rows(const std::string& name, const ChannelMap& out) {
    const HostTensor old = read(name);
    if (old.shape.size() != 1 || old.shape[0] != out.oldSize)
      fail("widen: ", name, " has shape ", ocl::toString(old.shape), ", expected [", out.oldSize,
           "]");
    std::vector<double> v;
    for (int o = 0; o < out.size(); ++o)
      v.push_back(old.values[size_t(out.source[size_t(o)])]);
    write(name, v);
  }

  /// A ConvBlock: <prefix>.conv.{weight,bias} and, when the block has one, its norm.
  void convBlock(const std::string& prefix, const ChannelMap& out, const ChannelMap& in) {
    linear(prefix + ".conv.weight", prefix + ".conv.bias", out, in);
    if (to_.contains(prefix + ".norm.gamma")) {
      rows(prefix + ".norm.gamma", out);
      rows(prefix + ".norm.beta", out);
    }
  }

  /// A residual that was the identity and becomes a 1x1 convolution (its input widened, its
  /// output not): the mean of each channel's copies, which are equal, so the identity again.
  void identityAsConv(const std::string& prefix, const ChannelMap& out, const ChannelMap& in) {
    const std::string weight = prefix + ".conv.weight";
    const ocl::Shape shape = to_.get(weight).shape();
    const int64_t inner = kernelVolume(shape);
    if (inner != 1 || shape[0] != out.size() || shape[1] != in.size())
      fail("widen: ", weight, " has shape ", ocl::toString(shape), ", expected a 1x1 conv ",
           in.size(), " -> ", out.size());
    const double sigma = options_.noise / in.copies;
    const std::vector<double> z = perturbation(weight, int64_t(out.size()) * in.oldSize);
    std::vector<double> v(size_t(out.size()) * size_t(in.size()), 0.0);
    for (int o = 0; o < out.size(); ++o)
      for (int i = 0; i < in.size(); ++i)
        if (in.source[size_t(i)] == out.source[size_t(o)])
          v[size_t(o * in.size() + i)] =
              1.0 / in.copies +
              share(in, i) * sigma * z[size_t(o * in.oldSize + in.source[size_t(i)])];
    write(weight, v);
    write(prefix + ".conv.bias", std::vector<double>(size_t(out.size()), 0.0));
  }

  /// Every parameter not written yet keeps its values (it must keep its shape too).
  void copyTheRest() {
    for (const std::string& name : to_.names()) {
      if (written_.count(name))
        continue;
      const HostTensor old = read(name);
      if (old.shape != to_.get(name).shape())
        fail("widen: ", name, " changes shape (", ocl::toString(old.shape), " -> ",
             ocl::toString(to_.get(name).shape()), ") but has no widening rule");
      write(name, old.values);
    }
  }

private:
  static int64_t kernelVolume(const ocl::Shape& s) {
    int64_t n = 1;
    for (size_t d = 2; d < s.size(); ++d)
      n *= s[d];
    return n;
  }
  static double rms(const std::vector<double>& v) {
    double s = 0;
    for (double x : v)
      s += x * x;
    return v.empty() ? 0.0 : std::sqrt(s / double(v.size()));
  }
  /// The sign and size of copy k's perturbation: k - (copies - 1) / 2 sums to zero over the
  /// copies of a channel, so what a reader adds up from equal copies is unchanged.
  static double share(const ChannelMap& in, int i) {
    return in.copies == 1 ? 0.0 : in.copy[size_t(i)] - 0.5 * (in.copies - 1);
  }
  /// One uniform draw in [-1, 1] per (new row, old column, kernel tap), shared by the copies of
  /// the column (each scales it by its share), from the seed and the parameter's name.
  std::vector<double> perturbation(const std::string& name, int64_t count) const {
    uint64_t h = 1469598103934665603ull ^ options_.seed; // FNV-1a of the name
    for (unsigned char c : name)
      h = (h ^ c) * 1099511628211ull;
    std::mt19937_64 rng(h);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    std::vector<double> z(static_cast<size_t>(count));
    for (double& x : z)
      x = uniform(rng);
    return z;
  }
  HostTensor read(const std::string& name) const {
    const ocl::Tensor& t = from_.get(name);
    return {t.shape(), t.toVector()};
  }
  void write(const std::string& name, const std::vector<double>& values) {
    if (!written_.insert(name).second)
      fail("widen: ", name, " written twice");
    ocl::Tensor t = to_.get(name);
    if (int64_t(values.size()) != t.numel())
      fail("widen: ", name, " gets ", values.size(), " values for shape ",
           ocl::toString(t.shape()));
    t.copyFromHost(values);
  }

  const ParameterStore& from_;
  ParameterStore& to_;
  WidenOptions options_;
  std::set<std::string> written_;
};

void widenFeatureExtractor(WeightMapper& m, const NetworkConfig& c, int f) {
  const std::vector<int>& w = c.featuresExtractor.widths;
  const std::string p = "features_extractor.";
  std::vector<ChannelMap> stage;
  for (int width : w)
    stage.push_back(copiedChannels(width, f));
  m.convBlock(p + "conv1a", stage[0], fixedChannels(c.featuresExtractor.inChannels));
  m.convBlock(p + "conv1b", stage[0], stage[0]);
  const char* names[3][2] = {{"conv2a", "conv2b"}, {"conv3a", "conv3b"}, {"conv4a", "conv4b"}};
  for (size_t s = 1; s < 4; ++s) {
    m.convBlock(p + names[s - 1][0], stage[s], stage[s - 1]);
    m.convBlock(p + names[s - 1][1], stage[s], stage[s]);
  }
  const ChannelMap head = copiedChannels(c.featuresExtractor.headWidth, f);
  m.convBlock(p + "convDa", head, concatenated(stage));
  m.convBlock(p + "convDb", fixedChannels(c.featuresExtractor.descriptors), head);
}

void widenTBlock(WeightMapper& m, const std::string& prefix, const TBlock& block,
                 const TBlockConfig& config, int f) {
  const std::vector<BlockDims> dims = postAggregateDims(config);
  ChannelMap in = fixedChannels(block.inChannels);
  for (size_t b = 0; b < dims.size(); ++b) {
    const bool last = b + 1 == dims.size();
    const std::string p = prefix + ".post_aggregate_block.model." + std::to_string(b);
    const ChannelMap inner = copiedChannels(dims[b].inner, f);
    const ChannelMap out = last ? fixedChannels(dims[b].out) : copiedChannels(dims[b].out, f);
    m.convBlock(p + ".double_conv.0", inner, in);
    m.convBlock(p + ".double_conv.1", out, inner);
    const bool oldConv = in.oldSize != dims[b].out, newConv = in.size() != out.size();
    if (oldConv && newConv)
      m.linear(p + ".residual_conv.conv.weight", p + ".residual_conv.conv.bias", out, in);
    else if (!oldConv && newConv)
      m.identityAsConv(p + ".residual_conv", out, in);
    else if (oldConv && !newConv)
      fail("widen: block ", p, " (", in.oldSize, " -> ", dims[b].inner, " -> ", dims[b].out,
           ") would become ", in.size(), " -> ", inner.size(), " -> ", out.size(),
           ": its residual 1x1 convolution turns into an identity, which cannot keep its "
           "function; choose another factor or widths");
    in = out;
  }
}

void widenDecoder(WeightMapper& m, const std::string& prefix, const ConvMLP& decoder,
                  const DecoderConfig& config, int f) {
  ChannelMap in = fixedChannels(decoder.inChannels());
  for (size_t l = 0; l <= config.hidden.size(); ++l) {
    const ChannelMap out = l < config.hidden.size() ? copiedChannels(config.hidden[l], f)
                                                    : fixedChannels(decoder.outChannels());
    m.linear(prefix + ".model." + std::to_string(l) + ".conv.weight",
             prefix + ".model." + std::to_string(l) + ".conv.bias", out, in);
    in = out;
  }
}

} // namespace

void checkWidenOptions(const WidenOptions& options) {
  if (options.factor < 2 || options.factor > 8)
    fail("widen: factor ", options.factor, " must be between 2 and 8");
  if (!(options.noise >= 0 && std::isfinite(options.noise)))
    fail("widen: noise ", options.noise, " must be finite and >= 0");
}

NetworkConfig widenedConfig(const NetworkConfig& config, int factor) {
  WidenOptions factorOnly;
  factorOnly.factor = factor;
  checkWidenOptions(factorOnly);
  NetworkConfig c = config;
  c.name =
      (config.name.empty() ? std::string("network") : config.name) + "-x" + std::to_string(factor);
  for (int& w : c.featuresExtractor.widths)
    w *= factor;
  c.featuresExtractor.headWidth *= factor;
  std::vector<TBlockConfig*> blocks{&c.sampiLvl0, &c.sampiLvl1};
  for (TBlockConfig& b : c.samliBlocks)
    blocks.push_back(&b);
  for (TBlockConfig* b : blocks)
    for (BlockDims& d : b->blocks) {
      d.inner *= factor;
      d.out *= factor;
    }
  for (DecoderConfig* d : {&c.alphaDecoder, &c.depthDecoder, &c.rgbaDecoder})
    for (int& h : d->hidden)
      h *= factor;
  return c;
}

LoadReport loadWithoutLvl0Prior(SimpliNetwork& net, const std::string& path) {
  NetworkConfig plain = net.config();
  if (!plain.lvl0PhotoPrior)
    fail("loadWithoutLvl0Prior: config '", plain.name, "' has no lvl0_photo_prior");
  plain.lvl0PhotoPrior = false;
  SimpliNetwork from(plain, net.parameters().dtype());
  const LoadReport report = from.parameters().load(path);
  for (const std::string& name : net.parameters().names()) {
    const ocl::Tensor& old = from.parameters().get(name);
    ocl::Tensor to = net.parameters().get(name);
    if (old.shape() == to.shape()) {
      to.copyFromHost(old.toVector());
      continue;
    }
    // A convolution reading the level-0 input: [out, in (+1), k...]; the prior is the last input.
    const ocl::Shape& a = old.shape();
    const ocl::Shape& b = to.shape();
    const bool oneMoreInput = a.size() == b.size() && a.size() >= 2 && b[1] == a[1] + 1 &&
                              a[0] == b[0] && std::equal(a.begin() + 2, a.end(), b.begin() + 2);
    if (!oneMoreInput || name.rfind("sampi_block_lvl0.", 0) != 0)
      fail("loadWithoutLvl0Prior: parameter \"", name, "\" is ", ocl::toString(a),
           " without the prior and ", ocl::toString(b), " with it");
    const std::vector<double> v = old.toVector();
    const size_t kernel = size_t(old.numel() / (a[0] * a[1]));
    std::vector<double> padded(size_t(to.numel()), 0.0);
    for (int64_t o = 0; o < a[0]; ++o)
      for (int64_t i = 0; i < a[1]; ++i)
        std::copy_n(v.begin() + long((size_t(o * a[1] + i)) * kernel), kernel,
                    padded.begin() + long((size_t(o * b[1] + i)) * kernel));
    to.copyFromHost(padded);
  }
  return report;
}

std::unique_ptr<SimpliNetwork> widenNetwork(const SimpliNetwork& from,
                                            const WidenOptions& options) {
  checkWidenOptions(options);
  const NetworkConfig& c = from.config();
  const int f = options.factor;
  auto to =
      std::make_unique<SimpliNetwork>(widenedConfig(c, f), from.parameters().dtype(), options.seed);
  WeightMapper m(from.parameters(), to->parameters(), options);
  widenFeatureExtractor(m, c, f);
  widenTBlock(m, "sampi_block_lvl0", from.sampiLvl0, c.sampiLvl0, f);
  widenDecoder(m, "alpha_decoder_lvl0", from.alphaDecoderLvl0, c.alphaDecoder, f);
  widenTBlock(m, "sampi_block_lvl1", from.sampiLvl1, c.sampiLvl1, f);
  if (from.depthDecoder)
    widenDecoder(m, "depth_decoder_lvl1", *from.depthDecoder, c.depthDecoder, f);
  for (size_t i = 0; i < from.rgbaDecoders.size(); ++i)
    widenDecoder(m, "rgba_decoder_lvl" + std::to_string(i + 1), from.rgbaDecoders[i], c.rgbaDecoder,
                 f);
  for (size_t i = 0; i < from.samliBlocks.size(); ++i)
    widenTBlock(m, "samli_block_lvl" + std::to_string(i + 2), from.samliBlocks[i], c.samliBlocks[i],
                f);
  m.copyTheRest();
  return to;
}

} // namespace simpli::network
