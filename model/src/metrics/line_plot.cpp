// Line plots as images (metrics/line_plot.h).
#include "simpli/model/metrics/line_plot.h"

#include "simpli/error.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>

namespace simpli::metrics {
namespace {

// 5x7 glyphs, one byte per row, bit 4 = leftmost column (the classic HD44780 character shapes).
struct Glyph {
  char c;
  unsigned char rows[7];
};
constexpr Glyph kFont[] = {
    {'0', {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E}},
    {'1', {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E}},
    {'2', {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F}},
    {'3', {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E}},
    {'4', {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02}},
    {'5', {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E}},
    {'6', {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E}},
    {'7', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08}},
    {'8', {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E}},
    {'9', {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C}},
    {'A', {0x0E, 0x11, 0x11, 0x11, 0x1F, 0x11, 0x11}},
    {'B', {0x1E, 0x11, 0x11, 0x1E, 0x11, 0x11, 0x1E}},
    {'C', {0x0E, 0x11, 0x10, 0x10, 0x10, 0x11, 0x0E}},
    {'D', {0x1C, 0x12, 0x11, 0x11, 0x11, 0x12, 0x1C}},
    {'E', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F}},
    {'F', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x10}},
    {'G', {0x0E, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0F}},
    {'H', {0x11, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}},
    {'I', {0x0E, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E}},
    {'J', {0x07, 0x02, 0x02, 0x02, 0x02, 0x12, 0x0C}},
    {'K', {0x11, 0x12, 0x14, 0x18, 0x14, 0x12, 0x11}},
    {'L', {0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1F}},
    {'M', {0x11, 0x1B, 0x15, 0x15, 0x11, 0x11, 0x11}},
    {'N', {0x11, 0x11, 0x19, 0x15, 0x13, 0x11, 0x11}},
    {'O', {0x0E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}},
    {'P', {0x1E, 0x11, 0x11, 0x1E, 0x10, 0x10, 0x10}},
    {'Q', {0x0E, 0x11, 0x11, 0x11, 0x15, 0x12, 0x0D}},
    {'R', {0x1E, 0x11, 0x11, 0x1E, 0x14, 0x12, 0x11}},
    {'S', {0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E}},
    {'T', {0x1F, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04}},
    {'U', {0x11, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}},
    {'V', {0x11, 0x11, 0x11, 0x11, 0x11, 0x0A, 0x04}},
    {'W', {0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0A}},
    {'X', {0x11, 0x11, 0x0A, 0x04, 0x0A, 0x11, 0x11}},
    {'Y', {0x11, 0x11, 0x11, 0x0A, 0x04, 0x04, 0x04}},
    {'Z', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x10, 0x1F}},
    {'.', {0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C}},
    {'-', {0x00, 0x00, 0x00, 0x1F, 0x00, 0x00, 0x00}},
    {'+', {0x00, 0x04, 0x04, 0x1F, 0x04, 0x04, 0x00}},
    {':', {0x00, 0x0C, 0x0C, 0x00, 0x0C, 0x0C, 0x00}},
    {'/', {0x00, 0x01, 0x02, 0x04, 0x08, 0x10, 0x00}},
    {'(', {0x02, 0x04, 0x08, 0x08, 0x08, 0x04, 0x02}},
    {')', {0x08, 0x04, 0x02, 0x02, 0x02, 0x04, 0x08}},
    {'%', {0x18, 0x19, 0x02, 0x04, 0x08, 0x13, 0x03}},
    {',', {0x00, 0x00, 0x00, 0x00, 0x0C, 0x04, 0x08}},
    {'=', {0x00, 0x00, 0x1F, 0x00, 0x1F, 0x00, 0x00}},
    {'_', {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x1F}},
};
constexpr int kGlyphW = 5, kGlyphH = 7, kAdvance = 6;

const Glyph* findGlyph(char c) {
  const char u = char(std::toupper(static_cast<unsigned char>(c)));
  for (const Glyph& g : kFont)
    if (g.c == u)
      return &g;
  return nullptr; // space and unknown characters leave a blank cell
}

using Colour = std::array<float, 3>;
constexpr Colour kBlack{0.f, 0.f, 0.f}, kGrid{0.88f, 0.88f, 0.88f}, kAxis{0.25f, 0.25f, 0.25f};

