// Classical plane-sweep stereo as a one-surface "network" output (baselines/plane_sweep_stereo.h).
#include "simpli/model/baselines/plane_sweep_stereo.h"

#include "simpli/error.h"
#include "simpli/model/geometry/plane_sweep.h"
#include "simpli/model/geometry/planes.h"

#include "simpli/ocl/autograd.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace simpli::baselines {

namespace {

/// Mean of `values` [H, W] over the window x window square around every pixel, counting only
/// pixels inside the image (summed-area table, double).
std::vector<double> boxMean(const std::vector<double>& values, int H, int W, int window) {
  const int r = window / 2;
  std::vector<double> table(size_t(H + 1) * (W + 1), 0.0);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      table[size_t(y + 1) * (W + 1) + x + 1] =
          values[size_t(y) * W + x] + table[size_t(y) * (W + 1) + x + 1] +
          table[size_t(y + 1) * (W + 1) + x] - table[size_t(y) * (W + 1) + x];
  std::vector<double> out(values.size());
  for (int y = 0; y < H; ++y) {
    const int y0 = std::max(0, y - r), y1 = std::min(H, y + r + 1);
    for (int x = 0; x < W; ++x) {
      const int x0 = std::max(0, x - r), x1 = std::min(W, x + r + 1);
      const double sum = table[size_t(y1) * (W + 1) + x1] - table[size_t(y0) * (W + 1) + x1] -
                         table[size_t(y1) * (W + 1) + x0] + table[size_t(y0) * (W + 1) + x0];
      out[size_t(y) * W + x] = sum / (double(y1 - y0) * (x1 - x0));
    }
  }
  return out;
}

/// Per-plane windowed cost [P][H * W] and the sources' mean colour [P][3 * H * W] (channel
/// planes), gathered `planesPerChunk` planes at a time.
struct SweepStatistics {
  std::vector<std::vector<double>> cost;
  std::vector<std::vector<float>> colour;
};

SweepStatistics sweepStatistics(const generator::GeneratorInput& in,
                                const std::vector<double>& depths,
                                const PlaneSweepStereoOptions& o) {
  const int V = int(in.images.size(0)), H = int(in.images.size(2)), W = int(in.images.size(3));
  const size_t HW = size_t(H) * W;
  const int window = windowPixels(o, W);
  SweepStatistics s;
  for (size_t first = 0; first < depths.size(); first += size_t(o.planesPerChunk)) {
    const size_t last = std::min(depths.size(), first + size_t(o.planesPerChunk));
    const std::vector<double> chunk(depths.begin() + long(first), depths.begin() + long(last));
    const int S = int(chunk.size());
    const geometry::SurfaceSamples g =
        geometry::planeSweep(in.images, in.reference, in.sources, chunk, H, W);
    const std::vector<double> samples = g.samples.toVector(); // [V, S, 3, H, W]
    const std::vector<double> mask = g.mask.toVector();       // [V, S, 1, H, W]
    for (int p = 0; p < S; ++p) {
      std::vector<double> cost(HW);
      std::vector<float> colour(3 * HW);
      for (size_t i = 0; i < HW; ++i) {
        double n = 0, sum[3] = {0, 0, 0}, sq[3] = {0, 0, 0};
        for (int v = 0; v < V; ++v) {
          const double m = mask[(size_t(v) * S + p) * HW + i];
          if (m <= 0)
            continue;
          n += m;
          for (int c = 0; c < 3; ++c) {
            const double x = samples[((size_t(v) * S + p) * 3 + c) * HW + i];
            sum[c] += m * x;
            sq[c] += m * x * x;
          }
        }
        double variance = 0;
        for (int c = 0; c < 3; ++c) {
          const double mean = n > 0 ? sum[c] / n : 0.0;
          colour[c * HW + i] = float(mean);
          variance += n > 0 ? std::max(0.0, sq[c] / n - mean * mean) : 0.0;
        }
        cost[i] = n >= 2 ? variance : kUnmatchedCost;
      }
      s.cost.push_back(boxMean(cost, H, W, window));
      s.colour.push_back(std::move(colour));
    }
  }
  return s;
}

/// The softmin distribution over the planes of pixel i's windowed cost into `weights` (P
/// values summing to 1), shifted by the smallest cost so that exp never underflows to all 0.
void softmin(const SweepStatistics& s, size_t i, double temperature, std::vector<double>& weights) {
  double best = std::numeric_limits<double>::infinity(), total = 0;
  for (const std::vector<double>& c : s.cost)
    best = std::min(best, c[i]);
  weights.resize(s.cost.size());
  for (size_t p = 0; p < s.cost.size(); ++p)
    total += weights[p] = std::exp(-(s.cost[p][i] - best) / temperature);
  for (double& w : weights)
    w /= total;
}

} // namespace

