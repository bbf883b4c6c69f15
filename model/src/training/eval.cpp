// Evaluation protocol (training/eval.h).
#include "simpli/model/training/eval.h"

#include "simpli/error.h"
#include "simpli/model/generator/generator.h"
#include "simpli/model/scene/reference_camera.h"
#include "simpli/model/training/sampler.h"
#include "simpli/model/training/trainer.h"

#include "simpli/ocl/autograd.h"
#include "simpli/ocl/device.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace simpli::training {

int nearestSourceView(const std::vector<scene::Camera>& sources, const scene::Camera& target) {
  if (sources.empty())
    fail("nearestSourceView: no sources");
  int best = 0;
  double bestD = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < sources.size(); ++i) {
    const double d = (sources[i].centre() - target.centre()).norm();
    if (d < bestD) {
      bestD = d;
      best = int(i);
    }
  }
  return best;
}

generator::GeneratorInput sampleInput(const TrainingSample& sample, double inputScale,
                                      ocl::Dtype dtype) {
  std::vector<const io::Image*> images;
  for (const io::Image& image : sample.sources)
    images.push_back(&image);
  return generator::scaledInput(images, sample.sourceCameras, sample.reference, inputScale, dtype);
}

io::Image renderedImage(const ocl::Tensor& t, const char* what) {
  if (t.dim() != 3 || t.size(0) != 3)
    fail(what, ": rendered colour ", t.describe(), " is not [3, H, W]");
  io::Image im(int(t.size(2)), int(t.size(1)));
  const std::vector<float> v = t.toVectorF32();
  std::copy(v.begin(), v.end(), im.data.begin());
  return im;
}

void forEachEvalSample(
    TrainingData& data, const EvalOptions& o,
    const std::function<void(const TrainingSample&, uint64_t scene, int repeat)>& onSample) {
  if (o.repeats < 1)
    fail("evaluate: repeats ", o.repeats, " must be >= 1");
  if (o.views < 1 || o.novelViews < 1)
    fail("evaluate: views ", o.views, " and novel views ", o.novelViews, " must be >= 1");
  SamplingConfig sc;
  sc.minViews = sc.maxViews = o.views;
  sc.novelViews = o.novelViews;
  sc.window = o.window;
  sc.mixupProbability = 0;
  Sampler sampler(sc, samplerSeed(o.seed));
  const uint64_t scenes = data.sceneCount() > 0 ? data.sceneCount() : uint64_t(o.scenes);
  for (uint64_t si = 0; si < scenes; ++si) {
    const scene::Scene& scene = data.scene(si);
    if (int(scene.size()) < o.views + 1)
      fail("evaluate: scene ", scene.root, " has ", scene.size(), " views; ", o.views,
           " sources need at least ", o.views + 1);
    for (int r = 0; r < o.repeats; ++r) {
      TrainingSample s = sampler.drawFromScene(scene, si);
      s.reference = scene::widenedCamera(s.reference, o.referenceMargin);
      onSample(s, si, r);
    }
  }
}

EvalResult evaluate(network::SimpliNetwork& network, TrainingData& data, const EvalOptions& o,
                    const std::function<void(int, int)>& progress,
                    const std::function<void(const EvalViewImages&)>& onView) {
  generator::Generator generator(network);
  generator::GeneratorOptions go;
  go.corrections = o.corrections;
  go.raster = o.raster;
  return evaluate([&](const generator::GeneratorInput& in) { return generator.forward(in, go); },
                  network.parameters().dtype(), data, o, progress, onView);
}

EvalResult evaluate(const SurfaceBuilder& build, ocl::Dtype inputDtype, TrainingData& data,
                    const EvalOptions& o, const std::function<void(int, int)>& progress,
                    const std::function<void(const EvalViewImages&)>& onView) {
  const uint64_t scenes = data.sceneCount() > 0 ? data.sceneCount() : uint64_t(o.scenes);
  const int total = int(scenes) * o.repeats;
  ocl::NoGradGuard noGrad;
  EvalResult result;
  int done = 0;
  forEachEvalSample(data, o, [&](const TrainingSample& s, uint64_t si, int r) {
    const generator::GeneratorInput in = sampleInput(s, o.inputScale, inputDtype);
    if (done == 0 && o.warmUp) { // warm-up: PoCL compiles kernels on first use, which is not
                                 // build time
      build(in);
      ocl::Device::current().finish();
    }
    const auto t0 = std::chrono::steady_clock::now();
    const generator::GeneratorOutput out = build(in);
    ocl::Device::current().finish();
    result.buildMs.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    for (size_t t = 0; t < s.targets.size(); ++t) {
      const metrics::MetricImage truth = metrics::metricImageFromImage(s.targets[t]);
      const raster::RenderedLayers rl =
          generator::renderNovelView(out, s.reference, s.targetCameras[t], o.raster);
      const io::Image render = renderedImage(rl.colour, "evaluate");
      result.model.push_back(
          metrics::evaluateImageQuality(metrics::metricImageFromImage(render), truth, o.keptArea));
      const int nearest = nearestSourceView(s.sourceCameras, s.targetCameras[t]);
      const io::Image& nearestImage = s.cleanSources[size_t(nearest)];
      result.baseline.push_back(metrics::evaluateImageQuality(
          metrics::metricImageFromImage(nearestImage), truth, o.keptArea));
      result.views.push_back(
          {si, r, s.sourceFrames, s.targetFrames[t], s.sourceFrames[size_t(nearest)]});
      if (onView)
        onView({result.views.back(), s.targets[t], render, nearestImage});
    }
    if (progress)
      progress(++done, total);
  });
  auto summary = [](const std::vector<metrics::ImageQuality>& q, metrics::MeanStd& p,
                    metrics::MeanStd& ss) {
    std::vector<double> a, b;
    for (const metrics::ImageQuality& x : q) {
      a.push_back(x.psnr);
      b.push_back(x.ssim);
    }
    p = metrics::meanAndStd(a);
    ss = metrics::meanAndStd(b);
  };
  summary(result.model, result.modelPsnr, result.modelSsim);
  summary(result.baseline, result.baselinePsnr, result.baselineSsim);
  result.build = metrics::meanAndStd(result.buildMs);
  return result;
}

} // namespace simpli::training
