// PSNR, SSIM and the central crop (model/metrics.h) against hand-computed values and against an
// independent, deliberately naive double implementation of Wang et al.'s SSIM.
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "simpli/error.h"
#include "simpli/model/metrics/image_quality.h"

namespace simpli {
namespace {

metrics::MetricImage constant(int w, int h, int c, float v) {
  metrics::MetricImage m(w, h, c);
  for (float& x : m.data)
    x = v;
  return m;
}

metrics::MetricImage random(int w, int h, int c, unsigned seed, float lo = 0.0f, float hi = 1.0f) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(lo, hi);
  metrics::MetricImage m(w, h, c);
  for (float& x : m.data)
    x = u(rng);
  return m;
}

// Smooth structure plus noise, like a photo (SSIM values away from 0 and 1).
metrics::MetricImage textured(int w, int h, int c, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.05);
  metrics::MetricImage m(w, h, c);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int k = 0; k < c; ++k) {
        const double v = 0.5 + 0.3 * std::sin(0.31 * x + k) * std::cos(0.17 * y) + noise(rng);
        m.at(y, x, k) = static_cast<float>(std::min(1.0, std::max(0.0, v)));
      }
  return m;
}

// Wang et al.'s SSIM written out directly: for every valid window position, the 2-D Gaussian
// weights exp(-(dx^2 + dy^2) / (2 sigma^2)) normalised over the window, weighted moments, the
// SSIM formula; mean over positions, then over channels. No separable filtering, no sharing.
double naiveSSIM(const metrics::MetricImage& a, const metrics::MetricImage& b, int win = 11,
                 double sigma = 1.5) {
  const double c1 = 0.01 * 0.01, c2 = 0.03 * 0.03;
  const int r = win / 2;
  double weights[64][64];
  double wsum = 0.0;
  for (int dy = -r; dy <= r; ++dy)
    for (int dx = -r; dx <= r; ++dx) {
      weights[dy + r][dx + r] = std::exp(-(dx * dx + dy * dy) / (2.0 * sigma * sigma));
      wsum += weights[dy + r][dx + r];
    }
  double total = 0.0;
  for (int c = 0; c < a.channels; ++c) {
    double sum = 0.0;
    int count = 0;
    for (int y = r; y + r < a.height; ++y)
      for (int x = r; x + r < a.width; ++x) {
        double ma = 0, mb = 0;
        for (int dy = -r; dy <= r; ++dy)
          for (int dx = -r; dx <= r; ++dx) {
            const double g = weights[dy + r][dx + r] / wsum;
            ma += g * a.at(y + dy, x + dx, c);
            mb += g * b.at(y + dy, x + dx, c);
          }
        double vaa = 0, vbb = 0, vab = 0;
        for (int dy = -r; dy <= r; ++dy)
          for (int dx = -r; dx <= r; ++dx) {
            const double g = weights[dy + r][dx + r] / wsum;
            const double da = a.at(y + dy, x + dx, c) - ma;
            const double db = b.at(y + dy, x + dx, c) - mb;
            vaa += g * da * da;
            vbb += g * db * db;
            vab += g * da * db;
          }
        sum += (2 * ma * mb + c1) * (2 * vab + c2) / ((ma * ma + mb * mb + c1) * (vaa + vbb + c2));
        ++count;
      }
    total += sum / count;
  }
  return total / a.channels;
}

void expectError(const std::function<void()>& f, const std::vector<std::string>& parts) {
  try {
    f();
    ADD_FAILURE() << "no simpli::Error thrown";
  } catch (const Error& e) {
    for (const auto& p : parts)
      EXPECT_NE(std::string(e.what()).find(p), std::string::npos)
          << "message '" << e.what() << "' lacks '" << p << "'";
  }
}

TEST(Metrics, IdenticalImages) {
  const metrics::MetricImage a = textured(40, 30, 3, 1);
  EXPECT_EQ(metrics::meanSquaredError(a, a), 0.0);
  EXPECT_TRUE(std::isinf(metrics::psnr(a, a)) && metrics::psnr(a, a) > 0);
  EXPECT_NEAR(metrics::ssim(a, a), 1.0, 1e-12);
  const metrics::ImageQuality q = metrics::evaluateImageQuality(a, a);
  EXPECT_TRUE(std::isinf(q.psnr));
  EXPECT_NEAR(q.ssim, 1.0, 1e-12);
}

