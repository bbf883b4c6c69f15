// The golden micro cases (shared/golden micro.safetensors): single modules of the reference
// with its random weights, reproduced within 10x the measured float32 error, in float32 and in
// float64 (whose difference to the float32 golden is the golden's own rounding).
#include "support/golden.h"

#include "simpli/model/network/attention.h"
#include "simpli/model/network/feature_extractor.h"
#include "simpli/model/network/layers.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/ops_norm.h"
#include "simpli/ocl/ops_shape.h"

#include <gtest/gtest.h>

namespace simpli::network {
namespace {

using ocl::Dtype;
using ocl::Tensor;
using test::expectGoldenClose;
using test::goldenTensor;
using test::goldenTolerance;

class GoldenMicro : public ::testing::TestWithParam<Dtype> {
protected:
  void SetUp() override {
    if (!test::goldenAvailable())
      GTEST_SKIP() << "golden data not found in " << test::goldenDir();
  }
  Dtype dtype() const { return GetParam(); }
  Tensor in(const std::string& key) const { return goldenTensor("micro", key, dtype()); }
  /// Loads the store's parameters from the golden weights (all must be there).
  void load(ParameterStore& store) const {
    const LoadReport r = store.load(test::goldenFile("weights"));
    EXPECT_EQ(r.loaded, store.size());
  }
  void check(const std::string& name, const Tensor& got, const std::string& key) const {
    expectGoldenClose("micro." + key, got, in(key), goldenTolerance("micro", name));
  }
  ocl::NoGradGuard noGrad_;
};

TEST_P(GoldenMicro, ConvMlpRelu) {
  ParameterStore store(dtype());
  const ConvMLP mlp(store, "depth_decoder_lvl1", 16, {{16, 8}, Activation::Relu}, 11);
  load(store);
  check("convmlp_relu", mlp.forward(in("convmlp_relu.in")), "convmlp_relu.out");
}

TEST_P(GoldenMicro, ConvMlpElu) {
  ParameterStore store(dtype());
  const ConvMLP mlp(store, "alpha_decoder_lvl0", 12, {{12, 12}, Activation::Elu}, 1);
  load(store);
  check("convmlp_elu", mlp.forward(in("convmlp_elu.in")), "convmlp_elu.out");
}

// LayerNormTotal with the reference's eps placement, parameters of the named norm layers.
TEST_P(GoldenMicro, LayerNormTotal2dAnd3d) {
  for (const auto& [name, prefix] :
       {std::pair<std::string, std::string>{"ln_total",
                                            "samli_block_lvl2.post_aggregate_block.model.0."
                                            "double_conv.0.norm."},
        {"ln_total_3d", "sampi_block_lvl0.post_aggregate_block.model.0.double_conv.0.norm."}}) {
    const Tensor gamma = goldenTensor("weights", prefix + "gamma", dtype());
    const Tensor beta = goldenTensor("weights", prefix + "beta", dtype());
    check(name, ocl::layerNormTotal(in(name + ".in"), gamma, beta, 1e-5), name + ".out");
  }
}

TEST_P(GoldenMicro, DoubleConvBlock2dResidualConv) {
  ParameterStore store(dtype());
  const DoubleConvBlock block(store, "samli_block_lvl3.post_aggregate_block.model.0", 2, 40, 16, 16,
                              false);
  load(store);
  check("res2d", block.forward(in("res2d.in")), "res2d.out");
}

TEST_P(GoldenMicro, DoubleConvBlock2dLast) {
  ParameterStore store(dtype());
  const DoubleConvBlock block(store, "samli_block_lvl3.post_aggregate_block.model.1", 2, 16, 16, 16,
                              true);
  load(store);
  check("res2d_last", block.forward(in("res2d_last.in")), "res2d_last.out");
}

TEST_P(GoldenMicro, DoubleConvBlock3d) {
  ParameterStore store(dtype());
  const DoubleConvBlock block(store, "sampi_block_lvl0.post_aggregate_block.model.0", 3, 36, 32, 32,
                              false);
  load(store);
  check("res3d", block.forward(in("res3d.in")), "res3d.out");
}

TEST_P(GoldenMicro, ViewAttention) {
  ParameterStore store(dtype());
  const ViewAttention attention(store, "samli_block_lvl2.attention_agg", 6, 16);
  load(store);
  Tensor maps;
  const Tensor out = attention.forward(in("attn_view.in"), &maps);
  check("attn_view", out, "attn_view.out");
  check("attn_view", maps, "attn_view.attn");
  // Without maps the fused attention kernel runs instead of the composed GEMMs.
  check("attn_view", attention.forward(in("attn_view.in")), "attn_view.out");
}

TEST_P(GoldenMicro, AnchoredRayAttention) {
  ParameterStore store(dtype());
  const AnchoredRayAttention deformer(store, "planes_deformer_lvl1", 16, 4, 2, 10);
  load(store);
  const Tensor positions = ocl::reshape(in("ray_attn.positions"), {41});
  check("ray_attn", deformer.forward(in("ray_attn.in"), positions), "ray_attn.out");
}

TEST_P(GoldenMicro, FeatureExtractor) {
  ParameterStore store(dtype());
  const FeatureExtractor fe(store, "features_extractor", FeatureExtractorConfig{});
  load(store);
  check("feat_extractor", fe.forward(in("feat_extractor.in")), "feat_extractor.out");
}

INSTANTIATE_TEST_SUITE_P(Dtypes, GoldenMicro, ::testing::Values(Dtype::F32, Dtype::F64),
                         [](const auto& info) { return ocl::toString(info.param); });

} // namespace
} // namespace simpli::network
