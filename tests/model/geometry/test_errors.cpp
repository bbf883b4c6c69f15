// Bad use of the geometry ops: every mistake is a simpli::Error naming the op and the offending
// value or shape, never a crash.
#include "geometry_reference.h"

#include "simpli/error.h"
#include "simpli/model/geometry/layer_unproject.h"
#include "simpli/model/geometry/mpi_render.h"
#include "simpli/model/geometry/plane_sweep.h"
#include "simpli/model/geometry/planes.h"

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
  scene::Camera ref = geomtest::referenceCamera();
  std::vector<scene::Camera> views{geomtest::referenceCamera(), geomtest::referenceCamera()};
  Tensor maps = Tensor::zeros({2, 3, 8, 10});
  std::vector<double> depths{1.0, 2.0};
};

TEST_F(GeometryErrors, PlaneDepths) {
  expectError([] { geometry::planeDepths(0, 1, 100); }, {"planeDepths", "count 0"});
  expectError([] { geometry::planeDepths(41, 0, 100); }, {"planeDepths", "near = 0"});
  expectError([] { geometry::planeDepths(41, 10, 1); }, {"planeDepths", "far = 1"});
  expectError([] { geometry::planeDepths(41, 1, std::numeric_limits<double>::infinity()); },
              {"planeDepths", "far = inf"});
  EXPECT_EQ(geometry::planeDepths(1, 2, 5), std::vector<double>{5.0});
}

TEST_F(GeometryErrors, PlaneSweepArguments) {
  expectError([&] { geometry::planeSweep(Tensor(), ref, views, depths, 4, 5); },
              {"planeSweep", "undefined"});
  expectError(
      [&] {
        geometry::planeSweep(Tensor::zeros({2, 8, 10}), ref, views, depths, 4, 5);
      },
      {"planeSweep", "f32[2, 8, 10]", "[V, C, Hs, Ws]"});
  expectError([&] { geometry::planeSweep(maps, ref, {views[0]}, depths, 4, 5); },
              {"planeSweep", "2 views", "1 source cameras"});
  expectError([&] { geometry::planeSweep(maps, ref, {}, depths, 4, 5); },
              {"planeSweep", "no source"});
  expectError([&] { geometry::planeSweep(maps, ref, views, {}, 4, 5); },
              {"planeSweep", "no plane depths"});
  expectError(
      [&] {
        geometry::planeSweep(maps, ref, views, {1.0, -2.0}, 4, 5);
      },
      {"planeSweep", "plane depth 1 = -2"});
  expectError([&] { geometry::planeSweep(maps, ref, views, {std::nan("")}, 4, 5); },
              {"planeSweep", "plane depth 0 = nan"});
  expectError([&] { geometry::planeSweep(maps, ref, views, depths, 0, 5); },
              {"planeSweep", "output grid 0x5"});
  expectError(
      [&] {
        geometry::planeSweep(Tensor::zeros({2, 3, 3, 8, 10}), ref, views, depths, 4, 5);
      },
      {"planeSweep", "3 surfaces, expected 2"});
  scene::Camera bad = ref;
  bad.fx = 0;
  expectError([&] { geometry::planeSweep(maps, bad, views, depths, 4, 5); },
              {"planeSweep", "reference camera", "fx = 0"});
  scene::Camera nanPose = ref;
  nanPose.t.x() = std::nan("");
  expectError(
      [&] {
        geometry::planeSweep(maps, ref, {views[0], nanPose}, depths, 4, 5);
      },
      {"planeSweep", "source camera 1", "non-finite pose"});
  scene::Camera infCy = ref;
  infCy.cy = std::numeric_limits<double>::infinity();
  expectError(
      [&] {
        geometry::planeSweep(maps, ref, {infCy, views[1]}, depths, 4, 5);
      },
      {"planeSweep", "source camera 0", "cy = inf"});
}

