// Training-view sampling (training/sampler.h).
#include "simpli/model/training/sampler.h"

#include "simpli/error.h"
#include "simpli/model/scene/reference_camera.h"
#include "simpli/model/training/augment.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace simpli::training {

FrameDraw drawFrames(int frames, const SamplingConfig& c, TrainRandom& random) {
  if (frames < 2)
    fail("sampler: a scene needs at least 2 frames (a source and a target), got ", frames);
  FrameDraw d;
  const int maxV = std::min(c.maxViews, frames - 1);
  const int minV = std::min(c.minViews, maxV);
  const int V = int(random.uniformInt(minV, maxV));
  const int N = std::min(c.novelViews, frames - V);
  int window = c.window > 0 ? std::max(c.window, V + N) : frames;
  window = std::min(window, frames);
  d.windowLength = window;
  d.windowStart = int(random.uniformInt(0, frames - window));
  // Partial Fisher-Yates over the window: V + N distinct frames in random order.
  std::vector<int> pool(window);
  std::iota(pool.begin(), pool.end(), d.windowStart);
  for (int i = 0; i < V + N; ++i) {
    const int j = int(random.uniformInt(i, window - 1));
    std::swap(pool[i], pool[j]);
  }
  d.sources.assign(pool.begin(), pool.begin() + V);
  d.targets.assign(pool.begin() + V, pool.begin() + V + N);
  return d;
}

scene::Camera cropCamera(const scene::Camera& camera, int x, int y, int width, int height) {
  if (width <= 0 || height <= 0 || camera.width <= 0 || camera.height <= 0)
    fail("cropCamera: window ", width, "x", height, " of a ", camera.width, "x", camera.height,
         " camera");
  scene::Camera c = camera;
  // Pixel intrinsics: fx_px = fx W is unchanged, cx_px = cx W - x; then relative to the crop.
  c.fx = camera.fx * camera.width / width;
  c.fy = camera.fy * camera.height / height;
  c.cx = (camera.cx * camera.width - x) / width;
  c.cy = (camera.cy * camera.height - y) / height;
  c.width = width;
  c.height = height;
  return c;
}

io::Image cropImage(const io::Image& image, int x, int y, int width, int height) {
  if (x < 0 || y < 0 || width <= 0 || height <= 0 || x + width > image.width ||
      y + height > image.height)
    fail("cropImage: window x ", x, " y ", y, " ", width, "x", height, " is not inside the ",
         image.width, "x", image.height, " image");
  io::Image out(width, height);
  for (int c = 0; c < io::Image::channels; ++c)
    for (int r = 0; r < height; ++r)
      std::copy_n(image.plane(c) + size_t(y + r) * image.width + x, width, &out.at(c, r, 0));
  return out;
}

namespace {

// The resized size and the centre crop's origin of a zoom by `factor`.
struct ZoomWindow {
  int width, height, x, y;
};

ZoomWindow zoomWindow(int width, int height, double factor) {
  if (!(factor >= 1))
    fail("zoom: factor ", factor, " must be >= 1");
  ZoomWindow z;
  z.width = std::max(width, int(std::lround(width * factor)));
  z.height = std::max(height, int(std::lround(height * factor)));
  z.x = (z.width - width) / 2;
  z.y = (z.height - height) / 2;
  return z;
}

} // namespace

scene::Camera zoomCamera(const scene::Camera& camera, double factor) {
  const ZoomWindow z = zoomWindow(camera.width, camera.height, factor);
  scene::Camera resized = camera; // relative intrinsics are unchanged by a resize
  resized.width = z.width;
  resized.height = z.height;
  return cropCamera(resized, z.x, z.y, camera.width, camera.height);
}

io::Image zoomImage(const io::Image& image, double factor) {
  const ZoomWindow z = zoomWindow(image.width, image.height, factor);
  return cropImage(io::resizeImage(image, z.width, z.height), z.x, z.y, image.width, image.height);
}

std::vector<float> zoomCropDepth(const std::vector<float>& depth, int width, int height,
                                 double factor, int x, int y, int cropWidth, int cropHeight) {
  if (depth.size() != size_t(width) * size_t(height))
    fail("zoomCropDepth: ", depth.size(), " depths for a ", width, "x", height, " view");
  if (x < 0 || y < 0 || x + cropWidth > width || y + cropHeight > height)
    fail("zoomCropDepth: window x ", x, " y ", y, " ", cropWidth, "x", cropHeight,
         " is not inside the ", width, "x", height, " view");
  const ZoomWindow z = zoomWindow(width, height, factor);
  std::vector<float> out(size_t(cropWidth) * size_t(cropHeight));
  for (int r = 0; r < cropHeight; ++r) {
    // Pixel centres of the zoomed image mapped back onto the source grid.
    const int sy = std::min(height - 1, int((r + y + z.y + 0.5) * height / z.height));
    for (int c = 0; c < cropWidth; ++c) {
      const int sx = std::min(width - 1, int((c + x + z.x + 0.5) * width / z.width));
      out[size_t(r) * cropWidth + c] = depth[size_t(sy) * width + sx];
    }
  }
  return out;
}

