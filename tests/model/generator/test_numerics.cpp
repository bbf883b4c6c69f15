// Numerical extremes, measured (docs/numerics.md): one table of cases for the whole forward
// pass of the tiny network (depth ranges from 1e-3 to 1e6 and far = infinity, decoder logits
// of +-1e4 so that every alpha saturates at 0 or 1, 1 and 16 views, grazing source cameras),
// each run in float32 and float64 with the same parameters and inputs. Per case:
//  - every output finite, alpha in [0, 1], RGB in [-1, 1], layer depths positive, inside the
//    plane range and ordered far to near at every texel;
//  - the MLI (toMLI) valid and a novel view rendered from it finite;
//  - float32 against float64 per stage (rel = max |x32 - x64| / max |x64| over every tensor the
//    stage hook reports), printed as "[numerics]" lines and bounded by the case's tolerance.
// And a known synthetic scene, rendered: two constant layers (an opaque back layer, a front
// layer of alpha 0.5) at depths from 1e-3 to 1e6, seen from the reference camera, a laterally
// shifted camera and a camera rotated to a grazing angle; inside the covered region the render
// is the analytic composite a c_front + (1 - a) c_back within 1e-5 (float64) / 1e-4 (float32).
#include "generator_test_util.h"
#include "support/golden.h"

#include "simpli/error.h"
#include "simpli/model/raster/render_mli.h"
#include "simpli/ocl/autograd.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <map>
#include <string>

