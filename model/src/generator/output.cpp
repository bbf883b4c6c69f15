// What the generator's output becomes: a novel view (spec §6.8) or a CPU MLI
// (mli/mli.h) for export.
#include "generator/internal.h"

#include "simpli/error.h"

#include "simpli/ocl/ops_elementwise.h"

#include <algorithm>
#include <cmath>

namespace simpli::generator {

namespace {

void checkOutput(const GeneratorOutput& output, const char* op) {
  if (!output.rgba.defined() || !output.depth.defined())
    fail(op, ": the generator output is empty");
  const ocl::Tensor &rgba = output.rgba, &depth = output.depth;
  if (rgba.dim() != 4 || rgba.size(1) != 4 || depth.dim() != 3 || depth.size(0) != rgba.size(0) ||
      depth.size(1) != rgba.size(2) || depth.size(2) != rgba.size(3))
    fail(op, ": output rgba ", rgba.describe(), " and depth ", depth.describe(),
         " must be [S, 4, H, W] and [S, H, W]");
}

} // namespace

raster::RenderedLayers renderNovelView(const GeneratorOutput& output,
                                       const scene::Camera& reference, const scene::Camera& target,
                                       const raster::RasterSettings& settings) {
  checkOutput(output, "renderNovelView");
  const raster::RasterSettings s =
      settingsForSurfaces(settings, static_cast<int>(output.rgba.size(0)), output.mpiOnly);
  raster::RenderedLayers r = raster::renderLayers(output.depth, output.rgba, reference, target, s);
  r.colour = ocl::clamp(r.colour, -1.0, 1.0);
  return r;
}

mli::MLI toMLI(const GeneratorOutput& output, const scene::Camera& reference,
               float dropEmptyBelow) {
  checkOutput(output, "toMLI");
  const int S = static_cast<int>(output.rgba.size(0));
  const int H = static_cast<int>(output.rgba.size(2)), W = static_cast<int>(output.rgba.size(3));
  const std::vector<float> rgba = output.rgba.toVectorF32();
  const std::vector<float> depth = output.depth.toVectorF32();
  const std::size_t texels = static_cast<std::size_t>(H) * W;

  mli::MLI mli;
  mli.camera = reference;
  mli.camera.width = W;
  mli.camera.height = H;
  std::vector<mli::MLILayer> layers(static_cast<std::size_t>(S));
  std::vector<float> maxAlphas(static_cast<std::size_t>(S), 0.0f);
  for (int s = 0; s < S; ++s) {
    mli::MLILayer& layer = layers[s];
    layer.depth.assign(depth.begin() + s * texels, depth.begin() + (s + 1) * texels);
    layer.rgba.resize(texels * 4);
    const float* planes = rgba.data() + static_cast<std::size_t>(s) * 4 * texels; // [4, H, W]
    for (std::size_t i = 0; i < texels; ++i) {
      for (int c = 0; c < 3; ++c) // RGB [-1, 1] -> [0, 1]
        layer.rgba[4 * i + c] = std::clamp(0.5f * (planes[c * texels + i] + 1.0f), 0.0f, 1.0f);
      const float a = std::clamp(planes[3 * texels + i], 0.0f, 1.0f);
      layer.rgba[4 * i + 3] = a;
      maxAlphas[s] = std::max(maxAlphas[s], a);
    }
  }
  for (int s = 0; s < S; ++s)
    if (!(dropEmptyBelow > 0) || maxAlphas[s] >= dropEmptyBelow)
      mli.layers.push_back(std::move(layers[s]));
  if (mli.layers.empty()) {
    // Every surface is empty: keep the most opaque one, an MLI needs at least one layer.
    const auto best = std::max_element(maxAlphas.begin(), maxAlphas.end()) - maxAlphas.begin();
    mli.layers.push_back(std::move(layers[static_cast<std::size_t>(best)]));
  }
  mli::validateMLI(mli, "toMLI");
  return mli;
}

} // namespace simpli::generator
