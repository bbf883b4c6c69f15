// Line plots: nice ticks on known ranges, series drawn where their data says (pixel colours on a
// white canvas), gaps left open, log axes, bad input.
#include "support/expect_error.h"

#include "simpli/model/metrics/line_plot.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace simpli;
using simpli::test::expectError;

namespace {
// Pixels of exactly this colour (io::Image scale [-1, 1]) in columns [x0, x1).
int countColour(const io::Image& im, const std::array<float, 3>& c, int x0 = 0, int x1 = -1) {
  if (x1 < 0)
    x1 = im.width;
  int n = 0;
  for (int y = 0; y < im.height; ++y)
    for (int x = x0; x < x1; ++x) {
      bool same = true;
      for (int k = 0; k < 3; ++k)
        same = same && std::abs(im.at(k, y, x) - (2 * c[k] - 1)) < 1e-6f;
      n += same;
    }
  return n;
}

// Mean row of the pixels of colour c (-1 when there are none).
double meanRow(const io::Image& im, const std::array<float, 3>& c) {
  double sum = 0;
  int n = 0;
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width; ++x) {
      bool same = true;
      for (int k = 0; k < 3; ++k)
        same = same && std::abs(im.at(k, y, x) - (2 * c[k] - 1)) < 1e-6f;
      if (same) {
        sum += y;
        ++n;
      }
    }
  return n ? sum / n : -1;
}

constexpr std::array<float, 3> kRed{1.f, 0.f, 0.f}, kGreen{0.f, 0.8f, 0.f};
} // namespace

TEST(NiceTicks, AreRoundNumbersInsideTheRange) {
  EXPECT_EQ(metrics::niceTicks(0, 10), (std::vector<double>{0, 2, 4, 6, 8, 10}));
  const std::vector<double> t = metrics::niceTicks(0.013, 0.057, 5);
  ASSERT_EQ(t.size(), 4u); // range / 5 = 0.0088 -> step 0.01: 0.02, 0.03, 0.04, 0.05
  for (double v : t) {
    EXPECT_GE(v, 0.013);
    EXPECT_LE(v, 0.057);
  }
  EXPECT_NEAR(t[1] - t[0], 0.01, 1e-12);
  EXPECT_TRUE(metrics::niceTicks(1, 1).empty());
  EXPECT_TRUE(metrics::niceTicks(0, std::nan("")).empty());
  const std::vector<double> big = metrics::niceTicks(-3e6, 7e6);
  EXPECT_EQ(big.front(), -2e6);
  EXPECT_EQ(big.back(), 6e6);
}

TEST(RenderPlot, DrawsASeriesWhereItsValuesAre) {
  metrics::PlotPanel p;
  // A high green line and a low red one: red must be drawn below green.
  p.series.push_back({"", {0, 10}, {1, 1}, kRed});
  p.series.push_back({"", {0, 10}, {9, 9}, kGreen});
  const io::Image im = metrics::renderPlot({p}, 400, 300);
  ASSERT_EQ(im.width, 400);
  ASSERT_EQ(im.height, 300);
  ASSERT_GT(countColour(im, kRed), 200);
  ASSERT_GT(countColour(im, kGreen), 200);
  EXPECT_GT(meanRow(im, kRed), meanRow(im, kGreen) + 100);
}

TEST(RenderPlot, LeavesGapsAtNonFiniteValues) {
  metrics::PlotPanel p;
  // x from 0 to 10 over the plot width; NaN at x = 4..6 leaves the middle of the line out.
  p.series.push_back({"",
                      {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10},
                      {1, 2, 1, 2, std::nan(""), std::nan(""), std::nan(""), 2, 1, 2, 1},
                      kRed});
  const io::Image im = metrics::renderPlot({p}, 400, 300);
  // Plot area: x from 96 to 380, so x = 4..6 is about columns 210..267; 3..7 frame the gap.
  EXPECT_EQ(countColour(im, kRed, 215, 262), 0);
  EXPECT_GT(countColour(im, kRed, 100, 180), 50);
  EXPECT_GT(countColour(im, kRed, 300, 378), 50);
}

TEST(RenderPlot, LogAxisSkipsNonPositiveValues) {
  metrics::PlotPanel p;
  p.logY = true;
  p.series.push_back({"", {0, 1, 2, 3}, {-1, 0, 0, -5}, kRed});
  const io::Image im = metrics::renderPlot({p}, 400, 300); // no positive value: NO DATA
  EXPECT_EQ(countColour(im, kRed), 0);
  p.series[0].y = {1e-3, 1e-2, 1e-1, 1};
  const io::Image logged = metrics::renderPlot({p}, 400, 300);
  EXPECT_GT(countColour(logged, kRed), 200);
}

