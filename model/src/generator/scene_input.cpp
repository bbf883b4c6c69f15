#include "simpli/model/generator/scene_input.h"

#include "simpli/error.h"
#include "simpli/model/io/image.h"
#include "simpli/model/scene/reference_camera.h"

#include <algorithm>
#include <cmath>
#include <set>

namespace simpli::generator {

int scaledSize(int size, double scale) {
  return std::max(16, static_cast<int>(std::lround(size * scale / 16.0)) * 16);
}

void checkInputScale(double scale, const std::string& what) {
  if (!(scale > 0 && scale <= 2))
    fail(what, " ", scale, ": must be in (0, 2]");
}

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
  checkInputScale(options.inputScale, "input scale");
  const int H = scene.height(), W = scene.width();
  const bool resize = options.inputScale != 1.0;
  const int h = resize ? scaledSize(H, options.inputScale) : H;
  const int w = resize ? scaledSize(W, options.inputScale) : W;
  GeneratorInput input;
  std::vector<float> pixels;
  pixels.reserve(views.size() * 3 * static_cast<std::size_t>(h) * w);
  for (int v : views) {
    const scene::SceneView& view = scene.views[static_cast<std::size_t>(v)];
    if (view.camera.width != W || view.camera.height != H)
      fail("scene ", scene.root, ": view ", v, " (", view.name, ") is ", view.camera.width, " x ",
           view.camera.height, ", view 0 is ", W, " x ", H, "; the sources must share one size");
    if (resize) {
      const io::Image small = io::resizeImage(view.image, w, h);
      pixels.insert(pixels.end(), small.data.begin(), small.data.end());
    } else {
      pixels.insert(pixels.end(), view.image.data.begin(), view.image.data.end());
    }
    input.sources.push_back(view.camera);
    input.sources.back().width = w; // relative intrinsics: only the size changes
    input.sources.back().height = h;
  }
  input.images =
      ocl::Tensor::fromHost(pixels, {static_cast<int64_t>(views.size()), 3, h, w}, options.dtype);
  input.reference = scene::referenceCamera(input.sources);
  input.reference.width = w;
  input.reference.height = h;
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
