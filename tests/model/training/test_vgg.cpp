// VGG-19 loader (torchvision key names, widths read from the file, clear errors) and the
// perceptual loss against a plain double reference, on a small randomly initialised VGG.
#include "support/captured_warnings.h"
#include "support/expect_error.h"

#include "simpli/model/io/safetensors.h"
#include "simpli/model/training/trainer.h"
#include "simpli/model/training/vgg.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

namespace simpli::training {
namespace {
namespace fs = std::filesystem;

constexpr std::array<int, 16> kWidths{4, 4, 5, 5, 6, 6, 6, 6, 7, 7, 7, 7, 8, 8, 8, 8};

struct Img { // [C, H, W]
  int C = 0, H = 0, W = 0;
  std::vector<double> v;
  double& at(int c, int i, int j) { return v[size_t((c * H + i) * W + j)]; }
  double at(int c, int i, int j) const { return v[size_t((c * H + i) * W + j)]; }
};

struct SmallVgg {
  std::vector<io::HostTensor<float>> w, b;
  std::map<std::string, io::SafeTensorEntry> entries() const {
    std::map<std::string, io::SafeTensorEntry> e;
    for (size_t k = 0; k < 16; ++k) {
      const int idx = Vgg19Features::convIndices()[k];
      e["features." + std::to_string(idx) + ".weight"] = io::makeEntry(w[k]);
      e["features." + std::to_string(idx) + ".bias"] = io::makeEntry(b[k]);
    }
    io::HostTensor<float> extra{{2}, {1, 2}};
    e["classifier.0.weight"] = io::makeEntry(extra); // ignored
    return e;
  }
};

SmallVgg makeVgg(uint32_t seed) {
  std::mt19937 g(seed);
  SmallVgg vgg;
  int in = 3;
  for (int out : kWidths) {
    const double a = std::sqrt(6.0 / (in * 9));
    std::uniform_real_distribution<float> dw(float(-a), float(a)), db(-0.1f, 0.1f);
    io::HostTensor<float> w{{out, in, 3, 3}, {}}, b{{out}, {}};
    for (int i = 0; i < out * in * 9; ++i)
      w.data.push_back(dw(g));
    for (int i = 0; i < out; ++i)
      b.data.push_back(db(g));
    vgg.w.push_back(w);
    vgg.b.push_back(b);
    in = out;
  }
  return vgg;
}

Img conv(const Img& x, const io::HostTensor<float>& w, const io::HostTensor<float>& b) {
  Img y{int(w.shape[0]), x.H, x.W, {}};
  y.v.assign(size_t(y.C * y.H * y.W), 0);
  for (int o = 0; o < y.C; ++o)
    for (int i = 0; i < y.H; ++i)
      for (int j = 0; j < y.W; ++j) {
        double s = b.data[size_t(o)];
        for (int c = 0; c < x.C; ++c)
          for (int di = -1; di <= 1; ++di)
            for (int dj = -1; dj <= 1; ++dj) {
              const int ii = i + di, jj = j + dj;
              if (ii < 0 || jj < 0 || ii >= x.H || jj >= x.W)
                continue;
              s += w.data[size_t(((o * x.C + c) * 3 + di + 1) * 3 + dj + 1)] * x.at(c, ii, jj);
            }
        y.at(o, i, j) = std::max(0.0, s); // every conv is followed by its ReLU
      }
  return y;
}
Img pool(const Img& x) {
  Img y{x.C, x.H / 2, x.W / 2, {}};
  y.v.assign(size_t(y.C * y.H * y.W), 0);
  for (int c = 0; c < y.C; ++c)
    for (int i = 0; i < y.H; ++i)
      for (int j = 0; j < y.W; ++j)
        y.at(c, i, j) = 0.25 * (x.at(c, 2 * i, 2 * j) + x.at(c, 2 * i + 1, 2 * j) +
                                x.at(c, 2 * i, 2 * j + 1) + x.at(c, 2 * i + 1, 2 * j + 1));
  return y;
}
std::vector<Img> featuresRef(const SmallVgg& vgg, Img x) {
  const double mean[3] = {0.485, 0.456, 0.406}, sd[3] = {0.229, 0.224, 0.225};
  for (int c = 0; c < 3; ++c)
    for (int i = 0; i < x.H * x.W; ++i)
      x.v[size_t(c * x.H * x.W + i)] =
          (x.v[size_t(c * x.H * x.W + i)] - (2 * mean[c] - 1)) / (2 * sd[c]);
  const int perBlock[5] = {2, 2, 4, 4, 4};
  std::vector<Img> out;
  size_t k = 0;
  for (int blk = 0; blk < 5; ++blk) {
    if (blk > 0)
      x = pool(x);
    for (int c = 0; c < perBlock[blk]; ++c, ++k)
      x = conv(x, vgg.w[k], vgg.b[k]);
    out.push_back(x);
  }
  return out;
}
// Bilinear resize, align_corners False, border-clamped (one channel).
Img bilinear(const Img& m, int H, int W) {
  Img y{1, H, W, std::vector<double>(size_t(H * W))};
  auto src = [](int p, int in, int out, int& i0, int& i1, double& t) {
    double s = std::max(0.0, (p + 0.5) * in / out - 0.5);
    i0 = int(std::floor(s));
    i1 = std::min(i0 + 1, in - 1);
    t = s - i0;
  };
  for (int i = 0; i < H; ++i)
    for (int j = 0; j < W; ++j) {
      int a0, a1, b0, b1;
      double ti, tj;
      src(i, m.H, H, a0, a1, ti);
      src(j, m.W, W, b0, b1, tj);
      y.at(0, i, j) = (1 - ti) * ((1 - tj) * m.at(0, a0, b0) + tj * m.at(0, a0, b1)) +
                      ti * ((1 - tj) * m.at(0, a1, b0) + tj * m.at(0, a1, b1));
    }
  return y;
}

fs::path writeVgg(const SmallVgg& vgg, const std::string& name,
                  std::map<std::string, io::SafeTensorEntry> entries = {}) {
  const fs::path p =
      fs::temp_directory_path() / (name + "_" + std::to_string(::getpid()) + ".safetensors");
  io::writeSafeTensors(p.string(), entries.empty() ? vgg.entries() : entries);
  return p;
}

TEST(TrainVgg, PerceptualLossMatchesDoubleReference) {
  const SmallVgg vgg = makeVgg(1);
  const fs::path file = writeVgg(vgg, "vgg_small");
  const int N = 2, S = 16;
  std::mt19937 g(2);
  std::uniform_real_distribution<double> u(-1, 1), u01(0, 1);
  std::vector<double> pred, target, mask;
  for (int i = 0; i < N * 3 * S * S; ++i) {
    pred.push_back(u(g));
    target.push_back(u(g));
  }
  for (int i = 0; i < N * S * S; ++i)
    mask.push_back(u01(g));
  double ref = 0;
  for (int n = 0; n < N; ++n) {
    Img p{3, S, S, {pred.begin() + n * 3 * S * S, pred.begin() + (n + 1) * 3 * S * S}};
    Img t{3, S, S, {target.begin() + n * 3 * S * S, target.begin() + (n + 1) * 3 * S * S}};
    const Img m{1, S, S, {mask.begin() + n * S * S, mask.begin() + (n + 1) * S * S}};
    const std::vector<Img> fp = featuresRef(vgg, p), ft = featuresRef(vgg, t);
    for (size_t l = 0; l < 5; ++l) {
      const Img ml = fp[l].H == S ? m : bilinear(m, fp[l].H, fp[l].W);
      double perChannel = 0;
      for (int c = 0; c < fp[l].C; ++c) {
        double s = 0, z = 0;
        for (int i = 0; i < fp[l].H * fp[l].W; ++i) {
          const double w = ml.v[size_t(i)];
          s += std::abs(fp[l].v[size_t(c * fp[l].H * fp[l].W + i)] -
                        ft[l].v[size_t(c * fp[l].H * fp[l].W + i)]) *
               w;
          z += w;
        }
        perChannel += s / (z + 1e-6);
      }
      // mean over (n, c): divide by N * C
      ref += Vgg19Features::kLevelWeights[l] * perChannel / (N * fp[l].C);
    }
  }
  for (ocl::Dtype dtype : {ocl::Dtype::F64, ocl::Dtype::F32}) {
    const Vgg19Features f(file.string(), dtype);
    EXPECT_EQ(f.channels(15), 8);
    ocl::Tensor tp = ocl::Tensor::fromHost(pred, {N, 3, S, S}, dtype);
    const ocl::Tensor tt = ocl::Tensor::fromHost(target, {N, 3, S, S}, dtype);
    const ocl::Tensor tm = ocl::Tensor::fromHost(mask, {N, 1, S, S}, dtype);
    const std::vector<ocl::Tensor> feats = f.features(tp);
    ASSERT_EQ(feats.size(), 5u);
    EXPECT_EQ(feats[0].shape(), (ocl::Shape{N, 4, 16, 16}));
    EXPECT_EQ(feats[4].shape(), (ocl::Shape{N, 8, 1, 1}));
    const double loss = perceptualLoss(f, tp, tt, tm).item();
    const double tol = dtype == ocl::Dtype::F64 ? 1e-10 : 2e-5;
    EXPECT_NEAR(loss, ref, tol * ref) << (dtype == ocl::Dtype::F64 ? "f64" : "f32");
    // The prediction gets a gradient, the loss of identical images is 0.
    tp.setRequiresGrad(true);
    perceptualLoss(f, tp, tt, tm).backward();
    ASSERT_TRUE(tp.grad().defined());
    EXPECT_EQ(perceptualLoss(f, tt, tt, tm).item(), 0.0);
  }
  fs::remove(file);
}

TEST(TrainVgg, BadFilesNameFileAndKey) {
  const SmallVgg vgg = makeVgg(3);
  auto entries = vgg.entries();
  entries.erase("features.10.weight");
  const fs::path missing = writeVgg(vgg, "vgg_missing", entries);
  test::expectError([&] { Vgg19Features(missing.string(), ocl::Dtype::F32); },
                    {missing.string(), "features.10.weight", "missing"});
  entries = vgg.entries();
  io::HostTensor<float> wrong{{6, 3, 3, 3}, std::vector<float>(6 * 27, 0.f)};
  entries["features.2.weight"] = io::makeEntry(wrong);
  const fs::path bad = writeVgg(vgg, "vgg_shape", entries);
  test::expectError([&] { Vgg19Features(bad.string(), ocl::Dtype::F32); },
                    {bad.string(), "features.2.weight", "[6, 3, 3, 3]", "expected [out, 4, 3, 3]"});
  const fs::path junk = fs::temp_directory_path() / ("vgg_junk_" + std::to_string(::getpid()));
  std::ofstream(junk) << "not a safetensors file";
  test::expectError([&] { Vgg19Features(junk.string(), ocl::Dtype::F32); }, {junk.string()});
  test::expectError([&] { Vgg19Features("/no/such/vgg.safetensors", ocl::Dtype::F32); },
                    {"/no/such/vgg.safetensors"});
  for (const fs::path& p : {missing, bad, junk})
    fs::remove(p);
}

// The trainer computes and logs the perceptual term when given a VGG file and a positive weight.
TEST(TrainVgg, TrainerLogsThePerceptualTerm) {
  const fs::path file = writeVgg(makeVgg(4), "vgg_trainer");
  TrainingConfig cfg = parseTrainingConfig(
      R"({"network": "tiny.json", "steps": 1, "loss_weights": {"perceptual": 10},
                              "sampling": {"max_views": 2, "novel_views": 1}})",
      "t", SIMPLI_NETWORK_CONFIG_DIR);
  const fs::path run = fs::temp_directory_path() / ("simpli_vgg_run_" + std::to_string(::getpid()));
  fs::remove_all(run);
  TrainerOptions o;
  o.data = {{std::string(SIMPLI_DATASETS_SMALL_DIR) + "/synthetic/scene_01"}};
  o.runDir = run.string();
  o.dataOptions.height = 32;
  o.dataOptions.width = 48;
  o.vggPath = file.string();
  std::vector<std::string> messages;
  o.message = [&](const std::string& m) { messages.push_back(m); };
  Trainer t(&cfg, o);
  const StepReport r = t.trainStep();
  ASSERT_EQ(r.terms[1].first, "perceptual");
  EXPECT_TRUE(std::isfinite(r.terms[1].second));
  EXPECT_GT(r.terms[1].second, 0.0);
  double sum = 0;
  for (const auto& [name, v] : r.terms)
    if (std::isfinite(v))
      sum += cfg.weight(name) * v;
  EXPECT_NEAR(r.total, sum, 1e-5 * sum);
  EXPECT_NE(messages[0].find("perceptual loss: VGG-19 from"), std::string::npos) << messages[0];
  fs::remove_all(run);
  fs::remove(file);
}

