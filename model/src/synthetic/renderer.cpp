// CPU ray casting of synthetic scenes (see synthetic/renderer.h).
#include "simpli/model/synthetic/renderer.h"

#include "simpli/error.h"

#include <opencv2/core.hpp>

#include <algorithm>
#include <cmath>

namespace simpli::synthetic {

namespace {

// Rays start at the camera centre; anything nearer than this is ignored.
constexpr double kMinT = 1e-9;
// Stream of the jitter seeds (the generator uses 2 .. 6).
constexpr uint64_t kJitterStream = 7;

uint8_t quantise(double v) {
  const double q = std::round(std::min(1.0, std::max(0.0, v)) * 255.0);
  return uint8_t(q);
}

} // namespace

io::Image RenderedView::image() const {
  io::Image img(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c) {
        const uint8_t q = rgb[(size_t(y) * size_t(width) + size_t(x)) * 3 + size_t(c)];
        // As readImage: x / 127.5 - 1 in double, rounded once to float.
        img.at(c, y, x) = float(double(q) * (1.0 / 127.5) - 1.0);
      }
  return img;
}

Ray cameraRay(const scene::Camera& camera, double u, double v) {
  Ray ray;
  ray.origin = camera.centre();
  ray.direction = camera.R.transpose() *
                  Eigen::Vector3d((u - camera.cx) / camera.fx, (v - camera.cy) / camera.fy, 1.0);
  return ray;
}

SurfaceHit castRay(const SyntheticScene& scene, const Ray& ray) {
  SurfaceHit hit;
  const int n = scene.shapeCount();
  for (int i = 0; i < n; ++i)
    if (scene.shape(i).intersect(ray, kMinT, hit))
      hit.shape = i;
  return hit;
}

SurfaceHit castRay(const SyntheticScene& scene, const Ray& ray, const std::vector<int>& shapes) {
  SurfaceHit hit;
  for (int i : shapes)
    if (scene.shape(i).intersect(ray, kMinT, hit))
      hit.shape = i;
  return hit;
}

std::vector<int> shapesThroughWindow(const SyntheticScene& scene, const scene::Camera& camera,
                                     double u0, double u1, double v0, double v1) {
  if (!(u0 <= u1 && v0 <= v1))
    fail("shapesThroughWindow: empty window u [", u0, ", ", u1, "] x v [", v0, ", ", v1, "]");
  // Camera-space inward normals of the planes through the centre that hold the rays of the
  // window's edges (a ray's direction is ((u - cx) / fx, (v - cy) / fy, 1)).
  const double l = (u0 - camera.cx) / camera.fx, r = (u1 - camera.cx) / camera.fx;
  const double t = (v0 - camera.cy) / camera.fy, b = (v1 - camera.cy) / camera.fy;
  const Eigen::Vector3d inward[4] = {{1, 0, -l}, {-1, 0, r}, {0, 1, -t}, {0, -1, b}};
  const Eigen::Vector3d origin = camera.centre();
  std::vector<int> kept;
  for (int i = 0; i < scene.shapeCount(); ++i) {
    const Shape& s = scene.shape(i);
    const Eigen::Vector3d offset = s.centre - origin;
    // A margin far above rounding, far below any shape's size: it only keeps a few more.
    const double margin = 1e-7 * (1 + offset.norm());
    bool outside = false;
    for (const Eigen::Vector3d& n : inward) {
      const Eigen::Vector3d world = (camera.R.transpose() * n).normalized();
      outside = outside || world.dot(offset) + s.extent(world) < -margin;
    }
    if (!outside)
      kept.push_back(i);
  }
  return kept;
}

Eigen::Vector3d shadeHit(const SyntheticScene& scene, const SurfaceHit& hit) {
  const Shape& s = scene.shape(hit.shape);
  double lambert = hit.normal.dot(scene.lightDirection);
  const bool twoSided =
      s.kind == ShapeKind::Plane || s.kind == ShapeKind::Rectangle || s.kind == ShapeKind::Leaf;
  lambert = twoSided ? std::abs(lambert) : std::max(0.0, lambert);
  return s.texture.evaluate(hit.st) * (0.55 + 0.45 * lambert);
}

Eigen::Vector3d missColour(const SyntheticScene& scene, const Ray& ray) {
  if (!scene.hasSky)
    return Eigen::Vector3d(0.5, 0.5, 0.5);
  const Eigen::Vector3d& d = ray.direction;
  const double azimuth = std::atan2(d.x(), d.z());
  const double elevation = std::atan2(-d.y(), std::hypot(d.x(), d.z()));
  return scene.sky.evaluate(Eigen::Vector2d(azimuth, elevation));
}

namespace {

// The shapes each kTile x kTile block of pixels can see (shapesThroughWindow): most rays test
// a few of the scene's shapes instead of all of them.
constexpr int kTile = 16;

class TileShapes {
public:
  TileShapes(const SyntheticScene& scene, const scene::Camera& camera)
      : columns_((camera.width + kTile - 1) / kTile) {
    const int rows = (camera.height + kTile - 1) / kTile;
    const double w = camera.width, h = camera.height;
    for (int ty = 0; ty < rows; ++ty)
      for (int tx = 0; tx < columns_; ++tx)
        lists_.push_back(shapesThroughWindow(
            scene, camera, tx * kTile / w, std::min(w, double((tx + 1) * kTile)) / w,
            ty * kTile / h, std::min(h, double((ty + 1) * kTile)) / h));
  }
  const std::vector<int>& at(int x, int y) const {
    return lists_[size_t(y / kTile) * size_t(columns_) + size_t(x / kTile)];
  }

private:
  int columns_;
  std::vector<std::vector<int>> lists_;
};

} // namespace

RenderedView renderView(const SyntheticScene& scene, const scene::Camera& camera,
                        uint64_t jitterSeed) {
  const int w = camera.width, h = camera.height;
  if (w <= 0 || h <= 0)
    fail("renderView: camera image size ", w, " x ", h, " is not positive");
  const int aa = std::max(1, scene.params.antialias);
  RenderedView view;
  view.width = w;
  view.height = h;
  view.rgb.assign(size_t(w) * size_t(h) * 3, 0);
  view.depth.assign(size_t(w) * size_t(h), 0.0f);
  const TileShapes tiles(scene, camera);

  // Rows are independent and every sample position is a function of (seed, pixel, sample),
  // so the result does not depend on how the rows are split over threads.
  cv::parallel_for_(cv::Range(0, h), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y) {
      for (int x = 0; x < w; ++x) {
        const size_t pixel = size_t(y) * size_t(w) + size_t(x);
        const std::vector<int>& shapes = tiles.at(x, y);
        const Ray centreRay = cameraRay(camera, (x + 0.5) / w, (y + 0.5) / h);
        const SurfaceHit centre = castRay(scene, centreRay, shapes);
        view.depth[pixel] = centre.hit() ? float(centre.t) : 0.0f;

        Eigen::Vector3d sum = Eigen::Vector3d::Zero();
        if (aa == 1) {
          sum = centre.hit() ? shadeHit(scene, centre) : missColour(scene, centreRay);
        } else {
          const uint64_t pixelSeed = deriveSeed(jitterSeed, pixel);
          for (int k = 0; k < aa * aa; ++k) {
            const uint64_t bits = mix64(pixelSeed + uint64_t(k));
            const double jx = unitFromBits(bits), jy = unitFromBits(mix64(bits));
            const double sx = ((k % aa) + jx) / aa, sy = ((k / aa) + jy) / aa;
            const Ray ray = cameraRay(camera, (x + sx) / w, (y + sy) / h);
            const SurfaceHit hit = castRay(scene, ray, shapes);
            sum += hit.hit() ? shadeHit(scene, hit) : missColour(scene, ray);
          }
          sum /= double(aa * aa);
        }
        for (int c = 0; c < 3; ++c)
          view.rgb[pixel * 3 + size_t(c)] = quantise(sum[c]);
      }
    }
  });
  return view;
}

