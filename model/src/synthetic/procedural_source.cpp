// On-the-fly synthetic scenes (see synthetic/procedural_source.h).
#include "simpli/model/synthetic/procedural_source.h"

#include "simpli/error.h"
#include "simpli/model/scene/llff_writer.h"

#include <algorithm>

namespace simpli::synthetic {

ProceduralSceneSource::ProceduralSceneSource(const SyntheticSceneParams& params,
                                             uint64_t datasetSeed,
                                             const scene::NormalisationOptions& normalisation)
    : params_(params), datasetSeed_(datasetSeed), normalisation_(normalisation) {
  params_.validate();
}

SyntheticScene ProceduralSceneSource::geometry(uint64_t index) const {
  SyntheticSceneParams p = params_;
  p.seed = seedOf(index);
  return generateSyntheticScene(p);
}

SyntheticSample ProceduralSceneSource::sample(uint64_t index) const {
  const SyntheticScene g = geometry(index);
  SyntheticSample s = makeSample(g, renderViews(g), normalisation_);
  s.index = index;
  return s;
}

SyntheticSample ProceduralSceneSource::sample(const SyntheticScene& geometry, uint64_t index,
                                              const std::vector<int>& colourViews) const {
  const int n = int(geometry.cameras.size());
  std::vector<bool> colour(size_t(n), false);
  for (int v : colourViews) {
    if (v < 0 || v >= n)
      fail("synthetic sample ", index, ": view ", v, " out of range (the scene has ", n, " views)");
    colour[size_t(v)] = true;
  }
  std::vector<RenderedView> views;
  for (int i = 0; i < n; ++i)
    views.push_back(colour[size_t(i)] ? renderView(geometry, i) : renderDepth(geometry, i));
  SyntheticSample s = makeSample(geometry, views, normalisation_);
  s.index = index;
  return s;
}

SyntheticSample makeSample(const SyntheticScene& geometry, const std::vector<RenderedView>& views,
                           const scene::NormalisationOptions& normalisation) {
  if (views.size() != geometry.cameras.size() || views.empty())
    fail("synthetic sample: ", views.size(), " rendered views for ", geometry.cameras.size(),
         " cameras");
  SyntheticSample s;
  s.seed = geometry.params.seed;
  s.geometry = geometry;
  // Bounds as the LLFF reader settles them: min near and max far over the views.
  double nearB = 0, farB = 0;
  for (size_t i = 0; i < views.size(); ++i) {
    const DepthBounds b = depthBounds(views[i]);
    nearB = i == 0 ? b.near : std::min(nearB, b.near);
    farB = i == 0 ? b.far : std::max(farB, b.far);
  }
  const scene::Normalisation n = scene::chooseNormalisation(normalisation, nearB, {});
  scene::Scene& scene = s.scene;
  scene.root = "synthetic:" + std::to_string(s.seed);
  scene.format = scene::SceneFormat::LLFF; // the layout writeSyntheticScene would give it
  scene.normalisation = n;
  scene.near = n.toNormalised(nearB);
  scene.far = n.toNormalised(farB);
  scene.boundsSource = "synthetic ground-truth depth (per view 0.9 x min, 1.1 x max; min near, "
                       "max far over views)";
  for (size_t i = 0; i < views.size(); ++i) {
    scene::SceneView v;
    v.name = scene::llffViewName(i, views.size()) + ".png";
    if (!views[i].rgb.empty())
      v.image = views[i].image();
    v.camera = n.toNormalised(geometry.cameras[i]);
    v.originalWidth = views[i].width;
    v.originalHeight = views[i].height;
    scene.views.push_back(std::move(v));
    std::vector<float> d = views[i].depth;
    for (float& x : d)
      x = float(n.toNormalised(double(x)));
    s.depths.push_back(std::move(d));
  }
  return s;
}

} // namespace simpli::synthetic