TEST_F(GeometryErrors, MeanVarArguments) {
  expectError(
      [&] {
        geometry::planeSweepMeanVar(Tensor::zeros({2, 2, 3, 8, 10}), ref, views, depths, 4, 5);
      },
      {"planeSweepMeanVar", "[V, C, Hs, Ws]"});
  expectError(
      [&] {
        geometry::planeSweepMeanVar(maps, ref, views, depths, 4, 5,
                                    Tensor::zeros({2, 3, 1, 8, 10}));
      },
      {"planeSweepMeanVar", "weights f32[2, 3, 1, 8, 10]", "[2, 2, 1, 8, 10]"});
  expectError(
      [&] {
        geometry::planeSweepMeanVar(maps, ref, views, depths, 4, 5,
                                    Tensor::zeros({2, 2, 1, 8, 10}, Dtype::F64));
      },
      {"planeSweepMeanVar", "dtype mismatch"});
  const std::vector<scene::Camera> many(65, ref);
  expectError(
      [&] {
        geometry::planeSweepMeanVar(Tensor::zeros({65, 1, 4, 4}), ref, many, depths, 4, 5);
      },
      {"planeSweepMeanVar", "65 source views", "at most 64"});
}

TEST_F(GeometryErrors, CoverageArguments) {
  expectError(
      [&] {
        geometry::planeSweepCoverage(Tensor::zeros({2, 2, 3, 8, 10}), ref, views, depths, 4, 5);
      },
      {"planeSweepCoverage", "[V, C, Hs, Ws]"});
  expectError([&] { geometry::planeSweepCoverage(maps, ref, {views[0]}, depths, 4, 5); },
              {"planeSweepCoverage", "2 views", "1 source cameras"});
  expectError(
      [&] {
        geometry::planeSweepCoverage(maps, ref, views, {1.0, -2.0}, 4, 5);
      },
      {"planeSweepCoverage", "plane depth 1", "-2"});
  expectError([&] { geometry::planeSweepCoverage(maps, ref, views, depths, 0, 5); },
              {"planeSweepCoverage", "0x5"});
}

TEST_F(GeometryErrors, LayerArguments) {
  expectError([&] { geometry::unprojectLayers(maps, Tensor(), ref, views); },
              {"unprojectLayers", "undefined depth"});
  expectError(
      [&] {
        geometry::unprojectLayers(maps, Tensor::ones({4, 5}), ref, views);
      },
      {"unprojectLayers", "f32[4, 5]", "[L, H, W]"});
  expectError(
      [&] {
        geometry::unprojectLayers(maps, Tensor::ones({2, 1, 5}), ref, views);
      },
      {"unprojectLayers", "2x2"});
  expectError(
      [&] {
        geometry::unprojectLayersMeanVar(maps, Tensor::ones({2, 4, 5}, Dtype::F64), ref, views);
      },
      {"unprojectLayersMeanVar", "dtype mismatch"});
  expectError(
      [&] {
        geometry::unprojectLayersMeanVar(Tensor::zeros({2, 0, 8, 10}), Tensor::ones({2, 4, 5}), ref,
                                         views);
      },
      {"unprojectLayersMeanVar", "empty"});
}

TEST_F(GeometryErrors, RenderArguments) {
  const Tensor mpi = Tensor::zeros({2, 4, 6, 8});
  expectError([&] { geometry::renderMpi(Tensor(), depths, ref, views, 4, 5); },
              {"renderMpi", "undefined"});
  expectError(
      [&] {
        geometry::renderMpi(Tensor::zeros({2, 6, 8}), depths, ref, views, 4, 5);
      },
      {"renderMpi", "f32[2, 6, 8]", "[P, C + 1, h, w]"});
  expectError(
      [&] {
        geometry::renderMpi(Tensor::zeros({2, 1, 6, 8}), depths, ref, views, 4, 5);
      },
      {"renderMpi", "C >= 1"});
  expectError(
      [&] {
        geometry::renderMpi(mpi, {1.0, 2.0, 3.0}, ref, views, 4, 5);
      },
      {"renderMpi", "3 plane depths", "f32[2, 4, 6, 8]"});
  expectError(
      [&] {
        geometry::renderMpi(mpi, {1.0, 0.0}, ref, views, 4, 5);
      },
      {"renderMpi", "plane depth 1 = 0"});
  expectError([&] { geometry::renderMpi(mpi, depths, ref, {}, 4, 5); }, {"renderMpi", "no target"});
  expectError([&] { geometry::renderMpi(mpi, depths, ref, views, 4, -1); },
              {"renderMpi", "output size 4x-1"});
  scene::Camera bad = ref;
  bad.fy = std::numeric_limits<double>::infinity();
  expectError(
      [&] {
        geometry::renderMpi(mpi, depths, ref, {views[0], bad}, 4, 5);
      },
      {"renderMpi", "target camera 1", "fy = inf"});
}

} // namespace
} // namespace simpli
