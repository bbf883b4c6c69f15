// Sampler: distinct frames inside the window, V / N ranges, reproducibility, crop intrinsics,
// MixUp; the random generator's state round trip.
#include "support/cameras.h"
#include "support/expect_error.h"

#include "simpli/model/scene/reference_camera.h"
#include "simpli/model/training/sampler.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

namespace simpli::training {
namespace {

scene::Scene fakeScene(int frames, int W = 32, int H = 16) {
  scene::Scene s;
  s.root = "fake";
  for (int i = 0; i < frames; ++i) {
    scene::SceneView v;
    v.name = std::to_string(i);
    v.camera = test::pinholeCamera(W, H, 0.9, 1.7, 0.48, 0.53);
    v.camera.t = Eigen::Vector3d(0.01 * i, -0.02 * i, 0.005 * i);
    v.image = io::Image(W, H);
    for (size_t k = 0; k < v.image.data.size(); ++k)
      v.image.data[k] = float(i) / frames - 0.5f + 1e-4f * float(k % 97);
    s.views.push_back(std::move(v));
  }
  return s;
}

TEST(TrainRandom, StateRoundTripAndDeterminism) {
  TrainRandom a(42), b(42), c(43);
  EXPECT_EQ(a.bits(), b.bits());
  EXPECT_NE(a.bits(), c.bits());
  const std::string text = a.stateString();
  TrainRandom d(0);
  d.setState(TrainRandom::parseState(text, "test"));
  for (int i = 0; i < 100; ++i)
    EXPECT_EQ(a.bits(), d.bits());
  for (int i = 0; i < 1000; ++i) {
    const int64_t v = a.uniformInt(-3, 5);
    EXPECT_GE(v, -3);
    EXPECT_LE(v, 5);
    const double u = a.uniform();
    EXPECT_GE(u, 0.0);
    EXPECT_LT(u, 1.0);
  }
  test::expectError([] { TrainRandom::parseState("12:34", "ckpt/state.json"); },
                    {"ckpt/state.json", "12:34", "four 16-digit hex words"});
  test::expectError(
      [] {
        TrainRandom::parseState(std::string(16, '0') + ":" + std::string(16, '0') + ":" +
                                    std::string(16, '0') + ":" + std::string(16, '0'),
                                "s");
      },
      {"all zero"});
}

TEST(TrainSampler, FramesDistinctInsideWindowAndRanges) {
  SamplingConfig c;
  c.minViews = 2;
  c.maxViews = 8;
  c.novelViews = 4;
  c.window = 7;
  TrainRandom r(1);
  std::set<int> seenV;
  for (int it = 0; it < 500; ++it) {
    const FrameDraw d = drawFrames(12, c, r);
    const int V = int(d.sources.size()), N = int(d.targets.size());
    seenV.insert(V);
    EXPECT_GE(V, 2);
    EXPECT_LE(V, 8);
    EXPECT_EQ(N, std::min(4, 12 - V));
    EXPECT_EQ(d.windowLength, std::min(12, std::max(7, V + N)));
    std::set<int> all(d.sources.begin(), d.sources.end());
    all.insert(d.targets.begin(), d.targets.end());
    EXPECT_EQ(int(all.size()), V + N) << "frames not distinct";
    for (int f : all) {
      EXPECT_GE(f, d.windowStart);
      EXPECT_LT(f, d.windowStart + d.windowLength);
    }
  }
  EXPECT_EQ(seenV.size(), 7u) << "every V in 2..8 should occur";
  // A 3-frame scene: V clipped to 2, one target.
  for (int it = 0; it < 50; ++it) {
    const FrameDraw d = drawFrames(3, c, r);
    EXPECT_EQ(d.sources.size(), 2u);
    EXPECT_EQ(d.targets.size(), 1u);
  }
  test::expectError([&] { drawFrames(1, c, r); }, {"at least 2 frames", "got 1"});
}

TEST(TrainSampler, ReproducibleWithSeedAndResumableState) {
  SamplingConfig c;
  c.cropHeight = 16;
  c.cropWidth = 16;
  const scene::Scene scene = fakeScene(10);
  Sampler a(c, 7), b(c, 7), other(c, 8);
  bool differs = false;
  for (int i = 0; i < 20; ++i) {
    const TrainingSample sa = a.drawFromScene(scene, 0), sb = b.drawFromScene(scene, 0);
    const TrainingSample so = other.drawFromScene(scene, 0);
    EXPECT_EQ(sa.sourceFrames, sb.sourceFrames);
    EXPECT_EQ(sa.targetFrames, sb.targetFrames);
    EXPECT_EQ(sa.cropX, sb.cropX);
    EXPECT_EQ(sa.mixupLambda, sb.mixupLambda);
    EXPECT_EQ(sa.sources[0].data, sb.sources[0].data);
    differs |= sa.sourceFrames != so.sourceFrames || sa.cropX != so.cropX;
  }
  EXPECT_TRUE(differs) << "another seed should give other samples";
  // Restoring the state continues the same sequence.
  Sampler c2(c, 99);
  c2.random().setState(a.random().state());
  for (int i = 0; i < 5; ++i)
    EXPECT_EQ(a.drawFromScene(scene, 0).sourceFrames, c2.drawFromScene(scene, 0).sourceFrames);
}

// The jump (2^128 draws ahead) is a GF(2)-linear map of the state that commutes with a draw;
// the sample streams of data-parallel training are one seed's state jumped 0, 1, 2, ... times.
TEST(TrainSampler, RandomJumpIsLinearAndCommutesWithDraws) {
  TrainRandom a(5), b(6);
  const TrainRandom::State sa = a.state(), sb = b.state();
  TrainRandom x(0);
  x.setState({sa[0] ^ sb[0], sa[1] ^ sb[1], sa[2] ^ sb[2], sa[3] ^ sb[3]});
  a.jump();
  b.jump();
  x.jump();
  for (size_t i = 0; i < 4; ++i)
    EXPECT_EQ(x.state()[i], a.state()[i] ^ b.state()[i]) << "word " << i;
  TrainRandom drawFirst(9), jumpFirst(9);
  drawFirst.bits();
  drawFirst.jump();
  jumpFirst.jump();
  jumpFirst.bits();
  EXPECT_EQ(drawFirst.state(), jumpFirst.state());
  TrainRandom plain(9);
  EXPECT_NE(plain.state(), jumpFirst.state());
}

TEST(TrainSampler, CropIntrinsicsAnalytic) {
  scene::Camera cam = test::pinholeCamera(192, 128, 0.8, 1.2, 0.51, 0.47);
  const scene::Camera c = cropCamera(cam, 40, 24, 64, 48);
  EXPECT_EQ(c.width, 64);
  EXPECT_EQ(c.height, 48);
  EXPECT_DOUBLE_EQ(c.fx, 0.8 * 192 / 64);
  EXPECT_DOUBLE_EQ(c.fy, 1.2 * 128 / 48);
  EXPECT_DOUBLE_EQ(c.cx, (0.51 * 192 - 40) / 64);
  EXPECT_DOUBLE_EQ(c.cy, (0.47 * 128 - 24) / 48);
  // A world point projects to the same pixel, shifted by the crop origin.
  cam.R = Eigen::AngleAxisd(0.1, Eigen::Vector3d(0.3, 1, 0.2).normalized()).toRotationMatrix();
  cam.t = Eigen::Vector3d(0.1, -0.2, 0.3);
  const scene::Camera c2 = cropCamera(cam, 40, 24, 64, 48);
  const Eigen::Vector3d X(0.4, -0.3, 5.0);
  const Eigen::Vector2d full = cam.project(X), crop = c2.project(X);
  EXPECT_NEAR(crop.x() * 64, full.x() * 192 - 40, 1e-9);
  EXPECT_NEAR(crop.y() * 48, full.y() * 128 - 24, 1e-9);
}

TEST(TrainSampler, CropPixelsAndReferenceCameraAndMixup) {
  SamplingConfig c;
  c.cropHeight = 16;
  c.cropWidth = 16;
  c.mixupProbability = 1.0;
  c.mixupLambdaMin = 0.1;
  c.mixupLambdaMax = 0.3;
  const scene::Scene scene = fakeScene(9, 48, 32);
  Sampler s(c, 3);
  for (int it = 0; it < 10; ++it) {
    const TrainingSample t = s.drawFromScene(scene, 0);
    const int V = int(t.sources.size());
    ASSERT_EQ(t.cleanSources.size(), size_t(V));
    for (int v = 0; v < V; ++v) {
      const io::Image& full = scene.views[size_t(t.sourceFrames[size_t(v)])].image;
      const io::Image& clean = t.cleanSources[size_t(v)];
      EXPECT_EQ(clean.width, 16);
      EXPECT_EQ(clean.at(1, 3, 5), full.at(1, t.cropY + 3, t.cropX + 5));
      const int p = t.mixupPartner[size_t(v)];
      ASSERT_GE(p, 0);
      ASSERT_NE(p, v);
      const double l = t.mixupLambda[size_t(v)];
      EXPECT_GE(l, 0.1);
      EXPECT_LT(l, 0.3);
      const double expect = (1 - l) * clean.at(2, 7, 9) + l * t.cleanSources[size_t(p)].at(2, 7, 9);
      EXPECT_NEAR(t.sources[size_t(v)].at(2, 7, 9), expect, 1e-6);
    }
    const scene::Camera ref = scene::referenceCamera(t.sourceCameras);
    EXPECT_TRUE(ref.R.isApprox(t.reference.R, 1e-12));
    EXPECT_DOUBLE_EQ(t.reference.fx, t.sourceCameras[0].fx);
    EXPECT_EQ(t.sourceCameras[0].width, 16);
  }
  // A margin widens the reference of the same draw (same seed) and nothing else.
  SamplingConfig wide = c;
  wide.referenceMargin = 0.1;
  Sampler plain(c, 7), widened(wide, 7);
  for (int it = 0; it < 3; ++it) {
    const TrainingSample a = plain.drawFromScene(scene, 0), b = widened.drawFromScene(scene, 0);
    EXPECT_EQ(a.sourceFrames, b.sourceFrames);
    EXPECT_EQ(a.cropX, b.cropX);
    EXPECT_TRUE(a.reference.R.isApprox(b.reference.R, 1e-15));
    EXPECT_DOUBLE_EQ(b.reference.fx, a.reference.fx / 1.2);
    EXPECT_DOUBLE_EQ(b.reference.cx, (a.reference.cx + 0.1) / 1.2);
    EXPECT_EQ(b.reference.width, a.reference.width);
    EXPECT_EQ(b.sources[0].at(0, 3, 4), a.sources[0].at(0, 3, 4));
  }
  SamplingConfig big = c;
  big.cropHeight = 64;
  Sampler s2(big, 0);
  test::expectError([&] { s2.drawFromScene(scene, 0); }, {"crop 64x16", "larger", "32x48"});
}

// Photometric jitter: the same seed draws the same samples with and without it (frames, crops,
// MixUp, clean sources); every source is its MixUp image times its RGB gains in [0, 1], clipped;
// the log gains have the configured spread (exposure shared by the channels of a source); a
// restored sampler state draws the same gains.
TEST(TrainSampler, SourceGainJitterKeepsTheSamplesAndHasItsSpread) {
  SamplingConfig c;
  c.mixupProbability = 0.5;
  SamplingConfig j = c;
  j.sourceExposureStd = 0.05;
  j.sourceChannelStd = 0.02;
  const scene::Scene scene = fakeScene(9, 24, 16);
  Sampler plain(c, 11), jittered(j, 11);
  std::vector<double> exposure, channel; // mean log gain of a source; a channel's deviation
  for (int it = 0; it < 300; ++it) {
    const TrainingSample a = plain.drawFromScene(scene, 0), b = jittered.drawFromScene(scene, 0);
    ASSERT_EQ(a.sourceFrames, b.sourceFrames);
    ASSERT_EQ(a.mixupLambda, b.mixupLambda);
    ASSERT_EQ(a.cleanSources[0].data, b.cleanSources[0].data);
    EXPECT_TRUE(a.sourceGains.empty());
    ASSERT_EQ(b.sourceGains.size(), b.sources.size());
    for (size_t v = 0; v < b.sources.size(); ++v) {
      const std::array<double, 3>& g = b.sourceGains[v];
      const double mean = (std::log(g[0]) + std::log(g[1]) + std::log(g[2])) / 3;
      exposure.push_back(mean);
      channel.push_back(std::log(g[0]) - mean);
      for (int ch = 0; ch < 3; ++ch) {
        const double x = 0.5 * (a.sources[v].at(ch, 5, 7) + 1.0);
        const double expect = std::clamp(x * g[size_t(ch)], 0.0, 1.0) * 2 - 1;
        EXPECT_NEAR(b.sources[v].at(ch, 5, 7), expect, 1e-6);
      }
    }
  }
  auto rms = [](const std::vector<double>& x) {
    double s = 0;
    for (double v : x)
      s += v * v;
    return std::sqrt(s / double(x.size()));
  };
  // Mean of the three log gains: exposure + the channels' mean, sd sqrt(0.05^2 + 0.02^2 / 3).
  EXPECT_NEAR(rms(exposure), std::sqrt(0.05 * 0.05 + 0.02 * 0.02 / 3), 0.006);
  // One channel minus that mean: sd 0.02 sqrt(2 / 3).
  EXPECT_NEAR(rms(channel), 0.02 * std::sqrt(2.0 / 3.0), 0.002);
  Sampler restored(j, 99);
  restored.random().setState(jittered.random().state());
  const TrainingSample x = jittered.drawFromScene(scene, 0), y = restored.drawFromScene(scene, 0);
  EXPECT_EQ(x.sourceGains, y.sourceGains);
  EXPECT_EQ(x.sources[0].data, y.sources[0].data);
}

// Sharpening: the same samples as without it; every view, sources and targets alike, is the
// unsharp mask x + a (x - G x) of the plain view with one amount a per sample (checked at an
// interior pixel against a direct 5 x 5 Gaussian of sigma 1); amounts spread over [0, max].
TEST(TrainSampler, SharpenAppliesOneUnsharpMaskToEveryView) {
  SamplingConfig c;
  c.mixupProbability = 0;
  SamplingConfig sh = c;
  sh.sharpenProbability = 1.0;
  sh.sharpenMax = 2.0;
  scene::Scene scene = fakeScene(9, 24, 16);
  for (scene::SceneView& v : scene.views) // texture: a pattern with edges, not a ramp
    for (size_t k = 0; k < v.image.data.size(); ++k)
      v.image.data[k] = float(0.6 * std::sin(0.9 * double(k)) * std::cos(0.37 * double(k / 24)));
  Sampler plain(c, 5), sharp(sh, 5);
  double lo = 1e9, hi = 0;
  for (int it = 0; it < 40; ++it) {
    const TrainingSample a = plain.drawFromScene(scene, 0), b = sharp.drawFromScene(scene, 0);
    ASSERT_EQ(a.sourceFrames, b.sourceFrames);
    ASSERT_EQ(a.targetFrames, b.targetFrames);
    EXPECT_EQ(a.sharpen, 0.0);
    ASSERT_GT(b.sharpen, 0.0);
    ASSERT_LE(b.sharpen, 2.0);
    lo = std::min(lo, b.sharpen);
    hi = std::max(hi, b.sharpen);
    std::vector<std::pair<const io::Image*, const io::Image*>> views;
    for (size_t v = 0; v < a.cleanSources.size(); ++v)
      views.push_back({&a.cleanSources[v], &b.cleanSources[v]});
    for (size_t v = 0; v < a.targets.size(); ++v)
      views.push_back({&a.targets[v], &b.targets[v]});
    EXPECT_EQ(b.sources[0].data, b.cleanSources[0].data); // no MixUp: the network sees it too
    for (const auto& [x, y] : views) {
      const int c0 = 1, py = 7, px = 11;
      double blurred = 0;
      for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx)
          blurred += std::exp(-0.5 * (dx * dx + dy * dy)) * x->at(c0, py + dy, px + dx);
      blurred /= std::pow(2.48373, 2); // sum of exp(-k^2 / 2), k = -2 .. 2, squared
      const double expect =
          std::clamp(x->at(c0, py, px) + b.sharpen * (x->at(c0, py, px) - blurred), -1.0, 1.0);
      EXPECT_NEAR(y->at(c0, py, px), expect, 2e-5);
    }
  }
  EXPECT_LT(lo, 0.5);
  EXPECT_GT(hi, 1.5);
}

// A zoom is a resize and a centre crop: the zoomed camera must see, at each pixel, the point of
// the original image its ray goes through. Ramp images (channel 0 = relative x, channel 1 =
// relative y of the pixel centre) make that exact: bilinear interpolation reproduces a ramp.
TEST(TrainSampler, ZoomImageMatchesZoomCameraAnalytic) {
  const scene::Camera cam = test::pinholeCamera(64, 48, 0.9, 1.3, 0.46, 0.55);
  io::Image ramp(cam.width, cam.height);
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) {
      ramp.at(0, y, x) = float((x + 0.5) / cam.width);
      ramp.at(1, y, x) = float((y + 0.5) / cam.height);
      ramp.at(2, y, x) = -0.25f;
    }
  for (double factor : {1.0, 1.2, 1.3, 1.6, 2.5}) {
    const scene::Camera z = zoomCamera(cam, factor);
    const io::Image zoomed = zoomImage(ramp, factor);
    ASSERT_EQ(z.width, cam.width);
    ASSERT_EQ(z.height, cam.height);
    ASSERT_EQ(zoomed.width, cam.width);
    ASSERT_EQ(zoomed.height, cam.height);
    EXPECT_NEAR(z.fx / cam.fx, factor, 0.5 / cam.width * factor + 1e-12);
    double worst = 0;
    for (int y = 0; y < cam.height; ++y)
      for (int x = 0; x < cam.width; ++x) {
        // The ray through this pixel's centre, then where the original camera sees it.
        const double nx = ((x + 0.5) / z.width - z.cx) / z.fx;
        const double ny = ((y + 0.5) / z.height - z.cy) / z.fy;
        const double u = nx * cam.fx + cam.cx, v = ny * cam.fy + cam.cy;
        worst = std::max({worst, std::abs(zoomed.at(0, y, x) - u), std::abs(zoomed.at(1, y, x) - v),
                          std::abs(zoomed.at(2, y, x) + 0.25)});
      }
    EXPECT_LT(worst, 2e-6) << "factor " << factor;
  }
  test::expectError([&] { zoomCamera(cam, 0.5); }, {"zoom", "0.5", ">= 1"});
}

