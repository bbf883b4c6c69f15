#include "simpli/model/raster/render_mli.h"

#include <vector>

namespace simpli::raster {

MLITensors mliTensors(const mli::MLI& mli, ocl::Dtype dtype) {
  mli::validateMLI(mli, "mliTensors");
  const int64_t L = mli.numLayers(), H = mli.height(), W = mli.width();
  const std::size_t texels = mli.texels();
  std::vector<double> depth(static_cast<std::size_t>(L) * texels);
  std::vector<double> rgba(static_cast<std::size_t>(L) * 4 * texels);
  for (int64_t k = 0; k < L; ++k) {
    const mli::MLILayer& layer = mli.layers[static_cast<std::size_t>(k)];
    for (std::size_t p = 0; p < texels; ++p) {
      depth[k * texels + p] = layer.depth[p];
      // Interleaved RGBA -> channel planes.
      for (std::size_t c = 0; c < 4; ++c)
        rgba[(k * 4 + c) * texels + p] = layer.rgba[4 * p + c];
    }
  }
  return {ocl::Tensor::fromHost(depth, {L, H, W}, dtype),
          ocl::Tensor::fromHost(rgba, {L, 4, H, W}, dtype)};
}

RenderedLayers renderMLI(const mli::MLI& mli, const scene::Camera& target,
                         const RasterSettings& settings, ocl::Dtype dtype) {
  const MLITensors t = mliTensors(mli, dtype);
  return renderLayers(t.depth, t.rgba, mli.camera, target, settings);
}

} // namespace simpli::raster
