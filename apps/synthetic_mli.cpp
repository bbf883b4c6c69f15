// The synthetic MLI of `simpli bench render --synthetic` (see synthetic_mli.h).
#include "synthetic_mli.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

namespace simpli::app {

namespace {

// Smooth value noise in [0, 1] with `octaves` octaves, lattice spacing `cell` texels.
class ValueNoise {
public:
  explicit ValueNoise(std::uint32_t seed) : seed_(seed) {}
  double operator()(double x, double y, double cell, int octaves) const {
    double sum = 0, weight = 0, amplitude = 1;
    for (int o = 0; o < octaves; ++o, cell *= 0.5, amplitude *= 0.5) {
      sum += amplitude * smooth(x / cell, y / cell, static_cast<std::uint32_t>(o));
      weight += amplitude;
    }
    return sum / weight;
  }

private:
  double lattice(std::int64_t i, std::int64_t j, std::uint32_t octave) const {
    std::uint32_t h = seed_ ^ (static_cast<std::uint32_t>(i) * 0x8da6b343u) ^
                      (static_cast<std::uint32_t>(j) * 0xd8163841u) ^ (octave * 0xcb1ab31fu);
    h ^= h >> 13;
    h *= 0x5bd1e995u;
    h ^= h >> 15;
    return (h & 0xffffff) / static_cast<double>(0xffffff);
  }
  double smooth(double x, double y, std::uint32_t octave) const {
    const double fx = std::floor(x), fy = std::floor(y);
    const auto i = static_cast<std::int64_t>(fx), j = static_cast<std::int64_t>(fy);
    const double s = x - fx, t = y - fy;
    const double u = s * s * (3 - 2 * s), v = t * t * (3 - 2 * t);
    const double a = lattice(i, j, octave), b = lattice(i + 1, j, octave);
    const double c = lattice(i, j + 1, octave), d = lattice(i + 1, j + 1, octave);
    return a + u * (b - a) + v * (c - a) + u * v * (a - b - c + d);
  }
  std::uint32_t seed_;
};

double clamp01(double v) {
  return std::min(1.0, std::max(0.0, v));
}

void setTexel(mli::MLILayer& layer, std::size_t p, double depth, double r, double g, double b,
              double a) {
  layer.depth[p] = static_cast<float>(depth);
  layer.rgba[4 * p + 0] = static_cast<float>(clamp01(r));
  layer.rgba[4 * p + 1] = static_cast<float>(clamp01(g));
  layer.rgba[4 * p + 2] = static_cast<float>(clamp01(b));
  layer.rgba[4 * p + 3] = static_cast<float>(clamp01(a));
}

} // namespace

// A forward-facing scene as SIMPLI's layers look (layer 0 farthest): an opaque background
// receding towards the top (a slanted surface with fine texture), rolling hills over part of
// the image, three spheres with soft edges, and sparse foliage near the camera. Depths are ordered
// per texel (each layer nearer than the one behind it).
mli::MLI syntheticMLI(int W, int H) {
  scene::Camera ref;
  ref.fx = 0.9;
  ref.fy = 0.9 * W / H;
  ref.width = W;
  ref.height = H;
  mli::MLI mli = mli::MLI::allocate(ref, 4);
  const ValueNoise noise(20230101u);
  const double scale = W / 1008.0; // features keep their size in the image
  for (int i = 0; i < H; ++i)
    for (int j = 0; j < W; ++j) {
      const std::size_t p = static_cast<std::size_t>(i) * W + j;
      const double u = j / (W - 1.0), v = i / (H - 1.0);
      const double n1 = noise(j, i, 40 * scale, 4), n2 = noise(j + 500, i, 12 * scale, 3);
      // Background: 1/z from 1/40 at the top to 1/12 at the bottom.
      setTexel(mli.layers[0], p, 1.0 / (0.025 + 0.058 * v), 0.3 + 0.5 * n1, 0.45 + 0.3 * n2,
               0.6 - 0.4 * v + 0.2 * n2, 1.0);
      // Hills: depth 7..9, visible where a coarse noise is high, with a soft edge.
      const double hill = noise(j + 2000, i + 100, 160 * scale, 2);
      setTexel(mli.layers[1], p, 8.0 + std::sin(4 * u) * std::cos(3 * v), 0.25 + 0.4 * n2,
               0.5 + 0.3 * n1, 0.2, (hill - 0.45) * 12.0);
      // Round objects: spheres at depth ~4.5 (their depth bulge, 0.5, is about their radius
      // in scene units at this focal length), soft 3-texel edges.
      double depth2 = 4.5, alpha2 = 0.0, shade = 0.0;
      for (const auto& [cu, cv, radius] :
           {std::array<double, 3>{0.3, 0.6, 0.12}, std::array<double, 3>{0.7, 0.45, 0.09},
            std::array<double, 3>{0.55, 0.8, 0.07}}) {
        const double r = std::hypot((u - cu) * W, (v - cv) * H) / (radius * W);
        const double edge = clamp01((1.0 - r) * radius * W / 3.0);
        if (edge > alpha2) {
          alpha2 = edge;
          depth2 = 4.5 - 0.5 * std::sqrt(std::max(0.0, 1.0 - r * r));
          shade = 1.0 - 0.5 * r;
        }
      }
      setTexel(mli.layers[2], p, depth2, 0.8 * shade + 0.2 * n2, 0.3 * shade, 0.35 * n1, alpha2);
      // Foliage: depth 2..2.4 in the top-left third, alpha from fine noise.
      const double leaf = noise(j + 4000, i + 3000, 6 * scale, 2);
      const double region = clamp01((0.45 - std::hypot(u - 0.1, v - 0.15)) * 8.0);
      setTexel(mli.layers[3], p, 2.0 + 0.4 * u, 0.2 + 0.3 * leaf, 0.55 + 0.3 * n2, 0.15,
               region * clamp01((leaf - 0.5) * 6.0) * 0.9);
    }
  return mli;
}

} // namespace simpli::app
