// The whole tiny network in float32 against float64 with identical parameters and inputs,
// stage by stage (every tensor the generator reports through its stage hook), including the
// OpenCL rasterizer's source renders.
//
// Tolerance: the reference network's own float32-vs-float64 end-to-end envelope on the same
// kind of input (random weights, uniform-noise images; shared/golden/README.md §7, "simple
// rule"): rel = max|x32 - x64| / max|x64| <= 1e-4 up to the level-1 outputs and <= 2e-3 for
// the MLI corrections, where gathers from full-resolution noise images turn sampling-coordinate
// rounding (~5e-7 grid units) into value differences of ~5e-5, which the view attention and
// LayerNormTotal amplify. The tiny network uses the same operations with fewer channels.
#include "generator_test_util.h"
#include "support/golden.h"

#include "simpli/ocl/autograd.h"

#include <gtest/gtest.h>

#include <iostream>
#include <map>

namespace simpli {
namespace {

using ocl::Dtype;
using ocl::Tensor;

std::map<std::string, Tensor> runRecorded(network::SimpliNetwork& net,
                                          const generator::GeneratorInput& input,
                                          generator::GeneratorOutput* out) {
  std::map<std::string, Tensor> stages;
  generator::GeneratorOptions options;
  options.stageHook = [&stages](const std::string& name, const Tensor& t) { stages[name] = t; };
  *out = generator::Generator(net).forward(input, options);
  return stages;
}

TEST(GeneratorPrecision, Float32AgreesWithFloat64StageByStage) {
  ocl::NoGradGuard noGrad;
  auto net32 = test::configNetwork("tiny", Dtype::F32, 11);
  auto net64 = test::configNetwork("tiny", Dtype::F64, 11);
  for (const std::string& name : net32->parameters().names()) {
    Tensor target = net64->parameters().get(name); // a handle to the same buffer
    target.copyFromHost(net32->parameters().get(name).toVector());
  }

  const generator::GeneratorInput in32 = test::syntheticInput(3, 32, 48, Dtype::F32, 21);
  generator::GeneratorInput in64 = in32;
  in64.images = in32.images.to(Dtype::F64);
  generator::GeneratorOutput out32, out64;
  const auto s32 = runRecorded(*net32, in32, &out32);
  const auto s64 = runRecorded(*net64, in64, &out64);
  ASSERT_EQ(s32.size(), s64.size());
  ASSERT_GE(s32.size(), 20u);

  auto tolerance = [](const std::string& name) {
    const bool mli = name.rfind("samli", 0) == 0 || name.rfind("renderer_lvl", 0) == 0 ||
                     name.rfind("final", 0) == 0 || name == "rgba_decoder_lvl2.out" ||
                     name == "rgba_decoder_lvl3.out" || name == "rgba_decoder_lvl4.out";
    return mli ? 2e-3 : 1e-4;
  };
  for (const auto& [name, t32] : s32) {
    ASSERT_TRUE(s64.count(name)) << name;
    const double rel = test::relToMax(t32, s64.at(name));
    std::cout << "[f32 vs f64] " << name << " rel=" << rel << std::endl;
    EXPECT_LE(rel, tolerance(name)) << name;
  }
  EXPECT_LE(test::relToMax(out32.depth, out64.depth), 1e-4);
  EXPECT_LE(test::relToMax(out32.rgba, out64.rgba), 2e-3);
}

} // namespace
} // namespace simpli