TEST(Metrics, PsnrOfKnownMse) {
  // Differences exactly representable in float: 0.125 everywhere -> MSE 1/64 -> 10 log10(64).
  const metrics::MetricImage a = constant(13, 7, 3, 0.5f), b = constant(13, 7, 3, 0.625f);
  EXPECT_EQ(metrics::meanSquaredError(a, b), 1.0 / 64.0);
  EXPECT_DOUBLE_EQ(metrics::psnr(a, b), 10.0 * std::log10(64.0));
  EXPECT_NEAR(metrics::psnr(a, b), 18.061799739838872, 1e-12);
  // Half the values off by 0.25, half exact: MSE = 0.25^2 / 2 = 1/32.
  metrics::MetricImage c = a;
  for (std::size_t i = 0; i < c.data.size(); i += 2)
    c.data[i] = 0.75f;
  const double mse =
      (0.0625 * static_cast<double>((c.data.size() + 1) / 2)) / static_cast<double>(c.data.size());
  EXPECT_DOUBLE_EQ(metrics::meanSquaredError(a, c), mse);
  EXPECT_DOUBLE_EQ(metrics::psnr(a, c), 10.0 * std::log10(1.0 / mse));
  // A peak of 255 on 0..255 data gives the same dB as 1 on 0..1 data.
  metrics::MetricImage a255 = a, b255 = b;
  for (float& v : a255.data)
    v *= 255.0f;
  for (float& v : b255.data)
    v *= 255.0f;
  EXPECT_NEAR(metrics::psnr(a255, b255, 255.0), metrics::psnr(a, b), 1e-9);
}

TEST(Metrics, SsimOfConstantImages) {
  // Constant images: no variance, so SSIM = luminance term (2 m n + C1) / (m^2 + n^2 + C1).
  const double m = 0.25, n = 0.75, c1 = 1e-4;
  const double expected = (2 * m * n + c1) / (m * m + n * n + c1);
  EXPECT_NEAR(metrics::ssim(constant(16, 12, 3, 0.25f), constant(16, 12, 3, 0.75f)), expected,
              1e-12);
  EXPECT_NEAR(expected, 0.3751 / 0.6251, 1e-15);
}

TEST(Metrics, SsimOfConstantShiftOnlyDropsLuminance) {
  // b = a + s: variances and covariance agree, so the contrast-structure factor is exactly 1
  // and SSIM is the mean luminance term over windows, which is below 1.
  const metrics::MetricImage a = textured(32, 24, 1, 3);
  metrics::MetricImage b = a;
  for (float& v : b.data)
    v += 0.125f; // exact in float for these magnitudes
  const double s = metrics::ssim(a, b);
  EXPECT_LT(s, 1.0);
  EXPECT_GT(s, 0.9);
  // The luminance term alone, from the window means.
  const std::vector<double> g = ocl::ssimWindow(11, 1.5);
  double sum = 0.0;
  int count = 0;
  for (int y = 5; y + 5 < a.height; ++y)
    for (int x = 5; x + 5 < a.width; ++x) {
      double mu = 0.0;
      for (int dy = -5; dy <= 5; ++dy)
        for (int dx = -5; dx <= 5; ++dx)
          mu += g[dy + 5] * g[dx + 5] * a.at(y + dy, x + dx, 0);
      const double nu = mu + 0.125;
      sum += (2 * mu * nu + 1e-4) / (mu * mu + nu * nu + 1e-4);
      ++count;
    }
  EXPECT_NEAR(s, sum / count, 1e-10);
}

TEST(Metrics, Symmetry) {
  const metrics::MetricImage a = textured(29, 21, 3, 4), b = random(29, 21, 3, 5);
  EXPECT_DOUBLE_EQ(metrics::psnr(a, b), metrics::psnr(b, a));
  EXPECT_NEAR(metrics::ssim(a, b), metrics::ssim(b, a), 1e-14);
  const metrics::ImageQuality q1 = metrics::evaluateImageQuality(a, b),
                              q2 = metrics::evaluateImageQuality(b, a);
  EXPECT_DOUBLE_EQ(q1.psnr, q2.psnr);
  EXPECT_NEAR(q1.ssim, q2.ssim, 1e-14);
}

