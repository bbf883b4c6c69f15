// PSNR, SSIM and the paper's central crop (see metrics/image_quality.h).
#include "simpli/model/metrics/image_quality.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "simpli/error.h"

namespace simpli::metrics {

namespace {

void checkImage(const MetricImage& image, const char* fn, const char* which) {
  if (image.width <= 0 || image.height <= 0 || image.channels <= 0)
    fail(fn, ": ", which, " image is empty (", image.width, " x ", image.height, " x ",
         image.channels, ")");
  const std::size_t expected = static_cast<std::size_t>(image.width) * image.height *
                               static_cast<std::size_t>(image.channels);
  if (image.data.size() != expected)
    fail(fn, ": ", which, " image holds ", image.data.size(), " values, expected ", expected,
         " for ", image.width, " x ", image.height, " x ", image.channels);
  for (std::size_t i = 0; i < image.data.size(); ++i)
    if (!std::isfinite(image.data[i])) {
      const std::size_t pixel = i / static_cast<std::size_t>(image.channels);
      fail(fn, ": ", which, " image has the non-finite value ", image.data[i], " at row ",
           pixel / static_cast<std::size_t>(image.width), ", column ",
           pixel % static_cast<std::size_t>(image.width), ", channel ",
           i % static_cast<std::size_t>(image.channels));
    }
}

void checkPair(const MetricImage& a, const MetricImage& b, const char* fn) {
  checkImage(a, fn, "first");
  checkImage(b, fn, "second");
  if (a.width != b.width || a.height != b.height || a.channels != b.channels)
    fail(fn, ": the images differ in size: ", a.width, " x ", a.height, " x ", a.channels, " vs ",
         b.width, " x ", b.height, " x ", b.channels, " (width x height x channels)");
}

// "Valid" separable filtering of one channel's plane (h x w, doubles) with the 1-D window:
// output (h - n + 1) x (w - n + 1).
std::vector<double> filterValid(const std::vector<double>& plane, int h, int w,
                                const std::vector<double>& win) {
  const int n = static_cast<int>(win.size());
  const int ow = w - n + 1, oh = h - n + 1;
  std::vector<double> rows(static_cast<std::size_t>(h) * ow);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < ow; ++x) {
      double s = 0.0;
      const double* p = plane.data() + static_cast<std::size_t>(y) * w + x;
      for (int k = 0; k < n; ++k)
        s += win[static_cast<std::size_t>(k)] * p[k];
      rows[static_cast<std::size_t>(y) * ow + x] = s;
    }
  std::vector<double> out(static_cast<std::size_t>(oh) * ow);
  for (int y = 0; y < oh; ++y)
    for (int x = 0; x < ow; ++x) {
      double s = 0.0;
      for (int k = 0; k < n; ++k)
        s += win[static_cast<std::size_t>(k)] * rows[static_cast<std::size_t>(y + k) * ow + x];
      out[static_cast<std::size_t>(y) * ow + x] = s;
    }
  return out;
}

} // namespace

MetricImage::MetricImage(int w, int h, int c) : width(w), height(h), channels(c) {
  if (w < 0 || h < 0 || c < 1)
    fail("MetricImage: invalid size ", w, " x ", h, " x ", c, " (width x height x channels)");
  data.assign(static_cast<std::size_t>(w) * h * static_cast<std::size_t>(c), 0.0f);
}

MetricImage metricImageFromImage(const io::Image& image) {
  if (image.data.size() !=
      static_cast<std::size_t>(io::Image::channels) * image.width * image.height)
    fail("metricImageFromImage: image holds ", image.data.size(), " values, expected ",
         io::Image::channels, " x ", image.height, " x ", image.width);
  MetricImage out(image.width, image.height, io::Image::channels);
  for (int c = 0; c < io::Image::channels; ++c)
    for (int y = 0; y < image.height; ++y)
      for (int x = 0; x < image.width; ++x)
        out.at(y, x, c) = (image.at(c, y, x) + 1.0f) * 0.5f;
  return out;
}

CropWindow centralCrop(int width, int height, double keptArea) {
  if (!(keptArea > 0.0 && keptArea <= 1.0))
    fail("centralCrop: kept area fraction ", keptArea, " is not in (0, 1]");
  if (width <= 0 || height <= 0)
    fail("centralCrop: image size ", width, " x ", height, " is empty");
  const double side = (1.0 - std::sqrt(keptArea)) / 2.0;
  const int mx = static_cast<int>(std::lround(width * side));
  const int my = static_cast<int>(std::lround(height * side));
  CropWindow w{mx, my, width - 2 * mx, height - 2 * my};
  if (w.width <= 0 || w.height <= 0)
    fail("centralCrop: keeping ", keptArea, " of a ", width, " x ", height,
         " image leaves nothing");
  return w;
}

