// End to end: a two-layer conv net (conv3x3 -> ELU -> conv3x3) trained with Adam fits a fixed
// target produced by a random "teacher" net of the same shape to near-zero loss. Exercises
// conv forward/backward, the tape, gradient accumulation, clipping and the optimiser together.
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/ops_conv.h"
#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_loss.h"
#include "simpli/ocl/optim.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace simpli::ocl;

namespace {

Tensor twoLayerNet(const Tensor& x, const Tensor& w1, const Tensor& b1, const Tensor& w2,
                   const Tensor& b2) {
  return conv2d(elu(conv2d(x, w1, b1, 1, 1, PaddingMode::Replicate)), w2, b2, 1, 1);
}

} // namespace

TEST(EndToEnd, TwoLayerConvNetFitsTargetWithAdam) {
  const Shape input{2, 3, 12, 10};
  Tensor x = Tensor::uniform(input, -1, 1, 11);
  Tensor target;
  {
    NoGradGuard off;
    // A narrower teacher (4 hidden channels) than the student (16): the target is exactly
    // representable and the over-parameterised student reaches it reliably.
    target = twoLayerNet(
        x, Tensor::uniform({4, 3, 3, 3}, -0.4, 0.4, 12), Tensor::uniform({4}, -0.2, 0.2, 13),
        Tensor::uniform({2, 4, 3, 3}, -0.3, 0.3, 14), Tensor::uniform({2}, -0.2, 0.2, 15));
  }
  Tensor w1 = Tensor::uniform({16, 3, 3, 3}, -0.3, 0.3, 21).setRequiresGrad();
  Tensor b1 = Tensor::zeros({16}).setRequiresGrad();
  Tensor w2 = Tensor::uniform({2, 16, 3, 3}, -0.2, 0.2, 22).setRequiresGrad();
  Tensor b2 = Tensor::zeros({2}).setRequiresGrad();
  const int steps = 600;
  Adam adam({w1, b1, w2, b2}, 0.02);
  CosineLr schedule(0.02, steps, 1e-4);
  double first = 0.0, last = 0.0;
  for (int step = 0; step < steps; ++step) {
    adam.setLr(schedule.lrAt(step));
    adam.zeroGrad();
    Tensor loss = mseLoss(twoLayerNet(x, w1, b1, w2, b2), target);
    loss.backward();
    clipGradNorm({w1, b1, w2, b2}, 20.0);
    adam.step();
    last = loss.item();
    if (step == 0)
      first = last;
    ASSERT_TRUE(std::isfinite(last)) << "step " << step;
  }
  EXPECT_GT(first, 1e-2) << "the initial net must start far from the target";
  EXPECT_LT(last, 1e-3 * first) << "loss went from " << first << " to " << last;
}
