// Adam / AdamW against a plain double implementation of PyTorch's update, checkpoint
// export / import (bit-for-bit resume), a small end-to-end fit, learning-rate schedules at
// known steps, and bad use.
#include "simpli/error.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/ops_loss.h"
#include "simpli/ocl/optim.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace simpli;
using ocl::Dtype;
using ocl::Shape;
using ocl::Tensor;

namespace {

// torch.optim.Adam / AdamW (_single_tensor_adam, amsgrad off) in plain double.
struct ReferenceAdam {
  double lr, beta1, beta2, eps, weightDecay;
  bool decoupled;
  struct Slot {
    int64_t step = 0;
    std::vector<double> m, v;
  };
  std::vector<Slot> slots;

  void step(std::vector<std::vector<double>>& params,
            const std::vector<const std::vector<double>*>& grads) {
    slots.resize(params.size());
    for (std::size_t k = 0; k < params.size(); ++k) {
      if (!grads[k])
        continue; // no gradient: skipped, its step count unchanged
      Slot& s = slots[k];
      if (s.m.empty()) {
        s.m.assign(params[k].size(), 0.0);
        s.v.assign(params[k].size(), 0.0);
      }
      const int64_t t = ++s.step;
      const double bc1 = 1.0 - std::pow(beta1, static_cast<double>(t));
      const double bc2 = 1.0 - std::pow(beta2, static_cast<double>(t));
      for (std::size_t i = 0; i < params[k].size(); ++i) {
        double p = params[k][i], g = (*grads[k])[i];
        if (decoupled)
          p *= 1.0 - lr * weightDecay;
        else
          g += weightDecay * p;
        s.m[i] = beta1 * s.m[i] + (1.0 - beta1) * g;
        s.v[i] = beta2 * s.v[i] + (1.0 - beta2) * g * g;
        p -= lr / bc1 * s.m[i] / (std::sqrt(s.v[i]) / std::sqrt(bc2) + eps);
        params[k][i] = p;
      }
    }
  }
};

std::vector<double> randomVector(std::size_t n, std::mt19937_64& rng, double stddev = 1.0) {
  std::normal_distribution<double> dist(0.0, stddev);
  std::vector<double> v(n);
  for (auto& x : v)
    x = dist(rng);
  return v;
}

std::vector<double> roundToFloat(std::vector<double> v) {
  for (auto& x : v)
    x = static_cast<float>(x);
  return v;
}

struct AdamConfig {
  const char* name;
  double lr, beta1, beta2, eps, weightDecay;
  bool decoupled;
};

const AdamConfig kConfigs[] = {
    {"Adam defaults", 1e-2, 0.9, 0.999, 1e-8, 0.0, false},
    {"Adam + L2 weight decay", 3e-3, 0.9, 0.999, 1e-8, 0.1, false},
    {"AdamW", 3e-3, 0.9, 0.999, 1e-8, 0.1, true},
    {"Adam, other betas and eps", 5e-2, 0.5, 0.9, 1e-6, 0.0, false},
    {"Adam, beta1 0.3 (lerp's other branch)", 1e-2, 0.3, 0.99, 1e-8, 0.01, true},
};

} // namespace

TEST(Adam, MatchesPyTorchUpdateOverSeveralSteps) {
  const std::vector<Shape> shapes = {{7}, {3, 5}, {1}, {2, 1, 3}};
  for (const auto& cfg : kConfigs) {
    for (Dtype dtype : {Dtype::F64, Dtype::F32}) {
      SCOPED_TRACE(std::string(cfg.name) + (dtype == Dtype::F32 ? " f32" : " f64"));
      std::mt19937_64 rng(42);
      std::vector<std::vector<double>> hostParams;
      std::vector<Tensor> params;
      for (const auto& s : shapes) {
        hostParams.push_back(roundToFloat(randomVector(ocl::numelOf(s), rng)));
        params.push_back(Tensor::fromHost(hostParams.back(), s, dtype).setRequiresGrad(true));
      }
      ocl::Adam adam(params, cfg.lr, cfg.beta1, cfg.beta2, cfg.eps, cfg.weightDecay, cfg.decoupled);
      ReferenceAdam ref{cfg.lr, cfg.beta1, cfg.beta2, cfg.eps, cfg.weightDecay, cfg.decoupled, {}};
      for (int step = 0; step < 8; ++step) {
        std::vector<std::vector<double>> grads;
        std::vector<const std::vector<double>*> gradPtrs;
        for (std::size_t k = 0; k < shapes.size(); ++k) {
          // Parameter 2 only has a gradient on odd steps (skipped otherwise, like PyTorch).
          const bool has = k != 2 || step % 2 == 1;
          grads.push_back(roundToFloat(randomVector(ocl::numelOf(shapes[k]), rng, 0.5)));
          params[k].setGrad(has ? Tensor::fromHost(grads[k], shapes[k], dtype) : Tensor());
        }
        for (std::size_t k = 0; k < shapes.size(); ++k)
          gradPtrs.push_back(params[k].grad().defined() ? &grads[k] : nullptr);
        adam.step();
        ref.step(hostParams, gradPtrs);
        for (std::size_t k = 0; k < shapes.size(); ++k) {
          const auto got = params[k].toVector();
          for (std::size_t i = 0; i < got.size(); ++i) {
            const double tol = dtype == Dtype::F64 ? 1e-13 : 2e-6;
            ASSERT_NEAR(got[i], hostParams[k][i], tol * std::max(1.0, std::fabs(hostParams[k][i])))
                << "step " << step << " parameter " << k << " element " << i;
          }
        }
      }
      EXPECT_EQ(adam.steps(), 8);
      const auto state = adam.exportState();
      EXPECT_EQ(state.params[0].step, 8);
      EXPECT_EQ(state.params[2].step, 4);
    }
  }
}

