// Procedural textures and exact ray-primitive intersections (synthetic/texture.h, shapes.h).
#include "simpli/model/synthetic/shapes.h"

#include "support/expect_error.h"
#include "synthetic_test_util.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>

using namespace simpli::synthetic;
using Eigen::Vector2d;
using Eigen::Vector3d;

namespace {

Texture twoColour(Pattern pattern, double frequency) {
  Texture t;
  t.pattern = pattern;
  t.colourA = Vector3d(0.1, 0.2, 0.3);
  t.colourB = Vector3d(0.9, 0.8, 0.7);
  t.frequency = frequency;
  t.angle = 0;
  t.detail = 0;
  return t;
}

} // namespace

TEST(SyntheticTexture, PatternsAtKnownPoints) {
  const double f = 2.0; // cycles per unit
  const Texture checker = twoColour(Pattern::Checker, f);
  EXPECT_TRUE(checker.evaluate(Vector2d(0.25 / f, 0.25 / f)).isApprox(checker.colourA));
  EXPECT_TRUE(checker.evaluate(Vector2d(1.25 / f, 0.25 / f)).isApprox(checker.colourB));
  EXPECT_TRUE(checker.evaluate(Vector2d(1.25 / f, 1.25 / f)).isApprox(checker.colourA));
  EXPECT_TRUE(checker.evaluate(Vector2d(-0.25 / f, 0.25 / f)).isApprox(checker.colourB));

  const Texture stripes = twoColour(Pattern::Stripes, f);
  EXPECT_TRUE(stripes.evaluate(Vector2d(0.25 / f, 3.0)).isApprox(stripes.colourB));  // sin = 1
  EXPECT_TRUE(stripes.evaluate(Vector2d(0.75 / f, -1.0)).isApprox(stripes.colourA)); // sin = -1

  Texture gradient = twoColour(Pattern::Gradient, f);
  EXPECT_TRUE(gradient.evaluate(Vector2d(0, 0)).isApprox(gradient.colourB));
  EXPECT_TRUE(gradient.evaluate(Vector2d(2.0 / f, 0)).isApprox(gradient.colourA));
  // Rotating the pattern by 90 degrees swaps the roles of s and t.
  gradient.angle = M_PI / 2;
  EXPECT_TRUE(gradient.evaluate(Vector2d(5.0, 2.0 / f)).isApprox(gradient.colourA, 1e-9));
}

TEST(SyntheticTexture, ValuesInRangeDeterministicAndTextured) {
  simpli::synthetic::Random rng(11);
  for (int k = 0; k < 40; ++k) {
    const Texture t = randomTexture(rng, 0.01);
    double lo = 1, hi = 0;
    for (int i = 0; i < 200; ++i) {
      const Vector2d st(0.013 * i, 0.007 * i - 0.5);
      const Vector3d c = t.evaluate(st);
      EXPECT_TRUE(c.minCoeff() >= 0.0 && c.maxCoeff() <= 1.0) << c.transpose();
      EXPECT_EQ(c, t.evaluate(st));
      lo = std::min(lo, c.sum());
      hi = std::max(hi, c.sum());
    }
    EXPECT_GT(hi - lo, 0.05) << "texture " << k << " (" << toString(t.pattern) << ") is flat";
    // Features 8 .. 40 pixels of 0.01 units: one cycle spans two features.
    EXPECT_GE(t.frequency, 1.0 / (2 * 40 * 0.01) - 1e-9);
    EXPECT_LE(t.frequency, 1.0 / (2 * 8 * 0.01) + 1e-9);
  }
}