Sampler::Sampler(const SamplingConfig& config, uint64_t seed) : config_(config), random_(seed) {}

TrainingSample Sampler::draw(TrainingData& data) {
  const uint64_t count = data.sceneCount();
  const uint64_t index = count == 0 ? uint64_t(random_.uniformInt(0, (int64_t(1) << 31) - 1))
                                    : uint64_t(random_.uniformInt(0, int64_t(count) - 1));
  const FrameDraw d = drawFrames(data.frameCount(index), config_, random_);
  std::vector<int> frames = d.sources;
  frames.insert(frames.end(), d.targets.begin(), d.targets.end());
  const scene::Scene& scene = data.sceneForFrames(index, frames);
  return drawWithFrames(scene, index, data.depths(index), d);
}

TrainingSample Sampler::drawFromScene(const scene::Scene& scene, uint64_t sceneIndex,
                                      const std::vector<std::vector<float>>* depths) {
  const FrameDraw d = drawFrames(int(scene.size()), config_, random_);
  return drawWithFrames(scene, sceneIndex, depths, d);
}

TrainingSample Sampler::drawWithFrames(const scene::Scene& scene, uint64_t sceneIndex,
                                       const std::vector<std::vector<float>>* depths,
                                       const FrameDraw& d) {
  TrainingSample s;
  s.sceneIndex = sceneIndex;
  s.sceneRoot = scene.root;
  s.sourceFrames = d.sources;
  s.targetFrames = d.targets;
  const int W = scene.width(), H = scene.height();
  const std::vector<double>& zooms = config_.zoomScales;
  if (zooms.size() > 1) // a single factor draws nothing (keeps older runs' random stream)
    s.zoom = zooms[size_t(random_.uniformInt(0, int64_t(zooms.size()) - 1))];
  else if (!zooms.empty())
    s.zoom = zooms[0];
  int cw = W, ch = H;
  if (config_.cropHeight > 0) {
    if (config_.cropHeight > H || config_.cropWidth > W)
      fail("sampler: crop ", config_.cropHeight, "x", config_.cropWidth, " (HxW) is larger than ",
           "scene ", scene.root, "'s images (", H, "x", W, ")");
    ch = config_.cropHeight;
    cw = config_.cropWidth;
    s.cropX = int(random_.uniformInt(0, W - cw));
    s.cropY = int(random_.uniformInt(0, H - ch));
  }
  auto take = [&](int frame, std::vector<io::Image>& images, std::vector<scene::Camera>& cameras) {
    const scene::SceneView& v = scene.views.at(size_t(frame));
    if (v.image.empty())
      fail("sampler: scene ", scene.root, " view ", v.name, " has no image loaded");
    const bool zoom = s.zoom != 1.0, crop = cw != W || ch != H;
    io::Image image = zoom ? zoomImage(v.image, s.zoom) : v.image;
    scene::Camera camera = zoom ? zoomCamera(v.camera, s.zoom) : v.camera;
    images.push_back(crop ? cropImage(image, s.cropX, s.cropY, cw, ch) : std::move(image));
    cameras.push_back(crop ? cropCamera(camera, s.cropX, s.cropY, cw, ch) : camera);
  };
  for (int f : s.sourceFrames)
    take(f, s.cleanSources, s.sourceCameras);
  for (int f : s.targetFrames)
    take(f, s.targets, s.targetCameras);
  if (config_.sharpenProbability > 0 && config_.sharpenMax > 0) {
    s.sharpen = drawSharpenAmount(config_, random_.state());
    if (s.sharpen > 0) {
      for (io::Image& image : s.cleanSources)
        unsharpMask(image, s.sharpen);
      for (io::Image& image : s.targets)
        unsharpMask(image, s.sharpen);
    }
  }
  if (depths) {
    if (depths->size() != scene.size())
      fail("sampler: scene ", scene.root, " has ", scene.size(), " views but ", depths->size(),
           " depth maps");
    for (int f : s.targetFrames)
      s.targetDepths.push_back(
          zoomCropDepth((*depths)[size_t(f)], W, H, s.zoom, s.cropX, s.cropY, cw, ch));
    for (int f : s.sourceFrames)
      s.sourceDepths.push_back(
          zoomCropDepth((*depths)[size_t(f)], W, H, s.zoom, s.cropX, s.cropY, cw, ch));
  }
  s.reference =
      scene::widenedCamera(scene::referenceCamera(s.sourceCameras), config_.referenceMargin);
  mixupSources(s, config_, random_);
  if (config_.sourceExposureStd > 0 || config_.sourceChannelStd > 0)
    jitterSourceGains(s, config_, random_.state());
  return s;
}

} // namespace simpli::training
