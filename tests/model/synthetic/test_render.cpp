// Exact ray casting: analytic depth, projection, occlusion, anti-aliasing, determinism
// (synthetic/renderer.h).
#include "simpli/model/synthetic/renderer.h"

#include "support/expect_error.h"
#include "synthetic_test_util.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include <algorithm>
#include <cmath>

using namespace simpli::synthetic;
using Eigen::Vector2d;
using Eigen::Vector3d;
using simpli::scene::Camera;
using simpli::test::flatTexture;
using simpli::test::frontoPlane;
using simpli::test::frontoRectangle;
using simpli::test::smallParams;

namespace {

Camera identityCamera(int w, int h, double fx = 0.9) {
  Camera c;
  c.fx = fx;
  c.fy = fx * w / h;
  c.width = w;
  c.height = h;
  return c;
}

// Signed area test: is p strictly inside the convex polygon (either orientation), by more than
// `margin` pixels from every edge?
int insideQuad(const std::vector<Vector2d>& q, const Vector2d& p, double margin) {
  int pos = 0, neg = 0;
  for (size_t i = 0; i < q.size(); ++i) {
    const Vector2d a = q[i], b = q[(i + 1) % q.size()];
    const Vector2d e = b - a;
    const double cross = (e.x() * (p.y() - a.y()) - e.y() * (p.x() - a.x())) / e.norm();
    if (std::abs(cross) <= margin)
      return -1; // too close to call
    (cross > 0 ? pos : neg)++;
  }
  return (pos == 0 || neg == 0) ? 1 : 0;
}

} // namespace

TEST(SyntheticRender, FrontoPlaneDepthIsExact) {
  // Cameras without rotation: a plane at world depth d is at camera depth d - C.z everywhere.
  SyntheticSceneParams p = smallParams(40, 24, 4);
  p.rotationDegrees = 0;
  const double d = 7.25;
  const SyntheticScene scene =
      makeSyntheticScene(p, frontoPlane(d, flatTexture(0.3, 0.6, 0.9)), {});
  for (int v = 0; v < 4; ++v) {
    const RenderedView view = renderView(scene, v);
    const double expected = d - scene.cameras[size_t(v)].centre().z();
    for (float z : view.depth)
      ASSERT_NEAR(z, expected, 1e-6 * expected);
    // Flat colour, two-sided Lambert: every pixel the same value.
    for (size_t i = 3; i < view.rgb.size(); ++i)
      ASSERT_EQ(view.rgb[i], view.rgb[i % 3]);
  }
  // And an identity camera sees exactly d.
  const RenderedView view = renderView(scene, identityCamera(16, 16), 1);
  for (float z : view.depth)
    EXPECT_EQ(z, float(d));
}

TEST(SyntheticRender, SphereDepthMatchesTheAnalyticSolution) {
  SyntheticSceneParams p = smallParams(33, 25, 1);
  Shape sphere;
  sphere.kind = ShapeKind::Sphere;
  sphere.role = ShapeRole::Sphere;
  sphere.centre = Vector3d(0.2, -0.1, 5.0);
  sphere.size = Vector3d::Constant(1.0);
  sphere.texture = flatTexture(1, 0, 0);
  const SyntheticScene scene =
      makeSyntheticScene(p, frontoPlane(20, flatTexture(0, 0, 1)), {sphere});

  // Odd size: the centre pixel's ray is the optical axis.
  Shape centred = sphere;
  centred.centre = Vector3d(0, 0, 5.0);
  const SyntheticScene axial =
      makeSyntheticScene(p, frontoPlane(20, flatTexture(0, 0, 1)), {centred});
  const RenderedView a = renderView(axial, identityCamera(33, 25), 3);
  EXPECT_NEAR(a.depthAt(16, 12), 4.0, 1e-6);

  // Every pixel: the nearer root of |t d - c|^2 = r^2 for d = ((u - cx)/fx, (v - cy)/fy, 1),
  // or the background's 20 where the ray misses.
  const Camera cam = identityCamera(33, 25);
  const RenderedView view = renderView(scene, cam, 3);
  int onSphere = 0;
  for (int y = 0; y < 25; ++y)
    for (int x = 0; x < 33; ++x) {
      const Vector3d d(((x + 0.5) / 33 - 0.5) / cam.fx, ((y + 0.5) / 25 - 0.5) / cam.fy, 1.0);
      const Vector3d c = sphere.centre;
      const double b = d.dot(c), aa = d.dot(d), disc = b * b - aa * (c.dot(c) - 1.0);
      const double expected = disc >= 0 ? (b - std::sqrt(disc)) / aa : 20.0;
      onSphere += disc >= 0;
      ASSERT_NEAR(view.depthAt(x, y), expected, 1e-6 * expected) << x << ", " << y;
    }
  EXPECT_GT(onSphere, 50);
}

