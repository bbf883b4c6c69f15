#include "simpli/model/generator/scene_input.h"

#include "simpli/error.h"
#include "simpli/model/scene/reference_camera.h"

#include <set>

namespace simpli::generator {

std::vector<int> sceneInputViews(const scene::Scene& scene, const std::vector<int>& views) {
  if (scene.size() == 0)
    fail("scene ", scene.root, ": no views");
  std::vector<int> out = views;
  if (out.empty())
    for (std::size_t i = 0; i < scene.size(); ++i)
      out.push_back(static_cast<int>(i));
  std::set<int> seen;
  for (int v : out) {
    if (v < 0 || static_cast<std::size_t>(v) >= scene.size())
      fail("scene ", scene.root, ": source view ", v, " out of range (", scene.size(),
           " views, 0..", scene.size() - 1, ")");
    if (!seen.insert(v).second)
      fail("scene ", scene.root, ": source view ", v, " given twice");
  }
  return out;
}

GeneratorInput sceneInput(const scene::Scene& scene, const SceneInputOptions& options) {
  const std::vector<int> views = sceneInputViews(scene, options.views);
  const int H = scene.height(), W = scene.width();
  GeneratorInput input;
  std::vector<float> pixels;
  pixels.reserve(views.size() * 3 * static_cast<std::size_t>(H) * W);
  for (int v : views) {
    const scene::SceneView& view = scene.views[static_cast<std::size_t>(v)];
    if (view.camera.width != W || view.camera.height != H)
      fail("scene ", scene.root, ": view ", v, " (", view.name, ") is ", view.camera.width, " x ",
           view.camera.height, ", view 0 is ", W, " x ", H, "; the sources must share one size");
    pixels.insert(pixels.end(), view.image.data.begin(), view.image.data.end());
    input.sources.push_back(view.camera);
  }
  input.images =
      ocl::Tensor::fromHost(pixels, {static_cast<int64_t>(views.size()), 3, H, W}, options.dtype);
  input.reference = scene::referenceCamera(input.sources);
  input.reference.width = W;
  input.reference.height = H;
  if (options.depthRange == DepthRangeSource::Scene) {
    if (!(scene.near > 0 && scene.far > scene.near))
      fail("scene ", scene.root, ": near ", scene.near, ", far ", scene.far,
           " cannot serve as the depth range (need 0 < near < far)");
    input.minDepth = scene.near;
    input.maxDepth = scene.far;
  }
  return input;
}

} // namespace simpli::generator
