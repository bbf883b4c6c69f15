#pragma once
// Shared inputs of the generator tests: the golden inputs and stub renderer
// (shared/golden/README.md §3, §4), small synthetic forward-facing rigs, and tiny networks.
#include "simpli/model/generator/generator.h"
#include "simpli/model/network/network.h"

#include <memory>
#include <string>
#include <vector>

namespace simpli::test {

/// The golden forward pass's input (3 views of 64 x 96, reference camera from the file).
generator::GeneratorInput goldenInput(ocl::Dtype dtype);

/// The golden README's stub renderer (§4): surface 0 taken as opaque, the others composited
/// over it in index order, nearest-resized to the source size, the same image for every view.
/// Every call appends the RGBA it was given to `received` (when not null).
generator::SourceRenderer goldenStubRenderer(std::vector<ocl::Tensor>* received = nullptr);

/// A forward-facing rig of `views` cameras (relative intrinsics, baselines ~0.05 around the
/// identity reference) looking at width x height images; reference = referenceCamera(rig).
/// Images are uniform noise in [-1, 1] from `seed`.
generator::GeneratorInput syntheticInput(int views, int height, int width, ocl::Dtype dtype,
                                         uint64_t seed);

/// A network from model/configs/<name>.json with parameters drawn from `seed`.
std::unique_ptr<network::SimpliNetwork> configNetwork(const std::string& name, ocl::Dtype dtype,
                                                      uint64_t seed = 1);

/// Every element finite.
bool allFinite(const ocl::Tensor& t);

/// Largest |a - b| over the elements (a gtest failure when the shapes differ).
double maxAbsDiff(const ocl::Tensor& a, const ocl::Tensor& b);

} // namespace simpli::test