TEST(SyntheticTexture, ValueNoiseInterpolatesLatticeContinuously) {
  for (int i = 0; i < 200; ++i) {
    const double x = -3.7 + 0.0731 * i, y = 1.3 - 0.047 * i;
    const double v = valueNoise(x, y, 5);
    EXPECT_GE(v, 0.0);
    EXPECT_LE(v, 1.0);
    EXPECT_NEAR(valueNoise(x + 1e-7, y, 5), v, 1e-5); // continuous
    const double fr = fractalNoise(x, y, 5, 4);
    EXPECT_GE(fr, 0.0);
    EXPECT_LE(fr, 1.0);
  }
  // Continuity across a lattice line.
  EXPECT_NEAR(valueNoise(2.0 - 1e-9, 0.3, 9), valueNoise(2.0, 0.3, 9), 1e-7);
  EXPECT_NE(valueNoise(0.5, 0.5, 1), valueNoise(0.5, 0.5, 2));
}

TEST(SyntheticTexture, HsvToRgb) {
  EXPECT_TRUE(hsvToRgb(0.0, 1.0, 1.0).isApprox(Vector3d(1, 0, 0)));
  EXPECT_TRUE(hsvToRgb(1.0 / 3.0, 1.0, 1.0).isApprox(Vector3d(0, 1, 0)));
  EXPECT_TRUE(hsvToRgb(2.0 / 3.0, 1.0, 0.5).isApprox(Vector3d(0, 0, 0.5)));
  EXPECT_TRUE(hsvToRgb(0.3, 0.0, 0.4).isApprox(Vector3d(0.4, 0.4, 0.4)));
}

