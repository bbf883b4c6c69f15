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

Eigen::Vector3d shadeHit(const SyntheticScene& scene, const SurfaceHit& hit) {
  const Shape& s = scene.shape(hit.shape);
  double lambert = hit.normal.dot(scene.lightDirection);
  const bool twoSided = s.kind == ShapeKind::Plane || s.kind == ShapeKind::Rectangle;
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

  // Rows are independent and every sample position is a function of (seed, pixel, sample),
  // so the result does not depend on how the rows are split over threads.
  cv::parallel_for_(cv::Range(0, h), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y) {
      for (int x = 0; x < w; ++x) {
        const size_t pixel = size_t(y) * size_t(w) + size_t(x);
        const Ray centreRay = cameraRay(camera, (x + 0.5) / w, (y + 0.5) / h);
        const SurfaceHit centre = castRay(scene, centreRay);
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
            const SurfaceHit hit = castRay(scene, ray);
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
  // The centre rays of renderView, so the depths are the same to the bit.
  cv::parallel_for_(cv::Range(0, h), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y)
      for (int x = 0; x < w; ++x) {
        const SurfaceHit centre = castRay(scene, cameraRay(camera, (x + 0.5) / w, (y + 0.5) / h));
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
