// Photometric augmentations against analytic cases: the unsharp mask leaves linear ramps alone,
// turns an impulse into the closed form x + a (x - G x) with a separable sigma-1 Gaussian, and
// clips to [-1, 1]; MixUp off leaves the sources equal to the clean ones.
#include "simpli/model/training/augment.h"
#include "simpli/model/training/sampler.h"

#include <gtest/gtest.h>

#include <cmath>

namespace simpli::training {
namespace {

// The sigma-1 Gaussian's taps at offsets 0, 1, 2 (normalised over -2 .. 2), in double.
double gaussianTap(int offset) {
  double sum = 0;
  for (int k = -2; k <= 2; ++k)
    sum += std::exp(-0.5 * k * k);
  return std::exp(-0.5 * offset * offset) / sum;
}

TEST(Augment, UnsharpMaskLeavesLinearRampsAwayFromBordersUnchanged) {
  io::Image image(20, 12);
  for (int c = 0; c < 3; ++c)
    for (int y = 0; y < image.height; ++y)
      for (int x = 0; x < image.width; ++x)
        image.at(c, y, x) = float(-0.6 + 0.03 * x + 0.02 * (c + 1) * y);
  const io::Image before = image;
  unsharpMask(image, 2.5);
  for (int c = 0; c < 3; ++c)
    for (int y = 2; y < image.height - 2; ++y)
      for (int x = 2; x < image.width - 2; ++x)
        EXPECT_NEAR(image.at(c, y, x), before.at(c, y, x), 2e-6) << c << " " << y << " " << x;
  // At the clamped borders a ramp is not linear any more: the mask does change it there.
  EXPECT_GT(std::abs(image.at(0, 5, 0) - before.at(0, 5, 0)), 1e-3);
}

TEST(Augment, UnsharpMaskOfAnImpulseIsTheClosedForm) {
  io::Image image(15, 13);
  const double background = -0.2, peak = 0.4, amount = 0.8; // nothing clips
  for (float& v : image.data)
    v = float(background);
  for (int c = 0; c < 3; ++c)
    image.at(c, 6, 7) = float(peak);
  unsharpMask(image, amount);
  const double d = peak - background;
  for (int c = 0; c < 3; ++c)
    for (int dy = -3; dy <= 3; ++dy)
      for (int dx = -3; dx <= 3; ++dx) {
        // G x = background + d g(dy) g(dx) (zero beyond two pixels).
        const double g = (std::abs(dy) > 2 || std::abs(dx) > 2)
                             ? 0.0
                             : gaussianTap(std::abs(dy)) * gaussianTap(std::abs(dx));
        const double x = background + (dy == 0 && dx == 0 ? d : 0.0);
        const double expected = x + amount * (x - (background + d * g));
        EXPECT_NEAR(image.at(c, 6 + dy, 7 + dx), expected, 1e-6) << dy << " " << dx;
      }
}

TEST(Augment, UnsharpMaskClipsToTheImageRange) {
  io::Image image(9, 9);
  for (float& v : image.data)
    v = -0.9f;
  image.at(1, 4, 4) = 0.9f;
  unsharpMask(image, 3.0);
  EXPECT_EQ(image.at(1, 4, 4), 1.0f);  // 0.9 + 3 (1.8 (1 - 0.16)) clipped
  EXPECT_EQ(image.at(1, 4, 5), -1.0f); // pulled below the background, clipped
  EXPECT_NEAR(image.at(0, 4, 4), -0.9f, 1e-6);
}

TEST(Augment, MixupOffCopiesTheCleanSources) {
  TrainingSample sample;
  for (int v = 0; v < 3; ++v) {
    io::Image image(4, 3);
    for (size_t i = 0; i < image.data.size(); ++i)
      image.data[i] = float(0.1 * v - 0.01 * double(i));
    sample.cleanSources.push_back(image);
  }
  SamplingConfig config;
  config.mixupProbability = 0;
  TrainRandom random(7);
  const TrainRandom::State before = random.state();
  mixupSources(sample, config, random);
  ASSERT_EQ(sample.sources.size(), 3u);
  for (size_t v = 0; v < 3; ++v) {
    EXPECT_EQ(sample.sources[v].data, sample.cleanSources[v].data);
    EXPECT_EQ(sample.mixupPartner[v], -1);
    EXPECT_EQ(sample.mixupLambda[v], 0.0);
  }
  EXPECT_EQ(random.state(), before); // nothing drawn
}

} // namespace
} // namespace simpli::training