TEST(Metrics, SsimMatchesNaiveImplementation) {
  struct Case {
    int w, h, c;
    unsigned seed;
  };
  for (const Case& k :
       {Case{11, 11, 1, 6}, Case{23, 17, 3, 7}, Case{40, 12, 2, 8}, Case{31, 33, 4, 9}}) {
    const metrics::MetricImage a = textured(k.w, k.h, k.c, k.seed);
    metrics::MetricImage b = a;
    std::mt19937 rng(k.seed + 100);
    std::normal_distribution<float> noise(0.0f, 0.1f);
    for (float& v : b.data)
      v = std::min(1.0f, std::max(0.0f, v + noise(rng)));
    const double fast = metrics::ssim(a, b), slow = naiveSSIM(a, b);
    EXPECT_NEAR(fast, slow, 1e-12) << k.w << "x" << k.h << "x" << k.c;
    EXPECT_GT(fast, 0.05);
    EXPECT_LT(fast, 0.99);
    // Unrelated random images: SSIM near 0, still equal to the naive value.
    const metrics::MetricImage r1 = random(k.w, k.h, k.c, k.seed + 1),
                               r2 = random(k.w, k.h, k.c, k.seed + 2);
    EXPECT_NEAR(metrics::ssim(r1, r2), naiveSSIM(r1, r2), 1e-12);
  }
  // Another window configuration goes through the same code path.
  const metrics::MetricImage a = textured(20, 20, 1, 11), b = random(20, 20, 1, 12);
  metrics::SSIMOptions o;
  o.windowSize = 7;
  o.sigma = 1.0;
  EXPECT_NEAR(metrics::ssim(a, b, o), naiveSSIM(a, b, 7, 1.0), 1e-12);
}

TEST(Metrics, SsimAveragesChannels) {
  // Channel 0 identical (SSIM 1), channel 1 two constants (the luminance value): mean of both.
  metrics::MetricImage a(15, 15, 2), b(15, 15, 2);
  const metrics::MetricImage t = textured(15, 15, 1, 13);
  for (int y = 0; y < 15; ++y)
    for (int x = 0; x < 15; ++x) {
      a.at(y, x, 0) = b.at(y, x, 0) = t.at(y, x, 0);
      a.at(y, x, 1) = 0.25f;
      b.at(y, x, 1) = 0.75f;
    }
  EXPECT_NEAR(metrics::ssim(a, b), (1.0 + 0.3751 / 0.6251) / 2.0, 1e-12);
}

TEST(Metrics, SsimWindow) {
  const std::vector<double> g = ocl::ssimWindow(11, 1.5);
  ASSERT_EQ(g.size(), 11u);
  double sum = 0.0;
  for (double v : g)
    sum += v;
  EXPECT_NEAR(sum, 1.0, 1e-15);
  for (int i = 0; i < 5; ++i)
    EXPECT_DOUBLE_EQ(g[i], g[10 - i]);
  EXPECT_NEAR(g[5] / g[6], std::exp(1.0 / 4.5), 1e-14);
  EXPECT_NEAR(g[5] / g[0], std::exp(25.0 / 4.5), 1e-9);
}

TEST(Metrics, CentralCrop) {
  // (1 - sqrt(0.9)) / 2 = 0.0256584: 256 -> margin round(6.568) = 7, kept 242.
  metrics::CropWindow w = metrics::centralCrop(256, 256);
  EXPECT_EQ(w.x, 7);
  EXPECT_EQ(w.y, 7);
  EXPECT_EQ(w.width, 242);
  EXPECT_EQ(w.height, 242);
  w = metrics::centralCrop(100, 50); // margins round(2.566) = 3 and round(1.283) = 1
  EXPECT_EQ(w.x, 3);
  EXPECT_EQ(w.y, 1);
  EXPECT_EQ(w.width, 94);
  EXPECT_EQ(w.height, 48);
  w = metrics::centralCrop(1008, 752); // the reference scene size: area within 0.5 % of 90 %
  EXPECT_NEAR(double(w.width) * w.height / (1008.0 * 752.0), 0.9, 0.005);
  EXPECT_EQ(w.width + 2 * w.x, 1008);
  EXPECT_EQ(w.height + 2 * w.y, 752);
  w = metrics::centralCrop(10, 10, 1.0);
  EXPECT_EQ(w.x, 0);
  EXPECT_EQ(w.width, 10);
}

TEST(Metrics, EvaluationUsesOnlyTheCrop) {
  const metrics::MetricImage truth = textured(64, 48, 3, 14);
  metrics::MetricImage rendered = truth;
  const metrics::CropWindow w = metrics::centralCrop(64, 48);
  // Garbage outside the crop: invisible to the protocol.
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) {
      const bool inside = x >= w.x && x < w.x + w.width && y >= w.y && y < w.y + w.height;
      if (!inside)
        for (int c = 0; c < 3; ++c)
          rendered.at(y, x, c) = 1.0f - rendered.at(y, x, c);
    }
  metrics::ImageQuality q = metrics::evaluateImageQuality(rendered, truth);
  EXPECT_TRUE(std::isinf(q.psnr));
  EXPECT_NEAR(q.ssim, 1.0, 1e-12);
  // One changed pixel inside: exactly the cropped MSE.
  rendered.at(w.y + 3, w.x + 4, 1) = truth.at(w.y + 3, w.x + 4, 1) + 0.5f;
  q = metrics::evaluateImageQuality(rendered, truth);
  const double d =
      static_cast<double>(rendered.at(w.y + 3, w.x + 4, 1)) - truth.at(w.y + 3, w.x + 4, 1);
  const double mse = d * d / (3.0 * w.width * w.height);
  EXPECT_NEAR(q.psnr, 10.0 * std::log10(1.0 / mse), 1e-9);
  EXPECT_LT(q.ssim, 1.0);
  EXPECT_NEAR(q.ssim, metrics::ssim(cropImage(rendered, w), cropImage(truth, w)), 1e-15);
}

