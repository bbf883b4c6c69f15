#include "generator_test_util.h"

#include "support/golden.h"

#include "simpli/model/scene/reference_camera.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace simpli::test {

generator::GeneratorInput goldenInput(ocl::Dtype dtype) {
  const io::SafeTensorsReader& in = goldenFile("inputs");
  const io::HostTensor<double> ext = in.readF64("src_extrinsics"),
                               intr = in.readF64("src_intrinsics");
  generator::GeneratorInput input;
  input.images = goldenTensor("inputs", "images", dtype);
  const int H = static_cast<int>(input.images.size(2)), W = static_cast<int>(input.images.size(3));
  for (int v = 0; v < 3; ++v)
    input.sources.push_back(goldenCamera(&ext.data[12 * v], &intr.data[9 * v], W, H));
  input.reference = goldenCamera(in.readF64("ref_extrinsics").data.data(),
                                 in.readF64("ref_intrinsics").data.data(), W, H);
  input.minDepth = 1.0;
  input.maxDepth = 100.0;
  return input;
}

generator::SourceRenderer goldenStubRenderer(std::vector<ocl::Tensor>* received) {
  return [received](const ocl::Tensor& rgba, const ocl::Tensor& /*depth*/,
                    const generator::GeneratorInput& input, int /*level*/) {
    if (received)
      received->push_back(rgba);
    const std::vector<double> x = rgba.toVector(); // [S, 4, hm, wm]
    const int64_t S = rgba.size(0), hm = rgba.size(2), wm = rgba.size(3);
    const int64_t V = input.images.size(0), h = input.images.size(2), w = input.images.size(3);
    const int64_t n = hm * wm;
    std::vector<double> col(3 * n);
    for (int c = 0; c < 3; ++c)
      for (int64_t i = 0; i < n; ++i)
        col[c * n + i] = x[c * n + i];
    for (int64_t k = 1; k < S; ++k) {
      const double* layer = x.data() + k * 4 * n;
      for (int64_t i = 0; i < n; ++i) {
        const double a = layer[3 * n + i];
        for (int c = 0; c < 3; ++c)
          col[c * n + i] = a * layer[c * n + i] + (1 - a) * col[c * n + i];
      }
    }
    std::vector<double> image(static_cast<std::size_t>(V * 3 * h * w));
    for (int64_t v = 0; v < V; ++v)
      for (int c = 0; c < 3; ++c)
        for (int64_t r = 0; r < h; ++r)
          for (int64_t q = 0; q < w; ++q)
            image[((v * 3 + c) * h + r) * w + q] = col[c * n + (r * hm / h) * wm + (q * wm / w)];
    return ocl::Tensor::fromHost(image, {V, 3, h, w}, rgba.dtype());
  };
}

generator::GeneratorInput syntheticInput(int views, int height, int width, ocl::Dtype dtype,
                                         uint64_t seed) {
  generator::GeneratorInput input;
  for (int v = 0; v < views; ++v) {
    scene::Camera c;
    const double phase = 2.0 * M_PI * v / std::max(views, 1);
    const double radius = views == 1 ? 0.0 : 0.05;
    c.R = (Eigen::AngleAxisd(0.01 * std::sin(phase), Eigen::Vector3d::UnitY()) *
           Eigen::AngleAxisd(0.01 * std::cos(phase), Eigen::Vector3d::UnitX()))
              .toRotationMatrix();
    c.t = Eigen::Vector3d(radius * std::cos(phase), radius * std::sin(phase), 0.01 * v / views);
    c.fx = 1.0;
    c.fy = 1.0 * width / height;
    c.cx = 0.5;
    c.cy = 0.5;
    c.width = width;
    c.height = height;
    input.sources.push_back(c);
  }
  input.reference = scene::referenceCamera(input.sources);
  input.images = ocl::Tensor::uniform({views, 3, height, width}, -1.0, 1.0, seed, dtype);
  return input;
}

std::unique_ptr<network::SimpliNetwork> configNetwork(const std::string& name, ocl::Dtype dtype,
                                                      uint64_t seed) {
  return std::make_unique<network::SimpliNetwork>(
      network::loadNetworkConfig(std::string(SIMPLI_NETWORK_CONFIG_DIR) + "/" + name + ".json"),
      dtype, seed);
}

bool allFinite(const ocl::Tensor& t) {
  for (double v : t.toVector())
    if (!std::isfinite(v))
      return false;
  return true;
}

double maxAbsDiff(const ocl::Tensor& a, const ocl::Tensor& b) {
  EXPECT_EQ(a.shape(), b.shape());
  const std::vector<double> x = a.toVector(), y = b.toVector();
  double d = 0;
  for (size_t i = 0; i < std::min(x.size(), y.size()); ++i)
    d = std::max(d, std::abs(x[i] - y[i]));
  return d;
}

} // namespace simpli::test