TEST(RenderPlot, LegendHidesNoData) {
  // A curve low on the left that ends high on the right, where the legend used to sit: every
  // pixel of the curve drawn without a legend is still red with one.
  metrics::PlotPanel p;
  p.series.push_back(
      {"", {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10}, {0, 0, 0, 0, 0, 0, 5, 10, 10, 10, 10}, kRed, true});
  const io::Image bare = metrics::renderPlot({p}, 400, 300);
  p.series[0].name = "network";
  const io::Image named = metrics::renderPlot({p}, 400, 300);
  int hidden = 0, curve = 0;
  for (int y = 0; y < bare.height; ++y)
    for (int x = 0; x < bare.width; ++x) {
      const bool wasRed = bare.at(0, y, x) > 0.99f && bare.at(1, y, x) < -0.99f;
      const bool isRed = named.at(0, y, x) > 0.99f && named.at(1, y, x) < -0.99f;
      curve += wasRed;
      hidden += wasRed && !isRed;
    }
  EXPECT_GT(curve, 200);
  EXPECT_EQ(hidden, 0);
  EXPECT_GT(countColour(named, kRed), countColour(bare, kRed)); // the legend entry is there
}

// Red pixels of `bare` that are no longer red in `named` (the legend drawn over them).
int hiddenRed(const io::Image& bare, const io::Image& named) {
  int hidden = 0;
  for (int y = 0; y < bare.height; ++y)
    for (int x = 0; x < bare.width; ++x) {
      const bool wasRed = bare.at(0, y, x) > 0.99f && bare.at(1, y, x) < -0.99f;
      const bool isRed = named.at(0, y, x) > 0.99f && named.at(1, y, x) < -0.99f;
      hidden += wasRed && !isRed;
    }
  return hidden;
}

TEST(RenderPlot, LegendMovesToTheMiddleWhenEveryCornerHasData) {
  // A training run's validation panel: a flat, sparsely marked network curve along the top and a
  // dashed baseline along the bottom. Every corner holds a line (the segments between the
  // markers too), so the legend must go to the empty middle band.
  metrics::PlotPanel p;
  std::vector<double> x, top, low;
  for (int i = 0; i <= 11; ++i) {
    x.push_back(50 + 100 * i);
    top.push_back(18.3 - 0.03 * i);
    low.push_back(11.1);
  }
  p.series.push_back({"", x, top, kRed, true});
  p.series.push_back({"", x, low, kGreen, false, true});
  const io::Image bare = metrics::renderPlot({p}, 800, 360);
  p.series[0].name = "network";
  p.series[1].name = "nearest view";
  const io::Image named = metrics::renderPlot({p}, 800, 360);
  EXPECT_GT(countColour(bare, kRed), 500);
  EXPECT_EQ(hiddenRed(bare, named), 0);
  EXPECT_GE(countColour(named, kGreen), countColour(bare, kGreen)); // the baseline is whole
}

TEST(RenderPlot, StacksPanelsAndRejectsBadInput) {
  metrics::PlotPanel a, b;
  a.series.push_back({"a", {0, 1}, {0, 1}, kRed, true});
  b.series.push_back({"b", {0, 1}, {1, 0}, kGreen, false, true});
  const io::Image im = metrics::renderPlot({a, b}, 300, 200);
  EXPECT_EQ(im.height, 400);
  EXPECT_GT(meanRow(im, kGreen), meanRow(im, kRed)); // panel b is below panel a
  expectError([&] { metrics::renderPlot({a}, 100, 200); }, {"renderPlot", "100x200"});
  expectError([&] { metrics::renderPlot({}, 300, 200); }, {"no panels"});
  metrics::PlotPanel bad;
  bad.series.push_back({"broken", {0, 1, 2}, {0, 1}, kRed});
  expectError([&] { metrics::renderPlot({bad}, 300, 200); },
              {"broken", "3 x values", "2 y values"});
}

TEST(TextWidth, CountsFiveColumnGlyphsWithOneColumnGaps) {
  EXPECT_EQ(metrics::textWidth("", 2), 0);
  EXPECT_EQ(metrics::textWidth("A", 1), 5);
  EXPECT_EQ(metrics::textWidth("AB", 2), 22);
}
