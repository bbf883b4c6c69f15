#include "raster_reference.h"

#include "simpli/ocl/tensor.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <utility>

namespace simpli::test {
namespace {

constexpr int64_t kSnap = int64_t(1) << 30;
constexpr double kGuard = 4194304.0;
constexpr double kEdgeTolerance = 1e-3;  // pixels
constexpr double kDepthTolerance = 1e-6; // relative

struct Vertex {
  double x = 0, y = 0, z = 0;
  int64_t sx = 0, sy = 0;
  bool ok = false;
};

int sideOf(const Vertex& a, int ia, const Vertex& b, int ib, int64_t qx, int64_t qy) {
  // Canonical direction: lower vertex index first; ties broken by moving q by (eps, eps^2).
  const bool flip = ia > ib;
  const Vertex& o = flip ? b : a;
  const Vertex& e = flip ? a : b;
  const int64_t dx = e.sx - o.sx, dy = e.sy - o.sy;
  const __int128 f = __int128(dx) * (qy - o.sy) - __int128(dy) * (qx - o.sx);
  int s;
  if (f != 0)
    s = f > 0 ? 1 : -1;
  else if (dy != 0)
    s = dy < 0 ? 1 : -1;
  else
    s = dx > 0 ? 1 : -1;
  return flip ? -s : s;
}

double segmentDistance(double px, double py, const Vertex& a, const Vertex& b) {
  const double dx = b.x - a.x, dy = b.y - a.y;
  const double len2 = dx * dx + dy * dy;
  double t = len2 > 0 ? ((px - a.x) * dx + (py - a.y) * dy) / len2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return std::hypot(px - (a.x + t * dx), py - (a.y + t * dy));
}

int64_t floorDiv(int64_t a, int64_t b) {
  return a >= 0 ? a / b : -((-a + b - 1) / b);
}

struct Fragment {
  double z;
  int id;
  int v[3];
  double lam[3];
};

} // namespace

ocl::Tensor LayerScene::depthTensor(ocl::Dtype dtype) const {
  return ocl::Tensor::fromHost(depth, {L, H, W}, dtype);
}

ocl::Tensor LayerScene::attrTensor(ocl::Dtype dtype) const {
  return ocl::Tensor::fromHost(attrs, {L, A, H, W}, dtype);
}

int ReferenceImage::ambiguousCount() const {
  return static_cast<int>(std::count(ambiguous.begin(), ambiguous.end(), 1));
}

ReferenceImage referenceRender(const LayerScene& s) {
  const int Ht = s.target.height, Wt = s.target.width, K = s.settings.maxFragments;
  const int L = s.L, H = s.H, W = s.W, A = s.A;
  const double nearZ = s.settings.nearZ;
  const double farZ = (s.settings.farZ > 0 && std::isfinite(s.settings.farZ))
                          ? s.settings.farZ
                          : std::numeric_limits<double>::infinity();
  const bool perspective =
      s.settings.interpolation == raster::RasterInterpolation::PerspectiveCorrect;
  ReferenceImage out;
  out.Ht = Ht;
  out.Wt = Wt;
  out.K = K;
  out.A = A;
  const std::size_t plane = std::size_t(Ht) * Wt;
  out.colour.assign((A - 1) * plane, 0.0);
  out.opacity.assign(plane, 0.0);
  out.depth.assign(plane, 0.0);
  out.weights.assign(K * plane, 0.0);
  out.ids.assign(K * plane, -1);
  out.ambiguous.assign(plane, 0);

  // Vertices through world coordinates.
  const int NV = L * H * W;
  std::vector<Vertex> vert(NV);
  std::vector<char> nearAmbiguous(NV, 0);
  for (int v = 0; v < NV; ++v) {
    const int loc = v % (H * W), i = loc / W, j = loc % W;
    const Eigen::Vector2d uv(double(j) / (W - 1), double(i) / (H - 1));
    const Eigen::Vector3d Xc = s.target.worldToCamera(s.reference.backproject(uv, s.depth[v]));
    Vertex& p = vert[v];
    p.z = Xc.z();
    nearAmbiguous[v] = std::abs(Xc.z() - nearZ) < 1e-9 * std::max(1.0, nearZ);
    if (!Xc.allFinite() || !(Xc.z() > nearZ))
      continue;
    p.x = s.target.fx * Wt * Xc.x() / Xc.z() + s.target.cx * Wt;
    p.y = s.target.fy * Ht * Xc.y() / Xc.z() + s.target.cy * Ht;
    if (std::abs(p.x) > kGuard || std::abs(p.y) > kGuard)
      continue;
    p.ok = true;
    p.sx = static_cast<int64_t>(std::nearbyint(p.x * double(kSnap)));
    p.sy = static_cast<int64_t>(std::nearbyint(p.y * double(kSnap)));
  }

  // Usable triangles and, per edge, the triangles that use it (for silhouettes and folds).
  const int64_t numTri = int64_t(L) * 2 * (H - 1) * (W - 1);
  std::vector<char> usable(numTri, 0);
  std::vector<std::array<int64_t, 3>> tv(numTri);
  std::map<std::pair<int64_t, int64_t>, std::vector<std::pair<int64_t, int64_t>>> edges;
  for (int64_t t = 0; t < numTri; ++t) {
    tv[t] = raster::layerTriangleVertices(t, H, W);
    const Vertex &a = vert[tv[t][0]], &b = vert[tv[t][1]], &c = vert[tv[t][2]];
    if (!a.ok || !b.ok || !c.ok)
      continue;
    const __int128 area =
        __int128(b.sx - a.sx) * (c.sy - a.sy) - __int128(b.sy - a.sy) * (c.sx - a.sx);
    if (area == 0 || (a.z > farZ && b.z > farZ && c.z > farZ))
      continue;
    usable[t] = 1;
    for (int e = 0; e < 3; ++e) {
      const int64_t p = tv[t][(e + 1) % 3], q = tv[t][(e + 2) % 3];
      edges[{std::min(p, q), std::max(p, q)}].push_back({t, tv[t][e]});
    }
  }
  auto smooth = [&](int64_t p, int64_t q) {
    const auto& users = edges[{std::min(p, q), std::max(p, q)}];
    if (users.size() != 2)
      return false;
    const Vertex &a = vert[p], &b = vert[q];
    double side[2];
    for (int k = 0; k < 2; ++k) {
      const Vertex& o = vert[users[k].second];
      side[k] = (b.x - a.x) * (o.y - a.y) - (b.y - a.y) * (o.x - a.x);
    }
    return side[0] * side[1] < 0;
  };

  std::vector<std::vector<Fragment>> frags(plane);
  for (int64_t t = 0; t < numTri; ++t) {
    if (!usable[t])
      continue;
    const auto& v = tv[t];
    const Vertex* P[3] = {&vert[v[0]], &vert[v[1]], &vert[v[2]]};
    const __int128 area = __int128(P[1]->sx - P[0]->sx) * (P[2]->sy - P[0]->sy) -
                          __int128(P[1]->sy - P[0]->sy) * (P[2]->sx - P[0]->sx);
    const int orient = area > 0 ? 1 : -1;
    const double floatArea = std::abs((P[1]->x - P[0]->x) * (P[2]->y - P[0]->y) -
                                      (P[1]->y - P[0]->y) * (P[2]->x - P[0]->x));
    bool silhouette[3];
    for (int e = 0; e < 3; ++e)
      silhouette[e] = !smooth(v[(e + 1) % 3], v[(e + 2) % 3]);
    const bool nearEdge = nearAmbiguous[v[0]] || nearAmbiguous[v[1]] || nearAmbiguous[v[2]];
    int64_t xmin = P[0]->sx, xmax = xmin, ymin = P[0]->sy, ymax = ymin;
    for (int k = 1; k < 3; ++k) {
      xmin = std::min(xmin, P[k]->sx);
      xmax = std::max(xmax, P[k]->sx);
      ymin = std::min(ymin, P[k]->sy);
      ymax = std::max(ymax, P[k]->sy);
    }
    // One pixel of margin for the ambiguity marks (float may snap a unit differently).
    const int64_t mid = kSnap / 2;
    const int64_t c0 = std::max<int64_t>(-floorDiv(mid - xmin, kSnap) - 1, 0);
    const int64_t c1 = std::min<int64_t>(floorDiv(xmax - mid, kSnap) + 1, Wt - 1);
    const int64_t r0 = std::max<int64_t>(-floorDiv(mid - ymin, kSnap) - 1, 0);
    const int64_t r1 = std::min<int64_t>(floorDiv(ymax - mid, kSnap) + 1, Ht - 1);
    for (int64_t r = r0; r <= r1; ++r)
      for (int64_t c = c0; c <= c1; ++c) {
        const std::size_t pix = std::size_t(r) * Wt + c;
        const double px = c + 0.5, py = r + 0.5;
        if (floatArea < 1e-3 || nearEdge)
          out.ambiguous[pix] = 1;
        for (int e = 0; e < 3; ++e)
          if (silhouette[e] &&
              segmentDistance(px, py, *P[(e + 1) % 3], *P[(e + 2) % 3]) < kEdgeTolerance)
            out.ambiguous[pix] = 1;
        const int64_t qx = kSnap * c + mid, qy = kSnap * r + mid;
        const int s0 = sideOf(*P[1], int(v[1]), *P[2], int(v[2]), qx, qy);
        const int s1 = sideOf(*P[2], int(v[2]), *P[0], int(v[0]), qx, qy);
        const int s2 = sideOf(*P[0], int(v[0]), *P[1], int(v[1]), qx, qy);
        if (s0 != s1 || s1 != s2)
          continue;
        double e[3], b[3], sum = 0;
        for (int i = 0; i < 3; ++i) {
          const Vertex &a = *P[(i + 1) % 3], &d = *P[(i + 2) % 3];
          e[i] = orient * ((d.x - a.x) * (py - a.y) - (d.y - a.y) * (px - a.x));
          sum += std::max(e[i], 0.0);
        }
        for (int i = 0; i < 3; ++i)
          b[i] = sum > 1e-12 ? std::max(e[i], 0.0) / sum : 1.0 / 3.0;
        Fragment f;
        f.id = static_cast<int>(t);
        double z = 0;
        if (perspective) {
          double q = 0;
          for (int i = 0; i < 3; ++i)
            q += b[i] / P[i]->z;
          for (int i = 0; i < 3; ++i)
            f.lam[i] = b[i] / P[i]->z / q;
          z = 1.0 / q;
        } else {
          for (int i = 0; i < 3; ++i) {
            f.lam[i] = b[i];
            z += b[i] * P[i]->z;
          }
        }
        if (std::abs(z - farZ) < kDepthTolerance * std::max(1.0, farZ))
          out.ambiguous[pix] = 1;
        if (z > farZ)
          continue;
        f.z = z;
        for (int i = 0; i < 3; ++i)
          f.v[i] = static_cast<int>(v[i]);
        frags[pix].push_back(f);
      }
  }

  auto attr = [&](int v, int ch) {
    const int layer = v / (H * W);
    return s.attrs[(std::size_t(layer) * A + ch) * H * W + v % (H * W)];
  };
  for (std::size_t pix = 0; pix < plane; ++pix) {
    auto& fl = frags[pix];
    std::sort(fl.begin(), fl.end(), [](const Fragment& a, const Fragment& b) {
      return a.z < b.z || (a.z == b.z && a.id < b.id);
    });
    for (std::size_t k = 1; k < fl.size() && k <= std::size_t(K); ++k)
      if (std::abs(fl[k].z - fl[k - 1].z) < kDepthTolerance * std::max(1.0, std::abs(fl[k].z)))
        out.ambiguous[pix] = 1;
    const int n = std::min<int>(static_cast<int>(fl.size()), K);
    double trans = 1.0;
    for (int k = 0; k < n; ++k) {
      const Fragment& f = fl[k];
      double a = 0;
      for (int i = 0; i < 3; ++i)
        a += f.lam[i] * attr(f.v[i], A - 1);
      if (k == n - 1)
        a = 1.0;
      const double w = a * trans;
      trans *= (1.0 - a) + 1e-6;
      out.weights[k * plane + pix] = w;
      out.ids[k * plane + pix] = f.id;
      out.depth[pix] += w * f.z;
      for (int ch = 0; ch < A - 1; ++ch) {
        double val = 0;
        for (int i = 0; i < 3; ++i)
          val += f.lam[i] * attr(f.v[i], ch);
        out.colour[ch * plane + pix] += w * val;
      }
    }
    for (int k = n; k < K; ++k)
      trans *= 1.0 + 1e-6;
    out.opacity[pix] = n > 0 ? 1.0 - trans : 0.0;
  }
  return out;
}

DeviceImage download(const raster::RenderedLayers& r) {
  return {r.colour.toVector(), r.opacity.toVector(), r.depth.toVector(), r.weights.toVector()};
}

double maxRelativeError(const DeviceImage& d, const ReferenceImage& ref) {
  const std::size_t plane = std::size_t(ref.Ht) * ref.Wt;
  double worst = 0;
  auto compare = [&](const std::vector<double>& got, const std::vector<double>& want,
                     const char* what) {
    EXPECT_EQ(got.size(), want.size()) << what;
    if (got.size() != want.size())
      return;
    for (std::size_t i = 0; i < got.size(); ++i) {
      EXPECT_TRUE(std::isfinite(got[i])) << what << "[" << i << "] = " << got[i];
      if (ref.ambiguous[i % plane])
        continue;
      const double err = std::abs(got[i] - want[i]) / std::max(1.0, std::abs(want[i]));
      worst = std::max(worst, err);
    }
  };
  compare(d.colour, ref.colour, "colour");
  compare(d.opacity, ref.opacity, "opacity");
  compare(d.depth, ref.depth, "depth");
  compare(d.weights, ref.weights, "weights");
  return worst;
}

Eigen::Matrix3d smallRotation(double degrees, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Vector3d axis(n(rng), n(rng), n(rng));
  axis.normalize();
  return Eigen::AngleAxisd(degrees * M_PI / 180.0, axis).toRotationMatrix();
}

scene::Camera makeCamera(double fx, double fy, double cx, double cy, int width, int height,
                         const Eigen::Matrix3d& R, const Eigen::Vector3d& t) {
  scene::Camera c;
  c.fx = fx;
  c.fy = fy;
  c.cx = cx;
  c.cy = cy;
  c.width = width;
  c.height = height;
  c.R = R;
  c.t = t;
  return c;
}

scene::Camera cornerGridCamera(const scene::Camera& ref, int W, int H) {
  // Target u_t = a u_r + b with u_r = j/(W-1) -> u_t = (j + 0.5)/W: a = (W-1)/W, b = 0.5/W.
  scene::Camera c = ref;
  const double ax = double(W - 1) / W, ay = double(H - 1) / H;
  c.fx = ref.fx * ax;
  c.cx = ref.cx * ax + 0.5 / W;
  c.fy = ref.fy * ay;
  c.cy = ref.cy * ay + 0.5 / H;
  c.width = W;
  c.height = H;
  return c;
}

std::vector<double> randomValues(std::size_t n, double lo, double hi, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> d(lo, hi);
  std::vector<double> out(n);
  for (auto& x : out)
    x = d(rng);
  return out;
}

} // namespace simpli::test