TEST(SyntheticRender, ProjectedRectangleCornersFollowThePinholeModel) {
  // A rectangle seen by a translated and rotated camera: pixels whose centres lie inside the
  // quadrilateral of the projected corners (Camera::project) see the rectangle at the plane's
  // analytic depth, pixels outside see the background.
  SyntheticSceneParams p = smallParams(64, 48, 1);
  const Shape rect = frontoRectangle(Vector3d(0.3, -0.2, 4.0), 0.9, 0.6, flatTexture(1, 1, 0));
  const SyntheticScene scene = makeSyntheticScene(p, frontoPlane(12, flatTexture(0, 0, 1)), {rect});
  Camera cam = identityCamera(64, 48, 0.8);
  cam.R = (Eigen::AngleAxisd(0.04, Vector3d::UnitY()) *
           Eigen::AngleAxisd(-0.03, Vector3d::UnitX()) * Eigen::AngleAxisd(0.05, Vector3d::UnitZ()))
              .toRotationMatrix()
              .transpose();
  cam.t = -cam.R * Vector3d(0.15, 0.05, -0.2);

  std::vector<Vector2d> corners;
  for (const Vector2d& s : {Vector2d(-1, -1), Vector2d(1, -1), Vector2d(1, 1), Vector2d(-1, 1)}) {
    const Vector3d X = rect.centre + Vector3d(s.x() * 0.9, s.y() * 0.6, 0);
    const Vector2d uv = cam.project(X);
    corners.push_back(Vector2d(uv.x() * 64, uv.y() * 48)); // pixel-edge coordinates
  }
  // Plane z = 4 in camera coordinates: n . Xc = n . C' with n = R e_z.
  const Vector3d n = cam.R * Vector3d::UnitZ();
  const double offset = n.dot(cam.worldToCamera(rect.centre));
  const RenderedView view = renderView(scene, cam, 5);
  int inside = 0, outside = 0;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) {
      const int in = insideQuad(corners, Vector2d(x + 0.5, y + 0.5), 1e-6);
      if (in < 0)
        continue;
      const Vector3d d(((x + 0.5) / 64 - 0.5) / cam.fx, ((y + 0.5) / 48 - 0.5) / cam.fy, 1.0);
      if (in == 1) {
        ++inside;
        const double expected = offset / n.dot(d);
        ASSERT_NEAR(view.depthAt(x, y), expected, 1e-6 * expected) << x << ", " << y;
      } else {
        ++outside;
        ASSERT_GT(view.depthAt(x, y), 10.0) << x << ", " << y;
      }
    }
  EXPECT_GT(inside, 200);
  EXPECT_GT(outside, 200);
}

