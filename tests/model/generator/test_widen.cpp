// Function-preserving widening (network/widen.h): the widened config, the same generator output
// from the narrow and the wide network (float64, layered and MPI-only, with and without the
// symmetry-breaking perturbation), copies that differ only when perturbed, and bad options.
#include "generator_test_util.h"
#include "support/expect_error.h"

#include "simpli/model/network/widen.h"
#include "simpli/ocl/autograd.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace simpli {
namespace {

using ocl::Dtype;
using test::expectError;

using test::maxAbsDiff;

double spread(const ocl::Tensor& t) {
  const std::vector<double> v = t.toVector();
  const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
  return *hi - *lo;
}

// The widened network's generator output against the narrow one's on the same input.
void expectSameFunction(const std::string& config, double noise) {
  ocl::NoGradGuard noGrad;
  auto narrow = test::configNetwork(config, Dtype::F64, 3);
  network::WidenOptions o;
  o.noise = noise;
  o.seed = 11;
  auto wide = network::widenNetwork(*narrow, o);
  EXPECT_GT(wide->parameters().count(), 2 * narrow->parameters().count());
  const generator::GeneratorInput input = test::syntheticInput(3, 32, 48, Dtype::F64, 5);
  const generator::GeneratorOutput a = generator::Generator(*narrow).forward(input);
  const generator::GeneratorOutput b = generator::Generator(*wide).forward(input);
  // Not a comparison of constants: the outputs vary over the image.
  EXPECT_GT(spread(a.rgba), 0.05);
  // LayerNormTotal's unbiased variance over 2N instead of N elements: relative ~1 / (4 N).
  EXPECT_LT(maxAbsDiff(a.rgba, b.rgba), 2e-4) << config << ", noise " << noise;
  EXPECT_LT(maxAbsDiff(a.depth, b.depth), 2e-4 * 100) << config << ", noise " << noise;
}

TEST(Widen, ConfigMultipliesTheInternalWidthsOnly) {
  const network::NetworkConfig c = test::configNetwork("tiny", Dtype::F32)->config();
  const network::NetworkConfig w = network::widenedConfig(c, 3);
  EXPECT_EQ(w.name, "tiny-x3");
  EXPECT_EQ(w.featuresExtractor.widths, (std::vector<int>{48, 48, 96, 96}));
  EXPECT_EQ(w.featuresExtractor.headWidth, 3 * c.featuresExtractor.headWidth);
  EXPECT_EQ(w.featuresExtractor.descriptors, c.featuresExtractor.descriptors);
  EXPECT_EQ(w.sampiLvl0.blocks[0].inner, 3 * c.sampiLvl0.blocks[0].inner);
  EXPECT_EQ(w.sampiLvl0.outChannels, c.sampiLvl0.outChannels);
  EXPECT_EQ(w.sampiLvl0.stateChannels, c.sampiLvl0.stateChannels);
  EXPECT_EQ(w.samliBlocks[0].attentionHidden, c.samliBlocks[0].attentionHidden);
  EXPECT_EQ(w.rgbaDecoder.hidden, (std::vector<int>{48, 24}));
  EXPECT_EQ(w.numPlanes, c.numPlanes);
  EXPECT_EQ(w.numLayers, c.numLayers);
  w.validate("widened tiny");
  expectError([&] { network::widenedConfig(c, 1); }, {"factor 1", "between 2 and 8"});
  expectError([&] { network::widenedConfig(c, 9); }, {"factor 9"});
}

TEST(Widen, KeepsTheLayeredNetworksFunction) {
  expectSameFunction("tiny", 0.0);
  expectSameFunction("tiny", 0.05);
}

TEST(Widen, KeepsTheMpiOnlyNetworksFunction) {
  expectSameFunction("tiny-mpi", 0.05);
}

TEST(Widen, CopiesDifferOnlyWhenPerturbed) {
  auto narrow = test::configNetwork("tiny", Dtype::F64, 3);
  // A reader of copied channels: conv1b reads conv1a's 16 channels, now 32 (copy k of channel c
  // is channel c + 16 k). Its columns c and c + 16 are the halves of the old column.
  const std::string name = "features_extractor.conv1b.conv.weight";
  const std::vector<double> old = narrow->parameters().get(name).toVector();
  for (double noise : {0.0, 0.05}) {
    network::WidenOptions o;
    o.noise = noise;
    auto wide = network::widenNetwork(*narrow, o);
    const std::vector<double> w = wide->parameters().get(name).toVector();
    ASSERT_EQ(w.size(), old.size() * 4); // [32, 32, 3, 3] from [16, 16, 3, 3]
    double largest = 0, sumError = 0;
    for (int out = 0; out < 32; ++out)
      for (int c = 0; c < 16; ++c)
        for (int r = 0; r < 9; ++r) {
          const double a = w[size_t((out * 32 + c) * 9 + r)];
          const double b = w[size_t((out * 32 + c + 16) * 9 + r)];
          largest = std::max(largest, std::abs(a - b));
          sumError =
              std::max(sumError, std::abs(a + b - old[size_t(((out % 16) * 16 + c) * 9 + r)]));
        }
    EXPECT_LT(sumError, 1e-15) << "noise " << noise;
    if (noise == 0)
      EXPECT_EQ(largest, 0.0);
    else
      EXPECT_GT(largest, 1e-4);
  }
}

TEST(Widen, RejectsABlockWhoseResidualWouldVanish) {
  // A correction block 40 -> 16 -> 20 has a 1x1 residual (40 != 20); doubled it would be
  // 40 -> 32 -> 40, whose residual is the identity: that block cannot keep its function.
  network::NetworkConfig c = test::configNetwork("tiny", Dtype::F32)->config();
  c.samliBlocks[0].blocks = {{16, 20}};
  network::SimpliNetwork narrow(c, Dtype::F32, 1);
  expectError([&] { network::widenNetwork(narrow, {}); },
              {"samli_block_lvl2.post_aggregate_block.model.0", "40 -> 16 -> 20", "40 -> 32 -> 40",
               "identity"});
  network::WidenOptions bad;
  bad.noise = -0.1;
  expectError([&] { network::widenNetwork(narrow, bad); }, {"noise -0.1", ">= 0"});
  bad.noise = std::nan("");
  expectError([&] { network::widenNetwork(narrow, bad); }, {"noise"});
}

} // namespace
} // namespace simpli
