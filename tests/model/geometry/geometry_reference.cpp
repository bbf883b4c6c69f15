#include "geometry_reference.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

namespace simpli::geomtest {

double gridSample(const double* plane, int H, int W, double gx, double gy) {
  const double sx = ((gx + 1) * W - 1) / 2, sy = ((gy + 1) * H - 1) / 2;
  if (!(std::isfinite(sx) && std::isfinite(sy)))
    return 0.0;
  const double fx = std::floor(sx), fy = std::floor(sy);
  if (fx < -2 || fx > W + 1 || fy < -2 || fy > H + 1)
    return 0.0;
  const int x0 = static_cast<int>(fx), y0 = static_cast<int>(fy);
  const double tx = sx - fx, ty = sy - fy;
  auto at = [&](int y, int x) {
    return (x >= 0 && x < W && y >= 0 && y < H) ? plane[y * W + x] : 0.0;
  };
  return (1 - ty) * ((1 - tx) * at(y0, x0) + tx * at(y0, x0 + 1)) +
         ty * ((1 - tx) * at(y0 + 1, x0) + tx * at(y0 + 1, x0 + 1));
}

Eigen::Vector2d gridOf(const scene::Camera& camera, const Eigen::Vector3d& world) {
  return 2.0 * camera.project(world) - Eigen::Vector2d::Ones();
}

Eigen::Vector3d planePoint(const scene::Camera& ref, int x, int y, int h, int w, double d) {
  const Eigen::Vector2d uv((x + 0.5) / w, (y + 0.5) / h);
  const Eigen::Vector3d C = ref.centre();
  const Eigen::Vector3d r = (ref.backproject(uv, 1.0) - C).normalized();
  const Eigen::Vector3d n = ref.R.transpose() * Eigen::Vector3d::UnitZ();
  const double tau = (d + n.dot(C - C)) / (n.dot(r) + 1e-7);
  return C + tau * r;
}

Eigen::Vector3d layerPoint(const scene::Camera& ref, int x, int y, int h, int w, double d) {
  const Eigen::Vector2d uv(static_cast<double>(x) / (w - 1), static_cast<double>(y) / (h - 1));
  return ref.backproject(uv, d);
}

CpuSamples sampleSurfaces(const std::vector<double>& src, bool perSurface, int C, int Hs, int Ws,
                          const std::vector<scene::Camera>& views, int S, int h, int w,
                          const PointFn& point) {
  const int V = static_cast<int>(views.size());
  const std::size_t plane = static_cast<std::size_t>(Hs) * Ws, hw = std::size_t(h) * w;
  CpuSamples out;
  out.samples.assign(std::size_t(V) * S * C * hw, 0.0);
  out.mask.assign(std::size_t(V) * S * hw, 0.0);
  for (int s = 0; s < S; ++s)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const Eigen::Vector3d X = point(s, x, y);
        for (int v = 0; v < V; ++v) {
          const Eigen::Vector2d g = gridOf(views[v], X);
          const std::size_t pix = std::size_t(y) * w + x;
          out.mask[(std::size_t(v) * S + s) * hw + pix] =
              (std::fabs(g.x()) <= 1 && std::fabs(g.y()) <= 1) ? 1.0 : 0.0;
          for (int c = 0; c < C; ++c) {
            const std::size_t map =
                perSurface ? (std::size_t(v) * S + s) * C + c : std::size_t(v) * C + c;
            out.samples[((std::size_t(v) * S + s) * C + c) * hw + pix] =
                gridSample(src.data() + map * plane, Hs, Ws, g.x(), g.y());
          }
        }
      }
  return out;
}

std::vector<double> meanVar(const CpuSamples& s, const std::vector<double>& gatheredWeights, int V,
                            int S, int C, int h, int w) {
  const std::size_t hw = std::size_t(h) * w;
  std::vector<double> out(std::size_t(S) * 2 * C * hw);
  std::vector<double> wv(V);
  for (int p = 0; p < S; ++p)
    for (std::size_t pix = 0; pix < hw; ++pix) {
      double msum = 0;
      for (int v = 0; v < V; ++v)
        msum += s.mask[(std::size_t(v) * S + p) * hw + pix];
      for (int v = 0; v < V; ++v) {
        const std::size_t i = (std::size_t(v) * S + p) * hw + pix;
        wv[v] = s.mask[i] / (msum + 1e-7);
        if (!gatheredWeights.empty())
          wv[v] *= gatheredWeights[i];
      }
      for (int c = 0; c < C; ++c) {
        auto sample = [&](int v) {
          return s.samples[((std::size_t(v) * S + p) * C + c) * hw + pix];
        };
        double mean = 0, var = 0;
        for (int v = 0; v < V; ++v)
          mean += wv[v] * sample(v);
        for (int v = 0; v < V; ++v)
          var += wv[v] * (sample(v) - mean) * (sample(v) - mean);
        out[(std::size_t(p) * 2 * C + c) * hw + pix] = mean;
        out[(std::size_t(p) * 2 * C + C + c) * hw + pix] = var;
      }
    }
  return out;
}