TEST(SyntheticRender, NearerObjectWinsWhateverTheOrder) {
  SyntheticSceneParams p = smallParams(32, 32, 1);
  const Shape nearRect = frontoRectangle(Vector3d(0.2, 0, 3.0), 0.5, 0.5, flatTexture(1, 0, 0));
  const Shape farRect = frontoRectangle(Vector3d(-0.2, 0, 6.0), 2.5, 2.5, flatTexture(0, 1, 0));
  const Shape bg = frontoPlane(15, flatTexture(0, 0, 1));
  const Camera cam = identityCamera(32, 32, 1.0);
  for (bool nearFirst : {true, false}) {
    const std::vector<Shape> objects =
        nearFirst ? std::vector<Shape>{nearRect, farRect} : std::vector<Shape>{farRect, nearRect};
    const RenderedView view = renderView(makeSyntheticScene(p, bg, objects), cam, 9);
    // Pixel (18, 16): u = 0.578, ray x = 0.078 per unit depth: inside both rectangles.
    EXPECT_NEAR(view.depthAt(18, 16), 3.0, 1e-6);
    const size_t i = (16 * 32 + 18) * 3;
    EXPECT_GT(view.rgb[i], 100);
    EXPECT_EQ(view.rgb[i + 1], 0);
    EXPECT_EQ(view.rgb[i + 2], 0);
    // Pixel (4, 16): ray x = -0.36 per unit: misses the near one, hits the far one.
    EXPECT_NEAR(view.depthAt(4, 16), 6.0, 1e-6);
    const size_t j = (16 * 32 + 4) * 3;
    EXPECT_EQ(view.rgb[j], 0);
    EXPECT_GT(view.rgb[j + 1], 100);
  }
  // castRay reports the index of the nearest shape.
  const SyntheticScene scene = makeSyntheticScene(p, bg, {farRect, nearRect});
  const SurfaceHit hit = castRay(scene, cameraRay(cam, 0.55, 0.5));
  EXPECT_EQ(hit.shape, 2);
  EXPECT_NEAR(hit.t, 3.0, 1e-12);
}

TEST(SyntheticRender, EdgesAreAntiAliased) {
  // A vertical edge between black and white through the middle of column 8's pixels.
  SyntheticSceneParams p = smallParams(16, 4, 1);
  const Shape white =
      frontoRectangle(Vector3d(-5.0 + 0.0625, 0, 2.0), 5.0, 5.0, flatTexture(1, 1, 1));
  const Camera cam = identityCamera(16, 4, 0.5); // ray x = (u - 0.5) / 0.5 per unit depth
  for (int aa : {1, 4}) {
    p.antialias = aa;
    const RenderedView view =
        renderView(makeSyntheticScene(p, frontoPlane(10, flatTexture(0, 0, 0)), {white}), cam, 4);
    // Column 8 spans u in [0.5, 0.5625]: x at depth 2 in [0, 0.25]; the edge at 0.0625 cuts it
    // at a quarter: exactly the first column of the 4 x 4 strata is white.
    const int v = view.rgb[(1 * 16 + 8) * 3];
    EXPECT_EQ(v, aa == 1 ? 0 : 64); // centre sample only: black; 4 of 16 samples white
    EXPECT_EQ(view.rgb[(1 * 16 + 7) * 3], 255);
    EXPECT_EQ(view.rgb[(1 * 16 + 9) * 3], 0);
  }
}

TEST(SyntheticRender, NothingHitIsMidGreyWithDepthZero) {
  SyntheticSceneParams p = smallParams(8, 8, 1);
  const SyntheticScene scene = makeSyntheticScene(p, frontoPlane(-3, flatTexture(1, 0, 0)), {});
  const RenderedView view = renderView(scene, identityCamera(8, 8), 2);
  for (float z : view.depth)
    EXPECT_EQ(z, 0.0f);
  for (uint8_t c : view.rgb)
    EXPECT_EQ(c, 128);
  simpli::test::expectError([&] { depthBounds(view); }, {"hits no surface"});
  const simpli::io::Image img = view.image();
  EXPECT_NEAR(img.at(0, 0, 0), 128.0 / 127.5 - 1.0, 1e-7);
}

TEST(SyntheticRender, SameSeedSameImagesWhateverTheThreads) {
  SyntheticSceneParams p;
  p.width = 48;
  p.height = 32;
  p.views = 2;
  p.seed = 21;
  p.antialias = 2;
  const SyntheticScene a = generateSyntheticScene(p);
  const SyntheticScene b = generateSyntheticScene(p);
  const int threads = cv::getNumThreads();
  const std::vector<RenderedView> va = renderViews(a);
  cv::setNumThreads(1);
  const std::vector<RenderedView> vb = renderViews(b);
  cv::setNumThreads(threads);
  for (size_t i = 0; i < va.size(); ++i) {
    EXPECT_EQ(va[i].rgb, vb[i].rgb);
    EXPECT_EQ(va[i].depth, vb[i].depth);
  }
  p.seed = 22;
  const std::vector<RenderedView> vc = renderViews(generateSyntheticScene(p));
  EXPECT_NE(va[0].rgb, vc[0].rgb);
  // The views differ (parallax), but not wildly.
  EXPECT_NE(va[0].rgb, va[1].rgb);
}