namespace simpli {
namespace {

using ocl::Dtype;
using ocl::Tensor;

constexpr double kInf = std::numeric_limits<double>::infinity();

struct ExtremeCase {
  const char* name;
  double near = 0, far = 0; ///< 0, 0: the config's 1 .. 100
  int views = 3;
  double logit = 0;       ///< != 0: every decoder's output bias set to this (alpha 0 or 1)
  double grazingDeg = 0;  ///< != 0: source 1 sees the planes at this angle (see caseInput)
  double stageTol = 1e-4; ///< f32 vs f64 (see compare), levels 0 and 1
  double mliTol = 2e-3;   ///< the MLI corrections and the outputs
  /// The corrections' source renders must show something. Not when every layer is opaque at
  /// its group's nearest plane and all of them lie within 4e-3 of the cameras (logits +1e4,
  /// near 1e-3): there the layers cover only the reference frustum's 4e-3-wide tip, which
  /// sources 0.05 to the side do not see, and an empty render is the right one.
  bool seen = true;
};

std::ostream& operator<<(std::ostream& os, const ExtremeCase& c) {
  return os << c.name;
}

/// Sets the last conv bias of every decoder (alpha, depth, RGBA) to `logit`.
void forceLogits(network::SimpliNetwork& net, double logit) {
  for (const std::string& name : net.parameters().names()) {
    const bool decoder = name.find("decoder") != std::string::npos;
    const bool last = name.find(".model.2.conv.bias") != std::string::npos;
    if (decoder && last) {
      Tensor t = net.parameters().get(name);
      t.copyFromHost(std::vector<double>(static_cast<std::size_t>(t.numel()), logit));
    }
  }
}

generator::GeneratorInput caseInput(const ExtremeCase& c, Dtype dtype) {
  generator::GeneratorInput in = test::syntheticInput(c.views, 32, 48, dtype, 31);
  in.minDepth = c.near;
  in.maxDepth = c.far;
  if (c.grazingDeg != 0) {
    // Source 1 moved sideways to C = (-2 tan(theta), 0, 0) and turned by theta about y, so
    // that it looks at (0, 0, 2) on the nearest plane at theta from the planes' normal.
    const double theta = c.grazingDeg * M_PI / 180.0;
    scene::Camera& s = in.sources[1];
    s.R = Eigen::AngleAxisd(-theta, Eigen::Vector3d::UnitY()).toRotationMatrix();
    s.t = -s.R * Eigen::Vector3d(-2.0 * std::tan(theta), 0.0, 0.0);
  }
  return in;
}

/// max |a - b| / max(max |b|, 1): relative for tensors of magnitude >= 1, absolute below (a
/// tensor that is ~0 everywhere, e.g. the MPI opacity when every alpha is 0, would make a
/// relative error meaningless). Also returns the two maxima.
double compare(const Tensor& a, const Tensor& b, double* err = nullptr, double* mag = nullptr) {
  const std::vector<double> x = a.toVector(), y = b.toVector();
  double e = 0, m = 0;
  for (std::size_t i = 0; i < x.size() && x.size() == y.size(); ++i) {
    const double d = std::fabs(x[i] - y[i]);
    e = std::isnan(d) ? INFINITY : std::max(e, d);
    m = std::max(m, std::fabs(y[i]));
  }
  if (x.size() != y.size())
    e = INFINITY;
  if (err)
    *err = e;
  if (mag)
    *mag = m;
  return e / std::max(m, 1.0);
}

class GeneratorExtremes : public ::testing::TestWithParam<ExtremeCase> {};

TEST_P(GeneratorExtremes, FiniteOrderedAndFloat32MatchesFloat64) {
  const ExtremeCase& c = GetParam();
  ocl::NoGradGuard noGrad;
  auto net32 = test::configNetwork("tiny", Dtype::F32, 11);
  auto net64 = test::configNetwork("tiny", Dtype::F64, 11);
  if (c.logit != 0)
    forceLogits(*net32, c.logit);
  for (const std::string& name : net32->parameters().names()) {
    Tensor target = net64->parameters().get(name); // a handle to the same buffer
    target.copyFromHost(net32->parameters().get(name).toVector());
  }

  std::map<std::string, Tensor> s32, s64;
  generator::GeneratorOptions o32, o64;
  o32.stageHook = [&s32](const std::string& n, const Tensor& t) { s32[n] = t; };
  o64.stageHook = [&s64](const std::string& n, const Tensor& t) { s64[n] = t; };
  const generator::GeneratorInput in32 = caseInput(c, Dtype::F32);
  generator::GeneratorInput in64 = in32;
  in64.images = in32.images.to(Dtype::F64);
  const generator::GeneratorOutput out32 = generator::Generator(*net32).forward(in32, o32);
  const generator::GeneratorOutput out64 = generator::Generator(*net64).forward(in64, o64);

  const double near = c.near > 0 ? c.near : 1.0, far = c.far > 0 ? c.far : 100.0;
  const double farFinite = std::isfinite(far) ? far : near * 1e6; // generator.cpp
  for (const generator::GeneratorOutput* out : {&out32, &out64}) {
    const int S = static_cast<int>(out->rgba.size(0));
    const int64_t n = out->depth.size(1) * out->depth.size(2);
    const std::vector<double> rgba = out->rgba.toVector(), depth = out->depth.toVector();
    for (std::size_t i = 0; i < rgba.size(); ++i) {
      ASSERT_TRUE(std::isfinite(rgba[i])) << "rgba element " << i;
      const bool alpha = (i / static_cast<std::size_t>(n)) % 4 == 3;
      ASSERT_GE(rgba[i], alpha ? 0.0 : -1.0) << i;
      ASSERT_LE(rgba[i], 1.0) << i;
    }
    for (int s = 0; s < S; ++s)
      for (int64_t i = 0; i < n; ++i) {
        const double d = depth[static_cast<std::size_t>(s * n + i)];
        ASSERT_TRUE(std::isfinite(d) && d > 0) << "layer " << s << " texel " << i << ": " << d;
        ASSERT_GE(d, near * (1 - 1e-5)) << "layer " << s << " texel " << i;
        ASSERT_LE(d, farFinite * (1 + 1e-5)) << "layer " << s << " texel " << i;
        if (s > 0) {
          ASSERT_LE(d, depth[static_cast<std::size_t>((s - 1) * n + i)] * (1 + 1e-6))
              << "layer " << s << " texel " << i << " is behind layer " << s - 1;
        }
      }
    const mli::MLI mli = generator::toMLI(*out, in32.reference);
    EXPECT_NO_THROW(mli::validateMLI(mli, c.name));
    raster::RasterSettings wide; // the default near / far cut (0.01 .. 120) would drop them
    wide.nearZ = 1e-2 * near;
    wide.farZ = 0;
    const raster::RenderedLayers view = raster::renderMLI(mli, in32.sources.back(), wide);
    EXPECT_TRUE(test::allFinite(view.colour));
    EXPECT_TRUE(test::allFinite(view.opacity));
  }

  // The corrections' source renders see the surfaces: RGB not all the background (it was,
  // for ranges beyond the rasterizer's default far cut of 120, before generator.cpp widened
  // the cut to the range).
  for (const auto& [name, t] : s64)
    if (c.seen && name.rfind("renderer_lvl", 0) == 0) {
      const std::vector<double> v = t.toVector();
      double m = 0;
      for (double x : v)
        m = std::max(m, std::fabs(x));
      EXPECT_GT(m, 0.01) << name << ": the corrections saw an empty render";
    }

  // Per stage: levels 0 and 1 within stageTol, the corrections (samli*, their renders, the
  // final surfaces) within mliTol.
  ASSERT_EQ(s32.size(), s64.size());
  double worst[2] = {0, 0}, worstErr[2] = {0, 0}, worstMag[2] = {0, 0};
  std::string worstName[2];
  for (const auto& [name, t32] : s32) {
    ASSERT_TRUE(s64.count(name)) << name;
    double err = 0, mag = 0;
    const double rel = compare(t32, s64.at(name), &err, &mag);
    const bool mliStage = name.rfind("samli", 0) == 0 || name.rfind("renderer_lvl", 0) == 0 ||
                          name.rfind("final", 0) == 0 || name == "rgba_decoder_lvl2.out" ||
                          name == "rgba_decoder_lvl3.out" || name == "rgba_decoder_lvl4.out";
    ASSERT_TRUE(std::isfinite(rel)) << name;
    if (rel > worst[mliStage]) {
      worst[mliStage] = rel;
      worstErr[mliStage] = err;
      worstMag[mliStage] = mag;
      worstName[mliStage] = name;
    }
    EXPECT_LE(rel, mliStage ? c.mliTol : c.stageTol) << name;
  }
  const double depthRel = compare(out32.depth, out64.depth);
  const double rgbaRel = compare(out32.rgba, out64.rgba);
  std::cout << "[numerics] " << c.name << ": f32/f64 worst, levels 0-1 " << worst[0] << " ("
            << worstName[0] << ", max err " << worstErr[0] << " of max " << worstMag[0]
            << "), corrections " << worst[1] << " (" << worstName[1] << ", max err " << worstErr[1]
            << " of max " << worstMag[1] << "); output depth " << depthRel << ", rgba " << rgbaRel
            << std::endl;
  EXPECT_LE(depthRel, c.mliTol);
  EXPECT_LE(rgbaRel, c.mliTol);
}

INSTANTIATE_TEST_SUITE_P(
    Table, GeneratorExtremes,
    ::testing::Values(
        ExtremeCase{"config_range"}, ExtremeCase{"near_1em3_far_1e6", 1e-3, 1e6},
        ExtremeCase{"near_1em3_far_1", 1e-3, 1.0}, ExtremeCase{"near_1e3_far_1e6", 1e3, 1e6},
        ExtremeCase{"far_infinity", 1.0, kInf}, ExtremeCase{"near_1em3_far_infinity", 1e-3, kInf},
        ExtremeCase{"thin_1_to_1p000001", 1.0, 1.000001, 3, 0, 0, 1e-4, 1e-2},
        ExtremeCase{"logits_plus_1e4", 0, 0, 3, 1e4},
        ExtremeCase{"logits_minus_1e4", 0, 0, 3, -1e4},
        ExtremeCase{"logits_plus_1e4_near_1em3_far_1e6", 1e-3, 1e6, 3, 1e4, 0, 1e-4, 2e-3, false},
        ExtremeCase{"one_view", 0, 0, 1}, ExtremeCase{"sixteen_views", 0, 0, 16},
        ExtremeCase{"grazing_60deg", 0, 0, 3, 0, 60}, ExtremeCase{"grazing_85deg", 0, 0, 3, 0, 85}),
    [](const ::testing::TestParamInfo<ExtremeCase>& info) { return std::string(info.param.name); });

// ---- a known scene, rendered -------------------------------------------------------------

struct KnownSceneCase {
  const char* name;
  double front, back; ///< layer depths (reference-camera z)
};

std::ostream& operator<<(std::ostream& os, const KnownSceneCase& c) {
  return os << c.name;
}

class KnownSceneRender : public ::testing::TestWithParam<KnownSceneCase> {};

// The reference camera has a wide view (relative fx 0.3: 118 degrees across), so that the
// rotated camera sees the layers at up to ~76 degrees from their normal (grazing).
TEST_P(KnownSceneRender, AnalyticCompositeInsideTheCoveredRegion) {
  const KnownSceneCase& c = GetParam();
  ocl::NoGradGuard noGrad;
  const int H = 48, W = 64;
  scene::Camera ref;
  ref.fx = 0.3;
  ref.fy = 0.3 * W / H;
  ref.width = W;
  ref.height = H;
  mli::MLI mli = mli::MLI::allocate(ref, 2);
  const float back[3] = {0.2f, 0.4f, 0.6f}, front[3] = {0.9f, 0.1f, 0.5f};
  const float a = 0.5f;
  for (std::size_t p = 0; p < mli.texels(); ++p) {
    mli.layers[0].depth[p] = static_cast<float>(c.back);
    mli.layers[1].depth[p] = static_cast<float>(c.front);
    for (int ch = 0; ch < 3; ++ch) {
      mli.layers[0].rgba[4 * p + ch] = back[ch];
      mli.layers[1].rgba[4 * p + ch] = front[ch];
    }
    mli.layers[0].rgba[4 * p + 3] = 1.0f;
    mli.layers[1].rgba[4 * p + 3] = a;
  }
  scene::Camera shifted = ref;
  shifted.fx = shifted.fy = 1.0; // square-ish narrow view inside the reference frustum
  shifted.fy = 1.0 * W / H;
  shifted.t = Eigen::Vector3d(0.02 * c.front, 0.01 * c.front, 0.0);
  scene::Camera turned = ref;
  turned.fx = 1.0;
  turned.fy = 1.0 * W / H;
  turned.R = Eigen::AngleAxisd(50.0 * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
  double worst[2] = {0, 0};
  for (Dtype dtype : {Dtype::F64, Dtype::F32}) {
    // The rasterizer's compositing carries the reference's 1e-6 transmittance offset, so even
    // float64 is ~6e-7 off the exact composite.
    const double tol = dtype == Dtype::F64 ? 2e-6 : 1e-5;
    for (const scene::Camera* camera : {&ref, &shifted, &turned}) {
      raster::RasterSettings wide; // the default near / far cut (0.01 .. 120) would drop them
      wide.nearZ = 1e-2 * c.front;
      wide.farZ = 0;
      const raster::RenderedLayers r = raster::renderMLI(mli, *camera, wide, dtype);
      const std::vector<double> colour = r.colour.toVector(), opacity = r.opacity.toVector();
      ASSERT_TRUE(test::allFinite(r.colour));
      const std::size_t n = static_cast<std::size_t>(H) * W;
      int checked = 0;
      for (int y = 1; y + 1 < H; ++y)
        for (int x = 1; x + 1 < W; ++x) {
          // Inside: this pixel and its 8 neighbours covered (the layers' edges coincide in
          // rays only up to rounding).
          bool inside = true;
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx)
              inside = inside && opacity[static_cast<std::size_t>(y + dy) * W + x + dx] > 0.999;
          if (!inside)
            continue;
          ++checked;
          for (int ch = 0; ch < 3; ++ch) {
            const double expected = double(a) * front[ch] + (1 - double(a)) * back[ch];
            const double e =
                std::fabs(colour[ch * n + static_cast<std::size_t>(y) * W + x] - expected);
            worst[dtype == Dtype::F32] = std::max(worst[dtype == Dtype::F32], e);
            ASSERT_LE(e, tol) << "pixel " << x << ", " << y << " channel " << ch;
          }
        }
      EXPECT_GT(checked, W * H / 8) << "too little of the view is covered to test";
    }
  }
  std::cout << "[numerics] known scene " << c.name << ": worst |render - analytic| f64 " << worst[0]
            << ", f32 " << worst[1] << std::endl;
}

INSTANTIATE_TEST_SUITE_P(Table, KnownSceneRender,
                         ::testing::Values(KnownSceneCase{"depths_1_2", 1.0, 2.0},
                                           KnownSceneCase{"depths_1em3_2em3", 1e-3, 2e-3},
                                           KnownSceneCase{"depths_1e5_1e6", 1e5, 1e6},
                                           KnownSceneCase{"depths_1em3_1e6", 1e-3, 1e6}),
                         [](const ::testing::TestParamInfo<KnownSceneCase>& info) {
                           return std::string(info.param.name);
                         });

} // namespace
} // namespace simpli
