// Whole-network gradient check of Generator::forward in float64 on the tiny config: the
// analytic gradient of a random projection of the outputs (RGBA and depth) with respect to
// one entry of one or two parameter tensors of every module is compared with central differences of
// the full forward pass, through the plane sweep, MPI rendering, deformer, process_depth,
// layer unprojection, view attention and the OpenCL rasterizer.
//
// The rasterizer does not differentiate visibility (which triangles cover a pixel); the check
// is valid only where the perturbation leaves visibility unchanged, so the renderer used here
// records the fragment ids of every source render and each probe verifies that the +h and -h
// passes saw exactly the fragments of the unperturbed pass.
//
// Step h = 1e-6 (relative): the network's ReLU / ELU kinks and curvature leave O(h) errors in
// central differences (measured: up to 5e-5 of the largest gradient at h = 1e-5, 6e-4 at
// h = 1e-4, shrinking with h), while float64 rounding of the loss (~1e-13) stays far below the
// tolerance 1e-5 x max|grad| at this step.
#include "generator_test_util.h"

#include "simpli/ocl/autograd.h"
#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_reduce.h"
#include "simpli/ocl/ops_shape.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

namespace simpli {
namespace {

using ocl::Dtype;
using ocl::Tensor;

/// The default rasterizer, recording the triangle ids of every render.
struct RecordingRenderer {
  std::vector<std::vector<int32_t>> ids;
  generator::SourceRenderer renderer() {
    return [this](const Tensor& rgba, const Tensor& depth, const generator::GeneratorInput& input,
                  int) {
      std::vector<Tensor> views;
      for (const scene::Camera& source : input.sources) {
        scene::Camera target = source;
        target.width = static_cast<int>(input.images.size(3));
        target.height = static_cast<int>(input.images.size(2));
        const raster::RasterFragments f = raster::rasterizeLayers(depth.detach(), input.reference,
                                                                  target, raster::RasterSettings{});
        ids.push_back(f.triangleIds());
        views.push_back(ocl::unsqueeze(raster::shadeFragments(f, depth, rgba).colour, 0));
      }
      return ocl::concat(views, 0);
    };
  }
};

TEST(GeneratorGradient, WholeNetworkFloat64) {
  auto net = test::configNetwork("tiny", Dtype::F64, 5);
  const generator::GeneratorInput input = test::syntheticInput(2, 16, 24, Dtype::F64, 31);
  RecordingRenderer recorder;
  generator::GeneratorOptions options;
  options.sourceRenderer = recorder.renderer();
  const generator::Generator generator(*net);

  Tensor R1, R2;
  auto loss = [&](const generator::GeneratorOutput& out) {
    return ocl::add(ocl::sumAll(ocl::mul(out.rgba, R1)),
                    ocl::mulScalar(ocl::sumAll(ocl::mul(out.depth, R2)), 0.1));
  };
  {
    const generator::GeneratorOutput out = generator.forward(input, options);
    R1 = Tensor::uniform(out.rgba.shape(), -1, 1, 101, Dtype::F64);
    R2 = Tensor::uniform(out.depth.shape(), -1, 1, 102, Dtype::F64);
    net->parameters().zeroGrad();
    loss(out).backward();
  }
  const std::vector<std::vector<int32_t>> visibility = recorder.ids;
  ASSERT_EQ(visibility.size(), 6u); // 3 corrections x 2 views

  const std::vector<std::string> probed{
      "features_extractor.convDb.conv.weight",
      "features_extractor.conv1a.norm.gamma",
      "sampi_block_lvl0.post_aggregate_block.model.0.double_conv.0.conv.weight",
      "alpha_decoder_lvl0.model.2.conv.bias",
      "sampi_block_lvl1.post_aggregate_block.model.0.residual_conv.conv.weight",
      "planes_deformer_lvl1.anchor",
      "planes_deformer_lvl1.ray_attention.w_ks.weight",
      "depth_decoder_lvl1.model.2.conv.weight",
      "rgba_decoder_lvl1.model.2.conv.bias",
      "samli_block_lvl2.attention_agg.w_qs.weight",
      "samli_block_lvl2.post_aggregate_block.model.0.double_conv.1.norm.beta",
      "rgba_decoder_lvl2.model.0.conv.weight",
      "samli_block_lvl3.attention_agg.fc.weight",
      "rgba_decoder_lvl3.model.1.conv.bias",
      "samli_block_lvl4.post_aggregate_block.model.1.double_conv.0.conv.weight",
      "rgba_decoder_lvl4.model.2.conv.weight"};
  auto evaluate = [&] {
    ocl::NoGradGuard noGrad;
    recorder.ids.clear();
    const double value = loss(generator.forward(input, options)).item();
    EXPECT_TRUE(recorder.ids == visibility) << "visibility changed under the perturbation";
    return value;
  };
  double worst = 0; // largest |analytic - fd| / (largest gradient entry of the tensor)
  for (const std::string& name : probed) {
    SCOPED_TRACE(name);
    Tensor p = net->parameters().get(name);
    ASSERT_TRUE(p.grad().defined()) << name << " received no gradient";
    const std::vector<double> analytic = p.grad().toVector();
    double scale = 1e-6;
    for (double g : analytic)
      scale = std::max(scale, std::abs(g));
    std::vector<double> values = p.toVector();
    const std::size_t n = values.size();
    { // one entry per tensor (away from index 0, which is often a border / first channel)
      const std::size_t i = n / 3;
      const double v = values[i], h = 1e-6 * std::max(1.0, std::abs(v));
      values[i] = v + h;
      p.copyFromHost(values);
      const double up = evaluate();
      values[i] = v - h;
      p.copyFromHost(values);
      const double down = evaluate();
      values[i] = v;
      p.copyFromHost(values);
      const double fd = (up - down) / (2 * h);
      worst = std::max(worst, std::abs(analytic[i] - fd) / scale);
      EXPECT_NEAR(analytic[i], fd, 1e-5 * scale + 1e-9)
          << name << "[" << i << "] (largest gradient entry " << scale << ")";
    }
  }
  std::cout << "[gradcheck] " << probed.size()
            << " tensors, worst |analytic - fd| / max|grad| = " << worst << std::endl;
}

} // namespace
} // namespace simpli