TEST(Adam, ExportImportResumesBitForBit) {
  for (bool decoupled : {false, true}) {
    std::mt19937_64 rng(7);
    const Shape shape{4, 33};
    const std::vector<double> init = roundToFloat(randomVector(4 * 33, rng));
    std::vector<std::vector<double>> grads;
    for (int s = 0; s < 5; ++s)
      grads.push_back(roundToFloat(randomVector(4 * 33, rng)));

    Tensor a = Tensor::fromHost(init, shape, Dtype::F32).setRequiresGrad(true);
    Tensor untouched = Tensor::zeros({3}).setRequiresGrad(true); // never gets a gradient
    ocl::Adam first({a, untouched}, 1e-2, 0.9, 0.999, 1e-8, 0.05, decoupled);
    for (int s = 0; s < 4; ++s) {
      a.setGrad(Tensor::fromHost(grads[s], shape, Dtype::F32));
      first.step();
    }
    // Checkpoint: parameter values and optimiser state through host vectors.
    const std::vector<float> saved = a.toVectorF32();
    const ocl::Adam::State state = first.exportState();
    EXPECT_EQ(state.steps, 4);
    EXPECT_TRUE(state.params[1].m.empty());

    a.setGrad(Tensor::fromHost(grads[4], shape, Dtype::F32));
    first.step();
    const std::vector<float> expected = a.toVectorF32();

    Tensor b = Tensor::fromHost(std::vector<float>(saved), shape, Dtype::F32).setRequiresGrad(true);
    Tensor untouched2 = Tensor::zeros({3}).setRequiresGrad(true);
    ocl::Adam resumed({b, untouched2}, 1e-2, 0.9, 0.999, 1e-8, 0.05, decoupled);
    resumed.importState(state);
    EXPECT_EQ(resumed.steps(), 4);
    b.setGrad(Tensor::fromHost(grads[4], shape, Dtype::F32));
    resumed.step();
    const std::vector<float> got = b.toVectorF32();
    ASSERT_EQ(got.size(), expected.size());
    for (std::size_t i = 0; i < got.size(); ++i)
      ASSERT_EQ(got[i], expected[i]) << "element " << i; // bit-for-bit
    const auto s1 = first.exportState(), s2 = resumed.exportState();
    EXPECT_EQ(s1.params[0].m, s2.params[0].m);
    EXPECT_EQ(s1.params[0].v, s2.params[0].v);
    EXPECT_EQ(s1.params[0].step, s2.params[0].step);
  }
}

TEST(Adam, ZeroGradAndFitWithSchedule) {
  // Fit w to a target with mseLoss; the learning rate follows a cosine schedule.
  std::mt19937_64 rng(3);
  const std::vector<double> target = randomVector(10, rng);
  Tensor t = Tensor::fromHost(target, {10}, Dtype::F32);
  Tensor w = Tensor::zeros({10}).setRequiresGrad(true);
  ocl::Adam adam({w}, 0.1);
  ocl::CosineLr schedule(0.1, 400, 1e-3, 20);
  const double initial = ocl::mseLoss(w, t).item();
  for (int64_t step = 0; step < 400; ++step) {
    adam.setLr(schedule.lrAt(step));
    adam.zeroGrad();
    ocl::mseLoss(w, t).backward();
    adam.step();
  }
  EXPECT_LT(ocl::mseLoss(w, t).item(), initial * 1e-4);
  adam.zeroGrad();
  for (double g : w.grad().toVector())
    EXPECT_EQ(g, 0.0);
}

