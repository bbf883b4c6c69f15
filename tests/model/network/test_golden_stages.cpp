// Module-level checks against stages.safetensors (one forward pass of the official generator
// with random weights, 3 views of 64 x 96): every module whose recorded input suffices (no
// geometry), fed with the recorded input and compared on what was stored (subsets are along
// axes the modules treat independently; see the manifest in the file's __metadata__).
//
// sampi_block_lvl0.out cannot be checked from its stored post_aggregate_block.in0: only planes
// 0, 20 and 40 of that input are stored, and the 3-D block mixes all 41 planes (its
// LayerNormTotal spans the whole volume). Its first block is the micro case res3d; the whole
// 7-block stack is checked through the full level-0 TBlock, whose mean / variance channels come
// from the geometry's fused plane sweep (Level0TBlock below).
#include "support/golden.h"

#include "simpli/model/geometry/plane_sweep.h"
#include "simpli/model/network/network.h"
#include "simpli/model/network/surface_ops.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/ops_reduce.h"
#include "simpli/ocl/ops_resample.h"
#include "simpli/ocl/ops_shape.h"

#include <gtest/gtest.h>

#include <map>
#include <memory>

namespace simpli::network {
namespace {

using ocl::Dtype;
using ocl::Tensor;
using test::expectGoldenClose;
using test::goldenCamera;
using test::goldenTolerance;

class GoldenStages : public ::testing::TestWithParam<Dtype> {
protected:
  void SetUp() override {
    if (!test::goldenAvailable())
      GTEST_SKIP() << "golden data not found in " << test::goldenDir();
  }
  Dtype dtype() const { return GetParam(); }

