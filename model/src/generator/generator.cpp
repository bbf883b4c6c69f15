// Generator::forward: input checks and the order of the steps of spec §3.
//
// Stage hook names (GeneratorOptions::stageHook) and the layouts passed (S surfaces, P planes,
// V views, Cf feature channels; h0/h1/h2 the level sizes, Hf x Wf the features' size):
//   features_extractor.out                    [V, Cf, Hf, Wf]
//   sampi_block_lvl0.out                      [1, P, C0, h0, w0] raw level-0 features
//   sampi_block_lvl0.post_aggregate_block.in0 [1, Cst + 2 Cf, P, h0, w0] (state | mean | var)
//   alpha_decoder_lvl0.out                    [P, 1, h0, w0] logits
//   composer.mpi_render_lvl1.out.{color,opacity,weight}  [V, C0, Hf, Wf], [V, 1, ..],
//                                             [V, P, 1, Hf, Wf]
//   sampi_block_lvl1.in.source_features       [V, Cf, Hf, Wf] (rendered - features)
//   sampi_block_lvl1.post_aggregate_block.in0 [P, C0 + 1 + 2 Cf, h1, w1]
//   sampi_block_lvl1.out                      [P, Cs, h1, w1]
//   planes_deformer_lvl1.out                  [1, L, Cs, h1, w1]   (not MPI-only)
//   depth_decoder_lvl1.out                    [L, G, h1, w1]       (not MPI-only)
//   process_depth_lvl1.out, layered_depth     [1, L, h1, w1], [1, L, h2, w2] (not MPI-only)
//   process_depth_lvl2.in0                    [1, L * G, h2, w2] upsampled logits (not MPI-only)
//   rgba_decoder_lvlK.out                     [S, 4, h, w] raw (before tanh / sigmoid)
//   renderer_lvlK.out.images                  [V, 3, H, W]
//   samli_block_lvlK.in.source_features       [V, 6 (or 3), H, W]
//   samli_block_lvlK.attention_agg.{in0,out}  [S*h2*w2, V, 7], [S*h2*w2, V, 6]
//   samli_block_lvlK.post_aggregate_block.in0 [S, Cs + 4 * 6, h2, w2]
//   samli_block_lvlK.out                      [S, Cs, h2, w2]
//   final.rgba                                [S, 4, h2, w2]
#include "generator/internal.h"

#include "simpli/error.h"
#include "simpli/model/geometry/planes.h"
#include "simpli/model/network/surface_ops.h"

#include "simpli/ocl/autograd.h"
#include "simpli/ocl/device.h"
#include "simpli/ocl/ops_resample.h"
#include "simpli/ocl/ops_shape.h"

#include <algorithm>
#include <cmath>

