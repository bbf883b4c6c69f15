#pragma once
// Line plots as images, for reports the tools write without a plotting library (the training
// run's loss curve and validation scores, benchmark sweeps): one or more panels stacked
// vertically, each with its own axes, nice-number ticks (1, 2, 5 x 10^k), optional log-scaled
// y, and a legend. Text uses a built-in 5x7 pixel font (upper-case letters, digits and
// + - . , : / % ( ) = _), so lower-case labels are shown in upper case.
#include "simpli/model/io/image.h"

#include <array>
#include <string>
#include <vector>

namespace simpli::metrics {

struct PlotSeries {
  std::string name;            ///< legend entry; empty = not in the legend
  std::vector<double> x, y;    ///< same length; non-finite points are skipped (gaps)
  std::array<float, 3> colour; ///< RGB in [0, 1]
  bool markers = false;        ///< a small square at every point
  bool dashed = false;
};

struct PlotPanel {
  std::string title, xLabel, yLabel;
  bool logY = false; ///< only the positive y values are drawn
  std::vector<PlotSeries> series;
};

/// The panels stacked top to bottom, `width` x `panelHeight` pixels each, on white; io::Image
/// scale [-1, 1]. Throws simpli::Error for sizes below 160 x 120 or series whose x and y differ
/// in length. A panel without finite points is drawn with empty axes and "NO DATA".
io::Image renderPlot(const std::vector<PlotPanel>& panels, int width = 800, int panelHeight = 360);

/// Ticks covering [lo, hi]: about `target` nice numbers (1, 2, 5 x 10^k) inside the range.
std::vector<double> niceTicks(double lo, double hi, int target = 6);

/// Pixel width of `text` in the plot font at `scale` (for layout and tests).
int textWidth(const std::string& text, int scale);

} // namespace simpli::metrics
