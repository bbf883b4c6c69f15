// Generator::forward on the small configs (model/configs/tiny*.json): shapes, value ranges and
// finiteness for MPI-only and layered networks, 1 and 16 views, extreme images, the options
// (corrections, intermediates, stage timing, injected renderer), bad input, and the outputs'
// conversions (renderNovelView, toMLI).
#include "generator_test_util.h"
#include "support/expect_error.h"

#include "simpli/model/geometry/planes.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/ops_shape.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace simpli {
namespace {

using ocl::Dtype;
using ocl::Tensor;

/// RGB in [-1, 1], alpha in [0, 1], all finite; layer depths ordered far to near.
void expectValidOutput(const generator::GeneratorOutput& out, int surfaces, int h, int w,
                       bool ordered) {
  ASSERT_EQ(out.rgba.shape(), (ocl::Shape{surfaces, 4, h, w}));
  ASSERT_EQ(out.depth.shape(), (ocl::Shape{surfaces, h, w}));
  const std::vector<double> rgba = out.rgba.toVector(), depth = out.depth.toVector();
  const std::size_t n = static_cast<std::size_t>(h) * w;
  for (int s = 0; s < surfaces; ++s)
    for (int c = 0; c < 4; ++c)
      for (std::size_t i = 0; i < n; ++i) {
        const double v = rgba[(s * 4 + c) * n + i];
        ASSERT_TRUE(std::isfinite(v)) << "surface " << s << " channel " << c;
        ASSERT_GE(v, c == 3 ? 0.0 : -1.0);
        ASSERT_LE(v, 1.0);
      }
  for (int s = 0; s < surfaces; ++s)
    for (std::size_t i = 0; i < n; ++i) {
      const double d = depth[s * n + i];
      ASSERT_TRUE(std::isfinite(d) && d > 0) << "surface " << s << " texel " << i;
      if (ordered && s > 0) {
        ASSERT_LE(d, depth[(s - 1) * n + i] * (1 + 1e-6)) << "layer " << s << " texel " << i;
      }
    }
}

TEST(GeneratorTiny, MpiOnlyGivesOneSurfacePerPlane) {
  ocl::NoGradGuard noGrad;
  auto net = test::configNetwork("tiny-mpi", Dtype::F32);
  const int P = net->config().numPlanes;
  const generator::GeneratorInput input = test::syntheticInput(3, 32, 48, Dtype::F32, 7);
  const generator::GeneratorOutput out = generator::Generator(*net).forward(input);
  EXPECT_TRUE(out.mpiOnly);
  expectValidOutput(out, P, 32, 48, true);
  // Depth is constant per plane: the plane depths themselves.
  const std::vector<double> planes = geometry::planeDepths(P, 1.0, 100.0),
                            depth = out.depth.toVector();
  for (int p = 0; p < P; ++p)
    for (int i = 0; i < 32 * 48; i += 97)
      EXPECT_NEAR(depth[p * 32 * 48 + i], planes[p], 1e-5 * planes[p]);
  const raster::RenderedLayers view =
      generator::renderNovelView(out, input.reference, input.sources[1]);
  EXPECT_TRUE(test::allFinite(view.colour));
  EXPECT_EQ(generator::toMLI(out, input.reference).numLayers(), P);
}

TEST(GeneratorTiny, OneView) {
  ocl::NoGradGuard noGrad;
  auto net = test::configNetwork("tiny", Dtype::F32);
  const generator::GeneratorInput input = test::syntheticInput(1, 32, 48, Dtype::F32, 3);
  const generator::GeneratorOutput out = generator::Generator(*net).forward(input);
  expectValidOutput(out, net->config().numLayers, 32, 48, true);
}

TEST(GeneratorTiny, SixteenViews) {
  ocl::NoGradGuard noGrad;
  auto net = test::configNetwork("tiny", Dtype::F32);
  const generator::GeneratorInput input = test::syntheticInput(16, 32, 48, Dtype::F32, 4);
  const generator::GeneratorOutput out = generator::Generator(*net).forward(input);
  expectValidOutput(out, net->config().numLayers, 32, 48, true);
}

// The fused view aggregation of the corrections (the inference default) gives the composed
// form's MLI: in float64 to rounding, for 3 and 16 views.
TEST(GeneratorTiny, FusedAggregationGivesTheComposedResult) {
  ocl::NoGradGuard noGrad;
  auto net = test::configNetwork("tiny", Dtype::F64);
  for (int views : {3, 16}) {
    SCOPED_TRACE(std::to_string(views) + " views");
    const generator::GeneratorInput input = test::syntheticInput(views, 32, 48, Dtype::F64, 9);
    generator::GeneratorOptions composed;
    composed.fusedAggregation = false;
    const generator::GeneratorOutput a = generator::Generator(*net).forward(input);
    const generator::GeneratorOutput b = generator::Generator(*net).forward(input, composed);
    const std::vector<double> ra = a.rgba.toVector(), rb = b.rgba.toVector();
    const std::vector<double> da = a.depth.toVector(), db = b.depth.toVector();
    double rgbaDiff = 0, depthDiff = 0, spread = 0;
    for (std::size_t i = 0; i < ra.size(); ++i) {
      rgbaDiff = std::max(rgbaDiff, std::abs(ra[i] - rb[i]));
      spread = std::max(spread, std::abs(ra[i] - ra[0]));
    }
    for (std::size_t i = 0; i < da.size(); ++i)
      depthDiff = std::max(depthDiff, std::abs(da[i] - db[i]) / db[i]);
    EXPECT_GT(spread, 1e-3); // not a constant output
    EXPECT_LT(rgbaDiff, 1e-10);
    EXPECT_LT(depthDiff, 1e-10);
  }
}

// All-black (-1) and saturated (+1) images: constant inputs make LayerNormTotal see zero
// variance in the first layer; everything must stay finite.
TEST(GeneratorTiny, BlackAndSaturatedImages) {
  ocl::NoGradGuard noGrad;
  auto net = test::configNetwork("tiny", Dtype::F32);
  for (double value : {-1.0, 1.0}) {
    generator::GeneratorInput input = test::syntheticInput(2, 32, 48, Dtype::F32, 5);
    input.images = Tensor::full(input.images.shape(), value, Dtype::F32);
    const generator::GeneratorOutput out = generator::Generator(*net).forward(input);
    SCOPED_TRACE(value);
    expectValidOutput(out, net->config().numLayers, 32, 48, true);
  }
}

// Depth ranges far from the configs' 1 .. 100: a million-to-one range starting 1 cm from the
// cameras, a range 0.1 % deep (planes almost on top of each other) and a distant scene. The
// layered and the MPI-only networks stay finite, their depths stay inside the range, and the
// surfaces render into a source view.
TEST(GeneratorTiny, DepthRangeExtremes) {
  ocl::NoGradGuard noGrad;
  for (const char* config : {"tiny", "tiny-mpi"}) {
    auto net = test::configNetwork(config, Dtype::F32);
    const int S = net->config().surfaces();
    for (const auto& [near, far] : {std::pair{0.01, 1e4}, {1.0, 1.001}, {1e3, 1e5}}) {
      SCOPED_TRACE(std::string(config) + " near " + std::to_string(near) + " far " +
                   std::to_string(far));
      generator::GeneratorInput input = test::syntheticInput(3, 32, 48, Dtype::F32, 9);
      input.minDepth = near;
      input.maxDepth = far;
      const generator::GeneratorOutput out = generator::Generator(*net).forward(input);
      expectValidOutput(out, S, 32, 48, true);
      const std::vector<double> depth = out.depth.toVector();
      const auto [lo, hi] = std::minmax_element(depth.begin(), depth.end());
      EXPECT_GE(*lo, near * (1 - 1e-5));
      EXPECT_LE(*hi, far * (1 + 1e-5));
      const raster::RenderedLayers view =
          generator::renderNovelView(out, input.reference, input.sources[2]);
      EXPECT_TRUE(test::allFinite(view.colour));
      EXPECT_TRUE(test::allFinite(view.opacity));
    }
  }
}

TEST(GeneratorTiny, CorrectionsIntermediatesAndTiming) {
  ocl::NoGradGuard noGrad;
  auto net = test::configNetwork("tiny", Dtype::F32);
  const generator::GeneratorInput input = test::syntheticInput(2, 32, 48, Dtype::F32, 6);
  generator::GeneratorOptions options;
  options.keepIntermediates = true;
  options.timeStages = true;

  options.corrections = 0; // the level-1 surfaces at half resolution
  generator::GeneratorOutput out = generator::Generator(*net).forward(input, options);
  expectValidOutput(out, 4, 16, 24, true);
  ASSERT_EQ(out.intermediateSourceRenders.size(), 1u);
  EXPECT_EQ(out.intermediateSourceRenders[0].shape(), (ocl::Shape{2, 3, 16, 24}));

  options.corrections = 1;
  out = generator::Generator(*net).forward(input, options);
  expectValidOutput(out, 4, 32, 48, true);
  ASSERT_EQ(out.intermediateSourceRenders.size(), 2u);
  EXPECT_EQ(out.intermediateSourceRenders[1].shape(), (ocl::Shape{2, 3, 32, 48}));
  std::vector<std::string> names;
  for (const auto& [name, ms] : out.stageMs) {
    names.push_back(name);
    EXPECT_GE(ms, 0.0) << name;
  }
  EXPECT_EQ(names,
            (std::vector<std::string>{"features", "level0", "mpi_render", "level1",
                                      "planes_to_layers", "level2_render", "level2_unproject",
                                      "level2_attention", "level2_convs", "level2_decode"}));

  // The injected renderer is called once per correction with the current mesh.
  std::vector<int> levels;
  options.corrections = -1;
  options.sourceRenderer = [&levels](const Tensor& rgba, const Tensor& depth,
                                     const generator::GeneratorInput& in, int level) {
    levels.push_back(level);
    EXPECT_EQ(rgba.size(0), depth.size(0));
    return Tensor::zeros(in.images.shape(), in.images.dtype());
  };
  out = generator::Generator(*net).forward(input, options);
  EXPECT_EQ(levels, (std::vector<int>{2, 3, 4}));
  EXPECT_EQ(out.intermediateSourceRenders.size(), 4u);
}

// progress(stage, done, total) follows the stages exactly (done = 1..total, the last call's done
// is the total) for any number of corrections, and returning false cancels the pass.
TEST(GeneratorTiny, ProgressReportsEveryStageAndCancels) {
  ocl::NoGradGuard noGrad;
  auto net = test::configNetwork("tiny", Dtype::F32);
  const generator::GeneratorInput input = test::syntheticInput(2, 32, 48, Dtype::F32, 8);
  for (int corrections : {0, 1, 3}) {
    generator::GeneratorOptions options;
    options.corrections = corrections;
    std::vector<std::string> reported;
    std::vector<int> done, totals;
    options.progress = [&](const std::string& stage, int d, int total) {
      reported.push_back(stage);
      done.push_back(d);
      totals.push_back(total);
      return true;
    };
    const generator::GeneratorOutput out = generator::Generator(*net).forward(input, options);
    ASSERT_EQ(reported.size(), out.stageMs.size()) << corrections << " corrections";
    for (size_t i = 0; i < reported.size(); ++i) {
      EXPECT_EQ(reported[i], out.stageMs[i].first);
      EXPECT_EQ(done[i], int(i) + 1);
      EXPECT_EQ(totals[i], int(reported.size())) << reported[i];
    }
  }
  // Cancelled at the third stage: nothing after it runs.
  generator::GeneratorOptions options;
  std::vector<std::string> reported;
  options.progress = [&](const std::string& stage, int done, int) {
    reported.push_back(stage);
    return done < 3;
  };
  EXPECT_THROW(generator::Generator(*net).forward(input, options), generator::GeneratorCancelled);
  EXPECT_EQ(reported, (std::vector<std::string>{"features", "level0", "mpi_render"}));
  // The MPI-only network counts its stages too.
  auto mpi = test::configNetwork("tiny-mpi", Dtype::F32);
  int last = 0, total = -1;
  options.progress = [&](const std::string&, int done, int t) {
    last = done;
    total = t;
    return true;
  };
  generator::Generator(*mpi).forward(input, options);
  EXPECT_EQ(last, total);
}

TEST(GeneratorTiny, BadInput) {
  ocl::NoGradGuard noGrad;
  auto net = test::configNetwork("tiny", Dtype::F32);
  const generator::Generator generator(*net);
  const generator::GeneratorInput good = test::syntheticInput(2, 32, 48, Dtype::F32, 8);

  generator::GeneratorInput in = good;
  in.images = good.images.to(Dtype::F64);
  test::expectError([&] { generator.forward(in); }, {"f64", "network's dtype f32"});
  in = good;
  in.sources.pop_back();
  test::expectError([&] { generator.forward(in); }, {"1 source cameras", "f32[2, 3, 32, 48]"});
  in = test::syntheticInput(2, 36, 48, Dtype::F32, 8);
  test::expectError([&] { generator.forward(in); }, {"multiples of 8"});
  in = good;
  in.sources[1].fx = std::nan("");
  test::expectError([&] { generator.forward(in); }, {"source camera 1"});
  in = good;
  in.minDepth = 5;
  in.maxDepth = 2;
  test::expectError([&] { generator.forward(in); }, {"minDepth = 5", "maxDepth = 2"});
  generator::GeneratorOptions options;
  options.corrections = 4;
  test::expectError([&] { generator.forward(good, options); }, {"4 corrections", "has 3"});
  options.corrections = 1;
  options.sourceRenderer = [](const Tensor&, const Tensor&, const generator::GeneratorInput&, int) {
    return Tensor::zeros({1, 3, 32, 48});
  };
  test::expectError([&] { generator.forward(good, options); },
                    {"source renderer returned f32[1, 3, 32, 48] at level 2"});
}

TEST(GeneratorTiny, ToMliDropsEmptyLayers) {
  generator::GeneratorOutput out;
  // 3 surfaces of 2 x 3: surface 1 is fully transparent, surface 2 barely visible.
  std::vector<double> rgba(3 * 4 * 6, 0.0), depth(3 * 6);
  for (int s = 0; s < 3; ++s)
    for (int i = 0; i < 6; ++i) {
      rgba[(s * 4 + 0) * 6 + i] = -1.0; // R -> 0
      rgba[(s * 4 + 1) * 6 + i] = 1.0;  // G -> 1
      rgba[(s * 4 + 3) * 6 + i] = s == 0 ? 1.0 : (s == 1 ? 0.0 : (i == 4 ? 0.01 : 0.0));
      depth[s * 6 + i] = 10.0 - 3 * s;
    }
  out.rgba = Tensor::fromHost(rgba, {3, 4, 2, 3}, Dtype::F32);
  out.depth = Tensor::fromHost(depth, {3, 2, 3}, Dtype::F32);
  scene::Camera reference;
  reference.width = 99; // replaced by the texture size
  mli::MLI all = generator::toMLI(out, reference);
  ASSERT_EQ(all.numLayers(), 3);
  EXPECT_EQ(all.width(), 3);
  EXPECT_EQ(all.height(), 2);
  EXPECT_FLOAT_EQ(all.layers[0].rgba[0], 0.0f);
  EXPECT_FLOAT_EQ(all.layers[0].rgba[1], 1.0f);
  EXPECT_FLOAT_EQ(all.layers[0].rgba[2], 0.5f);
  EXPECT_FLOAT_EQ(all.layers[2].depth[0], 4.0f);
  const mli::MLI dropped = generator::toMLI(out, reference, 1.0f / 255.0f);
  ASSERT_EQ(dropped.numLayers(), 2);
  EXPECT_FLOAT_EQ(dropped.layers[1].depth[0], 4.0f); // the far layer and the faint one remain
  EXPECT_EQ(generator::toMLI(out, reference, 0.5f).numLayers(), 1);
  // Nothing visible: the most opaque surface is kept (an MLI has at least one layer).
  out.rgba = Tensor::zeros({3, 4, 2, 3});
  EXPECT_EQ(generator::toMLI(out, reference, 0.5f).numLayers(), 1);
  test::expectError([&] { generator::toMLI(generator::GeneratorOutput{}, reference); },
                    {"toMLI", "empty"});
}

TEST(GeneratorTiny, NovelViewAtSourceIsClampedAndFinite) {
  ocl::NoGradGuard noGrad;
  auto net = test::configNetwork("tiny", Dtype::F32);
  const generator::GeneratorInput input = test::syntheticInput(2, 32, 48, Dtype::F32, 9);
  const generator::GeneratorOutput out = generator::Generator(*net).forward(input);
  scene::Camera target = input.sources[0];
  target.width = 40;
  target.height = 24;
  const raster::RenderedLayers r = generator::renderNovelView(out, input.reference, target);
  ASSERT_EQ(r.colour.shape(), (ocl::Shape{3, 24, 40}));
  for (double v : r.colour.toVector())
    ASSERT_TRUE(std::isfinite(v) && v >= -1.0 && v <= 1.0);
  // The layers fill the view: the farthest fragment is opaque, so opacity is ~1 mid-image.
  EXPECT_GT(r.opacity.toVector()[12 * 40 + 20], 0.99);
}

} // namespace
} // namespace simpli
