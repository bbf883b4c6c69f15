#pragma once
// Photometric augmentations of a drawn training sample (training/sampler.h draws the views):
// source-only MixUp, per-source exposure and channel gains, and an unsharp mask on every view.
// MixUp advances the sampler's random stream (it predates checkpointed runs that must keep their
// samples); the gains and the sharpening read the stream's state without advancing it, so turning
// them on or off leaves every other draw of a run unchanged.
#include "simpli/model/io/image.h"
#include "simpli/model/training/config.h"
#include "simpli/model/training/random.h"

namespace simpli::training {

struct TrainingSample;

/// Source-only MixUp (kornia RandomMixUp): with probability mixup_probability a source becomes
/// (1 - lambda) * itself + lambda * another source of the sample, lambda ~ U[low, high]. Fills
/// sample.sources from sample.cleanSources and records partners and lambdas.
void mixupSources(TrainingSample& sample, const SamplingConfig& config, TrainRandom& random);

/// SamplingConfig::sourceExposureStd / sourceChannelStd: each source's RGB gains exp(e + c_k),
/// e and c_k normal, applied in [0, 1] and clipped; recorded in sample.sourceGains.
void jitterSourceGains(TrainingSample& sample, const SamplingConfig& config,
                       const TrainRandom::State& state);

/// SamplingConfig::sharpenProbability / sharpenMax: the amount for every view of one sample
/// (0 = none).
double drawSharpenAmount(const SamplingConfig& config, const TrainRandom::State& state);

/// x + amount (x - G(x)) per channel, G a Gaussian of sigma 1 pixel (taps -2 .. 2, borders
/// clamped), clipped to [-1, 1]. Real photographs are sharper than rendered procedural scenes;
/// this closes that gap in the training data.
void unsharpMask(io::Image& image, double amount);

} // namespace simpli::training
