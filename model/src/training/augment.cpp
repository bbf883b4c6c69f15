// Photometric augmentations of training samples (training/augment.h).
#include "simpli/model/training/augment.h"

#include "simpli/model/training/sampler.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace simpli::training {

void mixupSources(TrainingSample& sample, const SamplingConfig& config, TrainRandom& random) {
  const int V = int(sample.cleanSources.size());
  sample.sources = sample.cleanSources;
  sample.mixupPartner.assign(size_t(V), -1);
  sample.mixupLambda.assign(size_t(V), 0.0);
  if (V < 2 || config.mixupProbability <= 0)
    return;
  for (int v = 0; v < V; ++v) {
    if (!random.chance(config.mixupProbability))
      continue;
    int other = int(random.uniformInt(0, V - 2));
    if (other >= v)
      ++other;
    const double lambda = random.uniform(config.mixupLambdaMin, config.mixupLambdaMax);
    const io::Image& a = sample.cleanSources[size_t(v)];
    const io::Image& b = sample.cleanSources[size_t(other)];
    io::Image& out = sample.sources[size_t(v)];
    for (size_t i = 0; i < out.data.size(); ++i)
      out.data[i] = float((1.0 - lambda) * a.data[i] + lambda * b.data[i]);
    sample.mixupPartner[size_t(v)] = other;
    sample.mixupLambda[size_t(v)] = lambda;
  }
}

// Seeds of the augmentations' own streams: the sampler's state mixed with a golden-ratio or
// SplitMix64 multiplier and a tag (ASCII "PHOTO", "SHARP") that keeps the two streams apart.
// Changing any of them changes every run's gains or sharpening (and breaks bit-for-bit resume
// of runs made before).
constexpr uint64_t kGainMultiplier = 0x9E3779B97F4A7C15ULL, kGainTag = 0x50484f544fULL;
constexpr uint64_t kSharpenMultiplier = 0xBF58476D1CE4E5B9ULL, kSharpenTag = 0x5348415250ULL;

/// SamplingConfig::sourceExposureStd: the gains come from a stream seeded by the sampler's state
/// after this sample's draws (read, not advanced), so the sample sequence is the same with or
/// without the jitter and a resumed run draws the same gains.
void jitterSourceGains(TrainingSample& s, const SamplingConfig& config,
                       const TrainRandom::State& state) {
  TrainRandom random(state[0] ^ (state[1] * kGainMultiplier) ^ kGainTag);
  for (io::Image& image : s.sources) {
    const double exposure = config.sourceExposureStd * random.normal();
    std::array<double, 3> gains{};
    for (double& g : gains)
      g = std::exp(exposure + config.sourceChannelStd * random.normal());
    const size_t plane = image.data.size() / 3;
    for (size_t c = 0; c < 3; ++c)
      for (size_t i = c * plane; i < (c + 1) * plane; ++i) {
        const double x = std::clamp(0.5 * (double(image.data[i]) + 1.0) * gains[c], 0.0, 1.0);
        image.data[i] = float(2.0 * x - 1.0);
      }
    s.sourceGains.push_back(gains);
  }
}

void unsharpMask(io::Image& image, double amount) {
  static const double kTaps[5] = {0.05448868, 0.24420134, 0.40261995, 0.24420134, 0.05448868};
  const int W = image.width, H = image.height;
  std::vector<double> rows(size_t(W) * H), blurred(size_t(W) * H);
  for (int c = 0; c < 3; ++c) {
    float* x = image.plane(c);
    for (int y = 0; y < H; ++y)
      for (int i = 0; i < W; ++i) {
        double sum = 0;
        for (int k = -2; k <= 2; ++k)
          sum += kTaps[k + 2] * x[size_t(y) * W + size_t(std::clamp(i + k, 0, W - 1))];
        rows[size_t(y) * W + i] = sum;
      }
    for (int y = 0; y < H; ++y)
      for (int i = 0; i < W; ++i) {
        double sum = 0;
        for (int k = -2; k <= 2; ++k)
          sum += kTaps[k + 2] * rows[size_t(std::clamp(y + k, 0, H - 1)) * W + i];
        blurred[size_t(y) * W + i] = sum;
      }
    for (size_t i = 0; i < size_t(W) * H; ++i)
      x[i] = float(std::clamp(x[i] + amount * (x[i] - blurred[i]), -1.0, 1.0));
  }
}

/// SamplingConfig::sharpenProbability: one amount for every view of the sample, drawn from the
/// sampler's state after the frame and crop draws (read, not advanced).
double drawSharpenAmount(const SamplingConfig& config, const TrainRandom::State& state) {
  TrainRandom random(state[2] ^ (state[3] * kSharpenMultiplier) ^ kSharpenTag);
  if (!random.chance(config.sharpenProbability))
    return 0.0;
  return random.uniform(0.0, config.sharpenMax);
}

} // namespace simpli::training