TEST(SyntheticRender, DepthBoundsEncloseTheDepths) {
  SyntheticSceneParams p = smallParams(16, 12, 1);
  const SyntheticScene scene =
      makeSyntheticScene(p, frontoPlane(10, flatTexture(0.5, 0.5, 0.5)),
                         {frontoRectangle(Vector3d(0, 0, 4), 0.5, 0.5, flatTexture(1, 1, 1))});
  const RenderedView view = renderView(scene, identityCamera(16, 12), 1);
  const DepthBounds b = depthBounds(view);
  EXPECT_NEAR(b.near, 0.9 * 4.0, 1e-6);
  EXPECT_NEAR(b.far, 1.1 * 10.0, 1e-5);
}

// The depth-only pass casts renderView's centre rays: the same depths, to the bit, no colour.
TEST(SyntheticRender, DepthOnlyIsTheRenderedDepth) {
  SyntheticSceneParams p = smallParams(40, 24, 3, 5);
  p.objects = 4;
  p.antialias = 2;
  const SyntheticScene scene = generateSyntheticScene(p);
  for (int i = 0; i < int(scene.cameras.size()); ++i) {
    const RenderedView full = renderView(scene, i), depth = renderDepth(scene, i);
    EXPECT_EQ(depth.width, full.width);
    EXPECT_EQ(depth.height, full.height);
    EXPECT_TRUE(depth.rgb.empty());
    EXPECT_EQ(depth.depth, full.depth) << "view " << i;
  }
  simpli::test::expectError([&] { renderDepth(scene, int(scene.cameras.size())); },
                            {"renderDepth", "out of range"});
}

// The per-tile shape lists (shapesThroughWindow) change no pixel: every view of a world scene,
// cast through all shapes pixel by pixel, gives the renderer's depth and (without
// antialiasing) its colour; and the lists do leave shapes out, or this would test nothing.
TEST(SyntheticRender, TileShapeListsChangeNoPixel) {
  SyntheticSceneParams p = smallParams(96, 64, 3, 17);
  p.style = SceneStyle::World;
  p.objects = 10;
  p.antialias = 1;
  const SyntheticScene scene = generateSyntheticScene(p);
  size_t listed = 0, windows = 0;
  for (int i = 0; i < int(scene.cameras.size()); ++i) {
    const Camera& camera = scene.cameras[size_t(i)];
    const RenderedView view = renderView(scene, i);
    for (int y = 0; y < camera.height; ++y)
      for (int x = 0; x < camera.width; ++x) {
        const Ray ray = cameraRay(camera, (x + 0.5) / camera.width, (y + 0.5) / camera.height);
        const SurfaceHit hit = castRay(scene, ray);
        ASSERT_EQ(view.depthAt(x, y), hit.hit() ? float(hit.t) : 0.0f) << i << " " << x << " " << y;
        const Vector3d rgb = hit.hit() ? shadeHit(scene, hit) : missColour(scene, ray);
        for (int c = 0; c < 3; ++c)
          ASSERT_EQ(int(view.rgb[(size_t(y) * size_t(camera.width) + size_t(x)) * 3 + size_t(c)]),
                    int(std::round(std::clamp(rgb[c], 0.0, 1.0) * 255)))
              << i << " " << x << " " << y;
      }
    for (int k = 0; k < 6; ++k) { // windows of 8 x 8 pixels along the diagonal
      const double u0 = k / 6.0, v0 = k / 6.0, du = 8.0 / camera.width, dv = 8.0 / camera.height;
      listed += shapesThroughWindow(scene, camera, u0, u0 + du, v0, v0 + dv).size();
      ++windows;
    }
  }
  EXPECT_LT(double(listed) / double(windows), 0.7 * scene.shapeCount())
      << "the lists keep most shapes: nothing is culled";
  EXPECT_EQ(shapesThroughWindow(scene, scene.cameras[0], 0, 1, 0, 1).front(), 0);
  simpli::test::expectError([&] { shapesThroughWindow(scene, scene.cameras[0], 0.5, 0.4, 0, 1); },
                            {"shapesThroughWindow", "empty window", "0.5"});
}
