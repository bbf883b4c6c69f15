#pragma once
// Scene builders and guards shared by the rasterizer tests.
#include "raster_reference.h"

#include "simpli/ocl/buffer_pool.h"
#include "simpli/ocl/device.h"

namespace simpli::test {

/// Fills every newly acquired device buffer with NaN while alive, so unwritten outputs show.
class PoisonScope {
public:
  PoisonScope() { ocl::Device::current().pool().setPoison(true); }
  ~PoisonScope() { ocl::Device::current().pool().setPoison(false); }
  PoisonScope(const PoisonScope&) = delete;
  PoisonScope& operator=(const PoisonScope&) = delete;
};

/// L layers on an H x W grid with random RGBA (alpha in [alphaLo, alphaHi]) and random depths:
/// layer k (0 = farthest) in [base_k (1 - bump), base_k (1 + bump)], base_k decreasing with k.
LayerScene randomScene(int L, int H, int W, int A, double bump, unsigned seed, double alphaLo = 0.1,
                       double alphaHi = 0.9);

/// Every layer at one constant depth (flat fronto-parallel planes in the reference camera).
LayerScene flatScene(const std::vector<double>& depths, int H, int W, int A, unsigned seed);

/// The reference camera used by most tests: off-centre principal point, a small rotation and
/// translation, size W x H.
scene::Camera testReferenceCamera(int W, int H);

/// Whether every value is finite.
bool allFinite(const std::vector<double>& values);

} // namespace simpli::test
