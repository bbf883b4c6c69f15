// TrainingConfig: strict JSON reading (unknown keys rejected), writing and validation.
#include "simpli/model/training/config.h"

#include "simpli/model/network/loader.h"
#include "simpli/model/scene/reference_camera.h"
#include "simpli/model/training/data.h"

#include "io/json_object_reader.h"
#include "simpli/error.h"
#include "simpli/model/io/files.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <set>

namespace simpli::training {
namespace {

using json = nlohmann::json;
namespace fs = std::filesystem;

using io::jsonExcerpt;
using io::JsonObjectReader;

network::NetworkConfig resolveNetwork(const json& v, const std::string& source,
                                      const std::string& baseDir) {
  if (v.is_object())
    return network::parseNetworkConfig(v.dump(), source + " (field \"network\")");
  if (!v.is_string())
    fail(source, ": field \"network\" is ", io::jsonExcerpt(v),
         ", expected \"official-4l\", \"official-8l\", a file name or an object");
  const std::string name = v.get<std::string>();
  if (name == "official-4l")
    return network::officialConfig(4);
  if (name == "official-8l")
    return network::officialConfig(8);
  fs::path p(name);
  if (p.is_relative() && !baseDir.empty())
    p = fs::path(baseDir) / p;
  if (!fs::exists(p))
    fail(source, ": field \"network\": network config '", p.string(), "' does not exist");
  return network::loadNetworkConfig(p.string());
}

std::string stringField(io::JsonObjectReader& f, const std::string& key,
                        const std::string& fallback) {
  const json* v = f.find(key);
  if (!v)
    return fallback;
  if (!v->is_string())
    fail(f.source(), ": ", f.where(key), " is ", io::jsonExcerpt(*v), ", expected a string");
  return v->get<std::string>();
}

void readSynthetic(const json& object, const std::string& source, SyntheticConfig& out) {
  io::JsonObjectReader f(object, source, "synthetic");
  auto named = [&](const char* key) {
    return source + ": field \"synthetic." + std::string(key) + "\"";
  };
  out.style = synthetic::parseSceneStyle(stringField(f, "style", toString(out.style)),
                                         named("style") + " is");
  out.textures = synthetic::parseTextureSet(stringField(f, "textures", toString(out.textures)),
                                            named("textures") + " is");
  f.readNumber("photo_probability", out.photoProbability);
  out.photoDir = stringField(f, "photo_dir", out.photoDir);
  if (const json* v = f.find("photos_required")) {
    if (!v->is_boolean())
      fail(named("photos_required"), " is ", io::jsonExcerpt(*v), ", expected true or false");
    out.photosRequired = v->get<bool>();
  }
  f.readInteger("views", out.views);
  f.readInteger("objects", out.objects);
  f.readInteger("antialias", out.antialias);
  f.readPair("translation", out.translationMin, out.translationMax);
  f.readPair("object_size", out.objectSizeMin, out.objectSizeMax);
  f.readIntegerPair("bushes", out.bushesMin, out.bushesMax);
  f.readPair("bush_scale", out.bushScaleMin, out.bushScaleMax);
  f.readNumber("bush_shared_texture", out.bushSharedTexture);
  const std::string size = stringField(f, "size", "");
  if (!size.empty())
    parseWidthHeight(size, named("size"), out.width, out.height);
  f.finish();
}

} // namespace

const std::vector<std::string>& lossTermNames() {
  static const std::vector<std::string> names{"l1",
                                              "perceptual",
                                              "intermediate_loss_0_l1",
                                              "intermediate_loss_1_l1",
                                              "intermediate_loss_2_l1",
                                              "intermediate_loss_3_l1",
                                              "smooth_layers",
                                              "depth",
                                              "mpi_depth",
                                              "ssim"};
  return names;
}

TrainingConfig::TrainingConfig() {
  // configs/tblock4_train.yaml (spec §8.1, §14 item 2).
  lossWeights = {{"l1", 1.0},
                 {"perceptual", 0.0},
                 {"intermediate_loss_0_l1", 1.0},
                 {"intermediate_loss_1_l1", 1.0},
                 {"intermediate_loss_2_l1", 1.0},
                 {"intermediate_loss_3_l1", 1.0},
                 {"smooth_layers", 0.01},
                 {"depth", 0.0},
                 {"mpi_depth", 0.0},
                 {"ssim", 0.0}};
}

double TrainingConfig::weight(const std::string& term) const {
  auto it = lossWeights.find(term);
  if (it == lossWeights.end())
    fail("training config: unknown loss term '", term, "'");
  return it->second;
}

void TrainingConfig::validate(const std::string& source) const {
  network.validate(source + " (network)");
  const SamplingConfig& s = sampling;
  auto bad = [&](const char* field, auto value, const char* why) {
    fail(source, ": field \"", field, "\" = ", value, ": ", why);
  };
  if (steps < 0)
    bad("steps", steps, "must be >= 0");
  if (checkpointEvery < 1)
    bad("checkpoint_every", checkpointEvery, "must be >= 1");
  if (!(emaDecay >= 0 && emaDecay < 1))
    bad("ema_decay", emaDecay, "must be in [0, 1) (0 = no average)");
  if (corrections < -1 || corrections > network.mliCorrections())
    fail(source, ": field \"corrections\" = ", corrections, ": must be -1 .. ",
         network.mliCorrections(), " (the network's correction steps)");
  if (maxFragments < 1 || maxFragments > 64)
    bad("max_fragments", maxFragments, "must be 1 .. 64");
  const OptimizerConfig& o = optimizer;
  if (!(o.lr > 0))
    bad("optimizer.lr", o.lr, "must be > 0");
  if (!(o.beta1 >= 0 && o.beta1 < 1))
    bad("optimizer.beta1", o.beta1, "must be in [0, 1)");
  if (!(o.beta2 >= 0 && o.beta2 < 1))
    bad("optimizer.beta2", o.beta2, "must be in [0, 1)");
  if (!(o.eps > 0))
    bad("optimizer.eps", o.eps, "must be > 0");
  if (!(o.gamma > 0 && o.gamma <= 1))
    bad("optimizer.gamma", o.gamma, "must be in (0, 1]");
  if (!(o.clipGradNorm > 0))
    bad("optimizer.clip_grad_norm", o.clipGradNorm, "must be > 0");
  if (o.warmupSteps < 0)
    bad("optimizer.warmup_steps", o.warmupSteps, "must be >= 0 (0 = no warm-up)");
  for (const auto& [term, w] : lossWeights)
    if (!(w >= 0) || !std::isfinite(w))
      fail(source, ": field \"loss_weights.", term, "\" = ", w, ": must be finite and >= 0");
  if (s.minViews < 1)
    bad("sampling.min_views", s.minViews, "must be >= 1");
  if (s.maxViews < s.minViews)
    fail(source, ": field \"sampling.max_views\" = ", s.maxViews, ": must be >= min_views (",
         s.minViews, ")");
  if (s.novelViews < 1)
    bad("sampling.novel_views", s.novelViews, "must be >= 1");
  if (s.window < 0)
    bad("sampling.window", s.window, "must be >= 0 (0 = the whole scene)");
  if (s.cropHeight < 0 || s.cropWidth < 0 || (s.cropHeight == 0) != (s.cropWidth == 0))
    fail(source, ": field \"sampling.crop\" = [", s.cropHeight, ", ", s.cropWidth,
         "]: both 0 (no crop) or both positive");
  if (s.cropHeight % 16 != 0 || s.cropWidth % 16 != 0)
    fail(source, ": field \"sampling.crop\" = [", s.cropHeight, ", ", s.cropWidth,
         "]: the network needs multiples of 16");
  for (double z : s.zoomScales)
    if (!(z >= 1 && z <= 4))
      bad("sampling.zoom", z, "every factor must be in [1, 4]");
  if (!(s.mixupProbability >= 0 && s.mixupProbability <= 1))
    bad("sampling.mixup_probability", s.mixupProbability, "must be in [0, 1]");
  if (!(s.mixupLambdaMin >= 0 && s.mixupLambdaMin <= s.mixupLambdaMax && s.mixupLambdaMax <= 1))
    fail(source, ": field \"sampling.mixup_lambda\" = [", s.mixupLambdaMin, ", ", s.mixupLambdaMax,
         "]: need 0 <= low <= high <= 1");
  if (!(s.referenceMargin >= 0 && s.referenceMargin <= scene::maxReferenceMargin))
    bad("sampling.reference_margin", s.referenceMargin, "must be in [0, 0.5]");
  if (!(s.sourceExposureStd >= 0 && s.sourceExposureStd <= 0.5 && s.sourceChannelStd >= 0 &&
        s.sourceChannelStd <= 0.5))
    fail(source, ": field \"sampling.source_gain_std\" = [", s.sourceExposureStd, ", ",
         s.sourceChannelStd, "]: need both in [0, 0.5] (log-gain standard deviations)");
  if (!(s.sharpenProbability >= 0 && s.sharpenProbability <= 1 && s.sharpenMax >= 0 &&
        s.sharpenMax <= 10))
    fail(source, ": field \"sampling.sharpen\" = [", s.sharpenProbability, ", ", s.sharpenMax,
         "]: need a probability in [0, 1] and a largest amount in [0, 10]");
  const SyntheticConfig& y = synthetic;
  if (!(y.photoProbability >= 0 && y.photoProbability <= 1))
    bad("synthetic.photo_probability", y.photoProbability, "must be in [0, 1]");
  if (y.views < 2 || y.views > 10000)
    bad("synthetic.views", y.views, "must be 2 .. 10000 (training needs a source and a target)");
  if (y.objects < 0 || y.objects > 1000)
    bad("synthetic.objects", y.objects, "must be 0 .. 1000");
  if (y.antialias < 1 || y.antialias > 16)
    bad("synthetic.antialias", y.antialias, "must be 1 .. 16");
  using World = synthetic::WorldStyleParams;
  if (!(y.translationMin >= World::kTranslationLow && y.translationMin <= y.translationMax &&
        y.translationMax <= World::kTranslationHigh))
    fail(source, ": field \"synthetic.translation\" = [", y.translationMin, ", ", y.translationMax,
         "]: need ", World::kTranslationLow, " <= low <= high <= ", World::kTranslationHigh,
         " (x the nearest depth)");
  if (!(y.objectSizeMin >= World::kObjectSizeLow && y.objectSizeMin <= y.objectSizeMax &&
        y.objectSizeMax <= World::kObjectSizeHigh))
    fail(source, ": field \"synthetic.object_size\" = [", y.objectSizeMin, ", ", y.objectSizeMax,
         "]: need ", World::kObjectSizeLow, " <= low <= high <= ", World::kObjectSizeHigh,
         " (x the image width)");
  if (!(y.bushesMin >= 0 && y.bushesMin <= y.bushesMax && y.bushesMax <= World::kBushesHigh))
    fail(source, ": field \"synthetic.bushes\" = [", y.bushesMin, ", ", y.bushesMax,
         "]: need 0 <= low <= high <= ", World::kBushesHigh);
  if (!(y.bushScaleMin >= World::kBushScaleLow && y.bushScaleMin <= y.bushScaleMax &&
        y.bushScaleMax <= World::kBushScaleHigh))
    fail(source, ": field \"synthetic.bush_scale\" = [", y.bushScaleMin, ", ", y.bushScaleMax,
         "]: need ", World::kBushScaleLow, " <= low <= high <= ", World::kBushScaleHigh);
  if (!(y.bushSharedTexture >= 0 && y.bushSharedTexture <= 1))
    bad("synthetic.bush_shared_texture", y.bushSharedTexture, "must be 0 .. 1 (a probability)");
  if ((y.width == 0) != (y.height == 0) || y.width % 16 != 0 || y.height % 16 != 0 || y.width < 0 ||
      y.height < 0)
    fail(source, ": field \"synthetic.size\" = \"", y.width, "x", y.height,
         "\": width and height must be positive multiples of 16");
}

TrainingConfig parseTrainingConfig(const std::string& jsonText, const std::string& source,
                                   const std::string& baseDir) {
  const json root = io::parseJson(jsonText, source);
  TrainingConfig c;
  io::JsonObjectReader top(root, source, "");
  const json* net = top.find("network");
  if (!net)
    fail(source, ": missing field \"network\"");
  c.network = resolveNetwork(*net, source, baseDir);
  if (const json* d = top.find("dtype")) {
    if (*d == "f32")
      c.dtype = ocl::Dtype::F32;
    else if (*d == "f64")
      c.dtype = ocl::Dtype::F64;
    else
      fail(source, ": field \"dtype\" is ", io::jsonExcerpt(*d), ", expected \"f32\" or \"f64\"");
  }
  if (const json* v = top.find("seed")) {
    if (!v->is_number_unsigned())
      fail(source, ": field \"seed\" is ", io::jsonExcerpt(*v), ", expected an integer >= 0");
    c.seed = v->get<uint64_t>();
  }
  top.readInteger("steps", c.steps);
  top.readInteger("checkpoint_every", c.checkpointEvery);
  top.readInteger("corrections", c.corrections);
  top.readInteger("max_fragments", c.maxFragments);
  top.readNumber("ema_decay", c.emaDecay);
  if (const json* o = top.find("optimizer")) {
    io::JsonObjectReader f(*o, source, "optimizer");
    f.readNumber("lr", c.optimizer.lr);
    f.readNumber("beta1", c.optimizer.beta1);
    f.readNumber("beta2", c.optimizer.beta2);
    f.readNumber("eps", c.optimizer.eps);
    f.readNumber("gamma", c.optimizer.gamma);
    f.readInteger("warmup_steps", c.optimizer.warmupSteps);
    f.readNumber("clip_grad_norm", c.optimizer.clipGradNorm);
    f.finish();
  }
  if (const json* w = top.find("loss_weights")) {
    io::JsonObjectReader f(*w, source, "loss_weights");
    for (const std::string& term : lossTermNames())
      f.readNumber(term, c.lossWeights[term]);
    f.finish();
  }
  if (const json* s = top.find("sampling")) {
    io::JsonObjectReader f(*s, source, "sampling");
    SamplingConfig& sc = c.sampling;
    f.readInteger("min_views", sc.minViews);
    f.readInteger("max_views", sc.maxViews);
    f.readInteger("novel_views", sc.novelViews);
    f.readInteger("window", sc.window);
    f.readIntegerPair("crop", sc.cropHeight, sc.cropWidth);
    f.readNumbers("zoom", sc.zoomScales);
    f.readNumber("mixup_probability", sc.mixupProbability);
    f.readPair("mixup_lambda", sc.mixupLambdaMin, sc.mixupLambdaMax);
    f.readNumber("reference_margin", sc.referenceMargin);
    f.readPair("source_gain_std", sc.sourceExposureStd, sc.sourceChannelStd);
    f.readPair("sharpen", sc.sharpenProbability, sc.sharpenMax);
    f.finish();
  }
  if (const json* s = top.find("synthetic"))
    readSynthetic(*s, source, c.synthetic);
  top.finish();
  c.validate(source);
  return c;
}

TrainingConfig loadTrainingConfig(const std::string& path) {
  const std::vector<unsigned char> bytes = io::readFileBytes(path, "training config");
  const std::string base = fs::path(path).parent_path().string();
  return parseTrainingConfig(std::string(bytes.begin(), bytes.end()), path, base);
}

std::string toJson(const TrainingConfig& c) {
  json root;
  root["network"] = json::parse(network::toJson(c.network));
  root["dtype"] = c.dtype == ocl::Dtype::F64 ? "f64" : "f32";
  root["seed"] = c.seed;
  root["steps"] = c.steps;
  root["checkpoint_every"] = c.checkpointEvery;
  root["corrections"] = c.corrections;
  root["max_fragments"] = c.maxFragments;
  root["ema_decay"] = c.emaDecay;
  root["optimizer"] = {{"lr", c.optimizer.lr},
                       {"beta1", c.optimizer.beta1},
                       {"beta2", c.optimizer.beta2},
                       {"eps", c.optimizer.eps},
                       {"gamma", c.optimizer.gamma},
                       {"clip_grad_norm", c.optimizer.clipGradNorm},
                       {"warmup_steps", c.optimizer.warmupSteps}};
  json w = json::object();
  for (const std::string& term : lossTermNames())
    w[term] = c.weight(term);
  root["loss_weights"] = w;
  const SamplingConfig& s = c.sampling;
  root["sampling"] = {{"min_views", s.minViews},
                      {"max_views", s.maxViews},
                      {"novel_views", s.novelViews},
                      {"window", s.window},
                      {"crop", {s.cropHeight, s.cropWidth}},
                      {"zoom", s.zoomScales},
                      {"mixup_probability", s.mixupProbability},
                      {"mixup_lambda", {s.mixupLambdaMin, s.mixupLambdaMax}},
                      {"reference_margin", s.referenceMargin},
                      {"source_gain_std", {s.sourceExposureStd, s.sourceChannelStd}},
                      {"sharpen", {s.sharpenProbability, s.sharpenMax}}};
  const SyntheticConfig& y = c.synthetic;
  root["synthetic"] = {{"style", synthetic::toString(y.style)},
                       {"textures", synthetic::toString(y.textures)},
                       {"photo_probability", y.photoProbability},
                       {"photo_dir", y.photoDir},
                       {"photos_required", y.photosRequired},
                       {"views", y.views},
                       {"objects", y.objects},
                       {"antialias", y.antialias},
                       {"translation", {y.translationMin, y.translationMax}},
                       {"object_size", {y.objectSizeMin, y.objectSizeMax}},
                       {"bushes", {y.bushesMin, y.bushesMax}},
                       {"bush_scale", {y.bushScaleMin, y.bushScaleMax}},
                       {"bush_shared_texture", y.bushSharedTexture},
                       {"size", y.width > 0
                                    ? std::to_string(y.width) + "x" + std::to_string(y.height)
                                    : std::string()}};
  return root.dump(2) + "\n";
}

std::string firstIncompatibleField(const TrainingConfig& a, const TrainingConfig& b) {
  json ja = json::parse(toJson(a)), jb = json::parse(toJson(b));
  for (const char* k : {"steps", "checkpoint_every"}) {
    ja.erase(k);
    jb.erase(k);
  }
  for (auto it = ja.begin(); it != ja.end(); ++it)
    if (!jb.contains(it.key()) || jb[it.key()] != it.value())
      return it.key();
  return "";
}

namespace {

bool looksLikePath(const std::string& s) {
  return s.find('/') != std::string::npos ||
         (s.size() > 5 && s.compare(s.size() - 5, 5, ".json") == 0);
}

} // namespace

TrainingConfig resolveTrainingConfig(const std::string& config) {
  namespace fs = std::filesystem;
  if (!looksLikePath(config)) {
    const std::string shipped = network::networkConfigDir() + "/training/" + config + ".json";
    if (fs::exists(shipped))
      return loadTrainingConfig(shipped);
    TrainingConfig out;
    out.network = network::resolveNetworkConfig(config);
    return out;
  }
  if (!fs::exists(config))
    fail("Config '", config, "': the file does not exist");
  try {
    return loadTrainingConfig(config);
  } catch (const Error& asTraining) {
    // Not a training config: a network config trained with the default settings?
    try {
      TrainingConfig out;
      out.network = network::resolveNetworkConfig(config);
      return out;
    } catch (const Error&) {
      fail("Config '", config,
           "' is neither a training config nor a network config; as a training config: ",
           asTraining.what());
    }
  }
}

network::NetworkConfig resolveNetworkOrTrainingConfig(const std::string& nameOrPath) {
  return resolveTrainingConfig(nameOrPath).network;
}

} // namespace simpli::training