TEST(Metrics, CropImageCopiesTheWindow) {
  const metrics::MetricImage a = random(9, 7, 2, 15);
  const metrics::MetricImage c = cropImage(a, {2, 1, 5, 4});
  ASSERT_EQ(c.width, 5);
  ASSERT_EQ(c.height, 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 5; ++x)
      for (int k = 0; k < 2; ++k)
        EXPECT_EQ(c.at(y, x, k), a.at(y + 1, x + 2, k));
}

TEST(Metrics, FromNetworkImage) {
  io::Image im(3, 2);
  for (int c = 0; c < 3; ++c)
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 3; ++x)
        im.at(c, y, x) = -1.0f + 0.25f * (c + 3 * y + x); // distinct per position
  const metrics::MetricImage m = metrics::metricImageFromImage(im);
  ASSERT_EQ(m.channels, 3);
  for (int c = 0; c < 3; ++c)
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 3; ++x)
        EXPECT_EQ(m.at(y, x, c), (im.at(c, y, x) + 1.0f) * 0.5f);
  EXPECT_EQ(m.at(0, 0, 0), 0.0f);
}

TEST(Metrics, MeanAndStd) {
  metrics::MeanStd s = metrics::meanAndStd({1.0, 2.0, 3.0, 4.0});
  EXPECT_DOUBLE_EQ(s.mean, 2.5);
  EXPECT_DOUBLE_EQ(s.std, std::sqrt(1.25));
  s = metrics::meanAndStd({7.0});
  EXPECT_EQ(s.mean, 7.0);
  EXPECT_EQ(s.std, 0.0);
  s = metrics::meanAndStd({});
  EXPECT_TRUE(std::isnan(s.mean) && std::isnan(s.std));
  s = metrics::meanAndStd({1.0, std::numeric_limits<double>::infinity()});
  EXPECT_TRUE(std::isinf(s.mean));
  EXPECT_TRUE(std::isnan(s.std));
}

TEST(Metrics, BadInput) {
  const metrics::MetricImage a = constant(16, 16, 3, 0.5f);
  expectError([&] { metrics::psnr(a, constant(16, 15, 3, 0.5f)); },
              {"meanSquaredError", "differ in size", "16 x 16 x 3", "16 x 15 x 3"});
  expectError([&] { metrics::ssim(a, constant(16, 16, 1, 0.5f)); }, {"ssim", "16 x 16 x 1"});
  expectError([&] { metrics::ssim(constant(10, 30, 1, 0.5f), constant(10, 30, 1, 0.5f)); },
              {"ssim", "10 x 30", "smaller than the 11 x 11 window"});
  metrics::MetricImage nan = a;
  nan.at(3, 4, 2) = std::numeric_limits<float>::quiet_NaN();
  expectError([&] { metrics::psnr(a, nan); },
              {"second", "non-finite", "row 3", "column 4", "channel 2"});
  metrics::MetricImage broken = a;
  broken.data.pop_back();
  expectError([&] { metrics::ssim(broken, a); }, {"first", "767 values", "expected 768"});
  expectError([&] { metrics::centralCrop(10, 10, 0.0); }, {"centralCrop", "0 is not in (0, 1]"});
  expectError([&] { metrics::centralCrop(10, 10, 1.5); }, {"1.5"});
  expectError([&] { metrics::centralCrop(0, 10); }, {"0 x 10"});
  expectError([&] { cropImage(a, {10, 0, 7, 4}); }, {"cropImage", "not inside", "16 x 16"});
  expectError([&] { metrics::psnr(a, a, 0.0); }, {"peak value 0"});
  expectError([&] { ocl::ssimWindow(10, 1.5); }, {"window size 10"});
  expectError([&] { ocl::ssimWindow(11, 0.0); }, {"sigma 0"});
  expectError([&] { metrics::MetricImage(-1, 2, 3); }, {"MetricImage", "-1 x 2 x 3"});
  expectError([&] { metrics::evaluateImageQuality(metrics::MetricImage(), a); },
              {"evaluateImageQuality", "empty"});
}

} // namespace
} // namespace simpli