TEST(SyntheticShapes, FrameFromAxisIsRightHandedOrthonormal) {
  const Vector3d axis = Vector3d(0.1, 1.0, -0.2).normalized();
  const Eigen::Matrix3d m = frameFromAxis(axis, Vector3d::UnitZ());
  EXPECT_LT((m.transpose() * m - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_NEAR(m.determinant(), 1.0, 1e-12);
  EXPECT_TRUE(m.col(2).isApprox(axis));
  EXPECT_GT(m.col(1).z(), 0.9);
  simpli::test::expectError([] { frameFromAxis(Vector3d::UnitZ(), Vector3d(0, 0, 2)); },
                            {"parallel"});
}

TEST(SyntheticShapes, RectangleHitsInsideOnly) {
  const Shape r = simpli::test::frontoRectangle(Vector3d(1, 0, 5), 0.5, 0.25, {});
  SurfaceHit hit;
  Ray ray{Vector3d::Zero(), Vector3d(0.2, 0.04, 1.0)}; // reaches (1, 0.2, 5)
  ASSERT_TRUE(r.intersect(ray, 1e-9, hit));
  EXPECT_DOUBLE_EQ(hit.t, 5.0);
  EXPECT_TRUE(hit.st.isApprox(Vector2d(0.0, 0.2)));
  EXPECT_TRUE(hit.normal.isApprox(Vector3d::UnitZ()));
  SurfaceHit miss;
  EXPECT_FALSE(r.intersect({Vector3d::Zero(), Vector3d(0.2, 0.06, 1.0)}, 1e-9, miss)); // y = 0.3
  EXPECT_FALSE(r.intersect({Vector3d::Zero(), Vector3d(0.2, 0.0, -1.0)}, 1e-9, miss)); // behind
  EXPECT_FALSE(miss.hit());
  // A nearer hit already recorded is kept.
  SurfaceHit nearer;
  nearer.t = 4.0;
  EXPECT_FALSE(r.intersect(ray, 1e-9, nearer));
  EXPECT_EQ(nearer.t, 4.0);
}

TEST(SyntheticShapes, LeafHitsBetweenItsParabolas) {
  // Half length 2, half width 0.5 at depth 5, turned 90 degrees in its plane: its long axis is
  // the image's y. Edge: |x| <= 0.5 (1 - (y / 2)^2) in camera coordinates.
  Shape leaf;
  leaf.kind = ShapeKind::Leaf;
  leaf.centre = Vector3d(0, 0, 5);
  leaf.axes = Eigen::AngleAxisd(M_PI / 2, Vector3d::UnitZ()).toRotationMatrix();
  leaf.size = Vector3d(2, 0.5, 0);
  auto hits = [&](double x, double y) {
    SurfaceHit h;
    return leaf.intersect({Vector3d::Zero(), Vector3d(x / 5, y / 5, 1)}, 1e-9, h);
  };
  SurfaceHit hit;
  ASSERT_TRUE(leaf.intersect({Vector3d::Zero(), Vector3d(0.02, 0.1, 1)}, 1e-9, hit));
  EXPECT_DOUBLE_EQ(hit.t, 5.0);
  EXPECT_TRUE(hit.st.isApprox(Vector2d(0.5, -0.1))); // local x along the image's y
  // At y = 1 the edge is at |x| = 0.375; at the tips (|y| = 2) the width is zero.
  EXPECT_TRUE(hits(0.37, 1.0));
  EXPECT_TRUE(hits(-0.37, -1.0));
  EXPECT_FALSE(hits(0.38, 1.0));
  EXPECT_FALSE(hits(-0.38, -1.0));
  EXPECT_TRUE(hits(0.0, 1.99));
  EXPECT_FALSE(hits(0.0, 2.01));
  EXPECT_FALSE(hits(0.05, 1.99));
  // The rectangle of the same size would hold (0.45, 1): the leaf does not.
  EXPECT_FALSE(hits(0.45, 1.0));
  EXPECT_EQ(leaf.boundingRadius(), 2.0);
  // Its support across the long axis is its half width, along it the half length.
  EXPECT_NEAR(leaf.extent(Vector3d::UnitX()), 0.5, 1e-12);
  EXPECT_NEAR(leaf.extent(-Vector3d::UnitY()), 2.0, 1e-12);
  EXPECT_NEAR(leaf.extent(Vector3d::UnitZ()), 0.0, 1e-12);
}

TEST(SyntheticShapes, SphereBoxCylinderAnalyticHits) {
  Shape sphere;
  sphere.kind = ShapeKind::Sphere;
  sphere.centre = Vector3d(0, 0, 10);
  sphere.size = Vector3d::Constant(2.0);
  SurfaceHit hit;
  ASSERT_TRUE(sphere.intersect({Vector3d::Zero(), Vector3d::UnitZ()}, 1e-9, hit));
  EXPECT_DOUBLE_EQ(hit.t, 8.0);
  EXPECT_TRUE(hit.normal.isApprox(-Vector3d::UnitZ()));
  SurfaceHit miss;
  EXPECT_FALSE(sphere.intersect({Vector3d(2.001, 0, 0), Vector3d::UnitZ()}, 1e-9, miss));
  // Oblique ray: solve |t d - c|^2 = r^2 by hand.
  const Vector3d d(0.1, -0.05, 1.0);
  const Vector3d c = sphere.centre;
  const double b = d.dot(c), a = d.dot(d);
  const double tExpected = (b - std::sqrt(b * b - a * (c.dot(c) - 4.0))) / a;
  SurfaceHit h2;
  ASSERT_TRUE(sphere.intersect({Vector3d::Zero(), d}, 1e-9, h2));
  EXPECT_NEAR(h2.t, tExpected, 1e-12);

  Shape box;
  box.kind = ShapeKind::Box;
  box.centre = Vector3d(0, 0, 10);
  box.size = Vector3d(1, 1, 1);
  SurfaceHit hb;
  ASSERT_TRUE(box.intersect({Vector3d::Zero(), Vector3d::UnitZ()}, 1e-9, hb));
  EXPECT_DOUBLE_EQ(hb.t, 9.0);
  EXPECT_TRUE(hb.normal.isApprox(-Vector3d::UnitZ()));
  // Turned 45 degrees about y: the front edge is sqrt(2) in front of the centre.
  box.axes = Eigen::AngleAxisd(M_PI / 4, Vector3d::UnitY()).toRotationMatrix();
  SurfaceHit hr;
  ASSERT_TRUE(box.intersect({Vector3d(0, 0.5, 0), Vector3d::UnitZ()}, 1e-9, hr));
  EXPECT_NEAR(hr.t, 10.0 - std::sqrt(2.0), 1e-12);

  Shape pole;
  pole.kind = ShapeKind::Cylinder;
  pole.centre = Vector3d(0, 0, 6);
  pole.axes = frameFromAxis(Vector3d::UnitY(), Vector3d::UnitZ());
  pole.size = Vector3d(0.5, 0, 3.0);
  SurfaceHit hp;
  ASSERT_TRUE(pole.intersect({Vector3d::Zero(), Vector3d::UnitZ()}, 1e-9, hp));
  EXPECT_DOUBLE_EQ(hp.t, 5.5);
  EXPECT_TRUE(hp.normal.isApprox(-Vector3d::UnitZ()));
  SurfaceHit above;
  EXPECT_FALSE(pole.intersect({Vector3d(0, -3.01, 0), Vector3d::UnitZ()}, 1e-9, above));
  // Down the axis from above: the cap at y = -3.
  SurfaceHit cap;
  ASSERT_TRUE(pole.intersect({Vector3d(0.1, -10, 6), Vector3d::UnitY()}, 1e-9, cap));
  EXPECT_DOUBLE_EQ(cap.t, 7.0);
  EXPECT_TRUE(cap.normal.isApprox(-Vector3d::UnitY()));
}

TEST(SyntheticShapes, ExtentIsTheSupportFunction) {
  simpli::synthetic::Random rng(3);
  for (int k = 0; k < 25; ++k) {
    Shape s;
    s.kind = ShapeKind(1 + k % 5); // rectangle, box, sphere, cylinder, leaf
    s.centre = Vector3d(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(3, 5));
    s.axes = (Eigen::AngleAxisd(rng.uniform(0, 3), Vector3d::UnitY()) *
              Eigen::AngleAxisd(rng.uniform(0, 3), Vector3d::UnitX()))
                 .toRotationMatrix();
    s.size = Vector3d(rng.uniform(0.1, 1), rng.uniform(0.1, 1), rng.uniform(0.1, 1));
    if (s.kind == ShapeKind::Sphere)
      s.size = Vector3d::Constant(s.size.x());
    const Vector3d dir = Vector3d(rng.normal(), rng.normal(), rng.normal()).normalized();
    // Brute force: rays from far along dir towards the centre, offset across; the largest
    // dir-coordinate of the hits approaches the support value from below. A flat shape seen
    // edge-on along dir shows a sliver those rays can miss: it is scanned along its normal.
    const bool flat = s.kind == ShapeKind::Rectangle || s.kind == ShapeKind::Leaf;
    const Vector3d view = flat ? Vector3d(s.axes.col(2)) : dir;
    const Eigen::Matrix3d frame = frameFromAxis(
        -view, view.cross(Vector3d::UnitX()).norm() > 0.1 ? Vector3d::UnitX() : Vector3d::UnitY());
    double best = -1e9;
    const int n = 120;
    for (int i = 0; i <= n; ++i)
      for (int j = 0; j <= n; ++j) {
        const double a = 2.0 * (i - n / 2) / n * 2.0, b = 2.0 * (j - n / 2) / n * 2.0;
        Ray ray{s.centre + 10.0 * view + a * frame.col(0) + b * frame.col(1), -view};
        SurfaceHit h;
        if (s.intersect(ray, 1e-9, h))
          best = std::max(best, dir.dot(ray.origin + h.t * ray.direction - s.centre));
      }
    const double e = s.extent(dir);
    EXPECT_LE(best, e + 1e-9) << toString(s.kind);
    EXPECT_GT(best, e - 0.06) << toString(s.kind);
    EXPECT_LE(e, s.boundingRadius() + 1e-12);
  }
}
