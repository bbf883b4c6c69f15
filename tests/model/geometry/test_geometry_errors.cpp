// Bad use of the geometry ops: every mistake is a simpli::Error naming the op and the offending
// value or shape, never a crash.
#include "geometry_reference.h"

#include <simpli/error.h>
#include <simpli/model/geometry/layer_unproject.h>
#include <simpli/model/geometry/mpi_render.h>
#include <simpli/model/geometry/plane_sweep.h>
#include <simpli/model/geometry/planes.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

namespace simpli {
namespace {

using ocl::Dtype;
using ocl::Tensor;

template <typename F> void expectError(F&& f, const std::vector<std::string>& parts) {
  try {
    f();
    ADD_FAILURE() << "no simpli::Error thrown; expected one mentioning " << parts.front();
  } catch (const Error& e) {
    const std::string message = e.what();
    for (const std::string& p : parts)
      EXPECT_NE(message.find(p), std::string::npos) << "'" << p << "' missing in: " << message;
  }
}

class GeometryErrors : public ::testing::Test {
protected:
  Camera ref = geomtest::referenceCamera();
  std::vector<Camera> views{geomtest::referenceCamera(), geomtest::referenceCamera()};
  Tensor maps = Tensor::zeros({2, 3, 8, 10});
  std::vector<double> depths{1.0, 2.0};
};

TEST_F(GeometryErrors, PlaneDepths) {
  expectError([] { planeDepths(0, 1, 100); }, {"planeDepths", "count 0"});
  expectError([] { planeDepths(41, 0, 100); }, {"planeDepths", "near = 0"});
  expectError([] { planeDepths(41, 10, 1); }, {"planeDepths", "far = 1"});
  expectError([] { planeDepths(41, 1, std::numeric_limits<double>::infinity()); },
              {"planeDepths", "far = inf"});
  EXPECT_EQ(planeDepths(1, 2, 5), std::vector<double>{5.0});
}

TEST_F(GeometryErrors, PlaneSweepArguments) {
  expectError([&] { planeSweep(Tensor(), ref, views, depths, 4, 5); }, {"planeSweep", "undefined"});
  expectError(
      [&] {
        planeSweep(Tensor::zeros({2, 8, 10}), ref, views, depths, 4, 5);
      },
      {"planeSweep", "f32[2, 8, 10]", "[V, C, Hs, Ws]"});
  expectError([&] { planeSweep(maps, ref, {views[0]}, depths, 4, 5); },
              {"planeSweep", "2 views", "1 source cameras"});
  expectError([&] { planeSweep(maps, ref, {}, depths, 4, 5); }, {"planeSweep", "no source"});
  expectError([&] { planeSweep(maps, ref, views, {}, 4, 5); }, {"planeSweep", "no plane depths"});
  expectError(
      [&] {
        planeSweep(maps, ref, views, {1.0, -2.0}, 4, 5);
      },
      {"planeSweep", "plane depth 1 = -2"});
  expectError([&] { planeSweep(maps, ref, views, {std::nan("")}, 4, 5); },
              {"planeSweep", "plane depth 0 = nan"});
  expectError([&] { planeSweep(maps, ref, views, depths, 0, 5); },
              {"planeSweep", "output grid 0x5"});
  expectError(
      [&] {
        planeSweep(Tensor::zeros({2, 3, 3, 8, 10}), ref, views, depths, 4, 5);
      },
      {"planeSweep", "3 surfaces, expected 2"});
  Camera bad = ref;
  bad.fx = 0;
  expectError([&] { planeSweep(maps, bad, views, depths, 4, 5); },
              {"planeSweep", "reference camera", "fx = 0"});
  Camera nanPose = ref;
  nanPose.t.x() = std::nan("");
  expectError(
      [&] {
        planeSweep(maps, ref, {views[0], nanPose}, depths, 4, 5);
      },
      {"planeSweep", "source camera 1", "non-finite pose"});
  Camera infCy = ref;
  infCy.cy = std::numeric_limits<double>::infinity();
  expectError(
      [&] {
        planeSweep(maps, ref, {infCy, views[1]}, depths, 4, 5);
      },
      {"planeSweep", "source camera 0", "cy = inf"});
}

TEST_F(GeometryErrors, MeanVarArguments) {
  expectError(
      [&] {
        planeSweepMeanVar(Tensor::zeros({2, 2, 3, 8, 10}), ref, views, depths, 4, 5);
      },
      {"planeSweepMeanVar", "[V, C, Hs, Ws]"});
  expectError(
      [&] {
        planeSweepMeanVar(maps, ref, views, depths, 4, 5, Tensor::zeros({2, 3, 1, 8, 10}));
      },
      {"planeSweepMeanVar", "weights f32[2, 3, 1, 8, 10]", "[2, 2, 1, 8, 10]"});
  expectError(
      [&] {
        planeSweepMeanVar(maps, ref, views, depths, 4, 5,
                          Tensor::zeros({2, 2, 1, 8, 10}, Dtype::F64));
      },
      {"planeSweepMeanVar", "dtype mismatch"});
  const std::vector<Camera> many(65, ref);
  expectError(
      [&] {
        planeSweepMeanVar(Tensor::zeros({65, 1, 4, 4}), ref, many, depths, 4, 5);
      },
      {"planeSweepMeanVar", "65 source views", "at most 64"});
}

TEST_F(GeometryErrors, LayerArguments) {
  expectError([&] { unprojectLayers(maps, Tensor(), ref, views); },
              {"unprojectLayers", "undefined depth"});
  expectError(
      [&] {
        unprojectLayers(maps, Tensor::ones({4, 5}), ref, views);
      },
      {"unprojectLayers", "f32[4, 5]", "[L, H, W]"});
  expectError(
      [&] {
        unprojectLayers(maps, Tensor::ones({2, 1, 5}), ref, views);
      },
      {"unprojectLayers", "2x2"});
  expectError(
      [&] {
        unprojectLayersMeanVar(maps, Tensor::ones({2, 4, 5}, Dtype::F64), ref, views);
      },
      {"unprojectLayersMeanVar", "dtype mismatch"});
  expectError(
      [&] {
        unprojectLayersMeanVar(Tensor::zeros({2, 0, 8, 10}), Tensor::ones({2, 4, 5}), ref, views);
      },
      {"unprojectLayersMeanVar", "empty"});
}

TEST_F(GeometryErrors, RenderArguments) {
  const Tensor mpi = Tensor::zeros({2, 4, 6, 8});
  expectError([&] { renderMpi(Tensor(), depths, ref, views, 4, 5); }, {"renderMpi", "undefined"});
  expectError(
      [&] {
        renderMpi(Tensor::zeros({2, 6, 8}), depths, ref, views, 4, 5);
      },
      {"renderMpi", "f32[2, 6, 8]", "[P, C + 1, h, w]"});
  expectError(
      [&] {
        renderMpi(Tensor::zeros({2, 1, 6, 8}), depths, ref, views, 4, 5);
      },
      {"renderMpi", "C >= 1"});
  expectError(
      [&] {
        renderMpi(mpi, {1.0, 2.0, 3.0}, ref, views, 4, 5);
      },
      {"renderMpi", "3 plane depths", "f32[2, 4, 6, 8]"});
  expectError(
      [&] {
        renderMpi(mpi, {1.0, 0.0}, ref, views, 4, 5);
      },
      {"renderMpi", "plane depth 1 = 0"});
  expectError([&] { renderMpi(mpi, depths, ref, {}, 4, 5); }, {"renderMpi", "no target"});
  expectError([&] { renderMpi(mpi, depths, ref, views, 4, -1); },
              {"renderMpi", "output size 4x-1"});
  Camera bad = ref;
  bad.fy = std::numeric_limits<double>::infinity();
  expectError(
      [&] {
        renderMpi(mpi, depths, ref, {views[0], bad}, 4, 5);
      },
      {"renderMpi", "target camera 1", "fy = inf"});
}

} // namespace
} // namespace simpli
