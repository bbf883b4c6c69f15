// Steps 1-4 of the generator (spec §3): feature extraction, the level-0 MPI
// (3-D aggregation of the plane sweep), the MPI rendered into the sources (level-1
// discrepancy) and the level-1 corrected MPI.
#include "generator/internal.h"

#include "simpli/model/baselines/plane_sweep_stereo.h"

#include "simpli/model/geometry/mpi_render.h"
#include "simpli/model/geometry/plane_sweep.h"
#include "simpli/model/network/surface_ops.h"

#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_reduce.h"
#include "simpli/ocl/ops_resample.h"
#include "simpli/ocl/ops_shape.h"

namespace simpli::generator {

namespace {

using ocl::Tensor;

/// Planes per call of the level-1 post-aggregation stack in inference (memory bound only:
/// every plane is normalised on its own).
constexpr int64_t kPlanesPerChunk = 8;

/// Bicubic resize of [N, C, h, w] maps, skipped when the size already matches (the reference
/// calls F.interpolate only where sizes differ).
Tensor resizeTo(const Tensor& x, int height, int width) {
  if (x.size(2) == height && x.size(3) == width)
    return x;
  return ocl::resizeBicubic(x, height, width);
}

/// NetworkConfig::lvl0PhotoPrior: the plane-sweep stereo distribution over the network's planes
/// on the level-0 grid, [1, 1, P, h0, w0] (on the device, in the network's dtype). A function of
/// the input images only (no gradient flows into it).
Tensor photoPrior(const Context& ctx) {
  const Tensor prob = baselines::planeProbabilityVolume(
      ctx.input, ctx.planeDepths, {}, static_cast<int>(ctx.h0), static_cast<int>(ctx.w0));
  return ocl::reshape(prob, {1, 1, prob.size(0), ctx.h0, ctx.w0});
}

} // namespace

MpiLevels runMpiLevels(const Context& ctx) {
  const network::SimpliNetwork& net = ctx.net;
  const network::NetworkConfig& cfg = net.config();
  const int P = cfg.numPlanes;
  const int64_t h0 = ctx.h0, w0 = ctx.w0;
  MpiLevels out;

  // Step 1: per-view features [V, Cf, H/2, W/2] (descriptors | box-downsampled RGB).
  out.features = chunked(ctx.input.images, 1,
                         [&](const Tensor& views) { return net.featuresExtractor.forward(views); });
  ctx.hook("features_extractor.out", out.features);
  ctx.clock->mark("features");
  const int64_t Hf = out.features.size(2), Wf = out.features.size(3);

  // Step 2: level-0 MPI. Weighted mean / variance of the plane sweep (fused, never
  // materialised), state = PE(plane index), 3-D DoubleConvResnet over [C, P, h0, w0].
  {
    const Tensor maps = resizeTo(out.features, ctx.h0, ctx.w0);
    const Tensor meanVar =
        geometry::planeSweepMeanVar(maps, ctx.input.reference, ctx.input.sources, ctx.planeDepths,
                                    ctx.h0, ctx.w0); // [P, 2Cf, h0, w0]
    const Tensor stats = ocl::unsqueeze(ocl::permute(meanVar, {1, 0, 2, 3}), 0);
    const int Cst = net.sampiLvl0.stateChannels;
    const Tensor state = ocl::expand(
        ocl::reshape(ocl::transpose(network::planeState(P, Cst, net.parameters().dtype()), 0, 1),
                     {1, Cst, P, 1, 1}),
        {1, Cst, P, h0, w0});
    std::vector<Tensor> inputs{state, stats};
    if (cfg.lvl0PhotoPrior)
      inputs.push_back(photoPrior(ctx));
    const Tensor x = ocl::concat(inputs, 1); // [1, Cst + 2Cf (+ 1), P, h0, w0]
    ctx.hook("sampi_block_lvl0.post_aggregate_block.in0", x);
    const Tensor volume = net.sampiLvl0.postAggregate.forward(x);
    const Tensor raw = ocl::permute(volume, {0, 2, 1, 3, 4}); // [1, P, C0, h0, w0]
    ctx.hook("sampi_block_lvl0.out", raw);
    const int64_t C0 = raw.size(2);
    // Alpha from the untouched features, then the tanh quirk on the nearest planes (§3 step 8).
    const Tensor alphaLogits = net.alphaDecoderLvl0.forward(ocl::reshape(raw, {P, C0, h0, w0}));
    ctx.hook("alpha_decoder_lvl0.out", alphaLogits);
    out.fmpi0 =
        ocl::reshape(network::assembleMpi0(raw, ocl::reshape(alphaLogits, {1, P, 1, h0, w0}),
                                           cfg.lvl0TanhPlanes),
                     {P, C0 + 1, h0, w0});
  }
  ctx.clock->mark("level0");

  // Step 3: fMPI0 composited into every source at the feature resolution; the per-plane
  // compositing weights are kept as level-1 aggregation weights.
  const geometry::MpiRendering rendering =
      geometry::renderMpi(out.fmpi0, ctx.planeDepths, ctx.input.reference, ctx.input.sources,
                          static_cast<int>(Hf), static_cast<int>(Wf));
  out.rendered = rendering.color;
  out.renderWeights = rendering.weights;
  ctx.hook("composer.mpi_render_lvl1.out.color", rendering.color);
  ctx.hook("composer.mpi_render_lvl1.out.opacity", rendering.opacity);
  ctx.hook("composer.mpi_render_lvl1.out.weight", rendering.weights);
  const Tensor error = ocl::sub(rendering.color, out.features); // rendered - observed
  ctx.hook("sampi_block_lvl1.in.source_features", error);
  ctx.clock->mark("mpi_render");

  // Step 4: level-1 TBlock, every plane a separate 2-D sample: [state | mean | var].
  {
    const Tensor state = resizeTo(out.fmpi0, ctx.h1, ctx.w1); // [P, C0 + 1, h1, w1]
    const Tensor meanVar =
        geometry::planeSweepMeanVar(error, ctx.input.reference, ctx.input.sources, ctx.planeDepths,
                                    ctx.h1, ctx.w1, rendering.weights); // [P, 2Cf, h1, w1]
    const Tensor x = ocl::concat({state, meanVar}, 1);
    ctx.hook("sampi_block_lvl1.post_aggregate_block.in0", x);
    out.fmpi1 = chunked(x, kPlanesPerChunk, [&](const Tensor& planes) {
      return net.sampiLvl1.postAggregate.forward(planes);
    }); // [P, Cs, h1, w1]
    ctx.hook("sampi_block_lvl1.out", out.fmpi1);
  }
  ctx.clock->mark("level1");
  return out;
}

} // namespace simpli::generator