// An RGB canvas in [0, 1], y down.
class Canvas {
public:
  Canvas(int w, int h) : w_(w), h_(h), rgb_(size_t(w) * h * 3, 1.0f) {}
  int width() const { return w_; }
  int height() const { return h_; }
  void put(int x, int y, const Colour& c) {
    if (x < 0 || y < 0 || x >= w_ || y >= h_)
      return;
    std::copy(c.begin(), c.end(), rgb_.begin() + std::ptrdiff_t(3 * (size_t(y) * w_ + x)));
  }
  void fill(int x0, int y0, int x1, int y1, const Colour& c) {
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x)
        put(x, y, c);
  }
  // A line 2 px wide; dashed lines alternate 6 px drawn, 6 px blank.
  void line(double x0, double y0, double x1, double y1, const Colour& c, bool dashed, double& arc) {
    const double len = std::hypot(x1 - x0, y1 - y0);
    const int n = std::max(1, int(std::ceil(2 * len)));
    for (int i = 0; i <= n; ++i) {
      const double t = double(i) / n;
      if (!dashed || int((arc + t * len) / 6.0) % 2 == 0)
        fill(int(std::floor(x0 + t * (x1 - x0))), int(std::floor(y0 + t * (y1 - y0))),
             int(std::floor(x0 + t * (x1 - x0))) + 2, int(std::floor(y0 + t * (y1 - y0))) + 2, c);
    }
    arc += len;
  }
  void text(int x, int y, const std::string& s, int scale, const Colour& c) {
    for (size_t k = 0; k < s.size(); ++k) {
      const Glyph* g = findGlyph(s[k]);
      if (!g)
        continue;
      const int gx = x + int(k) * kAdvance * scale;
      for (int r = 0; r < kGlyphH; ++r)
        for (int col = 0; col < kGlyphW; ++col)
          if (g->rows[r] & (0x10 >> col))
            fill(gx + col * scale, y + r * scale, gx + (col + 1) * scale, y + (r + 1) * scale, c);
    }
  }
  io::Image image() const {
    io::Image im(w_, h_);
    for (int c = 0; c < 3; ++c)
      for (int y = 0; y < h_; ++y)
        for (int x = 0; x < w_; ++x)
          im.at(c, y, x) = 2.0f * rgb_[3 * (size_t(y) * w_ + x) + c] - 1.0f;
    return im;
  }

private:
  int w_, h_;
  std::vector<float> rgb_;
};

std::string tickLabel(double v, double step) {
  char buf[32];
  const double a = std::abs(v);
  if (v != 0 && (a >= 1e5 || a < 1e-3)) {
    std::snprintf(buf, sizeof buf, "%.0e", v);
  } else {
    const int decimals = std::max(0, int(-std::floor(std::log10(step) + 1e-9)));
    std::snprintf(buf, sizeof buf, "%.*f", std::min(decimals, 4), v);
  }
  return buf;
}

