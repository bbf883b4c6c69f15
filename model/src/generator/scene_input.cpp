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

GeneratorInput scaledInput(const std::vector<const io::Image*>& images,
                           std::vector<scene::Camera> cameras, scene::Camera reference,
                           double inputScale, ocl::Dtype dtype) {
  checkInputScale(inputScale, "input scale");
  if (images.empty() || images.size() != cameras.size())
    fail("scaledInput: ", images.size(), " images for ", cameras.size(), " cameras");
  const int W = images[0]->width, H = images[0]->height;
  const bool resize = inputScale != 1.0;
  const int w = resize ? scaledSize(W, inputScale) : W;
  const int h = resize ? scaledSize(H, inputScale) : H;
  std::vector<float> pixels;
  pixels.reserve(images.size() * 3 * static_cast<std::size_t>(h) * w);
  for (const io::Image* image : images) {
    if (image->width != W || image->height != H)
      fail("scaledInput: images of different sizes (", W, "x", H, " and ", image->width, "x",
           image->height, ")");
    if (w == W && h == H) {
      pixels.insert(pixels.end(), image->data.begin(), image->data.end());
    } else {
      const io::Image resized = io::resizeImage(*image, w, h);
      pixels.insert(pixels.end(), resized.data.begin(), resized.data.end());
    }
  }
  GeneratorInput input;
  input.images =
      ocl::Tensor::fromHost(pixels, {static_cast<int64_t>(images.size()), 3, h, w}, dtype);
  for (scene::Camera& c : cameras) {
    c.width = w;
    c.height = h;
  }
  input.sources = std::move(cameras);
  input.reference = std::move(reference);
  input.reference.width = w;
  input.reference.height = h;
  return input;
}

GeneratorInput sceneInput(const scene::Scene& scene, const SceneInputOptions& options) {
  const std::vector<int> views = sceneInputViews(scene, options.views);
  checkInputScale(options.inputScale, "input scale");
  const int H = scene.height(), W = scene.width();
  std::vector<const io::Image*> images;
  std::vector<scene::Camera> cameras;
  for (int v : views) {
    const scene::SceneView& view = scene.views[static_cast<std::size_t>(v)];
    if (view.camera.width != W || view.camera.height != H)
      fail("scene ", scene.root, ": view ", v, " (", view.name, ") is ", view.camera.width, " x ",
           view.camera.height, ", view 0 is ", W, " x ", H, "; the sources must share one size");
    images.push_back(&view.image);
    cameras.push_back(view.camera);
  }
  const scene::Camera reference =
      scene::widenedCamera(scene::referenceCamera(cameras), options.referenceMargin);
  GeneratorInput input =
      scaledInput(images, std::move(cameras), reference, options.inputScale, options.dtype);
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