std::vector<std::vector<double>> planeProbabilities(const generator::GeneratorInput& in,
                                                    const std::vector<double>& depths,
                                                    const PlaneSweepStereoOptions& o, int height,
                                                    int width) {
  checkOptions(o);
  checkDivides(in, height, width);
  const int H = int(in.images.size(2)), W = int(in.images.size(3));
  ocl::NoGradGuard noGrad;
  const SweepStatistics s = sweepStatistics(in, depths, o);
  const size_t HW = size_t(H) * W, P = depths.size();
  const int fy = H / height, fx = W / width;
  std::vector<std::vector<double>> out(P, std::vector<double>(size_t(height) * width, 0.0));
  std::vector<double> w;
  for (size_t i = 0; i < HW; ++i) {
    softmin(s, i, o.temperature, w);
    const size_t y = i / size_t(W), x = i % size_t(W);
    const size_t j = (y / size_t(fy)) * size_t(width) + x / size_t(fx);
    for (size_t p = 0; p < P; ++p)
      out[p][j] += w[p] / (double(fy) * fx);
  }
  return out;
}

int windowPixels(const PlaneSweepStereoOptions& o, int width) {
  const int n = int(std::lround(o.windowFraction * width));
  return std::max(1, n % 2 == 1 ? n : n + 1);
}

void checkDivides(const generator::GeneratorInput& in, int height, int width) {
  const int H = int(in.images.size(2)), W = int(in.images.size(3));
  if (height < 1 || width < 1 || H % height != 0 || W % width != 0)
    fail("plane-sweep stereo: ", width, " x ", height, " does not divide the input's ", W, " x ",
         H);
}

void checkOptions(const PlaneSweepStereoOptions& o) {
  if (o.planes < 2 || o.planes > 4096)
    fail("plane-sweep stereo: planes ", o.planes, " must be 2 .. 4096");
  if (!(o.windowFraction >= 0 && o.windowFraction <= 1))
    fail("plane-sweep stereo: windowFraction ", o.windowFraction, " must be in [0, 1]");
  if (!(o.temperature > 0 && std::isfinite(o.temperature)))
    fail("plane-sweep stereo: temperature ", o.temperature, " must be finite and > 0");
  if (o.planesPerChunk < 1)
    fail("plane-sweep stereo: planesPerChunk ", o.planesPerChunk, " must be >= 1");
}

generator::GeneratorOutput planeSweepStereo(const generator::GeneratorInput& in,
                                            const PlaneSweepStereoOptions& o) {
  checkOptions(o);
  if (in.images.dim() != 4 || in.images.size(1) != 3 || in.images.size(0) < 1)
    fail("plane-sweep stereo: images ", in.images.describe(), " are not [V >= 1, 3, H, W]");
  if (size_t(in.images.size(0)) != in.sources.size())
    fail("plane-sweep stereo: ", in.images.size(0), " images for ", in.sources.size(),
         " source cameras");
  ocl::NoGradGuard noGrad;
  const double near = in.minDepth > 0 ? in.minDepth : 1.0;
  double far = in.maxDepth > 0 ? in.maxDepth : 100.0;
  if (std::isinf(far))
    far = near * 1e6; // as the generator: finite, indistinguishable from infinity
  const std::vector<double> depths = geometry::planeDepths(o.planes, near, far);
  const int H = int(in.images.size(2)), W = int(in.images.size(3));
  const size_t HW = size_t(H) * W;
  const SweepStatistics s = sweepStatistics(in, depths, o);

  std::vector<float> rgba(4 * HW), depth(HW);
  std::vector<double> weight;
  for (size_t i = 0; i < HW; ++i) {
    softmin(s, i, o.temperature, weight);
    double disparity = 0;
    for (size_t p = 0; p < depths.size(); ++p)
      disparity += weight[p] / depths[p];
    size_t nearest = 0;
    for (size_t p = 1; p < depths.size(); ++p)
      if (std::abs(1.0 / depths[p] - disparity) < std::abs(1.0 / depths[nearest] - disparity))
        nearest = p;
    depth[i] = float(1.0 / disparity);
    for (int c = 0; c < 3; ++c)
      rgba[c * HW + i] = s.colour[nearest][c * HW + i];
    rgba[3 * HW + i] = 1.0f;
  }
  generator::GeneratorOutput out;
  out.rgba = ocl::Tensor::fromHost(rgba, {1, 4, H, W});
  out.depth = ocl::Tensor::fromHost(depth, {1, H, W});
  out.planeDepths = depths;
  return out;
}

} // namespace simpli::baselines