// `--vgg FILE` with a file that is not VGG-19 weights is a named error listing the missing keys,
// also when the config's perceptual weight is 0 (the file was once not even opened then); a
// real VGG file with weight 0 trains with a warning that it is unused.
TEST(TrainVgg, FileThatIsNotVggWeightsIsAnError) {
  const fs::path notVgg = fs::temp_directory_path() / ("not_vgg_" + std::to_string(::getpid()));
  io::writeSafeTensors(notVgg.string(),
                       {{"encoder.0.weight", io::makeEntry(io::HostTensor<float>{{2}, {1, 2}})}});
  test::expectError([&] { Vgg19Features::check(notVgg.string()); },
                    {notVgg.string(), "not VGG-19 weights", "32 of the 32 keys",
                     "features.0.weight, features.0.bias, features.2.weight", "..."});
  test::expectError([&] { Vgg19Features(notVgg.string(), ocl::Dtype::F32); },
                    {notVgg.string(), "not VGG-19 weights"});
  const fs::path vgg = writeVgg(makeVgg(4), "vgg_unused");
  EXPECT_NO_THROW(Vgg19Features::check(vgg.string()));

  const TrainingConfig cfg = parseTrainingConfig(
      R"({"network": "tiny.json", "steps": 1, "sampling": {"max_views": 2, "novel_views": 1}})",
      "t", SIMPLI_NETWORK_CONFIG_DIR);
  ASSERT_EQ(cfg.weight("perceptual"), 0.0);
  const fs::path run = fs::temp_directory_path() / ("simpli_vgg_off_" + std::to_string(::getpid()));
  fs::remove_all(run);
  TrainerOptions o;
  o.data = {{std::string(SIMPLI_DATASETS_SMALL_DIR) + "/synthetic/scene_01"}};
  o.runDir = run.string();
  o.dataOptions.height = 32;
  o.dataOptions.width = 48;
  o.message = [](const std::string&) {};
  o.vggPath = notVgg.string();
  test::expectError([&] { Trainer(&cfg, o); }, {notVgg.string(), "not VGG-19 weights"});
  EXPECT_FALSE(fs::exists(run)); // refused before the run folder is made
  o.vggPath = vgg.string();
  {
    test::CapturedWarnings warnings;
    Trainer t(&cfg, o);
    EXPECT_EQ(warnings.count({vgg.string(), "loss_weights.perceptual is 0", "not used"}), 1)
        << warnings.text();
  }
  fs::remove_all(run);
  fs::remove(vgg);
  fs::remove(notVgg);
}

} // namespace
} // namespace simpli::training