  /// The official 4-layer network with the golden weights (built once per dtype).
  const SimpliNetwork& net() const {
    static std::map<Dtype, std::unique_ptr<SimpliNetwork>> nets;
    auto& n = nets[dtype()];
    if (!n) {
      n = std::make_unique<SimpliNetwork>(officialConfig(4), dtype());
      const LoadReport r = n->parameters().load(test::goldenFile("weights"));
      EXPECT_TRUE(r.unexpected.empty()) << r.unexpected.front();
    }
    return *n;
  }
  Tensor stage(const std::string& key) const { return test::goldenTensor("stages", key, dtype()); }
  Tensor input(const std::string& key) const { return test::goldenTensor("inputs", key, dtype()); }
  std::vector<double> planeDepths() const {
    return test::goldenFile("inputs").readF64("plane_depths").data;
  }
  ocl::NoGradGuard noGrad_;
};

TEST_P(GoldenStages, FeatureExtractor) {
  expectGoldenClose("features_extractor.out", net().featuresExtractor.forward(input("images")),
                    stage("features_extractor.out"),
                    goldenTolerance("module_level", "features_extractor"));
}

TEST_P(GoldenStages, AlphaDecoderLevel0) {
  const Tensor features = ocl::reshape(stage("sampi_block_lvl0.out"), {41, 12, 16, 24});
  expectGoldenClose("alpha_decoder_lvl0.out", net().alphaDecoderLvl0.forward(features),
                    stage("alpha_decoder_lvl0.out"),
                    goldenTolerance("module_level", "alpha_decoder_lvl0"));
}

// The level-0 state channels of the 3-D aggregator input are PE_12(plane index); the reference
// evaluates them at linspace(0, 1, 41) * 40 in float32, 1.8e-6 from the exact indices.
TEST_P(GoldenStages, Level0PlaneState) {
  const Tensor in0 = stage("sampi_block_lvl0.post_aggregate_block.in0.planes_0_20_40");
  const Tensor golden = ocl::slice(in0, 1, 0, 12); // [1, 12, 3, 16, 24]
  const Tensor state = ocl::indexSelect(planeState(41, 12, dtype()), 0, {0, 20, 40}); // [3, 12]
  const Tensor expected =
      ocl::expand(ocl::reshape(ocl::transpose(state, 0, 1), {1, 12, 3, 1, 1}), golden.shape());
  expectGoldenClose("sampi_block_lvl0.post_aggregate_block.in0[state]", expected, golden, 5e-6);
}

// Level-1 state = bicubic(fMPI0 -> 32 x 48), fMPI0 = [level-0 features with the tanh quirk on
// the three nearest planes | sigmoid(alpha)]; plane 40 is one of the quirk's planes.
TEST_P(GoldenStages, Level1StateWithTanhQuirk) {
  const Tensor m = stage("sampi_block_lvl0.out"); // [1, 41, 12, 16, 24]
  const Tensor alpha = ocl::reshape(stage("alpha_decoder_lvl0.out"), {1, 41, 1, 16, 24});
  const Tensor mpi0 = assembleMpi0(m, alpha, net().config().lvl0TanhPlanes); // [1, 41, 13, ...]
  const Tensor planes = ocl::indexSelect(ocl::reshape(mpi0, {41, 13, 16, 24}), 0, {0, 20, 40});
  const Tensor state = ocl::resizeBicubic(planes, 32, 48);
  const Tensor golden =
      ocl::slice(stage("sampi_block_lvl1.post_aggregate_block.in0.planes_0_20_40"), 1, 0, 13);
  expectGoldenClose("sampi_block_lvl1.post_aggregate_block.in0[state]", state, golden, 5e-6);
  // Without the quirk plane 40 would differ visibly: the check can tell.
  const Tensor plain = ocl::resizeBicubic(
      ocl::indexSelect(ocl::reshape(assembleMpi0(m, alpha, 0), {41, 13, 16, 24}), 0, {40}), 32, 48);
  EXPECT_GT(test::relToMax(plain, ocl::slice(golden, 0, 2, 3)), 1e-2);
}

TEST_P(GoldenStages, Level1PostAggregateBlock) {
  const Tensor in0 = stage("sampi_block_lvl1.post_aggregate_block.in0.planes_0_20_40");
  const Tensor out = net().sampiLvl1.postAggregate.forward(in0); // [3, 16, 32, 48]
  expectGoldenClose("sampi_block_lvl1.out.planes_0_20_40", ocl::reshape(out, {1, 3, 16, 32, 48}),
                    stage("sampi_block_lvl1.out.planes_0_20_40"),
                    goldenTolerance("module_level", "sampi_block_lvl1.post_aggregate_block"));
}

TEST_P(GoldenStages, PlanesDeformerRows) {
  const Tensor in = stage("planes_deformer_lvl1.in0.rows_0_31"); // [1, 41, 16, 2, 48]
  const Tensor out = net().planesDeformer->forward(in, input("plane_positions"));
  const Tensor golden = ocl::indexSelect(stage("planes_deformer_lvl1.out"), 3, {0, 31});
  expectGoldenClose("planes_deformer_lvl1.out.rows_0_31", out, golden,
                    goldenTolerance("module_level", "planes_deformer_lvl1"));
}

TEST_P(GoldenStages, Level1Decoders) {
  const Tensor layers = ocl::reshape(stage("planes_deformer_lvl1.out"), {4, 16, 32, 48});
  expectGoldenClose("depth_decoder_lvl1.out", net().depthDecoder->forward(layers),
                    stage("depth_decoder_lvl1.out"),
                    goldenTolerance("module_level", "depth_decoder_lvl1"));
  expectGoldenClose("rgba_decoder_lvl1.out", net().rgbaDecoders[0].forward(layers),
                    stage("rgba_decoder_lvl1.out"),
                    goldenTolerance("module_level", "rgba_decoder_lvl1"));
}

TEST_P(GoldenStages, ProcessDepthLevel1) {
  const Tensor logits = ocl::reshape(stage("depth_decoder_lvl1.out"), {1, 44, 32, 48});
  expectGoldenClose("process_depth_lvl1.out", processDepth(logits, planeDepths(), 4),
                    stage("process_depth_lvl1.out"),
                    goldenTolerance("module_level", "process_depth_lvl1"));
}

// Level 2 re-decodes the depth from the bicubic-upsampled logits (reference §3 step 6.4).
TEST_P(GoldenStages, ProcessDepthLevel2) {
  const Tensor logits = ocl::reshape(stage("depth_decoder_lvl1.out"), {1, 44, 32, 48});
  const Tensor up = ocl::resizeBicubic(logits, 64, 96);
  expectGoldenClose("process_depth_lvl2.in0.rows_0_63",
                    ocl::reshape(ocl::indexSelect(up, 2, {0, 63}), {1, 44, 1, 2, 96}),
                    stage("process_depth_lvl2.in0.rows_0_63"), 2e-6);
  expectGoldenClose("layered_depth", processDepth(up, planeDepths(), 4), stage("layered_depth"),
                    goldenTolerance("module_level", "process_depth_lvl2"));
}

// Level-2 state = bicubic(fMLI0 -> 64 x 96); layer 3 of the aggregator input is stored.
TEST_P(GoldenStages, Level2State) {
  const Tensor layer3 = ocl::slice(stage("planes_deformer_lvl1.out"), 1, 3, 4); // [1,1,16,32,48]
  const Tensor state = ocl::resizeBicubic(ocl::reshape(layer3, {1, 16, 32, 48}), 64, 96);
  const Tensor golden =
      ocl::slice(stage("samli_block_lvl2.post_aggregate_block.in0.layers_3"), 1, 0, 16);
  expectGoldenClose("samli_block_lvl2.post_aggregate_block.in0[state]", state, golden, 5e-6);
}

TEST_P(GoldenStages, Level2PostAggregateBlock) {
  const Tensor in0 = stage("samli_block_lvl2.post_aggregate_block.in0.layers_3"); // layer 3
  const Tensor out = net().samliBlocks[0].postAggregate.forward(in0);             // [1, 16, ...]
  const Tensor golden =
      ocl::reshape(ocl::slice(stage("samli_block_lvl2.out.layers_0_3"), 1, 1, 2), out.shape());
  expectGoldenClose("samli_block_lvl2.out.layers_3", out, golden,
                    goldenTolerance("module_level", "samli_block_lvl2.post_aggregate_block"));
}

TEST_P(GoldenStages, RgbaDecodersLevels2And3) {
  for (int level : {2, 3}) {
    const std::string l = std::to_string(level);
    const Tensor layers =
        ocl::reshape(stage("samli_block_lvl" + l + ".out.layers_0_3"), {2, 16, 64, 96});
    const Tensor golden = ocl::indexSelect(stage("rgba_decoder_lvl" + l + ".out"), 0, {0, 3});
    expectGoldenClose("rgba_decoder_lvl" + l + ".out.layers_0_3",
                      net().rgbaDecoders[level - 1].forward(layers), golden,
                      goldenTolerance("module_level", "rgba_decoder_lvl" + l));
  }
}

// The final RGBA is act(rgba_decoder_lvl4(fMLI3)): decoder and squashing together.
TEST_P(GoldenStages, FinalRgba) {
  const Tensor layers = ocl::reshape(stage("samli_block_lvl4.out.layers_0_3"), {2, 16, 64, 96});
  const Tensor rgba = activateRgba(net().rgbaDecoders[3].forward(layers), 1);
  const Tensor golden =
      ocl::reshape(ocl::indexSelect(stage("final.rgba"), 2, {0, 3}), {2, 4, 64, 96});
  expectGoldenClose("final.rgba.layers_0_3", rgba, golden,
                    goldenTolerance("module_level", "rgba_decoder_lvl4"));
}

// The whole level-0 aggregation (reference §3 step 2): FE out bicubic to 16 x 24, the fused
// plane-sweep mean / variance of model/geometry, the PE state, the 7-block 3-D stack.
TEST_P(GoldenStages, Level0TBlock) {
  const io::SafeTensorsReader& in = test::goldenFile("inputs");
  const io::HostTensor<double> ext = in.readF64("src_extrinsics"),
                               intr = in.readF64("src_intrinsics");
  std::vector<scene::Camera> views;
  for (int v = 0; v < 3; ++v)
    views.push_back(goldenCamera(&ext.data[12 * v], &intr.data[9 * v]));
  const scene::Camera reference = goldenCamera(in.readF64("ref_extrinsics").data.data(),
                                               in.readF64("ref_intrinsics").data.data());

  const Tensor maps = ocl::resizeBicubic(stage("features_extractor.out"), 16, 24);
  const Tensor meanVar = geometry::planeSweepMeanVar(maps, reference, views, planeDepths(), 16, 24);
  // [P, 24, h, w] -> the volume layout [1, 24, P, h, w]; state PE_12(p) broadcast over pixels.
  const Tensor stats = ocl::unsqueeze(ocl::permute(meanVar, {1, 0, 2, 3}), 0);
  const Tensor state = ocl::expand(
      ocl::reshape(ocl::transpose(planeState(41, 12, dtype()), 0, 1), {1, 12, 41, 1, 1}),
      {1, 12, 41, 16, 24});
  const Tensor out = net().sampiLvl0.postAggregate.forward(ocl::concat({state, stats}, 1));
  expectGoldenClose("sampi_block_lvl0.out", ocl::permute(out, {0, 2, 1, 3, 4}),
                    stage("sampi_block_lvl0.out"),
                    goldenTolerance("module_level", "sampi_block_lvl0"));
}

INSTANTIATE_TEST_SUITE_P(Dtypes, GoldenStages, ::testing::Values(Dtype::F32, Dtype::F64),
                         [](const auto& info) { return ocl::toString(info.param); });

} // namespace
} // namespace simpli::network
