// Error maps and side-by-side rows (metrics/comparison_grid.h).
#include "simpli/model/metrics/comparison_grid.h"

#include "simpli/error.h"

#include <algorithm>
#include <cmath>

namespace simpli::metrics {

namespace {
// A "hot" ramp: red rises over the first third, green over the second, blue over the last;
// returned on io::Image's [-1, 1] scale.
float ramp(double e, int channel) {
  return float(2.0 * std::clamp(3.0 * e - channel, 0.0, 1.0) - 1.0);
}
} // namespace

io::Image errorMap(const io::Image& render, const io::Image& truth, double gain) {
  if (render.width != truth.width || render.height != truth.height)
    fail("errorMap: render ", render.width, "x", render.height, " and ground truth ", truth.width,
         "x", truth.height, " differ in size");
  if (!(gain > 0) || !std::isfinite(gain))
    fail("errorMap: gain ", gain, " must be positive and finite");
  io::Image out(render.width, render.height);
  for (int y = 0; y < render.height; ++y)
    for (int x = 0; x < render.width; ++x) {
      double sum = 0;
      for (int c = 0; c < io::Image::channels; ++c)
        sum += 0.5 * std::abs(double(render.at(c, y, x)) - truth.at(c, y, x)); // [0, 1] scale
      const double e = std::clamp(gain * sum / io::Image::channels, 0.0, 1.0);
      for (int c = 0; c < io::Image::channels; ++c)
        out.at(c, y, x) = ramp(e, c);
    }
  return out;
}

io::Image sideBySide(const std::vector<const io::Image*>& images, int gap) {
  if (images.empty())
    fail("sideBySide: no images");
  if (gap < 0)
    fail("sideBySide: gap ", gap, " must be >= 0");
  const int w = images[0]->width, h = images[0]->height;
  for (size_t i = 1; i < images.size(); ++i)
    if (images[i]->width != w || images[i]->height != h)
      fail("sideBySide: image ", i, " is ", images[i]->width, "x", images[i]->height,
           ", image 0 is ", w, "x", h);
  const int n = int(images.size());
  io::Image out(n * w + (n - 1) * gap, h);
  std::fill(out.data.begin(), out.data.end(), 1.0f);
  for (int i = 0; i < n; ++i)
    for (int c = 0; c < io::Image::channels; ++c)
      for (int y = 0; y < h; ++y)
        std::copy_n(images[size_t(i)]->plane(c) + size_t(y) * w, w, &out.at(c, y, i * (w + gap)));
  return out;
}

} // namespace simpli::metrics