struct Range {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  void add(double v) {
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  bool valid() const { return lo <= hi; }
  void pad() {
    if (lo == hi) {
      const double d = lo == 0 ? 1 : 0.05 * std::abs(lo);
      lo -= d;
      hi += d;
    }
  }
};

bool usable(double x, double y, bool logY) {
  return std::isfinite(x) && std::isfinite(y) && (!logY || y > 0);
}

// Top-left corner of a w x h legend inside the plot area [x0, x1] x [y0, y1], where it covers
// the fewest of the drawn pixels `points` (margins included, so that a line passing just beside
// the box stays visible). Candidates in order of preference: the four corners, then the middle
// of the right and left sides, the middle of the top and bottom, the centre (a flat curve at the
// top and a baseline at the bottom leave only the middle band free).
std::array<int, 2> legendCorner(const std::vector<std::array<double, 2>>& points, int x0, int y0,
                                int x1, int y1, int w, int h) {
  const int margin = 6;
  const int right = x1 - 4 - w, left = x0 + margin, top = y0 + margin, bottom = y1 - margin - h;
  const int midX = (x0 + x1 - w) / 2, midY = (y0 + y1 - h) / 2;
  const std::array<std::array<int, 2>, 9> candidates{{{right, top},
                                                      {left, top},
                                                      {right, bottom},
                                                      {left, bottom},
                                                      {right, midY},
                                                      {left, midY},
                                                      {midX, top},
                                                      {midX, bottom},
                                                      {midX, midY}}};
  std::array<int, 2> best = candidates[0];
  size_t fewest = SIZE_MAX;
  for (const std::array<int, 2>& c : candidates) {
    size_t covered = 0;
    for (const std::array<double, 2>& q : points)
      covered += q[0] >= c[0] - margin && q[0] <= c[0] + w + margin && q[1] >= c[1] - margin &&
                 q[1] <= c[1] + h + margin;
    if (covered < fewest) {
      fewest = covered;
      best = c;
    }
  }
  return best;
}

// Points every ~2 pixels along the segment (ax, ay) -> (bx, by), end excluded, appended to `out`:
// what the legend must not cover is the lines, not only their vertices.
void sampleSegment(double ax, double ay, double bx, double by,
                   std::vector<std::array<double, 2>>& out) {
  const int n = std::max(1, int(std::ceil(std::hypot(bx - ax, by - ay) / 2)));
  for (int i = 0; i < n; ++i) {
    const double t = double(i) / n;
    out.push_back({ax + t * (bx - ax), ay + t * (by - ay)});
  }
}

void drawPanel(Canvas& cv, const PlotPanel& p, int top, int height) {
  constexpr int left = 96, right = 20, titleH = 34, bottom = 52, scale = 2;
  const int x0 = left, x1 = cv.width() - right, y0 = top + titleH, y1 = top + height - bottom;
  cv.text((cv.width() - textWidth(p.title, scale)) / 2, top + 8, p.title, scale, kBlack);
  cv.text(8, top + 8, p.yLabel, scale, kAxis);

  Range xr, yr;
  for (const PlotSeries& s : p.series) {
    if (s.x.size() != s.y.size())
      fail("renderPlot: series '", s.name, "' has ", s.x.size(), " x values and ", s.y.size(),
           " y values");
    for (size_t i = 0; i < s.x.size(); ++i)
      if (usable(s.x[i], s.y[i], p.logY)) {
        xr.add(s.x[i]);
        yr.add(p.logY ? std::log10(s.y[i]) : s.y[i]);
      }
  }
  // Axes box.
  cv.fill(x0, y1, x1 + 1, y1 + 1, kAxis);
  cv.fill(x0, y0, x0 + 1, y1 + 1, kAxis);
  if (!xr.valid()) {
    cv.text((x0 + x1 - textWidth("NO DATA", scale)) / 2, (y0 + y1) / 2, "NO DATA", scale, kAxis);
    return;
  }
  xr.pad();
  yr.pad();
  const double ySpan = yr.hi - yr.lo;
  yr.lo -= 0.04 * ySpan;
  yr.hi += 0.04 * ySpan;
  auto px = [&](double x) { return x0 + (x - xr.lo) / (xr.hi - xr.lo) * (x1 - x0); };
  auto py = [&](double y) { return y1 - (y - yr.lo) / (yr.hi - yr.lo) * (y1 - y0); };

  const std::vector<double> xt = niceTicks(xr.lo, xr.hi);
  const double xStep = xt.size() > 1 ? xt[1] - xt[0] : 1;
  for (double t : xt) {
    const int x = int(std::lround(px(t)));
    cv.fill(x, y0, x + 1, y1, kGrid);
    cv.fill(x, y1, x + 1, y1 + 6, kAxis);
    const std::string s = tickLabel(t, xStep);
    cv.text(x - textWidth(s, scale) / 2, y1 + 10, s, scale, kBlack);
  }
  // Ticks as values (tv) and where they go on the (possibly log10) y axis (yt).
  std::vector<double> tv;
  if (p.logY && yr.hi - yr.lo >= 1.0) {
    const double every = std::max(1.0, std::ceil((yr.hi - yr.lo) / 6));
    for (double e = std::ceil(yr.lo); e <= yr.hi; e += every)
      tv.push_back(std::pow(10.0, e));
  } else if (p.logY) { // less than a decade: linear nice values on the log axis
    tv = niceTicks(std::pow(10.0, yr.lo), std::pow(10.0, yr.hi));
  } else {
    tv = niceTicks(yr.lo, yr.hi);
  }
  const double tStep = tv.size() > 1 ? tv[1] - tv[0] : 1;
  for (double v : tv) {
    const int y = int(std::lround(py(p.logY ? std::log10(v) : v)));
    cv.fill(x0 + 1, y, x1, y + 1, kGrid);
    cv.fill(x0 - 6, y, x0, y + 1, kAxis);
    const std::string s = tickLabel(v, p.logY && yr.hi - yr.lo >= 1.0 ? v : tStep);
    cv.text(x0 - 10 - textWidth(s, scale), y - kGlyphH * scale / 2, s, scale, kBlack);
  }
  cv.text((x0 + x1 - textWidth(p.xLabel, scale)) / 2, y1 + 32, p.xLabel, scale, kAxis);

  std::vector<std::array<double, 2>> drawn; // pixels of the points and lines, for the legend
  for (const PlotSeries& s : p.series) {
    double arc = 0;
    bool have = false;
    double lx = 0, ly = 0;
    for (size_t i = 0; i < s.x.size(); ++i) {
      if (!usable(s.x[i], s.y[i], p.logY)) {
        have = false; // a gap
        continue;
      }
      const double x = px(s.x[i]), y = py(p.logY ? std::log10(s.y[i]) : s.y[i]);
      drawn.push_back({x, y});
      if (have) {
        cv.line(lx, ly, x, y, s.colour, s.dashed, arc);
        sampleSegment(lx, ly, x, y, drawn);
      }
      if (s.markers)
        cv.fill(int(x) - 3, int(y) - 3, int(x) + 4, int(y) + 4, s.colour);
      lx = x;
      ly = y;
      have = true;
    }
  }
  // The legend last, on white, so that no line runs through it, where it hides the fewest of the
  // drawn pixels (a validation curve that ends high would vanish under a fixed corner).
  int widest = 0, entries = 0;
  for (const PlotSeries& s : p.series)
    if (!s.name.empty()) {
      widest = std::max(widest, textWidth(s.name, scale));
      ++entries;
    }
  if (entries == 0)
    return;
  const int lineH = kGlyphH * scale + 6, boxW = widest + 54, boxH = entries * lineH + 6;
  const auto [boxX, boxY] = legendCorner(drawn, x0, y0, x1, y1, boxW, boxH);
  cv.fill(boxX, boxY, boxX + boxW, boxY + boxH, {1.f, 1.f, 1.f});
  int legendY = boxY + 6;
  for (const PlotSeries& s : p.series) {
    if (s.name.empty())
      continue;
    double a = 0;
    cv.line(boxX + 6, legendY + 6, boxX + 36, legendY + 6, s.colour, s.dashed, a);
    cv.text(boxX + 46, legendY, s.name, scale, s.colour);
    legendY += lineH;
  }
}

} // namespace

int textWidth(const std::string& text, int scale) {
  return text.empty() ? 0 : (int(text.size()) * kAdvance - 1) * scale;
}

std::vector<double> niceTicks(double lo, double hi, int target) {
  if (!std::isfinite(lo) || !std::isfinite(hi) || !(hi > lo) || target < 1)
    return {};
  const double raw = (hi - lo) / target;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  double step = mag;
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * mag >= raw) {
      step = m * mag;
      break;
    }
  std::vector<double> ticks;
  for (double t = std::ceil(lo / step) * step; t <= hi + 1e-9 * step; t += step)
    ticks.push_back(std::abs(t) < 1e-12 * step ? 0.0 : t);
  return ticks;
}

io::Image renderPlot(const std::vector<PlotPanel>& panels, int width, int panelHeight) {
  if (width < 160 || panelHeight < 120)
    fail("renderPlot: size ", width, "x", panelHeight, " is below 160x120");
  if (panels.empty())
    fail("renderPlot: no panels");
  Canvas cv(width, panelHeight * int(panels.size()));
  for (size_t i = 0; i < panels.size(); ++i)
    drawPanel(cv, panels[i], int(i) * panelHeight, panelHeight);
  return cv.image();
}

} // namespace simpli::metrics
