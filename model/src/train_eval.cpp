// Evaluation protocol (train_eval.h).
#include "simpli/model/training/train_eval.h"

#include "simpli/error.h"
#include "simpli/model/generator/generator.h"
#include "simpli/model/training/train_sampler.h"
#include "simpli/model/training/trainer.h"

#include <simpli/ocl/autograd.h>
#include <simpli/ocl/device.h>

#include <chrono>

#include <limits>

namespace simpli::train {

int nearestSourceView(const std::vector<Camera>& sources, const Camera& target) {
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

namespace {
Image tensorToImage(const ocl::Tensor& t) {
  if (t.dim() != 3 || t.size(0) != 3)
    fail("evaluate: rendered colour ", t.describe(), " is not [3, H, W]");
  Image im(int(t.size(2)), int(t.size(1)));
  const std::vector<float> v = t.toVectorF32();
  std::copy(v.begin(), v.end(), im.data.begin());
  return im;
}
} // namespace

EvalResult evaluate(net::SimpliNetwork& network, TrainingData& data, const EvalOptions& o,
                    const std::function<void(int, int)>& progress) {
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
  const int total = int(scenes) * o.repeats;
  ocl::NoGradGuard noGrad;
  Generator generator(network);
  GeneratorOptions go;
  go.corrections = o.corrections;
  go.raster = o.raster;
  EvalResult result;
  int done = 0;
  for (uint64_t si = 0; si < scenes; ++si) {
    const Scene& scene = data.scene(si);
    if (int(scene.size()) < o.views + 1)
      fail("evaluate: scene ", scene.root, " has ", scene.size(), " views; ", o.views,
           " sources need at least ", o.views + 1);
    for (int r = 0; r < o.repeats; ++r) {
      const TrainingSample s = sampler.drawFromScene(scene, si);
      GeneratorInput in;
      in.images = imagesToTensor(s.sources, network.parameters().dtype());
      in.sources = s.sourceCameras;
      in.reference = s.reference;
      if (done == 0) { // warm-up: PoCL compiles kernels on first use, which is not build time
        generator.forward(in, go);
        ocl::Device::current().finish();
      }
      const auto t0 = std::chrono::steady_clock::now();
      const GeneratorOutput out = generator.forward(in, go);
      ocl::Device::current().finish();
      result.buildMs.push_back(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      for (size_t t = 0; t < s.targets.size(); ++t) {
        const MetricImage truth = metricImageFromImage(s.targets[t]);
        const RenderedLayers rl = renderNovelView(out, s.reference, s.targetCameras[t], o.raster);
        result.model.push_back(evaluateImageQuality(metricImageFromImage(tensorToImage(rl.colour)),
                                                    truth, o.keptArea));
        const int nearest = nearestSourceView(s.sourceCameras, s.targetCameras[t]);
        result.baseline.push_back(evaluateImageQuality(
            metricImageFromImage(s.cleanSources[size_t(nearest)]), truth, o.keptArea));
      }
      if (progress)
        progress(++done, total);
    }
  }
  auto summary = [](const std::vector<ImageQuality>& q, MeanStd& p, MeanStd& ss) {
    std::vector<double> a, b;
    for (const ImageQuality& x : q) {
      a.push_back(x.psnr);
      b.push_back(x.ssim);
    }
    p = meanAndStd(a);
    ss = meanAndStd(b);
  };
  summary(result.model, result.modelPsnr, result.modelSsim);
  summary(result.baseline, result.baselinePsnr, result.baselineSsim);
  result.build = meanAndStd(result.buildMs);
  return result;
}

} // namespace simpli::train