TEST(TrainSampler, ZoomIsDrawnPerSampleAndAppliedBeforeTheCrop) {
  SamplingConfig c;
  c.cropHeight = 16;
  c.cropWidth = 16;
  c.mixupProbability = 0;
  c.zoomScales = {1.0, 1.25, 1.5};
  const scene::Scene scene = fakeScene(6, 48, 32);
  Sampler s(c, 11);
  std::set<double> seen;
  for (int it = 0; it < 30; ++it) {
    const TrainingSample t = s.drawFromScene(scene, 0);
    seen.insert(t.zoom);
    const int f = t.sourceFrames[0];
    const scene::SceneView& view = scene.views[size_t(f)];
    const io::Image expect = cropImage(zoomImage(view.image, t.zoom), t.cropX, t.cropY, 16, 16);
    EXPECT_EQ(t.cleanSources[0].data, expect.data);
    const scene::Camera cam = cropCamera(zoomCamera(view.camera, t.zoom), t.cropX, t.cropY, 16, 16);
    EXPECT_DOUBLE_EQ(t.sourceCameras[0].fx, cam.fx);
    EXPECT_DOUBLE_EQ(t.sourceCameras[0].cx, cam.cx);
  }
  EXPECT_EQ(seen, (std::set<double>{1.0, 1.25, 1.5}));
  // One factor: no draw, so the random stream (frames, crops) is that of a zoom-free run.
  SamplingConfig plain = c, fixed = c;
  plain.zoomScales = {1.0};
  fixed.zoomScales = {1.5};
  Sampler a(plain, 4), b(fixed, 4);
  for (int it = 0; it < 5; ++it) {
    const TrainingSample ta = a.drawFromScene(scene, 0), tb = b.drawFromScene(scene, 0);
    EXPECT_EQ(ta.sourceFrames, tb.sourceFrames);
    EXPECT_EQ(ta.cropX, tb.cropX);
    EXPECT_EQ(ta.zoom, 1.0);
    EXPECT_EQ(tb.zoom, 1.5);
  }
}

