#pragma once
// Synthetic training scenes generated on the fly (nothing touches the disk). Sample i is
// scene seed deriveSeed(datasetSeed, i), so it is the same on every call, in any order, from
// any thread (the source holds no mutable state).
//
// A sample's Scene is what readScene would return for the scene written by
// writeSyntheticScene and read back: images quantised to 8 bits and mapped to [-1, 1] (CHW),
// cameras and bounds normalised by the same rule (NormalisationOptions, default: the near
// bound -> 1), view names "000.png" ... . The ground-truth depth maps come along in the same
// normalised units.
#include "simpli/model/scene/normalisation.h"
#include "simpli/model/scene/scene.h"
#include "simpli/model/synthetic/renderer.h"

#include <cstdint>
#include <vector>

namespace simpli::synthetic {

struct SyntheticSample {
  uint64_t index = 0;
  uint64_t seed = 0;                      ///< the scene seed (params.seed of `geometry`)
  scene::Scene scene;                     ///< normalised units, as readScene
  std::vector<std::vector<float>> depths; ///< per view, height x width camera z (normalised)
  SyntheticScene geometry;                ///< the generated scene, in scene units
};

class ProceduralSceneSource {
public:
  /// `params.seed` is ignored: each sample gets its own seed. Throws for invalid params.
  explicit ProceduralSceneSource(const SyntheticSceneParams& params, uint64_t datasetSeed = 0,
                                 const scene::NormalisationOptions& normalisation = {});

  uint64_t seedOf(uint64_t index) const { return deriveSeed(datasetSeed_, index); }
  SyntheticSample sample(uint64_t index) const;
  /// The generated scene of sample `index`, not rendered (its cameras say how many views).
  SyntheticScene geometry(uint64_t index) const;
  /// Sample `index` from its geometry with colour only for the views in `colourViews` (the
  /// others have an empty image; every view has its depth, which the bounds need). The
  /// rendered views, cameras, bounds and depths are those of sample(index), to the bit.
  /// Throws for a view index out of range.
  SyntheticSample sample(const SyntheticScene& geometry, uint64_t index,
                         const std::vector<int>& colourViews) const;
  const SyntheticSceneParams& params() const { return params_; }

private:
  SyntheticSceneParams params_;
  uint64_t datasetSeed_;
  scene::NormalisationOptions normalisation_;
};

/// The Scene + normalised depths for an already generated and rendered scene (what sample()
/// does after generating). A view rendered without colour (renderDepth) gets an empty image.
SyntheticSample makeSample(const SyntheticScene& geometry, const std::vector<RenderedView>& views,
                           const scene::NormalisationOptions& normalisation = {});

} // namespace simpli::synthetic