MetricImage cropImage(const MetricImage& image, const CropWindow& window) {
  checkImage(image, "cropImage", "input");
  if (window.x < 0 || window.y < 0 || window.width <= 0 || window.height <= 0 ||
      window.x + window.width > image.width || window.y + window.height > image.height)
    fail("cropImage: window (x ", window.x, ", y ", window.y, ", ", window.width, " x ",
         window.height, ") is not inside the ", image.width, " x ", image.height, " image");
  MetricImage out(window.width, window.height, image.channels);
  const std::size_t rowValues = static_cast<std::size_t>(window.width) * image.channels;
  for (int y = 0; y < window.height; ++y) {
    const float* src =
        image.data.data() + (static_cast<std::size_t>(window.y + y) * image.width + window.x) *
                                static_cast<std::size_t>(image.channels);
    std::copy(src, src + rowValues, &out.at(y, 0, 0));
  }
  return out;
}

double meanSquaredError(const MetricImage& a, const MetricImage& b) {
  checkPair(a, b, "meanSquaredError");
  double sum = 0.0;
  for (std::size_t i = 0; i < a.data.size(); ++i) {
    const double d = static_cast<double>(a.data[i]) - static_cast<double>(b.data[i]);
    sum += d * d;
  }
  return sum / static_cast<double>(a.data.size());
}

double psnr(const MetricImage& a, const MetricImage& b, double peak) {
  if (!(peak > 0.0) || !std::isfinite(peak))
    fail("psnr: peak value ", peak, " must be finite and > 0");
  const double mse = meanSquaredError(a, b);
  if (mse == 0.0)
    return std::numeric_limits<double>::infinity();
  return 10.0 * std::log10(peak * peak / mse);
}

double ssim(const MetricImage& a, const MetricImage& b, const SSIMOptions& options) {
  checkPair(a, b, "ssim");
  const std::vector<double> win = ocl::ssimWindow(options.windowSize, options.sigma);
  if (a.width < options.windowSize || a.height < options.windowSize)
    fail("ssim: image ", a.width, " x ", a.height, " is smaller than the ", options.windowSize,
         " x ", options.windowSize, " window");
  if (!(options.dataRange > 0.0) || !std::isfinite(options.dataRange))
    fail("ssim: data range ", options.dataRange, " must be finite and > 0");
  const double c1 = (options.k1 * options.dataRange) * (options.k1 * options.dataRange);
  const double c2 = (options.k2 * options.dataRange) * (options.k2 * options.dataRange);

  const int w = a.width, h = a.height;
  const std::size_t n = static_cast<std::size_t>(w) * h;
  std::vector<double> x(n), y(n), xx(n), yy(n), xy(n);
  double total = 0.0;
  for (int c = 0; c < a.channels; ++c) {
    for (std::size_t i = 0; i < n; ++i) {
      const double va = a.data[i * static_cast<std::size_t>(a.channels) + c];
      const double vb = b.data[i * static_cast<std::size_t>(a.channels) + c];
      x[i] = va;
      y[i] = vb;
      xx[i] = va * va;
      yy[i] = vb * vb;
      xy[i] = va * vb;
    }
    const std::vector<double> mx = filterValid(x, h, w, win);
    const std::vector<double> my = filterValid(y, h, w, win);
    const std::vector<double> exx = filterValid(xx, h, w, win);
    const std::vector<double> eyy = filterValid(yy, h, w, win);
    const std::vector<double> exy = filterValid(xy, h, w, win);
    double sum = 0.0;
    for (std::size_t i = 0; i < mx.size(); ++i) {
      const double sxx = exx[i] - mx[i] * mx[i];
      const double syy = eyy[i] - my[i] * my[i];
      const double sxy = exy[i] - mx[i] * my[i];
      sum += ((2.0 * mx[i] * my[i] + c1) * (2.0 * sxy + c2)) /
             ((mx[i] * mx[i] + my[i] * my[i] + c1) * (sxx + syy + c2));
    }
    total += sum / static_cast<double>(mx.size());
  }
  return total / a.channels;
}

ImageQuality evaluateImageQuality(const MetricImage& rendered, const MetricImage& truth,
                                  double keptArea) {
  checkPair(rendered, truth, "evaluateImageQuality");
  const CropWindow window = centralCrop(rendered.width, rendered.height, keptArea);
  const MetricImage r = cropImage(rendered, window);
  const MetricImage t = cropImage(truth, window);
  return {psnr(r, t), ssim(r, t)};
}

MeanStd meanAndStd(const std::vector<double>& values) {
  MeanStd out;
  if (values.empty())
    return out;
  double sum = 0.0;
  for (double v : values)
    sum += v;
  out.mean = sum / static_cast<double>(values.size());
  double sq = 0.0;
  for (double v : values)
    sq += (v - out.mean) * (v - out.mean);
  out.std = std::sqrt(sq / static_cast<double>(values.size()));
  return out;
}

} // namespace simpli::metrics