namespace simpli::generator {

StageClock::StageClock(bool finish, std::vector<std::pair<std::string, double>>* out,
                       const GeneratorOptions::ProgressFn* progress, int total)
    : finish_(finish), out_(out), progress_(progress && *progress ? progress : nullptr),
      total_(total) {
  if (finish_)
    ocl::Device::current().finish();
  last_ = std::chrono::steady_clock::now();
}

void StageClock::mark(const std::string& name) {
  if (finish_)
    ocl::Device::current().finish();
  const auto now = std::chrono::steady_clock::now();
  out_->emplace_back(name, std::chrono::duration<double, std::milli>(now - last_).count());
  last_ = now;
  ++done_;
  if (progress_ && !(*progress_)(name, done_, std::max(total_, done_)))
    throw GeneratorCancelled{};
}

ocl::Tensor chunked(const ocl::Tensor& x, int64_t chunk,
                    const std::function<ocl::Tensor(const ocl::Tensor&)>& f) {
  const int64_t n = x.size(0);
  if (ocl::GradMode::enabled() || chunk <= 0 || n <= chunk)
    return f(x);
  std::vector<ocl::Tensor> parts;
  for (int64_t begin = 0; begin < n; begin += chunk)
    parts.push_back(f(ocl::slice(x, 0, begin, std::min(n, begin + chunk))));
  return ocl::concat(parts, 0);
}

namespace {

/// round(size * scale), which must be a positive integer size (e.g. H / 4).
int scaledSize(int size, double scale, const char* key, const char* axis) {
  const double exact = size * scale;
  const int rounded = static_cast<int>(std::lround(exact));
  if (rounded < 2 || std::abs(exact - rounded) > 1e-9)
    fail("Generator: image ", axis, " ", size, " times the config's ", key, " ", scale,
         " is not an integer size >= 2");
  return rounded;
}

void checkInput(const network::SimpliNetwork& net, const GeneratorInput& input) {
  const ocl::Tensor& images = input.images;
  if (!images.defined())
    fail("Generator: input images are undefined");
  if (images.dim() != 4 || images.size(1) != 3 || images.size(0) < 1)
    fail("Generator: input images ", images.describe(), " must be [V >= 1, 3, H, W]");
  if (images.dtype() != net.parameters().dtype())
    fail("Generator: input images ", images.describe(), " do not match the network's dtype ",
         ocl::toString(net.parameters().dtype()));
  if (static_cast<int64_t>(input.sources.size()) != images.size(0))
    fail("Generator: ", input.sources.size(), " source cameras for images ", images.describe());
  // The feature extractor pools three times and concatenates upsampled maps (§1.5).
  if (images.size(2) % 8 != 0 || images.size(3) % 8 != 0)
    fail("Generator: input images ", images.describe(),
         ": height and width must be multiples of 8 (16 recommended)");
  const auto finiteCamera = [](const scene::Camera& c) {
    return c.R.allFinite() && c.t.allFinite() && std::isfinite(c.fx) && std::isfinite(c.fy) &&
           std::isfinite(c.cx) && std::isfinite(c.cy) && c.fx > 0 && c.fy > 0;
  };
  for (std::size_t v = 0; v < input.sources.size(); ++v)
    if (!finiteCamera(input.sources[v]))
      fail("Generator: source camera ", v, " has non-finite values or non-positive focal lengths");
  if (!finiteCamera(input.reference))
    fail("Generator: the reference camera has non-finite values or non-positive focal lengths");
  const bool customRange = input.minDepth > 0 || input.maxDepth > 0;
  if (customRange && !(input.minDepth > 0 && std::isfinite(input.minDepth) &&
                       input.maxDepth >= input.minDepth && !std::isnan(input.maxDepth)))
    fail("Generator: depth range minDepth = ", input.minDepth, ", maxDepth = ", input.maxDepth,
         " must satisfy 0 < minDepth <= maxDepth, minDepth finite (or both <= 0 for the "
         "config's)");
}

} // namespace

Generator::Generator(network::SimpliNetwork& network) : network_(network) {
  if (network_.config().scaleFeatExtractor != 1.0)
    fail("Generator: config '", network_.config().name, "' has scale_feat_extractor ",
         network_.config().scaleFeatExtractor, "; only 1 (as in the reference) is supported");
}

GeneratorOutput Generator::forward(const GeneratorInput& input,
                                   const GeneratorOptions& options) const {
  const network::NetworkConfig& cfg = network_.config();
  checkInput(network_, input);
  const int corrections = options.corrections < 0 ? cfg.mliCorrections() : options.corrections;
  if (corrections > cfg.mliCorrections())
    fail("Generator: ", corrections, " corrections requested; config '", cfg.name, "' has ",
         cfg.mliCorrections());

  GeneratorOutput output;
  output.mpiOnly = cfg.mpiOnly;
  // Stages (StageClock marks): features, level0, mpi_render, level1, planes_to_layers, then per
  // correction render, unproject, [attention,] convs and decode.
  int stages = 5;
  for (int k = 0; k < corrections; ++k)
    stages += network_.samliBlocks[static_cast<std::size_t>(k)].attention ? 5 : 4;
  StageClock clock(options.timeStages, &output.stageMs, &options.progress, stages);
  const double near = input.minDepth > 0 ? input.minDepth : cfg.minDepth;
  double far = input.maxDepth > 0 ? input.maxDepth : cfg.maxDepth;
  // far = infinity (scenes with sky): the farthest plane would sit at disparity 0, i.e. at an
  // infinite depth, and every depth, homography and MLI value derived from it would be
  // non-finite. It goes to 1e6 x near instead, where a camera moved by up to
  // `near` shifts it by at most f_px 1e-6 pixels: indistinguishable from infinity for images
  // below 10^4 pixels, and finite in float32.
  if (std::isinf(far))
    far = near * 1e6;
  // The corrections' source renders keep fragments inside the rasterizer's near / far cut
  // (0.01 .. 120 by default: the config range 1 .. 100 with margins). A depth range outside it
  // (1e3 .. 1e6, say) would cut every surface and feed the corrections empty renders, so the
  // cut is widened by the same margins to cover the range (unchanged for the config's range).
  GeneratorOptions adjusted = options;
  adjusted.raster.nearZ = std::min(adjusted.raster.nearZ, 0.01 * near);
  if (adjusted.raster.farZ > 0 && std::isfinite(adjusted.raster.farZ))
    adjusted.raster.farZ = std::max(adjusted.raster.farZ, 1.2 * far);
  Context ctx{network_, input, adjusted, geometry::planeDepths(cfg.numPlanes, near, far)};
  ctx.V = static_cast<int>(input.images.size(0));
  ctx.H = static_cast<int>(input.images.size(2));
  ctx.W = static_cast<int>(input.images.size(3));
  ctx.h0 = scaledSize(ctx.H, cfg.scaleLvl0, "scale_lvl0", "height");
  ctx.w0 = scaledSize(ctx.W, cfg.scaleLvl0, "scale_lvl0", "width");
  ctx.h1 = scaledSize(ctx.H, cfg.scaleLvl1, "scale_lvl1", "height");
  ctx.w1 = scaledSize(ctx.W, cfg.scaleLvl1, "scale_lvl1", "width");
  ctx.h2 = scaledSize(ctx.H, cfg.scaleLvl2, "scale_lvl2", "height");
  ctx.w2 = scaledSize(ctx.W, cfg.scaleLvl2, "scale_lvl2", "width");
  ctx.clock = &clock;

  const MpiLevels mpi = runMpiLevels(ctx);
  if (options.keepIntermediates) {
    // The RGB-like channels of the MPI render (after the descriptors), for intermediate loss 0.
    const int64_t d = cfg.featuresExtractor.descriptors;
    output.intermediateSourceRenders.push_back(ocl::slice(mpi.rendered, 1, d, d + 3));
    output.level0SourceWeights = mpi.renderWeights;
    output.planeDepths = ctx.planeDepths;
  }
  const Level1Surfaces level1 = planesToLayers(ctx, mpi);

  if (corrections == 0) {
    // No correction: the level-1 surfaces (RGBA1 with the depths they were decoded with) at
    // scale_lvl1 resolution are the output.
    output.rgba = level1.mesh.rgba;
    output.depth = level1.mesh.depth;
    return output;
  }

  // Level 2 starts from the level-1 features resized to the final resolution.
  ocl::Tensor state = level1.features;
  if (state.size(2) != ctx.h2 || state.size(3) != ctx.w2)
    state = ocl::resizeBicubic(state, ctx.h2, ctx.w2);
  Surfaces mesh = level1.mesh;
  for (int k = 0; k < corrections; ++k) {
    const int level = k + 2;
    ocl::Tensor render;
    state = mliCorrection(ctx, level, mesh, level1.finalDepth, state, &render);
    if (options.keepIntermediates)
      output.intermediateSourceRenders.push_back(render);
    const ocl::Tensor raw =
        network_.rgbaDecoders[static_cast<std::size_t>(level - 1)].forward(state);
    ctx.hook("rgba_decoder_lvl" + std::to_string(level) + ".out", raw);
    mesh = {network::activateRgba(raw, 1), level1.finalDepth};
    clock.mark("level" + std::to_string(level) + "_decode");
  }
  output.rgba = mesh.rgba;
  output.depth = mesh.depth;
  ctx.hook("final.rgba", output.rgba);
  return output;
}

} // namespace simpli::generator