TEST(LrSchedule, KnownSteps) {
  ocl::ConstantLr constant(3e-4);
  EXPECT_EQ(constant.lrAt(0), 3e-4);
  EXPECT_EQ(constant.lrAt(123456), 3e-4);

  // The reference: lr 3e-4, gamma 0.999994 per iteration (x0.05 after 500k, x0.019 at 660k).
  ocl::ExponentialLr exponential(3e-4, 0.999994);
  EXPECT_EQ(exponential.lrAt(0), 3e-4);
  EXPECT_DOUBLE_EQ(exponential.lrAt(1), 3e-4 * 0.999994);
  EXPECT_NEAR(exponential.lrAt(500000) / 3e-4, 0.0498, 5e-4);
  EXPECT_NEAR(exponential.lrAt(660000) / 3e-4, 0.019, 5e-4);
  double recursive = 3e-4; // PyTorch's ExponentialLR multiplies once per step
  for (int s = 0; s < 1000; ++s)
    recursive *= 0.999994;
  EXPECT_NEAR(exponential.lrAt(1000), recursive, recursive * 1e-12);

  // A linear warm-up on top: (step + 1) / warmup of the exponential, then the exponential itself.
  ocl::ExponentialLr warmExp(1e-3, 0.99, 4);
  EXPECT_DOUBLE_EQ(warmExp.lrAt(0), 1e-3 * 0.25);
  EXPECT_DOUBLE_EQ(warmExp.lrAt(2), 1e-3 * 0.99 * 0.99 * 0.75);
  EXPECT_DOUBLE_EQ(warmExp.lrAt(3), 1e-3 * std::pow(0.99, 3));
  EXPECT_DOUBLE_EQ(warmExp.lrAt(9), 1e-3 * std::pow(0.99, 9));

  const double pi = std::acos(-1.0);
  ocl::CosineLr cosine(1e-3, 100, 1e-5);
  EXPECT_DOUBLE_EQ(cosine.lrAt(0), 1e-3);
  EXPECT_DOUBLE_EQ(cosine.lrAt(25), 1e-5 + 0.5 * (1e-3 - 1e-5) * (1 + std::cos(pi / 4)));
  EXPECT_DOUBLE_EQ(cosine.lrAt(50), 0.5 * (1e-3 + 1e-5));
  EXPECT_DOUBLE_EQ(cosine.lrAt(100), 1e-5);
  EXPECT_DOUBLE_EQ(cosine.lrAt(5000), 1e-5);

  ocl::CosineLr warm(1e-3, 110, 0.0, 10);
  EXPECT_DOUBLE_EQ(warm.lrAt(0), 1e-4);
  EXPECT_DOUBLE_EQ(warm.lrAt(4), 5e-4);
  EXPECT_DOUBLE_EQ(warm.lrAt(9), 1e-3);
  EXPECT_DOUBLE_EQ(warm.lrAt(10), 1e-3);
  EXPECT_NEAR(warm.lrAt(60), 5e-4, 1e-18);
  EXPECT_DOUBLE_EQ(warm.lrAt(110), 0.0);
}

TEST(LrSchedule, BadUseThrows) {
  EXPECT_THROW(ocl::ConstantLr(-1.0), Error);
  EXPECT_THROW(ocl::ExponentialLr(1e-3, 0.0), Error);
  EXPECT_THROW(ocl::ExponentialLr(1e-3, 1.5), Error);
  EXPECT_THROW(ocl::ExponentialLr(1e-3, 0.99, -1), Error);
  EXPECT_THROW(ocl::CosineLr(1e-3, 10, 0.0, 10), Error);
  EXPECT_THROW(ocl::CosineLr(1e-3, 10, 2e-3), Error);
  try {
    ocl::ExponentialLr(1e-3, 0.99).lrAt(-2);
    FAIL() << "expected simpli::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("ExponentialLr"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("-2"), std::string::npos) << e.what();
  }
}

TEST(Adam, BadUseThrows) {
  Tensor p = Tensor::zeros({4}).setRequiresGrad(true);
  EXPECT_THROW(ocl::Adam({p}, -1e-3), Error);
  EXPECT_THROW(ocl::Adam({p}, 1e-3, 1.0), Error);
  EXPECT_THROW(ocl::Adam({p}, 1e-3, 0.9, -0.1), Error);
  EXPECT_THROW(ocl::Adam({p, Tensor()}, 1e-3), Error);

  ocl::Adam adam({p}, 1e-3);
  EXPECT_THROW(adam.setLr(-1.0), Error);
  p.setGrad(Tensor::zeros({4}, Dtype::F64)); // dtype differs from the parameter's
  try {
    adam.step();
    FAIL() << "expected simpli::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("f64[4]"), std::string::npos) << e.what();
  }

  ocl::Adam::State state;
  state.params.resize(2);
  EXPECT_THROW(adam.importState(state), Error); // two entries for one parameter
  state.params.resize(1);
  state.params[0].step = 3;
  state.params[0].m.assign(5, 0.0);
  state.params[0].v.assign(5, 0.0);
  try {
    adam.importState(state);
    FAIL() << "expected simpli::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("parameter 0"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("5"), std::string::npos) << e.what();
  }
  EXPECT_EQ(adam.steps(), 0); // a rejected state changes nothing
}
