// The level-0 photo prior (NetworkConfig::lvl0PhotoPrior, not in the reference): the config key,
// one more input channel of the level-0 block, weights of the network without it loading with a
// zero weight on that channel (the same function, float64), the channel being read once its
// weight is not zero, and named errors.
#include "generator_test_util.h"
#include "support/expect_error.h"
#include "support/temp_dir.h"

#include "simpli/model/network/config.h"
#include "simpli/model/network/loader.h"
#include "simpli/model/network/widen.h"
#include "simpli/ocl/autograd.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace simpli {
namespace {

using ocl::Dtype;

using test::maxAbsDiff;

TEST(Lvl0Prior, ConfigKeyAndOneMoreInputChannel) {
  const network::NetworkConfig plain = network::resolveNetworkConfig("tiny");
  const network::NetworkConfig prior = network::resolveNetworkConfig("tiny-prior");
  EXPECT_FALSE(plain.lvl0PhotoPrior);
  EXPECT_TRUE(prior.lvl0PhotoPrior);
  EXPECT_EQ(network::toJson(plain).find("lvl0_photo_prior"), std::string::npos);
  EXPECT_NE(network::toJson(prior).find("\"lvl0_photo_prior\": true"), std::string::npos);
  EXPECT_TRUE(network::parseNetworkConfig(network::toJson(prior), "back").lvl0PhotoPrior);
  network::SimpliNetwork a(plain), b(prior);
  EXPECT_EQ(b.sampiLvl0.inChannels, a.sampiLvl0.inChannels + 1);
  EXPECT_EQ(b.sampiLvl0.extraChannels, 1);
  EXPECT_GT(b.parameters().count(), a.parameters().count());
}

TEST(Lvl0Prior, WeightsWithoutItKeepTheFunctionUntilThePriorIsWeighted) {
  ocl::NoGradGuard noGrad;
  test::TempDir tmp;
  auto plain = test::configNetwork("tiny", Dtype::F64, 3);
  const std::string file = tmp.str("plain.safetensors");
  plain->parameters().save(file);
  network::NetworkConfig c = plain->config();
  c.lvl0PhotoPrior = true;
  network::SimpliNetwork prior(c, Dtype::F64, 99);
  const network::LoadReport r = network::loadWithoutLvl0Prior(prior, file);
  EXPECT_EQ(r.loaded, plain->parameters().size());
  const generator::GeneratorInput input = test::syntheticInput(3, 32, 48, Dtype::F64, 5);
  const generator::GeneratorOutput a = generator::Generator(*plain).forward(input);
  const generator::GeneratorOutput b = generator::Generator(prior).forward(input);
  EXPECT_LT(maxAbsDiff(a.rgba, b.rgba), 1e-12);
  EXPECT_LT(maxAbsDiff(a.depth, b.depth), 1e-10);
  // A weight on the prior's channel (the last input of every convolution reading the level-0
  // input) changes the output: the channel is wired in.
  int changed = 0;
  for (const std::string& name : prior.parameters().names()) {
    ocl::Tensor t = prior.parameters().get(name);
    const ocl::Tensor& old = plain->parameters().get(name);
    if (t.shape() == old.shape())
      continue;
    std::vector<double> v = t.toVector();
    const int64_t out = t.shape()[0], in = t.shape()[1];
    const int64_t kernel = t.numel() / (out * in);
    for (int64_t o = 0; o < out; ++o)
      for (int64_t k = 0; k < kernel; ++k) {
        double& w = v[size_t((o * in + in - 1) * kernel + k)];
        EXPECT_EQ(w, 0.0) << name;
        w = 0.5;
      }
    t.copyFromHost(v);
    ++changed;
  }
  EXPECT_GE(changed, 1);
  const generator::GeneratorOutput d = generator::Generator(prior).forward(input);
  EXPECT_GT(maxAbsDiff(a.rgba, d.rgba), 1e-3);
}

TEST(Lvl0Prior, LoadErrorsAreNamed) {
  test::TempDir tmp;
  network::SimpliNetwork plain(network::resolveNetworkConfig("tiny"));
  test::expectError([&] { network::loadWithoutLvl0Prior(plain, tmp.str("x.safetensors")); },
                    {"config 'tiny' has no lvl0_photo_prior"});
  network::SimpliNetwork prior(network::resolveNetworkConfig("tiny-prior"));
  test::expectError([&] { network::loadWithoutLvl0Prior(prior, tmp.str("missing.safetensors")); },
                    {"missing.safetensors"});
}

} // namespace
} // namespace simpli
