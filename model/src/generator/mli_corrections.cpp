// The MLI corrections (spec §3 steps 6-8, §4.7, §7): the current mesh is
// rendered into every source view, the discrepancy [rendered - image | image] is unprojected
// onto the final surfaces (corner grid, depth D), aggregated over views as weighted mean /
// variance plus view self-attention, and a per-surface 2-D DoubleConvResnet refines the state.
#include "generator/internal.h"

#include "simpli/error.h"
#include "simpli/model/geometry/layer_unproject.h"

#include "simpli/ocl/autograd.h"
#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_reduce.h"
#include "simpli/ocl/ops_shape.h"

#include <algorithm>

namespace simpli::generator {

namespace {

using ocl::Tensor;

/// Weighted mean and (not normalised) weighted variance over views (axis 0):
/// samples [V, S, C, h, w], weights [V, S, 1, h, w] -> mean, var [S, C, h, w].
std::pair<Tensor, Tensor> weightedMeanVar(const Tensor& samples, const Tensor& weights) {
  const Tensor mean = ocl::sum(ocl::mul(samples, weights), 0);
  const Tensor centred = ocl::sub(samples, ocl::unsqueeze(mean, 0));
  const Tensor var = ocl::sum(ocl::mul(ocl::square(centred), weights), 0);
  return {mean, var};
}

// The aggregation as composed ops (the reference's form; the training path): state, the
// weighted mean / variance of the samples and, with attention, of the attended tokens ->
// [S, Cs + 2C (+ 2C), h, w].
Tensor composedAggregation(const Context& ctx, const network::TBlock& block,
                           const std::string& name, const std::string& stage, const Tensor& state,
                           const Tensor& samples, const Tensor& weights) {
  const int64_t V = samples.size(0), S = samples.size(1), C = samples.size(2);
  const int64_t h = samples.size(3), w = samples.size(4);
  const auto [mean, var] = weightedMeanVar(samples, weights);
  std::vector<Tensor> parts{state, mean, var};
  ctx.clock->mark(stage + "_unproject");

  if (block.attention) {
    // Tokens [S*h*w, V, C + 1] = [samples | weight] per (surface, pixel); every view attends to
    // every view (invalid views included, with zero samples and zero weight).
    const Tensor tokens = ocl::reshape(
        ocl::permute(ocl::concat({samples, weights}, 2), {1, 3, 4, 0, 2}), {S * h * w, V, C + 1});
    ctx.hook(name + ".attention_agg.in0", tokens);
    const Tensor attended = chunked(tokens, h * w, [&](const Tensor& surface) {
      return block.attention->forward(surface);
    }); // [S*h*w, V, C], one surface at a time in inference
    ctx.hook(name + ".attention_agg.out", attended);
    const Tensor perView =
        ocl::permute(ocl::reshape(attended, {S, h, w, V, C}), {3, 0, 4, 1, 2}); // [V, S, C, h, w]
    const auto [attMean, attVar] = weightedMeanVar(perView, weights);
    parts.push_back(attMean);
    parts.push_back(attVar);
    ctx.clock->mark(stage + "_attention");
  }
  return ocl::concat(parts, 1);
}

// The fused aggregation gives no tokens to a stage hook.
bool useFusedAggregation(const Context& ctx, int64_t views) {
  return ctx.options.fusedAggregation && !ctx.options.stageHook &&
         views <= network::ViewAttention::kMaxFusedViews;
}

} // namespace

raster::RasterSettings settingsForSurfaces(raster::RasterSettings settings, int surfaces,
                                           bool mpiOnly) {
  // MPI planes never occlude each other's triangles within a plane, so a pixel has at most one
  // fragment per plane; keep them all (the reference composites all its planes).
  if (mpiOnly)
    settings.maxFragments = std::min(64, std::max(settings.maxFragments, surfaces));
  return settings;
}

Tensor rasterizeIntoSources(const Tensor& rgba, const Tensor& depth, const GeneratorInput& input,
                            const raster::RasterSettings& settings) {
  const int H = static_cast<int>(input.images.size(2)), W = static_cast<int>(input.images.size(3));
  std::vector<Tensor> views;
  views.reserve(input.sources.size());
  for (const scene::Camera& source : input.sources) {
    scene::Camera target = source; // relative intrinsics: only the output size is set here
    target.width = W;
    target.height = H;
    views.push_back(ocl::unsqueeze(
        raster::renderLayers(depth, rgba, input.reference, target, settings).colour, 0));
  }
  return views.size() == 1 ? views[0] : ocl::concat(views, 0); // [V, 3, H, W]
}

Tensor mliCorrection(const Context& ctx, int level, const Surfaces& mesh, const Tensor& depth,
                     const Tensor& state, Tensor* render) {
  const network::SimpliNetwork& net = ctx.net;
  const network::NetworkConfig& cfg = net.config();
  const network::TBlock& block = net.samliBlocks[static_cast<std::size_t>(level - 2)];
  const std::string name = "samli_block_lvl" + std::to_string(level);
  const std::string stage = "level" + std::to_string(level);

  // Render the current mesh into the sources.
  Tensor rendered;
  if (ctx.options.sourceRenderer) {
    rendered = ctx.options.sourceRenderer(mesh.rgba, mesh.depth, ctx.input, level);
    const ocl::Shape expected{ctx.V, 3, ctx.H, ctx.W};
    if (!rendered.defined() || rendered.shape() != expected ||
        rendered.dtype() != ctx.input.images.dtype())
      fail("Generator: the source renderer returned ",
           rendered.defined() ? rendered.describe() : std::string("nothing"), " at level ", level,
           ", expected ", ocl::toString(ctx.input.images.dtype()), ocl::toString(expected));
  } else {
    const raster::RasterSettings settings =
        settingsForSurfaces(ctx.options.raster, static_cast<int>(mesh.rgba.size(0)), cfg.mpiOnly);
    rendered = rasterizeIntoSources(mesh.rgba, mesh.depth, ctx.input, settings);
  }
  ctx.hook("renderer_lvl" + std::to_string(level) + ".out.images", rendered);
  if (render)
    *render = rendered;
  ctx.clock->mark(stage + "_render");

  // Per-view maps: the discrepancy (rendered - observed), with the image appended (§7).
  const Tensor error = ocl::sub(rendered, ctx.input.images);
  const Tensor maps = cfg.mliErrorWithImage ? ocl::concat({error, ctx.input.images}, 1) : error;
  ctx.hook(name + ".in.source_features", maps);

  // Unproject onto the final surfaces: samples [V, S, C, h, w], mask [V, S, 1, h, w].
  const geometry::SurfaceSamples sampled =
      geometry::unprojectLayers(maps, depth, ctx.input.reference, ctx.input.sources);
  const Tensor& samples = sampled.samples;
  // w_v = m_v / (sum_v m_v + 1e-7).
  const Tensor weights =
      ocl::div(sampled.mask, ocl::addScalar(ocl::sum(sampled.mask, 0, /*keepdim=*/true), 1e-7));
  Tensor x;
  if (block.attention && useFusedAggregation(ctx, samples.size(0))) {
    // [S, Cs + 4C, h, w]: state | mean | var | attended mean | attended var, as composed below.
    ctx.clock->mark(stage + "_unproject");
    x = ocl::concat({state, block.attention->aggregate(samples, weights)}, 1);
    ctx.clock->mark(stage + "_attention"); // the samples' mean / variance included
  } else {
    x = composedAggregation(ctx, block, name, stage, state, samples, weights);
  }
  ctx.hook(name + ".post_aggregate_block.in0", x);
  const Tensor out =
      chunked(x, 1, [&](const Tensor& surface) { return block.postAggregate.forward(surface); });
  ctx.hook(name + ".out", out);
  ctx.clock->mark(stage + "_convs");
  return out;
}

} // namespace simpli::generator
