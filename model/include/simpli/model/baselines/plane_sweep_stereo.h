#pragma once
// A non-learned yardstick for the network: classical plane-sweep stereo in the reference camera,
// written as one opaque surface that renders like the network's layers. Per plane (disparity
// uniform over the input's depth range, as the network's planes), the sources are gathered into
// the reference grid (geometry::planeSweep); the matching cost is the variance of the gathered
// RGB over the views that see the point, summed over the channels and averaged over a square
// window; the depth is the softmin-expected disparity over the planes, and the colour the
// sources' mean at the plane nearest to it. A point seen by fewer than two sources gets the same
// high cost on every plane.
//
// What it says: on LLFF flower (5 sources from 256x192) this one-layer matcher renders the held-
// out views about as well as the shipped tiny network (docs/training.md, session 17), so a
// network has learnt geometry only where it beats it.
#include "simpli/model/generator/generator.h"

namespace simpli::baselines {

struct PlaneSweepStereoOptions {
  /// Planes, uniform in disparity between the input's depth bounds (GeneratorInput::minDepth /
  /// maxDepth; <= 0 means 1 .. 100, the network configs' range; an infinite far bound puts the
  /// farthest plane at 1e6 x the near one). At least 2.
  int planes = 64;
  /// Edge of the square cost window as a fraction of the image width, rounded to an odd pixel
  /// count >= 1 (15 px at 256 wide).
  double windowFraction = 1.0 / 17.0;
  /// Softmin temperature of the windowed cost (RGB in [-1, 1], variance summed over RGB).
  double temperature = 4e-3;
  /// Planes gathered per planeSweep call (memory bound only: V x chunk x 3 x H x W values).
  int planesPerChunk = 8;
};

/// Throws simpli::Error naming the field for options out of range.
void checkOptions(const PlaneSweepStereoOptions& options);

/// Throws simpli::Error unless height x width divides the input's image size.
void checkDivides(const generator::GeneratorInput& input, int height, int width);

/// One opaque surface: rgba [1, 4, H, W] (alpha 1), depth [1, H, W] (reference-camera z), in the
/// input's reference camera (its size). Needs at least one source (a point seen by fewer than
/// two has no match: it keeps the high cost on every plane and the mean of those that see it).
generator::GeneratorOutput planeSweepStereo(const generator::GeneratorInput& input,
                                            const PlaneSweepStereoOptions& options = {});

/// The matcher's softmin distribution over `depths` (any plane set, e.g. a network's), area-
/// averaged from the input's H x W to height x width (divisors of H and W): [P][height * width].
std::vector<std::vector<double>> planeProbabilities(const generator::GeneratorInput& input,
                                                    const std::vector<double>& depths,
                                                    const PlaneSweepStereoOptions& options,
                                                    int height, int width);

/// planeProbabilities computed on the OpenCL device in the images' dtype: [P, height, width]
/// (what the network's level-0 photo prior reads, NetworkConfig::lvl0PhotoPrior). The same
/// cost, window, softmin and area average; no gradient flows into it. The host version stays
/// the double-precision reference it is tested against.
ocl::Tensor planeProbabilityVolume(const generator::GeneratorInput& input,
                                   const std::vector<double>& depths,
                                   const PlaneSweepStereoOptions& options, int height, int width);

/// Cost of a point seen by fewer than two sources, on every plane: above any windowed RGB
/// variance of points that match (RGB in [-1, 1]; flower's best planes score ~0.01).
inline constexpr double kUnmatchedCost = 0.2;

/// Window edge in pixels for an image `width` wide: the odd number nearest to
/// windowFraction x width, at least 1.
int windowPixels(const PlaneSweepStereoOptions& options, int width);

} // namespace simpli::baselines