// Depth maps that name their texel (z = 1 + index) show which texel each output pixel took.
std::vector<std::vector<float>> indexDepths(int frames, int W, int H) {
  std::vector<std::vector<float>> d(size_t(frames), std::vector<float>(size_t(W) * H));
  for (auto& m : d)
    for (size_t k = 0; k < m.size(); ++k)
      m[k] = float(1 + k);
  return d;
}

// The target depths go through the targets' zoom and crop: each pixel holds the texel of the
// original view that the zoomed and cropped camera's ray through the pixel centre hits.
TEST(TrainSampler, TargetDepthsFollowTheZoomAndCropOfTheTargets) {
  const int W = 48, H = 32;
  SamplingConfig c;
  c.cropHeight = 16;
  c.cropWidth = 24;
  c.mixupProbability = 0;
  c.zoomScales = {1.0, 1.5, 2.0};
  const scene::Scene scene = fakeScene(6, W, H);
  const std::vector<std::vector<float>> depths = indexDepths(6, W, H);
  Sampler withDepth(c, 5), without(c, 5);
  for (int it = 0; it < 12; ++it) {
    const TrainingSample t = withDepth.drawFromScene(scene, 0, &depths);
    const TrainingSample u = without.drawFromScene(scene, 0);
    // Depths draw nothing: the same frames, zoom and crop as a sample without them.
    EXPECT_EQ(t.targetFrames, u.targetFrames);
    EXPECT_EQ(t.zoom, u.zoom);
    EXPECT_EQ(t.cropX, u.cropX);
    EXPECT_TRUE(u.targetDepths.empty());
    ASSERT_EQ(t.targetDepths.size(), t.targetFrames.size());
    const scene::Camera& original = scene.views[size_t(t.targetFrames[0])].camera;
    const scene::Camera& cam = t.targetCameras[0];
    ASSERT_EQ(t.targetDepths[0].size(), size_t(24 * 16));
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 24; ++x) {
        const double nx = ((x + 0.5) / cam.width - cam.cx) / cam.fx;
        const double ny = ((y + 0.5) / cam.height - cam.cy) / cam.fy;
        // Where the ray meets the original image, in texels; the texel taken must contain it
        // (either neighbour when it lies on their shared edge).
        const double sx = (nx * original.fx + original.cx) * W;
        const double sy = (ny * original.fy + original.cy) * H;
        const int k = int(t.targetDepths[0][size_t(y) * 24 + x]) - 1;
        ASSERT_LE(std::abs(k % W + 0.5 - sx), 0.5 + 1e-9)
            << "zoom " << t.zoom << " pixel " << x << "," << y;
        ASSERT_LE(std::abs(k / W + 0.5 - sy), 0.5 + 1e-9)
            << "zoom " << t.zoom << " pixel " << x << "," << y;
      }
  }
  std::vector<std::vector<float>> short_ = indexDepths(5, W, H);
  test::expectError([&] { withDepth.drawFromScene(scene, 0, &short_); },
                    {"6 views", "5 depth maps"});
  test::expectError([&] { zoomCropDepth(depths[0], W, H, 1.0, 40, 0, 24, 16); },
                    {"zoomCropDepth", "x 40", "not inside"});
}

} // namespace
} // namespace simpli::training