CpuRender compose(const std::vector<double>& features, int N, int P, int C1, int Ht, int Wt) {
  const int C = C1 - 1;
  const std::size_t hw = std::size_t(Ht) * Wt;
  CpuRender r;
  r.color.assign(std::size_t(N) * C * hw, 0.0);
  r.opacity.assign(std::size_t(N) * hw, 0.0);
  r.weights.assign(std::size_t(N) * P * hw, 0.0);
  std::vector<double> a(P), T(P);
  for (int n = 0; n < N; ++n)
    for (std::size_t pix = 0; pix < hw; ++pix) {
      auto f = [&](int p, int c) {
        return features[((std::size_t(n) * P + p) * C1 + c) * hw + pix];
      };
      // ComposerStereoMagnification.precompute_features: clamp, masked background, then the
      // transmittance as a cumulative product over the flipped planes.
      double sum = 0;
      for (int p = 0; p < P; ++p) {
        a[p] = std::clamp(f(p, C), 0.0, 1.0);
        sum += a[p];
      }
      a[0] = sum > 1e-6 ? 1.0 : 0.0;
      double cum = 1;
      for (int p = P - 1; p >= 0; --p) {
        T[p] = cum;
        cum *= 1 - a[p] + 1e-6;
      }
      r.opacity[std::size_t(n) * hw + pix] = 1 - cum;
      for (int p = 0; p < P; ++p) {
        const double wp = a[p] * T[p];
        r.weights[(std::size_t(n) * P + p) * hw + pix] = wp;
        for (int c = 0; c < C; ++c)
          r.color[(std::size_t(n) * C + c) * hw + pix] += wp * f(p, c);
      }
    }
  return r;
}

CpuRender renderMpi(const std::vector<double>& mpi, int P, int C1, int h, int w,
                    const std::vector<double>& depths, const scene::Camera& ref,
                    const std::vector<scene::Camera>& targets, int Ht, int Wt) {
  const int N = static_cast<int>(targets.size());
  const std::size_t hw = std::size_t(h) * w, hwt = std::size_t(Ht) * Wt;
  std::vector<double> features(std::size_t(N) * P * C1 * hwt);
  const Eigen::Vector3d n = ref.R.transpose() * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d Cref = ref.centre();
  for (int k = 0; k < N; ++k) {
    const scene::Camera& cam = targets[k];
    const Eigen::Vector3d Cc = cam.centre();
    for (int y = 0; y < Ht; ++y)
      for (int x = 0; x < Wt; ++x) {
        const Eigen::Vector2d uv((x + 0.5) / Wt, (y + 0.5) / Ht);
        const Eigen::Vector3d r = (cam.backproject(uv, 1.0) - Cc).normalized();
        for (int p = 0; p < P; ++p) {
          const double tau = (depths[p] + n.dot(Cref - Cc)) / (n.dot(r) + 1e-7);
          const Eigen::Vector2d g = gridOf(ref, Cc + tau * r);
          for (int c = 0; c < C1; ++c)
            features[((std::size_t(k) * P + p) * C1 + c) * hwt + std::size_t(y) * Wt + x] =
                gridSample(mpi.data() + (std::size_t(p) * C1 + c) * hw, h, w, g.x(), g.y());
        }
      }
  }
  return compose(features, N, P, C1, Ht, Wt);
}

Eigen::Matrix3d rotation(double a, double b, double c) {
  const Eigen::Matrix3d Ry = Eigen::AngleAxisd(a, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Eigen::Matrix3d Rx = Eigen::AngleAxisd(b, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Eigen::Matrix3d Rz = Eigen::AngleAxisd(c, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return Ry * Rx * Rz;
}

scene::Camera randomCamera(std::mt19937_64& rng, double maxAngle, double baseline) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  scene::Camera c;
  c.R = rotation(maxAngle * u(rng), maxAngle * u(rng), maxAngle * u(rng));
  const Eigen::Vector3d centre(baseline * u(rng), baseline * u(rng), baseline * u(rng));
  c.t = -c.R * centre;
  c.fx = 1.0 + 0.1 * u(rng);
  c.fy = 1.3 + 0.1 * u(rng);
  c.cx = 0.5 + 0.02 * u(rng);
  c.cy = 0.5 + 0.02 * u(rng);
  return c;
}

scene::Camera referenceCamera() {
  scene::Camera c;
  c.fx = 1.0;
  c.fy = 1.3;
  return c;
}

std::vector<double> randomValues(std::size_t n, double low, double high, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(low, high);
  std::vector<double> v(n);
  for (auto& x : v)
    x = u(rng);
  return v;
}

double relError(const std::vector<double>& a, const std::vector<double>& b, double floor) {
  if (a.size() != b.size())
    return std::numeric_limits<double>::infinity();
  double maxRef = floor, maxDiff = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (!std::isfinite(a[i]))
      return std::numeric_limits<double>::infinity();
    maxRef = std::max(maxRef, std::fabs(b[i]));
    maxDiff = std::max(maxDiff, std::fabs(a[i] - b[i]));
  }
  return maxDiff / maxRef;
}

bool allFinite(const std::vector<double>& v) {
  return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
}

double kinkMargin(double g, int n) {
  const double s = ((g + 1) * n - 1) / 2;
  const double toKink = std::fabs(s - std::round(s));
  const double toBorder = std::fabs(std::fabs(g) - 1) * n / 2;
  return std::min(toKink, toBorder);
}

} // namespace simpli::geomtest