namespace {

void checkViewIndex(const SyntheticScene& scene, int index, const char* what) {
  if (index < 0 || index >= int(scene.cameras.size()))
    fail(what, ": view ", index, " out of range (the scene has ", scene.cameras.size(),
         " cameras)");
}

} // namespace

RenderedView renderDepth(const SyntheticScene& scene, int index) {
  checkViewIndex(scene, index, "renderDepth");
  const scene::Camera& camera = scene.cameras[size_t(index)];
  const int w = camera.width, h = camera.height;
  if (w <= 0 || h <= 0)
    fail("renderDepth: camera image size ", w, " x ", h, " is not positive");
  RenderedView view;
  view.width = w;
  view.height = h;
  view.depth.assign(size_t(w) * size_t(h), 0.0f);
  const TileShapes tiles(scene, camera);
  // The centre rays of renderView, so the depths are the same to the bit.
  cv::parallel_for_(cv::Range(0, h), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y)
      for (int x = 0; x < w; ++x) {
        const Ray ray = cameraRay(camera, (x + 0.5) / w, (y + 0.5) / h);
        const SurfaceHit centre = castRay(scene, ray, tiles.at(x, y));
        view.depth[size_t(y) * size_t(w) + size_t(x)] = centre.hit() ? float(centre.t) : 0.0f;
      }
  });
  return view;
}

RenderedView renderView(const SyntheticScene& scene, int index) {
  checkViewIndex(scene, index, "renderView");
  return renderView(scene, scene.cameras[size_t(index)],
                    deriveSeed(deriveSeed(scene.params.seed, kJitterStream), uint64_t(index)));
}

std::vector<RenderedView> renderViews(const SyntheticScene& scene) {
  std::vector<RenderedView> views;
  for (int i = 0; i < int(scene.cameras.size()); ++i)
    views.push_back(renderView(scene, i));
  return views;
}

DepthBounds depthBounds(const RenderedView& view) {
  double lo = std::numeric_limits<double>::infinity(), hi = 0;
  for (float d : view.depth)
    if (d > 0) {
      lo = std::min(lo, double(d));
      hi = std::max(hi, double(d));
    }
  if (!(hi > 0))
    fail("depthBounds: the view hits no surface, so it has no depth bounds");
  return {0.9 * lo, 1.1 * hi};
}

} // namespace simpli::synthetic
