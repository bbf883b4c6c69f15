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

// tiny-prior-mpi, the MPI-only baseline of the shipped network (issue 10's comparison at equal
// recipe and budget), is tiny-prior without the planes-to-layers stages: the shipped weights load
// into it (the layer stages' tensors unused) and its level-0 MPI is the same function.
TEST(Lvl0Prior, MpiOnlyBaselineSharesTheLevel0Mpi) {
  ocl::NoGradGuard noGrad;
  test::TempDir tmp;
  auto simpliNet = test::configNetwork("tiny-prior", Dtype::F64, 3);
  const std::string file = tmp.str("prior.safetensors");
  simpliNet->parameters().save(file);
  const network::NetworkConfig mpiConfig = network::resolveNetworkConfig("tiny-prior-mpi");
  ASSERT_TRUE(mpiConfig.mpiOnly);
  ASSERT_TRUE(mpiConfig.lvl0PhotoPrior);
  network::SimpliNetwork mpi(mpiConfig, Dtype::F64, 99);
  const network::LoadReport r = mpi.parameters().load(file);
  EXPECT_EQ(r.loaded, mpi.parameters().size());
  EXPECT_FALSE(r.unexpected.empty());
  const generator::GeneratorInput input = test::syntheticInput(3, 32, 48, Dtype::F64, 5);
  generator::GeneratorOptions options;
  options.keepIntermediates = true;
  const generator::GeneratorOutput a = generator::Generator(*simpliNet).forward(input, options);
  const generator::GeneratorOutput b = generator::Generator(mpi).forward(input, options);
  EXPECT_LT(maxAbsDiff(a.level0SourceWeights, b.level0SourceWeights), 1e-12);
  EXPECT_EQ(a.planeDepths, b.planeDepths);
  EXPECT_EQ(a.rgba.size(0), simpliNet->config().numLayers);
  EXPECT_TRUE(b.mpiOnly);
  EXPECT_EQ(b.rgba.size(0), mpiConfig.numPlanes);
  EXPECT_TRUE(test::allFinite(b.rgba));
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
